//! `[solver]` of a scenario of any plant: the step-size control profile, the relative
//! tolerance, an absolute tolerance per plant state (by name, in SI units: a tolerance is
//! the solver's, which integrates in SI) and the largest step; checked against the plant
//! into [`Tolerances`], which build the solver's [`Options`]. Unset fields take the
//! runner's defaults ([`SolverDefaults`]) or, with `profile = "ode45"`, MATLAB's.

use crate::error::{invalid, Result};
use crate::plant::Quantity;
use crate::units::S_PER_MS;
use rhonn_ode::{Options, Profile, State};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Step-size control profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ProfileSpec {
    /// Hairer's DOPRI5 control (default), at the runner's tolerances.
    #[default]
    Hairer,
    /// MATLAB ode45's defaults and step control: RelTol 1e-3, AbsTol 1e-6 (SI) on every
    /// state, MaxStep span/10.
    Ode45,
    /// Simulink's variable-step ode45: as `ode45` but MaxStep span/50.
    SimulinkOde45,
}

/// `[solver]`: unset fields take the profile's defaults.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SolverSpec {
    /// Step-size control profile.
    pub profile: ProfileSpec,
    /// Relative tolerance (every state).
    pub rtol: Option<f64>,
    /// Absolute tolerance per plant state, by name, in SI units (`{ p_line = 1.0, stroke =
    /// 1e-9 }`: Pa and m); states not named take the default.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub atol_si: BTreeMap<String, f64>,
    /// Largest step \[ms\].
    pub max_step_ms: Option<f64>,
}

pub use crate::plant::SolverDefaults;

/// The absolute tolerance of a state no setting names (SI), and of the states a runner
/// adds to the plant's (an identifier's, a controller's).
pub const DEFAULT_ATOL: f64 = 1e-9;

/// Checked solver settings (SI): what a run's solver is built with.
#[derive(Debug, Clone, PartialEq)]
pub struct Tolerances {
    /// Profile.
    pub profile: ProfileSpec,
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance per plant state (SI), in the plant's order.
    pub atol: Vec<f64>,
    /// Largest step \[s\].
    pub max_step_s: f64,
}

impl Tolerances {
    /// The defaults `d` as they are, for a plant of `n_states` states.
    pub fn of_defaults(d: &SolverDefaults, n_states: usize) -> Self {
        Tolerances {
            profile: ProfileSpec::Hairer,
            rtol: d.rtol,
            atol: (0..n_states)
                .map(|i| d.atol.get(i).copied().unwrap_or(DEFAULT_ATOL))
                .collect(),
            max_step_s: d.max_step_s,
        }
    }

    /// The solver's options for a system of `dim` states whose first are the plant's;
    /// the others (an identifier's, a controller's) at [`DEFAULT_ATOL`].
    pub fn options<S: State>(&self, dim: usize) -> Options<S> {
        let mut o = Options::<S>::uniform(dim, self.rtol, DEFAULT_ATOL);
        for (a, v) in o.atol.as_mut_slice().iter_mut().zip(&self.atol) {
            *a = *v;
        }
        o.h_max_s = self.max_step_s;
        o.profile = match self.profile {
            ProfileSpec::Hairer => Profile::Hairer,
            ProfileSpec::Ode45 | ProfileSpec::SimulinkOde45 => Profile::Ode45,
        };
        o
    }
}

