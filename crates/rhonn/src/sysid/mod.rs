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

pub mod cascade;
mod checks;
mod predict;
mod train;
pub use checks::{data_warnings, decorrelation_lag};
pub use predict::{predict, samples_needed, PredictSummary, Prediction};
pub use train::{train, BaselineSummary, FitSummary, MemberSummary, RecordFigures, TrainingFigures};

use crate::data::Record;
use crate::error::{invalid, Error, Result};
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
}

/// Training law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Law {
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
    /// Training law.
    pub law: Law,
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
            law: Law::BatchLs,
            ridge: 1e-6,
            epochs: 20,
            gain: 0.5,
            output_margin: 0.5,
            horizon: 10,
            input_filters_s: vec![],
            output_lag_start: 1,
            max_terms: None,
            nonlinear_lags: None,
            neurons: 2,
            free_exponents: true,
            starts: 16,
            settle: 5,
            seed: 1,
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

/// Figures of one output.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OutputFigures {
    /// Output name.
    pub output: String,
    /// RMS of y - yhat.
    pub rms_error: f64,
    /// 100 (1 - |y - yhat| / |y - mean y|).
    pub fit_percent: f64,
    /// RMS error / range of y.
    pub nrmse: f64,
    /// Samples compared.
    pub samples: usize,
}

impl ModelSpec {
    /// Validate.
    pub fn check(&self) -> Result<()> {
        let int_in = |name: &str, v: usize, lo: usize, hi: usize| {
            if (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(invalid(
                    format!("model.{name}"),
                    v,
                    format!("an integer in [{lo}, {hi}]"),
                ))
            }
        };
        int_in("na", self.na, 1, 50)?;
        int_in("nb", self.nb, 0, 50)?;
        int_in("nk", self.nk, 0, 50)?;
        if self.kind == Kind::Rhonn {
            int_in("degree", self.degree, 1, 5)?;
            int_in("max_factors", self.max_factors, 1, self.degree)?;
        }
        int_in("epochs", self.epochs, 1, 100_000)?;
        int_in("horizon", self.horizon, 1, 10_000)?;
        int_in("output_lag_start", self.output_lag_start, 1, 1000)?;
        if let Some(m) = self.max_terms {
            int_in("max_terms", m, 1, crate::net::MAX_TERMS)?;
        }
        if let Some(m) = self.nonlinear_lags {
            int_in("nonlinear_lags", m, 1, 50)?;
        }
        if self.kind == Kind::Cascade {
            int_in("neurons", self.neurons, 1, 4)?;
            int_in("starts", self.starts, 1, 10_000)?;
            int_in("settle", self.settle, 2, 1000)?;
            if matches!(self.law, Law::Rls | Law::Gradient | Law::MultiStep) {
                return Err(invalid(
                    "model.law",
                    match self.law {
                        Law::Rls => "rls",
                        Law::Gradient => "gradient",
                        _ => "multi-step",
                    },
                    "simulation-error (a `cascade` model is always trained on its free-run error)",
                ));
            }
            if !self.input_filters_s.is_empty() {
                return Err(invalid(
                    "model.input_filters_s",
                    format!("{:?}", self.input_filters_s),
                    "none for a `cascade` model (its hidden neurons are the filters)",
                ));
            }
        }
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
        if self.kind == Kind::Cascade {
            return self.settle;
        }
        (self.output_lag_start + self.na - 1)
            .max(if self.nb > 0 { self.nk + self.nb - 1 } else { 0 })
            .max(self.nk)
    }
}

/// The most lagged regressors (output lags, input lags and filtered inputs) a lagged
/// model may have: the RHONN's regressor vector lives on the stack.
pub const MAX_REGRESSORS: usize = 128;

