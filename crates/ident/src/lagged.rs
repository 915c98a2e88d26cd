//! The online identifier's lagged structure (`structure = "lagged"`): a discrete-time
//! RHONN of lagged measurements, `y(k) = w^T [phi(k), z(tanh(phi_y(k)), phi_u(k)), 1]`,
//! exactly the `rhonn` model of `rhonn fit` (the same regressor code,
//! `crate::models::Model`'s), learned one sample at a time by the sampled least-squares
//! law (recursive least squares, `P(0) = p0 I`) or the normalised gradient law. This is
//! the discrete-time RHONN trained online of Sanchez, Alanis & Loukianov (Discrete-Time
//! High Order Neural Control, Springer 2008, where an extended Kalman filter trains it:
//! for a model linear in its weights that filter is recursive least squares).
//!
//! Its states are the lagged measurements themselves, so a hidden state needs no
//! estimate: the output lags carry it (the pump's stroke shows in the last few pressure
//! samples and the current's past). With `output_lag_start = K` the estimate of `y(k)`
//! uses measurements up to `k - K` only: a direct K-step-ahead predictor learned online.

use super::engine::{EngineState, OnlineEngine};
use super::online_spec::{LagSpec, OnlineSpec, Scaling};
use crate::error::{invalid, Result};
use crate::law::{GainSpec, Gradient, LawSpec, LearningLaw, LeastSquares, Rule};
use crate::models::{Kind, Model, ModelSpec};
use crate::net::Terms;

/// The lagged engine: a `models::Model` whose weights learn per sample, and windows of the
/// last `max_lag + 1` normalised samples.
#[derive(Debug, Clone)]
pub(super) struct Lagged {
    model: Model,
    terms: Terms,
    rule: Rule,
    /// Law states (covariance) per output.
    p: Vec<Vec<f64>>,
    /// Per normalised input (then each input's filters): the window, oldest first.
    win_u: Vec<Vec<f64>>,
    /// Per normalised output: the window (measured, or the model's own in a free run).
    win_y: Vec<Vec<f64>>,
    filter_a: Vec<f64>,
    pub(super) seen: usize,
    pub(super) t_last: Option<f64>,
    pub(super) frozen: bool,
    pub(super) free_run: bool,
    dead_zone: Vec<f64>,
    bounds: Vec<(f64, f64)>,
    feat: Vec<f64>,
    work: Vec<f64>,
    pub(super) y_hat: Vec<f64>,
}

/// What [`Lagged`] saves around a K-step-ahead prediction.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct LaggedSnapshot {
    w: Vec<Vec<f64>>,
    p: Vec<Vec<f64>>,
    win_u: Vec<Vec<f64>>,
    win_y: Vec<Vec<f64>>,
    seen: usize,
    t_last: Option<f64>,
}

/// `scaling.y_bounds` in normalised units (unbounded without).
fn normalised_bounds(scaling: &Scaling, ny: usize) -> Vec<(f64, f64)> {
    match &scaling.y_bounds {
        Some(b) => b
            .iter()
            .zip(scaling.y_offset.iter().zip(&scaling.y_scale))
            .map(|([lo, hi], (m, s))| ((lo - m) / s, (hi - m) / s))
            .collect(),
        None => vec![(f64::NEG_INFINITY, f64::INFINITY); ny],
    }
}

/// The first sample a frozen model of `spec` predicts in a free run (before it, it holds
/// the measurement): the lagged structure's largest lag, else the sample after the first.
pub fn first_prediction(spec: &OnlineSpec) -> usize {
    match spec.structure {
        super::OnlineStructure::Lagged => model_spec(spec, &spec.lags.clone().unwrap_or_default()).max_lag(),
        super::OnlineStructure::PerOutput => spec.per_output.as_ref().map_or(1, |p| p.most(first_prediction)),
        _ => 1,
    }
}

