//! The online identifier's Wiener-Hammerstein structure (`structure =
//! "wiener-hammerstein"`): `rhonn fit`'s block structure (`kind = "wiener-hammerstein"`:
//! a filter, a static polynomial, a second filter; `models::wiener_hammerstein`) learned
//! from a stream.
//!
//! Learning a block structure sample by sample from nothing was measured and does not
//! reach its batch fit: the recursive prediction-error method over the whole parameter
//! vector (Wigren's route) from the split best linear approximation ran free at 10-15 mV
//! on the Wiener-Hammerstein benchmark where the batch fit reaches 0.7 mV, and diverged
//! by covariance wind-up with forgetting (docs/results.md). Its poles need the many
//! Levenberg-Marquardt iterations of a batch fit. So this structure learns in two stages:
//!
//! 1. **Window.** The first `block.window` samples learned are kept (each record apart);
//!    meanwhile the estimate is the last measured output. At the window's last sample
//!    the block structure is fitted on them by `rhonn fit`'s own training (the best
//!    linear approximation, its poles and zeros split between the filters in every way,
//!    Levenberg-Marquardt on the free-run error), and the window is dropped: the memory
//!    held is bounded by the window, whatever the stream's length.
//! 2. **Recursive least squares.** The filters stay; the polynomial's coefficients and
//!    the offset keep learning. With G1 and G2 fixed the free-run output is linear in
//!    them (`y = sum_j c_j G2(h_j(x)) + bias`), and their regressors are functions of the
//!    inputs alone: least squares on them minimises the free-run error the fit minimised,
//!    unbiased by output noise. (The one-step equation-error form, `A2(q) y` against
//!    `B2(q) v`, weighs the errors by `A2` and moved the benchmark's model from 0.66 to
//!    1.06 mV.) The covariance starts at the inverse of the window's information matrix:
//!    the recursion continues least squares over every sample seen, from the fit's
//!    coefficients, never forgetting (the law's bound: the covariance only shrinks, the
//!    poles stay where the fit put them, stable).
//!
//! The model runs as `rhonn fit`'s: normalised by the window's means and deviations, G1's
//! output held in its window range, the estimate in the window's output range widened by
//! `output_margin` (and in the identifier's bounds, as every structure's).

use super::engine::{EngineState, OnlineEngine};
use super::online_spec::{BlockOnlineSpec, OnlineSpec, Scaling};
use crate::data::Record;
use crate::error::{invalid, Error, Result};
use crate::models::wiener_hammerstein::{hermite, Params};
use crate::models::{Estimator, Kind, ModelSpec};
use nalgebra::{DMatrix, DVector};

/// The stored vector's header: the input's mean and deviation, the output's mean and
/// deviation, the normalised output bounds.
const HEADER: usize = 6;

/// The fitted block structure and what its recursion carries.
#[derive(Debug, Clone, PartialEq)]
struct Fitted {
    p: Params,
    /// Input mean and deviation, output mean and deviation.
    norm: [f64; 4],
    /// The estimate's range (normalised).
    bounds: (f64, f64),
    /// The covariance of (c, bias) for recursive least squares.
    cov: DMatrix<f64>,
    /// The input delay (samples).
    nk: usize,
}

/// What changes with a sample: the filters' pasts, newest first (normalised).
#[derive(Debug, Clone, PartialEq, Default)]
pub(super) struct BlockState {
    /// u(k), u(k-1), ...: `nk + m1` values.
    u: Vec<f64>,
    /// x(k-1), x(k-2), ...: n1 values.
    x: Vec<f64>,
    /// The polynomial's basis at x(k), x(k-1), ...: m2 vectors.
    h: Vec<Vec<f64>>,
    /// G2's past output (measured in series-parallel, its own in free run): n2 values.
    w: Vec<f64>,
    /// Each basis function through G2, at k-1, k-2, ...: n2 vectors (the recursion's
    /// regressors).
    s: Vec<Vec<f64>>,
    /// The last measured output (output units), the estimate before the fit.
    y_last: f64,
    /// Samples since the record started.
    seen: usize,
    t_last: Option<f64>,
}

