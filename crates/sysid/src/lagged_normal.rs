//! The normal equations of a lagged model's free-run error (the `simulation-error` law),
//! `J^T J` and `J^T r`, by forward sensitivities. Along the free run each output
//! `y_j(k) = w_j^T phi(k)` (held within its range) has the sensitivity to every weight
//!
//! ```text
//! S_j(k) = [phi(k) in w_j's columns] + sum over the output lags q of c_jq(k) S_j'(k - i)
//! c_jq(k) = w_j[q] + sum over the terms t of w_j[t] dz_t/dy_q dy_q/dphi_q
//! ```
//!
//! (`q` the regressor of output `j'` at lag `i`; `S = 0` on the measured start and where
//! the output is held at its bound), so one pass over the data gives the exact Jacobian
//! where forward differences took a free run per weight: the degree-3 structure of two
//! inputs (244 weights) trains 8 times faster, Bouc-Wen's default 5 times (`docs/results.md`).
//! The rows are summed a block at a time
//! ([`Acc`]) and the records in order, so the result is the same bits on any number of
//! threads.

use super::*;
use crate::lm::Acc;

/// Free-run residuals (`horizon` None) or `horizon`-step predictions' (normalised units)
/// of `m` over `records`, into `out`.
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

/// `(J^T J, J^T r, sum of squared residuals)` of `m`'s free run over `records`, the
/// residuals in normalised units as [`free_run_residuals`] gives them
/// (and their sum of squares in its order, so a step's cost and the start's agree).
pub(super) fn normal(m: &Model, records: &[Record]) -> (DMatrix<f64>, DVector<f64>, f64) {
    let np = m.no() * m.n_features();
    let mut acc = Acc::new(np);
    let mut cost = 0.0;
    for r in records {
        for v in record(m, r, &mut acc).iter().flatten() {
            cost += v * v;
        }
    }
    acc.flush();
    (acc.jtj, acc.g, cost)
}

/// One record's rows into `acc`; returns its residuals per output.
fn record(m: &Model, r: &Record, acc: &mut Acc) -> Vec<Vec<f64>> {
    let spec = &m.spec;
    let (un, yn) = m.normalise(r);
    let (n, no, nf) = (r.len(), m.no(), m.n_features());
    let np = no * nf;
    let lag = spec.max_lag();
    let terms = m.terms();
    let nphi = n_phi(spec, m.ni(), no);
    let n_out = no * spec.na;
    let squash = spec.kind == Kind::Rhonn && spec.activation == Activation::Tanh;
    let bounds: Vec<(f64, f64)> = m
        .output_range
        .iter()
        .zip(&m.output_norm)
        .map(|((lo, hi), (mean, s))| {
            let w = (hi - lo) * spec.output_margin;
            ((lo - w - mean) / s, (hi + w - mean) / s)
        })
        .collect();
    // The sensitivities of the last `lag + 1` samples, a ring: slot k % (lag + 1) holds
    // S_j(k) for every output j, each of `np` entries (zero on the measured start).
    let slots = lag + 1;
    let mut ring = vec![0.0; slots * no * np];
    let mut pred = yn.clone();
    let mut feat = vec![0.0; nf];
    let mut c = vec![0.0; n_out];
    let mut y = vec![0.0; nphi];
    let mut res = vec![Vec::with_capacity(n.saturating_sub(lag)); no];
    let mut row = vec![0.0; np];
    for k in lag..n {
        {
            let p = &pred;
            m.features(&|j, i| p[j][i], &un, k, &terms, &mut feat);
        }
        // The regressors as the terms see them, once per sample for every output.
        for (q, yq) in y.iter_mut().enumerate() {
            *yq = if q < n_out && squash {
                feat[q].tanh()
            } else {
                feat[q]
            };
        }
        for j in 0..no {
            let w = &m.weights[j];
            let v: f64 = w.iter().zip(&feat).map(|(a, b)| a * b).sum();
            let p = v.max(bounds[j].0).min(bounds[j].1);
            pred[j][k] = p;
            row.iter_mut().for_each(|x| *x = 0.0);
            // Held at its bound (or not a number): no sensitivity, as the hold's slope.
            if v == p {
                coefficients(m, w, &y, nphi, squash, &mut c);
                row[j * nf..(j + 1) * nf].copy_from_slice(&feat);
                for (q, &cq) in c.iter().enumerate() {
                    let i = spec.output_lag_start + q % spec.na;
                    if cq == 0.0 || k - i < lag {
                        continue;
                    }
                    let src = ((k - i) % slots * no + q / spec.na) * np;
                    for (x, s) in row.iter_mut().zip(&ring[src..src + np]) {
                        *x += cq * s;
                    }
                }
            }
            let dst = (k % slots * no + j) * np;
            ring[dst..dst + np].copy_from_slice(&row);
            let (mean, s) = m.output_norm[j];
            let e = ((p * s + mean) - r.outputs[j][k]) / s;
            res[j].push(e);
            acc.push(&row, e);
        }
    }
    res
}

