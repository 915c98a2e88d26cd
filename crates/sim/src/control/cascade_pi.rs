//! The classical baseline with the adaptive cascade's sensors: an outer PI on the line
//! pressure with set-point weighting gives a stroke reference, an inner proportional
//! stroke loop with the pilot valve's static inverse as feed-forward gives the current.
//! Anti-windup on both levels by conditional integration.
//!
//! ```text
//! x_d = x_bias + kp (b r - p) + ki sum(r - p) T            clipped to [0, x_max]
//! I   = K_a/phi (x_d + g (x_d - x))                          clipped to [0, I_max]
//! ```
//!
//! `K_a/phi` is the pilot valve's steady state `x = phi I / K_a` inverted (the same
//! feed-forward as the adaptive cascade's stroke loop); `x_bias` the stroke whose pump
//! flow equals the lubricating flow Q_0 (a bumpless start); `b` weights the set-point in
//! the proportional term (b < 1 softens the kick of a set-point step without slowing the
//! response to a disturbance; the integral starts at `kp (1 - b) r(0)`, so that at
//! `p = r` the stroke reference starts at its bias). The integral does not grow while the
//! stroke reference or the current is saturated and the error pushes further into
//! saturation.

use super::{Controller, LoopContext, LoopSettings, LoopSpec};
use crate::error::{invalid, Result};
use crate::plant::{PumpParams, P_LINE, STROKE};
use serde::{Deserialize, Serialize};

/// Gains of a [`CascadePi`] (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CascadePiGains {
    /// Outer proportional gain \[m/Pa\].
    pub kp: f64,
    /// Outer integral time \[s\].
    pub ti_s: f64,
    /// Set-point weight b of the proportional term, in [0, 1].
    pub setpoint_weight: f64,
    /// Inner stroke feedback gain g (dimensionless).
    pub stroke_gain: f64,
}

/// The cascade PI of the module docs.
#[derive(Debug, Clone, PartialEq)]
pub struct CascadePi {
    gains: CascadePiGains,
    /// K_a / phi \[A/m\].
    amp_per_m: f64,
    x_bias: f64,
    x_max: f64,
    i_max: f64,
    period_s: f64,
    /// The plant states it measures: the pressure, then the stroke.
    pub measured: [usize; 2],
    integral: f64,
    x_d: f64,
    started: bool,
}

impl CascadePi {
    /// A controller for a pilot valve of static gain `amp_per_m` = K_a/phi \[A/m\],
    /// stroke bias `x_bias` and range `[0, x_max]` \[m\], current range `[0, i_max]` \[A\],
    /// sampled every `period_s`.
    pub fn new(
        gains: CascadePiGains,
        amp_per_m: f64,
        x_bias: f64,
        x_max: f64,
        i_max: f64,
        period_s: f64,
    ) -> Self {
        CascadePi {
            gains,
            amp_per_m,
            x_bias,
            x_max,
            i_max,
            period_s,
            measured: [0, 1],
            integral: 0.0,
            x_d: x_bias,
            started: false,
        }
    }

    /// The gains.
    pub fn gains(&self) -> CascadePiGains {
        self.gains
    }

    /// The stroke reference of the last control instant \[m\].
    pub fn stroke_reference(&self) -> f64 {
        self.x_d
    }

    fn outputs(&self, r: f64, p: f64, x: f64, integral: f64) -> (f64, f64, f64, f64) {
        let g = &self.gains;
        let x_raw = self.x_bias + g.kp * (g.setpoint_weight * r - p) + integral;
        let x_d = x_raw.clamp(0.0, self.x_max);
        let i_raw = self.amp_per_m * (x_d + g.stroke_gain * (x_d - x));
        (x_raw, x_d, i_raw, i_raw.clamp(0.0, self.i_max))
    }
}

