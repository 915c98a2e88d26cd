//! Solver errors. Every variant carries the time reached and a snapshot of the state,
//! so a caller can say where and in which state a run failed.

use core::fmt;

/// The first few components of the state when an error happened (no allocation, so
/// the type stays `no_std`).
#[derive(Clone, Copy, PartialEq)]
pub struct Snapshot {
    values: [f64; Snapshot::CAP],
    len: usize,
    dim: usize,
}

impl Snapshot {
    /// How many components a snapshot keeps.
    pub const CAP: usize = 8;

    /// Take a snapshot of `x`.
    pub fn of(x: &[f64]) -> Self {
        let mut values = [0.0; Self::CAP];
        let len = x.len().min(Self::CAP);
        values[..len].copy_from_slice(&x[..len]);
        Snapshot {
            values,
            len,
            dim: x.len(),
        }
    }

    /// The components kept (all of them when the state has at most [`Snapshot::CAP`]).
    pub fn values(&self) -> &[f64] {
        &self.values[..self.len]
    }

    /// The dimension of the state the snapshot was taken of.
    pub fn dim(&self) -> usize {
        self.dim
    }
}

impl fmt::Debug for Snapshot {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(self, f)
    }
}

impl fmt::Display for Snapshot {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "[")?;
        for (i, v) in self.values().iter().enumerate() {
            if i > 0 {
                write!(f, ", ")?;
            }
            write!(f, "{v:e}")?;
        }
        if self.dim > self.len {
            write!(f, ", ... ({} components)", self.dim)?;
        }
        write!(f, "]")
    }
}

/// What can go wrong while integrating.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// An option is out of its allowed range.
    #[error("solver option `{name}` = {value:e} is not allowed: {allowed}")]
    InvalidOption {
        /// The option's name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
    /// The initial state, time or stop time is not usable.
    #[error("invalid initial value: {what} (t = {t} s, state {state})")]
    InvalidInitial {
        /// What is wrong.
        what: &'static str,
        /// Time.
        t: f64,
        /// State.
        state: Snapshot,
    },
    /// The right-hand side or the new state contains NaN or infinity.
    #[error("non-finite value (NaN or infinity) in the solution at t = {t} s, state {state}")]
    NonFinite {
        /// Time of the step that produced it.
        t: f64,
        /// State at the start of that step.
        state: Snapshot,
    },
    /// The step size fell below the minimum allowed.
    #[error("step size {h:e} s fell below the minimum {h_min:e} s at t = {t} s, state {state}")]
    StepSizeUnderflow {
        /// Time.
        t: f64,
        /// Step size proposed.
        h: f64,
        /// The minimum.
        h_min: f64,
        /// State.
        state: Snapshot,
    },
    /// More steps than allowed.
    #[error("more than {max_steps} steps at t = {t} s, state {state}")]
    TooManySteps {
        /// Time.
        t: f64,
        /// The limit.
        max_steps: u64,
        /// State.
        state: Snapshot,
    },
    /// Events keep firing without time advancing (Zeno behaviour).
    #[error("{count} events without time advancing by more than the event tolerance at t = {t} s (last: {last}), state {state}")]
    EventChatter {
        /// Time.
        t: f64,
        /// How many events in a row.
        count: u32,
        /// The last event.
        last: crate::EventKind,
        /// State.
        state: Snapshot,
    },
    /// The system declares more event functions than the solver supports.
    #[error("the system declares {n} event functions; at most {max} are supported")]
    TooManyEvents {
        /// Declared.
        n: usize,
        /// Supported.
        max: usize,
    },
}
