//! `kind = "mean"`: each output's training mean, a constant whatever the inputs. The
//! reference every model is judged against (a fit of 0 %; the selection's "no better than
//! predicting the training mean"), as a model of its own, so that `rhonn predict`, Python
//! and the report score it as they score any other. It is also the smallest model kind,
//! the one to copy when adding a kind (docs/ARCHITECTURE.md): this file and
//! `sysid/mean.rs`.
//!
//! `model.json` stores output j's mean, in its own units, in `weights[j] = [mean]`. The
//! spec's other keys (lags, degree, law) do not apply and are not read.

use super::{Model, ModelSpec};
use crate::data::Record;
use crate::error::{invalid, Result};

/// `kind = "mean"`.
pub struct Mean;

impl super::kinds::Structure for Mean {
    fn with_article(&self, _kind: super::Kind) -> &'static str {
        "a mean"
    }

    fn check_spec(&self, _spec: &ModelSpec) -> Result<()> {
        Ok(())
    }

    fn max_lag(&self, _spec: &ModelSpec) -> usize {
        0
    }

    /// Every sample, free run or K steps ahead, is the training mean: a genuine prediction
    /// from the first sample on.
    fn predict(&self, m: &Model, r: &Record, _steps_ahead: Option<usize>) -> Result<(Vec<Vec<f64>>, usize)> {
        let cols = m.weights.iter().map(|w| vec![w[0]; r.len()]).collect();
        Ok((cols, 0))
    }

    fn validate(&self, m: &Model) -> Result<()> {
        let shape_ok = m.weights.len() == m.no() && m.weights.iter().all(|w| w.len() == 1);
        if !shape_ok {
            let lens: Vec<usize> = m.weights.iter().map(Vec::len).collect();
            return Err(invalid(
                "model.weights",
                format!("{} vectors of lengths {lens:?}", m.weights.len()),
                format!(
                    "one vector of one value, the mean, for each of the {} outputs",
                    m.no()
                ),
            ));
        }
        match m.weights.iter().position(|w| !w[0].is_finite()) {
            Some(j) => Err(invalid(
                format!("model.weights[{j}][0]"),
                m.weights[j][0],
                "a finite mean",
            )),
            None => Ok(()),
        }
    }

    fn n_params(&self, _m: &Model) -> usize {
        1
    }

    fn data_warnings_apply(&self) -> bool {
        false
    }
}