/// The Wiener-Hammerstein engine.
#[derive(Debug, Clone)]
pub(super) struct BlockOnline {
    set: BlockOnlineSpec,
    output_margin: f64,
    scaling: Scaling,
    frozen: bool,
    free_run: bool,
    /// The window's records (t, u, y), until the fit.
    window: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)>,
    kept: usize,
    /// Fits made after the first (at most `block.refits`).
    refitted: usize,
    /// [`settle`], read once.
    settle: usize,
    fitted: Option<Fitted>,
    state: BlockState,
    out: Vec<f64>,
}

/// The measured outputs a free run holds as G2's past at a record's start: `rhonn fit`'s
/// (`ModelSpec::settle`, which the window's fit trains with), so that the model runs as
/// the fit's of the same parameters.
pub(crate) fn settle() -> usize {
    ModelSpec::default().settle.max(1)
}

/// Shift `v` one place to the right (dropping its oldest) and put `x` first.
fn push(v: &mut [f64], x: f64) {
    if !v.is_empty() {
        v.rotate_right(1);
        v[0] = x;
    }
}

impl BlockOnline {
    pub(super) fn new(spec: &OnlineSpec, ny: usize, nu: usize, scaling: Scaling) -> Result<Self> {
        if ny != 1 || nu != 1 {
            return Err(invalid(
                "inputs and outputs",
                format!("{nu} inputs, {ny} outputs"),
                "one input and one output with `structure = \"wiener-hammerstein\"`",
            ));
        }
        Ok(BlockOnline {
            set: spec.block.clone().unwrap_or_default(),
            output_margin: spec.output_margin.max(0.0),
            scaling,
            frozen: false,
            free_run: false,
            window: vec![(Vec::new(), Vec::new(), Vec::new())],
            kept: 0,
            refitted: 0,
            settle: settle(),
            fitted: None,
            state: BlockState::default(),
            out: vec![0.0],
        })
    }

    /// The number of stored values: the header, the orders, every filter's coefficients
    /// at their most (a split gives G1 and G2 together `poles` poles and at most `poles`
    /// zeros), the polynomial, the offset and x's range.
    fn stored_len(&self) -> usize {
        let p = self.set.poles;
        HEADER + 4 + 2 * (p + 1) + 2 * p + self.set.degree + 3
    }

    fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<&[f64]> {
        if u.len() != 1 || y.len() != 1 {
            return Err(invalid(
                "update",
                format!("{} inputs and {} outputs", u.len(), y.len()),
                "1 input and 1 output",
            ));
        }
        let measured = y[0].is_finite();
        super::engine::check_sample_finite(t, u, y, !self.free_run)?;
        if let Some(tl) = self.state.t_last.filter(|tl| t <= *tl) {
            return Err(invalid(
                "t",
                t,
                format!("a time after the previous sample's, {tl} s"),
            ));
        }
        let learn = !self.frozen && !self.free_run && measured;
        // G2's past is measured in series-parallel, and in a free run over its first
        // samples: as many as `rhonn fit`'s free run of the same parameters settles on.
        let read = measured && (!self.free_run || self.state.seen < self.settle);
        self.out[0] = match &mut self.fitted {
            Some(f) => step(f, &mut self.state, u[0], y[0], read, learn)?,
            None => {
                if read {
                    self.state.y_last = y[0];
                }
                if self.state.y_last.is_finite() {
                    self.state.y_last
                } else {
                    self.scaling.y_offset[0]
                }
            }
        };
        if self.free_run && read {
            // A free run holds its settling samples' measurements, as `rhonn fit`'s does.
            self.out[0] = y[0];
        }
        if let Some([lo, hi]) = self.scaling.y_bounds.as_ref().map(|b| b[0]) {
            self.out[0] = self.out[0].clamp(lo, hi);
        }
        if self.collecting() && learn {
            if self.window.is_empty() {
                self.window.push((Vec::new(), Vec::new(), Vec::new()));
            }
            if let Some(last) = self.window.last_mut() {
                last.0.push(t);
                last.1.push(u[0]);
                last.2.push(y[0]);
            }
            self.kept += 1;
            if self.kept >= self.set.window {
                let refit = self.fitted.is_some();
                self.refitted += usize::from(refit);
                match self.fit() {
                    // A refit that fails, whatever the cause (for example no record of the
                    // window long enough), keeps the last fit.
                    Err(_) if refit => {
                        self.window = Vec::new();
                        self.kept = 0;
                    }
                    r => r?,
                }
            }
        }
        self.state.seen += 1;
        self.state.t_last = Some(t);
        Ok(&self.out)
    }

