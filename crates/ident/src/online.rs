//! Online RHONN identification of sampled signals: [`OnlineIdentifier`] takes one sample
//! at a time (`update(t, u, y) -> y_hat`), as a user's own loop or `rhonn identify` over
//! recordings gives them, and runs the thesis's continuous-time identifier between
//! samples (classical RK4 on the identifier's ODE; any law of [`crate::law`]). The update
//! itself is `rhonn_core::online`'s, the very code a microcontroller runs
//! (`rhonn_core::online_fixed::FixedOnline`); this type owns its buffers, builds the
//! structure from an [`OnlineSpec`] and turns the core's refusals into errors.
//!
//! - *Series-parallel*: each neuron is driven by the measured outputs, held between
//!   samples; the estimate at a sample is computed before that sample is seen, so it is
//!   a genuine one-sample-ahead prediction.
//! - *Inputs*: held between samples (the default: sampled commands are held by the
//!   actuator's DAC) or interpolated linearly (for inputs that were themselves sampled
//!   from something continuous).
//! - *States nobody measures* (an upper tank's level, a pump's stroke) are stood in for by
//!   filtered regressors: each input also enters through first-order low-pass filters
//!   with the time constants `filters_s`. A hidden state of a chain of reservoirs is a
//!   filtered, nonlinearly distorted copy of the input; a few filters with spread time
//!   constants span it, and the weights stay linear in the parameters, so the laws'
//!   stability proofs (Lyapunov, bounded errors) hold unchanged. Parallel hidden neurons
//!   would make the model nonlinear in its parameters and lose that proof.
//! - *Noise*: a dead zone (errors below it do not adapt the weights, Ioannou & Sun 1996
//!   section 8.5.4), the sigma laws of [`crate::law::sigma`], or both.
//!
//! Signals are normalised inside ([`Scaling`]): offset and scale per output and input.

use super::block_online::BlockOnline;
use super::cascade_online::CascadeOnline;
use super::continuous::Continuous;
use super::engine::{EngineState, OnlineEngine};
use super::lagged::LaggedOnline;
use super::online_spec::{check_spec, OnlineStructure};
pub use super::online_spec::{InputHold, OnlineSpec, Scaling};
use super::per_output::PerOutputOnline;
use crate::error::{invalid, Result};
use serde::{Deserialize, Serialize};

/// A frozen online model as `model.json` holds it: `rhonn identify` writes it and
/// `rhonn predict` runs it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OnlineModel {
    /// `online-rhonn`.
    pub kind: String,
    /// Input columns.
    pub inputs: Vec<String>,
    /// Output columns.
    pub outputs: Vec<String>,
    /// Sample time \[s\].
    pub sample_time_s: f64,
    /// Settings.
    pub model: OnlineSpec,
    /// Scaling.
    pub scaling: Scaling,
    /// Weights per neuron (normalised units).
    pub weights: Vec<Vec<f64>>,
    /// The `per-output` structure: the range each output's own structure holds its
    /// estimate in (output units), in `model.per_output.own`'s order (null: unbounded);
    /// `scaling.y_bounds` is the joint structure's. Absent for every other structure.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub own_y_bounds: Vec<Option<[f64; 2]>>,
}

impl OnlineModel {
    /// The kind name in `model.json`.
    pub const KIND: &'static str = "online-rhonn";

    /// The model `id` stands for now (its settings `spec`, scaling and weights), as
    /// `model.json` holds it.
    pub fn of(
        id: &OnlineIdentifier,
        spec: OnlineSpec,
        inputs: &[String],
        outputs: &[String],
        sample_time_s: f64,
    ) -> Self {
        OnlineModel {
            kind: Self::KIND.into(),
            inputs: inputs.to_vec(),
            outputs: outputs.to_vec(),
            sample_time_s,
            model: spec,
            scaling: id.scaling().clone(),
            weights: id.weights(),
            own_y_bounds: id.engine.own_y_bounds(),
        }
    }