/// A lagged model's regressor count against [`MAX_REGRESSORS`], for a spec trained here or
/// read from a hand-edited `model.json`.
fn check_regressor_count(spec: &ModelSpec, ni: usize, no: usize) -> Result<()> {
    let nphi = n_phi(spec, ni, no);
    if spec.kind != Kind::Cascade && nphi > MAX_REGRESSORS {
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
    fn features(
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
            // y = [tanh of the output lags, input lags]
            let ny = nphi;
            let mut y = [0.0; MAX_REGRESSORS];
            let n_out_lags = self.no() * s.na;
            for q in 0..ny {
                y[q] = if q < n_out_lags { feat[q].tanh() } else { feat[q] };
            }
            let l = terms.len();
            terms.eval(&y[..ny], &mut feat[nphi..nphi + l]);
            c += l;
        }
        feat[c] = 1.0;
    }

    /// Check a model read from a file: names, normalisation, terms and weight lengths.
    pub fn validate(&self) -> Result<()> {
        self.spec.check()?;
        if self.outputs.is_empty() {
            return Err(invalid("model.outputs", "[]", "at least one output"));
        }
        if self.input_norm.len() != self.ni()
            || self.output_norm.len() != self.no()
            || self.output_range.len() != self.no()
        {
            return Err(invalid(
                "model normalisation",
                "lengths",
                "one entry per input and per output",
            ));
        }
        for (m, s) in self.input_norm.iter().chain(&self.output_norm) {
            if !(m.is_finite() && s.is_finite() && *s > 0.0) {
                return Err(invalid(
                    "model normalisation",
                    format!("({m}, {s})"),
                    "a finite mean and a standard deviation > 0",
                ));
            }
        }
        if self.spec.kind == Kind::Cascade {
            if self.no() != 1 || self.weights.len() != 1 || self.weights[0].len() != self.n_features() {
                return Err(invalid(
                    "model.weights",
                    format!("{} vectors", self.weights.len()),
                    format!("one output and one vector of {} parameters", self.n_features()),
                ));
            }
            return cascade::Params::from_stored(self.spec.neurons, self.ni(), &self.weights[0]).check();
        }
        check_regressor_count(&self.spec, self.ni(), self.no())?;
        if !self.terms.is_empty() {
            Terms::from_lists(
                &self.terms,
                n_phi(&self.spec, self.ni(), self.no()),
                "model.terms",
            )?;
        }
        let nf = self.n_features();
        if self.weights.len() != self.no()
            || self
                .weights
                .iter()
                .any(|w| w.len() != nf || w.iter().any(|v| !v.is_finite()))
        {
            return Err(invalid(
                "model.weights",
                format!("{} vectors", self.weights.len()),
                format!("one vector of {nf} finite weights per output"),
            ));
        }
        if !(self.sample_time_s.is_finite() && self.sample_time_s > 0.0) {
            return Err(invalid("model.sample_time_s", self.sample_time_s, "a number > 0"));
        }
        Ok(())
    }

    /// Number of features (regressors, terms, bias).
    pub fn n_features(&self) -> usize {
        if self.spec.kind == Kind::Cascade {
            return cascade::n_params(self.spec.neurons, self.ni());
        }
        n_phi(&self.spec, self.ni(), self.no()) + self.terms.len() + 1
    }

    fn terms(&self) -> Terms {
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
        if self.spec.kind == Kind::Cascade {
            return cascade::predict(self, r, steps_ahead);
        }
        let (un, yn) = self.normalise(r);
        let n = r.len();
        let lag = self.spec.max_lag();
        let terms = self.terms();
        let nf = self.n_features();
        let mut feat = vec![0.0; nf];
        let no = self.no();
        let bounds: Vec<(f64, f64)> = self
            .output_range
            .iter()
            .zip(&self.output_norm)
            .map(|((lo, hi), (m, s))| {
                let w = (hi - lo) * self.spec.output_margin;
                ((lo - w - m) / s, (hi + w - m) / s)
            })
            .collect();
        let mut pred = yn.clone();
        let first;
        match steps_ahead {
            None => {
                first = lag;
                for k in lag..n {
                    {
                        let p = &pred;
                        self.features(&|j, i| p[j][i], &un, k, &terms, &mut feat);
                    }
                    for j in 0..no {
                        let v: f64 = self.weights[j].iter().zip(&feat).map(|(w, f)| w * f).sum();
                        pred[j][k] = v.clamp(bounds[j].0, bounds[j].1);
                    }
                }
            }
            Some(kk) => {
                let kk = kk.max(1);
                first = lag + kk - 1;
                // A window of the last lag + K values: measured, then predicted.
                let mut hist = vec![vec![0.0; n]; no];
                for end in first..n {
                    let start = end + 1 - kk;
                    for j in 0..no {
                        hist[j][start - lag..start].copy_from_slice(&yn[j][start - lag..start]);
                    }
                    for k in start..=end {
                        {
                            let h = &hist;
                            self.features(&|j, i| h[j][i], &un, k, &terms, &mut feat);
                        }
                        for j in 0..no {
                            let v: f64 = self.weights[j].iter().zip(&feat).map(|(w, f)| w * f).sum();
                            hist[j][k] = v.clamp(bounds[j].0, bounds[j].1);
                        }
                    }
                    for j in 0..no {
                        pred[j][end] = hist[j][end];
                    }
                }
            }
        }
        let out = pred
            .iter()
            .zip(&self.output_norm)
            .map(|(c, (m, s))| c.iter().map(|v| v * s + m).collect())
            .collect();
        Ok((out, first))
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

fn mean_std(cols: &[&[f64]]) -> (f64, f64) {
    let n: usize = cols.iter().map(|c| c.len()).sum();
    let m = cols.iter().flat_map(|c| c.iter()).sum::<f64>() / n as f64;
    let v = cols
        .iter()
        .flat_map(|c| c.iter())
        .map(|x| (x - m) * (x - m))
        .sum::<f64>()
        / n as f64;
    (m, if v > 0.0 { v.sqrt() } else { 1.0 })
}

/// Train a model of `outputs` from `inputs` on `records` (uniformly sampled at the same
/// interval; see [`Record::uniform`]).
pub fn fit(spec: &ModelSpec, records: &[Record], inputs: &[String], outputs: &[String]) -> Result<Model> {
    let model = fit_pruned(spec, records, inputs, outputs)?;
    ensure_finite_model(&model, records)?;
    Ok(model)
}

/// A fitted model whose scaling or weights are NaN or infinite is an error that names the
/// data's range (the usual cause: values so large that their squares overflow).
fn ensure_finite_model(m: &Model, records: &[Record]) -> Result<()> {
    let finite_pairs = |v: &[(f64, f64)]| v.iter().all(|(a, b)| a.is_finite() && b.is_finite());
    let ok = finite_pairs(&m.input_norm)
        && finite_pairs(&m.output_norm)
        && finite_pairs(&m.output_range)
        && m.weights.iter().flatten().all(|w| w.is_finite());
    if ok {
        return Ok(());
    }
    let mut largest = (0.0_f64, String::new(), String::new());
    for r in records {
        let cols = m
            .inputs
            .iter()
            .zip(&r.inputs)
            .chain(m.outputs.iter().zip(&r.outputs));
        for (name, col) in cols {
            for v in col {
                if v.abs() > largest.0 {
                    largest = (v.abs(), name.clone(), r.source.clone());
                }
            }
        }
    }
    let cause = if largest.0 > 1e150 {
        format!(
            "the data reach |{:e}| (column `{}` of {}); values beyond about 1e150 overflow the \
             scaling's squares: rescale the data (e.g. to other units) so that they stay well below",
            largest.0, largest.1, largest.2
        )
    } else {
        format!(
            "the data's largest value is |{:e}| (column `{}` of {}); the training diverged: \
             try a smaller `degree`, fewer lags, a larger `ridge` or the `batch-ls` law",
            largest.0, largest.1, largest.2
        )
    };
    Err(Error::NotFinite {
        what: "a scale or weight of the fitted model".into(),
        cause,
    })
}

/// An error when any figure (RMS error, fit, NRMSE) of a prediction on `source` is NaN or
/// infinite: a prediction that overflowed must not be written as a result.
pub fn ensure_finite_figures(figures: &[OutputFigures], source: &str) -> Result<()> {
    match figures
        .iter()
        .find(|f| !(f.rms_error.is_finite() && f.fit_percent.is_finite() && f.nrmse.is_finite()))
    {
        None => Ok(()),
        Some(f) => Err(Error::NotFinite {
            what: format!("the prediction of `{}` on {source}", f.output),
            cause: "it overflows on these data (a free run that diverges, or data far outside the \
                    training range); nothing was written"
                .into(),
        }),
    }
}

fn fit_pruned(spec: &ModelSpec, records: &[Record], inputs: &[String], outputs: &[String]) -> Result<Model> {
    let full = fit_terms(spec, records, inputs, outputs, None)?;
    match spec.max_terms {
        Some(keep) if spec.kind == Kind::Rhonn && full.terms.len() > keep => {
            // Prune by weight magnitude: the terms work on normalised signals, so their
            // weights are comparable; keep the `keep` largest (largest over the outputs),
            // in their original order, and train again.
            let nphi = n_phi(spec, inputs.len(), outputs.len());
            let mut rank: Vec<(usize, f64)> = (0..full.terms.len())
                .map(|q| {
                    (
                        q,
                        full.weights.iter().map(|w| w[nphi + q].abs()).fold(0.0, f64::max),
                    )
                })
                .collect();
            rank.sort_by(|a, b| b.1.total_cmp(&a.1));
            let mut kept: Vec<usize> = rank[..keep].iter().map(|r| r.0).collect();
            kept.sort_unstable();
            let terms = kept.iter().map(|&q| full.terms[q].clone()).collect();
            fit_terms(spec, records, inputs, outputs, Some(terms))
        }
        _ => Ok(full),
    }
}

fn fit_terms(
    spec: &ModelSpec,
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
    given_terms: Option<Vec<Vec<[usize; 2]>>>,
) -> Result<Model> {
    let mut model = blank_model(spec, records, inputs, outputs)?;
    if spec.kind == Kind::Cascade {
        cascade::fit(spec, records, &mut model)?;
        return Ok(model);
    }
    let (ni, no) = (inputs.len(), outputs.len());
    check_regressor_count(spec, ni, no)?;
    model.terms = match (spec.kind, given_terms) {
        (Kind::Rhonn, Some(t)) => t,
        (Kind::Rhonn, None) => {
            let sub = nonlinear_regressors(spec, ni, no);
            let t = Terms::monomials(sub.len(), spec.degree, spec.max_factors);
            (0..t.len())
                .map(|k| t.factors(k).into_iter().map(|[i, e]| [sub[i], e]).collect())
                .collect()
        }
        _ => vec![],
    };
    fit_weights(model, records)
}

/// Check the spec and the records and make an untrained model: names, sample time,
/// normalisation and output ranges.
fn blank_model(spec: &ModelSpec, records: &[Record], inputs: &[String], outputs: &[String]) -> Result<Model> {
    spec.check()?;
    if spec.kind == Kind::Cascade && outputs.len() != 1 {
        return Err(invalid(
            "--outputs",
            outputs.join(","),
            "exactly one output for a `cascade` model (its last neuron)",
        ));
    }
    if records.is_empty() {
        return Err(invalid("--data", "no files", "at least one CSV file"));
    }
    let lag = spec.max_lag();
    for r in records {
        r.check(lag + 2)?;
    }
    let dt = records[0].median_interval();
    for r in &records[1..] {
        let d = r.median_interval();
        if (d - dt).abs() > 1e-6 * dt {
            return Err(invalid(
                format!("{}: sampling interval", r.source),
                d,
                format!("the first file's, {dt} s"),
            ));
        }
    }
    let ni = inputs.len();
    let no = outputs.len();
    let input_norm = (0..ni)
        .map(|j| mean_std(&records.iter().map(|r| r.inputs[j].as_slice()).collect::<Vec<_>>()))
        .collect();
    let output_norm: Vec<(f64, f64)> = (0..no)
        .map(|j| {
            mean_std(
                &records
                    .iter()
                    .map(|r| r.outputs[j].as_slice())
                    .collect::<Vec<_>>(),
            )
        })
        .collect();
    let output_range = (0..no)
        .map(|j| {
            records
                .iter()
                .flat_map(|r| r.outputs[j].iter())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                    (l.min(v), h.max(v))
                })
        })
        .collect();
    Ok(Model {
        spec: spec.clone(),
        inputs: inputs.to_vec(),
        outputs: outputs.to_vec(),
        sample_time_s: dt,
        input_norm,
        output_norm,
        output_range,
        terms: vec![],
        weights: vec![],
    })
}

