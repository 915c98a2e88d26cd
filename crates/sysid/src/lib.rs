//! rhonn's offline identification (`rhonn::sysid`). Identification from measured data: discrete-time models of lagged outputs and inputs
//! (a time-delay embedding), trained on records and run free or K steps ahead; and
//! continuous-time RHONNs with hidden states (`cascade`, see [`cascade`]'s docs), which
//! settle their hidden states on measured samples, then run free or K steps ahead.
//!
//! Two kinds share one regressor:
//! - `arx`: `y(k) = theta^T [phi(k), 1]` — the linear baseline (least squares);
//! - `rhonn`: `y(k) = theta^T [phi(k), z(s(phi_y(k)), phi_u(k)), 1]` — the discrete-time
//!   RHONN neuron with lagged measurements: the linear state terms of `dx = -a x + w^T z`,
//!   plus high-order terms of the sigmoids of the normalised lagged outputs and of the
//!   normalised lagged inputs (all monomials up to `degree` with at most `max_factors`
//!   factors).
//!
//! `phi(k)` holds, normalised by the training data's mean and standard deviation, every
//! output at lags 1..=na and every input at lags nk..nk+nb-1. Only the outputs need to
//! be measured: the model's states are its lagged outputs, so a neuron per output and
//! the filtered-error / least-squares laws apply to each output's row of weights.
//!
//! Training laws (`law`): `batch-ls` (default: ridge least squares over all records, the
//! limit of the least-squares law run to convergence), `rls` (the recursive least
//! squares law over `epochs`, the weights of one epoch starting the next), `gradient`
//! (the normalised gradient law over `epochs`), `simulation-error` (parallel training:
//! from the least-squares weights, Levenberg-Marquardt on the free-run error — a model
//! judged by free runs is trained on free runs).

#![deny(missing_docs)]
// `!(a < b)` is deliberate throughout: it is also true when either side is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Numerical kernels index several slices in lockstep; index loops read best there.
#![allow(clippy::needless_range_loop)]

// The foundations, under the names this crate's modules use (`crate::data`, ...).
pub(crate) use rhonn_base::{cancel, data, error, law, metrics, models, net, Error};

pub mod benchmarks;
pub mod budget;
pub mod cascade;
mod checks;
mod estimate;
mod fitted;
mod fold_queue;
mod folds;
mod kinds;
mod lagged;
mod lagged_normal;
mod lm;
mod mean;
mod poles;
mod predict;
mod probes;
pub mod pump_grey;
pub mod select;
mod select_candidates;
mod select_cascade;
mod select_ensemble;
mod select_mean;
pub mod select_rule;
mod state_space;
mod term_selection;
mod train;
mod wiener_hammerstein;
use checks::ensure_finite_model;
pub use checks::{
    data_warnings, decorrelation_lag, ensure_finite_errors, ensure_finite_figures, free_run_at_bound,
    milliseconds_hint, outputs_at_bound, signal_warnings, DataWarning, OutputAtBound,
};
pub use estimate::fit;
pub use fitted::{
    fit_ensemble, fit_own_structures, fit_with_baseline, parse_spec_file, FittedModel, OutputModel,
};
use lm::{lm, lm_normal};
pub use predict::{check_prediction_options, check_window, prediction_options};
pub use predict::{
    inputs_beyond_training, outputs_beyond_training, predict, predict_with, samples_needed, InputBeyond,
    OutputBeyond, PredictSummary, Prediction, BEYOND_SPAN,
};
pub use train::{
    best_arx, fit_records, train, train_beside, train_selected, BaselineSummary, FitRun, FitStructure,
    FitSummary, MemberSummary, OutputStructureSummary, RecordFigures, TrainingFigures,
};

use crate::data::Record;
use crate::error::{invalid, Result};
pub(crate) use crate::models::{check_regressor_count, lagged_terms, model_kind, n_phi};
pub use crate::models::{
    Activation, Estimator, Kind, Model, ModelSpec, NonlinearIn, OutputFigures, TermSelection, MAX_REGRESSORS,
};
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

/// The training of `kind` (see the `kinds` module): the registry of the kinds' training,
/// one line per kind (their structures: [`crate::models::model_kind`]).
pub(crate) fn fitter(kind: Kind) -> &'static dyn kinds::Fit {
    match kind {
        Kind::Arx | Kind::Rhonn => &lagged::Lagged,
        Kind::Cascade => &cascade::Cascade,
        Kind::Pump => &pump_grey::PumpGrey,
        Kind::WienerHammerstein => &wiener_hammerstein::WienerHammerstein,
        Kind::StateSpace => &state_space::StateSpace,
        Kind::Mean => &mean::Mean,
    }
}

/// Least squares (the block structures' and the state-space models' linear starts) with a ridge of 1e-9 of the mean diagonal (normal equations, Cholesky);
/// None when the columns are collinear even so.
pub(crate) fn least_squares(a: &DMatrix<f64>, t: &DVector<f64>) -> Option<DVector<f64>> {
    let n = a.ncols();
    // One transpose for both products (the same products, so the same bits).
    let at = a.transpose();
    let mut ata = &at * a;
    let mean_diag = (0..n).map(|i| ata[(i, i)]).sum::<f64>() / n as f64;
    for i in 0..n {
        ata[(i, i)] += 1e-9 * mean_diag;
    }
    Some(ata.cholesky()?.solve(&(&at * t)))
}

#[cfg(test)]
#[path = "tests.rs"]
mod tests;
