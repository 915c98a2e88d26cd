//! The pump's parameters as a scenario's `[plant]` sets them: every field of
//! [`PumpParamsSpec`] but the control period and the transport delay (`[control]`'s
//! `period_s` and `delay_periods`), in display units; the thesis's uncertain ones first,
//! with its stated tolerances (pump-model.md table: beta, mu_1 and mu_2 +-20 %, Q_0 and the
//! demand's largest slew rate +-10 %), the others known (tolerance 0).

use super::params::PumpParamsSpec;
use crate::error::{invalid, Result};
use crate::plant::Parameter;

const fn known(name: &'static str, nominal: f64, description: &'static str) -> Parameter {
    Parameter {
        name,
        nominal,
        tolerance: 0.0,
        description,
    }
}

const fn uncertain(name: &'static str, nominal: f64, tolerance: f64, description: &'static str) -> Parameter {
    Parameter {
        name,
        nominal,
        tolerance,
        description,
    }
}

/// Every parameter of the pump a scenario may set, at table 3.3 of the thesis.
pub const PARAMETERS: [Parameter; 22] = [
    uncertain("beta_mpa", 1200.0, 0.2, "bulk modulus of the oil [MPa]"),
    uncertain("mu_1", 78e-6, 0.2, "pilot valve flow coefficient mu_1"),
    uncertain("mu_2", 78e-6, 0.2, "pilot valve flow coefficient mu_2"),
    uncertain("q_0_dm3_s", 0.13, 0.1, "leakage flow Q_0 [dm^3/s]"),
    uncertain(
        "qdot_max_dm3_s2",
        2.0,
        0.1,
        "largest slew rate of the demanded flow [dm^3/s^2]",
    ),
    known("v_l0_dm3", 0.25, "line volume V_l0 [dm^3]"),
    known(
        "alpha_v_per_mpa",
        0.04,
        "volume change with pressure alpha_v [1/MPa]",
    ),
    known("p_max_mpa", 25.0, "relief pressure P_max [MPa]"),
    known("k_l_m2", 0.6e-3, "pump displacement constant k_l [m^2]"),
    known("omega_rad_s", 200.0, "shaft speed omega [rad/s]"),
    known("i_max_a", 0.8, "largest solenoid current [A]"),
    known("a_a_dm2", 0.05, "actuator piston area A_a [dm^2]"),
    known("x_max_mm", 24.0, "largest stroke x_max [mm]"),
    known("phi_n_per_a", 28.0, "solenoid force constant phi [N/A]"),
    known("k_c_n_per_m", 27300.0, "pilot spring K_c [N/m]"),
    known("k_a_n_per_m", 1300.0, "actuator spring K_a [N/m]"),
    known("k_n_per_m", 8300.0, "return spring K [N/m]"),
    known("f_u_n", 400.0, "spring preload F_u [N]"),
    known("gamma_l", 0.2, "pilot pressure ratio gamma_l [-]"),
    known("p_0_mpa", 0.4, "tank pressure P_0 [MPa]"),
    known(
        "p_min_mpa",
        1.0,
        "lowest line pressure the model holds, P_min [MPa]",
    ),
    known(
        "solenoid_lag_ms",
        0.0,
        "first-order lag on the solenoid current [ms] (0: none)",
    ),
];

impl PumpParamsSpec {
    /// The spec of `values` in [`PARAMETERS`]' order (display units), the control
    /// period and transport delay at the table's; checked by [`PumpParamsSpec::check`].
    pub fn from_values(values: &[f64]) -> Result<Self> {
        let v = <[f64; 22]>::try_from(values).map_err(|_| {
            invalid(
                "plant",
                format!("{} values", values.len()),
                "the 22 parameters of the pump",
            )
        })?;
        Ok(PumpParamsSpec {
            beta_mpa: v[0],
            mu_1: v[1],
            mu_2: v[2],
            q_0_dm3_s: v[3],
            qdot_max_dm3_s2: v[4],
            v_l0_dm3: v[5],
            alpha_v_per_mpa: v[6],
            p_max_mpa: v[7],
            k_l_m2: v[8],
            omega_rad_s: v[9],
            i_max_a: v[10],
            a_a_dm2: v[11],
            x_max_mm: v[12],
            phi_n_per_a: v[13],
            k_c_n_per_m: v[14],
            k_a_n_per_m: v[15],
            k_n_per_m: v[16],
            f_u_n: v[17],
            gamma_l: v[18],
            p_0_mpa: v[19],
            p_min_mpa: v[20],
            solenoid_lag_ms: v[21],
            ..PumpParamsSpec::default()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_is_the_specs_default_field_by_field() {
        let nominal: Vec<f64> = PARAMETERS.iter().map(|p| p.nominal).collect();
        assert_eq!(
            PumpParamsSpec::from_values(&nominal).unwrap(),
            PumpParamsSpec::default()
        );
        let table = toml::Table::try_from(PumpParamsSpec::default()).unwrap();
        for p in PARAMETERS {
            assert_eq!(table[p.name].as_float(), Some(p.nominal), "{}", p.name);
        }
        // Every field but the two `[control]` gives.
        assert_eq!(table.len(), PARAMETERS.len() + 2);
    }
}