/// Train the weights of a lagged model (`arx` or `rhonn`) whose terms are set.
fn fit_weights(mut model: Model, records: &[Record]) -> Result<Model> {
    let spec = model.spec.clone();
    let spec = &spec;
    let no = model.no();
    let lag = spec.max_lag();
    if model.terms.len() > crate::net::MAX_TERMS {
        return Err(invalid(
            "model.degree",
            spec.degree,
            format!(
                "a structure with at most {} high-order terms (this one gives {}: lower degree, max_factors or the lags)",
                crate::net::MAX_TERMS,
                model.terms.len()
            ),
        ));
    }
    let nf = model.n_features();
    let t = model.terms();
    // The regression rows (series-parallel: lagged measured outputs).
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut targets: Vec<Vec<f64>> = vec![Vec::new(); no];
    for r in records {
        let (un, yn) = model.normalise(r);
        for k in lag..r.len() {
            let mut feat = vec![0.0; nf];
            model.features(&|j, i| yn[j][i], &un, k, &t, &mut feat);
            rows.push(feat);
            for j in 0..no {
                targets[j].push(yn[j][k]);
            }
        }
    }
    let weights = match spec.law {
        Law::BatchLs | Law::SimulationError | Law::MultiStep => batch_ls(&rows, &targets, spec.ridge)?,
        Law::Rls => recursive(&rows, &targets, spec.epochs, None),
        Law::Gradient => recursive(&rows, &targets, spec.epochs, Some(spec.gain)),
    };
    model.weights = weights;
    match spec.law {
        Law::SimulationError => simulation_error(&mut model, records, None),
        Law::MultiStep => simulation_error(&mut model, records, Some(spec.horizon)),
        _ => {}
    }
    Ok(model)
}

