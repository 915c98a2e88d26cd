//! The solenoid-controlled variable-displacement pump feeding a hydraulic line
//! (`docs/pump-model.md` section 1): states `[P_l, x, i]`, inputs
//! `[current, demand]`.

mod parameters;
mod params;
mod system;

pub use super::Input;
pub use params::{PumpParams, PumpParamsSpec};
pub use system::{Pilot, PumpSystem, CURRENT_EFF, PLANT_DIM, PUMP_EVENTS, P_LINE, STROKE};

use super::{Parameter, Plant, Quantity};
use crate::units::M3_PER_DM3;

/// The largest steady pump flow of the thesis, Q_l,max = 2.1 dm^3/s (its eq. (1)):
/// demanded-flow peaks must stay below it.
pub const Q_L_MAX_DM3_S: f64 = 2.1;

/// The pump's states, in state order.
pub const STATES: [Quantity; PLANT_DIM] = [
    Quantity {
        name: "p_line",
        unit: "Pa",
        display_unit: "MPa",
        display_per_si: 1e-6,
        description: "line pressure P_l, a limited integrator on [0, P_max]",
    },
    Quantity {
        name: "stroke",
        unit: "m",
        display_unit: "mm",
        display_per_si: 1e3,
        description: "pump stroke x, a limited integrator on [0, x_max]",
    },
    Quantity {
        name: "current_eff",
        unit: "A",
        display_unit: "A",
        display_per_si: 1.0,
        description: "the current the solenoid carries (the commanded one through the solenoid's lag)",
    },
];

/// The pump's inputs.
pub const INPUTS: [Quantity; 2] = [
    Quantity {
        name: "current",
        unit: "A",
        display_unit: "A",
        display_per_si: 1.0,
        description: "commanded solenoid current, clipped to [0, i_max]",
    },
    Quantity {
        name: "demand",
        unit: "m^3/s",
        display_unit: "dm^3/s",
        display_per_si: 1e3,
        description: "flow the load draws from the line",
    },
];

pub use parameters::PARAMETERS;

/// The largest slew rate of the demanded flow, +-10 % in the thesis's table: it bounds
/// the pump scenarios' demand profiles (their campaigns draw it after the four uncertain
/// parameters of the model).
pub const DEMAND_SLEW: Parameter = PARAMETERS[4];

/// What a pump campaign draws: the uncertain ones of [`PARAMETERS`] (the first five).
pub const CAMPAIGN_PARAMETERS: [Parameter; 5] = [
    PARAMETERS[0],
    PARAMETERS[1],
    PARAMETERS[2],
    PARAMETERS[3],
    DEMAND_SLEW,
];

/// The pump's settling time \[s\] ([`Plant::settle_s`]): deviations from the set-point are
/// judged this long after each set-point change (the start counts as one) for the settled
/// deviation, and each step's overshoot within it.
pub const SETTLE_S: f64 = 1.0;

/// The pump's solver defaults, the thesis's: rtol 1e-6, atol 1 Pa and 1e-9 m (the
/// current: 1e-9 A), largest step 100 ms, for every experiment.
pub fn solver_defaults() -> super::SolverDefaults {
    super::SolverDefaults {
        rtol: 1e-6,
        atol: vec![1.0, 1e-9],
        max_step_s: 0.1,
    }
}

