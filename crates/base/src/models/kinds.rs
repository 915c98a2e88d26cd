//! The model kinds behind one trait, after linfa's `Predict` (their training, linfa's
//! `Fit`, is `sysid::kinds::Fit`): each kind is one file with one implementation of
//! [`Structure`] (the lagged `arx` and `rhonn` in `lagged.rs`, `cascade.rs`, `pump_grey/`,
//! `wiener_hammerstein.rs`), and [`model_kind`](super::model_kind) is the one place that
//! maps a spec's `kind` to it. [`Model`] calls through it; a new kind is a
//! file here, a file in `sysid`, a variant of [`Kind`](super::Kind) and a line in each
//! registry (`model_kind`, `sysid::fitter`).

use super::{Model, ModelSpec};
use crate::data::Record;
use crate::error::Result;

/// What a model kind provides: its own spec rules, prediction and the check of a stored
/// model.
pub trait Structure: Sync {
    /// The kind with its article, for messages ("an ARX", "a cascade"); `kind` tells the
    /// kinds that share an implementation apart.
    fn with_article(&self, kind: super::Kind) -> &'static str;

    /// Check the keys of `spec` this kind has rules of its own for (the common keys are
    /// checked first by [`ModelSpec::check`]).
    fn check_spec(&self, spec: &ModelSpec) -> Result<()>;

    /// Samples the model needs before its first prediction.
    fn max_lag(&self, spec: &ModelSpec) -> usize {
        spec.settle
    }

    /// Refuse outputs this kind cannot model (before the records are read).
    fn check_outputs(&self, _outputs: &[String]) -> Result<()> {
        Ok(())
    }

    /// Predict `r` (see [`Model::predict`]).
    fn predict(&self, m: &Model, r: &Record, steps_ahead: Option<usize>) -> Result<(Vec<Vec<f64>>, usize)>;

    /// Check a stored model's parameters (its spec and scaling are checked first).
    fn validate(&self, m: &Model) -> Result<()>;

    /// Number of stored parameters (per output for a lagged model).
    fn n_params(&self, m: &Model) -> usize;

    /// Whether the data checks of a model of lagged samples (`data_warnings`: sampling,
    /// lags, suspicious columns) apply to this kind.
    fn data_warnings_apply(&self) -> bool {
        true
    }

    /// The trained parameters by name, for a kind whose parameters mean something on
    /// their own (`summary.json`'s `parameters`); None otherwise.
    fn named_parameters(&self, _m: &Model) -> Option<std::collections::BTreeMap<String, f64>> {
        None
    }

    /// Whether `spec`'s terms are unbounded polynomials (see `ModelSpec::polynomial_terms`).
    fn polynomial_terms(&self, _spec: &ModelSpec) -> bool {
        false
    }

    /// Whether a free run is held within the outputs' widened training range, so that
    /// reaching that bound tells of an unstable model (`sysid::free_run_at_bound`).
    fn holds_outputs_in_range(&self) -> bool {
        true
    }
}
