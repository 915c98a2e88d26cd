//! The model structures both identifiers learn, below both: the spec (`--model SPEC.toml`),
//! the stored model (`model.json`) and what each kind does with its parameters (its spec
//! rules, prediction, the check of a stored model). The offline fitter (`sysid`) trains
//! these models on whole records; the online identifier (`ident`) learns the lagged and
//! cascade kinds one sample at a time. Each kind is one file here with one
//! [`kinds::Structure`]; its training is one file in `sysid`.
//!
//! The lagged kinds share one regressor (see the `sysid` module's docs for the laws):
//! - `arx`: `y(k) = theta^T [phi(k), 1]`;
//! - `rhonn`: `y(k) = theta^T [phi(k), z(s(phi_y(k)), phi_u(k)), 1]`: the linear state
//!   terms and the high-order terms of the sigmoids of the normalised lagged outputs and
//!   of the normalised lagged inputs.
//!
//! `phi(k)` holds, normalised by the training data's mean and standard deviation, every
//! output at lags 1..=na and every input at lags nk..nk+nb-1.

pub mod cascade;
pub mod kinds;
mod lagged;
pub mod mean;
mod model;
pub mod pump_grey;
pub mod state_space;
pub mod wiener_hammerstein;

pub(crate) use model::hold;
pub use model::{Model, OutputFigures};

use crate::error::{invalid, Result};
use crate::net::Terms;
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
    /// A discrete-time nonlinear state-space model, from the best linear approximation
    /// (see the `state_space` module).
    StateSpace,
    /// Each output's training mean, a constant: the reference a model must beat (see the
    /// `mean` module).
    Mean,
}

impl Kind {
    /// The kind with its article, for messages: "an ARX", "a RHONN", "a cascade", "the
    /// pump's grey-box".
    pub fn with_article(self) -> &'static str {
        model_kind(self).with_article(self)
    }

    /// An ARX or a lagged RHONN: weights over lagged measurements, one set per output.
    pub fn is_lagged(self) -> bool {
        matches!(self, Kind::Arx | Kind::Rhonn)
    }
}

/// The implementation of `kind` (see the `kinds` module): the registry of model kinds,
/// one line per kind.
pub fn model_kind(kind: Kind) -> &'static dyn kinds::Structure {
    match kind {
        Kind::Arx | Kind::Rhonn => &lagged::Lagged,
        Kind::Cascade => &cascade::Cascade,
        Kind::Pump => &pump_grey::PumpGrey,
        Kind::WienerHammerstein => &wiener_hammerstein::WienerHammerstein,
        Kind::StateSpace => &state_space::StateSpace,
        Kind::Mean => &mean::Mean,
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
    /// Whether it is the default, `tanh` (a spec file leaves it out then).
    pub fn is_tanh(&self) -> bool {
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

/// What the nonlinear terms of a `state-space` model are made of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum NonlinearIn {
    /// The states and the inputs (default; PNLSS's full polynomial).
    #[default]
    StatesAndInputs,
    /// The states alone: the inputs enter linearly (a force on a mechanical system with a
    /// nonlinear spring or hysteresis); fewer terms, and no polynomial of an input that
    /// leaves its training range.
    States,
}

impl NonlinearIn {
    /// Whether it is the default (a spec file leaves it out then).
    pub fn is_default(&self) -> bool {
        *self == NonlinearIn::StatesAndInputs
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
    /// What the nonlinear terms of a `state-space` model take: `states-and-inputs`
    /// (default) or `states`.
    #[serde(skip_serializing_if = "NonlinearIn::is_default")]
    pub nonlinear_in: NonlinearIn,
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
            nonlinear_in: NonlinearIn::StatesAndInputs,
            neurons: 2,
            free_exponents: true,
            starts: 16,
            settle: 5,
            seed: 1,
            pump: Default::default(),
        }
    }
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

    /// Whether its terms are unbounded polynomials (`activation = "identity"` in a lagged
    /// `rhonn` or a `state-space` model): the selection asks them to win by a margin and
    /// keeps them out of ensembles.
    pub fn polynomial_terms(&self) -> bool {
        model_kind(self.kind).polynomial_terms(self)
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
pub fn check_regressor_count(spec: &ModelSpec, ni: usize, no: usize) -> Result<()> {
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
pub fn nonlinear_regressors(spec: &ModelSpec, ni: usize, no: usize) -> Vec<usize> {
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
pub fn n_phi(spec: &ModelSpec, ni: usize, no: usize) -> usize {
    no * spec.na + ni * spec.nb + ni * spec.input_filters_s.len()
}

/// The high-order terms of a lagged structure (`rhonn`: every monomial of its
/// nonlinear regressors; `arx`: none), as factor lists over the regressors.
pub fn lagged_terms(spec: &ModelSpec, ni: usize, no: usize) -> Vec<Vec<[usize; 2]>> {
    if spec.kind != Kind::Rhonn {
        return vec![];
    }
    let sub = nonlinear_regressors(spec, ni, no);
    let t = Terms::monomials(sub.len(), spec.degree, spec.max_factors);
    (0..t.len())
        .map(|k| t.factors(k).into_iter().map(|[i, e]| [sub[i], e]).collect())
        .collect()
}
