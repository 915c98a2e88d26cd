/*!
Simulation, identification and control of the solenoid-controlled variable-displacement
pump of the thesis "Adaptive identification of a pneumatic pump" (Petraki, 2011).

# Simulate
A scenario (a TOML file, or one of the shipped ones in [`experiment::preset`]) is checked
once into an [`experiment::Scenario`] and run by [`experiment::run`], which integrates the
[`plant::PumpSystem`] with the event-locating Dormand-Prince solver of `rhonn-ode`
(valve switching and the limited integrators of line pressure and stroke are located,
not stepped across), drives it with an open-loop current or the sampled
[`control::Pi`] regulator, and hands every output sample to a
[`experiment::Recorder`]. The returned [`experiment::Summary`] holds the solver's counters
and the run's figures.

```
use rhonn::experiment::{preset, run, Trace};
let scenario = preset::load_any("thesis-ch3")?.pump_run()?;
let mut trace = Trace::default();
let summary = run(&scenario, &mut trace)?;
// The stroke follows phi I / K_a and holds 17.23 mm at 0.8 A.
assert!((summary.figures.stroke_max_mm - 17.23).abs() < 0.01);
# Ok::<(), rhonn::Error>(())
```

All quantities are SI inside ([`units`] converts); people read MPa, mm and dm^3/s.
*/
#![deny(missing_docs)]
// `!(a < b)` is deliberate throughout: it is also true when either side is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Numerical kernels index several slices in lockstep; index loops read best there.
#![allow(clippy::needless_range_loop)]

pub mod activity;
pub mod any_model;
pub mod benchmark;
pub mod cancel;
pub mod control;
pub mod corpus;
pub mod data;
pub mod error;
pub mod experiment;
pub mod ident;
pub mod identification;
pub mod law;
pub mod metrics;
pub mod models;
pub mod net;
pub mod plant;
pub mod signal;
pub mod sysid;
pub mod units;

pub use error::{Error, ErrorKind, InvalidValue, Result};
