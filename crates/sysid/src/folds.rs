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

pub(super) use super::probes::PartRun;

/// A model's predictions on the held-out parts: per part, the prediction of every output
/// and its first predicted sample (None for a part shorter than the model's lags need), and
/// the outputs' training standard deviations the errors are divided by.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct HeldOut {
    pub parts: Vec<Option<PartRun>>,
    pub output_sd: Vec<f64>,
    /// How the model runs free on held steps and perturbed inputs (`probes`).
    pub probe: super::probes::Probe,
}

/// `m`'s predictions on the held-out parts `test` (free run, or `steps` ahead).
pub(super) fn held_out_runs(m: &Model, test: &[Record], steps: Option<usize>) -> Result<HeldOut> {
    let parts = test
        .iter()
        .map(|r| {
            let needed = m
                .spec
                .max_lag()
                .saturating_add(steps.unwrap_or(1))
                .saturating_add(2);
            if r.len() < needed {
                Ok(None)
            } else {
                m.predict(r, steps).map(Some)
            }
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(HeldOut {
        parts,
        output_sd: m.output_norm.iter().map(|n| n.1).collect(),
        probe: super::probes::probe(m, test),
    })
}

/// The RMS error of the predictions `h` on the held-out parts `test`, divided by each
/// output's training standard deviation and averaged over parts and outputs.
pub(super) fn held_out_score(h: &HeldOut, test: &[Record]) -> Result<f64> {
    let mut total = 0.0;
    let mut count = 0.0;
    for (r, part) in test.iter().zip(&h.parts) {
        let Some((pred, first)) = part else { continue };
        for (j, (y, yh)) in r.outputs.iter().zip(pred).enumerate() {
            let e = metrics::rms_error(&y[*first..], &yh[*first..]) / h.output_sd[j];
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

/// A model's RMS error on the held-out parts `test`, divided by each output's training
/// standard deviation and averaged over parts and outputs.
#[cfg(test)]
pub(super) fn held_out_error(m: &Model, test: &[Record], steps: Option<usize>) -> Result<f64> {
    held_out_score(&held_out_runs(m, test, steps)?, test)
}

/// Per output and fold, the normalised RMS error of the predictions `runs` (one per fold)
/// on the held-out parts of `parts`, averaged over the fold's parts (empty without runs).
pub(super) fn output_scores(runs: &[HeldOut], parts: &[(Vec<Record>, Vec<Record>)]) -> Vec<Vec<f64>> {
    let no = runs.first().map_or(0, |h| h.output_sd.len());
    let by_fold: Vec<Vec<f64>> = runs
        .iter()
        .zip(parts)
        .map(|(h, (_, test))| fold_output_scores(h, test))
        .collect();
    (0..no).map(|j| by_fold.iter().map(|f| f[j]).collect()).collect()
}

/// One fold's normalised RMS error per output: the mean over its held-out parts.
pub(super) fn fold_output_scores(h: &HeldOut, test: &[Record]) -> Vec<f64> {
    (0..h.output_sd.len())
        .map(|j| {
            let (mut sum, mut count) = (0.0, 0.0f64);
            for (r, part) in test.iter().zip(&h.parts) {
                let Some((pred, first)) = part else { continue };
                sum += metrics::rms_error(&r.outputs[j][*first..], &pred[j][*first..]) / h.output_sd[j];
                count += 1.0;
            }
            sum / count.max(1.0)
        })
        .collect()
}

/// Per output and fold, the error of predicting the fold's training mean on its held-out
/// parts, normalised as the candidates' (by the training parts' standard deviation) and
/// averaged the same way: what a model must beat to say more than a constant.
pub(super) fn mean_scores(parts: &[(Vec<Record>, Vec<Record>)], no: usize) -> Vec<Vec<f64>> {
    (0..no)
        .map(|j| {
            parts
                .iter()
                .map(|(train, test)| {
                    // The models' own normalisation (`blank_model`): a constant divides by 1.
                    let cols: Vec<&[f64]> = train.iter().map(|r| r.outputs[j].as_slice()).collect();
                    let (mean, sd) = metrics::mean_std(&cols);
                    let (mut sum, mut count) = (0.0, 0.0f64);
                    for r in test {
                        let e = (r.outputs[j].iter().map(|v| (v - mean).powi(2)).sum::<f64>()
                            / r.len().max(1) as f64)
                            .sqrt();
                        sum += e / sd;
                        count += 1.0;
                    }
                    sum / count.max(1.0)
                })
                .collect()
        })
        .collect()
}

/// The mean of each row.
pub(super) fn row_means(v: &[Vec<f64>]) -> Vec<f64> {
    v.iter()
        .map(|r| r.iter().sum::<f64>() / r.len().max(1) as f64)
        .collect()
}
