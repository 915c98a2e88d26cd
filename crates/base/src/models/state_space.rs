//! `kind = "state-space"`: a discrete-time nonlinear state-space model (PNLSS, Paduart et
//! al., "Identification of nonlinear systems using polynomial nonlinear state space
//! models", Automatica 46(4) 2010), for any number of inputs and outputs:
//!
//! ```text
//! x(k+1) = A x(k) + B u(k) + E z(k)        z(k) = every monomial of degree 2..=degree
//! y(k)   = C x(k) + D u(k) + F z(k) + bias        of s(x(k)) and s(u(k))
//! ```
//!
//! with `s` the identity (`activation = "identity"`: PNLSS's polynomial terms) or tanh
//! (the default: the RHONN's bounded high-order terms of sigmoids of the states and
//! inputs). `na` is the number of states per output (`na * outputs` states), `nk` the
//! input delay (0: `D` is trained; 1: `D = 0`), `degree` the terms' highest degree (1: a
//! linear state-space model), `nonlinear_in = "states"` keeps the inputs out of the terms
//! (they then enter through B and D alone). Units inside are normalised (inputs and outputs by their
//! training mean and standard deviation; the states are whitened on the training data by
//! the training). Each state is held within its training range widened by
//! `output_margin`, as the outputs are.
//!
//! **The initial state** (the encoder): with `settle = 0` a record starts at rest (x = 0,
//! the state of constant mean inputs); otherwise x(0) is the least-squares fit of the
//! first `settle` measured outputs through the linear part (`C A^k x(0)` against the
//! outputs less the response from rest), and prediction starts at sample `settle`.
//!
//! This file is the structure and its prediction; its training is `sysid::state_space`.
//!
//! `model.json` stores the parameters in `weights[0]`: `[nx, ni, no, has_d]`, then A, B,
//! C (row-major), D (when `has_d`), the bias, E, F, and each state's held range (lows, then
//! highs).

use super::{int_in, Activation, Estimator, Model, ModelSpec, NonlinearIn};
use crate::data::Record;
use crate::error::{invalid, Result};
use crate::law::dot;
use nalgebra::{DMatrix, DVector};

/// Highest degree of the terms.
pub const MAX_DEGREE: usize = 5;
/// Most states.
pub const MAX_STATES: usize = 32;
/// Most terms a model may have (its `J^T J` grows with the square of its parameters).
pub const MAX_TERMS: usize = 2000;
/// A simulated state or output beyond this (normalised units) marks an unstable model.
pub const DIVERGED: f64 = 1e6;

/// The terms z of `v = [s(x), s(u)]`: every monomial of degree 2..=`degree`, as
/// `(variable, exponent)` factors.
#[derive(Debug, Clone, PartialEq)]
pub struct Monomials {
    factors: Vec<Vec<(usize, i32)>>,
    tanh: bool,
}

impl Monomials {
    /// The terms of `nx` states and `ni` inputs of `spec` (its `degree`, `activation` and
    /// `nonlinear_in`).
    pub fn of(spec: &ModelSpec, nx: usize, ni: usize) -> Self {
        let only_states = spec.nonlinear_in == NonlinearIn::States;
        Monomials::new(
            nx + ni,
            if only_states { ni } else { 0 },
            spec.degree,
            spec.activation,
        )
    }

    /// How many terms [`Monomials::of`] makes, counted without making them (saturating):
    /// every monomial of degree 2..=`degree` of its variables, `C(m + d, d) - 1 - m`.
    pub fn count(spec: &ModelSpec, nx: usize, ni: usize) -> usize {
        let m = if spec.nonlinear_in == NonlinearIn::States {
            nx
        } else {
            nx + ni
        } as u128;
        if spec.degree < 2 {
            return 0;
        }
        let mut c: u128 = 1;
        for k in 1..=spec.degree as u128 {
            c = c * (m + k) / k;
            if c > u64::MAX as u128 {
                return usize::MAX;
            }
        }
        usize::try_from(c - 1 - m).unwrap_or(usize::MAX)
    }