    /// Whether learned samples go into the window: before the first fit, and after it
    /// while refits remain.
    fn collecting(&self) -> bool {
        self.fitted.is_none() || self.refitted < self.set.refits
    }

    /// `rhonn fit`'s spec of the structure the window is fitted with.
    pub(super) fn window_spec(&self) -> ModelSpec {
        let s = &self.set;
        ModelSpec {
            kind: Kind::WienerHammerstein,
            na: s.poles,
            nb: s.poles + 1,
            nk: s.nk,
            degree: s.degree,
            law: Estimator::SimulationError,
            epochs: s.iterations,
            output_margin: self.output_margin,
            ..Default::default()
        }
    }

    /// Fit the block structure on the window (from scratch: a refit keeps nothing of the
    /// last fit), drop it, and bring the filters' pasts to the current record's end.
    fn fit(&mut self) -> Result<()> {
        let s = &self.set;
        let spec = self.window_spec();
        // A record too short for the structure's lags is left out of the fit.
        let least = 2 * (s.poles + s.nk + 2);
        let records: Vec<Record> = self
            .window
            .iter()
            .filter(|(t, _, _)| t.len() >= least)
            .map(|(t, u, y)| Record {
                source: "the online window".into(),
                t: t.clone(),
                inputs: vec![u.clone()],
                outputs: vec![y.clone()],
            })
            .collect();
        if records.is_empty() {
            return Err(Error::Argument(format!(
                "the wiener-hammerstein structure's window of {} samples has no record of {least} samples or more to fit on",
                self.kept
            )));
        }
        let names = |s: &str| vec![s.to_string()];
        let m = rhonn_sysid::fit(&spec, &records, &names("u"), &names("y"))?;
        let p = Params::from_stored(s.degree, &m.weights[0])?;
        let (mu, su) = m.input_norm[0];
        let (my, sy) = m.output_norm[0];
        let bounds = crate::models::wiener_hammerstein::bounds(&m);
        let cov = information(&p, s.nk, &records, [mu, su, my, sy]);
        let mut fitted = Fitted {
            p,
            norm: [mu, su, my, sy],
            bounds,
            cov,
            nk: s.nk,
        };
        // The current record's pasts, replayed without learning.
        let (_, u, y) = self.window.pop().unwrap_or_default();
        let mut st = BlockState {
            seen: self.state.seen,
            t_last: self.state.t_last,
            ..fresh(&fitted)
        };
        for (&uk, &yk) in u.iter().zip(&y) {
            step(&mut fitted, &mut st, uk, yk, true, false)?;
        }
        self.state = st;
        self.fitted = Some(fitted);
        self.window = Vec::new();
        self.kept = 0;
        Ok(())
    }

    /// Weights as stored: one vector of [`Self::stored_len`] values (zeros before the
    /// fit: a deviation of 0 marks a structure never fitted).
    fn weights(&self) -> Vec<Vec<f64>> {
        let mut v = vec![0.0; self.stored_len()];
        if let Some(f) = &self.fitted {
            let p = &f.p;
            v[..HEADER]
                .copy_from_slice(&[f.norm[0], f.norm[1], f.norm[2], f.norm[3], f.bounds.0, f.bounds.1]);
            let orders = [p.g1.a.len(), p.g1.b.len(), p.g2.a.len(), p.g2.b.len()];
            for (k, o) in orders.iter().enumerate() {
                v[HEADER + k] = *o as f64;
            }
            let mut at = HEADER + 4;
            let n = self.set.poles;
            for (part, room) in [
                (&p.g1.b, n + 1),
                (&p.g1.a, n),
                (&p.c, self.set.degree),
                (&p.g2.b, n + 1),
                (&p.g2.a, n),
            ] {
                v[at..at + part.len()].copy_from_slice(part);
                at += room;
            }
            v[at..].copy_from_slice(&[p.bias, p.x_range.0, p.x_range.1]);
        }
        vec![v]
    }

