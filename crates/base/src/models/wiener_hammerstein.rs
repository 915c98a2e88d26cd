//! `kind = "wiener-hammerstein"`: a block structure for one input and one output, a linear
//! filter, a static polynomial, a second linear filter:
//!
//! ```text
//! x(k) = G1(q) u(k - nk)      G1 = B1(q^-1) / A1(q^-1)
//! v(k) = c_1 h_1(x) + ... + c_D h_D(x)    (Hermite polynomials; x held within its training range)
//! y(k) = G2(q) v(k) + bias    G2 = B2(q^-1) / A2(q^-1)
//! ```
//!
//! The structure of electronic circuits and of sensors behind an actuator (the
//! Wiener-Hammerstein benchmark is one); with G2 = 1 it is a Wiener model, with G1 = 1 a
//! Hammerstein one. Units inside are normalised (input and output by their training mean
//! and standard deviation).
//!
//! This file is the structure and its prediction; its training is
//! `sysid::wiener_hammerstein`.
//!
//! `model.json` stores the parameters in `weights[0]`: the orders `[n1, m1, n2, m2]` (poles
//! and numerator coefficients of G1 and G2, as numbers), then B1, A1 (without its leading
//! 1), c_1..c_D, B2, A2, the bias and the held range of x.

use super::{Model, ModelSpec};
use crate::data::Record;
use crate::error::{invalid, Result};

/// Highest polynomial degree (the Wiener-Hammerstein benchmark's diode-like saturation
/// still gained from 15 to 40 on its training record's last fifth: docs/results.md).
pub const MAX_DEGREE: usize = 40;

/// The polynomial's basis at `x`: `He_n(x) / sqrt(n!)` for n = 1..=h.len(), the
/// probabilists' Hermite polynomials, orthonormal for a standard normal x (G1 is scaled
/// so that x has unit deviation): the least squares stay well conditioned at degrees
/// where powers of x are not.
pub fn hermite(x: f64, h: &mut [f64]) {
    // He_0 = 1, He_1 = x, He_(n+1) = x He_n - n He_(n-1); carried normalised.
    let (mut prev, mut cur) = (1.0, x);
    for (n, slot) in h.iter_mut().enumerate() {
        *slot = cur;
        let n1 = (n + 1) as f64;
        let next = (x * cur - n1.sqrt() * prev) / (n1 + 1.0).sqrt();
        prev = cur;
        cur = next;
    }
}

/// Samples whose basis [`hermite_rows`] computes together.
const LANES: usize = 64;

/// [`hermite`] of each of `xs`, `d` values a sample, sample after sample, into `out`
/// (`xs.len() * d` values). The same operations on the same values as [`hermite`], so the
/// same bits; the recursion's steps run across a block of samples at a time, so its
/// divisions, each waiting on the last within one sample, pipeline across samples (the
/// basis was most of the Wiener-Hammerstein training's time).
pub fn hermite_rows(xs: &[f64], d: usize, out: &mut [f64]) {
    if d == 0 {
        return;
    }
    for (xc, oc) in xs.chunks(LANES).zip(out.chunks_mut(LANES * d)) {
        let n = xc.len();
        let mut prev = [1.0f64; LANES];
        let mut cur = [0.0f64; LANES];
        cur[..n].copy_from_slice(xc);
        for j in 0..d {
            let n1 = (j + 1) as f64;
            let (s, r) = (n1.sqrt(), (n1 + 1.0).sqrt());
            for k in 0..n {
                oc[k * d + j] = cur[k];
                let next = (xc[k] * cur[k] - s * prev[k]) / r;
                prev[k] = cur[k];
                cur[k] = next;
            }
        }
    }
}

/// A simulated value beyond this (normalised units) marks an unstable parameter set.
pub const DIVERGED: f64 = 1e6;

/// A linear filter `x(k) = sum_i b_i u(k - i) - sum_i a_i x(k - 1 - i)` started at rest.
#[derive(Debug, Clone, PartialEq)]
pub struct Filter {
    /// Numerator coefficients.
    pub b: Vec<f64>,
    /// Denominator coefficients (without the leading 1).
    pub a: Vec<f64>,
}

