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

use super::cascade_online::{CascadeOnline, CascadeSnapshot};
use super::lagged::{LaggedOnline, LaggedSnapshot};
use super::online_spec::{check_spec, OnlineStructure};
pub use super::online_spec::{InputHold, OnlineSpec, Scaling};
use super::{Identifier, Mode, Scratch};
use crate::error::{invalid, Error, Result};
use crate::law::{GainSpec, LawSpec, Rule};
use crate::net::{Network, Sigmoid, Terms};
use rhonn_core::online::{Buffers, Online, Settings, Status, UpdateError};
use rhonn_core::online_fixed::online_terms;
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
        }
    }

    /// The identifier with these weights, frozen; every size and value checked (the file
    /// may have been edited by hand).
    pub fn identifier(&self) -> Result<OnlineIdentifier> {
        if self.kind != Self::KIND {
            return Err(invalid("kind", &self.kind, Self::KIND));
        }
        let (ny, nu) = (self.outputs.len(), self.inputs.len());
        let mut id = OnlineIdentifier::new(&self.model, ny, nu, self.sample_time_s, self.scaling.clone())?;
        let l = id.n_terms();
        if self.weights.len() != ny || self.weights.iter().any(|w| w.len() != l) {
            return Err(invalid(
                "weights",
                format!(
                    "{} vectors of lengths {:?}",
                    self.weights.len(),
                    self.weights.iter().map(Vec::len).collect::<Vec<_>>()
                ),
                format!("{ny} vectors of {l} weights (one per output, one per term)"),
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
        if let Engine::Cascade(c) = &id.engine {
            c.check_weights(&self.weights)?;
        }
        id.set_weights(&self.weights);
        id.freeze(true);
        Ok(id)
    }
}

/// What [`OnlineIdentifier::snapshot`] saves.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot(Saved);

#[derive(Debug, Clone, PartialEq)]
enum Saved {
    Continuous {
        state: Vec<f64>,
        t_last: Option<f64>,
        y_last: Vec<f64>,
        u_last: Vec<f64>,
    },
    Lagged(LaggedSnapshot),
    Cascade(CascadeSnapshot),
}

/// The online identifier (see the module docs): continuous-time neurons (the default)
/// or the lagged structure (`structure = "lagged"`, the `lagged` module). Buffers are
/// allocated once: a continuous update does not allocate.
#[derive(Debug, Clone)]
pub struct OnlineIdentifier {
    engine: Engine,
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

#[derive(Debug, Clone)]
enum Engine {
    Continuous(Box<Continuous>),
    Lagged(Box<LaggedOnline>),
    Cascade(Box<CascadeOnline>),
}

/// The continuous-time engine.
#[derive(Debug, Clone)]
struct Continuous {
    ident: Identifier,
    scaling: Scaling,
    hold: InputHold,
    filters_s: Vec<f64>,
    dead_zone: Vec<f64>,
    period_s: f64,
    state: Vec<f64>,
    k: Vec<f64>,
    acc: Vec<f64>,
    tmp: Vec<f64>,
    scratch: Scratch,
    /// Last sample's time, frozen, free run.
    status: Status<f64>,
    /// Last sample's normalised outputs and regressor inputs (inputs, filters, 1).
    y_last: Vec<f64>,
    u_last: Vec<f64>,
    yn: Vec<f64>,
    u_now: Vec<f64>,
    u_mid: Vec<f64>,
    y_hat: Vec<f64>,
}

impl OnlineIdentifier {
    /// An identifier of `ny` outputs from `nu` inputs sampled every `period_s`.
    pub fn new(spec: &OnlineSpec, ny: usize, nu: usize, period_s: f64, scaling: Scaling) -> Result<Self> {
        check_spec(spec, ny, nu, period_s, &scaling)?;
        let engine = match spec.structure {
            OnlineStructure::Continuous => {
                Engine::Continuous(Box::new(Continuous::new(spec, ny, nu, period_s, scaling)?))
            }
            OnlineStructure::Lagged => {
                Engine::Lagged(Box::new(LaggedOnline::new(spec, ny, nu, period_s, scaling)?))
            }
            OnlineStructure::Cascade => {
                Engine::Cascade(Box::new(CascadeOnline::new(spec, ny, nu, period_s, scaling)?))
            }
        };
        Ok(OnlineIdentifier {
            engine,
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
        let r = SeenRange { lo, hi, margin };
        self.set_y_bounds(widened(&r.lo, &r.hi, r.margin));
        self.range = Some(r);
    }

    fn set_y_bounds(&mut self, b: Vec<[f64; 2]>) {
        match &mut self.engine {
            Engine::Continuous(c) => c.scaling.y_bounds = Some(b),
            Engine::Lagged(l) => {
                l.scaling.y_bounds = Some(b);
                l.core.set_bounds(&l.scaling);
            }
            Engine::Cascade(c) => c.scaling.y_bounds = Some(b),
        }
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
            return match &mut self.engine {
                Engine::Continuous(c) => c.update(t, u, y),
                Engine::Lagged(l) => l.update(t, u, y),
                Engine::Cascade(c) => c.update(t, u, y),
            };
        }
        match &mut self.engine {
            Engine::Continuous(c) => c.update(t, u, y).map(|_| ()),
            Engine::Lagged(l) => l.update(t, u, y).map(|_| ()),
            Engine::Cascade(c) => c.update(t, u, y).map(|_| ()),
        }?;
        self.widen(y);
        Ok(match &self.engine {
            Engine::Continuous(c) => &c.y_hat,
            Engine::Lagged(l) => l.estimate(),
            Engine::Cascade(c) => &c.out,
        })
    }

    /// Stop (`true`) or resume adapting the weights.
    pub fn freeze(&mut self, frozen: bool) {
        self.frozen = frozen;
        match &mut self.engine {
            Engine::Continuous(c) => c.freeze(frozen),
            Engine::Lagged(l) => l.core.frozen = frozen,
            Engine::Cascade(c) => c.frozen = frozen,
        }
    }

    /// Run free (`true`): the model on its own outputs, weights frozen; or back to
    /// series-parallel.
    pub fn set_free_run(&mut self, free: bool) {
        self.free_run = free;
        match &mut self.engine {
            Engine::Continuous(c) => c.set_free_run(free),
            Engine::Lagged(l) => l.core.free_run = free,
            Engine::Cascade(c) => c.free_run = free,
        }
    }

    /// Forget the last sample (a new record starts): the next update restarts the model
    /// at its measurement; the weights stay.
    pub fn reset(&mut self) {
        match &mut self.engine {
            Engine::Continuous(c) => c.reset(),
            Engine::Lagged(l) => l.reset(),
            Engine::Cascade(c) => c.reset(),
        }
    }

    /// A new pass over recordings starts: the lagged structure's least-squares covariance
    /// restarts at `p0 I` (as each epoch of `rhonn fit`'s `rls`); the cascade's filters
    /// widen their parameter variances by `pass_var` and their free runs' errors start
    /// over; nothing for the continuous-time neurons, whose law states carry over.
    pub fn new_pass(&mut self) {
        match &mut self.engine {
            // Least squares carries its covariance into the next pass: over passes it is
            // least squares on the records repeated, which settles. Restarting it at p0 I
            // each pass let an over-parameterised structure (a recursive ARX of lags 8 on a
            // first-order system) drift along its poorly excited directions, pass after
            // pass (tests/online_bank.rs).
            Engine::Lagged(_) => {}
            Engine::Cascade(c) => c.new_pass(),
            Engine::Continuous(_) => {}
        }
    }

    /// Put the model's estimate at `y` (output units), as at a record's first sample.
    pub fn set_estimate(&mut self, y: &[f64]) {
        match &mut self.engine {
            Engine::Continuous(c) => c.set_estimate(y),
            Engine::Lagged(l) => l.set_estimate(y),
            Engine::Cascade(c) => c.set_estimate(y),
        }
    }

    /// Weights, one vector per output's neuron (normalised units).
    pub fn weights(&self) -> Vec<Vec<f64>> {
        match &self.engine {
            Engine::Continuous(c) => c.weights(),
            Engine::Lagged(l) => l.core.weights().to_vec(),
            Engine::Cascade(c) => c.weights(),
        }
    }

    /// Set the weights (e.g. saved ones).
    pub fn set_weights(&mut self, w: &[Vec<f64>]) {
        match &mut self.engine {
            Engine::Continuous(c) => c.set_weights(w),
            Engine::Lagged(l) => l.core.set_weights(w),
            Engine::Cascade(c) => c.set_weights(w),
        }
    }

    /// Each term's name, in weight order, e.g. `tanh(y)*u`, `u^2`, `u[filter 20 s]`, `1`
    /// (outputs are scaled before the tanh, inputs before entering); lagged: `y[k-1]`,
    /// `tanh(y[k-1])*u[k-1]`, `1`.
    pub fn term_names(&self, outputs: &[String], inputs: &[String]) -> Vec<String> {
        match &self.engine {
            Engine::Continuous(c) => c.term_names(outputs, inputs),
            Engine::Lagged(l) => l.core.feature_names(outputs, inputs),
            Engine::Cascade(c) => c.term_names(inputs),
        }
    }

    /// Number of terms (weights) per neuron.
    pub fn n_terms(&self) -> usize {
        match &self.engine {
            Engine::Continuous(c) => c.n_terms(),
            Engine::Lagged(l) => l.core.n_features(),
            Engine::Cascade(c) => c.n_terms(),
        }
    }

    /// The scaling.
    pub fn scaling(&self) -> &Scaling {
        match &self.engine {
            Engine::Continuous(c) => c.scaling(),
            Engine::Lagged(l) => &l.scaling,
            Engine::Cascade(c) => &c.scaling,
        }
    }

    /// Everything that changes with a sample (model, weights, law states, filters, the
    /// last samples), to save and restore around a K-step-ahead prediction.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot(match &self.engine {
            Engine::Continuous(c) => c.snapshot(),
            Engine::Lagged(l) => Saved::Lagged(l.core.snapshot()),
            Engine::Cascade(c) => Saved::Cascade(c.snapshot()),
        })
    }

    /// Restore a [`OnlineIdentifier::snapshot`] (of this identifier).
    pub fn restore(&mut self, snap: &Snapshot) {
        match (&mut self.engine, &snap.0) {
            (Engine::Continuous(c), s) => c.restore(s),
            (Engine::Lagged(l), Saved::Lagged(s)) => l.core.restore(s),
            (Engine::Cascade(c), Saved::Cascade(s)) => c.restore(s),
            (Engine::Lagged(_) | Engine::Cascade(_), _) => {}
        }
    }
}

impl Continuous {
    fn new(spec: &OnlineSpec, ny: usize, nu: usize, period_s: f64, scaling: Scaling) -> Result<Self> {
        let nf = spec.filters_s.len();
        let m = nu * (1 + nf) + 1;
        // Monomials of the outputs' sigmoids, the inputs and their filters, and one
        // constant term (the last network input is 1).
        let first = if spec.output_terms { 0 } else { ny };
        // An upper bound on the monomials before building them (a spec with many filters
        // and a high degree would otherwise take the memory before the check below).
        let signals = (ny + m - 1 - first) as f64;
        let bound: f64 = (1..=spec.degree)
            .map(|k| {
                (0..k)
                    .map(|j| (signals + j as f64) / (j + 1) as f64)
                    .product::<f64>()
            })
            .sum();
        if bound > 1e6 {
            return Err(invalid(
                "model.degree",
                spec.degree,
                format!("a structure with at most 400 terms (degree {} over {signals} signals gives up to {bound:.0}: lower degree or max_factors, or use fewer filters)", spec.degree),
            ));
        }
        // The terms as a target's fixed-size identifier builds them (rhonn_core).
        let mut lists: Vec<Vec<[usize; 2]>> = vec![vec![]];
        let mut cur = vec![0; ny + m - 1];
        let dims = (ny, nu, nf);
        online_terms(
            dims,
            spec.output_terms,
            spec.degree,
            spec.max_factors,
            &mut cur,
            |f| match f {
                Some((j, d)) => {
                    if let Some(term) = lists.last_mut() {
                        term.push([j, d as usize]);
                    }
                }
                None => lists.push(vec![]),
            },
        );
        lists.pop();
        let terms = Terms::from_lists(&lists, ny + m, "model.terms")?;
        let l = terms.len();
        if l > 400 {
            return Err(invalid(
                "model.degree",
                spec.degree,
                format!("a structure with at most 400 terms (this one has {l}: lower degree or max_factors, or use fewer filters)"),
            ));
        }
        let a = spec.a_per_s.unwrap_or(0.1 / period_s);
        let net = Network {
            n: ny,
            m,
            sigmoid: Sigmoid::TANH,
            state_scale: vec![1.0; ny],
            input_scale: vec![1.0; m],
            terms,
            a: vec![a; ny],
        };
        let law_spec = spec.law.clone().unwrap_or_else(|| LawSpec::FilteredError {
            gamma: vec![GainSpec::Scalar(spec.gain / (period_s * l as f64)); ny],
        });
        let law = law_spec.check(ny, l, "model.law")?;
        let ident = Identifier::new(net, law, Mode::Train);
        let state = ident.initial_state(&vec![0.0; ny], None);
        let d = ident.dim();
        let scratch = Scratch::for_identifier(&ident);
        Ok(Continuous {
            dead_zone: scaling.y_scale.iter().map(|s| spec.dead_zone / s).collect(),
            scaling,
            hold: spec.inputs,
            filters_s: spec.filters_s.clone(),
            period_s,
            k: vec![0.0; d],
            acc: vec![0.0; d],
            tmp: vec![0.0; d],
            state,
            scratch,
            status: Status::default(),
            y_last: vec![0.0; ny],
            u_last: vec![0.0; m],
            yn: vec![0.0; ny],
            u_now: vec![0.0; m],
            u_mid: vec![0.0; m],
            y_hat: vec![0.0; ny],
            ident,
        })
    }

    /// Take the sample `(t, u, y)`: integrate from the last sample to `t`, return the
    /// estimate of `y(t)` made before seeing `y` (the first sample returns `y`), then
    /// learn from `y`. In a free run `y` is ignored (give anything of the right length).
    fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<&[f64]> {
        match self.core().update(t, u, y) {
            Ok(()) => Ok(&self.y_hat),
            Err(UpdateError::Sizes) => Err(invalid(
                "update",
                format!("{} inputs and {} outputs", u.len(), y.len()),
                format!(
                    "{} inputs and {} outputs",
                    self.scaling.u_scale.len(),
                    self.scaling.y_scale.len()
                ),
            )),
            Err(UpdateError::NotFinite) => Err(invalid(
                format!("sample at t = {t} s"),
                format!("u = {u:?}, y = {y:?}"),
                "finite numbers",
            )),
            Err(UpdateError::NotAfter { t_last }) => Err(invalid(
                "t",
                t,
                format!("a time after the previous sample's, {t_last} s"),
            )),
            Err(UpdateError::Diverged) => {
                // The last estimate is that of the sample before (the core left y_hat).
                Err(Error::NotFinite {
                    what: format!("the online identifier's state at t = {t} s"),
                    cause: format!(
                        "the weights diverged (last estimate {:?}, measured {:?}): lower the gain, add a dead zone, or use a sigma law",
                        self.y_hat, y
                    ),
                })
            }
        }
    }

    /// The buffers borrowed as `rhonn_core`'s update runs on them.
    fn core(&mut self) -> Online<'_, f64, Rule> {
        let (ident, zones) = self.ident.view_and_zones();
        Online {
            ident,
            zones,
            settings: Settings {
                scaling: rhonn_core::online::Scaling {
                    y_offset: &self.scaling.y_offset,
                    y_scale: &self.scaling.y_scale,
                    u_offset: &self.scaling.u_offset,
                    u_scale: &self.scaling.u_scale,
                    y_bounds: self.scaling.y_bounds.as_deref(),
                },
                hold: self.hold,
                filters_s: &self.filters_s,
                dead_zone: &self.dead_zone,
                period_s: self.period_s,
            },
            buf: Buffers {
                state: &mut self.state,
                k: &mut self.k,
                acc: &mut self.acc,
                tmp: &mut self.tmp,
                y_last: &mut self.y_last,
                u_last: &mut self.u_last,
                yn: &mut self.yn,
                u_now: &mut self.u_now,
                u_mid: &mut self.u_mid,
                y_hat: &mut self.y_hat,
                work: self.scratch.work(),
            },
            status: &mut self.status,
        }
    }

    /// Stop (`true`) or resume adapting the weights.
    fn freeze(&mut self, frozen: bool) {
        self.status.frozen = frozen;
    }

    /// Run free (`true`): the model on its own outputs, weights frozen; or back to
    /// series-parallel.
    fn set_free_run(&mut self, free: bool) {
        self.status.free_run = free;
    }

    /// Forget the last sample (a new record starts): the next update restarts the model
    /// at its measurement; the weights stay.
    fn reset(&mut self) {
        self.status.t_last = None;
    }

    /// Put the model's estimate at `y` (output units), as at a record's first sample.
    fn set_estimate(&mut self, y: &[f64]) {
        self.core().set_estimate(y);
    }

    /// Weights, one vector per output's neuron (normalised units).
    fn weights(&self) -> Vec<Vec<f64>> {
        self.ident.weights(&self.state)
    }

    /// Set the weights (e.g. saved ones).
    fn set_weights(&mut self, w: &[Vec<f64>]) {
        self.ident.set_weights(&mut self.state, w);
    }

    /// Each term's name, in weight order, e.g. `tanh(y)*u`, `u^2`, `u[filter 20 s]`, `1`
    /// (outputs are scaled before the tanh, inputs before entering).
    fn term_names(&self, outputs: &[String], inputs: &[String]) -> Vec<String> {
        let (ny, nu) = (outputs.len(), inputs.len());
        let signal = |i: usize| -> String {
            if i < ny {
                format!("tanh({})", outputs[i])
            } else if i - ny < nu {
                inputs[i - ny].clone()
            } else if i - ny < nu * (1 + self.filters_s.len()) {
                let q = (i - ny) / nu - 1;
                format!("{}[filter {} s]", inputs[(i - ny) % nu], self.filters_s[q])
            } else {
                "1".into()
            }
        };
        let terms = &self.ident.net.terms;
        (0..terms.len())
            .map(|k| {
                terms
                    .factors(k)
                    .iter()
                    .map(|[i, e]| {
                        if *e == 1 {
                            signal(*i)
                        } else {
                            format!("{}^{e}", signal(*i))
                        }
                    })
                    .collect::<Vec<_>>()
                    .join("*")
            })
            .collect()
    }

    /// Number of terms per neuron.
    fn n_terms(&self) -> usize {
        self.ident.net.n_terms()
    }

    /// The scaling.
    fn scaling(&self) -> &Scaling {
        &self.scaling
    }

    /// Everything that changes with a sample (model, weights, law states, filters, the
    /// last sample), to save and restore around a K-step-ahead prediction.
    fn snapshot(&self) -> Saved {
        Saved::Continuous {
            state: self.state.clone(),
            t_last: self.status.t_last,
            y_last: self.y_last.clone(),
            u_last: self.u_last.clone(),
        }
    }

    /// Restore a [`OnlineIdentifier::snapshot`].
    fn restore(&mut self, snap: &Saved) {
        if let Saved::Continuous {
            state,
            t_last,
            y_last,
            u_last,
        } = snap
        {
            self.state.copy_from_slice(state);
            self.status.t_last = *t_last;
            self.y_last.copy_from_slice(y_last);
            self.u_last.copy_from_slice(u_last);
        }
    }
}
