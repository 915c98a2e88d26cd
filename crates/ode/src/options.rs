//! Solver options with named, documented defaults.

use crate::{Error, State};

/// How the step size is controlled and the error measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Profile {
    /// Hairer's DOPRI5: RMS norm of `e_i / (atol_i + rtol_i max(|y_i|, |ynew_i|))`, a PI
    /// step controller (beta = 0.04, safety 0.9, growth in \[0.2, 10\]) and Hairer's
    /// two-evaluation initial step.
    Hairer,
    /// MATLAB's ode45: max norm of `e_i / max(rtol_i max(|y_i|, |ynew_i|), atol_i)`, the
    /// I-controller with exponent 1/5 (growth at most 5x, no growth after a rejection,
    /// halving after a second rejection) and the one-evaluation initial step.
    Ode45,
}

/// Options of [`crate::Dopri5`]. Tolerances are per state.
#[derive(Debug, Clone, PartialEq)]
pub struct Options<S: State> {
    /// Relative tolerance per state (default 1e-6).
    pub rtol: S,
    /// Absolute tolerance per state, in the state's own unit (default 1e-9).
    pub atol: S,
    /// Largest step \[s\] (default infinity).
    pub h_max_s: f64,
    /// Smallest step \[s\] before the solver gives up (default 1e-14).
    pub h_min_s: f64,
    /// First step \[s\]; `None` lets the profile's rule choose (default `None`).
    pub h_init_s: Option<f64>,
    /// Steps allowed in one run, accepted and rejected (default 10,000,000).
    pub max_steps: u64,
    /// Width of the final bracket when locating an event \[s\] (default 1e-10; the
    /// solver stops at the bracket's far end, just past the crossing).
    pub event_tol_s: f64,
    /// Step-size control (default [`Profile::Hairer`]).
    pub profile: Profile,
}

/// The most steps one solve takes by default ([`Options::max_steps`]).
pub const DEFAULT_MAX_STEPS: u64 = 10_000_000;

impl<S: State> Options<S> {
    /// Hairer profile with the same tolerances on every state.
    pub fn uniform(dim: usize, rtol: f64, atol: f64) -> Self {
        Options {
            rtol: S::splat(dim, rtol),
            atol: S::splat(dim, atol),
            h_max_s: f64::INFINITY,
            h_min_s: 1e-14,
            h_init_s: None,
            max_steps: DEFAULT_MAX_STEPS,
            event_tol_s: 1e-10,
            profile: Profile::Hairer,
        }
    }

    /// MATLAB's ode45 defaults for a run of `span_s` seconds: RelTol 1e-3, AbsTol 1e-6,
    /// MaxStep = span/10, and the ode45 step control.
    pub fn ode45(dim: usize, span_s: f64) -> Self {
        Options {
            h_max_s: 0.1 * span_s.abs(),
            profile: Profile::Ode45,
            ..Self::uniform(dim, 1e-3, 1e-6)
        }
    }

    /// Simulink's variable-step ode45 defaults: as [`Options::ode45`] but MaxStep =
    /// span/50. (Simulink's adaptive per-state AbsTol is not reproduced: AbsTol stays
    /// at 1e-6.)
    pub fn simulink_ode45(dim: usize, span_s: f64) -> Self {
        Options {
            h_max_s: span_s.abs() / 50.0,
            ..Self::ode45(dim, span_s)
        }
    }

    /// Check every option; an error names the option, its value and what is allowed.
    pub fn check(&self, dim: usize) -> Result<(), Error> {
        let bad = |name, value, allowed| Err(Error::InvalidOption { name, value, allowed });
        if self.rtol.dim() != dim {
            return bad("rtol (length)", self.rtol.dim() as f64, "one value per state");
        }
        if self.atol.dim() != dim {
            return bad("atol (length)", self.atol.dim() as f64, "one value per state");
        }
        for &r in self.rtol.as_slice() {
            if !(1e-14..1.0).contains(&r) {
                return bad("rtol", r, "a number in [1e-14, 1)");
            }
        }
        for &a in self.atol.as_slice() {
            if !(a.is_finite() && a > 0.0) {
                return bad("atol", a, "a finite number > 0");
            }
        }
        if !(self.h_max_s > 0.0) || self.h_max_s.is_nan() {
            return bad("h_max_s", self.h_max_s, "a number > 0 (infinity allowed)");
        }
        if !(self.h_min_s >= 0.0 && self.h_min_s < self.h_max_s) {
            return bad("h_min_s", self.h_min_s, "a number in [0, h_max_s)");
        }
        if let Some(h) = self.h_init_s {
            if !(h.is_finite() && h > 0.0) {
                return bad("h_init_s", h, "a finite number > 0");
            }
        }
        if !(self.event_tol_s.is_finite() && self.event_tol_s > 0.0 && self.event_tol_s <= 1e-3) {
            return bad("event_tol_s", self.event_tol_s, "a number in (0, 1e-3]");
        }
        if self.max_steps == 0 {
            return bad("max_steps", 0.0, "at least 1");
        }
        Ok(())
    }
}

impl<const N: usize> Default for Options<[f64; N]> {
    fn default() -> Self {
        Self::uniform(N, 1e-6, 1e-9)
    }
}
