//! `kind = "cascade"`: a continuous-time RHONN with hidden states, for processes that
//! store something in a chain of reservoirs (tanks, thermal masses) of which only the
//! last is measured.
//!
//! Neuron `i` (of `neurons`, the last one measured) is a limited integrator on
//! `[0, xmax_i]` driven by power-law activations `s_i = x_i^alpha_i` (Torricelli's
//! square-root outflow is `alpha = 1/2`; the exponent is learned unless
//! `free_exponents = false`):
//!
//! ```text
//! dx_1/dt = sum_q b_q u_q           - k_1 s_1
//! dx_i/dt = g_i s_(i-1) + o_i v_(i-1) - k_i s_i           (i > 1)
//! y       = x_n + c
//! ```
//!
//! `v_(i-1)` is the overflow of neuron `i-1`: while it is held at its upper bound, the
//! inflow it cannot store (its unclamped derivative), of which the share `o_i` reaches
//! the next neuron (the rest is lost). The bounds are the solver's limited integrators:
//! each reaching and leaving of a bound is located, not stepped across. Units inside
//! are normalised: levels in standard deviations of the output, time in samples,
//! inputs divided by their standard deviation (not centred: an inflow is proportional
//! to the input).
//!
//! This file is the structure (parameters, simulation, prediction); its training is
//! `sysid::cascade`. Training minimises the free-run simulation error over every record by
//! Levenberg-Marquardt from `starts` seeded random starts (run in parallel; the best
//! final cost wins), the hidden initial states of each record estimated with the
//! weights. A free run estimates the hidden initial states from the first `settle`
//! measured samples (a grid search, then a golden-section refinement) and runs on the
//! inputs alone; `K` steps ahead settles them on the `settle` samples up to each k and
//! runs K samples on.

use super::{Model, ModelSpec};
use crate::data::Record;
use crate::error::{invalid, Error, Result};
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rhonn_ode::{Dopri5, Options, System};

/// Range of a learned exponent.
/// Range of a learned exponent. Below 0.2 a neuron that drains faster than it fills
/// settles at a level so close to 0 that its outflow's slope there (`k alpha
/// x^(alpha - 1)`) makes the system too stiff for an explicit solver.
pub const EXPONENT_RANGE: (f64, f64) = (0.2, 1.5);
/// Solver steps allowed per sample: a simulation that needs more is too stiff to be
/// the answer, and fails (a training start then avoids it).
const MAX_STEPS_PER_SAMPLE: u64 = 200;
/// Exponent when they are not learned (Torricelli).
pub const FIXED_EXPONENT: f64 = 0.5;
/// Relative and absolute tolerance of the simulations (normalised units): tight, so
/// that the finite-difference Jacobian sees the parameters, not the step-size control.
const RTOL: f64 = 1e-8;
const ATOL: f64 = 1e-10;

/// The physical parameters (normalised units), as `model.json` stores them in
/// `weights[0]`: `b` (one per input), `k`, `alpha`, `g`, `o`, `xmax`, `c`.
#[derive(Debug, Clone, PartialEq)]
pub struct Params {
    /// Input gains, one per input.
    pub b: Vec<f64>,
    /// Outflow rates, one per neuron.
    pub k: Vec<f64>,
    /// Activation exponents, one per neuron.
    pub alpha: Vec<f64>,
    /// Gains of each neuron's inflow from the one before (all but the first).
    pub g: Vec<f64>,
    /// Shares of the overflow passed on (all but the first).
    pub o: Vec<f64>,
    /// Upper bounds of the levels, one per neuron.
    pub xmax: Vec<f64>,
    /// The output's offset.
    pub c: f64,
}

/// Number of stored parameters for `n` neurons and `ni` inputs.
pub fn n_params(n: usize, ni: usize) -> usize {
    ni + 3 * n + 2 * (n - 1) + 1
}