impl Filter {
    /// [`Filter::run`] over each of `d` signals at once: `u` holds `d` values a sample,
    /// sample after sample, and so does `out`. Each signal gets the same operations in the
    /// same order as `run` gives it, so the same bits; the signals' recursions are
    /// independent, so they run side by side rather than each waiting on its own last
    /// sample (the polynomial's basis through G2 for every split of the poles).
    pub fn run_columns(&self, u: &[f64], d: usize, delay: usize, out: &mut Vec<f64>) {
        out.clear();
        if d == 0 {
            return;
        }
        let n = u.len() / d;
        out.resize(n * d, 0.0);
        let mut v = vec![0.0; d];
        for k in 0..n {
            v.fill(0.0);
            for (i, bi) in self.b.iter().enumerate() {
                if k >= delay + i {
                    for (ve, ue) in v.iter_mut().zip(&u[(k - delay - i) * d..][..d]) {
                        *ve += bi * ue;
                    }
                }
            }
            for (i, ai) in self.a.iter().enumerate() {
                if k > i {
                    for (ve, oe) in v.iter_mut().zip(&out[(k - 1 - i) * d..][..d]) {
                        *ve -= ai * oe;
                    }
                }
            }
            out[k * d..(k + 1) * d].copy_from_slice(&v);
        }
    }

    /// Run over `u` delayed by `delay` samples into `out`.
    pub fn run(&self, u: &[f64], delay: usize, out: &mut Vec<f64>) {
        out.clear();
        for k in 0..u.len() {
            let past_in = if k >= delay { &u[..=k - delay] } else { &[] };
            let v = self.at(past_in, out);
            out.push(v);
        }
    }

    /// The filter's next output from the inputs `past_in` (its last the newest that reaches
    /// it) and the outputs `past_out` so far: `sum_i b_i past_in[-1 - i] - sum_i a_i
    /// past_out[-1 - i]` over the taps that reach a sample, newest first.
    fn at(&self, past_in: &[f64], past_out: &[f64]) -> f64 {
        let mut v = 0.0;
        for (bi, ui) in self.b.iter().zip(past_in.iter().rev()) {
            v += bi * ui;
        }
        for (ai, xi) in self.a.iter().zip(past_out.iter().rev()) {
            v -= ai * xi;
        }
        v
    }

    /// Whether every pole lies strictly inside the unit circle: the Schur-Cohn step-down
    /// test on `1 + a_1 z^-1 + ... + a_n z^-n` (each reflection coefficient below 1 in
    /// magnitude). Written out: no numerical crate gives the test, and finding the roots
    /// for it would cost an eigenvalue problem at every training step.
    pub fn is_stable(&self) -> bool {
        let mut a: Vec<f64> = self.a.clone();
        while let Some(&k) = a.last() {
            if !(k.abs() < 1.0) {
                return false;
            }
            let n = a.len();
            let d = 1.0 - k * k;
            // a_i <- (a_i - k a_(n-i)) / (1 - k^2), i = 1..n-1 (a_0 = 1 throughout).
            let next: Vec<f64> = (0..n - 1).map(|i| (a[i] - k * a[n - 2 - i]) / d).collect();
            a = next;
        }
        true
    }
}

/// The parameters of one model (normalised units).
#[derive(Debug, Clone, PartialEq)]
pub struct Params {
    /// The first filter.
    pub g1: Filter,
    /// The polynomial's coefficients (Hermite basis).
    pub c: Vec<f64>,
    /// The second filter.
    pub g2: Filter,
    /// The output's offset.
    pub bias: f64,
    /// The range G1's output is held in.
    pub x_range: (f64, f64),
}

impl Params {
    /// The stored layout: orders, B1, A1, c, B2, A2, bias, x range.
    pub fn to_stored(&self) -> Vec<f64> {
        let mut v = vec![
            self.g1.a.len() as f64,
            self.g1.b.len() as f64,
            self.g2.a.len() as f64,
            self.g2.b.len() as f64,
        ];
        v.extend(self.free());
        v.extend([self.x_range.0, self.x_range.1]);
        v
    }

    /// The parameters training moves (all but the orders and the x range).
    pub fn free(&self) -> Vec<f64> {
        let mut v = self.g1.b.clone();
        v.extend(&self.g1.a);
        v.extend(&self.c);
        v.extend(&self.g2.b);
        v.extend(&self.g2.a);
        v.push(self.bias);
        v
    }

    /// Set the parameters training moves (the order of [`Params::free`]).
    pub fn set_free(&mut self, th: &[f64]) {
        let mut o = 0;
        for part in [
            &mut self.g1.b,
            &mut self.g1.a,
            &mut self.c,
            &mut self.g2.b,
            &mut self.g2.a,
        ] {
            let l = part.len();
            part.copy_from_slice(&th[o..o + l]);
            o += l;
        }
        self.bias = th[o];
    }

