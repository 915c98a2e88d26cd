//! Levenberg-Marquardt on residuals that may fail: the lagged models' free-run
//! refinement, the cascade models and the pump's grey box.

use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// Levenberg-Marquardt on the residuals `resid(theta, out)` (false: the model could not
/// be simulated there, a step to avoid), at most `iters` iterations from `theta`, with
/// a forward-difference Jacobian of relative step `fd_rel`. Leaves the best `theta`
/// found and returns its cost (sum of squared residuals; infinity when the start
/// itself fails). Shared by the lagged models' `simulation-error` law and the
/// `cascade` models; nalgebra's Cholesky solves each damped step (no crate of the
/// workspace offers a Levenberg-Marquardt with user-defined failure of a residual).
pub(super) fn lm(
    theta: &mut Vec<f64>,
    iters: usize,
    fd_rel: f64,
    resid: &(dyn Fn(&[f64], &mut Vec<f64>) -> bool + Sync),
) -> f64 {
    lm_with_columns(theta, iters, fd_rel, resid, &|th, _, _, out| resid(th, out))
}

/// The residuals at `theta` moved in coordinate `p` alone, given the residuals `r0` at
/// `theta` (false: not simulated): what a Jacobian column needs, for residuals of which a
/// coordinate moves only a part (a record's hidden initial state moves that record's).
pub(super) type Column<'a> = &'a (dyn Fn(&[f64], usize, &[f64], &mut Vec<f64>) -> bool + Sync);

/// [`lm`] with each Jacobian column's residuals from `column`, which must give exactly
/// what `resid` gives at the moved point (the same bits: the training does not depend on
/// which is used).
pub(super) fn lm_with_columns(
    theta: &mut Vec<f64>,
    iters: usize,
    fd_rel: f64,
    resid: &(dyn Fn(&[f64], &mut Vec<f64>) -> bool + Sync),
    column: Column,
) -> f64 {
    let mut r0 = Vec::new();
    if !resid(theta, &mut r0) {
        return f64::INFINITY;
    }
    let mut p = Differences {
        fd_rel,
        resid,
        column,
        r0,
        r1: Vec::new(),
    };
    minimise(&mut p, theta, iters)
}

/// Levenberg-Marquardt from the normal equations: `normal(theta)` gives `(J^T J, J^T r,
/// cost)` at `theta` (None: not simulated there), for a model whose Jacobian is computed
/// along with its residuals (forward sensitivities) rather than by differences; `cost(theta)`
/// the sum of squared residuals alone (a trial step's, cheaper). The same damping, steps and
/// stopping rule as [`lm`].
pub(super) fn lm_normal(theta: &mut Vec<f64>, iters: usize, cost: Cost, normal: Normal) -> f64 {
    let Some((jtj, g, c)) = normal(theta) else {
        return f64::INFINITY;
    };
    let mut p = Exact {
        cost_at: cost,
        normal,
        at: (jtj, g),
        cost: c,
        pending: None,
    };
    minimise(&mut p, theta, iters)
}

/// The sum of squared residuals at a point, or None (see [`lm_normal`]).
pub(super) type Cost<'a> = &'a (dyn Fn(&[f64]) -> Option<f64> + Sync);

/// `(J^T J, J^T r, sum of squared residuals)` at a point, or None (see [`lm_normal`]).
pub(super) type Normal<'a> = &'a (dyn Fn(&[f64]) -> Option<(DMatrix<f64>, DVector<f64>, f64)> + Sync);

/// What the damped iteration needs of a least-squares problem.
trait Problem {
    /// The cost at the current point.
    fn cost(&self) -> f64;
    /// `J^T J` and `J^T r` at the current point `theta`.
    fn normal(&mut self, theta: &[f64]) -> (DMatrix<f64>, DVector<f64>);
    /// The cost at `theta` (None or not finite: a step to avoid), kept for [`Problem::accept`].
    fn trial(&mut self, theta: &[f64]) -> Option<f64>;
    /// The last trial point becomes the current one.
    fn accept(&mut self);
}

/// The residuals' Jacobian by forward differences, a column per parameter in parallel.
struct Differences<'a> {
    fd_rel: f64,
    resid: &'a (dyn Fn(&[f64], &mut Vec<f64>) -> bool + Sync),
    column: Column<'a>,
    r0: Vec<f64>,
    r1: Vec<f64>,
}

fn sum_sq(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum::<f64>()
}

impl Problem for Differences<'_> {
    fn cost(&self) -> f64 {
        sum_sq(&self.r0)
    }

    fn normal(&mut self, theta: &[f64]) -> (DMatrix<f64>, DVector<f64>) {
        let (np, nr) = (theta.len(), self.r0.len());
        let r0 = &self.r0;
        // The columns in parallel: each is a full evaluation of the residuals.
        let columns: Vec<Option<Vec<f64>>> = (0..np)
            .into_par_iter()
            .map(|p| {
                let h = self.fd_rel * theta[p].abs().max(1e-3);
                let mut th = theta.to_vec();
                th[p] += h;
                let mut r = Vec::with_capacity(nr);
                ((self.column)(&th, p, r0, &mut r) && r.len() == nr).then(|| {
                    for (a, b) in r.iter_mut().zip(r0) {
                        *a = (*a - b) / h;
                    }
                    r
                })
            })
            .collect();
        let mut jac = DMatrix::<f64>::zeros(nr, np);
        for (p, col) in columns.iter().enumerate() {
            if let Some(c) = col {
                jac.column_mut(p).copy_from_slice(c);
            }
        }
        // One transpose for both products (the same products, so the same bits).
        let jt = jac.transpose();
        let jtj = &jt * &jac;
        let g = &jt * DVector::from_column_slice(r0);
        (jtj, g)
    }

    fn trial(&mut self, theta: &[f64]) -> Option<f64> {
        (self.resid)(theta, &mut self.r1).then(|| sum_sq(&self.r1))
    }

    fn accept(&mut self) {
        std::mem::swap(&mut self.r0, &mut self.r1);
    }
}

