/*!
Identification and adaptive control of nonlinear dynamical systems with recurrent
high-order neural networks (RHONN): the library under one name. Its layers are crates of
their own, each re-exported here under its module's name:
- `rhonn-base`: [`plant`], [`signal`], [`net`], [`law`], [`data`], [`metrics`], [`models`]
  (the model structures both identifiers learn), [`units`], [`error`], [`cancel`],
  [`activity`];
- `rhonn-ident`: [`ident`], online identification;
- `rhonn-sysid`: [`sysid`], offline identification;
- `rhonn-sim`: [`experiment`] and [`control`], simulation and control;
- this crate: what uses several of them, [`identification`] (`rhonn identify`: the online
  model beside the offline ARX), [`benchmark`], [`corpus`] and [`any_model`].

# Simulate
A scenario (a TOML file in the one format every plant shares, or one of the shipped ones
in [`experiment::preset`]) is an [`experiment::ScenarioSpec`]; [`experiment::ScenarioSpec::run`]
runs it on the generic runner, whatever its plant (the pump, the cascaded tanks, or a
user's own [`plant::Plant`] through [`experiment::run_plant_scenario_on`]): the plant is
integrated with the event-locating Dormand-Prince solver of `rhonn-ode` (the pump's valve
switching and the limited integrators of its line pressure and stroke are located, not
stepped across), driven by its input profiles, an online identifier or a sampled
controller from [`control`]. The returned [`experiment::PlantRunOutput`] holds the
trajectory's columns (SI) and the summary (`summary.json`, display units).

```
use rhonn::experiment::preset;
let out = preset::load_any("thesis-ch3")?.run()?;
// The stroke follows phi I / K_a and holds 17.23 mm at 0.8 A.
let ranges = out.summary.open_loop.as_ref().unwrap();
let stroke = ranges.iter().find(|r| r.state == "stroke").unwrap();
assert!((stroke.max_value - 17.23).abs() < 0.01);
# Ok::<(), rhonn::Error>(())
```

All quantities are SI inside ([`units`] converts); people read MPa, mm and dm^3/s.
*/
#![deny(missing_docs)]
// `!(a < b)` is deliberate throughout: it is also true when either side is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Numerical kernels index several slices in lockstep; index loops read best there.
#![allow(clippy::needless_range_loop)]

pub mod any_model;
pub mod benchmark;
pub mod corpus;
pub mod identification;

pub use rhonn_base::{activity, cancel, data, error, law, metrics, models, net, plant, signal, units};
pub use rhonn_base::{Error, ErrorKind, InvalidValue, Result};
pub use rhonn_ident as ident;
pub use rhonn_sim::{control, experiment};
pub use rhonn_sysid as sysid;
