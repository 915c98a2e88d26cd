//! Identification from measured data: discrete-time models of lagged outputs and inputs
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
mod lm;
mod predict;
mod probes;
pub mod pump_grey;
pub mod select;
mod select_candidates;
mod select_cascade;
mod select_ensemble;
mod select_mean;
pub mod select_rule;
mod term_selection;
mod train;
mod wiener_hammerstein;
use checks::ensure_finite_model;
pub use checks::{
    data_warnings, decorrelation_lag, ensure_finite_errors, ensure_finite_figures, free_run_at_bound,
    signal_warnings, DataWarning,
};
pub use estimate::fit;
pub(crate) use estimate::lagged_terms;
pub use fitted::{
    fit_ensemble, fit_own_structures, fit_with_baseline, parse_spec_file, FittedModel, OutputModel,
};
use lm::lm;
pub(crate) use predict::check_window;
pub use predict::{predict, predict_with, samples_needed, PredictSummary, Prediction};
pub use train::{
    best_arx, fit_records, train, train_beside, train_selected, BaselineSummary, FitRun, FitStructure,
    FitSummary, MemberSummary, OutputStructureSummary, RecordFigures, TrainingFigures,
};

use crate::data::Record;
use crate::error::{invalid, Result};
use crate::metrics;
use crate::net::Terms;
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

/// Model family.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Kind {
    /// Linear ARX.
    Arx,
    /// Discrete-time RHONN with lagged measurements.
    #[default]
    Rhonn,
    /// Continuous-time RHONN with hidden states in a chain of limited integrators,
    /// trained on the free-run error (see the `cascade` module).
    Cascade,
    /// The pump's own equations with unknown parameters and a state estimator (see the
    /// `pump_grey` module).
    Pump,
    /// A linear filter, a static polynomial and a linear filter, from the best linear
    /// approximation (see the `wiener_hammerstein` module).
    WienerHammerstein,
}

impl Kind {
    /// The kind with its article, for messages: "an ARX", "a RHONN", "a cascade", "the
    /// pump's grey-box".
    pub fn with_article(self) -> &'static str {
        match self {
            Kind::Arx => "an ARX",
            Kind::Rhonn => "a RHONN",
            Kind::Cascade => "a cascade",
            Kind::Pump => "the pump's grey-box",
            Kind::WienerHammerstein => "a Wiener-Hammerstein",
        }
    }
}

/// The implementation of `kind` (see the `kinds` module): the registry of model kinds,
/// one line per kind.
pub(crate) fn model_kind(kind: Kind) -> &'static dyn kinds::ModelKind {
    match kind {
        Kind::Arx | Kind::Rhonn => &lagged::Lagged,
        Kind::Cascade => &cascade::Cascade,
        Kind::Pump => &pump_grey::PumpGrey,
        Kind::WienerHammerstein => &wiener_hammerstein::WienerHammerstein,
    }
}

/// Training law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Estimator {
    /// Ridge least squares over all data.
    #[default]
    BatchLs,
    /// Recursive least squares over epochs.
    Rls,
    /// Normalised gradient over epochs.
    Gradient,
    /// Parallel (free-run) training: start from batch least squares, then minimise the
    /// free-run simulation error over every record by Levenberg-Marquardt (at most
    /// `epochs` iterations).
    SimulationError,
    /// As `simulation-error`, on the error `horizon` steps ahead instead of the free run.
    MultiStep,
}

impl Estimator {
    /// Its name in a spec file (`batch-ls`, ...), as errors quote it.
    pub fn name(&self) -> &'static str {
        match self {
            Estimator::BatchLs => "batch-ls",
            Estimator::Rls => "rls",
            Estimator::Gradient => "gradient",
            Estimator::SimulationError => "simulation-error",
            Estimator::MultiStep => "multi-step",
        }
    }
}

/// What the high-order terms of a lagged `rhonn` model take of each lagged output.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Activation {
    /// Its tanh, the thesis's sigmoid (default): bounded terms.
    #[default]
    Tanh,
    /// The normalised output itself: the terms are monomials of the lagged outputs and
    /// inputs, a polynomial NARX, which extrapolates a polynomial law (a cubic spring)
    /// beyond the training range where a sigmoid saturates.
    Identity,
}

impl Activation {
    pub(crate) fn is_tanh(&self) -> bool {
        *self == Activation::Tanh
    }
}