impl Controller for CascadePi {
    fn name(&self) -> &'static str {
        "cascade-pi"
    }
    fn measurements(&self) -> &[usize] {
        &self.measured
    }
    fn control(&mut self, _t: f64, measured: &[f64], r: f64) -> f64 {
        let (p, x) = (measured[0], measured[1]);
        if !self.started {
            // Bumpless start: at p = r the proportional and integral terms cancel, so the
            // stroke reference starts at its bias whatever the set-point weight.
            self.integral = self.gains.kp * (1.0 - self.gains.setpoint_weight) * r;
            self.started = true;
        }
        let e = r - p;
        let candidate = self.integral + self.gains.kp / self.gains.ti_s * self.period_s * e;
        let (x_raw, _, i_raw, _) = self.outputs(r, p, x, candidate);
        let high = x_raw > self.x_max || i_raw > self.i_max;
        let low = x_raw < 0.0 || i_raw < 0.0;
        if !((high && e > 0.0) || (low && e < 0.0)) {
            self.integral = candidate;
        }
        let (_, x_d, _, i) = self.outputs(r, p, x, self.integral);
        self.x_d = x_d;
        i
    }
    fn inner_reference(&self) -> Option<f64> {
        Some(self.x_d)
    }
}

/// `kind = "pump-cascade-pi"` in a plant scenario of the pump (`[plant] kind = "pump"`):
/// the cascade PI with the adaptive controller's sensors, built from the nominal table as
/// in the pump's own scenarios (its gains in the units of those: the robust tuning is kp
/// 0.15 mm/MPa, ti 0.07 s, b 0.8, g 8; the nominal-optimal 0.75, 0.05, 0.2, 4).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PumpCascadePiLoop {
    /// The regulated state: `p_line`.
    pub state: String,
    /// Outer proportional gain \[mm/MPa\].
    pub kp_mm_per_mpa: f64,
    /// Outer integral time \[s\].
    pub ti_s: f64,
    /// Set-point weight b, in [0, 1].
    pub setpoint_weight: f64,
    /// Inner stroke gain g.
    pub stroke_gain: f64,
}

/// The cascade PI's gains when a scenario gives none: the **robust** tuning found by
/// `cargo run --release -p rhonn-study --example tune_cascade_pi` (the lowest nominal IAE
/// that still regulates with doubled gains, a 5 ms solenoid lag and a one-period delay,
/// and keeps a gain margin of 6 dB and a phase margin of 45 degrees measured on the
/// simulated pump at every operating point: `rhonn_study::tuning`).
pub const ROBUST: CascadePiGainsMpa = CascadePiGainsMpa {
    kp_mm_per_mpa: 0.15,
    ti_s: 0.07,
    setpoint_weight: 0.8,
    stroke_gain: 8.0,
};

/// The **nominal-optimal** tuning of the same search: the lowest IAE on the nominal
/// plant with every set-point step's overshoot at most 10 %.
pub const NOMINAL_OPTIMAL: CascadePiGainsMpa = CascadePiGainsMpa {
    kp_mm_per_mpa: 0.75,
    ti_s: 0.05,
    setpoint_weight: 0.2,
    stroke_gain: 4.0,
};

/// Cascade PI gains in the units a scenario file uses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CascadePiGainsMpa {
    /// Outer proportional gain \[mm/MPa\].
    pub kp_mm_per_mpa: f64,
    /// Outer integral time \[s\].
    pub ti_s: f64,
    /// Set-point weight b, in [0, 1].
    pub setpoint_weight: f64,
    /// Inner stroke gain g.
    pub stroke_gain: f64,
}

impl CascadePiGainsMpa {
    /// The cascade PI of these gains on the pump's pressure, as a scenario names it.
    pub fn loop_spec(self) -> LoopSpec {
        LoopSpec::PumpCascadePi(self.on("p_line"))
    }

    /// The cascade PI of these gains on `state`.
    fn on(self, state: &str) -> PumpCascadePiLoop {
        PumpCascadePiLoop {
            state: state.into(),
            kp_mm_per_mpa: self.kp_mm_per_mpa,
            ti_s: self.ti_s,
            setpoint_weight: self.setpoint_weight,
            stroke_gain: self.stroke_gain,
        }
    }
}