/// The logistic function, `1 / (1 + e^-v)`.
pub fn logistic(v: f64) -> f64 {
    1.0 / (1.0 + (-v).exp())
}

fn logit(p: f64) -> f64 {
    let p = p.clamp(1e-9, 1.0 - 1e-9);
    (p / (1.0 - p)).ln()
}

impl Params {
    /// Read the stored vector.
    pub fn from_stored(n: usize, ni: usize, w: &[f64]) -> Params {
        let mut it = w.iter().copied();
        let mut take = |m: usize| {
            (0..m)
                .map(|_| it.next().expect("length checked"))
                .collect::<Vec<_>>()
        };
        let b = take(ni);
        let k = take(n);
        let alpha = take(n);
        let g = take(n - 1);
        let o = take(n - 1);
        let xmax = take(n);
        let c = take(1)[0];
        Params {
            b,
            k,
            alpha,
            g,
            o,
            xmax,
            c,
        }
    }

    /// The stored vector (`model.json`'s order).
    pub fn stored(&self) -> Vec<f64> {
        let mut w = Vec::new();
        for v in [&self.b, &self.k, &self.alpha, &self.g, &self.o, &self.xmax] {
            w.extend_from_slice(v);
        }
        w.push(self.c);
        w
    }

    /// Check a stored vector: rates, shares and bounds > 0 (shares >= 0), exponents in
    /// their range, everything finite.
    pub fn check(&self) -> Result<()> {
        let bad = |what: &str, v: f64, allowed: &str| {
            Err(invalid(format!("model.weights (cascade {what})"), v, allowed))
        };
        for &v in self.b.iter().chain(&self.k).chain(&self.g).chain(&self.xmax) {
            if !(v.is_finite() && v > 0.0) {
                return bad("rate or bound", v, "a finite number > 0");
            }
        }
        for &v in &self.o {
            if !(v.is_finite() && v >= 0.0) {
                return bad("overflow share", v, "a finite number >= 0");
            }
        }
        for &a in &self.alpha {
            if !(a.is_finite() && a >= EXPONENT_RANGE.0 && a <= EXPONENT_RANGE.1) {
                return bad("exponent", a, "a number in [0.2, 1.5]");
            }
        }
        if !self.c.is_finite() {
            return bad("output offset", self.c, "a finite number");
        }
        Ok(())
    }
}

/// The unconstrained coordinates Levenberg-Marquardt works in: logarithms of the rates,
/// shares and bounds, the exponents through a logistic onto their range (absent when
/// fixed), the offset as it is; then, per training record, the logits of the hidden
/// initial states as fractions of their bounds.
#[derive(Debug, Clone, Copy)]
pub struct Coords {
    /// Neurons.
    pub n: usize,
    /// Inputs.
    pub ni: usize,
    /// Whether the exponents are learned.
    pub free_exp: bool,
}

impl Coords {
    /// Number of model coordinates (without the hidden initial states).
    pub fn n_model(&self) -> usize {
        n_params(self.n, self.ni) - if self.free_exp { 0 } else { self.n }
    }

    /// The parameters at coordinates `th` (its first [`Coords::n_model`] values).
    pub fn params(&self, th: &[f64]) -> Params {
        let (n, ni) = (self.n, self.ni);
        let mut it = th.iter().copied();
        let mut take = |m: usize| (0..m).map(|_| it.next().expect("length")).collect::<Vec<_>>();
        let exp = |v: Vec<f64>| v.into_iter().map(f64::exp).collect::<Vec<_>>();
        let b = exp(take(ni));
        let k = exp(take(n));
        let alpha = if self.free_exp {
            let (lo, hi) = EXPONENT_RANGE;
            take(n)
                .into_iter()
                .map(|v| lo + (hi - lo) * logistic(v))
                .collect()
        } else {
            vec![FIXED_EXPONENT; n]
        };
        let g = exp(take(n - 1));
        let o = exp(take(n - 1));
        let xmax = exp(take(n));
        let c = take(1)[0];
        Params {
            b,
            k,
            alpha,
            g,
            o,
            xmax,
            c,
        }
    }

