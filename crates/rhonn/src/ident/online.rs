//! Online RHONN identification of sampled signals: [`OnlineIdentifier`] takes one sample
//! at a time (`update(t, u, y) -> y_hat`), as a user's own loop or `rhonn identify` over
//! recordings gives them, and runs the thesis's continuous-time identifier between
//! samples (classical RK4 on the identifier's ODE, [`super::Identifier::rhs`]; any law
//! of [`crate::law`]).
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

use super::online_spec::check_spec;
pub use super::online_spec::{InputHold, OnlineSpec, Scaling};
use super::{Identifier, Mode, Scratch};
use crate::error::{invalid, Error, Result};
use crate::law::{GainSpec, LawSpec};
use crate::net::{Network, Sigmoid, Terms};
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
        id.set_weights(&self.weights);
        id.freeze(true);
        Ok(id)
    }
}

/// What [`OnlineIdentifier::snapshot`] saves.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    state: Vec<f64>,
    t_last: Option<f64>,
    y_last: Vec<f64>,
    u_last: Vec<f64>,
}

/// The online identifier (see the module docs). Buffers are allocated once: an update
/// does not allocate.
#[derive(Debug, Clone)]
pub struct OnlineIdentifier {
    ident: Identifier,
    scaling: Scaling,
    hold: InputHold,
    filters_s: Vec<f64>,
    dead_zone: Vec<f64>,
    period_s: f64,
    state: Vec<f64>,
    k: [Vec<f64>; 4],
    tmp: Vec<f64>,
    scratch: Scratch,
    /// Last sample's time; its normalised outputs and regressor inputs (inputs,
    /// filters, 1).
    t_last: Option<f64>,
    y_last: Vec<f64>,
    u_last: Vec<f64>,
    yn: Vec<f64>,
    u_now: Vec<f64>,
    u_mid: Vec<f64>,
    y_hat: Vec<f64>,
    frozen: bool,
    free_run: bool,
}

impl OnlineIdentifier {
    /// An identifier of `ny` outputs from `nu` inputs sampled every `period_s`.
    pub fn new(spec: &OnlineSpec, ny: usize, nu: usize, period_s: f64, scaling: Scaling) -> Result<Self> {
        check_spec(spec, ny, nu, period_s, &scaling)?;
        let nf = spec.filters_s.len();
        let m = nu * (1 + nf) + 1;
        // Monomials of the outputs' sigmoids, the inputs and their filters, and one
        // constant term (the last network input is 1; it takes no part in products,
        // which it would only duplicate).
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
        let mono = Terms::monomials(ny + m - 1 - first, spec.degree, spec.max_factors);
        let mut lists: Vec<Vec<[usize; 2]>> = (0..mono.len())
            .map(|k| mono.factors(k).into_iter().map(|[i, e]| [i + first, e]).collect())
            .collect();
        lists.push(vec![[ny + m - 1, 1]]);
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
        Ok(OnlineIdentifier {
            dead_zone: scaling.y_scale.iter().map(|s| spec.dead_zone / s).collect(),
            scaling,
            hold: spec.inputs,
            filters_s: spec.filters_s.clone(),
            period_s,
            k: std::array::from_fn(|_| vec![0.0; d]),
            tmp: vec![0.0; d],
            state,
            scratch,
            t_last: None,
            y_last: vec![0.0; ny],
            u_last: vec![0.0; m],
            yn: vec![0.0; ny],
            u_now: vec![0.0; m],
            u_mid: vec![0.0; m],
            y_hat: vec![0.0; ny],
            ident,
            frozen: false,
            free_run: false,
        })
    }