/// The measured outputs a frozen model of `spec` reads in a free run before it runs on its
/// own: a lagged structure's largest lag, the cascade's `settle` samples (its filters
/// settle the hidden levels on them, though it predicts from the second sample on), the
/// block structure's `rhonn fit` settling samples (G2's past held at them), one
/// for continuous-time neurons. A state-initialisation window must hold them
/// (`data::within_window`).
pub fn outputs_read_in_free_run(spec: &OnlineSpec) -> usize {
    match spec.structure {
        super::OnlineStructure::Cascade => spec.cascade.clone().unwrap_or_default().settle.max(1),
        super::OnlineStructure::WienerHammerstein => super::block_online::settle(),
        super::OnlineStructure::PerOutput => spec
            .per_output
            .as_ref()
            .map_or(1, |p| p.most(outputs_read_in_free_run)),
        _ => first_prediction(spec),
    }
}

/// The `rhonn fit` structure a lagged online spec stands for.
pub(super) fn model_spec(spec: &OnlineSpec, lags: &LagSpec) -> ModelSpec {
    ModelSpec {
        // Degree 1 is linear in the lagged samples: an ARX (the high-order terms of
        // degree 1 would be the inputs again and the outputs' sigmoids).
        kind: if spec.degree == 1 { Kind::Arx } else { Kind::Rhonn },
        na: lags.na,
        nb: lags.nb,
        nk: lags.nk,
        output_lag_start: lags.output_lag_start,
        nonlinear_lags: lags.nonlinear_lags,
        degree: spec.degree,
        max_factors: spec.max_factors,
        activation: spec.activation,
        input_filters_s: spec.filters_s.clone(),
        // The online identifier holds its estimate within `scaling.y_bounds` itself.
        output_margin: 0.0,
        ..ModelSpec::default()
    }
}

/// The sampled law of a lagged spec: least squares (default, `p0 = 1e3` as `rhonn fit`'s
/// `rls`; or `filtered-regressor-ls` with one `p0`) or the normalised gradient law
/// (`filtered-regressor-gradient` with one scalar `gamma`, or none: the spec's `gain`),
/// whose sampled step is stable for a step in (0, 2). Nothing given is ignored.
fn rule(spec: &OnlineSpec) -> Result<Rule> {
    let allowed = "for `structure = \"lagged\"`: none (least squares, p0 = 1e3), `filtered-regressor-ls` with one p0 > 0 and no floor, or `filtered-regressor-gradient` with one scalar gamma in (0, 2) (or none: `gain`)";
    match &spec.law {
        None => Ok(Rule::LeastSquares(LeastSquares {
            p0: vec![1e3],
            floor: vec![0.0],
        })),
        Some(LawSpec::FilteredRegressorLs { p0, floor: None })
            if p0.len() == 1 && p0[0].is_finite() && p0[0] > 0.0 =>
        {
            Ok(Rule::LeastSquares(LeastSquares {
                p0: p0.clone(),
                floor: vec![0.0],
            }))
        }
        Some(LawSpec::FilteredRegressorGradient { gamma }) => {
            let g = match gamma.as_slice() {
                [] => spec.gain,
                [GainSpec::Scalar(g)] => *g,
                _ => return Err(invalid("model.law.gamma", format!("{gamma:?}"), allowed)),
            };
            if !(g.is_finite() && g > 0.0 && g < 2.0) {
                return Err(invalid("model.law.gamma", g, allowed));
            }
            Ok(Rule::Gradient(Gradient::scalar(g, 1)))
        }
        Some(other) => Err(invalid("model.law", format!("{other:?}"), allowed)),
    }
}

