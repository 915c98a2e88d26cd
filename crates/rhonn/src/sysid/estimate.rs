//! The estimators of the lagged models: batch ridge least squares, recursive laws over
//! epochs, and the free-run (simulation-error) refinement by Levenberg-Marquardt.

use super::*;
use crate::law::{Gradient, LearningLaw, LeastSquares, Rule};

/// Free-run residuals (normalised units) of `m` over `records`, appended to `out`.
pub(super) fn free_run_residuals(m: &Model, records: &[Record], horizon: Option<usize>, out: &mut Vec<f64>) {
    out.clear();
    for r in records {
        let (p, first) = m
            .predict(r, horizon)
            .expect("a lagged model predicts every record");
        for (j, (col, (_, sd))) in r.outputs.iter().zip(&m.output_norm).enumerate() {
            for k in first..r.len() {
                out.push((p[j][k] - col[k]) / sd);
            }
        }
    }
}

/// Levenberg-Marquardt on the free-run error, from the current weights. The Jacobian
/// is taken by forward differences (a few dozen weights and a cheap simulation make
/// that simpler and as fast as differentiating through the clipped recursion).
pub(super) fn simulation_error(m: &mut Model, records: &[Record], horizon: Option<usize>) {
    let shapes: Vec<usize> = m.weights.iter().map(|w| w.len()).collect();
    let set = |m: &mut Model, th: &[f64]| {
        let mut o = 0;
        for (w, &l) in m.weights.iter_mut().zip(&shapes) {
            w.copy_from_slice(&th[o..o + l]);
            o += l;
        }
    };
    let mut theta: Vec<f64> = m.weights.iter().flatten().copied().collect();
    let iters = m.spec.epochs;
    let cell = std::cell::RefCell::new(m.clone());
    lm(&mut theta, iters, 1e-6, &|th, out| {
        let mut w = cell.borrow_mut();
        set(&mut w, th);
        free_run_residuals(&w, records, horizon, out);
        true
    });
    set(m, &theta);
}

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
    resid: &dyn Fn(&[f64], &mut Vec<f64>) -> bool,
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
        let nr = r0.len();
        let mut jac = DMatrix::<f64>::zeros(nr, np);
        for p in 0..np {
            let h = fd_rel * theta[p].abs().max(1e-3);
            let mut th = theta.clone();
            th[p] += h;
            if resid(&th, &mut r1) && r1.len() == nr {
                for i in 0..nr {
                    jac[(i, p)] = (r1[i] - r0[i]) / h;
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

/// Ridge least squares by the normal equations and a Cholesky factorisation.
pub(super) fn batch_ls(rows: &[Vec<f64>], targets: &[Vec<f64>], ridge: f64) -> Result<Vec<Vec<f64>>> {
    let nf = rows[0].len();
    let x = DMatrix::from_fn(rows.len(), nf, |i, j| rows[i][j]);
    let mut xtx = x.transpose() * &x;
    let mean_diag = (0..nf).map(|i| xtx[(i, i)]).sum::<f64>() / nf as f64;
    for i in 0..nf {
        xtx[(i, i)] += ridge * mean_diag + 1e-12 * mean_diag;
    }
    // Collinear regressors (an input that is constant or equals another, an output lag
    // that repeats an input) leave the Gram matrix singular without a ridge.
    let chol = xtx.cholesky().ok_or_else(|| {
        invalid(
            "model.ridge",
            ridge,
            "a larger ridge (e.g. 1e-6): the regressors are collinear on these data (a constant \
             input, an input equal to another or to an output, or more lags than the data can tell \
             apart), so least squares has no unique solution without one",
        )
    })?;
    Ok(targets
        .iter()
        .map(|y| {
            let rhs = x.transpose() * DVector::from_column_slice(y);
            chol.solve(&rhs).iter().copied().collect()
        })
        .collect())
}

/// The recursive least-squares law (gain None) or the normalised gradient law over
/// epochs, the weights of one epoch starting the next.
pub(super) fn recursive(
    rows: &[Vec<f64>],
    targets: &[Vec<f64>],
    epochs: usize,
    gain: Option<f64>,
) -> Vec<Vec<f64>> {
    let nf = rows[0].len();
    // One neuron per output; normalised gradient or recursive least squares with
    // P reset to 1e3 I each epoch (the library's laws, sampled).
    let rule = match gain {
        Some(g) => Rule::Gradient(Gradient::scalar(g, 1)),
        None => Rule::LeastSquares(LeastSquares {
            p0: vec![1e3],
            floor: vec![0.0],
        }),
    };
    let mut p = vec![0.0; rule.law_states(nf)];
    let mut work = vec![0.0; nf];
    targets
        .iter()
        .map(|y| {
            let mut w = vec![0.0; nf];
            for _ in 0..epochs {
                rule.init(0, nf, &mut p);
                for (row, &yk) in rows.iter().zip(y) {
                    let e = crate::law::dot(&w, row) - yk;
                    rule.update(0, row, e, &mut w, &mut p, &mut work);
                }
            }
            w
        })
        .collect()
}