impl LoopSettings for PumpCascadePiLoop {
    fn state(&self) -> &str {
        &self.state
    }
    fn name(&self) -> &'static str {
        "cascade-pi"
    }
    /// The stroke: its outer PI sets the stroke's reference.
    fn inner_state(&self) -> Option<&str> {
        Some("stroke")
    }
    fn tunings(&self) -> &'static [&'static str] {
        &["nominal-optimal", "robust"]
    }
    fn tuning(&self, name: &str) -> Option<LoopSpec> {
        let g = match name {
            "nominal-optimal" => NOMINAL_OPTIMAL,
            "robust" => ROBUST,
            _ => return None,
        };
        Some(LoopSpec::PumpCascadePi(g.on(&self.state)))
    }
    fn build(&self, cx: &LoopContext) -> Result<Box<dyn Controller>> {
        super::adaptive::pump_states(cx, &self.state)?;
        let field = |k: &str| format!("{}.{k}", cx.field);
        for (k, v) in [
            ("kp_mm_per_mpa", self.kp_mm_per_mpa),
            ("stroke_gain", self.stroke_gain),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(invalid(field(k), v, "a finite number >= 0"));
            }
        }
        let ti = cx.positive("ti_s", self.ti_s)?;
        if !(0.0..=1.0).contains(&self.setpoint_weight) {
            return Err(invalid(
                field("setpoint_weight"),
                self.setpoint_weight,
                "a number in [0, 1]",
            ));
        }
        let n = PumpParams::default();
        let gains = CascadePiGains {
            kp: self.kp_mm_per_mpa * 1e-3 / 1e6,
            ti_s: ti,
            setpoint_weight: self.setpoint_weight,
            stroke_gain: self.stroke_gain,
        };
        let mut c = CascadePi::new(
            gains,
            n.k_a / n.phi,
            n.q_0 / (n.k_l * n.omega),
            n.x_max,
            cx.range.1,
            cx.period_s,
        );
        c.measured = [P_LINE, STROKE];
        Ok(Box::new(c))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ctl(b: f64) -> CascadePi {
        let gains = CascadePiGains {
            kp: 1e-9,
            ti_s: 0.1,
            setpoint_weight: b,
            stroke_gain: 2.0,
        };
        CascadePi::new(gains, 50.0, 0.001, 0.02, 0.8, 0.005)
    }

    #[test]
    fn outer_pi_then_stroke_loop_with_feed_forward() {
        let mut c = ctl(1.0);
        // b = 1: the integral starts at 0.
        // r - p = 1 MPa: x_d = 1 mm + 1e-9 * 1e6 m + 1e-8 * 0.005 * 1e6 m = 2.05 mm;
        // I = 50 (2.05 mm + 2 (2.05 - 1) mm) = 0.2075 A.
        let i = c.control(0.0, &[9e6, 0.001], 10e6);
        assert!(
            (c.stroke_reference() - 2.05e-3).abs() < 1e-12,
            "{}",
            c.stroke_reference()
        );
        assert!((i - 0.2075).abs() < 1e-9, "{i}");
    }

    #[test]
    fn set_point_weight_acts_on_the_set_point_only() {
        let (mut full, mut soft) = (ctl(1.0), ctl(0.5));
        // Both start at rest at 10 MPa (bumpless: the same current), then the set-point
        // steps to 12 MPa.
        let a0 = full.control(0.0, &[10e6, 0.001], 10e6);
        let b0 = soft.control(0.0, &[10e6, 0.001], 10e6);
        assert!((a0 - b0).abs() < 1e-12, "{a0} {b0}");
        let a = full.control(0.0, &[10e6, 0.001], 12e6);
        let b = soft.control(0.0, &[10e6, 0.001], 12e6);
        assert!(b < a, "a softer kick on a set-point step: {b} < {a}");
        // A disturbance (p moves, r fixed) meets the same proportional gain.
        let (mut full, mut soft) = (ctl(1.0), ctl(0.5));
        let d_full = full.control(0.0, &[0.9e6, 0.0001], 1e6) - ctl(1.0).control(0.0, &[1e6, 0.0001], 1e6);
        let d_soft = soft.control(0.0, &[0.9e6, 0.0001], 1e6) - ctl(0.5).control(0.0, &[1e6, 0.0001], 1e6);
        assert!(d_full > 0.0);
        assert!((d_full - d_soft).abs() < 1e-12);
    }

    #[test]
    fn integral_does_not_wind_up_when_the_current_saturates() {
        let mut c = ctl(1.0);
        for _ in 0..10_000 {
            assert_eq!(c.control(0.0, &[0.0, 0.0], 20e6), 0.8);
        }
        // Saturated the whole time: the integral stayed where the current first hit 0.8 A.
        assert!(c.integral < 0.02, "{}", c.integral);
        // Once the error reverses, the current leaves saturation at once.
        assert!(c.control(0.0, &[21e6, 0.016], 20e6) < 0.8);
    }
}