/// Free-run residuals (normalised units) of `m` over `records`, appended to `out`.
fn free_run_residuals(m: &Model, records: &[Record], horizon: Option<usize>, out: &mut Vec<f64>) {
    out.clear();
    for r in records {
        let (p, first) = m
            .predict(r, horizon)
            .expect("a lagged model predicts every record");
        for (j, (col, (_, sd))) in r.outputs.iter().zip(&m.output_norm).enumerate() {
            for k in first..r.len() {
                out.push((p[j][k] - col[k]) / sd);
            }
        }
    }
}

/// Levenberg-Marquardt on the free-run error, from the current weights. The Jacobian
/// is taken by forward differences (a few dozen weights and a cheap simulation make
/// that simpler and as fast as differentiating through the clipped recursion).
fn simulation_error(m: &mut Model, records: &[Record], horizon: Option<usize>) {
    let shapes: Vec<usize> = m.weights.iter().map(|w| w.len()).collect();
    let set = |m: &mut Model, th: &[f64]| {
        let mut o = 0;
        for (w, &l) in m.weights.iter_mut().zip(&shapes) {
            w.copy_from_slice(&th[o..o + l]);
            o += l;
        }
    };
    let mut theta: Vec<f64> = m.weights.iter().flatten().copied().collect();
    let iters = m.spec.epochs;
    let cell = std::cell::RefCell::new(m.clone());
    lm(&mut theta, iters, 1e-6, &|th, out| {
        let mut w = cell.borrow_mut();
        set(&mut w, th);
        free_run_residuals(&w, records, horizon, out);
        true
    });
    set(m, &theta);
}

/// Levenberg-Marquardt on the residuals `resid(theta, out)` (false: the model could not
/// be simulated there, a step to avoid), at most `iters` iterations from `theta`, with
/// a forward-difference Jacobian of relative step `fd_rel`. Leaves the best `theta`
/// found and returns its cost (sum of squared residuals; infinity when the start
/// itself fails). Shared by the lagged models' `simulation-error` law and the
/// `cascade` models; nalgebra's Cholesky solves each damped step (no crate of the
/// workspace offers a Levenberg-Marquardt with user-defined failure of a residual).
pub(crate) fn lm(
    theta: &mut Vec<f64>,
    iters: usize,
    fd_rel: f64,
    resid: &dyn Fn(&[f64], &mut Vec<f64>) -> bool,
) -> f64 {
    let np = theta.len();
    let mut r0 = Vec::new();
    if !resid(theta, &mut r0) {
        return f64::INFINITY;
    }
    let cost = |r: &[f64]| r.iter().map(|v| v * v).sum::<f64>();
    let mut c0 = cost(&r0);
    let mut lambda = 1e-2;
    let mut r1 = Vec::new();
    for _ in 0..iters {
        let nr = r0.len();
        let mut jac = DMatrix::<f64>::zeros(nr, np);
        for p in 0..np {
            let h = fd_rel * theta[p].abs().max(1e-3);
            let mut th = theta.clone();
            th[p] += h;
            if resid(&th, &mut r1) && r1.len() == nr {
                for i in 0..nr {
                    jac[(i, p)] = (r1[i] - r0[i]) / h;
                }
            }
        }
        let jtj = jac.transpose() * &jac;
        let g = jac.transpose() * DVector::from_column_slice(&r0);
        let mut improved = false;
        for _ in 0..10 {
            let mut a = jtj.clone();
            for d in 0..np {
                a[(d, d)] += lambda * jtj[(d, d)].max(1e-12);
            }
            let Some(ch) = a.cholesky() else {
                lambda *= 10.0;
                continue;
            };
            let step = ch.solve(&g);
            let th: Vec<f64> = theta.iter().zip(step.iter()).map(|(t, s)| t - s).collect();
            if resid(&th, &mut r1) {
                let c1 = cost(&r1);
                if c1.is_finite() && c1 < c0 {
                    *theta = th;
                    std::mem::swap(&mut r0, &mut r1);
                    let rel = (c0 - c1) / c0;
                    c0 = c1;
                    lambda = (lambda / 3.0).max(1e-9);
                    improved = rel > 1e-6;
                    break;
                }
            }
            lambda *= 4.0;
        }
        if !improved {
            break;
        }
    }
    c0
}

