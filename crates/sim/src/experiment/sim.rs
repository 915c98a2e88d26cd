//! The one run loop, for any plant: the system (a plant alone, or with an identifier
//! along) in the event-locating solver, stopped at the sampling instants, where a hook
//! acts (a controller measures and sets the held input, or a sample is taken); after
//! every step a hook reads the step's dense output (figures, output samples). Every
//! plant's scenarios run through it (`any_plant.rs`, `closed_loop.rs`).

use super::integrated::Integrated;
use crate::error::{Error, Result};
use crate::plant::Plant;
use rhonn_ode::{Dopri5, Options, State, StepResult};

/// Sampling instants `k * every / per_second` seconds, k = 0, 1, ...: with `every` in
/// ms and `per_second` 1000, an instant and an output sample at the same decimal time
/// are the same double.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Instants {
    /// The period, in units of 1 / `per_second` seconds.
    pub every: f64,
    /// Units of `every` per second (1 when `every` is in seconds).
    pub per_second: f64,
}

impl Instants {
    /// Every `period_s` seconds.
    pub fn seconds(period_s: f64) -> Self {
        Instants {
            every: period_s,
            per_second: 1.0,
        }
    }

    /// Every `period_ms` milliseconds.
    pub fn milliseconds(period_ms: f64) -> Self {
        Instants {
            every: period_ms,
            per_second: 1000.0,
        }
    }

    /// Instant k \[s\].
    pub fn at(&self, k: u64) -> f64 {
        k as f64 * self.every / self.per_second
    }
}

/// What a run does at its instants and after its steps.
pub trait Hooks<S: Integrated> {
    /// At t = 0 and at each sampling instant before the end: measure, act (e.g. hold a
    /// new input in `solver.system_mut().plant_mut()`), record.
    fn instant(&mut self, _solver: &mut Dopri5<S>) -> Result<()> {
        Ok(())
    }
    /// After every step (`[t_prev, t]`), `done` on the one that reaches the end.
    fn stepped(&mut self, _solver: &Dopri5<S>, _done: bool) -> Result<()> {
        Ok(())
    }
}

/// Run `solver` to `t_end`, stopping at `instants` (t = 0 included, the end excluded)
/// when given, calling `hooks`. A solver failure is an error with the time and the
/// plant's state.
pub fn drive<S: Integrated>(
    solver: &mut Dopri5<S>,
    t_end: f64,
    instants: Option<Instants>,
    hooks: &mut impl Hooks<S>,
) -> Result<()> {
    let mut k = 0u64;
    if instants.is_some() {
        hooks.instant(solver)?;
        k = 1;
    }
    loop {
        let t_stop = instants.map_or(t_end, |c| c.at(k).min(t_end));
        let r = solver.step(t_stop).map_err(|e| solver_error(e, solver))?;
        let done = solver.t() >= t_end;
        hooks.stepped(solver, done)?;
        if done {
            return Ok(());
        }
        if let (StepResult::Reached { .. }, Some(_)) = (r, instants) {
            hooks.instant(solver)?;
            k += 1;
        }
    }
}

/// `system` from `x0` at t = 0 in the event-locating solver; a failure to start names
/// the plant's initial state.
pub fn start<S: Integrated>(system: S, x0: S::State, opts: Options<S::State>) -> Result<Dopri5<S>> {
    // Described before the solver takes the system (a few numbers, once per run).
    let state = describe(system.plant(), x0.as_slice());
    Dopri5::new(system, 0.0, x0, opts).map_err(|e| Error::Solver {
        t_s: 0.0,
        state,
        source: Box::new(e),
    })
}

/// A solver failure at the solver's time, with the plant's state.
pub fn solver_error<S: Integrated>(e: rhonn_ode::Error, solver: &Dopri5<S>) -> Error {
    Error::Solver {
        t_s: solver.t(),
        state: describe(solver.system().plant(), solver.state()),
        source: Box::new(e),
    }
}

/// A plant's state (the first components of `x`) named and in display units, for
/// error messages.
pub fn describe<P: Plant>(plant: &P, x: &[f64]) -> String {
    plant
        .states()
        .iter()
        .zip(x)
        .map(|(q, v)| format!("{} = {:.6} {}", q.name, q.to_display(*v), q.display_unit))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiment::Alone;
    use crate::plant::{Input, Tanks, TanksParams};
    use rhonn_ode::Options;

    /// Counts what the loop calls.
    #[derive(Default)]
    struct Count {
        instants: Vec<f64>,
        steps: usize,
        done_at: Vec<f64>,
        fail_at: Option<f64>,
    }

    impl<S: Integrated> Hooks<S> for Count {
        fn instant(&mut self, solver: &mut Dopri5<S>) -> Result<()> {
            self.instants.push(solver.t());
            if self.fail_at.is_some_and(|t| solver.t() >= t) {
                return Err(crate::error::invalid("test", solver.t(), "before the failure"));
            }
            Ok(())
        }
        fn stepped(&mut self, solver: &Dopri5<S>, done: bool) -> Result<()> {
            self.steps += 1;
            if done {
                self.done_at.push(solver.t());
            }
            Ok(())
        }
    }

    fn tanks_solver() -> Dopri5<Alone<Tanks>> {
        let tanks = Alone(Tanks::new(TanksParams::default(), Input::Held(5.0)));
        Dopri5::new(tanks, 0.0, [0.05, 0.05], Options::uniform(2, 1e-7, 1e-9)).unwrap()
    }

    #[test]
    fn the_loop_stops_at_every_instant_before_the_end_and_ends_once() {
        let mut s = tanks_solver();
        let mut c = Count::default();
        drive(&mut s, 2.5, Some(Instants::seconds(0.5)), &mut c).unwrap();
        assert_eq!(c.instants, vec![0.0, 0.5, 1.0, 1.5, 2.0]);
        assert_eq!(c.done_at, vec![2.5]);
        assert!(c.steps >= 5, "{}", c.steps);
        // Without instants: no stop, the same end.
        let (mut s, mut c) = (tanks_solver(), Count::default());
        drive(&mut s, 2.5, None, &mut c).unwrap();
        assert!(c.instants.is_empty());
        assert_eq!(c.done_at, vec![2.5]);
        // Instants in ms give the decimal times exactly.
        assert_eq!(Instants::milliseconds(10.0).at(301), 3.01);
        // A hook's error ends the run where it happened.
        let (mut s, mut c) = (
            tanks_solver(),
            Count {
                fail_at: Some(1.0),
                ..Count::default()
            },
        );
        assert!(drive(&mut s, 2.5, Some(Instants::seconds(0.5)), &mut c).is_err());
        assert_eq!(s.t(), 1.0);
    }

    #[test]
    fn a_solver_failure_names_the_time_and_the_plant_state() {
        let tanks = Alone(Tanks::new(TanksParams::default(), Input::Held(5.0)));
        let mut o = Options::uniform(2, 1e-7, 1e-9);
        o.max_steps = 3;
        let mut s = Dopri5::new(tanks, 0.0, [0.05, 0.05], o).unwrap();
        let e = drive(&mut s, 100.0, None, &mut Count::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("t = ") && e.contains(" mm, h2 = "), "{e}");
    }
}