impl Lagged {
    /// The engine for `ny` outputs and `nu` inputs, normalised by `scaling`, its estimate
    /// held within `scaling.y_bounds` (unbounded without).
    pub(super) fn new(
        spec: &OnlineSpec,
        lags: &LagSpec,
        ny: usize,
        nu: usize,
        period_s: f64,
        scaling: &Scaling,
    ) -> Result<Self> {
        let ms = model_spec(spec, lags);
        ms.check()?;
        crate::models::check_regressor_count(&ms, nu, ny)?;
        let terms = crate::models::lagged_terms(&ms, nu, ny);
        if terms.len() > crate::net::MAX_TERMS {
            return Err(invalid(
                "model.degree",
                spec.degree,
                format!(
                    "a lagged structure with at most {} high-order terms (this one gives {}: lower degree, max_factors, nonlinear_lags or the lags)",
                    crate::net::MAX_TERMS,
                    terms.len()
                ),
            ));
        }
        let bounds = normalised_bounds(scaling, ny);
        let mut model = Model {
            spec: ms,
            inputs: (0..nu).map(|j| format!("u{j}")).collect(),
            outputs: (0..ny).map(|j| format!("y{j}")).collect(),
            sample_time_s: period_s,
            input_norm: scaling
                .u_offset
                .iter()
                .copied()
                .zip(scaling.u_scale.iter().copied())
                .collect(),
            output_norm: scaling
                .y_offset
                .iter()
                .copied()
                .zip(scaling.y_scale.iter().copied())
                .collect(),
            output_range: vec![(0.0, 1.0); ny],
            // A stream has no training range known in advance.
            input_range: Vec::new(),
            terms,
            weights: vec![],
        };
        let nf = model.n_features();
        model.weights = vec![vec![0.0; nf]; ny];
        let terms = model.terms();
        let rule = rule(spec)?;
        let mut p = vec![vec![0.0; rule.law_states(nf)]; ny];
        for pj in &mut p {
            rule.init(0, nf, pj);
        }
        let w = model.spec.max_lag() + 1;
        let nq = nu * (1 + spec.filters_s.len());
        Ok(Lagged {
            filter_a: spec.filters_s.iter().map(|tau| (-period_s / tau).exp()).collect(),
            dead_zone: scaling.y_scale.iter().map(|s| spec.dead_zone / s).collect(),
            win_u: vec![vec![0.0; w]; nq],
            win_y: vec![vec![0.0; w]; ny],
            model,
            terms,
            rule,
            p,
            seen: 0,
            t_last: None,
            frozen: false,
            free_run: false,
            bounds,
            feat: vec![0.0; nf],
            work: vec![0.0; nf],
            y_hat: vec![0.0; ny],
        })
    }

    /// One sample, normalised: `un` the inputs, `yn` the outputs. Writes the normalised
    /// estimate of `y(k)` (the measurement itself until the windows hold `max_lag`
    /// samples) into `y_hat`, then learns unless frozen or free. Whether it predicted.
    pub(super) fn step(&mut self, un: &[f64], yn: &[f64]) -> bool {
        let (nu, w) = (un.len(), self.win_y[0].len());
        let last = w - 1;
        for c in self.win_u.iter_mut().chain(self.win_y.iter_mut()) {
            c.copy_within(1.., 0);
        }
        for (j, &v) in un.iter().enumerate() {
            self.win_u[j][last] = v;
            for (q, &a) in self.filter_a.iter().enumerate() {
                // The filter starts at the record's first value, as `rhonn fit`'s does.
                let c = &mut self.win_u[nu + j * self.filter_a.len() + q];
                c[last] = if self.seen == 0 {
                    v
                } else {
                    a * c[last - 1] + (1.0 - a) * v
                };
            }
        }
        let predicting = self.seen >= self.model.spec.max_lag();
        if predicting {
            let wy = &self.win_y;
            self.model
                .features(&|j, i| wy[j][i], &self.win_u, last, &self.terms, &mut self.feat);
        }
        for j in 0..yn.len() {
            let raw = if predicting {
                crate::law::dot(&self.model.weights[j], &self.feat)
            } else {
                yn[j]
            };
            // The bounds limit what the model puts out (and feeds back in a free run);
            // least squares learns from its own prediction's error, unlimited, so a
            // bound that the data outgrow (an online identifier's range seen so far)
            // does not bend the weights.
            let est = raw.clamp(self.bounds[j].0, self.bounds[j].1);
            self.y_hat[j] = est;
            let e = raw - yn[j];
            let outside = self.dead_zone[j] == 0.0 || e.abs() > self.dead_zone[j];
            if predicting && !self.frozen && !self.free_run && outside {
                let w = &mut self.model.weights[j];
                self.rule
                    .update(0, &self.feat, e, w, &mut self.p[j], &mut self.work);
            }
            self.win_y[j][last] = if self.free_run && predicting { est } else { yn[j] };
        }
        self.seen += 1;
        predicting
    }

    /// Hold the estimate within `scaling.y_bounds` from now on.
    pub(super) fn set_bounds(&mut self, scaling: &Scaling) {
        self.bounds = normalised_bounds(scaling, self.bounds.len());
    }

