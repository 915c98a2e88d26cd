//! RHONN indirect adaptive control of the pump (pump-model.md section 4, thesis 4.5.2):
//! the affine neuron, the cascade and its settings live in `rhonn_core::adaptive` (the
//! very code that runs on a microcontroller, see `embedded/`); here they become a
//! [`Controller`] of the library's runs.

use super::{AdaptiveView, Controller, LoopContext, LoopSettings};
use crate::error::{invalid, Result};
use crate::plant::{PumpParams, P_LINE, STROKE};
pub use rhonn_core::adaptive::{
    AffineNeuron, CascadeSettings, CascadeState, RhonnCascade, INTEGRAL_BAND_MPA, L_DRIFT, L_GAIN,
};
use serde::{Deserialize, Serialize};

impl AdaptiveView {
    /// The view of a controller built on `neuron`.
    pub fn of(
        neuron: &AffineNeuron<L_DRIFT, L_GAIN>,
        model_output: f64,
        inner_reference: Option<f64>,
        identifying: bool,
        projections: u64,
    ) -> Self {
        AdaptiveView {
            model_output,
            inner_reference,
            w_norm: neuron.w_norm(),
            w1_norm: neuron.w1_norm(),
            identifying,
            w1_distance: neuron.w1_distance(),
            ball_radius: neuron.radius,
            w_bound: neuron.w_bound,
            w1: neuron.w1,
            projections,
            actuator: None,
        }
    }
}

impl Controller for RhonnCascade {
    fn name(&self) -> &'static str {
        "rhonn-adaptive"
    }
    fn measurements(&self) -> &[usize] {
        &[P_LINE, STROKE]
    }
    fn control(&mut self, t: f64, measured: &[f64], setpoint: f64) -> f64 {
        self.update(t, measured[0], measured[1], setpoint)
    }
    fn inner_reference(&self) -> Option<f64> {
        Some(self.state().stroke_ref)
    }
    fn adaptive(&self, t: f64) -> Option<AdaptiveView> {
        let identifying = t < self.settings.identification_s;
        let mut view = AdaptiveView::of(
            &self.neuron,
            self.neuron.xh * 1e6,
            Some(self.state().stroke_ref),
            identifying,
            self.projections(),
        );
        view.actuator = self.actuator();
        Some(view)
    }
}

/// The pump's adaptive cascade from the **nominal** table (the controller does not know the
/// plant's deviations), its gain weights starting from `beta k_l omega / V_l` at the
/// set-point `p_ref0` \[Pa\] (MPa/(s mm)); current up to `i_max` \[A\], stroke up to
/// `x_max` \[m\], pressure up to `p_max` \[Pa\], sampled every `period_s`, the pressure
/// starting at `p0` \[Pa\].
pub fn pump_cascade(
    settings: CascadeSettings,
    (i_max, x_max, p_max): (f64, f64, f64),
    period_s: f64,
    p_ref0: f64,
    p0: f64,
) -> RhonnCascade {
    let n = PumpParams::default();
    let gain = n.beta * n.k_l * n.omega / (n.v_l0 * (1.0 + n.alpha_v * p_ref0)) * 1e-9; // Pa/(s m) -> MPa/(s mm)
    RhonnCascade::new(settings, n.k_a, n.phi, i_max, x_max, p_max, period_s, gain, p0)
}

/// `kind = "pump-rhonn-adaptive"` in a plant scenario of the pump (`[plant] kind =
/// "pump"`): the pump's RHONN adaptive cascade, measuring the line pressure and the
/// stroke, driving the current; every setting optional (the defaults of
/// [`CascadeSettings`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PumpAdaptiveLoop {
    /// The regulated state: `p_line`.
    pub state: String,
    /// Closed-loop pressure pole lambda \[1/s\].
    #[serde(default)]
    pub lambda_per_s: Option<f64>,
    /// lambda during the identification phase \[1/s\].
    #[serde(default)]
    pub lambda_ident_per_s: Option<f64>,
    /// Identification phase \[s\].
    #[serde(default)]
    pub identification_s: Option<f64>,
    /// Stroke feedback gain g.
    #[serde(default)]
    pub stroke_gain: Option<f64>,
    /// Lead on the stroke reference \[s\].
    #[serde(default)]
    pub lead_s: Option<f64>,
    /// Identifier filter pole a \[1/s\].
    #[serde(default)]
    pub observer_pole_per_s: Option<f64>,
    /// Learning rate of the drift weights.
    #[serde(default)]
    pub gamma_w: Option<f64>,
    /// Learning rate of the gain weights.
    #[serde(default)]
    pub gamma_w1: Option<f64>,
    /// The gain weights' ball, a fraction of the largest safe radius.
    #[serde(default)]
    pub ball_fraction: Option<f64>,
    /// Integral action \[1/s^2\].
    #[serde(default)]
    pub integral_per_s2: Option<f64>,
    /// Memory of the actuator's online identification \[s\].
    #[serde(default)]
    pub actuator_memory_s: Option<f64>,
    /// The stroke gain's scale for an identified lag \[s\].
    #[serde(default)]
    pub lag_scale_s: Option<f64>,
}