    /// The identifier with these weights, frozen; every size and value checked (the file
    /// may have been edited by hand).
    pub fn identifier(&self) -> Result<OnlineIdentifier> {
        if self.kind != Self::KIND {
            return Err(invalid("kind", &self.kind, Self::KIND));
        }
        let dt = self.sample_time_s;
        if !(dt.is_finite() && (1e-9..=1e9).contains(&dt)) {
            let allowed = "a number of seconds in [1e-9, 1e9]";
            return Err(invalid("sample_time_s", crate::metrics::sig(dt, 6), allowed));
        }
        let (ny, nu) = (self.outputs.len(), self.inputs.len());
        let mut id = OnlineIdentifier::new(&self.model, ny, nu, self.sample_time_s, self.scaling.clone())?;
        let lengths = id.weight_lengths();
        if self.weights.iter().map(Vec::len).ne(lengths.iter().copied()) {
            let allowed = match lengths.iter().all(|&n| n == id.n_terms()) {
                true => format!(
                    "{ny} vectors of {} weights (one per output, one per term)",
                    id.n_terms()
                ),
                false => format!(
                    "{} vectors of lengths {lengths:?} (the joint model's, then each output's own)",
                    lengths.len()
                ),
            };
            return Err(invalid(
                "weights",
                format!(
                    "{} vectors of lengths {:?}",
                    self.weights.len(),
                    self.weights.iter().map(Vec::len).collect::<Vec<_>>()
                ),
                allowed,
            ));
        }
        if let Some((i, k)) = self
            .weights
            .iter()
            .enumerate()
            .find_map(|(i, w)| w.iter().position(|v| !v.is_finite()).map(|k| (i, k)))
        {
            return Err(invalid(
                format!("weights[{i}][{k}]"),
                self.weights[i][k],
                "a finite number",
            ));
        }
        id.engine.check_weights(&self.weights)?;
        id.set_weights(&self.weights);
        let own = self.model.per_output.as_ref().map_or(0, |p| p.own.len());
        if !self.own_y_bounds.is_empty() || own > 0 {
            check_own_bounds(&self.own_y_bounds, own)?;
            id.engine.set_own_y_bounds(&self.own_y_bounds);
        }
        id.freeze(true);
        Ok(id)
    }
}

/// A `per-output` model's `own_y_bounds`: one entry per output with a structure of its
/// own, each null or finite `[low, high]` with low < high.
fn check_own_bounds(b: &[Option<[f64; 2]>], own: usize) -> Result<()> {
    if b.len() != own {
        return Err(invalid(
            "own_y_bounds",
            format!("{} entries", b.len()),
            format!("{own} (one per output with a structure of its own, in `model.per_output.own`'s order)"),
        ));
    }
    for (k, r) in b.iter().enumerate() {
        if let Some([lo, hi]) = r {
            if !(lo.is_finite() && hi.is_finite() && lo < hi && lo.abs() <= 1e150 && hi.abs() <= 1e150) {
                return Err(invalid(
                    format!("own_y_bounds[{k}]"),
                    format!("[{lo}, {hi}]"),
                    "null, or finite [low, high] with low < high, of magnitude at most 1e150",
                ));
            }
        }
    }
    Ok(())
}

/// What [`OnlineIdentifier::snapshot`] saves.
#[derive(Debug)]
pub struct Snapshot(Box<dyn EngineState>);

impl Clone for Snapshot {
    fn clone(&self) -> Self {
        Snapshot(self.0.clone_box())
    }
}

/// The online identifier (see the module docs): continuous-time neurons (the default)
/// or the lagged structure (`structure = "lagged"`, the `lagged` module). Buffers are
/// allocated once: a continuous update does not allocate.
#[derive(Debug, Clone)]
pub struct OnlineIdentifier {
    engine: Box<dyn OnlineEngine>,
    /// With [`OnlineIdentifier::track_bounds`]: the outputs' range over the samples
    /// learned from, which the estimate's bounds follow.
    range: Option<SeenRange>,
    /// Not adapting (frozen or in a free run): nothing widens the range.
    frozen: bool,
    free_run: bool,
}