/// How `max_terms` chooses the high-order terms a lagged `rhonn` model keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum TermSelection {
    /// The largest weights of a fit with every term (default).
    #[default]
    Weight,
    /// Orthogonal forward regression by error reduction ratio (FROLS): with the linear
    /// regressors and the bias in, the term that explains the most of what is left of
    /// the outputs, then the next, `max_terms` times.
    ErrorReduction,
}

impl TermSelection {
    pub(crate) fn is_weight(&self) -> bool {
        *self == TermSelection::Weight
    }
}

/// A model structure as `--model SPEC.toml` writes it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ModelSpec {
    /// `rhonn` (default) or `arx`.
    pub kind: Kind,
    /// Output lags 1..=na (default 2).
    pub na: usize,
    /// Number of input lags (default 2).
    pub nb: usize,
    /// Input delay in samples (default 1).
    pub nk: usize,
    /// Degree of the high-order terms (rhonn; default 2).
    pub degree: usize,
    /// Most distinct factors per term (rhonn; default 2).
    pub max_factors: usize,
    /// What the high-order terms take of each lagged output (rhonn): `tanh` (default) or
    /// `identity` (a polynomial NARX).
    #[serde(skip_serializing_if = "Activation::is_tanh")]
    pub activation: Activation,
    /// Training law.
    pub law: Estimator,
    /// Ridge weight of batch least squares, relative to the mean diagonal (default 1e-6).
    pub ridge: f64,
    /// Epochs (rls, gradient; default 20).
    pub epochs: usize,
    /// Gain of the gradient law (default 0.5).
    pub gain: f64,
    /// Free runs keep each output within its training range widened by this fraction
    /// on both sides (default 0.5), so that a model cannot run away to infinity.
    pub output_margin: f64,
    /// Prediction horizon of the `multi-step` law, in samples (default 10).
    pub horizon: usize,
    /// Time constants \[s\] of first-order filters each input also passes through (the
    /// filtered-regressor idea of the thesis applied to inputs: a filtered current
    /// stands for a lagged state that is not measured, such as the pump stroke).
    /// Default none.
    pub input_filters_s: Vec<f64>,
    /// First output lag (default 1). A model with `output_lag_start = K` and input lags
    /// covering the horizon is a direct K-step-ahead predictor: `--steps-ahead K` then
    /// uses only measured outputs, with no recursion on its own predictions.
    pub output_lag_start: usize,
    /// Keep at most this many high-order terms: train with all, keep those with the
    /// largest weights, train again (default: keep all).
    pub max_terms: Option<usize>,
    /// How `max_terms` chooses the terms: `weight` (default) or `error-reduction`.
    #[serde(skip_serializing_if = "TermSelection::is_weight")]
    pub term_selection: TermSelection,
    /// The high-order terms take only the first this-many lags of each output and of
    /// each input (and every filtered input): a long linear history (the memory of an
    /// unmeasured state, such as the pump's stroke in the current's past) with a small
    /// nonlinear part (default: every lag).
    pub nonlinear_lags: Option<usize>,
    /// Neurons of a `cascade` model, the last one measured (default 2).
    pub neurons: usize,
    /// Learn each `cascade` neuron's activation exponent (default true; else 1/2).
    pub free_exponents: bool,
    /// Seeded random starts of a `cascade` model's training (default 16).
    pub starts: usize,
    /// Measured samples a `cascade` model settles its hidden states on before a
    /// prediction (default 5).
    pub settle: usize,
    /// Seed of a `cascade` model's random starts (default 1).
    pub seed: u64,
    /// The `[pump]` table of a `pump` model.
    #[serde(skip_serializing_if = "pump_grey::PumpGreySpec::is_default")]
    pub pump: pump_grey::PumpGreySpec,
}

impl Default for ModelSpec {
    fn default() -> Self {
        ModelSpec {
            kind: Kind::Rhonn,
            na: 2,
            nb: 2,
            nk: 1,
            degree: 2,
            max_factors: 2,
            activation: Activation::Tanh,
            law: Estimator::BatchLs,
            ridge: 1e-6,
            epochs: 20,
            gain: 0.5,
            output_margin: 0.5,
            horizon: 10,
            input_filters_s: vec![],
            output_lag_start: 1,
            max_terms: None,
            term_selection: TermSelection::Weight,
            nonlinear_lags: None,
            neurons: 2,
            free_exponents: true,
            starts: 16,
            settle: 5,
            seed: 1,
            pump: Default::default(),
        }
    }
}