impl Plant for PumpSystem {
    fn name(&self) -> &'static str {
        "pump"
    }
    fn states(&self) -> &'static [Quantity] {
        &STATES
    }
    fn inputs(&self) -> &'static [Quantity] {
        &INPUTS
    }
    fn measured(&self) -> &'static [usize] {
        &[P_LINE, STROKE]
    }
    #[inline(always)]
    fn input_at(&self, t: f64, k: usize) -> f64 {
        if k == 0 {
            self.current_at(t)
        } else {
            self.demand_at(t)
        }
    }
    fn hold_input(&mut self, k: usize, value: f64) {
        if k == 0 {
            self.set_current(value);
        } else {
            self.set_demand(value);
        }
    }
    fn parameters(&self) -> &'static [Parameter] {
        &PARAMETERS
    }
    /// Qdot_max ([`DEMAND_SLEW`], the fifth parameter) bounds the demand's slew.
    fn slew_parameter(&self) -> Option<(usize, usize)> {
        Some((4, 1))
    }
    /// The solenoid's effective current: the model's, not a measurement.
    fn internal_states(&self) -> &'static [usize] {
        &[CURRENT_EFF]
    }
    /// The current within [0, i_max] (the solenoid's driver clips it); the demand a flow
    /// out of the line, >= 0 (a profile below is clipped there by the runner).
    fn input_range(&self, k: usize) -> (f64, f64) {
        if k == 0 {
            (0.0, self.params.i_max)
        } else {
            (0.0, f64::INFINITY)
        }
    }
    /// The demand's pulses: their slew at most Qdot_max, their peaks below the largest
    /// steady pump flow Q_l,max ([`Q_L_MAX_DM3_S`]; the thesis's eq. (1)).
    fn input_profile_limits(&self, k: usize) -> super::ProfileLimits {
        if k == 1 {
            (
                Some((
                    self.params.qdot_max / M3_PER_DM3,
                    "Qdot_max of the plant, dm^3/s^2",
                )),
                Some((Q_L_MAX_DM3_S, "the max pump flow Q_l,max, dm^3/s")),
            )
        } else {
            (None, None)
        }
    }
    /// The balance current ([`PumpParams::balance_current`]) and no demand.
    fn operating_input(&self, k: usize) -> f64 {
        if k == 0 {
            self.params.balance_current()
        } else {
            0.0
        }
    }
    /// The pressure within [0, P_max], the stroke within [0, x_max], the current free.
    fn state_bounds(&self) -> Vec<(f64, f64)> {
        let p = &self.params;
        vec![(0.0, p.p_max), (0.0, p.x_max), (f64::NEG_INFINITY, f64::INFINITY)]
    }
    /// [`solver_defaults`].
    fn solver_defaults(&self) -> Option<super::SolverDefaults> {
        Some(solver_defaults())
    }
    /// [`SETTLE_S`]: the thesis's settling window after a set-point step.
    fn settle_s(&self) -> f64 {
        SETTLE_S
    }
    /// P_min on the pressure: below it the lubrication fails.
    fn floor(&self) -> Option<(usize, f64)> {
        Some((P_LINE, self.params.p_min))
    }
    /// The line pressure and the stroke (2 MPa and 0 mm when none are given): the
    /// solenoid's current starts at the current input.
    fn initial_given(&self) -> Vec<f64> {
        vec![2e6, 0.0]
    }
    fn initial_state(&self, given: &[f64], inputs0: &[f64]) -> Vec<f64> {
        let mut x = given.to_vec();
        if x.len() == 2 {
            x.push(inputs0.first().map_or(0.0, |i| i.clamp(0.0, self.params.i_max)));
        }
        x
    }
    fn set_input(&mut self, k: usize, input: Input) -> crate::Result<()> {
        let (current, demand) = match k {
            0 => (input, self.demand.clone()),
            1 => (self.current.clone(), input),
            _ => return Err(crate::error::invalid("input", k, "0 (current) or 1 (demand)")),
        };
        *self = PumpSystem::new(self.params.clone(), current, demand);
        Ok(())
    }
    /// [`PARAMETERS`]' values (display units), checked as a scenario's `[plant]` is.
    fn with_parameters(&self, values: &[f64]) -> crate::Result<Self> {
        let params = PumpParamsSpec::from_values(values)?.check()?;
        Ok(PumpSystem::new(params, self.current.clone(), self.demand.clone()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tolerance_table_holds_the_default_values() {
        let d = PumpParamsSpec::default();
        let by_name = |n: &str| match n {
            "beta_mpa" => d.beta_mpa,
            "mu_1" => d.mu_1,
            "mu_2" => d.mu_2,
            "q_0_dm3_s" => d.q_0_dm3_s,
            "qdot_max_dm3_s2" => d.qdot_max_dm3_s2,
            other => panic!("{other} is not a pump parameter"),
        };
        for p in CAMPAIGN_PARAMETERS {
            assert_eq!(p.nominal, by_name(p.name), "{}", p.name);
        }
    }
}
