//! The integrator's 4th-order dense output over its last step: the state at any time of
//! the step, one component at a time, or as a polynomial for many points.

use super::Dopri5;
use crate::{State, System};

/// One component's dense output over the last step (see [`Dopri5::dense_component`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DenseComponent {
    r: [f64; 5],
}

impl DenseComponent {
    /// Value at `theta` (0 at the step's start, 1 at its planned end).
    #[inline(always)]
    pub fn at(&self, theta: f64) -> f64 {
        let t1 = 1.0 - theta;
        let r = &self.r;
        r[0] + theta * (r[1] + t1 * (r[2] + theta * (r[3] + t1 * r[4])))
    }
}

impl<Sys: System> Dopri5<Sys> {
    /// The state at time `t` in `[t_prev(), t()]` from the 4th-order dense output of the
    /// last step, into `out`.
    #[inline]
    pub fn interpolate(&self, t: f64, out: &mut [f64]) {
        debug_assert!(
            t >= self.t_prev - 1e-12 * (1.0 + self.t_prev.abs())
                && t <= self.t + 1e-12 * (1.0 + self.t.abs())
        );
        if self.h_step == 0.0 {
            out.copy_from_slice(self.x.as_slice());
            return;
        }
        let theta = (t - self.t_prev) / self.h_step;
        Self::dense_eval(&self.dense, theta, out);
    }

    /// The part of the last attempted step that was kept: `(t() - t_prev()) / h`, 1
    /// unless the step was cut at an event.
    #[inline]
    pub fn step_fraction(&self) -> f64 {
        if self.h_step == 0.0 {
            0.0
        } else {
            (self.t - self.t_prev) / self.h_step
        }
    }

    /// Component `i` of the dense output at `theta` of the last step (theta = 0 at
    /// `t_prev()`, `step_fraction()` at `t()`): for quadrature at fixed nodes of each
    /// step, without a division per point.
    #[inline]
    pub fn dense_at(&self, theta: f64, i: usize) -> f64 {
        if self.h_step == 0.0 {
            return self.x.as_slice()[i];
        }
        let t1 = 1.0 - theta;
        let d = &self.dense;
        let r = |k: usize| d[k].as_slice()[i];
        r(0) + theta * (r(1) + t1 * (r(2) + theta * (r(3) + t1 * r(4))))
    }

    /// Component `i`'s dense output of the last step as a polynomial in theta:
    /// [`DenseComponent::at`] gives exactly [`Dopri5::dense_at`], with the coefficients
    /// read once for many points.
    #[inline]
    pub fn dense_component(&self, i: usize) -> DenseComponent {
        if self.h_step == 0.0 {
            let x = self.x.as_slice()[i];
            return DenseComponent {
                r: [x, 0.0, 0.0, 0.0, 0.0],
            };
        }
        DenseComponent {
            r: core::array::from_fn(|k| self.dense[k].as_slice()[i]),
        }
    }

    /// Theta of time `t` in the last step, as [`Dopri5::interpolate`] computes it.
    #[inline]
    pub fn theta_of(&self, t: f64) -> f64 {
        if self.h_step == 0.0 {
            0.0
        } else {
            (t - self.t_prev) / self.h_step
        }
    }

    /// As [`Dopri5::interpolate`], for the first `out.len()` components only.
    #[inline]
    pub fn interpolate_first(&self, t: f64, out: &mut [f64]) {
        if self.h_step == 0.0 {
            out.copy_from_slice(&self.x.as_slice()[..out.len()]);
            return;
        }
        let theta = (t - self.t_prev) / self.h_step;
        Self::dense_eval(&self.dense, theta, out);
    }

    #[inline(always)]
    pub(super) fn dense_eval(d: &[Sys::State; 5], theta: f64, out: &mut [f64]) {
        let t1 = 1.0 - theta;
        let (r1, r2, r3, r4, r5) = (
            d[0].as_slice(),
            d[1].as_slice(),
            d[2].as_slice(),
            d[3].as_slice(),
            d[4].as_slice(),
        );
        for i in 0..out.len() {
            out[i] = r1[i] + theta * (r2[i] + t1 * (r3[i] + theta * (r4[i] + t1 * r5[i])));
        }
    }
}