/// A trained model (`model.json`): everything needed to run it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Model {
    /// The structure it was trained with.
    pub spec: ModelSpec,
    /// Input column names.
    pub inputs: Vec<String>,
    /// Output column names.
    pub outputs: Vec<String>,
    /// Sampling interval \[s\].
    pub sample_time_s: f64,
    /// (mean, std) of each input.
    pub input_norm: Vec<(f64, f64)>,
    /// (mean, std) of each output.
    pub output_norm: Vec<(f64, f64)>,
    /// (min, max) of each output in the training data.
    pub output_range: Vec<(f64, f64)>,
    /// High-order terms (rhonn), `[y index, exponent]` factors.
    pub terms: Vec<Vec<[usize; 2]>>,
    /// One weight vector per output.
    pub weights: Vec<Vec<f64>>,
}

/// `v` held within `(lo, hi)`; unlike `f64::clamp`, never a panic (a NaN bound, or
/// bounds in the wrong order from data whose statistics overflowed): NaN then propagates
/// to the figures' finiteness checks, which name the data.
fn hold(v: f64, (lo, hi): (f64, f64)) -> f64 {
    v.max(lo).min(hi)
}

/// Figures of one output.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OutputFigures {
    /// Output name.
    pub output: String,
    /// RMS of y - yhat.
    pub rms_error: f64,
    /// 100 (1 - |y - yhat| / |y - mean y|); undefined (left out of JSON) for a constant y.
    #[serde(skip_serializing_if = "crate::metrics::undefined")]
    pub fit_percent: f64,
    /// RMS error / range of y; undefined (left out of JSON) for a constant y.
    #[serde(skip_serializing_if = "crate::metrics::undefined")]
    pub nrmse: f64,
    /// Samples compared.
    pub samples: usize,
}

/// `model.NAME` = `v` within `[lo, hi]`, or the error that names it.
pub(crate) fn int_in(name: &str, v: usize, lo: usize, hi: usize) -> Result<()> {
    if (lo..=hi).contains(&v) {
        Ok(())
    } else {
        Err(invalid(
            format!("model.{name}"),
            v,
            format!("an integer in [{lo}, {hi}]"),
        ))
    }
}

impl ModelSpec {
    /// Validate.
    pub fn check(&self) -> Result<()> {
        int_in("na", self.na, 1, 50)?;
        int_in("nb", self.nb, 0, 50)?;
        int_in("nk", self.nk, 0, 50)?;
        int_in("epochs", self.epochs, 1, 100_000)?;
        int_in("horizon", self.horizon, 1, 10_000)?;
        int_in("output_lag_start", self.output_lag_start, 1, 1000)?;
        if let Some(m) = self.max_terms {
            int_in("max_terms", m, 1, crate::net::MAX_TERMS)?;
        }
        if self.term_selection == TermSelection::ErrorReduction && self.max_terms.is_none() {
            return Err(invalid(
                "model.term_selection",
                "\"error-reduction\"",
                "with `max_terms = N` (it chooses which N high-order terms of a `rhonn` model to keep)",
            ));
        }
        if let Some(m) = self.nonlinear_lags {
            int_in("nonlinear_lags", m, 1, 50)?;
        }
        model_kind(self.kind).check_spec(self)?;
        if !(self.ridge.is_finite() && self.ridge >= 0.0) {
            return Err(invalid("model.ridge", self.ridge, "a number >= 0"));
        }
        if !(self.gain.is_finite() && self.gain > 0.0 && self.gain < 2.0) {
            return Err(invalid("model.gain", self.gain, "a number in (0, 2)"));
        }
        if !(self.output_margin.is_finite() && self.output_margin >= 0.0) {
            return Err(invalid(
                "model.output_margin",
                self.output_margin,
                "a number >= 0",
            ));
        }
        if self.input_filters_s.len() > 16 {
            return Err(invalid(
                "model.input_filters_s",
                self.input_filters_s.len(),
                "at most 16 filters",
            ));
        }
        for (q, tau) in self.input_filters_s.iter().enumerate() {
            if !(tau.is_finite() && *tau > 0.0) {
                return Err(invalid(
                    format!("model.input_filters_s[{q}]"),
                    tau,
                    "a time constant > 0 s",
                ));
            }
        }
        Ok(())
    }

    /// Largest lag: samples needed before the first prediction.
    pub fn max_lag(&self) -> usize {
        model_kind(self.kind).max_lag(self)
    }

    /// The lags in words, e.g. `na 4 nb 4 nk 1`.
    pub fn lags_name(&self) -> String {
        format!("na {} nb {} nk {}", self.na, self.nb, self.nk)
    }
}