    /// The structure stored in `w` (one vector of [`Self::stored_len`]), or why not.
    fn read(&self, w: &[Vec<f64>]) -> Result<Fitted> {
        let v = match w {
            [v] if v.len() == self.stored_len() => v,
            _ => {
                return Err(invalid(
                    "weights",
                    format!("{} vectors", w.len()),
                    format!("one vector of {} numbers", self.stored_len()),
                ))
            }
        };
        let [mu, su, my, sy, lo, hi] = [v[0], v[1], v[2], v[3], v[4], v[5]];
        if !(su > 0.0 && sy > 0.0 && lo < hi) {
            return Err(invalid(
                "weights[0][0..6]",
                format!("deviations {su} and {sy}, bounds [{lo}, {hi}]"),
                "positive deviations and low < high bounds (a structure never fitted: its stream ended before `block.window` samples)",
            ));
        }
        let orders: Vec<usize> = v[HEADER..HEADER + 4]
            .iter()
            .map(|o| o.max(0.0) as usize)
            .collect();
        let n = self.set.poles;
        let rooms = [n, n + 1, n, n + 1];
        if orders
            .iter()
            .zip(v[HEADER..HEADER + 4].iter())
            .any(|(o, r)| *o as f64 != *r)
            || orders.iter().zip(rooms).any(|(o, r)| *o > r)
        {
            return Err(invalid(
                "weights[0][6..10]",
                format!("{:?}", &v[HEADER..HEADER + 4]),
                format!(
                    "the filters' orders [n1, m1, n2, m2]: whole numbers within [{n}, {}, {n}, {}]",
                    n + 1,
                    n + 1
                ),
            ));
        }
        let [n1, m1, n2, m2] = [orders[0], orders[1], orders[2], orders[3]];
        let mut stored: Vec<f64> = v[HEADER..HEADER + 4].to_vec();
        let mut at = HEADER + 4;
        for (len, room) in [
            (m1, n + 1),
            (n1, n),
            (self.set.degree, self.set.degree),
            (m2, n + 1),
            (n2, n),
        ] {
            stored.extend_from_slice(&v[at..at + len]);
            at += room;
        }
        stored.extend_from_slice(&v[at..]);
        let p = Params::from_stored(self.set.degree, &stored)?;
        let d = self.set.degree + 1;
        Ok(Fitted {
            p,
            norm: [mu, su, my, sy],
            bounds: (lo, hi),
            // A stored model carries no covariance: learning on from it starts at a
            // small one (its coefficients are a fit's, not a guess).
            cov: DMatrix::identity(d, d) * 1e-3,
            nk: self.set.nk,
        })
    }
}

/// The filters' pasts at rest, sized for `f`.
fn fresh(f: &Fitted) -> BlockState {
    BlockState {
        u: vec![0.0; f.nk + f.p.g1.b.len().max(1)],
        x: vec![0.0; f.p.g1.a.len()],
        h: vec![vec![0.0; f.p.c.len()]; f.p.g2.b.len()],
        w: vec![0.0; f.p.g2.a.len()],
        s: vec![vec![0.0; f.p.c.len()]; f.p.g2.a.len()],
        ..BlockState::default()
    }
}

