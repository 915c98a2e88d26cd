//! Plants: continuous-time systems whose states may be limited integrators, driven by
//! inputs, described by a [`Plant`] so that the solver, the online identifier, the
//! controllers and the reports work on any of them.
//!
//! Each plant lives in its own folder: [`pump`] (the thesis's solenoid-controlled
//! variable-displacement pump) and [`tanks`] (two tanks in series, the upper one
//! overflowing into the lower). Adding a plant is a folder with a type that implements
//! [`rhonn_ode::System`] (the equations, events and bounds) and [`Plant`] (what its
//! states, inputs and parameters are called, in which units); for scenario files, one
//! arm in [`with_kind`].

mod input;
pub mod pump;
pub mod tanks;

pub use input::Input;
pub use pump::{
    Pilot, PumpParams, PumpParamsSpec, PumpSystem, CURRENT_EFF, PLANT_DIM, PUMP_EVENTS, P_LINE, STROKE,
};
pub use tanks::{Tanks, TanksParams};

use rhonn_ode::System;

/// Something done with the plant a scenario names (`[plant] kind`), whatever its type.
pub trait WithPlant {
    /// What it gives.
    type Output;
    /// Do it with `nominal`, the plant with its nominal parameters.
    fn with<P: Plant>(self, nominal: P) -> crate::Result<Self::Output>;
}

/// The plants scenario files can name.
pub const KINDS: [&str; 2] = ["tanks", "pump"];

/// `w` done with the plant named `kind`, nominal: **the one place a plant is registered**
/// for scenario files (`rhonn run`, `campaign`, `bench`; an arm here and its name in
/// [`KINDS`]).
pub fn with_kind<W: WithPlant>(kind: &str, w: W) -> crate::Result<W::Output> {
    match kind {
        "tanks" => w.with(Tanks::new(TanksParams::default(), Input::Held(0.0))),
        "pump" => w.with(PumpSystem::new(
            PumpParams::default(),
            Input::Held(0.0),
            Input::Held(0.0),
        )),
        other => Err(crate::error::invalid(
            "plant.kind",
            format!("\"{other}\""),
            format!("one of {KINDS:?} (the pump's own scenarios have no kind)"),
        )),
    }
}

/// A named quantity of a plant (a state or an input): its column name, its SI unit, and
/// the unit people read with the factor that converts to it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantity {
    /// Column name (`p_line`, `h1`, `voltage`): lower case, no spaces.
    pub name: &'static str,
    /// The SI unit the code uses (`Pa`, `m`, `m^3/s`, `V`).
    pub unit: &'static str,
    /// The unit of tables and plots (`MPa`, `mm`, `dm^3/s`).
    pub display_unit: &'static str,
    /// Display value per SI value (1e-6 for Pa -> MPa).
    pub display_per_si: f64,
    /// One sentence on what it is.
    pub description: &'static str,
}

impl Quantity {
    /// A quantity shown in its own SI unit.
    pub const fn si(name: &'static str, unit: &'static str, description: &'static str) -> Self {
        Quantity {
            name,
            unit,
            display_unit: unit,
            display_per_si: 1.0,
            description,
        }
    }

    /// `v` (SI) in the display unit.
    pub fn to_display(&self, v: f64) -> f64 {
        v * self.display_per_si
    }
}

/// An uncertain parameter of a plant: its key in a scenario's `[plant]` table (display
/// units, the unit in the name), its nominal value and its relative tolerance, which is
/// what Monte Carlo campaigns draw from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Parameter {
    /// Key in `[plant]` (`beta_mpa`, `outlet_1_mm2`).
    pub name: &'static str,
    /// Nominal value, display units.
    pub nominal: f64,
    /// Relative half-width of the tolerance band (0.2 = +-20 %).
    pub tolerance: f64,
    /// What it is.
    pub description: &'static str,
}

/// What a runner takes when `[solver]` leaves a field unset (profile `hairer`).
#[derive(Debug, Clone, PartialEq)]
pub struct SolverDefaults {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance per plant state, SI (states beyond the list: 1e-9).
    pub atol: Vec<f64>,
    /// Largest step \[s\] (infinite: no limit).
    pub max_step_s: f64,
}