/// The normal equations given by the model (see [`lm_normal`]).
struct Exact<'a> {
    cost_at: Cost<'a>,
    normal: Normal<'a>,
    /// The normal equations at the current point.
    at: (DMatrix<f64>, DVector<f64>),
    cost: f64,
    /// The last trial point and its cost.
    pending: Option<(Vec<f64>, f64)>,
}

impl Problem for Exact<'_> {
    fn cost(&self) -> f64 {
        self.cost
    }

    fn normal(&mut self, _theta: &[f64]) -> (DMatrix<f64>, DVector<f64>) {
        self.at.clone()
    }

    fn trial(&mut self, theta: &[f64]) -> Option<f64> {
        let c = (self.cost_at)(theta)?;
        self.pending = Some((theta.to_vec(), c));
        Some(c)
    }

    fn accept(&mut self) {
        if let Some((theta, c)) = self.pending.take() {
            // The normal equations of the accepted point (its cost was computed; a point
            // whose sensitivities fail where its cost did not keeps zero equations, and the
            // next step stops).
            let n = theta.len();
            let (a, g) = (self.normal)(&theta)
                .map(|(a, g, _)| (a, g))
                .unwrap_or_else(|| (DMatrix::zeros(n, n), DVector::zeros(n)));
            self.at = (a, g);
            self.cost = c;
        }
    }
}

/// The damped Gauss-Newton iteration shared by [`lm`] and [`lm_normal`]: at most `iters`
/// iterations from `theta` (left at the best point found); returns its cost.
fn minimise(p: &mut impl Problem, theta: &mut Vec<f64>, iters: usize) -> f64 {
    let np = theta.len();
    let mut c0 = p.cost();
    let mut lambda = 1e-2;
    for _ in 0..iters {
        // A stop asked for (Python's Ctrl-C): the caller's `cancel::check` says so.
        if crate::cancel::requested() {
            break;
        }
        let (jtj, g) = p.normal(theta);
        let mut improved = false;
        for _ in 0..10 {
            let mut a = jtj.clone();
            for d in 0..np {
                a[(d, d)] += lambda * jtj[(d, d)].max(1e-12);
            }
            let Some(ch) = a.cholesky() else {
                lambda *= 10.0;
                continue;
            };
            let step = ch.solve(&g);
            let th: Vec<f64> = theta.iter().zip(step.iter()).map(|(t, s)| t - s).collect();
            if let Some(c1) = p.trial(&th) {
                if c1.is_finite() && c1 < c0 {
                    *theta = th;
                    p.accept();
                    let rel = (c0 - c1) / c0;
                    c0 = c1;
                    lambda = (lambda / 3.0).max(1e-9);
                    improved = rel > 1e-6;
                    break;
                }
            }
            lambda *= 4.0;
        }
        if !improved {
            break;
        }
    }
    c0
}

/// Rows gathered before they join `J^T J`.
const BLOCK: usize = 256;

/// `J^T J`, `J^T r` and the cost of a model whose Jacobian rows come from its forward
/// sensitivities (the state-space models', the lagged models' free run), summed a block of
/// [`BLOCK`] rows at a time by one matrix product each: the rows are never stored whole.
pub(super) struct Acc {
    pub(super) jtj: DMatrix<f64>,
    pub(super) g: DVector<f64>,
    pub(super) cost: f64,
    rows: DMatrix<f64>,
    r: DVector<f64>,
    n: usize,
}

impl Acc {
    pub(super) fn new(np: usize) -> Acc {
        Acc {
            jtj: DMatrix::zeros(np, np),
            g: DVector::zeros(np),
            cost: 0.0,
            rows: DMatrix::zeros(BLOCK, np),
            r: DVector::zeros(BLOCK),
            n: 0,
        }
    }

    pub(super) fn push(&mut self, row: &[f64], r: f64) {
        for (c, v) in row.iter().enumerate() {
            self.rows[(self.n, c)] = *v;
        }
        self.r[self.n] = r;
        self.cost += r * r;
        self.n += 1;
        if self.n == BLOCK {
            self.flush();
        }
    }

    pub(super) fn flush(&mut self) {
        if self.n == 0 {
            return;
        }
        let b = self.rows.rows(0, self.n);
        self.jtj.gemm_tr(1.0, &b, &b, 1.0);
        self.g.gemv_tr(1.0, &b, &self.r.rows(0, self.n), 1.0);
        self.n = 0;
    }
}

/// For the tests of a model's normal equations: `2 g` (`g = J^T r` from its sensitivities)
/// is the gradient of `cost_at` at `theta` by central differences, for every parameter, to
/// 1e-4 of the derivative (or of 1e-3 of the cost when the derivative is near zero).
#[cfg(test)]
pub(super) fn assert_gradient(
    theta: &[f64],
    g: &[f64],
    cost: f64,
    cost_at: impl Fn(&[f64]) -> f64,
    what: &str,
) {
    for k in 0..theta.len() {
        let h = 1e-6 * theta[k].abs().max(1e-2);
        let (mut up, mut down) = (theta.to_vec(), theta.to_vec());
        up[k] += h;
        down[k] -= h;
        let fd = (cost_at(&up) - cost_at(&down)) / (2.0 * h);
        assert!(
            (fd - 2.0 * g[k]).abs() <= 1e-4 * fd.abs().max(1e-3 * cost),
            "{what} parameter {k}: differences {fd}, sensitivities {}",
            2.0 * g[k]
        );
    }
}