    /// [`Monomials::count`] within [`MAX_TERMS`], or the error naming `model.degree`.
    pub fn check_count(spec: &ModelSpec, nx: usize, ni: usize) -> Result<()> {
        let n = Monomials::count(spec, nx, ni);
        if n > MAX_TERMS {
            return Err(invalid(
                "model.degree",
                spec.degree,
                format!(
                    "at most {MAX_TERMS} terms in all: {nx} states and {ni} inputs make {n} of degree 2 to                      {}; lower `degree` or `na`, or set `nonlinear_in = \"states\"`",
                    spec.degree
                ),
            ));
        }
        Ok(())
    }

    /// The terms of `n_vars` variables (states then inputs), the last `n_inputs_out` of
    /// which stay out of them.
    pub fn new(n_vars: usize, n_inputs_out: usize, degree: usize, activation: Activation) -> Self {
        let mut factors = Vec::new();
        if degree >= 2 {
            rhonn_core::terms::for_each_monomial(degree, degree, &mut vec![0; n_vars], |e| {
                if e.iter().sum::<usize>() >= 2 && e[n_vars - n_inputs_out..].iter().all(|d| *d == 0) {
                    factors.push(
                        e.iter()
                            .enumerate()
                            .filter(|(_, d)| **d > 0)
                            .map(|(j, d)| (j, *d as i32))
                            .collect(),
                    );
                }
            });
        }
        Monomials {
            factors,
            tanh: activation == Activation::Tanh,
        }
    }

    /// Number of terms.
    pub fn len(&self) -> usize {
        self.factors.len()
    }

    /// Whether there are none (a linear model).
    pub fn is_empty(&self) -> bool {
        self.factors.is_empty()
    }

    /// `z` of `v` and its Jacobian in the first `nx` variables, `jz` (terms x nx,
    /// row-major); `v` is overwritten by its activation.
    pub fn eval_with_jacobian(&self, v: &mut [f64], nx: usize, z: &mut [f64], jz: &mut [f64]) {
        // The activation's slope at each state: 1 for the identity, 1 - tanh^2 for tanh.
        let mut slope = [1.0; MAX_STATES];
        if self.tanh {
            v.iter_mut().for_each(|x| *x = x.tanh());
            for i in 0..nx {
                slope[i] = 1.0 - v[i] * v[i];
            }
        }
        jz.iter_mut().for_each(|d| *d = 0.0);
        for (t, f) in self.factors.iter().enumerate() {
            z[t] = f.iter().map(|&(j, d)| v[j].powi(d)).product();
            for (a, &(i, di)) in f.iter().enumerate() {
                if i >= nx {
                    continue;
                }
                let others: f64 = f
                    .iter()
                    .enumerate()
                    .filter(|(b, _)| *b != a)
                    .map(|(_, &(j, d))| v[j].powi(d))
                    .product();
                jz[t * nx + i] = f64::from(di) * v[i].powi(di - 1) * others * slope[i];
            }
        }
    }

    /// `z` of `v` (`v` is overwritten by its activation).
    fn eval(&self, v: &mut [f64], z: &mut [f64]) {
        if self.tanh {
            v.iter_mut().for_each(|x| *x = x.tanh());
        }
        for (zk, f) in z.iter_mut().zip(&self.factors) {
            *zk = f.iter().map(|&(j, d)| v[j].powi(d)).product();
        }
    }
}