impl SolverSpec {
    /// The tolerances for a run of `duration_s` of a plant with `states` (named `plant` in
    /// errors), unset fields from the profile or `defaults`; every failure names the field,
    /// the value and what is allowed.
    pub fn check(
        &self,
        plant: &str,
        states: &[Quantity],
        defaults: &SolverDefaults,
        duration_s: f64,
    ) -> Result<Tolerances> {
        let mut t = Tolerances::of_defaults(defaults, states.len());
        t.profile = self.profile;
        let span = match self.profile {
            ProfileSpec::Hairer => None,
            ProfileSpec::Ode45 => Some(0.1 * duration_s),
            ProfileSpec::SimulinkOde45 => Some(duration_s / 50.0),
        };
        if let Some(h) = span {
            (t.rtol, t.max_step_s) = (1e-3, h);
            t.atol.iter_mut().for_each(|a| *a = 1e-6);
        }
        t.rtol = self.rtol.unwrap_or(t.rtol);
        if !(1e-13..0.1).contains(&t.rtol) {
            return Err(invalid("solver.rtol", t.rtol, "a number in [1e-13, 0.1)"));
        }
        for (name, v) in &self.atol_si {
            let field = format!("solver.atol_si.{name}");
            let i = crate::plant::state_named(plant, states, &field, name)?;
            if !(v.is_finite() && *v > 0.0) {
                return Err(invalid(
                    field,
                    v,
                    format!("a number > 0 ({}, the state's SI unit)", states[i].unit),
                ));
            }
            t.atol[i] = *v;
        }
        if let Some(ms) = self.max_step_ms {
            t.max_step_s = ms * S_PER_MS;
        }
        // At most 10,000,000 steps of the largest size over the run: a smaller bound ran
        // until the solver's step budget failed it, naming no setting.
        let min_step_s = duration_s / 1e7;
        if t.max_step_s.is_nan() || t.max_step_s < min_step_s {
            return Err(invalid(
                "solver.max_step_ms",
                crate::metrics::sig(t.max_step_s / S_PER_MS, 6),
                format!(
                    "a number of ms of at least {} (duration_s / 10,000,000 steps)",
                    crate::metrics::sig(min_step_s / S_PER_MS, 3)
                ),
            ));
        }
        Ok(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const STATES: [Quantity; 2] = [Quantity::si("a", "m", "one"), Quantity::si("b", "Pa", "two")];

    #[test]
    fn named_states_take_their_tolerance_and_the_rest_the_default() {
        let spec: SolverSpec =
            toml::from_str("rtol = 1e-5\natol_si = { b = 0.5 }\nmax_step_ms = 20.0").unwrap();
        let t = spec
            .check("test", &STATES, &SolverDefaults::plant(1e-7), 10.0)
            .unwrap();
        assert_eq!(
            (t.rtol, t.atol.clone(), t.max_step_s),
            (1e-5, vec![DEFAULT_ATOL, 0.5], 0.02)
        );
        // An identifier's states after the plant's keep the default.
        let o = t.options::<Vec<f64>>(4);
        assert_eq!(o.atol, vec![DEFAULT_ATOL, 0.5, DEFAULT_ATOL, DEFAULT_ATOL]);
        assert_eq!(o.rtol, vec![1e-5; 4]);
    }

    #[test]
    fn the_ode45_profiles_take_matlab_s_defaults_and_set_fields_override_them() {
        let d = SolverDefaults::plant(1e-7);
        let ode45: SolverSpec = toml::from_str("profile = \"ode45\"").unwrap();
        let t = ode45.check("test", &STATES, &d, 10.0).unwrap();
        assert_eq!((t.rtol, t.atol.clone(), t.max_step_s), (1e-3, vec![1e-6; 2], 1.0));
        assert_eq!(t.options::<Vec<f64>>(2).profile, Profile::Ode45);
        let simulink: SolverSpec =
            toml::from_str("profile = \"simulink-ode45\"\natol_si = { a = 1e-4 }").unwrap();
        let t = simulink.check("test", &STATES, &d, 10.0).unwrap();
        assert_eq!((t.atol.clone(), t.max_step_s), (vec![1e-4, 1e-6], 0.2));
        // Nothing set: the runner's defaults as they are.
        let t = SolverSpec::default().check("test", &STATES, &d, 10.0).unwrap();
        assert_eq!(t, Tolerances::of_defaults(&d, 2));
    }
}