    /// Put the newest output sample of the windows at `yn` (normalised).
    pub(super) fn set_estimate(&mut self, yn: &[f64]) {
        let last = self.win_y[0].len() - 1;
        for (c, &v) in self.win_y.iter_mut().zip(yn) {
            c[last] = v;
        }
    }

    /// Whether every weight is finite.
    pub(super) fn finite(&self) -> bool {
        self.model.weights.iter().flatten().all(|v| v.is_finite())
    }

    pub(super) fn weights(&self) -> &[Vec<f64>] {
        &self.model.weights
    }

    pub(super) fn set_weights(&mut self, w: &[Vec<f64>]) {
        for (a, b) in self.model.weights.iter_mut().zip(w) {
            a.copy_from_slice(b);
        }
    }

    pub(super) fn n_features(&self) -> usize {
        self.feat.len()
    }

    /// Each feature's name, in weight order: `y[k-1]`, `u[k-1]`, `u[filter 20 s][k-1]`,
    /// `tanh(y[k-1])*u[k-1]`, `1`.
    pub(super) fn feature_names(&self, outputs: &[String], inputs: &[String]) -> Vec<String> {
        let s = &self.model.spec;
        let mut phi = Vec::new();
        for o in outputs {
            phi.extend((s.output_lag_start..s.output_lag_start + s.na).map(|i| format!("{o}[k-{i}]")));
        }
        for u in inputs {
            phi.extend((0..s.nb).map(|i| format!("{u}[k-{}]", s.nk + i)));
        }
        for u in inputs {
            for tau in &s.input_filters_s {
                phi.push(format!("{u}[filter {tau} s][k-{}]", s.nk));
            }
        }
        let n_out = outputs.len() * s.na;
        let mut names = phi.clone();
        for k in 0..self.terms.len() {
            let f: Vec<String> = self
                .terms
                .factors(k)
                .iter()
                .map(|[i, e]| {
                    let base = if *i < n_out {
                        format!("tanh({})", phi[*i])
                    } else {
                        phi[*i].clone()
                    };
                    if *e == 1 {
                        base
                    } else {
                        format!("{base}^{e}")
                    }
                })
                .collect();
            names.push(f.join("*"));
        }
        names.push("1".into());
        names
    }

    pub(super) fn snapshot(&self) -> LaggedSnapshot {
        LaggedSnapshot {
            w: self.model.weights.clone(),
            p: self.p.clone(),
            win_u: self.win_u.clone(),
            win_y: self.win_y.clone(),
            seen: self.seen,
            t_last: self.t_last,
        }
    }

    pub(super) fn restore(&mut self, s: &LaggedSnapshot) {
        self.model.weights.clone_from(&s.w);
        self.p.clone_from(&s.p);
        self.win_u.clone_from(&s.win_u);
        self.win_y.clone_from(&s.win_y);
        self.seen = s.seen;
        self.t_last = s.t_last;
    }
}

/// The lagged engine with its scaling and the checks of a sample, as the online
/// identifier runs it.
#[derive(Debug, Clone)]
pub(super) struct LaggedOnline {
    pub(super) core: Lagged,
    pub(super) scaling: Scaling,
    un: Vec<f64>,
    yn: Vec<f64>,
    out: Vec<f64>,
}

impl LaggedOnline {
    pub(super) fn new(
        spec: &OnlineSpec,
        ny: usize,
        nu: usize,
        period_s: f64,
        scaling: Scaling,
    ) -> Result<Self> {
        let lags = spec.lags.clone().unwrap_or_default();
        Ok(LaggedOnline {
            core: Lagged::new(spec, &lags, ny, nu, period_s, &scaling)?,
            scaling,
            un: vec![0.0; nu],
            yn: vec![0.0; ny],
            out: vec![0.0; ny],
        })
    }

    /// The last estimate (output units).
    pub(super) fn estimate(&self) -> &[f64] {
        &self.out
    }