/// The parameters of one model (normalised units).
#[derive(Debug, Clone, PartialEq)]
pub struct Params {
    /// States.
    pub nx: usize,
    /// Inputs.
    pub ni: usize,
    /// Outputs.
    pub no: usize,
    /// Whether `D` is trained (input delay 0).
    pub has_d: bool,
    /// A (nx x nx), row-major.
    pub a: Vec<f64>,
    /// B (nx x ni).
    pub b: Vec<f64>,
    /// C (no x nx).
    pub c: Vec<f64>,
    /// D (no x ni; empty unless `has_d`).
    pub d: Vec<f64>,
    /// The outputs' offsets.
    pub bias: Vec<f64>,
    /// E (nx x terms).
    pub e: Vec<f64>,
    /// F (no x terms).
    pub f: Vec<f64>,
    /// Each state's held range: lows.
    pub x_lo: Vec<f64>,
    /// Each state's held range: highs.
    pub x_hi: Vec<f64>,
}

impl Params {
    /// Whether every eigenvalue of A lies strictly inside the unit circle: the rest point
    /// at the mean input is stable (the terms, of degree 2 and more, vanish to first order
    /// there). False when A is not finite or its eigenvalues are not found.
    pub fn is_stable(&self) -> bool {
        if !self.a.iter().all(|v| v.is_finite()) {
            return false;
        }
        let a = DMatrix::from_row_slice(self.nx, self.nx, &self.a);
        nalgebra::linalg::Schur::try_new(a, f64::EPSILON, 10_000)
            .is_some_and(|s| s.complex_eigenvalues().iter().all(|z| z.norm() < 1.0))
    }

    /// A linear model of these sizes with every parameter zero, states unbounded.
    pub fn zeros(nx: usize, ni: usize, no: usize, has_d: bool, nt: usize) -> Params {
        Params {
            nx,
            ni,
            no,
            has_d,
            a: vec![0.0; nx * nx],
            b: vec![0.0; nx * ni],
            c: vec![0.0; no * nx],
            d: vec![0.0; if has_d { no * ni } else { 0 }],
            bias: vec![0.0; no],
            e: vec![0.0; nx * nt],
            f: vec![0.0; no * nt],
            x_lo: vec![f64::NEG_INFINITY; nx],
            x_hi: vec![f64::INFINITY; nx],
        }
    }

    fn parts(&self) -> [&Vec<f64>; 7] {
        [&self.a, &self.b, &self.c, &self.d, &self.bias, &self.e, &self.f]
    }

    /// The parameters training moves: A, B, C, D, bias, E, F.
    pub fn free(&self) -> Vec<f64> {
        self.parts().into_iter().flatten().copied().collect()
    }

    /// Set the parameters training moves (the order of [`Params::free`]).
    pub fn set_free(&mut self, th: &[f64]) {
        let mut o = 0;
        for part in [
            &mut self.a,
            &mut self.b,
            &mut self.c,
            &mut self.d,
            &mut self.bias,
            &mut self.e,
            &mut self.f,
        ] {
            let l = part.len();
            part.copy_from_slice(&th[o..o + l]);
            o += l;
        }
    }

    /// The stored layout (see the module's docs).
    pub fn to_stored(&self) -> Vec<f64> {
        let mut v = vec![
            self.nx as f64,
            self.ni as f64,
            self.no as f64,
            f64::from(u8::from(self.has_d)),
        ];
        v.extend(self.free());
        v.extend(&self.x_lo);
        v.extend(&self.x_hi);
        v
    }

