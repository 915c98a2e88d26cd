//! The parameters of table 3.3 of the thesis (pump-model.md section 1): SI values for the
//! code, a display-unit spec for scenario files, and the stated uncertainties.

use crate::error::{invalid, Result};
use crate::units::*;
use serde::{Deserialize, Serialize};

/// Pump and line parameters in SI units. Build with [`PumpParams::default`] (the
/// thesis's values) or from a [`PumpParamsSpec`].
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct PumpParams {
    /// Line volume at zero pressure V_l0 \[m^3\].
    pub v_l0: f64,
    /// Bulk modulus beta \[Pa\].
    pub beta: f64,
    /// Volume variation rate alpha_v \[1/Pa\].
    pub alpha_v: f64,
    /// Maximum line pressure P_max \[Pa\].
    pub p_max: f64,
    /// Maximum slew rate of the demanded flow Qdot_max \[m^3/s^2\].
    pub qdot_max: f64,
    /// Pump gain k_l \[m^2\].
    pub k_l: f64,
    /// Pump angular rate omega \[rad/s\].
    pub omega: f64,
    /// Lubricating flow Q_0 \[m^3/s\].
    pub q_0: f64,
    /// Largest solenoid current \[A\] (the range is 0 to this).
    pub i_max: f64,
    /// Piston area A_a \[m^2\].
    pub a_a: f64,
    /// Control time unit T \[s\].
    pub t_control: f64,
    /// Maximum pump stroke x_max \[m\].
    pub x_max: f64,
    /// Flow aperture coefficient mu_1 \[m^2/s/sqrt(Pa)\].
    pub mu_1: f64,
    /// Second-order aperture coefficient mu_2 \[m/s/sqrt(Pa)\].
    pub mu_2: f64,
    /// Solenoid gain phi \[N/A\].
    pub phi: f64,
    /// Pilot valve spring stiffness K_c \[N/m\].
    pub k_c: f64,
    /// Feedback spring stiffness K_a \[N/m\].
    pub k_a: f64,
    /// Bias spring stiffness K \[N/m\].
    pub k: f64,
    /// Bias force F_u \[N\].
    pub f_u: f64,
    /// Line pressure fraction gamma_l \[-\].
    pub gamma_l: f64,
    /// Bias pressure P_0 \[Pa\].
    pub p_0: f64,
    /// Minimum line pressure of the model's validity P_min \[Pa\].
    pub p_min: f64,
    /// Time constant of a first-order lag on the solenoid current \[s\] (0: none). An
    /// unmodeled dynamic for robustness studies (pump-model.md section 3).
    pub solenoid_lag: f64,
    /// Transport delay between a controller's output and the solenoid, in control
    /// periods (0: none). An unmodeled dynamic for robustness studies.
    pub delay_periods: u32,
}

impl Default for PumpParams {
    fn default() -> Self {
        PumpParamsSpec::default()
            .check()
            .expect("the thesis's parameters are valid")
    }
}

impl PumpParams {
    /// The current \[A\] whose steady stroke balances the lubricating flow `q_0` with no
    /// demand: the pump's operating input ([`crate::plant::Plant::operating_input`], a
    /// pressure PI's bias when none is given).
    pub fn balance_current(&self) -> f64 {
        self.k_a * self.q_0 / (self.k_l * self.omega * self.phi)
    }

    /// The coefficients of the pump's equations (`rhonn_core::pump`).
    #[inline(always)]
    pub fn equations(&self) -> rhonn_core::pump::PumpEquations {
        rhonn_core::pump::PumpEquations {
            v_l0: self.v_l0,
            beta: self.beta,
            alpha_v: self.alpha_v,
            k_l: self.k_l,
            omega: self.omega,
            q_0: self.q_0,
            a_a: self.a_a,
            mu_1: self.mu_1,
            mu_2: self.mu_2,
            phi: self.phi,
            k_c: self.k_c,
            k_a: self.k_a,
            k: self.k,
            f_u: self.f_u,
            gamma_l: self.gamma_l,
            p_0: self.p_0,
        }
    }
    /// Steady-state stroke at current `i` (s = 0): phi I / K_a \[m\].
    pub fn steady_stroke(&self, i: f64) -> f64 {
        self.phi * i / self.k_a
    }
    /// Pump flow k_l omega x \[m^3/s\] at stroke `x`.
    pub fn pump_flow(&self, x: f64) -> f64 {
        self.k_l * self.omega * x
    }
    /// The largest steady pump flow, at the largest current \[m^3/s\].
    pub fn max_pump_flow(&self) -> f64 {
        self.pump_flow(self.steady_stroke(self.i_max).min(self.x_max))
    }
    /// P_min from the parameters, F_u / (A_a (1 - gamma_l)) \[Pa\] (the thesis's bound
    /// below which the pilot pressure drop changes sign).
    pub fn p_min_derived(&self) -> f64 {
        self.f_u / (self.a_a * (1.0 - self.gamma_l))
    }
}