    /// Take the sample `(t, u, y)`: integrate from the last sample to `t`, return the
    /// estimate of `y(t)` made before seeing `y` (the first sample returns `y`), then
    /// learn from `y`. In a free run `y` is ignored (give anything of the right length).
    pub fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<&[f64]> {
        let (ny, nu) = (self.scaling.y_scale.len(), self.scaling.u_scale.len());
        if u.len() != nu || y.len() != ny {
            return Err(invalid(
                "update",
                format!("{} inputs and {} outputs", u.len(), y.len()),
                format!("{nu} inputs and {ny} outputs"),
            ));
        }
        if !t.is_finite()
            || u.iter().any(|v| !v.is_finite())
            || (!self.free_run && y.iter().any(|v| !v.is_finite()))
        {
            return Err(invalid(
                format!("sample at t = {t} s"),
                format!("u = {u:?}, y = {y:?}"),
                "finite numbers",
            ));
        }
        for i in 0..ny {
            self.yn[i] = (y[i] - self.scaling.y_offset[i]) / self.scaling.y_scale[i];
        }
        self.regressor_inputs(u);
        let Some(t0) = self.t_last else {
            // The first sample: the model starts at the measurement, the filters at rest.
            let yn = std::mem::take(&mut self.yn);
            self.set_estimate_normalised(&yn);
            self.start_filters();
            self.start_regressor_filters(&yn);
            self.yn = yn;
            self.remember(t);
            return Ok(self.denormalised());
        };
        let h = t - t0;
        if !(h > 0.0) {
            return Err(invalid(
                "t",
                t,
                format!("a time after the previous sample's, {t0} s"),
            ));
        }
        let adapt = !self.frozen
            && !self.free_run
            && (0..ny).any(|i| (self.estimate_normalised(i) - self.y_last[i]).abs() >= self.dead_zone[i]);
        self.ident.mode = match (self.free_run, adapt) {
            (true, _) => Mode::Parallel,
            (false, true) => Mode::Train,
            (false, false) => Mode::SeriesParallel,
        };
        let (y0, u0) = (std::mem::take(&mut self.y_last), std::mem::take(&mut self.u_last));
        self.integrate(h, &y0, &u0);
        self.advance_filters(h, &u0);
        self.hold_in_bounds();
        (self.y_last, self.u_last) = (y0, u0);
        if self.state.iter().any(|v| !v.is_finite()) {
            return Err(Error::NotFinite {
                what: format!("the online identifier's state at t = {t} s"),
                cause: format!(
                    "the weights diverged (last estimate {:?}, measured {:?}): lower the gain, add a dead zone, or use a sigma law",
                    self.y_hat, y
                ),
            });
        }
        self.remember(t);
        Ok(self.denormalised())
    }

    /// Keep this sample as the last one.
    fn remember(&mut self, t: f64) {
        self.t_last = Some(t);
        self.y_last.copy_from_slice(&self.yn);
        self.u_last.copy_from_slice(&self.u_now);
    }

    /// Stop (`true`) or resume adapting the weights.
    pub fn freeze(&mut self, frozen: bool) {
        self.frozen = frozen;
    }

    /// Run free (`true`): the model on its own outputs, weights frozen; or back to
    /// series-parallel.
    pub fn set_free_run(&mut self, free: bool) {
        self.free_run = free;
    }

    /// Forget the last sample (a new record starts): the next update restarts the model
    /// at its measurement; the weights stay.
    pub fn reset(&mut self) {
        self.t_last = None;
    }

    /// Put the model's estimate at `y` (output units), as at a record's first sample.
    pub fn set_estimate(&mut self, y: &[f64]) {
        let yn: Vec<f64> = (0..y.len())
            .map(|i| (y[i] - self.scaling.y_offset[i]) / self.scaling.y_scale[i])
            .collect();
        self.set_estimate_normalised(&yn);
    }

    /// Weights, one vector per output's neuron (normalised units).
    pub fn weights(&self) -> Vec<Vec<f64>> {
        self.ident.weights(&self.state)
    }

    /// Set the weights (e.g. saved ones).
    pub fn set_weights(&mut self, w: &[Vec<f64>]) {
        self.ident.set_weights(&mut self.state, w);
    }