    /// Read `weights[0]` of a model of `ni` inputs, `no` outputs and terms of `spec`;
    /// errors name the field.
    pub fn from_stored(spec: &ModelSpec, ni: usize, no: usize, w: &[f64]) -> Result<Params> {
        let head = |i: usize, hi: usize, what: &str| -> Result<usize> {
            match w.get(i) {
                Some(&v) if v.is_finite() && v.fract() == 0.0 && (0.0..=hi as f64).contains(&v) => {
                    Ok(v as usize)
                }
                other => Err(invalid(
                    format!("model.weights[0][{i}]"),
                    format!("{other:?}"),
                    format!("{what}: a whole number in [0, {hi}]"),
                )),
            }
        };
        let nx = head(0, MAX_STATES, "the number of states")?;
        let (wi, wo, has_d) = (
            head(1, 1000, "inputs")?,
            head(2, 1000, "outputs")?,
            head(3, 1, "has_d")?,
        );
        if nx == 0 || wi != ni || wo != no {
            return Err(invalid(
                "model.weights[0][0..3]",
                format!("[{nx}, {wi}, {wo}]"),
                format!("[states >= 1, {ni} inputs, {no} outputs] (the model's columns)"),
            ));
        }
        Monomials::check_count(spec, nx, ni)?;
        let nt = Monomials::of(spec, nx, ni).len();
        let mut p = Params::zeros(nx, ni, no, has_d == 1, nt);
        let nfree = p.free().len();
        let need = 4 + nfree + 2 * nx;
        if w.len() != need || w[4..4 + nfree].iter().any(|v| !v.is_finite()) {
            return Err(invalid(
                "model.weights[0]",
                format!("{} numbers", w.len()),
                format!("{need} numbers: the sizes, A, B, C, D, bias, E, F (finite), the states' ranges"),
            ));
        }
        p.set_free(&w[4..4 + nfree]);
        p.x_lo.copy_from_slice(&w[4 + nfree..4 + nfree + nx]);
        p.x_hi.copy_from_slice(&w[4 + nfree + nx..]);
        if p.x_lo.iter().zip(&p.x_hi).any(|(lo, hi)| !(lo <= hi)) {
            return Err(invalid(
                "model.weights[0] (state ranges)",
                "low > high",
                "low <= high for every state",
            ));
        }
        Ok(p)
    }

    /// Run from `x0` over inputs `un` (per input, normalised) and write the outputs
    /// (per output) into `y`; the state at every sample into `xs` when given (nx values a
    /// sample). False when a value passes [`DIVERGED`] or is not finite.
    pub fn simulate(
        &self,
        mono: &Monomials,
        un: &[&[f64]],
        x0: &[f64],
        y: &mut [Vec<f64>],
        mut xs: Option<&mut Vec<f64>>,
    ) -> bool {
        let (nx, ni, no) = (self.nx, self.ni, self.no);
        let n = un.first().map_or(0, |u| u.len());
        let nt = mono.len();
        let mut x = x0.to_vec();
        let mut next = vec![0.0; nx];
        let mut v = vec![0.0; nx + ni];
        let mut act = vec![0.0; nx + ni];
        let mut z = vec![0.0; nt];
        for yj in y.iter_mut() {
            yj.clear();
        }
        if let Some(xs) = xs.as_deref_mut() {
            xs.clear();
        }
        for k in 0..n {
            v[..nx].copy_from_slice(&x);
            for q in 0..ni {
                v[nx + q] = un[q][k];
            }
            if let Some(xs) = xs.as_deref_mut() {
                xs.extend(&x);
            }
            act.copy_from_slice(&v);
            mono.eval(&mut act, &mut z);
            for j in 0..no {
                let mut s = self.bias[j]
                    + dot(&self.c[j * nx..(j + 1) * nx], &x)
                    + dot(&self.f[j * nt..(j + 1) * nt], &z);
                if self.has_d {
                    s += dot(&self.d[j * ni..(j + 1) * ni], &v[nx..]);
                }
                if !(s.abs() < DIVERGED) {
                    return false;
                }
                y[j].push(s);
            }
            for i in 0..nx {
                let s = dot(&self.a[i * nx..(i + 1) * nx], &x)
                    + dot(&self.b[i * ni..(i + 1) * ni], &v[nx..])
                    + dot(&self.e[i * nt..(i + 1) * nt], &z);
                if !(s.abs() < DIVERGED) {
                    return false;
                }
                next[i] = s.max(self.x_lo[i]).min(self.x_hi[i]);
            }
            std::mem::swap(&mut x, &mut next);
        }
        true
    }

