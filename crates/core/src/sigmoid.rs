//! The RHONN's sigmoid (pump-model.md section 2, thesis chapter 4).

use crate::Real;

/// `s(v) = a / (1 + exp(-b v)) - c`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(deny_unknown_fields))]
pub struct Sigmoid {
    /// Amplitude.
    pub a: f64,
    /// Slope.
    pub b: f64,
    /// Offset.
    pub c: f64,
}

impl Sigmoid {
    /// The logistic function (a = b = 1, c = 0), range (0, 1).
    pub const LOGISTIC: Sigmoid = Sigmoid {
        a: 1.0,
        b: 1.0,
        c: 0.0,
    };
    /// tanh (a = b = 2, c = 1), range (-1, 1).
    pub const TANH: Sigmoid = Sigmoid {
        a: 2.0,
        b: 2.0,
        c: 1.0,
    };

    /// Evaluate (with [`crate::exp`]).
    #[inline(always)]
    pub fn eval(&self, v: f64) -> f64 {
        self.eval_in(v)
    }

    /// Evaluate in `T` (the same operations as [`Sigmoid::eval`] for `f64`).
    #[inline(always)]
    pub fn eval_in<T: Real>(&self, v: T) -> T {
        let (a, c) = (T::of(self.a), T::of(self.c));
        let bv = T::of(self.b) * v;
        // Saturated arguments (raw SI pressures are ~1e6) would send exp() down its
        // slow overflow path; the limits are exact to double precision there.
        if bv > T::of(40.0) {
            a - c
        } else if bv < T::of(-745.0) {
            -c
        } else {
            a / (T::of(1.0) + (-bv).exp()) - c
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn logistic_and_tanh_forms() {
        assert_eq!(Sigmoid::LOGISTIC.eval(0.0), 0.5);
        assert!((Sigmoid::TANH.eval(0.3) - libm::tanh(0.3)).abs() < 1e-15);
        assert_eq!(Sigmoid::LOGISTIC.eval(1e6), 1.0);
        assert_eq!(Sigmoid::TANH.eval(-1e6), -1.0);
    }
}
