//! The selection's work budget: what bounds `rhonn fit`'s selection, computed from the
//! data before it starts, so that the chosen structure depends only on the data, the
//! options and the seed (never on the machine's speed, its load or its threads).
//!
//! Each candidate's work is estimated from its structure and the data's size in units
//! of about one multiply-add: a least-squares fit accumulates the normal equations
//! (samples x features^2); a fit on the free-run error takes, per iteration, one free run
//! per weight for its Jacobian by differences (samples x outputs^2 x features^2: what it
//! took until its Jacobian came from the free run's sensitivities, 3.6 to 8 times faster on
//! the lagged RHONNs; the estimate is kept, so the budget runs the same candidates); a
//! Wiener-Hammerstein fit the same over its few parameters; a cascade its 16 starts. A
//! candidate whose estimated work on the folds exceeds the budget is skipped, said, and
//! listed in `summary.json`; ARX structures always run. One unit is about 6 ns on one
//! core of this project's 2-core test machine (the lagged RHONN of na = nb = 8 trained on
//! its free run: 1.31e10 units on Bouc-Wen's folds in 42 s on 2 cores), so the default
//! budget of 1.5e10 units is under a minute on 2 cores for the largest candidate. It was
//! set to keep what the wall-clock budget ran on an idle machine: that candidate on
//! Bouc-Wen (1.31e10, chosen there), not on Silverbox (2.08e10) or Wiener-Hammerstein
//! (3.2e10), where a faster candidate is chosen.

use super::ModelSpec;

/// The default budget per candidate, in work units (about 6 ns each on one core).
pub const DEFAULT_BUDGET: f64 = 1.5e10;

/// The parameters of `spec` for `ni` inputs and `no` outputs, as its kind counts them
/// (`kinds::Fit::parameters`: a lagged model's features per output, a Wiener-Hammerstein's
/// filters and polynomial, a cascade's neurons, a state-space model's matrices).
pub fn parameters(spec: &ModelSpec, ni: usize, no: usize) -> usize {
    super::fitter(spec.kind).parameters(spec, ni, no)
}

/// The estimated work of training `spec` once on `samples` samples (see the module's
/// docs and each kind's `kinds::Fit::work`).
pub fn work(spec: &ModelSpec, samples: usize, ni: usize, no: usize) -> f64 {
    let p = parameters(spec, ni, no) as f64;
    super::fitter(spec.kind).work(spec, samples as f64, p, no as f64)
}

/// The estimated work of judging `spec` on `folds` folds of `samples` samples in all
/// (each fold trains on the others' share).
pub fn fold_work(spec: &ModelSpec, samples: usize, folds: usize, ni: usize, no: usize) -> f64 {
    let train = samples * folds.saturating_sub(1) / folds.max(1);
    folds as f64 * work(spec, train, ni, no)
}

/// [`fold_work`] of each candidate of `list` (names and structures).
pub fn works(
    list: &[(String, ModelSpec)],
    samples: usize,
    folds: usize,
    (ni, no): (usize, usize),
) -> Vec<f64> {
    list.iter()
        .map(|(_, s)| fold_work(s, samples, folds, ni, no))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Estimator;

    #[test]
    fn work_grows_with_samples_outputs_and_free_run_training() {
        let ls = ModelSpec::default();
        let se = ModelSpec {
            law: Estimator::SimulationError,
            epochs: 15,
            ..ModelSpec::default()
        };
        assert_eq!(work(&ls, 2000, 1, 1), 2.0 * work(&ls, 1000, 1, 1));
        assert!(work(&se, 1000, 1, 1) > 10.0 * work(&ls, 1000, 1, 1));
        assert!(work(&se, 1000, 6, 6) > 100.0 * work(&se, 1000, 1, 1));
        assert_eq!(fold_work(&ls, 3000, 3, 1, 1), 3.0 * work(&ls, 2000, 1, 1));
    }
}