/// Per output, the lowest and highest value learned from, and the margin the bounds
/// keep around them.
#[derive(Debug, Clone)]
struct SeenRange {
    lo: Vec<f64>,
    hi: Vec<f64>,
    margin: f64,
}

/// Per output, the range `[lo, hi]` widened by `margin` of it on each side (an output
/// that has not moved: by `margin` of the smallest positive width).
pub fn widened(lo: &[f64], hi: &[f64], margin: f64) -> Vec<[f64; 2]> {
    lo.iter()
        .zip(hi)
        .map(|(l, h)| {
            let m = margin * (h - l).max(f64::EPSILON);
            [l - m, h + m]
        })
        .collect()
}

impl OnlineIdentifier {
    /// An identifier of `ny` outputs from `nu` inputs sampled every `period_s`.
    pub fn new(spec: &OnlineSpec, ny: usize, nu: usize, period_s: f64, scaling: Scaling) -> Result<Self> {
        check_spec(spec, ny, nu, period_s, &scaling)?;
        // The registry of online structures: one line each.
        let engine: Box<dyn OnlineEngine> = match spec.structure {
            OnlineStructure::Continuous => Box::new(Continuous::new(spec, ny, nu, period_s, scaling)?),
            OnlineStructure::Lagged => Box::new(LaggedOnline::new(spec, ny, nu, period_s, scaling)?),
            OnlineStructure::Cascade => Box::new(CascadeOnline::new(spec, ny, nu, period_s, scaling)?),
            OnlineStructure::WienerHammerstein => Box::new(BlockOnline::new(spec, ny, nu, scaling)?),
            OnlineStructure::PerOutput => {
                let build = |s: &OnlineSpec, n: usize, sc: Scaling| -> Result<Box<dyn OnlineEngine>> {
                    Ok(Box::new(OnlineIdentifier::new(s, n, nu, period_s, sc)?))
                };
                Box::new(PerOutputOnline::new(spec, ny, scaling, &build)?)
            }
        };
        Ok(OnlineIdentifier {
            engine,
            range: None,
            frozen: false,
            free_run: false,
        })
    }

    /// The `per-output` structure `spec` of identifiers that have learned already: `joint`
    /// for every output and, per `(output, identifier)` of `own`, that output's own (as
    /// the bank over a stream ends: each as it stands, still learning).
    pub(crate) fn per_output(
        joint: OnlineIdentifier,
        own: Vec<(usize, OnlineIdentifier)>,
        spec: &OnlineSpec,
    ) -> Result<Self> {
        let p = spec
            .per_output
            .as_ref()
            .filter(|p| p.own.iter().map(|o| o.output).eq(own.iter().map(|(j, _)| *j)))
            .ok_or_else(|| {
                invalid(
                    "model.per_output",
                    "other outputs",
                    "the outputs of the identifiers given",
                )
            })?;
        let own = own
            .into_iter()
            .map(|(j, id)| (j, Box::new(id) as Box<dyn OnlineEngine>))
            .collect();
        Ok(OnlineIdentifier {
            engine: Box::new(PerOutputOnline::from_parts(Box::new(joint), own, p)),
            range: None,
            frozen: false,
            free_run: false,
        })
    }

    /// From now on, hold the estimate within the outputs' range seen so far, widened by
    /// `margin` of it on each side: starting from `[lo, hi]` (e.g. a warm-up window's
    /// range), each sample learned from widens it before the next estimate. A bound of
    /// data not yet seen is never used, so an online identifier may use it.
    pub fn track_bounds(&mut self, lo: Vec<f64>, hi: Vec<f64>, margin: f64) {
        if self.engine.track_bounds(&lo, &hi, margin) {
            return;
        }
        let r = SeenRange { lo, hi, margin };
        self.set_y_bounds(widened(&r.lo, &r.hi, r.margin));
        self.range = Some(r);
    }