/// The most lagged regressors (output lags, input lags and filtered inputs) a lagged
/// model may have: the RHONN's regressor vector lives on the stack.
pub const MAX_REGRESSORS: usize = 128;

/// A lagged model's regressor count against [`MAX_REGRESSORS`], for a spec trained here or
/// read from a hand-edited `model.json`.
pub(crate) fn check_regressor_count(spec: &ModelSpec, ni: usize, no: usize) -> Result<()> {
    let nphi = n_phi(spec, ni, no);
    if matches!(spec.kind, Kind::Arx | Kind::Rhonn) && nphi > MAX_REGRESSORS {
        return Err(invalid(
            "model.na",
            spec.na,
            format!(
                "at most {MAX_REGRESSORS} lagged regressors in all (na * outputs + (nb + filters) * \
                 inputs; here {} * {no} + ({} + {}) * {ni} = {nphi}): lower na or nb",
                spec.na,
                spec.nb,
                spec.input_filters_s.len()
            ),
        ));
    }
    Ok(())
}

/// The regressors the high-order terms are made of (indices into phi): the first
/// `nonlinear_lags` lags of each output and input, and every filtered input.
fn nonlinear_regressors(spec: &ModelSpec, ni: usize, no: usize) -> Vec<usize> {
    let nl = spec.nonlinear_lags.unwrap_or(usize::MAX);
    let mut sub = Vec::new();
    for j in 0..no {
        sub.extend((0..spec.na.min(nl)).map(|i| j * spec.na + i));
    }
    for q in 0..ni {
        sub.extend((0..spec.nb.min(nl)).map(|i| no * spec.na + q * spec.nb + i));
    }
    sub.extend(no * spec.na + ni * spec.nb..n_phi(spec, ni, no));
    sub
}

/// Number of regressors for `ni` inputs and `no` outputs (without terms and bias).
fn n_phi(spec: &ModelSpec, ni: usize, no: usize) -> usize {
    no * spec.na + ni * spec.nb + ni * spec.input_filters_s.len()
}

impl Model {
    fn ni(&self) -> usize {
        self.inputs.len()
    }
    fn no(&self) -> usize {
        self.outputs.len()
    }

    /// The features at sample k, given normalised output history `yn(j, k - i)` and
    /// inputs; written into `feat` (length [`Model::n_features`]).
    pub(crate) fn features(
        &self,
        yhist: &dyn Fn(usize, usize) -> f64,
        un: &[Vec<f64>],
        k: usize,
        terms: &Terms,
        feat: &mut [f64],
    ) {
        let s = &self.spec;
        let mut c = 0;
        for j in 0..self.no() {
            for i in s.output_lag_start..s.output_lag_start + s.na {
                feat[c] = yhist(j, k - i);
                c += 1;
            }
        }
        for u in un.iter().take(self.ni()) {
            for i in 0..s.nb {
                feat[c] = u[k - s.nk - i];
                c += 1;
            }
        }
        // Filtered inputs (appended to `un` by `normalise`), at lag nk.
        for u in un.iter().skip(self.ni()) {
            feat[c] = u[k - s.nk];
            c += 1;
        }
        let nphi = c;
        if s.kind == Kind::Rhonn {
            // y = [tanh of the output lags (or the lags themselves), input lags]
            let ny = nphi;
            let mut y = [0.0; MAX_REGRESSORS];
            let n_out_lags = self.no() * s.na;
            let squash = s.activation == Activation::Tanh;
            for q in 0..ny {
                y[q] = if q < n_out_lags && squash {
                    feat[q].tanh()
                } else {
                    feat[q]
                };
            }
            let l = terms.len();
            terms.eval(&y[..ny], &mut feat[nphi..nphi + l]);
            c += l;
        }
        feat[c] = 1.0;
    }

