//! Two tanks in series (the cascaded-tanks benchmark's plant, in physical units): a pump
//! driven by a voltage fills the upper tank, which drains through an orifice into the
//! lower one, which drains through its own; when the upper tank is full, the inflow it
//! cannot hold overflows and a share of it falls into the lower tank.
//!
//! States `[h1, h2]` (levels \[m\], limited integrators on `[0, height_i]`), input
//! `voltage` \[V\] clipped to `[0, voltage_max]`:
//!
//! ```text
//! q_in  = k_p u                       q_12 = a_1 sqrt(2 g h1)      q_out = a_2 sqrt(2 g h2)
//! dh1/dt = (q_in - q_12) / A_1        (held at height_1 while q_in > q_12: overflowing)
//! dh2/dt = (q_12 + s_o max(0, q_in - q_12) [while overflowing] - q_out) / A_2
//! ```
//! (Torricelli's law for both orifices; the lower tank's own overflow is lost.)

mod system;

pub use system::{Tanks, H1, H2, TANKS_DIM};

use super::{Parameter, Plant, Quantity};

/// Standard gravity \[m/s^2\].
pub const G: f64 = 9.81;

/// The tanks' parameters, SI. The defaults are a laboratory-sized rig: tanks of 14 cm
/// diameter and 30 cm height, 7 mm orifices, a pump of 15 ml/s per volt: at 5 V the
/// levels settle near 18 cm with a time constant near 50 s, and above about 6.5 V the
/// upper tank overflows.
#[derive(Debug, Clone, PartialEq)]
pub struct TanksParams {
    /// Cross-section of the upper tank A_1 \[m^2\] (default 154 cm^2, +-2 %).
    pub area_1: f64,
    /// Cross-section of the lower tank A_2 \[m^2\] (default 154 cm^2, +-2 %).
    pub area_2: f64,
    /// Effective outlet area of the upper tank a_1 \[m^2\] (default 40 mm^2, +-10 %: the
    /// discharge coefficient is rarely known better).
    pub outlet_1: f64,
    /// Effective outlet area of the lower tank a_2 \[m^2\] (default 40 mm^2, +-10 %).
    pub outlet_2: f64,
    /// Pump gain k_p \[m^3/(s V)\] (default 15 ml/s per volt, +-10 %).
    pub pump_gain: f64,
    /// Height of the upper tank \[m\] (default 0.3 m).
    pub height_1: f64,
    /// Height of the lower tank \[m\] (default 0.3 m).
    pub height_2: f64,
    /// Share of the upper tank's overflow that falls into the lower tank (default 0.5,
    /// +-20 %).
    pub overflow_share: f64,
    /// Largest pump voltage \[V\] (default 10).
    pub voltage_max: f64,
}

impl Default for TanksParams {
    fn default() -> Self {
        TanksParams {
            area_1: 154e-4,
            area_2: 154e-4,
            outlet_1: 40e-6,
            outlet_2: 40e-6,
            pump_gain: 15e-6,
            height_1: 0.3,
            height_2: 0.3,
            overflow_share: 0.5,
            voltage_max: 10.0,
        }
    }
}

impl TanksParams {
    /// The steady levels `[h1, h2]` \[m\] at a constant voltage `u` below overflow.
    pub fn steady_levels(&self, u: f64) -> [f64; 2] {
        let q = self.pump_gain * u.clamp(0.0, self.voltage_max);
        let h = |a: f64| (q / (a * (2.0 * G).sqrt())).powi(2);
        [h(self.outlet_1), h(self.outlet_2)]
    }
}

/// The tanks' states, in state order.
pub const STATES: [Quantity; TANKS_DIM] = [
    Quantity {
        name: "h1",
        unit: "m",
        display_unit: "mm",
        display_per_si: 1e3,
        description: "level of the upper tank, a limited integrator on [0, height_1]",
    },
    Quantity {
        name: "h2",
        unit: "m",
        display_unit: "mm",
        display_per_si: 1e3,
        description: "level of the lower tank, a limited integrator on [0, height_2]",
    },
];

/// The tanks' input.
pub const INPUTS: [Quantity; 1] = [Quantity {
    name: "voltage",
    unit: "V",
    display_unit: "V",
    display_per_si: 1.0,
    description: "pump voltage, clipped to [0, voltage_max]",
}];

