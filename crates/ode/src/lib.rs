/*!
An explicit Dormand-Prince 5(4) integrator for hybrid systems: adaptive step with
per-state tolerances, the 4th-order "free" dense output, event location on the dense
output, Simulink-style limited integrators and input breakpoints.

# Overview
- A [`System`] is the problem: right-hand side, event functions, bounds of limited
  states, breakpoints of its inputs and its discrete modes. The solver never names a
  physical quantity, so a pump, a neural identifier or a test ODE plug in alike.
- [`Options`] is the method's configuration, with named defaults; [`Options::ode45`]
  reproduces MATLAB's ode45 defaults and step control, [`Profile::Hairer`] is Hairer's
  DOPRI5.
- [`Dopri5`] integrates: [`Dopri5::step`] takes one step and says why it ended
  ([`StepResult`]: an ordinary step, an event, a breakpoint, the stop time);
  [`Dopri5::interpolate`] reads the dense output of the last step; [`Stats`] counts
  evaluations, steps and events.

# Why hand-written
No crate offers `no_std`, Simulink's limited-integrator semantics and event location on
the dense output together (see `docs/pump-model.md` section 5). The core is `no_std`, does
not allocate per step, and works on `[f64; N]` on the stack or (feature `alloc`) on a
`Vec<f64>` allocated once per run.

# Events and modes
Modes are constant during a step, so each step integrates a smooth right-hand side. An
event function is located to within [`Options::event_tol_s`]; the solver stops at the
far end of the final bracket, where the function is strictly past zero, calls
[`System::on_event`], then [`System::update_modes`], and restarts. A limited state
that reaches a bound is clamped and held (derivative zero) until its unclamped
derivative turns inward, which is itself a located event.

Event functions are checked at the end of each step: a function that crosses zero and
back within one step is not seen. While a state is held its derivative is zero and does
not limit the step, so bound the step with [`Options::h_max_s`] when an input can
release a held state while every other state is at rest.

```
use rhonn_ode::{Dopri5, Options, StepResult, System};
// A saturating integrator: dx/dt = 1, held at 0.5.
struct Sat;
impl System for Sat {
    type State = [f64; 1];
    fn dim(&self) -> usize { 1 }
    fn rhs(&self, _t: f64, _x: &[f64], dx: &mut [f64]) { dx[0] = 1.0; }
    fn bounds(&self, _i: usize) -> (f64, f64) { (0.0, 0.5) }
}
let mut s = Dopri5::new(Sat, 0.0, [0.0], Options::default()).unwrap();
let mut hit = None;
loop {
    match s.step(1.0).unwrap() {
        StepResult::Event { t, .. } => hit = Some(t),
        StepResult::Reached { .. } => break,
        _ => {}
    }
}
assert!((hit.unwrap() - 0.5).abs() < 1e-9);
assert_eq!(s.state()[0], 0.5);
```
*/
#![no_std]
#![deny(missing_docs)]
// `!(a <= b)` is deliberate throughout: it is also true when either side is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

#[cfg(feature = "alloc")]
extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

mod dopri5;
mod error;
mod options;
mod state;
mod stats;
mod system;
mod tableau;

pub use dopri5::{DenseComponent, Dopri5, EventKind, StepResult, MAX_EVENTS};
pub use error::{Error, Snapshot};
pub use options::{Options, Profile, DEFAULT_MAX_STEPS};
pub use state::State;
pub use stats::Stats;
pub use system::{Direction, EventAction, System};