    /// Each term's name, in weight order, e.g. `tanh(y)*u`, `u^2`, `u[filter 20 s]`, `1`
    /// (outputs are scaled before the tanh, inputs before entering).
    pub fn term_names(&self, outputs: &[String], inputs: &[String]) -> Vec<String> {
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
    pub fn n_terms(&self) -> usize {
        self.ident.net.n_terms()
    }

    /// The scaling.
    pub fn scaling(&self) -> &Scaling {
        &self.scaling
    }

    /// Everything that changes with a sample (model, weights, law states, filters, the
    /// last sample), to save and restore around a K-step-ahead prediction.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            state: self.state.clone(),
            t_last: self.t_last,
            y_last: self.y_last.clone(),
            u_last: self.u_last.clone(),
        }
    }

    /// Restore a [`OnlineIdentifier::snapshot`].
    pub fn restore(&mut self, snap: &Snapshot) {
        self.state.copy_from_slice(&snap.state);
        self.t_last = snap.t_last;
        self.y_last.copy_from_slice(&snap.y_last);
        self.u_last.copy_from_slice(&snap.u_last);
    }

    fn estimate_normalised(&self, i: usize) -> f64 {
        let b = self.ident.block();
        let blk = &self.state[i * b..(i + 1) * b];
        match self.ident.law.structure {
            crate::law::Structure::FilteredError => blk[0],
            crate::law::Structure::FilteredRegressor => {
                let l = self.ident.net.n_terms();
                super::dot(&blk[..l], &blk[l..2 * l])
            }
        }
    }

    /// A frozen filtered-regressor model's filters zeta at rest for the first sample's
    /// regressor z (from the measurement `yn` and the inputs): zeta = z / a, where
    /// zeta' = -a zeta + z stands still. Not what an earlier record left in them: the
    /// frozen model's run of a record (`rhonn identify --validate`, `rhonn predict` of
    /// the saved model) then begins alike whatever ran before. While learning, the
    /// filters carry over from the last record: set at rest, their size (1/a times z's)
    /// with a fresh covariance would make the least-squares law stiff at once.
    fn start_regressor_filters(&mut self, yn: &[f64]) {
        if self.ident.law.structure != crate::law::Structure::FilteredRegressor
            || !(self.frozen || self.free_run)
        {
            return;
        }
        let (n, l, b) = (self.ident.net.n, self.ident.net.n_terms(), self.ident.block());
        let sc = &mut self.scratch;
        self.ident.net.regressor(yn, &self.u_now, &mut sc.y, &mut sc.z);
        for i in 0..n {
            let a = self.ident.net.a[i];
            for k in 0..l {
                self.state[i * b + k] = sc.z[k] / a;
            }
        }
    }

    /// A filtered-error model's state held within the bounds (a limited integrator).
    fn hold_in_bounds(&mut self) {
        let Some(bounds) = &self.scaling.y_bounds else {
            return;
        };
        if self.ident.law.structure != crate::law::Structure::FilteredError {
            return;
        }
        let b = self.ident.block();
        for (i, [lo, hi]) in bounds.iter().enumerate() {
            let (lo, hi) = (
                (lo - self.scaling.y_offset[i]) / self.scaling.y_scale[i],
                (hi - self.scaling.y_offset[i]) / self.scaling.y_scale[i],
            );
            self.state[i * b] = self.state[i * b].clamp(lo, hi);
        }
    }

    fn set_estimate_normalised(&mut self, yn: &[f64]) {
        if self.ident.law.structure == crate::law::Structure::FilteredError {
            let b = self.ident.block();
            for (i, y) in yn.iter().enumerate() {
                self.state[i * b] = *y;
            }
        }
    }

    fn denormalised(&mut self) -> &[f64] {
        for i in 0..self.y_hat.len() {
            self.y_hat[i] = self.estimate_normalised(i) * self.scaling.y_scale[i] + self.scaling.y_offset[i];
        }
        &self.y_hat
    }

    /// The network's inputs for the sample `u`: normalised inputs, their filters (kept
    /// from the last sample), and the constant 1.
    fn regressor_inputs(&mut self, u: &[f64]) {
        let nu = u.len();
        for j in 0..nu {
            self.u_now[j] = (u[j] - self.scaling.u_offset[j]) / self.scaling.u_scale[j];
        }
        if self.t_last.is_some() {
            self.u_now[nu..].copy_from_slice(&self.u_last[nu..]);
        }
        let m = self.u_now.len();
        self.u_now[m - 1] = 1.0;
    }

    fn start_filters(&mut self) {
        let nu = self.scaling.u_scale.len();
        for q in 0..self.filters_s.len() {
            for j in 0..nu {
                self.u_now[nu * (1 + q) + j] = self.u_now[j];
            }
        }
    }

    /// The filters over `h` with the input `u0` held (exact for a held input).
    fn advance_filters(&mut self, h: f64, u0: &[f64]) {
        let nu = self.scaling.u_scale.len();
        for (q, tau) in self.filters_s.iter().enumerate() {
            let k = 1.0 - (-h / tau).exp();
            for j in 0..nu {
                let f = &mut self.u_now[nu * (1 + q) + j];
                *f = u0[nu * (1 + q) + j] + k * (u0[j] - u0[nu * (1 + q) + j]);
            }
        }
    }

    /// A substep's first stage: the robust laws' zones, the inputs at fraction `f`, and
    /// the derivative into `k[0]` (with the previous regressor when `same_regressor`).
    fn start_substep(&mut self, y0: &[f64], u0: &[f64], f: f64, same_regressor: bool) {
        self.ident.update_modes(y0, u0, &self.state, &mut self.scratch);
        let nu = self.scaling.u_scale.len();
        stage_inputs(&mut self.u_mid, u0, &self.u_now, nu, self.hold, f);
        let k1 = &mut self.k[0];
        self.ident.rhs_general(
            y0,
            &self.u_mid,
            &self.state,
            k1,
            &mut self.scratch,
            same_regressor,
        );
    }

    /// Classical RK4 over `h` (in substeps of at most one sample time), the measured
    /// outputs `y0` held and the inputs held at `u0` or linear to `self.u_now`.
    fn integrate(&mut self, h: f64, y0: &[f64], u0: &[f64]) {
        // Substeps short enough for RK4 to follow the identifier's fastest motion (the
        // neuron's pole a, and the weight-error oscillation sqrt(gamma |z|^2)), so the
        // law's continuous-time stability carries over to the sampled run. The first
        // stage's regressor gives |z|^2 (it does not depend on the substep).
        // With inputs and measurements held over the sample, the regressor is the same at
        // every stage: computed once by the general path, used again by every later stage.
        let reuse = self.hold == InputHold::Hold;
        self.start_substep(y0, u0, 0.0, false);
        let rate = self.fastest_rate();
        let n_sub = (h / self.period_s)
            .max(h * rate / 0.5)
            .ceil()
            .clamp(1.0, 10_000.0) as usize;
        let hs = h / n_sub as f64;
        let d = self.state.len();
        for j in 0..n_sub {
            let f = |x: f64| (j as f64 + x) / n_sub as f64;
            if j > 0 {
                self.start_substep(y0, u0, f(0.0), reuse);
            }
            let [k1, k2, k3, k4] = &mut self.k;
            for i in 0..d {
                self.tmp[i] = self.state[i] + 0.5 * hs * k1[i];
            }
            if self.hold == InputHold::Linear {
                stage_inputs(
                    &mut self.u_mid,
                    u0,
                    &self.u_now,
                    self.scaling.u_scale.len(),
                    self.hold,
                    f(0.5),
                );
            }
            self.ident
                .rhs_general(y0, &self.u_mid, &self.tmp, k2, &mut self.scratch, reuse);
            for i in 0..d {
                self.tmp[i] = self.state[i] + 0.5 * hs * k2[i];
            }
            self.ident
                .rhs_general(y0, &self.u_mid, &self.tmp, k3, &mut self.scratch, reuse);
            for i in 0..d {
                self.tmp[i] = self.state[i] + hs * k3[i];
            }
            if self.hold == InputHold::Linear {
                stage_inputs(
                    &mut self.u_mid,
                    u0,
                    &self.u_now,
                    self.scaling.u_scale.len(),
                    self.hold,
                    f(1.0),
                );
            }
            self.ident
                .rhs_general(y0, &self.u_mid, &self.tmp, k4, &mut self.scratch, reuse);
            for i in 0..d {
                self.state[i] += hs / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
    }
}

impl OnlineIdentifier {
    /// The identifier's fastest rate \[1/s\] after an evaluation of its derivative by
    /// the general path (which left the regressor z in the scratch).
    fn fastest_rate(&self) -> f64 {
        let a_max = self.ident.net.a.iter().copied().fold(0.0, f64::max);
        if self.ident.mode != Mode::Train {
            // Frozen weights: only the neurons move (and a frozen model runs alike
            // whatever covariance its law last had, e.g. when rebuilt from model.json).
            return a_max;
        }
        let l = self.ident.net.n_terms();
        let z2: f64 = self.scratch.z[..l].iter().map(|v| v * v).sum();
        let b = self.ident.block();
        let g_max = (0..self.ident.net.n)
            .map(|i| match &self.ident.law.rule {
                crate::law::Rule::Gradient(g) => match &g.gamma[i] {
                    crate::law::Gain::Scalar(v) => *v,
                    crate::law::Gain::Matrix(m) => m.iter().map(|v| v.abs()).sum::<f64>(),
                },
                crate::law::Rule::LeastSquares(_) => {
                    let p = &self.state[i * b + 2 * l..i * b + 2 * l + l * l];
                    (0..l).map(|k| p[k * l + k]).sum::<f64>()
                }
            })
            .fold(0.0, f64::max);
        a_max.max((g_max * z2).sqrt())
    }
}

/// The network inputs at fraction `f` of the interval: `u0` held, or its first `nu`
/// (the inputs, not their filters) linear to this sample's `u_now`.
fn stage_inputs(u_mid: &mut [f64], u0: &[f64], u_now: &[f64], nu: usize, hold: InputHold, f: f64) {
    u_mid.copy_from_slice(u0);
    if hold == InputHold::Linear {
        for c in 0..nu {
            u_mid[c] = u0[c] + f * (u_now[c] - u0[c]);
        }
    }
}