    /// Read `weights[0]` of a model of polynomial degree `degree`; errors name the field.
    pub fn from_stored(degree: usize, w: &[f64]) -> Result<Params> {
        let bad = |why: &str| invalid("model.weights", format!("{} numbers", w.len()), why.to_string());
        if w.len() < 4 {
            return Err(bad("the orders [n1, m1, n2, m2] first"));
        }
        let mut orders = [0usize; 4];
        for (o, &v) in orders.iter_mut().zip(w) {
            if !(v.is_finite() && (0.0..=50.0).contains(&v) && v.fract() == 0.0) {
                return Err(invalid(
                    "model.weights[0..4]",
                    v,
                    "the filters' orders: whole numbers in [0, 50]",
                ));
            }
            *o = v as usize;
        }
        let [n1, m1, n2, m2] = orders;
        let need = 4 + n1 + m1 + degree + n2 + m2 + 3;
        if w.len() != need || w.iter().any(|v| !v.is_finite()) {
            return Err(invalid(
                "model.weights",
                format!("{} numbers", w.len()),
                format!("{need} finite numbers: the orders, B1, A1, c_1..c_{degree}, B2, A2, bias, x range"),
            ));
        }
        let mut p = Params {
            g1: Filter {
                b: vec![0.0; m1],
                a: vec![0.0; n1],
            },
            c: vec![0.0; degree],
            g2: Filter {
                b: vec![0.0; m2],
                a: vec![0.0; n2],
            },
            bias: 0.0,
            x_range: (w[need - 2], w[need - 1]),
        };
        p.set_free(&w[4..need - 2]);
        if p.x_range.0 > p.x_range.1 {
            return Err(invalid(
                "model.weights (x range)",
                format!("[{}, {}]", p.x_range.0, p.x_range.1),
                "low <= high",
            ));
        }
        Ok(p)
    }

    /// G1 and the polynomial: the input to G2, from the normalised input alone. Bit for
    /// bit `self.combine(&self.basis(un, nk))`, a block of samples' basis at a time.
    pub fn inner(&self, un: &[f64], nk: usize) -> Vec<f64> {
        let x = self.held_x(un, nk);
        let d = self.c.len();
        if d == 0 {
            return Vec::new();
        }
        let mut h = vec![0.0; LANES * d];
        let mut v = Vec::with_capacity(x.len());
        for xc in x.chunks(LANES) {
            let rows = &mut h[..xc.len() * d];
            hermite_rows(xc, d, rows);
            v.extend(
                rows.chunks(d)
                    .map(|h| self.c.iter().zip(h).map(|(c, h)| c * h).sum::<f64>()),
            );
        }
        v
    }

    /// G1's output, held in the x range, through the basis: `c.len()` values a sample.
    pub fn basis(&self, un: &[f64], nk: usize) -> Vec<f64> {
        let x = self.held_x(un, nk);
        let d = self.c.len();
        let mut out = vec![0.0; x.len() * d];
        hermite_rows(&x, d, &mut out);
        out
    }

    /// G1's output held in the x range.
    fn held_x(&self, un: &[f64], nk: usize) -> Vec<f64> {
        let mut x = Vec::new();
        self.g1.run(un, nk, &mut x);
        for v in &mut x {
            *v = v.max(self.x_range.0).min(self.x_range.1);
        }
        x
    }

    /// The polynomial of a [`Params::basis`]: the input to G2.
    pub fn combine(&self, basis: &[f64]) -> Vec<f64> {
        basis
            .chunks(self.c.len().max(1))
            .map(|h| self.c.iter().zip(h).map(|(c, h)| c * h).sum())
            .collect()
    }

    /// G2 run over `v` with its past measured over the first `measured` samples (the value
    /// is then `yn[k] - bias`); each output held within `bounds`.
    pub fn outer(&self, v: &[f64], yn: &[f64], measured: usize, bounds: (f64, f64)) -> Vec<f64> {
        let (lo, hi) = (bounds.0 - self.bias, bounds.1 - self.bias);
        let mut w: Vec<f64> = Vec::with_capacity(v.len());
        for k in 0..v.len() {
            let val = if k < measured {
                yn[k] - self.bias
            } else {
                self.g2.at(&v[..=k], &w).max(lo).min(hi)
            };
            w.push(val);
        }
        w
    }
}

/// Number of stored parameters of `model` (its weights' own orders).
pub fn n_params(m: &Model) -> usize {
    m.weights
        .first()
        .and_then(|w| Params::from_stored(m.spec.degree, w).ok())
        .map(|p| p.to_stored().len())
        .unwrap_or(4)
}

