//! The selection's folds: contiguous parts of every record, and a model's error on the
//! held-out ones.

use super::Model;
use crate::data::Record;
use crate::error::{invalid, Result};
use crate::metrics;

/// The folds: (training parts, held-out parts) for each fold.
pub(super) fn folds(records: &[Record], k: usize) -> Vec<(Vec<Record>, Vec<Record>)> {
    (0..k)
        .map(|f| {
            let mut train = Vec::new();
            let mut test = Vec::new();
            for r in records {
                let n = r.len();
                for g in 0..k {
                    let p = r.slice(g * n / k, (g + 1) * n / k);
                    if g == f {
                        test.push(p);
                    } else {
                        train.push(p);
                    }
                }
            }
            (train, test)
        })
        .collect()
}

/// A model's RMS error on the held-out parts `test`, divided by each output's training
/// standard deviation and averaged over parts and outputs.
pub(super) fn held_out_error(m: &Model, test: &[Record], steps: Option<usize>) -> Result<f64> {
    let mut total = 0.0;
    let mut count = 0.0;
    for r in test {
        if r.len()
            < m.spec
                .max_lag()
                .saturating_add(steps.unwrap_or(1))
                .saturating_add(2)
        {
            continue;
        }
        let (pred, first) = m.predict(r, steps)?;
        for (j, (y, yh)) in r.outputs.iter().zip(&pred).enumerate() {
            let e = metrics::rms_error(&y[first..], &yh[first..]) / m.output_norm[j].1;
            if !e.is_finite() {
                return Err(invalid("prediction", e, "a finite error"));
            }
            total += e;
            count += 1.0;
        }
    }
    if count == 0.0 {
        return Err(invalid(
            "folds",
            "too short",
            "held-out parts longer than the model's lags",
        ));
    }
    Ok(total / count)
}
