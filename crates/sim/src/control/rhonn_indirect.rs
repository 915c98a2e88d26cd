//! RHONN indirect adaptive control of any plant whose measured output `y` obeys a
//! first-order, input-affine law `dy/dt = f(y) + g(y) u` with `g` of known sign (pump-model.md
//! section 4, thesis 4.5.2): one affine RHONN neuron identified online, its input gain
//! kept away from zero by a projection, and the certainty-equivalence law
//! `u = (-lambda (y - r) - W S(y)) / (W_1 S'(y))`.
//!
//! The neuron works on scaled signals (`y / y_scale`, `u / u_scale`) so that its weights
//! are of order one whatever the plant's units:
//! `dy^/dt = -a (y^ - y) + W S(y) + (W_1 S'(y)) u`, `S = [1, s(y)]`, `S' = [1, s(y) - 1/2]`,
//! with the filtered-error gradient laws `dW/dt = -Gamma e S`, `dW_1/dt = -Gamma_1 e S' u`.
//! For the first `identification_s` a gentle `lambda_ident` acts while the weights
//! learn; then the ball that keeps `W_1 S' > 0` is centred on the identified `W_1`.
//! [`super::RhonnCascade`] is the same design with an inner stroke loop, for the pump.
//!
//! Reference: Rovithakis, Christodoulou, *Adaptive Control with RHONNs*, 2000, ch. 3;
//! Ioannou, Sun, *Robust Adaptive Control*, 1996, section 8.5 (projection).

use super::adaptive::{AffineNeuron, L_DRIFT, L_GAIN};
use super::{AdaptiveView, Controller, LoopContext, LoopSettings};
use crate::error::{invalid, Result};
use crate::net::Sigmoid;
use serde::{Deserialize, Serialize};

/// Settings of [`RhonnIndirect`]; the defaults suit a plant whose scaled output moves by
/// about one unit in some seconds.
#[derive(Debug, Clone, PartialEq)]
pub struct IndirectSettings {
    /// Closed-loop pole lambda \[1/s\].
    pub lambda_per_s: f64,
    /// lambda during the identification phase \[1/s\].
    pub lambda_ident_per_s: f64,
    /// Length of the identification phase \[s\].
    pub identification_s: f64,
    /// Identifier filter pole a \[1/s\].
    pub observer_pole_per_s: f64,
    /// Learning rate of the drift weights W.
    pub gamma_w: f64,
    /// Learning rate of the gain weights W_1.
    pub gamma_w1: f64,
    /// Radius of W_1's ball as a fraction of the largest safe radius (< 1).
    pub ball_fraction: f64,
    /// The output's scale: the neuron sees `y / y_scale` (SI).
    pub y_scale: f64,
    /// The input's scale: the neuron sees `u / u_scale` (SI).
    pub u_scale: f64,
}

impl Default for IndirectSettings {
    fn default() -> Self {
        IndirectSettings {
            lambda_per_s: 1.0,
            lambda_ident_per_s: 0.2,
            identification_s: 10.0,
            observer_pole_per_s: 5.0,
            gamma_w: 5.0,
            gamma_w1: 5.0,
            ball_fraction: 0.5,
            y_scale: 1.0,
            u_scale: 1.0,
        }
    }
}

impl IndirectSettings {
    /// Settings from the closed-loop pole `lambda_per_s` and the output's scale
    /// `y_scale` (SI): a gentle pole `lambda / 4` during an identification phase of
    /// `2 / lambda`, the identifier's filter pole and both learning rates `2.5 lambda`
    /// (the identifier several times faster than the loop, in the neuron's scaled units).
    pub fn for_pole(lambda_per_s: f64, y_scale: f64) -> Self {
        IndirectSettings {
            lambda_per_s,
            lambda_ident_per_s: lambda_per_s / 4.0,
            identification_s: 2.0 / lambda_per_s,
            observer_pole_per_s: 2.5 * lambda_per_s,
            gamma_w: 2.5 * lambda_per_s,
            gamma_w1: 2.5 * lambda_per_s,
            ball_fraction: 0.5,
            y_scale,
            u_scale: 1.0,
        }
    }
}

/// The RHONN indirect adaptive controller of one input from one measured state.
#[derive(Debug, Clone)]
pub struct RhonnIndirect {
    /// Settings.
    pub settings: IndirectSettings,
    /// The neuron (scaled units).
    pub neuron: AffineNeuron<L_DRIFT, L_GAIN>,
    measured: [usize; 1],
    period_s: f64,
    u_min: f64,
    u_max: f64,
    prev: Option<(f64, f64)>,
    ball_set: bool,
    projections: u64,
}

impl RhonnIndirect {
    /// A controller of an input in `[u_min, u_max]` (SI) from plant state `measured`,
    /// sampled every `period_s`; `gain0` is a guess of `dy/du` (scaled units, per
    /// second) of the right sign, the weights' starting point; `y0` the first output.
    pub fn new(
        settings: IndirectSettings,
        measured: usize,
        (u_min, u_max): (f64, f64),
        period_s: f64,
        gain0: f64,
        y0: f64,
    ) -> Self {
        let neuron = AffineNeuron::new(
            settings.observer_pole_per_s,
            (settings.gamma_w, settings.gamma_w1),
            gain0,
            settings.ball_fraction,
            y0 / settings.y_scale,
        );
        RhonnIndirect {
            settings,
            neuron,
            measured: [measured],
            period_s,
            u_min,
            u_max,
            prev: None,
            ball_set: false,
            projections: 0,
        }
    }