/// Ridge least squares by the normal equations and a Cholesky factorisation.
fn batch_ls(rows: &[Vec<f64>], targets: &[Vec<f64>], ridge: f64) -> Result<Vec<Vec<f64>>> {
    let nf = rows[0].len();
    let x = DMatrix::from_fn(rows.len(), nf, |i, j| rows[i][j]);
    let mut xtx = x.transpose() * &x;
    let mean_diag = (0..nf).map(|i| xtx[(i, i)]).sum::<f64>() / nf as f64;
    for i in 0..nf {
        xtx[(i, i)] += ridge * mean_diag + 1e-12 * mean_diag;
    }
    // Collinear regressors (an input that is constant or equals another, an output lag
    // that repeats an input) leave the Gram matrix singular without a ridge.
    let chol = xtx.cholesky().ok_or_else(|| {
        invalid(
            "model.ridge",
            ridge,
            "a larger ridge (e.g. 1e-6): the regressors are collinear on these data (a constant \
             input, an input equal to another or to an output, or more lags than the data can tell \
             apart), so least squares has no unique solution without one",
        )
    })?;
    Ok(targets
        .iter()
        .map(|y| {
            let rhs = x.transpose() * DVector::from_column_slice(y);
            chol.solve(&rhs).iter().copied().collect()
        })
        .collect())
}

/// The recursive least-squares law (gain None) or the normalised gradient law over
/// epochs, the weights of one epoch starting the next.
fn recursive(rows: &[Vec<f64>], targets: &[Vec<f64>], epochs: usize, gain: Option<f64>) -> Vec<Vec<f64>> {
    let nf = rows[0].len();
    targets
        .iter()
        .map(|y| {
            let mut w = DVector::<f64>::zeros(nf);
            for _ in 0..epochs {
                let mut p = DMatrix::<f64>::identity(nf, nf) * 1e3;
                for (row, &yk) in rows.iter().zip(y) {
                    let phi = DVector::from_column_slice(row);
                    let e = yk - w.dot(&phi);
                    match gain {
                        Some(g) => w += &phi * (g * e / (1.0 + phi.dot(&phi))),
                        None => {
                            let pphi = &p * &phi;
                            let den = 1.0 + phi.dot(&pphi);
                            w += &pphi * (e / den);
                            p -= &pphi * pphi.transpose() / den;
                        }
                    }
                }
            }
            w.iter().copied().collect()
        })
        .collect()
}

/// What `rhonn fit` writes to `model.json`: the model (with an ensemble's further
/// members) and, for a RHONN, the ARX baseline with the same lags, trained on the same
/// data.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FittedModel {
    /// rhonn's version.
    pub rhonn_version: String,
    /// The model (an ensemble's first member).
    pub model: Model,
    /// An ensemble's further members: its prediction is the mean of every member's own
    /// prediction (free run or K steps ahead). Empty for a single model.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub members: Vec<Model>,
    /// The linear baseline with the first member's lags (None when that is itself an
    /// ARX).
    pub baseline: Option<Model>,
    /// The data's units by column (`rhonn fit --units`), for what people read; absent
    /// when none were given.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub units: std::collections::BTreeMap<String, String>,
}

impl FittedModel {
    /// Every member, the first one first.
    pub fn all_members(&self) -> impl Iterator<Item = &Model> {
        std::iter::once(&self.model).chain(&self.members)
    }

    /// Check every member (and that they share inputs, outputs and sample time) and the
    /// baseline.
    pub fn validate(&self) -> Result<()> {
        for (k, m) in self.all_members().enumerate() {
            m.validate()?;
            if m.inputs != self.model.inputs
                || m.outputs != self.model.outputs
                || (m.sample_time_s - self.model.sample_time_s).abs() > 1e-9 * self.model.sample_time_s
            {
                return Err(invalid(
                    format!("members[{k}]"),
                    "other inputs, outputs or sample time",
                    "the first member's",
                ));
            }
        }
        if let Some(b) = &self.baseline {
            b.validate()?;
        }
        Ok(())
    }

    /// Samples needed before the first prediction, over every member.
    pub fn max_lag(&self) -> usize {
        self.all_members().map(|m| m.spec.max_lag()).max().unwrap_or(0)
    }

    /// The prediction of every output (see [`Model::predict`]): a single model's, or the
    /// mean of an ensemble's members' predictions, from the latest member's first
    /// predictable sample on (the measurement repeated before it).
    pub fn predict(&self, r: &Record, steps_ahead: Option<usize>) -> Result<(Vec<Vec<f64>>, usize)> {
        let (mut sum, mut first) = self.model.predict(r, steps_ahead)?;
        for m in &self.members {
            let (p, f) = m.predict(r, steps_ahead)?;
            first = first.max(f);
            for (s, pj) in sum.iter_mut().zip(&p) {
                for (a, b) in s.iter_mut().zip(pj) {
                    *a += b;
                }
            }
        }
        let k = (1 + self.members.len()) as f64;
        for (j, s) in sum.iter_mut().enumerate() {
            for (i, v) in s.iter_mut().enumerate() {
                *v = if i < first { r.outputs[j][i] } else { *v / k };
            }
        }
        Ok((sum, first))
    }
}