    /// The initial state fitted to the first `settle` outputs `yn` (see the module's
    /// docs): the response from rest, then least squares through `C A^k`. Zero when
    /// `settle` is 0; None when the response diverges.
    pub fn initial_state(
        &self,
        mono: &Monomials,
        un: &[&[f64]],
        yn: &[&[f64]],
        settle: usize,
    ) -> Option<Vec<f64>> {
        let (nx, no) = (self.nx, self.no);
        let zero = vec![0.0; nx];
        let settle = settle.min(un.first().map_or(0, |u| u.len()));
        if settle == 0 {
            return Some(zero);
        }
        let window: Vec<&[f64]> = un.iter().map(|u| &u[..settle]).collect();
        let mut rest = vec![Vec::new(); no];
        if !self.simulate(mono, &window, &zero, &mut rest, None) {
            return None;
        }
        let a = DMatrix::from_row_slice(nx, nx, &self.a);
        let c = DMatrix::from_row_slice(no, nx, &self.c);
        let mut obs = DMatrix::<f64>::zeros(settle * no, nx);
        let mut target = DVector::<f64>::zeros(settle * no);
        let mut cak = c.clone();
        for k in 0..settle {
            for j in 0..no {
                obs.row_mut(k * no + j).copy_from(&cak.row(j));
                target[k * no + j] = yn[j][k] - rest[j][k];
            }
            cak = &cak * &a;
        }
        let mut oto = obs.transpose() * &obs;
        let ridge = 1e-6 * (0..nx).map(|i| oto[(i, i)]).sum::<f64>() / nx as f64 + 1e-12;
        for i in 0..nx {
            oto[(i, i)] += ridge;
        }
        let x0 = oto.cholesky()?.solve(&(obs.transpose() * target));
        Some(
            x0.iter()
                .enumerate()
                .map(|(i, v)| v.max(self.x_lo[i]).min(self.x_hi[i]))
                .collect(),
        )
    }
}

/// The monomials of model `m`.
pub fn monomials(m: &Model, nx: usize) -> Monomials {
    Monomials::of(&m.spec, nx, m.ni())
}

/// Normalised inputs and outputs of a record (per column).
pub fn normalised(m: &Model, r: &Record) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let norm = |cols: &[Vec<f64>], ms: &[(f64, f64)]| -> Vec<Vec<f64>> {
        cols.iter()
            .zip(ms)
            .map(|(c, (mu, s))| c.iter().map(|v| (v - mu) / s).collect())
            .collect()
    };
    (norm(&r.inputs, &m.input_norm), norm(&r.outputs, &m.output_norm))
}

/// Free run of a record from its fitted initial state (normalised, per output, held
/// within the outputs' widened range); the first `settle` samples are the measured ones.
/// None when the model diverges.
pub fn free_run(
    p: &Params,
    mono: &Monomials,
    settle: usize,
    un: &[&[f64]],
    yn: &[&[f64]],
) -> Option<Vec<Vec<f64>>> {
    let x0 = p.initial_state(mono, un, yn, settle)?;
    let mut y = vec![Vec::new(); p.no];
    p.simulate(mono, un, &x0, &mut y, None).then_some(y)
}