/// `c[q] = d(w^T phi)/d phi_q` for each output-lag regressor `q`, given `y`, the
/// regressors as the terms see them (the output lags through `tanh` for a RHONN of sigmoids):
/// its weight, plus each term's weight times the term's slope in `y_q` and `y_q`'s in
/// `phi_q` (`tanh'` for a RHONN of sigmoids, 1 for a polynomial one).
fn coefficients(m: &Model, w: &[f64], y: &[f64], nphi: usize, squash: bool, c: &mut [f64]) {
    let n_out = c.len();
    c.copy_from_slice(&w[..n_out]);
    for (t, factors) in m.terms.iter().enumerate() {
        let wt = w[nphi + t];
        if wt == 0.0 {
            continue;
        }
        for (f, &[q, e]) in factors.iter().enumerate() {
            if q >= n_out {
                continue;
            }
            let yq = y[q];
            let mut d = e as f64 * yq.powi(e as i32 - 1);
            for (g, &[q2, e2]) in factors.iter().enumerate() {
                if g != f {
                    d *= y[q2].powi(e2 as i32);
                }
            }
            let slope = if squash { 1.0 - yq * yq } else { 1.0 };
            c[q] += wt * d * slope;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two outputs of two inputs: the bilinear system's state and a lag of it through a
    /// saturation, so each output's lags enter the other's regressor.
    fn two_outputs() -> Record {
        let mut r = crate::benchmarks::bilinear(5, 400);
        let x = r.outputs[0].clone();
        let mut z = 0.0;
        let y2 = x
            .iter()
            .map(|v| {
                z = 0.7 * z + 0.3 * (2.0 * v).tanh();
                z
            })
            .collect();
        r.outputs.push(y2);
        r
    }

    /// The sensitivities' cost is the free run's, bit for bit, and `2 J^T r` its gradient
    /// (central differences) for every weight: a RHONN of sigmoids and a polynomial one,
    /// two outputs, and an ARX.
    #[test]
    fn the_sensitivities_give_the_free_runs_cost_and_gradient() {
        let r = two_outputs();
        let (i, o) = (
            vec!["u1".to_string(), "u2".to_string()],
            vec!["y1".to_string(), "y2".to_string()],
        );
        for (kind, activation) in [
            (Kind::Rhonn, Activation::Tanh),
            (Kind::Rhonn, Activation::Identity),
            (Kind::Arx, Activation::Tanh),
        ] {
            let spec = ModelSpec {
                kind,
                activation,
                na: 2,
                nb: 2,
                degree: 3,
                max_factors: 3,
                output_margin: 100.0,
                ..ModelSpec::default()
            };
            let mut m = crate::fit(&spec, std::slice::from_ref(&r), &i, &o).unwrap();
            // Off the least-squares point, so the residuals are not orthogonal to J.
            for (k, w) in m.weights.iter_mut().flatten().enumerate() {
                *w += 0.01 * ((k % 5) as f64 - 2.0);
            }
            let records = std::slice::from_ref(&r);
            let (_, g, cost) = normal(&m, records);
            let cost_at = |th: &[f64]| {
                let mut q = m.clone();
                let mut o = 0;
                for w in q.weights.iter_mut() {
                    let l = w.len();
                    w.copy_from_slice(&th[o..o + l]);
                    o += l;
                }
                let mut out = Vec::new();
                free_run_residuals(&q, records, None, &mut out);
                out.iter().map(|v| v * v).sum::<f64>()
            };
            let th: Vec<f64> = m.weights.iter().flatten().copied().collect();
            assert_eq!(cost, cost_at(&th), "{kind:?} {activation:?}");
            crate::lm::assert_gradient(
                &th,
                g.as_slice(),
                cost,
                cost_at,
                &format!("{kind:?} {activation:?}"),
            );
        }
    }
}