impl SolverDefaults {
    /// A plant's runner: `rtol`, 1e-9 on every state, no step limit.
    pub fn plant(rtol: f64) -> Self {
        SolverDefaults {
            rtol,
            atol: Vec::new(),
            max_step_s: f64::INFINITY,
        }
    }
}

/// A profile's largest slew rate and peak, each with what it is ([`Plant::input_profile_limits`]).
pub type ProfileLimits = (Option<(f64, &'static str)>, Option<(f64, &'static str)>);

/// What the experiment layer needs to know about a plant beyond its equations.
///
/// The first [`Plant::states`]`.len()` components of the [`System`] state are the
/// plant's, in that order. Inputs are either signals of time or values held by a sampled
/// controller ([`Plant::hold_input`], zero-order hold); [`Plant::input_at`] evaluates them
/// in the current modes, so it is cheap enough to call inside the right-hand side of a
/// system that integrates an identifier along with the plant.
pub trait Plant: System + Clone + Send + Sync {
    /// Short name (`pump`, `tanks`; default `plant`).
    fn name(&self) -> &'static str {
        "plant"
    }
    /// The states, in state order.
    fn states(&self) -> &'static [Quantity];
    /// The inputs.
    fn inputs(&self) -> &'static [Quantity];
    /// Indices (into [`Plant::states`]) of the states a sensor measures (default: the
    /// first).
    fn measured(&self) -> &'static [usize] {
        &[0]
    }
    /// Input `k` at `t`, in the current modes (SI).
    fn input_at(&self, t: f64, k: usize) -> f64;
    /// Hold input `k` at `value` from now on (a sampled controller's output).
    fn hold_input(&mut self, k: usize, value: f64);
    /// Indices of the states the model carries that no instrument shows (the pump's
    /// lagged solenoid current): left out of a run's columns and state figures. Default:
    /// none.
    fn internal_states(&self) -> &'static [usize] {
        &[]
    }
    /// A parameter that is the largest slew rate of one of the plant's input profiles, as
    /// `(parameter index, input index)` (the pump's Qdot_max and its demand): a campaign's
    /// draw of it scales that input's trapezoids' slew by its ratio to the scenario's
    /// value. Default: none.
    fn slew_parameter(&self) -> Option<(usize, usize)> {
        None
    }
    /// The range the plant clips input `k` to (SI; default: none): a profile leaving it
    /// is warned of.
    fn input_range(&self, _k: usize) -> (f64, f64) {
        (f64::NEG_INFINITY, f64::INFINITY)
    }
    /// The largest slew rate and the peak a pulse profile of input `k` may have, in the
    /// input's display units per second and display units, each with what it is (the
    /// pump's demand: Qdot_max and the largest pump flow Q_l,max): a profile beyond them is
    /// an error. Default: none.
    fn input_profile_limits(&self, _k: usize) -> ProfileLimits {
        (None, None)
    }
    /// Input `k` at the plant's operating point (SI; default 0): what a PI on it adds
    /// when its settings give no bias.
    fn operating_input(&self, _k: usize) -> f64 {
        0.0
    }
    /// The first states a scenario's `[plant] initial` may give alone, at the values
    /// they take when it gives none (SI). Default: every state, at 0.
    fn initial_given(&self) -> Vec<f64> {
        vec![0.0; self.states().len()]
    }
    /// The whole state at t = 0 from the given states (SI, as many as
    /// [`Plant::initial_given`]) and the inputs at t = 0 (SI): a state not given (an
    /// actuator's) starts where its input puts it. Default: the given states.
    fn initial_state(&self, given: &[f64], _inputs0: &[f64]) -> Vec<f64> {
        given.to_vec()
    }
    /// Each state's bounds (SI; default unbounded): a run's figures clamp the solver's
    /// interpolant to them, and say whether every state stayed within.
    fn state_bounds(&self) -> Vec<(f64, f64)> {
        vec![(f64::NEG_INFINITY, f64::INFINITY); self.states().len()]
    }
    /// The plant's own solver defaults, where its runs want others than the runner's
    /// (`rtol` by experiment, 1e-9 on every state, no step limit); None: the runner's.
    fn solver_defaults(&self) -> Option<SolverDefaults> {
        None
    }
    /// The plant's settling time \[s\] (default 1 s): a regulated run's deviation counts
    /// as settled this long after each set-point change, and a step's overshoot is
    /// measured within it.
    fn settle_s(&self) -> f64 {
        1.0
    }
    /// A state's lower working limit (its index and the limit, SI; default none): a run's
    /// figures count the time below it (the pump's P_min on its pressure).
    fn floor(&self) -> Option<(usize, f64)> {
        None
    }
    /// The uncertain parameters with their nominal values and tolerances (default:
    /// none).
    fn parameters(&self) -> &'static [Parameter] {
        &[]
    }
    /// Drive input `k` by `input` from now on (a scenario's profile). Default: held
    /// values only, a profile is an error.
    fn set_input(&mut self, k: usize, input: Input) -> crate::Result<()> {
        match input {
            Input::Held(v) => {
                self.hold_input(k, v);
                Ok(())
            }
            Input::Signal(_) => Err(crate::error::invalid(
                format!("input.{}", self.inputs().get(k).map_or("?", |q| q.name)),
                "a profile",
                format!("plant `{}` takes held values only", self.name()),
            )),
        }
    }
    /// The same plant with its [`Plant::parameters`] set to `values` (display units, in
    /// that order): what scenarios and campaigns change. Default: a plant without
    /// parameters accepts an empty list only.
    fn with_parameters(&self, values: &[f64]) -> crate::Result<Self> {
        if values.len() == self.parameters().len() && values.is_empty() {
            Ok(self.clone())
        } else {
            Err(crate::error::invalid(
                "plant",
                format!("{} values", values.len()),
                format!(
                    "plant `{}` has {} parameters",
                    self.name(),
                    self.parameters().len()
                ),
            ))
        }
    }
}