    fn set_y_bounds(&mut self, b: Vec<[f64; 2]>) {
        self.engine.set_y_bounds(b);
    }

    /// After a sample learned from: widen the tracked range to `y`.
    fn widen(&mut self, y: &[f64]) {
        let Some(r) = &mut self.range else { return };
        if self.frozen || self.free_run {
            return;
        }
        let mut moved = false;
        for ((l, h), v) in r.lo.iter_mut().zip(r.hi.iter_mut()).zip(y) {
            if v.is_finite() && (*v < *l || *v > *h) {
                *l = l.min(*v);
                *h = h.max(*v);
                moved = true;
            }
        }
        if moved {
            let b = widened(&r.lo, &r.hi, r.margin);
            self.set_y_bounds(b);
        }
    }

    /// Take the sample `(t, u, y)` and return the estimate of `y(t)` made before seeing
    /// `y` (the first sample returns `y`), then learn from `y`. Continuous: integrate the
    /// identifier from the last sample to `t`. Lagged: the lagged model's prediction
    /// (the measurement itself until it has seen its largest lag). In a free run `y` is
    /// ignored (give anything of the right length).
    pub fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<&[f64]> {
        if self.range.is_none() {
            return self.engine.update(t, u, y);
        }
        self.engine.update(t, u, y)?;
        self.widen(y);
        Ok(self.engine.estimate())
    }

    /// Stop (`true`) or resume adapting the weights.
    pub fn freeze(&mut self, frozen: bool) {
        self.frozen = frozen;
        self.engine.freeze(frozen);
    }

    /// Run free (`true`): the model on its own outputs, weights frozen; or back to
    /// series-parallel.
    pub fn set_free_run(&mut self, free: bool) {
        self.free_run = free;
        self.engine.set_free_run(free);
    }

    /// Forget the last sample (a new record starts): the next update restarts the model
    /// at its measurement; the weights stay.
    pub fn reset(&mut self) {
        self.engine.reset();
    }

    /// A new pass over recordings starts: the cascade's filters widen their parameter
    /// variances by `pass_var` and their free runs' errors start over; nothing for the
    /// lagged structure, whose least squares carries its covariance into the next pass,
    /// nor for the continuous-time neurons, whose law states carry over.
    pub fn new_pass(&mut self) {
        self.engine.new_pass();
    }

    /// Put the model's estimate at `y` (output units), as at a record's first sample.
    pub fn set_estimate(&mut self, y: &[f64]) {
        self.engine.set_estimate(y);
    }

    /// Weights, one vector per output's neuron (normalised units).
    pub fn weights(&self) -> Vec<Vec<f64>> {
        self.engine.weights()
    }

    /// Set the weights (e.g. saved ones).
    pub fn set_weights(&mut self, w: &[Vec<f64>]) {
        self.engine.set_weights(w);
    }

    /// Each term's name, in weight order, e.g. `tanh(y)*u`, `u^2`, `u[filter 20 s]`, `1`
    /// (outputs are scaled before the tanh, inputs before entering); lagged: `y[k-1]`,
    /// `tanh(y[k-1])*u[k-1]`, `1`.
    pub fn term_names(&self, outputs: &[String], inputs: &[String]) -> Vec<String> {
        self.engine.term_names(outputs, inputs)
    }

    /// Why the structure has no model to freeze yet (a `wiener-hammerstein` structure
    /// before its window is full), or None.
    pub fn unfinished(&self) -> Option<String> {
        self.engine.unfinished()
    }

    /// Number of terms (weights) per neuron.
    pub fn n_terms(&self) -> usize {
        self.engine.n_terms()
    }

    /// The length of each weight vector, in [`OnlineIdentifier::weights`]' order: every
    /// neuron's [`OnlineIdentifier::n_terms`], but for the `per-output` structure, whose
    /// parts differ (the joint model's vectors, then each own structure's).
    pub fn weight_lengths(&self) -> Vec<usize> {
        self.engine.weight_lengths()
    }

