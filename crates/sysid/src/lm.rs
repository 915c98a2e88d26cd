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
    let np = theta.len();
    let mut r0 = Vec::new();
    if !resid(theta, &mut r0) {
        return f64::INFINITY;
    }
    let cost = |r: &[f64]| r.iter().map(|v| v * v).sum::<f64>();
    let mut c0 = cost(&r0);
    let mut lambda = 1e-2;
    let mut r1 = Vec::new();
    for _ in 0..iters {
        // A stop asked for (Python's Ctrl-C): the caller's `cancel::check` says so.
        if crate::cancel::requested() {
            break;
        }
        let nr = r0.len();
        // The columns in parallel: each is a full evaluation of the residuals.
        let columns: Vec<Option<Vec<f64>>> = (0..np)
            .into_par_iter()
            .map(|p| {
                let h = fd_rel * theta[p].abs().max(1e-3);
                let mut th = theta.clone();
                th[p] += h;
                let mut r = Vec::new();
                (column(&th, p, &r0, &mut r) && r.len() == nr)
                    .then(|| r.iter().zip(&r0).map(|(a, b)| (a - b) / h).collect())
            })
            .collect();
        let mut jac = DMatrix::<f64>::zeros(nr, np);
        for (p, col) in columns.iter().enumerate() {
            if let Some(c) = col {
                for i in 0..nr {
                    jac[(i, p)] = c[i];
                }
            }
        }
        let jtj = jac.transpose() * &jac;
        let g = jac.transpose() * DVector::from_column_slice(&r0);
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
            if resid(&th, &mut r1) {
                let c1 = cost(&r1);
                if c1.is_finite() && c1 < c0 {
                    *theta = th;
                    std::mem::swap(&mut r0, &mut r1);
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
