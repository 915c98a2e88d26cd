//! The training of `kind = "state-space"` (its structure and prediction:
//! `models::state_space`), PNLSS's route (Paduart et al., Automatica 46(4) 2010):
//!
//! 1. **The best linear approximation**: per output, an ARX of `na` poles from every input
//!    (least squares), realised in observer canonical form; the outputs' realisations side by
//!    side (`na * outputs` states), its poles on or outside the unit circle reflected
//!    inside. Its A, B, C, D and bias are then refined by Levenberg-Marquardt on the
//!    simulation error (an output-error model).
//! 2. **The states whitened**: the linear model's states over the training records have
//!    their covariance `L L^T`; the similarity `x = L x'` gives states of unit deviation and
//!    no correlation, so that the terms of degree 2 and more are of comparable size and the
//!    least squares well conditioned. Each state's held range is its training range
//!    widened by `output_margin`.
//! 3. **The nonlinear terms**: E and F from zero, every parameter refined together by
//!    Levenberg-Marquardt on the simulation error (`law = "simulation-error"`: the free run of
//!    each record from its fitted initial state; `law = "multi-step"`: subsections of
//!    `horizon` samples, each from the initial state fitted to the `settle` samples before
//!    it, SUBNET's truncated simulation, which keeps a long record's gradients tame). At most
//!    `epochs` iterations per stage; the states' ranges are then taken again. A step that
//!    puts an eigenvalue of A on or outside the unit circle is refused in both stages.
//!
//! Training is deterministic: the same data and spec give the same bits on any number of
//! threads (the Jacobian is exact, from forward sensitivities, its sums taken in a fixed
//! grouping: `state_space_normal.rs`).

use super::lm::lm_normal;
use super::{least_squares, Model, ModelSpec};
use crate::data::Record;
use crate::error::{invalid, Result};
pub(crate) use crate::models::state_space::*;
use crate::models::Estimator;
use nalgebra::{DMatrix, DVector};

/// Normalised (inputs, outputs) of one record, per column.
type Data = (Vec<Vec<f64>>, Vec<Vec<f64>>);

/// Train (see the module's docs): writes `weights[0]`.
pub(crate) fn fit(spec: &ModelSpec, records: &[Record], m: &mut Model) -> Result<()> {
    let (ni, no) = (m.ni(), m.no());
    let nx = spec.na * no;
    if nx > MAX_STATES {
        return Err(invalid(
            "model.na",
            spec.na,
            format!(
                "at most {MAX_STATES} states in all (na * outputs; here {} * {no})",
                spec.na
            ),
        ));
    }
    Monomials::check_count(spec, nx, ni)?;
    let data: Vec<Data> = records.iter().map(|r| normalised(m, r)).collect();
    let windows = training_windows(spec, &data);
    let linear = Monomials::new(nx + ni, 0, 1, spec.activation);
    let mut p = linear_start(spec, &data, ni, no)?;
    refine(&mut p, &linear, spec, &windows);
    whiten(&mut p, &linear, &data, spec);
    let mono = Monomials::of(spec, nx, ni);
    if !mono.is_empty() {
        let mut full = Params::zeros(nx, ni, no, p.has_d, mono.len());
        let mut th = p.free();
        th.extend(vec![0.0; (nx + no) * mono.len()]);
        full.set_free(&th);
        full.x_lo.clone_from(&p.x_lo);
        full.x_hi.clone_from(&p.x_hi);
        p = full;
        refine(&mut p, &mono, spec, &windows);
        held_ranges(&mut p, &mono, &data, spec);
    }
    m.weights = vec![p.to_stored()];
    Ok(())
}

/// What the simulation error is taken over: whole records, or subsections of `settle +
/// horizon` samples stepping by `horizon` (`multi-step`).
fn training_windows(spec: &ModelSpec, data: &[Data]) -> Vec<Data> {
    if spec.law != Estimator::MultiStep {
        return data.to_vec();
    }
    let (s, h) = (spec.settle, spec.horizon.max(1));
    let mut out = Vec::new();
    for (u, y) in data {
        let n = y.first().map_or(0, |c| c.len());
        let mut start = 0;
        while start + s + h <= n {
            let cut = |cols: &[Vec<f64>]| cols.iter().map(|c| c[start..start + s + h].to_vec()).collect();
            out.push((cut(u), cut(y)));
            start += h;
        }
    }
    if out.is_empty() {
        data.to_vec()
    } else {
        out
    }
}