    /// The coordinates of `p`.
    pub fn coords(&self, p: &Params) -> Vec<f64> {
        let ln = |v: &[f64]| v.iter().map(|x| x.ln()).collect::<Vec<_>>();
        let mut th = ln(&p.b);
        th.extend(ln(&p.k));
        if self.free_exp {
            let (lo, hi) = EXPONENT_RANGE;
            th.extend(p.alpha.iter().map(|a| logit((a - lo) / (hi - lo))));
        }
        th.extend(ln(&p.g));
        th.extend(ln(&p.o));
        th.extend(ln(&p.xmax));
        th.push(p.c);
        th
    }
}

/// Level below which an activation is linear (output standard deviations).
pub const LINEAR_BELOW: f64 = 1e-3;

/// The activation `x^alpha`, linear below [`LINEAR_BELOW`] (through 0 and continuous
/// there). With `alpha < 1` the power's slope grows without bound as the level empties:
/// a neuron that drains faster than it fills then settles just above 0, where an
/// explicit solver would need ever smaller steps. The linear piece bounds the slope at
/// `LINEAR_BELOW^(alpha - 1)` (at most 251 for alpha = 0.2). The power is
/// `exp(alpha ln x)`: most of a cascade's training time is this call, and glibc's `exp`
/// and `log` together take less than its `pow` (the hair dryer's default fit 5 % less CPU);
/// the two agree to a few units in the last place for these levels and exponents (unit
/// test), far below the solver's tolerances.
#[inline]
pub fn activation(x: f64, alpha: f64) -> f64 {
    if x >= LINEAR_BELOW {
        (alpha * x.ln()).exp()
    } else if x > 0.0 {
        x * LINEAR_BELOW.powf(alpha - 1.0)
    } else {
        0.0
    }
}

/// The chain's derivative (per sample) at levels `x` with the first neuron's inflow
/// `inflow`; a neuron at its upper bound passes what it cannot store (its unclamped
/// derivative) on as overflow.
pub fn derivative(p: &Params, inflow: f64, x: &[f64], dx: &mut [f64]) {
    derivative_by(p, inflow, x, dx, |i, xi| activation(xi, p.alpha[i]));
}

/// [`derivative`] with neuron `i`'s activation at level `xi` given by `act(i, xi)`.
#[inline]
fn derivative_by(p: &Params, inflow: f64, x: &[f64], dx: &mut [f64], mut act: impl FnMut(usize, f64) -> f64) {
    let (mut s_prev, mut over_prev) = (0.0, 0.0);
    for i in 0..x.len() {
        let s = act(i, x[i]);
        let d = if i == 0 {
            inflow - p.k[0] * s
        } else {
            p.g[i - 1] * s_prev + p.o[i - 1] * over_prev - p.k[i] * s
        };
        dx[i] = d;
        over_prev = if x[i] >= p.xmax[i] { d.max(0.0) } else { 0.0 };
        s_prev = s;
    }
}

impl Params {
    /// The inflow of the first neuron for normalised inputs `u`.
    pub fn inflow(&self, u: &[f64]) -> f64 {
        self.b.iter().zip(u).map(|(b, u)| b * u).sum()
    }

    /// Neuron `i`'s upper bound.
    pub fn level_bound(&self, i: usize) -> f64 {
        self.xmax[i]
    }

    /// The normalised output of levels `x`.
    pub fn output(&self, x: &[f64]) -> f64 {
        x[x.len() - 1] + self.c
    }

    /// The last neuron's level for the normalised output `y`, within its range.
    pub fn measured_level(&self, y: f64) -> f64 {
        let n = self.k.len();
        (y - self.c).clamp(0.0, self.xmax[n - 1])
    }

