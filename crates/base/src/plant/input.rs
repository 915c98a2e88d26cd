//! What drives a plant's input.

use crate::signal::{Affine, Signal};

/// An input of a plant: a signal of time, or a value held by a sampled controller
/// (zero-order hold).
#[derive(Debug, Clone, PartialEq)]
pub enum Input {
    /// A profile.
    Signal(Signal),
    /// Held constant until changed.
    Held(f64),
}

impl Input {
    #[inline]
    pub(crate) fn segment(&self, t: f64) -> usize {
        match self {
            Input::Signal(s) => s.segment(t),
            Input::Held(_) => 0,
        }
    }
    #[inline]
    pub(crate) fn eval_in(&self, seg: usize, t: f64) -> f64 {
        match self {
            Input::Signal(s) => s.eval_in(seg, t),
            Input::Held(v) => *v,
        }
    }
    /// The value at `t` (a signal evaluated in full: for a plant's right-hand side,
    /// a plant that keeps segments as modes evaluates within its segment instead).
    pub fn at(&self, t: f64) -> f64 {
        match self {
            Input::Signal(s) => s.eval(t),
            Input::Held(v) => *v,
        }
    }

    /// The first breakpoint of the input after `t` (infinity when held).
    #[inline]
    pub fn next_breakpoint(&self, t: f64) -> f64 {
        match self {
            Input::Signal(s) => s.next_breakpoint(t),
            Input::Held(_) => f64::INFINITY,
        }
    }
    pub(crate) fn affine_in(&self, seg: usize) -> Option<Affine> {
        match self {
            Input::Signal(s) => s.affine_in(seg),
            Input::Held(v) => Some(Affine::constant(*v)),
        }
    }
}