/// Predict (see [`Model::predict`]): a free run, or `K` steps ahead from the state fitted to
/// the `settle` measured samples before each start (a window per prediction).
pub fn predict(m: &Model, r: &Record, steps_ahead: Option<usize>) -> Result<(Vec<Vec<f64>>, usize)> {
    let p = Params::from_stored(&m.spec, m.ni(), m.no(), &m.weights[0])?;
    let mono = monomials(m, p.nx);
    let (un, yn) = normalised(m, r);
    let settle = m.spec.settle.min(r.len());
    let bounds: Vec<(f64, f64)> = (0..m.no()).map(|j| bounds(m, j)).collect();
    let cols = |v: &[Vec<f64>]| -> Vec<Vec<f64>> { v.to_vec() };
    let unr: Vec<&[f64]> = un.iter().map(|v| &v[..]).collect();
    let ynr: Vec<&[f64]> = yn.iter().map(|v| &v[..]).collect();
    let diverged = || {
        invalid(
            "model",
            "state-space",
            "a model whose free run stays finite on this record",
        )
    };
    let mut pred = match steps_ahead {
        None => free_run(&p, &mono, settle, &unr, &ynr).ok_or_else(diverged)?,
        Some(kk) => {
            let kk = kk.max(1);
            let mut out = cols(&yn);
            let mut y = vec![Vec::new(); p.no];
            for end in settle + kk - 1..r.len() {
                let start = end + 1 - kk;
                let lo = start - settle;
                let uw: Vec<&[f64]> = un.iter().map(|v| &v[lo..=end]).collect();
                let yw: Vec<&[f64]> = yn.iter().map(|v| &v[lo..=end]).collect();
                let x0 = p.initial_state(&mono, &uw, &yw, settle).ok_or_else(diverged)?;
                if !p.simulate(&mono, &uw, &x0, &mut y, None) {
                    return Err(diverged());
                }
                for j in 0..p.no {
                    out[j][end] = y[j][end - lo];
                }
            }
            out
        }
    };
    for (j, col) in pred.iter_mut().enumerate() {
        let (my, sy) = m.output_norm[j];
        for (k, v) in col.iter_mut().enumerate() {
            *v = if k < settle {
                yn[j][k]
            } else {
                v.max(bounds[j].0).min(bounds[j].1)
            } * sy
                + my;
        }
    }
    Ok((pred, settle + steps_ahead.map_or(0, |k| k.max(1) - 1)))
}

/// Output `j`'s held range in normalised units.
pub fn bounds(m: &Model, j: usize) -> (f64, f64) {
    let (lo, hi) = m.output_range[j];
    let (my, sy) = m.output_norm[j];
    let w = (hi - lo) * m.spec.output_margin;
    ((lo - w - my) / sy, (hi + w - my) / sy)
}

/// `kind = "state-space"`.
pub struct StateSpace;

impl super::kinds::Structure for StateSpace {
    fn polynomial_terms(&self, spec: &ModelSpec) -> bool {
        spec.activation == Activation::Identity && spec.degree >= 2
    }

    fn with_article(&self, _kind: super::Kind) -> &'static str {
        "a state-space"
    }

    fn check_spec(&self, spec: &ModelSpec) -> Result<()> {
        int_in("degree", spec.degree, 1, MAX_DEGREE)?;
        int_in("na", spec.na, 1, 8)?;
        int_in("nk", spec.nk, 0, 1)?;
        int_in("settle", spec.settle, 0, 1000)?;
        if matches!(spec.law, Estimator::Rls | Estimator::Gradient) {
            return Err(invalid(
                "model.law",
                spec.law.name(),
                "simulation-error (the free run over whole records) or multi-step (over subsections \
                 of `horizon` samples, each from its fitted initial state)",
            ));
        }
        Ok(())
    }

    fn max_lag(&self, spec: &ModelSpec) -> usize {
        spec.settle
    }

    fn predict(&self, m: &Model, r: &Record, steps_ahead: Option<usize>) -> Result<(Vec<Vec<f64>>, usize)> {
        predict(m, r, steps_ahead)
    }

    fn validate(&self, m: &Model) -> Result<()> {
        if m.weights.len() != 1 {
            return Err(invalid(
                "model.weights",
                format!("{} vectors", m.weights.len()),
                "one vector of parameters",
            ));
        }
        let p = Params::from_stored(&m.spec, m.ni(), m.no(), &m.weights[0])?;
        if p.nx > MAX_STATES {
            return Err(invalid(
                "model.weights[0][0]",
                p.nx,
                format!("at most {MAX_STATES} states"),
            ));
        }
        Ok(())
    }

    fn n_params(&self, m: &Model) -> usize {
        m.weights.first().map_or(0, |w| w.len())
    }

    fn data_warnings_apply(&self) -> bool {
        false
    }
}
