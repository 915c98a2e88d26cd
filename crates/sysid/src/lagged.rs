//! The training of the lagged models, `kind = "arx"` and `kind = "rhonn"` (their
//! structure and prediction: `models::lagged`): the high-order terms of the spec, then
//! the weights by [`fit_weights`](super::estimate).

use super::kinds::Fit;
use super::{check_regressor_count, Estimator, Model, ModelSpec};
use crate::data::Record;
use crate::error::Result;

/// `kind = "arx"` and `kind = "rhonn"`.
pub(crate) struct Lagged;

impl Fit for Lagged {
    fn fit(&self, spec: &ModelSpec, records: &[Record], m: &mut Model) -> Result<()> {
        let (ni, no) = (m.ni(), m.no());
        check_regressor_count(spec, ni, no)?;
        m.terms = super::lagged_terms(spec, ni, no);
        super::estimate::fit_weights(m, records)
    }

    fn parameters(&self, spec: &ModelSpec, ni: usize, no: usize) -> usize {
        super::n_phi(spec, ni, no) + super::lagged_terms(spec, ni, no).len() + 1
    }

    /// Least squares accumulate the normal equations (`n p^2`); on the free-run error,
    /// each iteration as a free run per weight of every output (its Jacobian by differences).
    /// The Jacobian now comes from the free run's sensitivities, several times less work
    /// (`lagged_normal`), but the estimate stays in the units the default budget was set in,
    /// so the same candidates run within it.
    fn work(&self, spec: &ModelSpec, n: f64, p: f64, no: f64) -> f64 {
        let epochs = spec.epochs.max(1) as f64;
        match spec.law {
            Estimator::SimulationError => n * p * p * (1.0 + epochs * no * no),
            _ => n * p * p,
        }
    }
}