/// Normalised input and output of a record.
pub fn normalised(m: &Model, r: &Record) -> (Vec<f64>, Vec<f64>) {
    let (mu, su) = m.input_norm[0];
    let (my, sy) = m.output_norm[0];
    (
        r.inputs[0].iter().map(|v| (v - mu) / su).collect(),
        r.outputs[0].iter().map(|v| (v - my) / sy).collect(),
    )
}

/// The output's held range in normalised units.
pub fn bounds(m: &Model) -> (f64, f64) {
    let (lo, hi) = m.output_range[0];
    let (my, sy) = m.output_norm[0];
    let w = (hi - lo) * m.spec.output_margin;
    ((lo - w - my) / sy, (hi + w - my) / sy)
}

/// Free-run prediction (normalised) of one record: the first `settle` outputs measured.
pub fn free_run(p: &Params, spec: &ModelSpec, un: &[f64], yn: &[f64], bounds: (f64, f64)) -> Vec<f64> {
    free_run_from(p, spec, &p.inner(un, spec.nk), yn, bounds)
}

/// [`free_run`] from G2's input `v`.
pub fn free_run_from(p: &Params, spec: &ModelSpec, v: &[f64], yn: &[f64], bounds: (f64, f64)) -> Vec<f64> {
    let settle = spec.settle.min(yn.len());
    let mut w = p.outer(v, yn, settle, bounds);
    for x in &mut w {
        *x += p.bias;
    }
    w
}

/// Predict (see [`Model::predict`]).
pub fn predict(m: &Model, r: &Record, steps_ahead: Option<usize>) -> Result<(Vec<Vec<f64>>, usize)> {
    let p = Params::from_stored(m.spec.degree, &m.weights[0])?;
    let (un, yn) = normalised(m, r);
    let b = bounds(m);
    let first = m.spec.settle.min(r.len());
    let pred = match steps_ahead {
        None => free_run(&p, &m.spec, &un, &yn, b),
        Some(kk) => {
            let kk = kk.max(1);
            let v = p.inner(&un, m.spec.nk);
            let mut out = yn.clone();
            let first = first + kk - 1;
            // G2's past measured up to each start, then K samples run on: the window
            // needs only G2's order of history.
            let hist = p.g2.a.len().max(p.g2.b.len());
            for end in first..yn.len() {
                let start = end + 1 - kk;
                let lo = start.saturating_sub(hist);
                let w = p.outer(&v[lo..=end], &yn[lo..=end], start - lo, b);
                out[end] = w[end - lo] + p.bias;
            }
            out
        }
    };
    let (my, sy) = m.output_norm[0];
    let out = vec![pred.iter().map(|v| v * sy + my).collect()];
    Ok((out, first + steps_ahead.map_or(0, |k| k.max(1) - 1)))
}

/// `kind = "wiener-hammerstein"`.
pub struct WienerHammerstein;

impl super::kinds::Structure for WienerHammerstein {
    fn with_article(&self, _kind: super::Kind) -> &'static str {
        "a Wiener-Hammerstein"
    }

    fn check_spec(&self, spec: &ModelSpec) -> Result<()> {
        use super::{int_in, Estimator};
        int_in("degree", spec.degree, 1, MAX_DEGREE)?;
        int_in("settle", spec.settle, 1, 1000)?;
        if matches!(
            spec.law,
            Estimator::Rls | Estimator::Gradient | Estimator::MultiStep
        ) {
            return Err(invalid(
                "model.law",
                spec.law.name(),
                "simulation-error (a `wiener-hammerstein` model is always trained on its free-run error)",
            ));
        }
        Ok(())
    }

    fn predict(&self, m: &Model, r: &Record, steps_ahead: Option<usize>) -> Result<(Vec<Vec<f64>>, usize)> {
        predict(m, r, steps_ahead)
    }

    fn validate(&self, m: &Model) -> Result<()> {
        if m.ni() != 1 || m.no() != 1 || m.weights.len() != 1 {
            return Err(invalid(
                "model.weights",
                format!(
                    "{} inputs, {} outputs, {} vectors",
                    m.ni(),
                    m.no(),
                    m.weights.len()
                ),
                "one input, one output and one vector of parameters",
            ));
        }
        Params::from_stored(m.spec.degree, &m.weights[0]).map(|_| ())
    }

    fn n_params(&self, m: &Model) -> usize {
        n_params(m)
    }
}