    /// What each weight vector belongs to, in [`OnlineIdentifier::weights`]' order: its
    /// output's name (`<output>_own` for an output's structure of its own).
    pub fn weight_labels(&self, outputs: &[String]) -> Vec<String> {
        self.engine.weight_labels(outputs)
    }

    /// The scaling.
    pub fn scaling(&self) -> &Scaling {
        self.engine.scaling()
    }

    /// Everything that changes with a sample (model, weights, law states, filters, the
    /// last samples), to save and restore around a K-step-ahead prediction.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot(self.engine.snapshot())
    }

    /// Restore a [`OnlineIdentifier::snapshot`] (of this identifier).
    pub fn restore(&mut self, snap: &Snapshot) {
        self.engine.restore(&*snap.0);
    }
}

/// An identifier is an engine too: a part of a `per-output` structure (`per_output.rs`),
/// which holds each part through the trait and so does not import this module. Each part
/// keeps its own range tracking.
impl OnlineEngine for OnlineIdentifier {
    fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<&[f64]> {
        OnlineIdentifier::update(self, t, u, y)
    }
    fn estimate(&self) -> &[f64] {
        self.engine.estimate()
    }
    fn freeze(&mut self, frozen: bool) {
        OnlineIdentifier::freeze(self, frozen);
    }
    fn set_free_run(&mut self, free: bool) {
        OnlineIdentifier::set_free_run(self, free);
    }
    fn reset(&mut self) {
        OnlineIdentifier::reset(self);
    }
    fn new_pass(&mut self) {
        OnlineIdentifier::new_pass(self);
    }
    fn set_estimate(&mut self, y: &[f64]) {
        OnlineIdentifier::set_estimate(self, y);
    }
    fn weights(&self) -> Vec<Vec<f64>> {
        OnlineIdentifier::weights(self)
    }
    fn set_weights(&mut self, w: &[Vec<f64>]) {
        OnlineIdentifier::set_weights(self, w);
    }
    fn term_names(&self, outputs: &[String], inputs: &[String]) -> Vec<String> {
        OnlineIdentifier::term_names(self, outputs, inputs)
    }
    fn n_terms(&self) -> usize {
        OnlineIdentifier::n_terms(self)
    }
    fn weight_lengths(&self) -> Vec<usize> {
        OnlineIdentifier::weight_lengths(self)
    }
    fn weight_labels(&self, outputs: &[String]) -> Vec<String> {
        OnlineIdentifier::weight_labels(self, outputs)
    }
    fn scaling(&self) -> &Scaling {
        OnlineIdentifier::scaling(self)
    }
    fn set_y_bounds(&mut self, b: Vec<[f64; 2]>) {
        self.engine.set_y_bounds(b);
    }
    fn own_y_bounds(&self) -> Vec<Option<[f64; 2]>> {
        self.engine.own_y_bounds()
    }
    fn set_own_y_bounds(&mut self, b: &[Option<[f64; 2]>]) {
        self.engine.set_own_y_bounds(b);
    }
    fn track_bounds(&mut self, lo: &[f64], hi: &[f64], margin: f64) -> bool {
        OnlineIdentifier::track_bounds(self, lo.to_vec(), hi.to_vec(), margin);
        true
    }
    fn snapshot(&self) -> Box<dyn EngineState> {
        self.engine.snapshot()
    }
    fn restore(&mut self, s: &dyn EngineState) {
        self.engine.restore(s);
    }
    fn check_weights(&self, w: &[Vec<f64>]) -> Result<()> {
        self.engine.check_weights(w)
    }
    fn unfinished(&self) -> Option<String> {
        self.engine.unfinished()
    }
    fn box_clone(&self) -> Box<dyn OnlineEngine> {
        Box::new(self.clone())
    }
}