impl PumpAdaptiveLoop {
    /// The checked settings, each unset one from [`CascadeSettings::default`]; errors name
    /// `<prefix>.<key>`.
    pub fn check(&self, prefix: &str) -> Result<CascadeSettings> {
        let d = CascadeSettings::default();
        let pos = |name: &str, v: Option<f64>, default: f64| -> Result<f64> {
            let v = v.unwrap_or(default);
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(invalid(format!("{prefix}.{name}"), v, "a finite number > 0"))
            }
        };
        let non_neg = |name: &str, v: Option<f64>, default: f64| -> Result<f64> {
            let v = v.unwrap_or(default);
            if v.is_finite() && v >= 0.0 {
                Ok(v)
            } else {
                Err(invalid(format!("{prefix}.{name}"), v, "a finite number >= 0"))
            }
        };
        let cascade = CascadeSettings {
            lambda_per_s: pos("lambda_per_s", self.lambda_per_s, d.lambda_per_s)?,
            lambda_ident_per_s: pos(
                "lambda_ident_per_s",
                self.lambda_ident_per_s,
                d.lambda_ident_per_s,
            )?,
            identification_s: non_neg("identification_s", self.identification_s, d.identification_s)?,
            stroke_gain: non_neg("stroke_gain", self.stroke_gain, d.stroke_gain)?,
            lead_s: non_neg("lead_s", self.lead_s, d.lead_s)?,
            observer_pole_per_s: pos(
                "observer_pole_per_s",
                self.observer_pole_per_s,
                d.observer_pole_per_s,
            )?,
            gamma_w: non_neg("gamma_w", self.gamma_w, d.gamma_w)?,
            gamma_w1: non_neg("gamma_w1", self.gamma_w1, d.gamma_w1)?,
            ball_fraction: self.ball_fraction.unwrap_or(d.ball_fraction),
            p_scale_mpa: d.p_scale_mpa,
            integral_per_s2: non_neg("integral_per_s2", self.integral_per_s2, d.integral_per_s2)?,
            actuator_memory_s: non_neg("actuator_memory_s", self.actuator_memory_s, d.actuator_memory_s)?,
            lag_scale_s: non_neg("lag_scale_s", self.lag_scale_s, d.lag_scale_s)?,
        };
        if !(cascade.ball_fraction > 0.0 && cascade.ball_fraction < 1.0) {
            return Err(invalid(
                format!("{prefix}.ball_fraction"),
                cascade.ball_fraction,
                "a number in (0, 1) (1 would let W_1 S' reach zero)",
            ));
        }
        Ok(cascade)
    }
}

/// The pump's pressure and stroke among `cx`'s states, or an error naming the field.
pub(crate) fn pump_states(cx: &LoopContext, state: &str) -> Result<()> {
    let (p, x) = (
        cx.state_index("state", state)?,
        cx.state_index("state", "stroke")?,
    );
    if (p, x) != (P_LINE, STROKE) {
        return Err(invalid(
            format!("{}.state", cx.field),
            format!("\"{state}\""),
            "\"p_line\" of the pump (`[plant] kind = \"pump\"`): the pump's controllers measure its pressure and stroke",
        ));
    }
    if cx.output.name != "current" {
        return Err(invalid(
            "control.input",
            format!("\"{}\"", cx.output.name),
            "\"current\" (the pump's controllers drive the solenoid)",
        ));
    }
    Ok(())
}

impl LoopSettings for PumpAdaptiveLoop {
    fn state(&self) -> &str {
        &self.state
    }
    fn name(&self) -> &'static str {
        "rhonn-adaptive"
    }
    /// The stroke: its outer loop sets the stroke's reference.
    fn inner_state(&self) -> Option<&str> {
        Some("stroke")
    }
    /// The cascade PI in its robust tuning, with the same sensors (on this state).
    fn default_baseline(&self) -> Option<super::LoopSpec> {
        match super::ROBUST.loop_spec() {
            super::LoopSpec::PumpCascadePi(l) => {
                Some(super::LoopSpec::PumpCascadePi(super::PumpCascadePiLoop {
                    state: self.state.clone(),
                    ..l
                }))
            }
            other => Some(other),
        }
    }
    fn build(&self, cx: &LoopContext) -> Result<Box<dyn Controller>> {
        pump_states(cx, &self.state)?;
        let settings = self.check(&cx.field)?;
        if !cx.setpoint0.is_finite() {
            return Err(invalid(
                format!("{}.kind", cx.field),
                "pump-rhonn-adaptive",
                "an outer loop (it needs the pressure set-point)",
            ));
        }
        // The controller knows the nominal table's stroke and pressure limits.
        let n = PumpParams::default();
        Ok(Box::new(pump_cascade(
            settings,
            (cx.range.1, n.x_max, n.p_max),
            cx.period_s,
            cx.setpoint0,
            cx.x0[P_LINE],
        )))
    }
}
