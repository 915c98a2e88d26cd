//! Counters reported with every run.

use core::fmt;

/// What the solver did: steps, right-hand-side evaluations, events.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stats {
    /// Right-hand-side evaluations, including those spent locating events.
    pub rhs_evaluations: u64,
    /// Accepted steps (a step cut short at an event counts as accepted).
    pub accepted_steps: u64,
    /// Rejected steps.
    pub rejected_steps: u64,
    /// State events located (user events and limited-integrator bound events).
    pub events: u64,
    /// Times a step was made to land on a breakpoint or stop time.
    pub breakpoints: u64,
}

impl core::ops::AddAssign for Stats {
    /// The counters of two runs together.
    fn add_assign(&mut self, st: Stats) {
        self.rhs_evaluations += st.rhs_evaluations;
        self.accepted_steps += st.accepted_steps;
        self.rejected_steps += st.rejected_steps;
        self.events += st.events;
        self.breakpoints += st.breakpoints;
    }
}

impl fmt::Display for Stats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} rhs evaluations, {} accepted steps, {} rejected steps, {} events, {} breakpoints",
            self.rhs_evaluations, self.accepted_steps, self.rejected_steps, self.events, self.breakpoints
        )
    }
}
