//! The training of `kind = "mean"` (its structure and prediction: `models::mean`): each
//! output's mean over every sample of every record.

use super::{Model, ModelSpec};
use crate::data::Record;
use crate::error::Result;
use crate::kinds::Fit;

/// `kind = "mean"`.
pub(crate) struct Mean;

impl Fit for Mean {
    fn fit(&self, _spec: &ModelSpec, records: &[Record], m: &mut Model) -> Result<()> {
        let samples: usize = records.iter().map(Record::len).sum();
        m.weights = (0..m.no())
            .map(|j| {
                let sum: f64 = records.iter().flat_map(|r| &r.outputs[j]).sum();
                vec![sum / samples.max(1) as f64]
            })
            .collect();
        Ok(())
    }

    fn parameters(&self, _spec: &ModelSpec, _ni: usize, no: usize) -> usize {
        no
    }

    /// A sum over the samples.
    fn work(&self, _spec: &ModelSpec, n: f64, _p: f64, no: f64) -> f64 {
        n * no
    }
}