    /// Levels of a chain in balance (each neuron's inflow equals its outflow) whose last
    /// level is `x_last`: how a hidden state starts when nothing else is known.
    pub fn balanced_levels(&self, x_last: f64, x: &mut [f64]) {
        let n = self.k.len();
        x[n - 1] = x_last.clamp(0.0, self.xmax[n - 1]);
        for i in (0..n - 1).rev() {
            // g_i s_i = k_(i+1) s_(i+1), s = x^alpha above the linear piece.
            let s = self.k[i + 1] * activation(x[i + 1], self.alpha[i + 1]) / self.g[i];
            x[i] = s.max(0.0).powf(1.0 / self.alpha[i]).clamp(0.0, self.xmax[i]);
        }
    }

    /// Advance levels `x` by `h` samples with the inflow held: classical RK4 over
    /// `substeps`, every stage's levels held in their ranges and no motion beyond a bound
    /// (limited integrators, as the solver's, but stepped, not located). `k` holds 4
    /// stages and a stage state (`5 n` values).
    pub fn step(&self, inflow: f64, x: &mut [f64], h: f64, substeps: usize, k: &mut [f64]) {
        let n = x.len();
        let dt = h / substeps.max(1) as f64;
        let (stages, probe) = k.split_at_mut(4 * n);
        for _ in 0..substeps.max(1) {
            for st in 0..4 {
                let a = [0.0, 0.5, 0.5, 1.0][st] * dt;
                for i in 0..n {
                    let prev = if st == 0 { 0.0 } else { stages[(st - 1) * n + i] };
                    probe[i] = (x[i] + a * prev).clamp(0.0, self.xmax[i]);
                }
                let (_, rest) = stages.split_at_mut(st * n);
                let d = &mut rest[..n];
                derivative(self, inflow, probe, d);
                for i in 0..n {
                    let (v, hi) = (probe[i], self.xmax[i]);
                    if (v <= 0.0 && d[i] < 0.0) || (v >= hi && d[i] > 0.0) {
                        d[i] = 0.0;
                    }
                }
            }
            for i in 0..n {
                let s = stages[i] + 2.0 * stages[n + i] + 2.0 * stages[2 * n + i] + stages[3 * n + i];
                x[i] = (x[i] + dt / 6.0 * s).clamp(0.0, self.xmax[i]);
            }
        }
    }
}

/// The chain as an ODE system on the solver, inputs held over each sample (time in
/// samples: the breakpoints are the integers).
pub struct Chain<'a> {
    p: &'a Params,
    u: &'a [Vec<f64>],
    inflow: f64,
    /// Per neuron, the last level's bits and its activation. `x^alpha` is most of a
    /// cascade's training time (glibc's `pow`, 59 % of the CPU), and a level often comes
    /// back unchanged: the whole state at a sample's restart (the last stage's), a level
    /// held at its bound between stages. Reusing the value is exact (the same function of
    /// the same bits) and saves about a fifth of the calls.
    activations: std::cell::RefCell<Vec<(u64, f64)>>,
}

impl<'a> Chain<'a> {
    /// The chain of `p` driven by the normalised inputs `u`.
    pub fn new(p: &'a Params, u: &'a [Vec<f64>]) -> Self {
        // NaN's bits with activation(NaN) = 0: an entry that only a NaN level matches.
        let empty = (f64::NAN.to_bits(), activation(f64::NAN, 1.0));
        Chain {
            p,
            u,
            inflow: 0.0,
            activations: std::cell::RefCell::new(vec![empty; p.k.len()]),
        }
    }
}