/// One sample through the fitted structure: the estimate of `y` (output units) before it
/// is seen; then G2's past takes the measured `y` (`measured`) or the estimate, and with
/// `learn` recursive least squares moves the polynomial and the offset.
fn step(f: &mut Fitted, st: &mut BlockState, u: f64, y: f64, measured: bool, learn: bool) -> Result<f64> {
    let [mu, su, my, sy] = f.norm;
    let p = &f.p;
    push(&mut st.u, (u - mu) / su);
    let mut x = 0.0;
    for (i, b) in p.g1.b.iter().enumerate() {
        x += b * st.u[f.nk + i];
    }
    for (i, a) in p.g1.a.iter().enumerate() {
        x -= a * st.x[i];
    }
    push(&mut st.x, x);
    if !st.h.is_empty() {
        st.h.rotate_right(1);
        hermite(x.clamp(p.x_range.0, p.x_range.1), &mut st.h[0]);
    }
    let mut w = 0.0;
    for (i, b) in p.g2.b.iter().enumerate() {
        w += b * dot(&p.c, &st.h[i]);
    }
    for (i, a) in p.g2.a.iter().enumerate() {
        w -= a * st.w[i];
    }
    let w = w.clamp(f.bounds.0 - p.bias, f.bounds.1 - p.bias);
    let estimate = (w + p.bias) * sy + my;
    if !estimate.is_finite() {
        return Err(Error::Argument(
            "the wiener-hammerstein structure's estimate is not finite".into(),
        ));
    }
    let yn = (y - my) / sy;
    let phi = regressor(p, &st.h, &mut st.s);
    if learn && yn.is_finite() {
        rls(f, &phi, yn);
    }
    let wk = if measured && yn.is_finite() {
        yn - f.p.bias
    } else {
        w
    };
    push(&mut st.w, wk);
    Ok(estimate)
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a * b).sum()
}

/// The output-error regressor of (c, bias) at the newest basis `h[0]`: each basis
/// function through G2 (`B2 / A2`, its past in `s`), and 1; `s` takes the new values.
/// With the filters fixed the free-run output is `c . (G2 h) + bias`, linear in (c, bias).
fn regressor(p: &Params, h: &[Vec<f64>], s: &mut [Vec<f64>]) -> DVector<f64> {
    let d = p.c.len();
    let mut phi = DVector::zeros(d + 1);
    for (i, b) in p.g2.b.iter().enumerate() {
        for j in 0..d {
            phi[j] += b * h[i][j];
        }
    }
    for (i, a) in p.g2.a.iter().enumerate() {
        for j in 0..d {
            phi[j] -= a * s[i][j];
        }
    }
    if !s.is_empty() {
        s.rotate_right(1);
        s[0].copy_from_slice(&phi.as_slice()[..d]);
    }
    phi[d] = 1.0;
    phi
}

/// One step of recursive least squares on (c, bias) towards the measured `yn`
/// (normalised), on the output-error regressor: the criterion the fit minimised.
fn rls(f: &mut Fitted, phi: &DVector<f64>, yn: f64) {
    let d = f.p.c.len();
    let e = yn - dot(&f.p.c, &phi.as_slice()[..d]) - f.p.bias;
    let pphi = &f.cov * phi;
    let denom = 1.0 + phi.dot(&pphi);
    if !(denom.is_finite() && e.is_finite()) {
        return;
    }
    let k = &pphi / denom;
    for j in 0..d {
        f.p.c[j] += k[j] * e;
    }
    f.p.bias += k[d] * e;
    f.cov -= &k * pphi.transpose();
    // Kept symmetric: over millions of samples rounding would part its halves.
    let sym = (&f.cov + f.cov.transpose()) * 0.5;
    f.cov = sym;
}

/// The inverse of the window's information matrix of (c, bias) (their output-error
/// regressors' sum of outer products, with a ridge of 1e-9 of its mean diagonal): the
/// covariance that makes the recursion continue least squares over the window.
fn information(p: &Params, nk: usize, records: &[Record], norm: [f64; 4]) -> DMatrix<f64> {
    let d = p.c.len();
    let mut a = DMatrix::<f64>::zeros(d + 1, d + 1);
    for r in records {
        let un: Vec<f64> = r.inputs[0].iter().map(|v| (v - norm[0]) / norm[1]).collect();
        let basis = p.basis(&un, nk);
        let mut h: Vec<Vec<f64>> = vec![vec![0.0; d]; p.g2.b.len()];
        let mut s: Vec<Vec<f64>> = vec![vec![0.0; d]; p.g2.a.len()];
        for b in basis.chunks(d.max(1)) {
            if !h.is_empty() {
                h.rotate_right(1);
                h[0].copy_from_slice(&b[..d]);
            }
            let phi = regressor(p, &h, &mut s);
            a.ger(1.0, &phi, &phi, 1.0);
        }
    }
    let ridge = 1e-9 * (a.trace() / (d + 1) as f64).max(1e-12);
    for i in 0..=d {
        a[(i, i)] += ridge;
    }
    a.cholesky()
        .map(|c| c.inverse())
        .unwrap_or_else(|| DMatrix::identity(d + 1, d + 1) * 1e-3)
}

