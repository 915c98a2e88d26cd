/*!
rhonn's foundations: what every other part stands on. Plants ([`plant`]: the pump, the
tanks, any `Plant`), signals, high-order networks ([`net`]) and their learning laws
([`law`]), recorded data ([`data`]), figures ([`metrics`]), units, errors, cancellation,
and the model structures both identifiers learn ([`models`]: the spec, the stored model,
each kind's prediction). The `rhonn` crate re-exports every module under its own name.

All quantities are SI inside ([`units`] converts); people read MPa, mm and dm^3/s.
*/
#![deny(missing_docs)]
// `!(a < b)` is deliberate throughout: it is also true when either side is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Numerical kernels index several slices in lockstep; index loops read best there.
#![allow(clippy::needless_range_loop)]

pub mod activity;
pub mod cancel;
pub mod data;
pub mod error;
pub mod law;
pub mod metrics;
pub mod models;
pub mod net;
pub mod plant;
pub mod signal;
pub mod units;

pub use error::{Error, ErrorKind, InvalidValue, Result};