impl System for Chain<'_> {
    type State = Vec<f64>;

    fn dim(&self) -> usize {
        self.p.k.len()
    }

    fn rhs(&self, _t: f64, x: &[f64], dx: &mut [f64]) {
        let mut cache = self.activations.borrow_mut();
        derivative_by(self.p, self.inflow, x, dx, |i, xi| {
            let c = &mut cache[i];
            if c.0 != xi.to_bits() {
                *c = (xi.to_bits(), activation(xi, self.p.alpha[i]));
            }
            c.1
        });
    }

    fn update_modes(&mut self, t: f64, _x: &[f64]) {
        let len = self.u.first().map_or(1, |u| u.len());
        let seg = ((t + 1e-9).floor().max(0.0) as usize).min(len - 1);
        self.inflow = self.p.b.iter().zip(self.u).map(|(b, u)| b * u[seg]).sum();
    }

    fn next_breakpoint(&self, t: f64) -> f64 {
        (t + 1e-9).floor() + 1.0
    }

    fn bounds(&self, i: usize) -> (f64, f64) {
        (0.0, self.p.xmax[i])
    }
}

/// A failed simulation: the time (in samples), the levels there, the solver's error.
type SimFailure = (f64, Vec<f64>, rhonn_ode::Error);

/// Simulate `len` samples from the hidden initial states `hidden` (neurons 1..n-1) and
/// the measured first output `y0` (normalised); the normalised output per sample into
/// `out`. A solver failure is returned with the time (in samples) and the state.
pub fn simulate(
    p: &Params,
    u: &[Vec<f64>],
    hidden: &[f64],
    y0: f64,
    len: usize,
    out: &mut Vec<f64>,
) -> std::result::Result<(), Box<SimFailure>> {
    let n = p.k.len();
    let mut x0: Vec<f64> = hidden.to_vec();
    x0.push(y0 - p.c);
    for (x, xm) in x0.iter_mut().zip(&p.xmax) {
        *x = x.clamp(0.0, *xm);
    }
    out.clear();
    out.push(x0[n - 1] + p.c);
    let sys = Chain::new(p, u);
    let opts = Options {
        max_steps: MAX_STEPS_PER_SAMPLE * len as u64 + 1000,
        ..Options::uniform(n, RTOL, ATOL)
    };
    let mut solver = Dopri5::new(sys, 0.0, x0.clone(), opts).map_err(|e| Box::new((0.0, x0, e)))?;
    for k in 1..len {
        solver
            .solve_to(k as f64, |_, _| {})
            .map_err(|e| Box::new((solver.t(), solver.state().to_vec(), e)))?;
        out.push(solver.state()[n - 1] + p.c);
    }
    Ok(())
}

fn minimize_golden(f: &dyn Fn(f64) -> f64, mut a: f64, mut b: f64, iters: usize) -> f64 {
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - r * (b - a), a + r * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..iters {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - r * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + r * (b - a);
            fd = f(d);
        }
    }
    0.5 * (a + b)
}

/// The hidden initial states that best explain the first `settle` samples of `y`:
/// each hidden neuron in turn (two sweeps when there are several) by a grid of 101
/// levels over its range, then a golden-section refinement within one grid cell.
pub fn settle_hidden(p: &Params, u: &[Vec<f64>], y: &[f64], settle: usize) -> Vec<f64> {
    let n = p.k.len();
    let m = settle.min(y.len()).max(2);
    let mut hidden: Vec<f64> = p.xmax[..n - 1].iter().map(|x| 0.5 * x).collect();
    let buf = std::cell::RefCell::new(Vec::new());
    let cost = |h: &[f64]| -> f64 {
        let mut out = buf.borrow_mut();
        match simulate(p, u, h, y[0], m, &mut out) {
            Ok(()) => out.iter().zip(y).map(|(a, b)| (a - b) * (a - b)).sum(),
            Err(_) => f64::INFINITY,
        }
    };
    let sweeps = if n > 2 { 2 } else { 1 };
    for _ in 0..sweeps {
        for i in 0..n - 1 {
            let xm = p.xmax[i];
            let grid = 100;
            let mut best = (f64::INFINITY, 0.0);
            for q in 0..=grid {
                let v = xm * q as f64 / grid as f64;
                hidden[i] = v;
                let c = cost(&hidden);
                if c < best.0 {
                    best = (c, v);
                }
            }
            let cell = xm / grid as f64;
            let (lo, hi) = ((best.1 - cell).max(0.0), (best.1 + cell).min(xm));
            let h0 = hidden.clone();
            let f = |v: f64| {
                let mut h = h0.clone();
                h[i] = v;
                cost(&h)
            };
            let v = minimize_golden(&f, lo, hi, 30);
            hidden[i] = if f(v) <= best.0 { v } else { best.1 };
        }
    }
    hidden
}