/// Simulation residuals of `p` over `windows` from each one's `settle`; false when it
/// diverges.
fn residuals(p: &Params, mono: &Monomials, settle: usize, windows: &[Data], out: &mut Vec<f64>) -> bool {
    out.clear();
    for (u, y) in windows {
        let ur: Vec<&[f64]> = u.iter().map(|c| &c[..]).collect();
        let yr: Vec<&[f64]> = y.iter().map(|c| &c[..]).collect();
        let Some(sim) = free_run(p, mono, settle, &ur, &yr) else {
            return false;
        };
        let n = yr.first().map_or(0, |c| c.len());
        for k in settle.min(n)..n {
            for (s, m) in sim.iter().zip(&yr) {
                out.push(s[k] - m[k]);
            }
        }
    }
    true
}

/// Levenberg-Marquardt on the simulation error (at most `epochs` iterations).
fn refine(p: &mut Params, mono: &Monomials, spec: &ModelSpec, windows: &[Data]) {
    let mut theta = p.free();
    let base = p.clone();
    let at = |th: &[f64]| {
        let mut q = base.clone();
        q.set_free(th);
        q
    };
    // A step that puts an eigenvalue of A on or outside the unit circle is refused: each
    // state is held within its range, which would hide an unstable A from the residuals
    // (the block structure's G2 did so on the corpus: `sysid::wiener_hammerstein`).
    let stable = |q: Params| q.is_stable().then_some(q);
    lm_normal(
        &mut theta,
        spec.epochs,
        &|th| normal::cost(&stable(at(th))?, mono, spec.settle, windows),
        &|th| normal::normal(&stable(at(th))?, mono, spec.settle, windows),
    );
    p.set_free(&theta);
}

/// Per output an ARX of `na` poles from every input, realised in observer canonical form,
/// side by side.
fn linear_start(spec: &ModelSpec, data: &[Data], ni: usize, no: usize) -> Result<Params> {
    let (n, nk) = (spec.na, spec.nk);
    let has_d = nk == 0;
    let mut p = Params::zeros(n * no, ni, no, has_d, 0);
    let nx = n * no;
    for j in 0..no {
        // Regressors: -y(k-1..=n), each input at lags nk..=n, 1.
        let ncol = n + ni * (n + 1 - nk) + 1;
        let mut rows: Vec<f64> = Vec::new();
        let mut target = Vec::new();
        for (u, y) in data {
            let len = y[j].len();
            for k in n..len {
                rows.extend((1..=n).map(|i| -y[j][k - i]));
                for uq in u {
                    rows.extend((nk..=n).map(|i| uq[k - i]));
                }
                rows.push(1.0);
                target.push(y[j][k]);
            }
        }
        let a = DMatrix::from_row_slice(target.len(), ncol, &rows);
        let th = least_squares(&a, &DVector::from_column_slice(&target)).ok_or_else(|| {
            invalid(
                "data",
                "collinear columns",
                "records whose inputs and outputs vary (a state-space model starts from an ARX)",
            )
        })?;
        // An ARX may have poles on or outside the unit circle: reflected inside, where the
        // refinement, which refuses an unstable A, can start.
        let coef_a: Vec<f64> = super::poles::stabilised(&th.iter().take(n).copied().collect::<Vec<_>>());
        let off = j * n;
        for i in 0..n {
            p.a[(off + i) * nx + off] = -coef_a[i];
            if i + 1 < n {
                p.a[(off + i) * nx + off + i + 1] = 1.0;
            }
        }
        p.c[j * nx + off] = 1.0;
        for q in 0..ni {
            let b = |i: usize| th[n + q * (n + 1 - nk) + (i - nk)];
            let b0 = if has_d { b(0) } else { 0.0 };
            if has_d {
                p.d[j * ni + q] = b0;
            }
            for i in 1..=n {
                p.b[(off + i - 1) * ni + q] = b(i) - coef_a[i - 1] * b0;
            }
        }
        p.bias[j] = th[ncol - 1] / (1.0 + coef_a.iter().sum::<f64>()).abs().max(1e-3);
    }
    Ok(p)
}

