/*!
rhonn's simulation and control (`rhonn::experiment`, `rhonn::control`): the one run loop
that integrates any plant with the event-locating solver, the controllers and the
registry of their kinds, scenarios (TOML) and campaigns.
*/
#![deny(missing_docs)]
// `!(a < b)` is deliberate throughout: it is also true when either side is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Numerical kernels index several slices in lockstep; index loops read best there.
#![allow(clippy::needless_range_loop)]

pub mod control;
pub mod experiment;

// The layers below, under the names this crate's modules use (`crate::plant`, ...).
pub(crate) use rhonn_base::{activity, error, law, metrics, net, plant, signal, units, Result};
pub(crate) use rhonn_ident as ident;
