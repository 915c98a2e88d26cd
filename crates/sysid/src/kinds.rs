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

    /// The parameters of `spec` for `ni` inputs and `no` outputs, as the selection's work
    /// budget counts them (`budget::parameters`).
    fn parameters(&self, spec: &ModelSpec, ni: usize, no: usize) -> usize;

    /// The estimated work of training `spec` once on `n` samples with `p` parameters
    /// ([`Fit::parameters`]) and `no` outputs, in the budget's units of about one scalar
    /// multiply-add (`budget::work`). By default a Levenberg-Marquardt on the free-run error
    /// with a Jacobian by differences: `n p^2` an iteration, `epochs` iterations at most.
    fn work(&self, spec: &ModelSpec, n: f64, p: f64, _no: f64) -> f64 {
        n * p * p * spec.epochs.max(1) as f64
    }
}