    fn features(y: f64) -> ([f64; L_DRIFT], [f64; L_GAIN]) {
        let s = Sigmoid::LOGISTIC.eval(y);
        ([1.0, s], [1.0, s - 0.5])
    }
}

impl Controller for RhonnIndirect {
    fn name(&self) -> &'static str {
        "rhonn-indirect"
    }
    fn measurements(&self) -> &[usize] {
        &self.measured
    }
    fn control(&mut self, t: f64, measured: &[f64], setpoint: f64) -> f64 {
        let st = &self.settings;
        let (y, r) = (measured[0] / st.y_scale, setpoint / st.y_scale);
        // The identifier catches up over the last period (input held, output
        // interpolated), then the control law acts on the updated model.
        if let Some((y0, u0)) = self.prev {
            let projected = self
                .neuron
                .advance(self.period_s, 2, (y0, y), (u0, u0), true, Self::features);
            self.projections += projected as u64;
        }
        let identifying = t < st.identification_s;
        if !identifying && !self.ball_set {
            self.neuron.recentre(st.ball_fraction);
            self.ball_set = true;
        }
        let lambda = if identifying {
            st.lambda_ident_per_s
        } else {
            st.lambda_per_s
        };
        let (s, s1) = Self::features(y);
        let (f, g) = self.neuron.drift_and_gain(&s, &s1);
        let g = if g.abs() < 1e-9 { 1e-9f64.copysign(g) } else { g };
        let u = (((-lambda * (y - r) - f) / g) * st.u_scale).clamp(self.u_min, self.u_max);
        self.prev = Some((y, u / st.u_scale));
        u
    }
    fn adaptive(&self, t: f64) -> Option<AdaptiveView> {
        let identifying = t < self.settings.identification_s;
        let y_hat = self.neuron.xh * self.settings.y_scale;
        Some(AdaptiveView::of(
            &self.neuron,
            y_hat,
            None,
            identifying,
            self.projections,
        ))
    }
}

/// `kind = "rhonn-indirect"` in a scenario file: RHONN indirect adaptive control of a
/// first-order input-affine state; unset settings follow [`IndirectSettings::for_pole`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IndirectLoop {
    /// The state it measures.
    pub state: String,
    /// Closed-loop pole \[1/s\].
    pub lambda_per_s: f64,
    /// The state's scale for the neuron (display units).
    pub y_scale: f64,
    /// A guess of d(state)/d(output) in scaled units per second, of the right sign
    /// (default 0.01: the state rises with the output).
    #[serde(default)]
    pub gain0: Option<f64>,
    /// Identification phase \[s\] (default 2 / lambda).
    #[serde(default)]
    pub identification_s: Option<f64>,
    /// Learning rates of W and W_1 (default 2.5 lambda).
    #[serde(default)]
    pub gamma: Option<f64>,
    /// W_1's ball, fraction of the largest safe radius (default 0.5).
    #[serde(default)]
    pub ball_fraction: Option<f64>,
}

impl LoopSettings for IndirectLoop {
    fn state(&self) -> &str {
        &self.state
    }
    fn name(&self) -> &'static str {
        "rhonn-indirect"
    }
    fn build(&self, cx: &LoopContext) -> Result<Box<dyn Controller>> {
        let field = &cx.field;
        let i = cx.state_index("state", &self.state)?;
        let q = &cx.states[i];
        let mut st = IndirectSettings::for_pole(
            cx.positive("lambda_per_s", self.lambda_per_s)?,
            cx.positive("y_scale", self.y_scale)? / q.display_per_si,
        );
        if let Some(v) = self.identification_s {
            st.identification_s = cx.positive("identification_s", v)?;
        }
        if let Some(v) = self.gamma {
            st.gamma_w = cx.positive("gamma", v)?;
            st.gamma_w1 = st.gamma_w;
        }
        if let Some(v) = self.ball_fraction {
            if !(v > 0.0 && v < 1.0) {
                return Err(invalid(format!("{field}.ball_fraction"), v, "in (0, 1)"));
            }
            st.ball_fraction = v;
        }
        let g0 = self.gain0.unwrap_or(0.01);
        // Bounded so that the weights' norms stay finite (|gain0| near 1e308 overflowed them).
        if !(g0.is_finite() && g0 != 0.0 && g0.abs() <= 1e6) {
            return Err(invalid(
                format!("{field}.gain0"),
                g0,
                "a number not 0 of magnitude at most 1e6 (scaled units per second)",
            ));
        }
        Ok(Box::new(RhonnIndirect::new(
            st,
            i,
            cx.range,
            cx.period_s,
            g0,
            cx.x0[i],
        )))
    }
}
