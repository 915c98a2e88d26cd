//! The training of `kind = "cascade"` (its structure, simulation and prediction:
//! `models::cascade`): Levenberg-Marquardt on the free-run simulation error over every
//! record from `starts` seeded random starts (run in parallel; the best final cost
//! wins), the hidden initial states of each record estimated with the weights.

use super::lm::lm_with_columns;
use super::{Model, ModelSpec};
use crate::data::Record;
use crate::error::{invalid, Result};
pub(crate) use crate::models::cascade::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Starts trained before the rest: when none of them ends valid, the fit stops.
pub(crate) const EARLY_STARTS: usize = 8;

/// Run starts `0..starts` through `run`: the first [`EARLY_STARTS`], then, only when one
/// of them is `valid`, the rest. In index order, so what runs does not depend on the
/// number of threads.
fn staged_starts<E>(
    starts: usize,
    run: impl Fn(std::ops::Range<usize>) -> Vec<E>,
    valid: impl Fn(&E) -> bool,
) -> Vec<E> {
    let first = starts.min(EARLY_STARTS);
    let mut ends = run(0..first);
    if ends.iter().any(valid) {
        ends.extend(run(first..starts));
    }
    ends
}

/// Train a cascade model: `m` arrives with its names and normalisation set. Returns the
/// training cost of the start it kept (the sum of squared normalised free-run residuals
/// that Levenberg-Marquardt minimised).
pub(crate) fn fit(spec: &ModelSpec, records: &[Record], m: &mut Model) -> Result<f64> {
    let n = spec.neurons;
    let co = Coords {
        n,
        ni: m.inputs.len(),
        free_exp: spec.free_exponents,
    };
    let data: Vec<(Vec<Vec<f64>>, Vec<f64>)> = records.iter().map(|r| normalised(m, r)).collect();
    let (ymin, ymax) = data
        .iter()
        .flat_map(|(_, y)| y.iter())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        });
    let nm = co.n_model();
    let fr = FreeRuns::new(co, &data);
    let residuals = |th: &[f64], out: &mut Vec<f64>| fr.all(th, out);
    let column = |th: &[f64], c: usize, r0: &[f64], out: &mut Vec<f64>| fr.column(th, c, r0, out);
    let run_starts = |range: std::ops::Range<usize>| -> Vec<(f64, usize, Vec<f64>)> {
        range
            .into_par_iter()
            .map(|s| {
                let mut rng = ChaCha8Rng::seed_from_u64(spec.seed.wrapping_add(s as u64));
                let mut th = random_start(co, ymin, ymax, data.len(), &mut rng);
                let cost = lm_with_columns(&mut th, spec.epochs, 1e-5, &residuals, &column);
                (cost, s, th)
            })
            .collect()
    };
    let is_valid = |e: &(f64, usize, Vec<f64>)| e.0.is_finite() && co.params(&e.2[..nm]).check().is_ok();
    // The first starts decide whether the rest are worth their time: when none of them
    // trains to a valid cascade the fit stops there (seconds, not minutes) and says why.
    let mut ends = staged_starts(spec.starts, run_starts, is_valid);
    let tried = ends.len();
    ends.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    if !ends.first().is_some_and(|e| e.0.is_finite()) {
        return Err(invalid(
            "model.starts",
            spec.starts,
            format!(
                "starts of which at least one simulates the records (the first {tried} failed: every \
                 simulation left the solver's step budget, the data do not behave like a chain of \
                 tanks); try `rhonn fit` without --model (it selects a structure)"
            ),
        ));
    }
    // The best start whose parameters are a valid cascade: a start can drive a rate or a
    // bound to zero (its logarithm to minus infinity) when the data do not need it.
    let valid = ends
        .iter()
        .find(|e| is_valid(e))
        .map(|e| (co.params(&e.2[..nm]), e.0));
    let Some((p, cost)) = valid else {
        let why = co
            .params(&ends[0].2[..nm])
            .check()
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        return Err(invalid(
            "model (kind = \"cascade\")",
            if tried < spec.starts {
                format!(
                    "the first {tried} of {} starts, none valid (the rest not tried)",
                    spec.starts
                )
            } else {
                format!("{} starts, none valid", spec.starts)
            },
            format!(
                "a structure the data fit: every start's training left an invalid cascade (the best: {why}), \
                 which happens when the data do not behave like a chain of tanks; try `rhonn fit` without \
                 --model (it selects a structure) or more neurons or starts"
            ),
        ));
    };
    m.weights = vec![p.stored()];
    Ok(cost)
}

/// `kind = "cascade"`.
pub(crate) struct Cascade;

impl super::kinds::Fit for Cascade {
    fn fit(&self, spec: &ModelSpec, records: &[Record], m: &mut Model) -> Result<()> {
        fit(spec, records, m).map(|_| ())
    }

    fn parameters(&self, spec: &ModelSpec, ni: usize, _no: usize) -> usize {
        n_params(spec.neurons, ni)
    }

    /// Every one of its seeded starts trained on the free-run error.
    fn work(&self, spec: &ModelSpec, n: f64, p: f64, _no: f64) -> f64 {
        n * p * p * spec.epochs.max(1) as f64 * spec.starts.max(1) as f64
    }
}

#[path = "cascade_free_runs.rs"]
mod free_runs;
pub(crate) use free_runs::FreeRuns;

#[cfg(test)]
#[path = "cascade_tests.rs"]
mod tests;
