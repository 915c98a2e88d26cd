//! PI with anti-windup: the classical baseline every adaptive controller is compared
//! with, and the inner loops of cascades.

/// `u = bias + kp e + integral`, clipped to `[u_min, u_max]`; the integral of
/// `ki e` over each period is not taken while the output is saturated in the error's
/// direction (conditional integration).
#[derive(Debug, Clone, PartialEq)]
pub struct AntiWindupPi {
    /// Proportional gain.
    pub kp: f64,
    /// Integral gain kp / Ti \[1/s\].
    pub ki: f64,
    /// Sample period \[s\].
    pub period_s: f64,
    /// Output at zero error and zero integral.
    pub bias: f64,
    /// Lowest output.
    pub u_min: f64,
    /// Highest output.
    pub u_max: f64,
    integral: f64,
}

impl AntiWindupPi {
    /// A PI with gain `kp`, integral time `ti_s`, period `period_s`, output `bias`
    /// and range `[u_min, u_max]`.
    pub fn new(kp: f64, ti_s: f64, period_s: f64, bias: f64, u_min: f64, u_max: f64) -> Self {
        AntiWindupPi {
            kp,
            ki: kp / ti_s,
            period_s,
            bias,
            u_min,
            u_max,
            integral: 0.0,
        }
    }

    /// One period: the output for `reference` and `measured`.
    #[inline]
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

    /// The integral part.
    pub fn integral(&self) -> f64 {
        self.integral
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proportional_and_integral_action() {
        let mut pi = AntiWindupPi::new(2.0, 1.0, 0.1, 0.0, -10.0, 10.0);
        // e = 1: u = 2*1 + 2*0.1*1 = 2.2, then 2.4 ...
        assert!((pi.update(1.0, 0.0) - 2.2).abs() < 1e-12);
        assert!((pi.update(1.0, 0.0) - 2.4).abs() < 1e-12);
    }

    #[test]
    fn integral_does_not_wind_up_in_saturation() {
        let mut pi = AntiWindupPi::new(1.0, 0.1, 0.1, 0.0, 0.0, 0.8);
        for _ in 0..1000 {
            assert_eq!(pi.update(10.0, 0.0), 0.8);
        }
        assert!(pi.integral() <= 0.8, "{}", pi.integral());
        // Once the error reverses the output leaves saturation at once.
        assert!(pi.update(0.0, 1.0) < 0.8);
    }
}