    /// Take the sample `(t, u, y)`: the estimate of `y(t)` from the lagged samples before
    /// it, then learn from `y` (see `OnlineIdentifier::update`).
    pub(super) fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<&[f64]> {
        let s = &self.scaling;
        if u.len() != s.u_scale.len() || y.len() != s.y_scale.len() {
            return Err(invalid(
                "update",
                format!("{} inputs and {} outputs", u.len(), y.len()),
                format!("{} inputs and {} outputs", s.u_scale.len(), s.y_scale.len()),
            ));
        }
        let free = self.core.free_run;
        super::engine::check_sample_finite(t, u, y, !free)?;
        if let Some(t_last) = self.core.t_last.filter(|tl| t <= *tl) {
            return Err(invalid(
                "t",
                t,
                format!("a time after the previous sample's, {t_last} s"),
            ));
        }
        for (j, v) in u.iter().enumerate() {
            self.un[j] = (v - s.u_offset[j]) / s.u_scale[j];
        }
        for (j, v) in y.iter().enumerate() {
            // In a free run the measurement is not used: any finite stand-in will do.
            let v = if v.is_finite() { *v } else { s.y_offset[j] };
            self.yn[j] = (v - s.y_offset[j]) / s.y_scale[j];
        }
        let predicted = self.core.step(&self.un, &self.yn);
        self.core.t_last = Some(t);
        if !self.core.finite() {
            return Err(crate::error::Error::NotFinite {
                what: format!("the online identifier's weights at t = {t} s"),
                cause: format!(
                    "the lagged least-squares update diverged (measured {y:?}): lower p0 (law.p0), add a dead zone, or use fewer lags"
                ),
            });
        }
        for (j, o) in self.out.iter_mut().enumerate() {
            // Before its largest lag the model holds the measurement itself.
            *o = if predicted {
                self.core.y_hat[j] * s.y_scale[j] + s.y_offset[j]
            } else {
                y[j]
            };
        }
        Ok(&self.out)
    }

    /// Put the newest output sample at `y` (output units).
    pub(super) fn set_estimate(&mut self, y: &[f64]) {
        let s = &self.scaling;
        for (j, v) in y.iter().enumerate() {
            self.yn[j] = (v - s.y_offset[j]) / s.y_scale[j];
        }
        self.core.set_estimate(&self.yn);
    }

    /// Forget the last samples (a new record starts); the weights stay.
    pub(super) fn reset(&mut self) {
        self.core.seen = 0;
        self.core.t_last = None;
    }
}

impl OnlineEngine for LaggedOnline {
    fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<&[f64]> {
        LaggedOnline::update(self, t, u, y)
    }
    fn estimate(&self) -> &[f64] {
        LaggedOnline::estimate(self)
    }
    fn freeze(&mut self, frozen: bool) {
        self.core.frozen = frozen;
    }
    fn set_free_run(&mut self, free: bool) {
        self.core.free_run = free;
    }
    fn reset(&mut self) {
        LaggedOnline::reset(self)
    }
    // `new_pass`: nothing. Least squares carries its covariance into the next pass: over
    // passes it is least squares on the records repeated, which settles. Restarting it at
    // p0 I each pass let an over-parameterised structure (a recursive ARX of lags 8 on a
    // first-order system) drift along its poorly excited directions, pass after pass
    // (crates/rhonn/tests/online_bank.rs).
    fn set_estimate(&mut self, y: &[f64]) {
        LaggedOnline::set_estimate(self, y)
    }
    fn weights(&self) -> Vec<Vec<f64>> {
        self.core.weights().to_vec()
    }
    fn set_weights(&mut self, w: &[Vec<f64>]) {
        self.core.set_weights(w);
    }
    fn term_names(&self, outputs: &[String], inputs: &[String]) -> Vec<String> {
        self.core.feature_names(outputs, inputs)
    }
    fn n_terms(&self) -> usize {
        self.core.n_features()
    }
    fn scaling(&self) -> &Scaling {
        &self.scaling
    }
    fn set_y_bounds(&mut self, b: Vec<[f64; 2]>) {
        self.scaling.y_bounds = Some(b);
        self.core.set_bounds(&self.scaling);
    }
    fn snapshot(&self) -> Box<dyn EngineState> {
        Box::new(self.core.snapshot())
    }
    fn restore(&mut self, s: &dyn EngineState) {
        if let Some(s) = s.as_any().downcast_ref::<LaggedSnapshot>() {
            self.core.restore(s);
        }
    }
    fn box_clone(&self) -> Box<dyn OnlineEngine> {
        Box::new(self.clone())
    }
}
