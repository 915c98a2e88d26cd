//! Sampled controllers: each is called every control period with the measurements it
//! declares and the set-point, and returns the plant input it drives, held until the
//! next call (zero-order hold). One file per controller; each implements [`Controller`],
//! so a run can carry a controller and a baseline and compare them on the same figures.

pub mod adaptive;
mod cascade;
mod cascade_pi;
mod loop_spec;
mod pi;
mod rhonn_indirect;
#[cfg(test)]
mod test_bang_bang;
pub use adaptive::{
    pump_cascade, AffineNeuron, CascadeSettings, CascadeState, PumpAdaptiveLoop, RhonnCascade,
};
pub use cascade::{Cascade, CascadeLoop};
pub use cascade_pi::{
    CascadePi, CascadePiGains, CascadePiGainsMpa, PumpCascadePiLoop, NOMINAL_OPTIMAL, ROBUST,
};
pub use loop_spec::{LoopContext, LoopSettings};
pub use pi::{Pi, PiLoop};
pub use rhonn_indirect::{IndirectLoop, IndirectSettings, RhonnIndirect};

/// Declares [`LoopSpec`], the controller kinds a scenario file can name: a variant per
/// kind (its `kind` is the variant's name in kebab-case), holding the settings type that
/// implements [`LoopSettings`], and the dispatch to it. A kind may carry a `cfg`.
macro_rules! loop_kinds {
    ($( $(#[cfg($c:meta)])? $variant:ident($settings:ty), )*) => {
        /// One control loop of a scenario file, tagged by `kind`: see each settings type.
        #[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
        #[serde(tag = "kind", rename_all = "kebab-case")]
        pub enum LoopSpec {
            $(
                $(#[cfg($c)])?
                #[doc = concat!("`", stringify!($settings), "`")]
                $variant($settings),
            )*
        }

        impl LoopSpec {
            /// The kind's settings.
            pub fn settings(&self) -> &dyn LoopSettings {
                match self {
                    $( $(#[cfg($c)])? LoopSpec::$variant(s) => s, )*
                }
            }
        }
    };
}

// The registry: adding a controller kind to scenario files is its file (the controller,
// its settings type, `impl LoopSettings`) and one line here.
loop_kinds! {
    Pi(PiLoop),
    RhonnIndirect(IndirectLoop),
    Cascade(CascadeLoop),
    PumpRhonnAdaptive(PumpAdaptiveLoop),
    PumpCascadePi(PumpCascadePiLoop),
    #[cfg(test)]
    TestBangBang(test_bang_bang::BangBangLoop),
}

impl LoopSpec {
    /// The state the loop regulates (a cascade: its outer loop's).
    pub fn state(&self) -> &str {
        self.settings().state()
    }

    /// Its name in reports.
    pub fn name(&self) -> &'static str {
        self.settings().name()
    }

    /// The output its settings add at rest (display units; a PI's `bias`), if given.
    pub fn bias(&self) -> Option<f64> {
        self.settings().bias()
    }
    /// A cascade's inner state (None for a single loop).
    pub fn inner_state(&self) -> Option<&str> {
        self.settings().inner_state()
    }

    /// The controller, checked against `cx`.
    pub fn build(&self, cx: &LoopContext) -> crate::Result<Box<dyn Controller>> {
        self.settings().build(cx)
    }
}

/// A sampled controller of one plant input.
///
/// ```
/// use rhonn_sim::control::{Controller, Pi};
/// // A PI on state 0 of some plant, output in [0, 1].
/// let mut pi = Pi::new(0.5, 2.0, 0.01, 0.0, 0.0, 1.0);
/// assert_eq!(pi.measurements(), &[0]);
/// let u = pi.control(0.0, &[0.2], 1.0);
/// assert!(u > 0.0 && u <= 1.0);
/// ```
pub trait Controller: Send {
    /// Short name, as reports print it (`pi`, `rhonn-adaptive`).
    fn name(&self) -> &'static str;
    /// The plant states it measures (indices into the plant's states), in the order
    /// [`Controller::control`] receives them.
    fn measurements(&self) -> &[usize];
    /// One control instant at `t` \[s\]: the measurements (SI, in
    /// [`Controller::measurements`] order) and the set-point (SI) in, the input out.
    fn control(&mut self, t: f64, measured: &[f64], setpoint: f64) -> f64;
    /// An adaptive controller's view of its weights at time `t` (None for a fixed one).
    fn adaptive(&self, _t: f64) -> Option<AdaptiveView> {
        None
    }
    /// A cascade's inner set-point of the last control instant (SI; None for a single
    /// loop).
    fn inner_reference(&self) -> Option<f64> {
        None
    }
}

/// What an adaptive controller shows of its weights at a control instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdaptiveView {
    /// The model's output (SI), e.g. its pressure.
    pub model_output: f64,
    /// A cascade's inner reference (SI), e.g. the pump's stroke reference.
    pub inner_reference: Option<f64>,
    /// |W| (the neuron's units).
    pub w_norm: f64,
    /// |W_1|.
    pub w1_norm: f64,
    /// Whether it is still in its identification phase.
    pub identifying: bool,
    /// |W_1 - centre| (MPa/(s mm) units).
    pub w1_distance: f64,
    /// Radius of W_1's ball.
    pub ball_radius: f64,
    /// Radius of W's ball (around 0).
    pub w_bound: f64,
    /// W_1.
    pub w1: [f64; adaptive::L_GAIN],
    /// Identifier substeps that ended with a projection, so far.
    pub projections: u64,
    /// The actuator as identified online, (lag \[s\], pilot flow against the nominal
    /// valve's): the pump's cascade with `actuator_memory_s` > 0; None otherwise.
    pub actuator: Option<(f64, f64)>,
}