/// Normalised inputs (divided by their standard deviation) and outputs of a record.
pub fn normalised(m: &Model, r: &Record) -> (Vec<Vec<f64>>, Vec<f64>) {
    let u = r
        .inputs
        .iter()
        .zip(&m.input_norm)
        .map(|(c, (_, s))| c.iter().map(|v| v / s).collect())
        .collect();
    let (mean, sd) = m.output_norm[0];
    (u, r.outputs[0].iter().map(|v| (v - mean) / sd).collect())
}

/// A solver failure of a cascade's simulation of `r` as an error with the time (the
/// simulation starting at sample `from`) and the levels.
fn solver_error(m: &Model, p: &Params, r: &Record, from: usize, f: SimFailure) -> Error {
    let (t, x, e) = f;
    let (mean, sd) = m.output_norm[0];
    Error::Solver {
        t_s: r.t[from] + t * m.sample_time_s,
        state: format!(
            "{}: cascade levels {:?} (output standard deviations), `{}` = {}; the solver's own times below are in samples",
            r.source,
            x,
            m.outputs[0],
            x.last().map_or(f64::NAN, |v| (v + p.c) * sd + mean)
        ),
        source: Box::new(e),
    }
}

/// Prediction of a cascade model. Free run (`steps_ahead = None`): the hidden states
/// settled on the first `settle` samples, then the inputs only; samples before
/// `settle` hold the measurements. `K` steps ahead: for each sample k, the hidden
/// states settled on the `settle` measured samples ending at k, then the inputs
/// carry the model to k + K (the first `settle - 1 + K` samples hold the
/// measurements).
pub fn predict(m: &Model, r: &Record, steps_ahead: Option<usize>) -> Result<(Vec<Vec<f64>>, usize)> {
    let ni = m.inputs.len();
    let p = Params::from_stored(m.spec.neurons, ni, &m.weights[0]);
    let (u, y) = normalised(m, r);
    let (mean, sd) = m.output_norm[0];
    let n = r.len();
    let s = m.spec.settle.min(n);
    let mut pred = r.outputs[0].clone();
    let mut out = Vec::new();
    let first = match steps_ahead {
        None => {
            let hidden = settle_hidden(&p, &u, &y, s);
            simulate(&p, &u, &hidden, y[0], n, &mut out).map_err(|f| solver_error(m, &p, r, 0, *f))?;
            for k in s..n {
                pred[k] = out[k] * sd + mean;
            }
            s
        }
        Some(kk) => {
            let kk = kk.max(1);
            let first = s - 1 + kk;
            for end in first..n {
                // The window of measurements [w0, w0 + s) ends K samples before `end`.
                let w0 = end + 1 - kk - s;
                let uw: Vec<Vec<f64>> = u.iter().map(|c| c[w0..=end].to_vec()).collect();
                let hidden = settle_hidden(&p, &uw, &y[w0..w0 + s], s);
                simulate(&p, &uw, &hidden, y[w0], s + kk, &mut out)
                    .map_err(|f| solver_error(m, &p, r, w0, *f))?;
                pred[end] = out[s + kk - 1] * sd + mean;
            }
            first
        }
    };
    Ok((vec![pred], first))
}