/// Read a model spec file: one structure, or an ensemble as `[[members]]` tables (each
/// a structure; its prediction is the mean of the members'). Errors name the key.
pub fn parse_spec_file(text: &str) -> std::result::Result<Vec<ModelSpec>, String> {
    let v: toml::Value = toml::from_str(text).map_err(|e| e.to_string())?;
    match v.get("members") {
        None => Ok(vec![toml::from_str::<ModelSpec>(text).map_err(|e| e.to_string())?]),
        Some(members) => {
            let table = v.as_table().expect("a TOML document is a table");
            if let Some(k) = table.keys().find(|k| *k != "members") {
                return Err(format!(
                    "`{k}` beside `members`: an ensemble file holds only `[[members]]` tables"
                ));
            }
            let list = members
                .as_array()
                .filter(|a| !a.is_empty())
                .ok_or("`members` must be a non-empty list of `[[members]]` tables")?;
            list.iter()
                .enumerate()
                .map(|(i, m)| {
                    m.clone()
                        .try_into::<ModelSpec>()
                        .map_err(|e| format!("members[{i}]: {e}"))
                })
                .collect()
        }
    }
}

/// Train `spec` and, for a RHONN, the ARX baseline with the same lags.
pub fn fit_with_baseline(
    spec: &ModelSpec,
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
) -> Result<FittedModel> {
    fit_ensemble(std::slice::from_ref(spec), records, inputs, outputs)
}