/// Parameter overrides as a scenario file writes them, in display units; every field
/// is optional and defaults to table 3.3 of the thesis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PumpParamsSpec {
    /// V_l0 \[dm^3\] (0.25).
    pub v_l0_dm3: f64,
    /// beta \[MPa\] (1200, +-20 %).
    pub beta_mpa: f64,
    /// alpha_v \[1/MPa\] (0.04).
    pub alpha_v_per_mpa: f64,
    /// P_max \[MPa\] (25).
    pub p_max_mpa: f64,
    /// Qdot_max \[dm^3/s^2\] (2, +-10 %).
    pub qdot_max_dm3_s2: f64,
    /// k_l \[m^2\] (0.6e-3).
    pub k_l_m2: f64,
    /// omega \[rad/s\] (200).
    pub omega_rad_s: f64,
    /// Q_0 \[dm^3/s\] (0.13, +-10 %).
    pub q_0_dm3_s: f64,
    /// Largest current \[A\] (0.8).
    pub i_max_a: f64,
    /// A_a \[dm^2\] (0.05).
    pub a_a_dm2: f64,
    /// T \[ms\] (5).
    pub t_control_ms: f64,
    /// x_max \[mm\] (24).
    pub x_max_mm: f64,
    /// mu_1 \[m^2/s/sqrt(Pa)\] (78e-6, +-20 %).
    pub mu_1: f64,
    /// mu_2 \[m/s/sqrt(Pa)\] (78e-6, +-20 %).
    pub mu_2: f64,
    /// phi \[N/A\] (28).
    pub phi_n_per_a: f64,
    /// K_c \[N/m\] (27300).
    pub k_c_n_per_m: f64,
    /// K_a \[N/m\] (1300).
    pub k_a_n_per_m: f64,
    /// K \[N/m\] (8300).
    pub k_n_per_m: f64,
    /// F_u \[N\] (400).
    pub f_u_n: f64,
    /// gamma_l \[-\] (0.2).
    pub gamma_l: f64,
    /// P_0 \[MPa\] (0.4).
    pub p_0_mpa: f64,
    /// P_min \[MPa\] (1).
    pub p_min_mpa: f64,
    /// First-order lag on the solenoid current \[ms\] (0: none; pump-model.md section 3).
    pub solenoid_lag_ms: f64,
    /// Transport delay from a controller's output to the solenoid \[control periods\] (0).
    pub transport_delay_periods: u32,
}

impl Default for PumpParamsSpec {
    fn default() -> Self {
        PumpParamsSpec {
            v_l0_dm3: 0.25,
            beta_mpa: 1200.0,
            alpha_v_per_mpa: 0.04,
            p_max_mpa: 25.0,
            qdot_max_dm3_s2: 2.0,
            k_l_m2: 0.6e-3,
            omega_rad_s: 200.0,
            q_0_dm3_s: 0.13,
            i_max_a: 0.8,
            a_a_dm2: 0.05,
            t_control_ms: 5.0,
            x_max_mm: 24.0,
            mu_1: 78e-6,
            mu_2: 78e-6,
            phi_n_per_a: 28.0,
            k_c_n_per_m: 27300.0,
            k_a_n_per_m: 1300.0,
            k_n_per_m: 8300.0,
            f_u_n: 400.0,
            gamma_l: 0.2,
            p_0_mpa: 0.4,
            p_min_mpa: 1.0,
            solenoid_lag_ms: 0.0,
            transport_delay_periods: 0,
        }
    }
}

