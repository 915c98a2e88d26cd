//! The pump's classical controllers as a scenario names them: their settings and
//! controllers are the registry's (`control::PiLoop`, `control::PumpCascadePiLoop`,
//! `control::PumpAdaptiveLoop`); here are the cascade PI's tunings found by `rhonn-study`,
//! the baseline an adaptive run is compared with (`[control.baseline]`, the robust cascade
//! PI when unset), and [`PumpLoop`], a loop of the pump's runner built by the registry.

use super::scenario::ControlSpec;
pub use crate::control::{CascadePiGainsMpa, NOMINAL_OPTIMAL, ROBUST};
use crate::control::{Controller, LoopContext, LoopSpec, PiLoop};
use crate::error::{invalid, Result};
use crate::plant::PumpParams;
use crate::signal::Signal;

/// The baseline of the adaptive controller of `c`: its `[control.baseline]` (`lower`
/// admits the cascade PI, or the PI on `p_line` without a bias), else the cascade PI's
/// robust tuning.
pub(crate) fn adaptive_baseline(c: &ControlSpec) -> LoopSpec {
    c.baseline.clone().unwrap_or_else(|| ROBUST.loop_spec())
}

/// The cascade PI with a named tuning (`nominal-optimal` or `robust`): a second baseline.
pub(super) fn named_cascade_pi(name: &str) -> Result<(&'static str, LoopSpec)> {
    match name {
        "nominal-optimal" => Ok(("nominal-optimal", NOMINAL_OPTIMAL.loop_spec())),
        "robust" => Ok(("robust", ROBUST.loop_spec())),
        other => Err(invalid(
            "control.second_baseline",
            format!("\"{other}\""),
            "\"nominal-optimal\" or \"robust\" (a tuning of the cascade PI)",
        )),
    }
}

/// One closed loop of the pump's runner: the controller as the scenario names it, built
/// by the controller registry on the pump's states, driving the current in `[0, i_max]`
/// every `t_control`; its set-point \[Pa\], the current at t = 0 \[A\] and a dither
/// added to the current \[A\].
#[derive(Debug, Clone, PartialEq)]
pub struct PumpLoop {
    /// Set-point \[Pa\].
    pub setpoint: Signal,
    /// The controller (a PI's unset bias set to [`PumpLoop::bias`]).
    pub controller: LoopSpec,
    /// The current at t = 0 \[A\]: a PI's bias, else the one whose steady stroke gives the
    /// flow Q_0.
    pub bias: f64,
    /// Excitation added to the current \[A\] (a PI's only).
    pub dither: Option<Signal>,
    /// Where it sits in the scenario (`control.controller`, `control.baseline`, ...).
    field: String,
}

impl PumpLoop {
    /// The loop of `controller` at `field`, checked by building it once on the plant of
    /// `params` from the state `x0` (SI).
    pub(crate) fn new(
        setpoint: Signal,
        mut controller: LoopSpec,
        params: &PumpParams,
        x0: &[f64],
        field: &str,
    ) -> Result<Self> {
        let balance = params.balance_current();
        let bias = match &mut controller {
            LoopSpec::Pi(PiLoop { bias, .. }) => *bias.get_or_insert(balance),
            _ => balance,
        };
        let l = PumpLoop {
            setpoint,
            controller,
            bias,
            dither: None,
            field: field.to_string(),
        };
        l.build(params, x0)?;
        Ok(l)
    }

    /// Its name in reports (`pi`, `cascade-pi`, `rhonn-adaptive`).
    pub fn name(&self) -> &'static str {
        self.controller.name()
    }

    /// The controller, on the plant of `params` from the state `x0` (SI).
    pub(crate) fn build(&self, params: &PumpParams, x0: &[f64]) -> Result<Box<dyn Controller>> {
        let cx = LoopContext {
            plant: "pump",
            states: &crate::plant::pump::STATES,
            field: self.field.clone(),
            output: &crate::plant::pump::INPUTS[0],
            range: (0.0, params.i_max),
            period_s: params.t_control,
            setpoint0: self.setpoint.eval(0.0),
            x0,
            operating_input: params.balance_current(),
        };
        self.controller.build(&cx)
    }
}