/// A random start (normalised units; rates per sample): rates in [0.02, 0.3], shares
/// in [0, 1], exponents in [0.2, 1], hidden bounds in [1, 10] output standard
/// deviations, the offset up to one standard deviation below the lowest output and the
/// output's bound up to 0.1 above its highest; hidden initial states anywhere.
pub fn random_start(co: Coords, ymin: f64, ymax: f64, n_rec: usize, rng: &mut ChaCha8Rng) -> Vec<f64> {
    let (n, ni) = (co.n, co.ni);
    let mut u = |a: f64, b: f64| rng.gen_range(a..b);
    let c = ymin - u(0.0, 1.0);
    let mut xmax: Vec<f64> = (0..n - 1).map(|_| u(1.0, 10.0)).collect();
    xmax.push(ymax - c + u(0.0, 0.1));
    let p = Params {
        b: (0..ni).map(|_| u(0.02, 0.3)).collect(),
        k: (0..n).map(|_| u(0.02, 0.3)).collect(),
        alpha: (0..n).map(|_| u(0.2, 1.0)).collect(),
        g: (0..n - 1).map(|_| u(0.02, 0.3)).collect(),
        o: (0..n - 1).map(|_| u(0.0, 1.0)).collect(),
        xmax,
        c,
    };
    let mut th = co.coords(&Params {
        alpha: if co.free_exp {
            p.alpha.clone()
        } else {
            vec![FIXED_EXPONENT; n]
        },
        o: p.o.iter().map(|v| v.max(1e-3)).collect(),
        ..p
    });
    for _ in 0..n_rec * (n - 1) {
        th.push(u(-2.0, 2.0));
    }
    th
}

/// `kind = "cascade"`.
pub struct Cascade;

impl super::kinds::Structure for Cascade {
    fn with_article(&self, _kind: super::Kind) -> &'static str {
        "a cascade"
    }

    fn check_spec(&self, spec: &ModelSpec) -> Result<()> {
        use super::{int_in, Estimator};
        int_in("neurons", spec.neurons, 1, 4)?;
        // 16 times the default at most: each start is a full fit (2,000 took minutes on
        // a 200-sample record, which reads as a hang).
        int_in("starts", spec.starts, 1, 256)?;
        int_in("settle", spec.settle, 2, 1000)?;
        if matches!(
            spec.law,
            Estimator::Rls | Estimator::Gradient | Estimator::MultiStep
        ) {
            return Err(invalid(
                "model.law",
                spec.law.name(),
                "simulation-error (a `cascade` model is always trained on its free-run error)",
            ));
        }
        if !spec.input_filters_s.is_empty() {
            return Err(invalid(
                "model.input_filters_s",
                format!("{:?}", spec.input_filters_s),
                "none for a `cascade` model (its hidden neurons are the filters)",
            ));
        }
        Ok(())
    }

    fn check_outputs(&self, outputs: &[String]) -> Result<()> {
        if outputs.len() != 1 {
            return Err(invalid(
                "outputs",
                outputs.join(","),
                "exactly one output for a `cascade` model (its last neuron)",
            ));
        }
        Ok(())
    }

    fn predict(&self, m: &Model, r: &Record, steps_ahead: Option<usize>) -> Result<(Vec<Vec<f64>>, usize)> {
        predict(m, r, steps_ahead)
    }

    fn validate(&self, m: &Model) -> Result<()> {
        if m.no() != 1 || m.weights.len() != 1 || m.weights[0].len() != m.n_features() {
            return Err(invalid(
                "model.weights",
                format!("{} vectors", m.weights.len()),
                format!("one output and one vector of {} parameters", m.n_features()),
            ));
        }
        Params::from_stored(m.spec.neurons, m.ni(), &m.weights[0]).check()
    }

    fn n_params(&self, m: &Model) -> usize {
        n_params(m.spec.neurons, m.inputs.len())
    }

    fn holds_outputs_in_range(&self) -> bool {
        false
    }
}

#[cfg(test)]
#[path = "cascade_tests.rs"]
mod tests;