/// The uncertain parameters (display units, as a scenario's `[plant]` keys).
pub const PARAMETERS: [Parameter; 6] = [
    Parameter {
        name: "area_1_cm2",
        nominal: 154.0,
        tolerance: 0.02,
        description: "cross-section of the upper tank [cm^2]",
    },
    Parameter {
        name: "area_2_cm2",
        nominal: 154.0,
        tolerance: 0.02,
        description: "cross-section of the lower tank [cm^2]",
    },
    Parameter {
        name: "outlet_1_mm2",
        nominal: 40.0,
        tolerance: 0.1,
        description: "effective outlet area of the upper tank [mm^2]",
    },
    Parameter {
        name: "outlet_2_mm2",
        nominal: 40.0,
        tolerance: 0.1,
        description: "effective outlet area of the lower tank [mm^2]",
    },
    Parameter {
        name: "pump_gain_ml_s_per_v",
        nominal: 15.0,
        tolerance: 0.1,
        description: "pump flow per volt [ml/s/V]",
    },
    Parameter {
        name: "overflow_share",
        nominal: 0.5,
        tolerance: 0.2,
        description: "share of the upper tank's overflow that reaches the lower tank",
    },
];

impl Plant for Tanks {
    fn name(&self) -> &'static str {
        "tanks"
    }
    /// 150 s: three of a tank's time constants (about 50 s at 5 V).
    fn settle_s(&self) -> f64 {
        150.0
    }
    fn states(&self) -> &'static [Quantity] {
        &STATES
    }
    fn inputs(&self) -> &'static [Quantity] {
        &INPUTS
    }
    fn measured(&self) -> &'static [usize] {
        &[H1, H2]
    }
    #[inline(always)]
    fn input_at(&self, t: f64, _k: usize) -> f64 {
        self.voltage_at(t)
    }
    fn hold_input(&mut self, _k: usize, value: f64) {
        self.set_voltage(value);
    }
    fn parameters(&self) -> &'static [Parameter] {
        &PARAMETERS
    }
    fn set_input(&mut self, _k: usize, input: super::Input) -> crate::Result<()> {
        *self = Tanks::new(self.params.clone(), input);
        Ok(())
    }
    fn with_parameters(&self, values: &[f64]) -> crate::Result<Self> {
        let [a1, a2, o1, o2, kp, share] = <[f64; 6]>::try_from(values).map_err(|_| {
            crate::error::invalid(
                "plant",
                format!("{} values", values.len()),
                "the 6 parameters of the tanks",
            )
        })?;
        for (p, v) in PARAMETERS.iter().zip(values) {
            let ok = v.is_finite()
                && if p.name == "overflow_share" {
                    (0.0..=1.0).contains(v)
                } else {
                    *v > 0.0
                };
            if !ok {
                let allowed = if p.name == "overflow_share" {
                    "in [0, 1]"
                } else {
                    "finite and > 0"
                };
                return Err(crate::error::invalid(format!("plant.{}", p.name), v, allowed));
            }
        }
        let params = TanksParams {
            area_1: a1 * 1e-4,
            area_2: a2 * 1e-4,
            outlet_1: o1 * 1e-6,
            outlet_2: o2 * 1e-6,
            pump_gain: kp * 1e-6,
            overflow_share: share,
            ..self.params.clone()
        };
        Ok(Tanks::new(params, self.voltage.clone()))
    }
}

#[cfg(test)]
mod parameter_tests {
    use super::*;
    use crate::plant::Input;

    #[test]
    fn nominal_parameters_give_the_default_tanks_and_bad_ones_are_refused() {
        let t = Tanks::new(TanksParams::default(), Input::Held(0.0));
        let nominal: Vec<f64> = PARAMETERS.iter().map(|p| p.nominal).collect();
        let same = t.with_parameters(&nominal).unwrap();
        for (a, b) in [
            (same.params.area_1, t.params.area_1),
            (same.params.outlet_2, t.params.outlet_2),
            (same.params.pump_gain, t.params.pump_gain),
        ] {
            assert!((a - b).abs() <= 1e-12 * b, "{a} {b}");
        }
        let mut bad = nominal.clone();
        bad[2] = -1.0;
        let e = t.with_parameters(&bad).unwrap_err().to_string();
        assert!(e.contains("plant.outlet_1_mm2") && e.contains("> 0"), "{e}");
        assert!(t.with_parameters(&nominal[..3]).is_err());
    }
}
