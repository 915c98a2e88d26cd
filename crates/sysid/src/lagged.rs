//! The training of the lagged models, `kind = "arx"` and `kind = "rhonn"` (their
//! structure and prediction: `models::lagged`): the high-order terms of the spec, then
//! the weights by [`fit_weights`](super::estimate).

use super::kinds::Fit;
use super::{check_regressor_count, Model, ModelSpec};
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
}
