//! PI pressure regulator with anti-windup: the baseline every adaptive controller is
//! compared with.

use super::Controller;
use crate::signal::Signal;

/// A discrete PI regulator `u = bias + kp e + ki sum(e T)`, output clipped to
/// `[u_min, u_max]`. Anti-windup by conditional integration: the integral does not
/// grow while the output is saturated and the error pushes further into saturation.
///
/// Units are the caller's; the pump uses Pa in and A out.
#[derive(Debug, Clone, PartialEq)]
pub struct Pi {
    /// Proportional gain \[A/Pa\].
    pub kp: f64,
    /// Integral gain kp / Ti \[A/(Pa s)\].
    pub ki: f64,
    /// Sampling period \[s\].
    pub period_s: f64,
    /// Output offset \[A\].
    pub bias: f64,
    /// Output range.
    pub u_min: f64,
    /// Output range.
    pub u_max: f64,
    /// The plant state it measures (default 0).
    pub measured: [usize; 1],
    /// A signal added to the output (an identification dither), then clipped again.
    pub dither: Option<Signal>,
    integral: f64,
}

impl Pi {
    /// A regulator with proportional gain `kp`, integral time `ti_s`, period `period_s`.
    pub fn new(kp: f64, ti_s: f64, period_s: f64, bias: f64, u_min: f64, u_max: f64) -> Self {
        Pi {
            kp,
            ki: kp / ti_s,
            period_s,
            bias,
            u_min,
            u_max,
            measured: [0],
            dither: None,
            integral: 0.0,
        }
    }

    /// One sample: reference and measurement in, clipped output out.
    pub fn update(&mut self, reference: f64, measured: f64) -> f64 {
        let e = reference - measured;
        let candidate = self.integral + self.ki * self.period_s * e;
        let u = self.bias + self.kp * e + candidate;
        let winding_up = (u > self.u_max && e > 0.0) || (u < self.u_min && e < 0.0);
        if !winding_up {
            self.integral = candidate;
        }
        (self.bias + self.kp * e + self.integral).clamp(self.u_min, self.u_max)
    }

    /// The integral term \[A\].
    pub fn integral(&self) -> f64 {
        self.integral
    }
}

impl Controller for Pi {
    fn name(&self) -> &'static str {
        "pi"
    }
    fn measurements(&self) -> &[usize] {
        &self.measured
    }
    fn control(&mut self, t: f64, measured: &[f64], setpoint: f64) -> f64 {
        let u = self.update(setpoint, measured[0]);
        match &self.dither {
            Some(d) => (u + d.eval(t)).clamp(self.u_min, self.u_max),
            None => u,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proportional_and_integral_action() {
        let mut pi = Pi::new(2.0, 1.0, 0.1, 0.0, -10.0, 10.0);
        // e = 1: u = 2*1 + 2*0.1*1 = 2.2, then 2.4 ...
        assert!((pi.update(1.0, 0.0) - 2.2).abs() < 1e-12);
        assert!((pi.update(1.0, 0.0) - 2.4).abs() < 1e-12);
    }

    #[test]
    fn integral_does_not_wind_up_in_saturation() {
        let mut pi = Pi::new(1.0, 0.1, 0.1, 0.0, 0.0, 0.8);
        for _ in 0..1000 {
            assert_eq!(pi.update(10.0, 0.0), 0.8);
        }
        assert!(pi.integral() <= 0.8, "{}", pi.integral());
        // Once the error reverses the output leaves saturation at once.
        assert!(pi.update(0.0, 1.0) < 0.8);
    }
}
