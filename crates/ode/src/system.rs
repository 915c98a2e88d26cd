//! The problem: what a plant (or a test ODE) tells the solver.

use crate::State;

/// Which zero crossings of an event function count.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// From `g <= 0` to `g > 0`.
    Rising,
    /// From `g >= 0` to `g < 0`.
    Falling,
    /// Either of the above, except a crossing that starts exactly at zero.
    Both,
}

impl Direction {
    /// Whether a change from `g_old` to `g_new` over a step is a crossing.
    #[inline]
    pub fn crossed(self, g_old: f64, g_new: f64) -> bool {
        match self {
            Direction::Rising => g_old <= 0.0 && g_new > 0.0,
            Direction::Falling => g_old >= 0.0 && g_new < 0.0,
            Direction::Both => (g_old < 0.0 && g_new > 0.0) || (g_old > 0.0 && g_new < 0.0),
        }
    }

    /// Whether `g` lies strictly past the crossing, seen from `g_old`.
    #[inline]
    pub(crate) fn past(self, g_old: f64, g: f64) -> bool {
        match self {
            Direction::Rising => g > 0.0,
            Direction::Falling => g < 0.0,
            Direction::Both => (g_old < 0.0 && g > 0.0) || (g_old > 0.0 && g < 0.0),
        }
    }
}

/// What the solver should do after an event.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventAction {
    /// Update modes and go on integrating.
    Continue,
    /// Return [`crate::StepResult::Stopped`] to the caller.
    Stop,
}

/// A system of ODEs `dx/dt = f(t, x)` with discrete modes, event functions and
/// limited integrators.
///
/// Modes (a valve branch, the segment of an input profile, a held controller output)
/// live in the system and are constant during a step: the solver calls
/// [`System::update_modes`] at the start and after every event, breakpoint and stop, so
/// the right-hand side is smooth within each step. Event functions are located on the
/// dense output to within the event tolerance; the solver stops there, calls
/// [`System::on_event`], and restarts.
pub trait System {
    /// The state storage (`[f64; N]` or `Vec<f64>`).
    type State: State;

    /// Number of states.
    fn dim(&self) -> usize;

    /// The right-hand side `dx = f(t, x)` in the current modes. It must not allocate
    /// (it runs thousands of times per simulated second). Non-finite results are caught
    /// by the solver.
    fn rhs(&self, t: f64, x: &[f64], dx: &mut [f64]);

    /// Number of event functions (at most [`crate::MAX_EVENTS`]).
    fn n_events(&self) -> usize {
        0
    }

    /// Evaluate the event functions at `(t, x)` into `g` (length [`System::n_events`]).
    fn events(&self, _t: f64, _x: &[f64], _g: &mut [f64]) {}

    /// Which crossings of event function `j` count, in the current modes.
    fn event_direction(&self, _j: usize) -> Direction {
        Direction::Both
    }

    /// Event `j` fired at `t`; `x` is the state there and may be changed (a reset).
    /// Modes are updated by [`System::update_modes`] right after.
    fn on_event(&mut self, _j: usize, _t: f64, _x: &mut [f64]) -> EventAction {
        EventAction::Continue
    }

    /// Choose the discrete modes for the interval starting at `t` in state `x`. The
    /// input profiles pick their segment here (right-continuous: the segment that starts
    /// at `t`).
    fn update_modes(&mut self, _t: f64, _x: &[f64]) {}

    /// The first breakpoint of an input strictly after `t` (a kink or jump of an input),
    /// or infinity. Steps land exactly on breakpoints.
    fn next_breakpoint(&self, _t: f64) -> f64 {
        f64::INFINITY
    }

    /// Limits `(lower, upper)` of state `i` when it is a limited integrator, as
    /// Simulink's Integrator with 'Limit output': at a bound the state is held while its
    /// derivative points outward, and released when the derivative turns inward. Use
    /// infinities for a free state.
    fn bounds(&self, _i: usize) -> (f64, f64) {
        (f64::NEG_INFINITY, f64::INFINITY)
    }
}