/// A state or an input of a plant, by position: what an identifier reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SignalRef {
    /// State `i` of the plant.
    State(usize),
    /// Input `k` of the plant.
    Input(usize),
}

impl SignalRef {
    /// Find the state or input called `name` in `plant`'s lists.
    pub fn find<P: Plant>(plant: &P, name: &str) -> Option<SignalRef> {
        if let Some(i) = plant.states().iter().position(|q| q.name == name) {
            return Some(SignalRef::State(i));
        }
        plant
            .inputs()
            .iter()
            .position(|q| q.name == name)
            .map(SignalRef::Input)
    }

    /// Its description in `plant`.
    pub fn quantity<P: Plant>(self, plant: &P) -> &'static Quantity {
        match self {
            SignalRef::State(i) => &plant.states()[i],
            SignalRef::Input(k) => &plant.inputs()[k],
        }
    }

    /// Its name in the lists `states` and `inputs` (a plant's tables).
    pub fn name_in(self, states: &'static [Quantity], inputs: &'static [Quantity]) -> &'static str {
        match self {
            SignalRef::State(i) => states.get(i).map_or("?", |q| q.name),
            SignalRef::Input(k) => inputs.get(k).map_or("?", |q| q.name),
        }
    }

    /// The state's index, None for an input.
    pub fn state_index(self) -> Option<usize> {
        match self {
            SignalRef::State(i) => Some(i),
            SignalRef::Input(_) => None,
        }
    }

    /// Its value at `(t, x)` (`x` begins with the plant's states).
    #[inline(always)]
    pub fn value<P: Plant>(self, plant: &P, t: f64, x: &[f64]) -> f64 {
        match self {
            SignalRef::State(i) => x[i],
            SignalRef::Input(k) => plant.input_at(t, k),
        }
    }
}

/// Index of the state `name` among `states` of the plant `plant`, or an error naming
/// `field` and the plant's states.
pub fn state_named(plant: &str, states: &[Quantity], field: &str, name: &str) -> crate::Result<usize> {
    states.iter().position(|q| q.name == name).ok_or_else(|| {
        crate::error::invalid(
            field,
            format!("\"{name}\""),
            format!(
                "a state of the {plant}: {}",
                states.iter().map(|q| q.name).collect::<Vec<_>>().join(", ")
            ),
        )
    })
}