impl PumpParamsSpec {
    /// Validate and convert to SI. Errors name the field (`plant.<name>`), the value
    /// and the allowed range.
    pub fn check(&self) -> Result<PumpParams> {
        let positive: [(&str, f64); 17] = [
            ("v_l0_dm3", self.v_l0_dm3),
            ("beta_mpa", self.beta_mpa),
            ("p_max_mpa", self.p_max_mpa),
            ("qdot_max_dm3_s2", self.qdot_max_dm3_s2),
            ("k_l_m2", self.k_l_m2),
            ("omega_rad_s", self.omega_rad_s),
            ("i_max_a", self.i_max_a),
            ("a_a_dm2", self.a_a_dm2),
            ("t_control_ms", self.t_control_ms),
            ("x_max_mm", self.x_max_mm),
            ("mu_1", self.mu_1),
            ("phi_n_per_a", self.phi_n_per_a),
            ("k_c_n_per_m", self.k_c_n_per_m),
            ("k_a_n_per_m", self.k_a_n_per_m),
            ("f_u_n", self.f_u_n),
            ("p_min_mpa", self.p_min_mpa),
            ("omega_rad_s", self.omega_rad_s),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(invalid(format!("plant.{name}"), v, "a finite number > 0"));
            }
        }
        let non_negative: [(&str, f64); 6] = [
            ("alpha_v_per_mpa", self.alpha_v_per_mpa),
            ("q_0_dm3_s", self.q_0_dm3_s),
            ("mu_2", self.mu_2),
            ("k_n_per_m", self.k_n_per_m),
            ("p_0_mpa", self.p_0_mpa),
            ("solenoid_lag_ms", self.solenoid_lag_ms),
        ];
        for (name, v) in non_negative {
            if !(v.is_finite() && v >= 0.0) {
                return Err(invalid(format!("plant.{name}"), v, "a finite number >= 0"));
            }
        }
        if !(self.gamma_l >= 0.0 && self.gamma_l < 1.0) {
            return Err(invalid("plant.gamma_l", self.gamma_l, "a number in [0, 1)"));
        }
        if self.transport_delay_periods > 1000 {
            return Err(invalid(
                "plant.transport_delay_periods",
                self.transport_delay_periods,
                "an integer in [0, 1000]",
            ));
        }
        if self.p_min_mpa >= self.p_max_mpa {
            return Err(invalid(
                "plant.p_min_mpa",
                self.p_min_mpa,
                format!("below plant.p_max_mpa = {} MPa", self.p_max_mpa),
            ));
        }
        Ok(PumpParams {
            v_l0: self.v_l0_dm3 * M3_PER_DM3,
            beta: self.beta_mpa * PA_PER_MPA,
            alpha_v: self.alpha_v_per_mpa / PA_PER_MPA,
            p_max: self.p_max_mpa * PA_PER_MPA,
            qdot_max: self.qdot_max_dm3_s2 * M3_PER_DM3,
            k_l: self.k_l_m2,
            omega: self.omega_rad_s,
            q_0: self.q_0_dm3_s * M3_PER_DM3,
            i_max: self.i_max_a,
            a_a: self.a_a_dm2 * M2_PER_DM2,
            t_control: self.t_control_ms * S_PER_MS,
            x_max: self.x_max_mm * M_PER_MM,
            mu_1: self.mu_1,
            mu_2: self.mu_2,
            phi: self.phi_n_per_a,
            k_c: self.k_c_n_per_m,
            k_a: self.k_a_n_per_m,
            k: self.k_n_per_m,
            f_u: self.f_u_n,
            gamma_l: self.gamma_l,
            p_0: self.p_0_mpa * PA_PER_MPA,
            p_min: self.p_min_mpa * PA_PER_MPA,
            solenoid_lag: self.solenoid_lag_ms * S_PER_MS,
            delay_periods: self.transport_delay_periods,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_core_crates_thesis_equations_are_the_nominal_parameters() {
        assert_eq!(
            PumpParams::default().equations(),
            rhonn_core::pump::PumpEquations::THESIS
        );
    }

    #[test]
    fn steady_state_checks_of_spec() {
        let p = PumpParams::default();
        // pump-model.md section 1: x = phi I / K_a = 17.23 mm and 2.07 dm^3/s at 0.8 A.
        assert!(
            (mm(p.steady_stroke(0.8)) - 17.23).abs() < 0.005,
            "{}",
            mm(p.steady_stroke(0.8))
        );
        assert!((dm3_s(p.pump_flow(p.steady_stroke(0.8))) - 2.07).abs() < 0.005);
        // P_min = F_u / (A_a (1 - gamma_l)) = 1 MPa.
        assert!((p.p_min_derived() - 1e6).abs() < 1.0);
    }

    #[test]
    fn a_bad_value_names_the_field_and_the_range() {
        let s = PumpParamsSpec {
            beta_mpa: -3.0,
            ..Default::default()
        };
        assert_eq!(
            s.check().unwrap_err().to_string(),
            "invalid value: `plant.beta_mpa` = -3 is not allowed: a finite number > 0"
        );
        let s = PumpParamsSpec {
            gamma_l: 1.0,
            ..Default::default()
        };
        assert!(s.check().unwrap_err().to_string().contains("plant.gamma_l"));
    }
}