    /// Normalisation and output ranges as a file may hold them: one per input and output,
    /// means and ranges finite and of magnitude at most 1e150, standard deviations in
    /// [1e-150, 1e150], each range low <= high. Errors name the field and its index.
    fn check_scaling(&self) -> Result<()> {
        const BIG: f64 = 1e150;
        type Pairs<'a> = &'a [(f64, f64)];
        let lists: [(&str, Pairs, usize); 3] = [
            ("model.input_norm", &self.input_norm, self.ni()),
            ("model.output_norm", &self.output_norm, self.no()),
            ("model.output_range", &self.output_range, self.no()),
        ];
        for (name, v, n) in lists {
            if v.len() != n {
                return Err(invalid(
                    name,
                    format!("{} entries", v.len()),
                    format!("{n}, one per column"),
                ));
            }
            for (k, &(a, b)) in v.iter().enumerate() {
                let ok = if name.ends_with("range") {
                    a.is_finite() && b.is_finite() && a <= b && a.abs() <= BIG && b.abs() <= BIG
                } else {
                    a.is_finite() && a.abs() <= BIG && b.is_finite() && (1.0 / BIG..=BIG).contains(&b)
                };
                if !ok {
                    let allowed = if name.ends_with("range") {
                        "[low, high], finite, low <= high, of magnitude at most 1e150"
                    } else {
                        "[mean, standard deviation]: a finite mean of magnitude at most 1e150, a deviation in [1e-150, 1e150]"
                    };
                    return Err(invalid(format!("{name}[{k}]"), format!("[{a}, {b}]"), allowed));
                }
            }
        }
        Ok(())
    }

    /// Check a model read from a file: names, normalisation, terms and weight lengths.
    pub fn validate(&self) -> Result<()> {
        self.spec.check()?;
        if self.outputs.is_empty() {
            return Err(invalid("model.outputs", "[]", "at least one output"));
        }
        self.check_scaling()?;
        if !(self.sample_time_s.is_finite() && self.sample_time_s > 0.0) {
            return Err(invalid(
                "model.sample_time_s",
                self.sample_time_s,
                "a finite number > 0",
            ));
        }
        model_kind(self.spec.kind).validate(self)
    }

    /// Number of features (regressors, terms, bias).
    pub fn n_features(&self) -> usize {
        model_kind(self.spec.kind).n_params(self)
    }

    pub(crate) fn terms(&self) -> Terms {
        if self.terms.is_empty() {
            Terms::empty()
        } else {
            Terms::from_lists(&self.terms, n_phi(&self.spec, self.ni(), self.no()), "terms")
                .expect("a trained model's terms are valid")
        }
    }

    /// Normalised inputs (then each input through each first-order filter of
    /// `input_filters_s`, started at its first value) and normalised outputs.
    fn normalise(&self, r: &Record) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        let mut un: Vec<Vec<f64>> = r
            .inputs
            .iter()
            .zip(&self.input_norm)
            .map(|(c, (m, s))| c.iter().map(|v| (v - m) / s).collect())
            .collect();
        for j in 0..self.ni() {
            for &tau in &self.spec.input_filters_s {
                let a = (-self.sample_time_s / tau).exp();
                let mut z = un[j][0];
                let f: Vec<f64> = un[j]
                    .iter()
                    .map(|&v| {
                        z = a * z + (1.0 - a) * v;
                        z
                    })
                    .collect();
                un.push(f);
            }
        }
        let yn = r
            .outputs
            .iter()
            .zip(&self.output_norm)
            .map(|(c, (m, s))| c.iter().map(|v| (v - m) / s).collect())
            .collect();
        (un, yn)
    }

    /// Predict every output of `r`: free run (`steps_ahead = None`: the model sees the
    /// inputs and the first `max_lag` measured outputs only) or `K` steps ahead (from
    /// the measurements up to k and the inputs, predict k + K). Returns the predictions
    /// (the first samples, which the model cannot predict, hold the measurements) and
    /// the index of the first genuine prediction.
    ///
    /// A `cascade` model settles its hidden states on the measured samples before each
    /// prediction's start (see [`cascade`]); its simulation reports a solver failure
    /// with the time and the levels.
    pub fn predict(&self, r: &Record, steps_ahead: Option<usize>) -> Result<(Vec<Vec<f64>>, usize)> {
        model_kind(self.spec.kind).predict(self, r, steps_ahead)
    }

    /// Figures per output of predictions against the record, from `first` on.
    pub fn figures(&self, r: &Record, pred: &[Vec<f64>], first: usize) -> Vec<OutputFigures> {
        self.outputs
            .iter()
            .enumerate()
            .map(|(j, name)| {
                let y = &r.outputs[j][first..];
                let yh = &pred[j][first..];
                OutputFigures {
                    output: name.clone(),
                    rms_error: metrics::rms_error(y, yh),
                    fit_percent: metrics::fit_percent(y, yh),
                    nrmse: metrics::nrmse(y, yh),
                    samples: y.len(),
                }
            })
            .collect()
    }
}

#[cfg(test)]
#[path = "tests.rs"]
mod tests;