/// The states of `p`'s free runs over every record (nx values a sample, all records).
fn training_states(p: &Params, mono: &Monomials, data: &[Data], spec: &ModelSpec) -> Vec<f64> {
    let mut all = Vec::new();
    let mut xs = Vec::new();
    let mut y = vec![Vec::new(); p.no];
    for (u, yn) in data {
        let ur: Vec<&[f64]> = u.iter().map(|c| &c[..]).collect();
        let yr: Vec<&[f64]> = yn.iter().map(|c| &c[..]).collect();
        if let Some(x0) = p.initial_state(mono, &ur, &yr, spec.settle) {
            if p.simulate(mono, &ur, &x0, &mut y, Some(&mut xs)) {
                all.extend(&xs);
            }
        }
    }
    all
}

/// The similarity that whitens the linear model's states (see the module's docs), then
/// the states' held ranges.
fn whiten(p: &mut Params, mono: &Monomials, data: &[Data], spec: &ModelSpec) {
    let nx = p.nx;
    let xs = training_states(p, mono, data, spec);
    let n = xs.len() / nx.max(1);
    if n < 2 {
        return;
    }
    let mean: Vec<f64> = (0..nx)
        .map(|i| xs.iter().skip(i).step_by(nx).sum::<f64>() / n as f64)
        .collect();
    let mut cov = DMatrix::<f64>::zeros(nx, nx);
    for x in xs.chunks(nx) {
        for i in 0..nx {
            for j in 0..nx {
                cov[(i, j)] += (x[i] - mean[i]) * (x[j] - mean[j]) / n as f64;
            }
        }
    }
    let tr = cov.trace() / nx as f64;
    for i in 0..nx {
        cov[(i, i)] += 1e-9 * tr + 1e-300;
    }
    let Some(ch) = cov.cholesky() else {
        return;
    };
    let l = ch.l();
    let Some(t) = l.clone().try_inverse() else {
        return;
    };
    let a = DMatrix::from_row_slice(nx, nx, &p.a);
    let b = DMatrix::from_row_slice(nx, p.ni, &p.b);
    let c = DMatrix::from_row_slice(p.no, nx, &p.c);
    let (a2, b2, c2) = (&t * a * &l, &t * b, c * &l);
    let rows = |mtx: &DMatrix<f64>| -> Vec<f64> { mtx.transpose().iter().copied().collect() };
    p.a = rows(&a2);
    p.b = rows(&b2);
    p.c = rows(&c2);
    held_ranges(p, mono, data, spec);
}

/// Each state held within its range over the training free runs (run with the ranges
/// it was trained with), widened by `output_margin` on both sides; where no run stays
/// finite, [`FALLBACK_RANGE`] (the whitened states have unit deviation).
fn held_ranges(p: &mut Params, mono: &Monomials, data: &[Data], spec: &ModelSpec) {
    let nx = p.nx;
    let xs = training_states(p, mono, data, spec);
    for i in 0..nx {
        let (lo, hi) = xs
            .iter()
            .skip(i)
            .step_by(nx)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        let w = (hi - lo) * spec.output_margin;
        (p.x_lo[i], p.x_hi[i]) = if lo <= hi && w.is_finite() {
            (lo - w, hi + w)
        } else {
            (-FALLBACK_RANGE, FALLBACK_RANGE)
        };
    }
}

/// A state's held range where the training runs give none: `[-this, this]`.
const FALLBACK_RANGE: f64 = 100.0;

/// `kind = "state-space"`.
pub(crate) struct StateSpace;

impl super::kinds::Fit for StateSpace {
    fn fit(&self, spec: &ModelSpec, records: &[Record], m: &mut Model) -> Result<()> {
        fit(spec, records, m)
    }

    fn parameters(&self, spec: &ModelSpec, ni: usize, no: usize) -> usize {
        let nx = spec.na * no;
        (nx + no).saturating_mul((nx + ni + 1).saturating_add(Monomials::count(spec, nx, ni)))
    }

    /// Per iteration one pass of forward sensitivities (each sample moves the states'
    /// nx x p sensitivities through (nx + outputs) rows) and J^T J by matrix products,
    /// which run about 32 times faster per multiply-add than the scalar loops a unit
    /// stands for.
    fn work(&self, spec: &ModelSpec, n: f64, p: f64, no: f64) -> f64 {
        let nx = (spec.na as f64) * no;
        n * spec.epochs.max(1) as f64 * ((nx + no) * nx * p + p * p / 32.0)
    }
}

#[path = "state_space_normal.rs"]
mod normal;

#[cfg(test)]
#[path = "state_space_tests.rs"]
mod tests;
