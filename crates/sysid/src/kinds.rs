//! The training of each model kind behind one trait, after linfa's `Fit` (their
//! prediction, linfa's `Predict`, is `models::kinds::Structure`): each kind's training is
//! one file (the lagged `arx` and `rhonn` in `lagged.rs`, `cascade.rs`, `pump_grey/`,
//! `wiener_hammerstein.rs`), and [`fitter`](super::fitter) is the one place that maps a
//! spec's `kind` to it.

use super::{Model, ModelSpec};
use crate::data::Record;
use crate::error::Result;

/// How a model kind trains.
pub(crate) trait Fit: Sync {
    /// Train the blank model `m` (names, sample time, scaling and output ranges set) on
    /// `records`.
    fn fit(&self, spec: &ModelSpec, records: &[Record], m: &mut Model) -> Result<()>;
}
