//! PI pressure regulator with anti-windup: the baseline every adaptive controller is
//! compared with. The law is `rhonn_core::pi::AntiWindupPi` (the same on a
//! microcontroller); here it becomes a [`Controller`] with a measured state (a dither
//! is the loop's, `experiment::LoopConditions`, not the controller's).

use super::{Controller, LoopContext, LoopSettings};
use crate::error::{invalid, Result};
pub use rhonn_core::pi::AntiWindupPi;
use serde::{Deserialize, Serialize};

/// A discrete PI regulator `u = bias + kp e + ki sum(e T)`, output clipped to
/// `[u_min, u_max]`. Anti-windup by conditional integration: the integral does not
/// grow while the output is saturated and the error pushes further into saturation.
///
/// Units are the caller's; the pump uses Pa in and A out.
#[derive(Debug, Clone, PartialEq)]
pub struct Pi {
    /// The law: gains, period, bias, output range and the integral.
    pub law: AntiWindupPi,
    /// The plant state it measures (default 0).
    pub measured: [usize; 1],
}

impl Pi {
    /// A PI with gain `kp`, integral time `ti_s`, period `period_s`, output `bias`
    /// and range `[u_min, u_max]`, measuring state 0.
    pub fn new(kp: f64, ti_s: f64, period_s: f64, bias: f64, u_min: f64, u_max: f64) -> Self {
        Pi {
            law: AntiWindupPi::new(kp, ti_s, period_s, bias, u_min, u_max),
            measured: [0],
        }
    }

    /// One period: the output for `reference` and `measured` (without the dither).
    pub fn update(&mut self, reference: f64, measured: f64) -> f64 {
        self.law.update(reference, measured)
    }

    /// The integral part.
    pub fn integral(&self) -> f64 {
        self.law.integral()
    }
}

impl Controller for Pi {
    fn name(&self) -> &'static str {
        "pi"
    }
    fn measurements(&self) -> &[usize] {
        &self.measured
    }
    fn control(&mut self, _t: f64, measured: &[f64], setpoint: f64) -> f64 {
        self.update(setpoint, measured[0])
    }
}

/// `kind = "pi"` in a scenario file: a PI with anti-windup on one measured state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PiLoop {
    /// The state it measures.
    pub state: String,
    /// Gain (display unit of the output per display unit of the state).
    pub kp: f64,
    /// Integral time \[s\].
    pub ti_s: f64,
    /// Output offset (display units; default the plant's operating input: 0 for the
    /// tanks' voltage, for the pump's current the one whose steady stroke balances the
    /// lubricating flow).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bias: Option<f64>,
}

impl LoopSettings for PiLoop {
    fn state(&self) -> &str {
        &self.state
    }
    fn name(&self) -> &'static str {
        "pi"
    }
    fn bias(&self) -> Option<f64> {
        self.bias
    }
    fn build(&self, cx: &LoopContext) -> Result<Box<dyn Controller>> {
        let field = &cx.field;
        let i = cx.state_index("state", &self.state)?;
        let q = &cx.states[i];
        let out = cx.output;
        let (kp, bias) = (
            self.kp,
            self.bias.unwrap_or(cx.operating_input * out.display_per_si),
        );
        if !kp.is_finite() {
            return Err(invalid(format!("{field}.kp"), kp, "a finite number"));
        }
        let ti = cx.positive("ti_s", self.ti_s)?;
        let (lo, hi) = (cx.range.0 * out.display_per_si, cx.range.1 * out.display_per_si);
        if !(bias.is_finite() && lo.min(hi) <= bias && bias <= hi.max(lo)) {
            return Err(invalid(
                format!("{field}.bias"),
                bias,
                format!("a number within the loop's output range [{lo}, {hi}]"),
            ));
        }
        let kp_si = kp * q.display_per_si / out.display_per_si;
        let mut pi = Pi::new(
            kp_si,
            ti,
            cx.period_s,
            bias / out.display_per_si,
            cx.range.0,
            cx.range.1,
        );
        pi.measured = [i];
        Ok(Box::new(pi))
    }
}