impl OnlineEngine for BlockOnline {
    fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<&[f64]> {
        BlockOnline::update(self, t, u, y)
    }
    fn estimate(&self) -> &[f64] {
        &self.out
    }
    fn freeze(&mut self, frozen: bool) {
        self.frozen = frozen;
    }
    fn set_free_run(&mut self, free: bool) {
        self.free_run = free;
    }
    fn reset(&mut self) {
        let kept = match &self.fitted {
            Some(f) => fresh(f),
            None => BlockState::default(),
        };
        self.state = BlockState {
            y_last: self.state.y_last,
            ..kept
        };
        if self.collecting() && self.window.last().is_some_and(|w| !w.0.is_empty()) {
            self.window.push((Vec::new(), Vec::new(), Vec::new()));
        }
    }
    fn set_estimate(&mut self, y: &[f64]) {
        match &self.fitted {
            Some(f) => {
                let yn = (y[0] - f.norm[2]) / f.norm[3];
                if let Some(w) = self.state.w.first_mut() {
                    *w = yn - f.p.bias;
                }
            }
            None => self.state.y_last = y[0],
        }
        self.out[0] = y[0];
    }
    fn weights(&self) -> Vec<Vec<f64>> {
        BlockOnline::weights(self)
    }
    fn set_weights(&mut self, w: &[Vec<f64>]) {
        if let Ok(f) = self.read(w) {
            self.state = BlockState {
                seen: self.state.seen,
                t_last: self.state.t_last,
                ..fresh(&f)
            };
            self.fitted = Some(f);
            self.window = Vec::new();
        }
    }
    fn term_names(&self, _outputs: &[String], _inputs: &[String]) -> Vec<String> {
        let n = self.set.poles;
        let mut v: Vec<String> = [
            "u mean",
            "u deviation",
            "y mean",
            "y deviation",
            "y low",
            "y high",
            "n1",
            "m1",
            "n2",
            "m2",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        for (key, count) in [
            ("b1", n + 1),
            ("a1", n),
            ("c", self.set.degree),
            ("b2", n + 1),
            ("a2", n),
        ] {
            v.extend((1..=count).map(|i| format!("{key}[{i}]")));
        }
        v.extend(["bias", "x low", "x high"].iter().map(|s| s.to_string()));
        v
    }
    fn n_terms(&self) -> usize {
        self.stored_len()
    }
    fn scaling(&self) -> &Scaling {
        &self.scaling
    }
    fn set_y_bounds(&mut self, b: Vec<[f64; 2]>) {
        self.scaling.y_bounds = Some(b);
    }
    fn snapshot(&self) -> Box<dyn EngineState> {
        Box::new(self.state.clone())
    }
    fn restore(&mut self, s: &dyn EngineState) {
        if let Some(s) = s.as_any().downcast_ref::<BlockState>() {
            self.state.clone_from(s);
        }
    }
    fn check_weights(&self, w: &[Vec<f64>]) -> Result<()> {
        self.read(w).map(|_| ())
    }
    fn unfinished(&self) -> Option<String> {
        self.fitted.is_none().then(|| {
            format!(
                "the wiener-hammerstein structure is fitted once its window of {} samples (`block.window`) is full, and it has learned {}: give a window of at most {} samples, or more data",
                self.set.window,
                crate::metrics::count(self.kept, "sample"),
                self.kept.max(20)
            )
        })
    }
    fn box_clone(&self) -> Box<dyn OnlineEngine> {
        Box::new(self.clone())
    }
}

#[cfg(test)]
#[path = "block_online_tests.rs"]
mod tests;