/// Train every structure of an ensemble (one structure: a single model) and, when the
/// first is a RHONN, the ARX baseline with the first one's lags.
pub fn fit_ensemble(
    specs: &[ModelSpec],
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
) -> Result<FittedModel> {
    let spec = specs
        .first()
        .ok_or_else(|| invalid("members", "[]", "at least one model structure"))?;
    let model = fit(spec, records, inputs, outputs)?;
    let members = specs[1..]
        .iter()
        .map(|s| fit(s, records, inputs, outputs))
        .collect::<Result<Vec<_>>>()?;
    let baseline = if spec.kind != Kind::Arx {
        let arx = ModelSpec {
            kind: Kind::Arx,
            law: Law::BatchLs,
            ridge: 1e-9,
            ..spec.clone()
        };
        Some(fit(&arx, records, inputs, outputs)?)
    } else {
        None
    };
    Ok(FittedModel {
        rhonn_version: env!("CARGO_PKG_VERSION").to_string(),
        model,
        members,
        baseline,
        units: Default::default(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue: "the Cholesky `expect` in `sysid/mod.rs` fires with `ridge = 0` on collinear
    /// data". A Gram matrix the factorisation refuses is now an error naming the ridge.
    #[test]
    fn a_gram_matrix_without_a_factorisation_is_an_error_naming_the_ridge() {
        let rows = vec![vec![1.0, f64::NAN], vec![2.0, 1.0], vec![3.0, 1.0]];
        let e = batch_ls(&rows, &[vec![1.0, 2.0, 3.0]], 0.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("`model.ridge` = 0") && e.contains("collinear"), "{e}");
        // Exactly collinear regressors (a column repeated) still solve with the tiny
        // diagonal load, and the weights are finite.
        let rows: Vec<Vec<f64>> = (0..50).map(|k| vec![k as f64, k as f64, 1.0]).collect();
        let y: Vec<f64> = (0..50).map(|k| 2.0 * k as f64 + 1.0).collect();
        let w = batch_ls(&rows, &[y], 0.0).unwrap();
        assert!(w[0].iter().all(|v| v.is_finite()));
        assert!((w[0][0] + w[0][1] - 2.0).abs() < 1e-3, "{:?}", w[0]);
    }

    /// A record of y(k) = 0.5 y(k-1) + 0.3 u(k-1) + 0.2 y(k-1)^2-ish nonlinear system.
    fn record(seed: u64, n: usize, nonlinear: bool) -> Record {
        let mut s = seed;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 33) as f64 / (1u64 << 31) as f64) - 0.5
        };
        let mut u = vec![0.0; n];
        let mut level = 0.0;
        for k in 0..n {
            if k % 7 == 0 {
                level = 2.0 * next();
            }
            u[k] = level;
        }
        let mut y = vec![0.0; n];
        for k in 1..n {
            let lin = 0.5 * y[k - 1] + 0.3 * u[k - 1];
            y[k] = if nonlinear {
                lin + 0.4 * (y[k - 1]).tanh() * u[k - 1]
            } else {
                lin
            };
        }
        Record {
            source: format!("r{seed}"),
            t: (0..n).map(|k| k as f64 * 0.1).collect(),
            inputs: vec![u],
            outputs: vec![y],
        }
    }

    fn names() -> (Vec<String>, Vec<String>) {
        (vec!["u".into()], vec!["y".into()])
    }

    #[test]
    fn spec_files_hold_one_structure_or_an_ensemble() {
        let one = parse_spec_file("na = 3\nnb = 1\n").unwrap();
        assert_eq!(one.len(), 1);
        assert_eq!((one[0].na, one[0].nb, one[0].kind), (3, 1, Kind::Rhonn));
        let two = parse_spec_file("[[members]]\nna = 2\n[[members]]\nkind = \"arx\"\nna = 4\n").unwrap();
        assert_eq!(two.len(), 2);
        assert_eq!((two[0].na, two[1].na, two[1].kind), (2, 4, Kind::Arx));
        for (text, says) in [
            ("members = []\n", "non-empty list"),
            ("na = 2\n[[members]]\nna = 3\n", "`na` beside `members`"),
            ("[[members]]\nna = 2\n[[members]]\nnaa = 3\n", "members[1]"),
            ("nope = 1\n", "nope"),
        ] {
            let e = parse_spec_file(text).unwrap_err();
            assert!(e.contains(says), "{text:?}: {e}");
        }
    }

    #[test]
    fn an_ensemble_predicts_the_mean_of_its_members() {
        let (i, o) = names();
        let specs = [
            ModelSpec {
                na: 1,
                nb: 1,
                ..Default::default()
            },
            ModelSpec {
                na: 3,
                nb: 2,
                degree: 1,
                max_factors: 1,
                ..Default::default()
            },
        ];
        let rec = record(1, 400, true);
        let ens = fit_ensemble(&specs, std::slice::from_ref(&rec), &i, &o).unwrap();
        assert_eq!(ens.members.len(), 1);
        ens.validate().unwrap();
        assert_eq!(ens.max_lag(), 3);
        let val = record(2, 300, true);
        for steps in [None, Some(1), Some(4)] {
            let (p, first) = ens.predict(&val, steps).unwrap();
            let (pa, fa) = ens.model.predict(&val, steps).unwrap();
            let (pb, fb) = ens.members[0].predict(&val, steps).unwrap();
            assert_eq!(first, fa.max(fb));
            for k in 0..val.len() {
                let want = if k < first {
                    val.outputs[0][k]
                } else {
                    (pa[0][k] + pb[0][k]) / 2.0
                };
                assert!((p[0][k] - want).abs() < 1e-12, "{steps:?} sample {k}");
            }
        }
        // A single structure is the one-member case, with no `members` in model.json.
        let single = fit_with_baseline(&specs[0], std::slice::from_ref(&rec), &i, &o).unwrap();
        assert!(single.members.is_empty());
        assert!(!serde_json::to_string(&single).unwrap().contains("members"));
        assert_eq!(
            single.predict(&val, None).unwrap(),
            single.model.predict(&val, None).unwrap()
        );
    }

    #[test]
    fn nonlinear_lags_limit_the_high_order_terms_to_the_newest_lags() {
        let (i, o) = names();
        let spec = ModelSpec {
            na: 3,
            nb: 4,
            degree: 2,
            max_factors: 2,
            nonlinear_lags: Some(2),
            input_filters_s: vec![1.0],
            ..Default::default()
        };
        // phi = [y lags 1..3 (0, 1, 2), u lags 1..4 (3..7), filtered u (7)]
        assert_eq!(nonlinear_regressors(&spec, 1, 1), vec![0, 1, 3, 4, 7]);
        let m = fit(&spec, &[record(1, 400, true)], &i, &o).unwrap();
        // 5 factors, degree 2: 5 linear + 5 squares + 10 products.
        assert_eq!(m.terms.len(), 20);
        let used: std::collections::BTreeSet<usize> = m.terms.iter().flatten().map(|f| f[0]).collect();
        assert_eq!(used.into_iter().collect::<Vec<_>>(), vec![0, 1, 3, 4, 7]);
        let all = ModelSpec {
            nonlinear_lags: None,
            ..spec.clone()
        };
        assert_eq!(nonlinear_regressors(&all, 1, 1), (0..8).collect::<Vec<_>>());
        let bad = ModelSpec {
            nonlinear_lags: Some(0),
            ..spec
        };
        let e = bad.check().unwrap_err().to_string();
        assert!(e.contains("model.nonlinear_lags") && e.contains("[1, 50]"), "{e}");
    }

    #[test]
    fn arx_recovers_a_linear_system_exactly_and_predicts_unseen_data() {
        let (i, o) = names();
        let spec = ModelSpec {
            kind: Kind::Arx,
            na: 1,
            nb: 1,
            nk: 1,
            ..Default::default()
        };
        let m = fit(&spec, &[record(1, 500, false)], &i, &o).unwrap();
        let val = record(2, 300, false);
        let (p, first) = m.predict(&val, None).unwrap();
        let f = m.figures(&val, &p, first);
        assert!(f[0].fit_percent > 99.9, "{f:?}");
        assert_eq!(first, 1);
    }

    #[test]
    fn rhonn_beats_arx_with_the_same_lags_on_a_nonlinear_system() {
        let (i, o) = names();
        let spec = ModelSpec {
            na: 1,
            nb: 1,
            nk: 1,
            ..Default::default()
        };
        let fm = fit_with_baseline(&spec, &[record(3, 800, true)], &i, &o).unwrap();
        let val = record(4, 400, true);
        let free = |m: &Model| {
            let (p, first) = m.predict(&val, None).unwrap();
            m.figures(&val, &p, first)[0].fit_percent
        };
        let (rh, arx) = (free(&fm.model), free(fm.baseline.as_ref().unwrap()));
        assert!(rh > 95.0 && rh > arx + 20.0, "rhonn {rh} %, arx {arx} %");
    }

    #[test]
    fn k_steps_ahead_sits_between_one_step_and_free_run() {
        let (i, o) = names();
        let m = fit(
            &ModelSpec {
                kind: Kind::Arx,
                na: 2,
                nb: 2,
                nk: 1,
                ..Default::default()
            },
            &[record(5, 500, true)],
            &i,
            &o,
        )
        .unwrap();
        let val = record(6, 300, true);
        let fit_of = |k: Option<usize>| {
            let (p, first) = m.predict(&val, k).unwrap();
            m.figures(&val, &p, first)[0].fit_percent
        };
        let (one, ten, free) = (fit_of(Some(1)), fit_of(Some(10)), fit_of(None));
        assert!(one >= ten - 1e-9 && ten >= free - 1.0, "{one} {ten} {free}");
    }

    #[test]
    fn simulation_and_multi_step_training_lower_their_own_criterion_below_least_squares() {
        let (i, o) = names();
        // Noisy measurements: one-step least squares is biased for free runs.
        let mut data = record(9, 600, true);
        let mut s = 7u64;
        for v in data.outputs[0].iter_mut() {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            *v += 0.05 * (((s >> 33) as f64 / (1u64 << 31) as f64) - 0.5);
        }
        let base = ModelSpec {
            na: 2,
            nb: 2,
            nk: 1,
            epochs: 20,
            ..Default::default()
        };
        let err = |m: &Model, h: Option<usize>| {
            let (p, first) = m.predict(&data, h).unwrap();
            m.figures(&data, &p, first)[0].rms_error
        };
        let ls = fit(&base, std::slice::from_ref(&data), &i, &o).unwrap();
        let se = fit(
            &ModelSpec {
                law: Law::SimulationError,
                ..base.clone()
            },
            std::slice::from_ref(&data),
            &i,
            &o,
        )
        .unwrap();
        let ms = fit(
            &ModelSpec {
                law: Law::MultiStep,
                horizon: 5,
                ..base.clone()
            },
            std::slice::from_ref(&data),
            &i,
            &o,
        )
        .unwrap();
        assert!(
            err(&se, None) < err(&ls, None),
            "free run: {} vs {}",
            err(&se, None),
            err(&ls, None)
        );
        assert!(
            err(&ms, Some(5)) < err(&ls, Some(5)),
            "5 steps: {} vs {}",
            err(&ms, Some(5)),
            err(&ls, Some(5))
        );
    }

    #[test]
    fn input_filters_stand_for_an_unmeasured_lagged_state() {
        // y(k) = 2 x(k-1), x a first-order lag (tau = 1 s, T = 0.1 s) of u: a static map
        // of the filtered input, which two input lags cannot express.
        let (i, o) = names();
        let mut r = record(11, 600, false);
        let a = (-0.1f64 / 1.0).exp();
        let mut x = r.inputs[0][0];
        let u = r.inputs[0].clone();
        for k in 0..r.len() {
            r.outputs[0][k] = 2.0 * x;
            x = a * x + (1.0 - a) * u[k];
        }
        let free_fit = |spec: &ModelSpec| {
            let m = fit(spec, std::slice::from_ref(&r), &i, &o).unwrap();
            let (p, first) = m.predict(&r, None).unwrap();
            m.figures(&r, &p, first)[0].fit_percent
        };
        let plain = ModelSpec {
            kind: Kind::Arx,
            na: 1,
            nb: 1,
            nk: 1,
            ..Default::default()
        };
        let filtered = ModelSpec {
            input_filters_s: vec![1.0],
            ..plain.clone()
        };
        let (f0, f1) = (free_fit(&plain), free_fit(&filtered));
        assert!(f1 > 99.9, "with the filter: {f1} %");
        assert!(f0 < f1, "{f0} vs {f1}");
        let bad = ModelSpec {
            input_filters_s: vec![-1.0],
            ..plain
        };
        assert!(bad
            .check()
            .unwrap_err()
            .to_string()
            .contains("`model.input_filters_s[0]` = -1"));
    }

    #[test]
    fn a_direct_two_step_predictor_is_exact_on_a_linear_system() {
        // y(k) = 0.5 y(k-1) + 0.3 u(k-1) = 0.25 y(k-2) + 0.15 u(k-2) + 0.3 u(k-1).
        let (i, o) = names();
        let spec = ModelSpec {
            kind: Kind::Arx,
            na: 1,
            nb: 2,
            nk: 1,
            output_lag_start: 2,
            ..Default::default()
        };
        assert_eq!(spec.max_lag(), 2);
        let m = fit(&spec, &[record(12, 400, false)], &i, &o).unwrap();
        let val = record(13, 200, false);
        let (p, first) = m.predict(&val, Some(2)).unwrap();
        assert!(m.figures(&val, &p, first)[0].fit_percent > 99.99);
    }

    #[test]
    fn pruning_keeps_the_terms_that_matter() {
        // The nonlinear record needs the product tanh(y(k-1)) u(k-1): with two terms kept
        // out of the nine of degree 2 the model must keep that one and stay accurate.
        let (i, o) = names();
        let data = [record(14, 800, true)];
        let spec = ModelSpec {
            na: 1,
            nb: 1,
            nk: 1,
            max_terms: Some(2),
            ..Default::default()
        };
        let m = fit(&spec, &data, &i, &o).unwrap();
        assert_eq!(m.terms.len(), 2);
        assert!(m.terms.contains(&vec![[0, 1], [1, 1]]), "{:?}", m.terms);
        let val = record(15, 300, true);
        let (p, first) = m.predict(&val, None).unwrap();
        assert!(m.figures(&val, &p, first)[0].fit_percent > 90.0);
        let full = fit(
            &ModelSpec {
                max_terms: None,
                ..spec
            },
            &data,
            &i,
            &o,
        )
        .unwrap();
        assert!(full.terms.len() > 2);
    }

    #[test]
    fn recursive_laws_approach_batch_least_squares() {
        let (i, o) = names();
        let data = [record(7, 600, false)];
        let base = ModelSpec {
            kind: Kind::Arx,
            na: 1,
            nb: 1,
            nk: 1,
            ..Default::default()
        };
        let w_ls = fit(&base, &data, &i, &o).unwrap().weights;
        let w_rls = fit(
            &ModelSpec {
                law: Law::Rls,
                epochs: 3,
                ..base.clone()
            },
            &data,
            &i,
            &o,
        )
        .unwrap()
        .weights;
        let w_g = fit(
            &ModelSpec {
                law: Law::Gradient,
                epochs: 200,
                ..base.clone()
            },
            &data,
            &i,
            &o,
        )
        .unwrap()
        .weights;
        for k in 0..w_ls[0].len() {
            assert!((w_ls[0][k] - w_rls[0][k]).abs() < 1e-3, "{w_ls:?} {w_rls:?}");
            assert!((w_ls[0][k] - w_g[0][k]).abs() < 2e-2, "{w_ls:?} {w_g:?}");
        }
    }
}
