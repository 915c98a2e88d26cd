//! The normal equations of a state-space model's simulation error, `J^T J` and `J^T r`,
//! by forward sensitivities: along the free run, `S(k) = dx(k)/dtheta` follows
//!
//! ```text
//! S(k+1) = (A + E dz/dx) S(k) + [x(k), u(k), z(k) in A's, B's and E's columns]
//! dy(k)/dtheta = (C + F dz/dx) S(k) + [x(k), u(k), 1, z(k) in C's, D's, the bias's and F's]
//! ```
//!
//! (a state held at its range's bound has a zero row), so one pass over the data gives the
//! exact Jacobian where differences would take a free run per parameter: for Silverbox's 57
//! parameters about 20 times less work, for a 6-state model's 600 about 200. The initial
//! state fitted to the `settle` samples is held fixed in the derivative (the cost, which
//! decides each step, includes it). The Jacobian's rows are never stored whole: blocks of
//! `BLOCK` rows are added to `J^T J` by one matrix product each, and the windows are summed in
//! a fixed grouping, so the result is the same bits on any number of threads.

use super::{Data, Monomials, Params, DIVERGED};
use crate::law::dot;
use crate::lm::Acc;
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;

/// Windows one task sums (a fixed grouping, whatever the threads).
const WINDOWS_PER_TASK: usize = 8;

/// `(J^T J, J^T r, sum of squared residuals)` of `p`'s simulation error over `windows`
/// (each from its sample `settle`); None when a run diverges.
pub(super) fn normal(
    p: &Params,
    mono: &Monomials,
    settle: usize,
    windows: &[Data],
) -> Option<(DMatrix<f64>, DVector<f64>, f64)> {
    let np = p.free().len();
    let parts: Vec<Option<Acc>> = windows
        .par_chunks(WINDOWS_PER_TASK)
        .map(|chunk| {
            let mut acc = Acc::new(np);
            for w in chunk {
                if !window(p, mono, settle, w, &mut acc) {
                    return None;
                }
            }
            acc.flush();
            Some(acc)
        })
        .collect();
    let mut jtj = DMatrix::zeros(np, np);
    let mut g = DVector::zeros(np);
    let mut cost = 0.0;
    for part in parts {
        let part = part?;
        jtj += part.jtj;
        g += part.g;
        cost += part.cost;
    }
    Some((jtj, g, cost))
}

/// The sum of squared simulation errors of `p` over `windows` (each from its sample
/// `settle`), summed in the same fixed grouping; None when a run diverges.
pub(super) fn cost(p: &Params, mono: &Monomials, settle: usize, windows: &[Data]) -> Option<f64> {
    let parts: Vec<Option<f64>> = windows
        .par_chunks(WINDOWS_PER_TASK)
        .map(|chunk| {
            let mut r = Vec::new();
            super::residuals(p, mono, settle, chunk, &mut r).then(|| r.iter().map(|v| v * v).sum::<f64>())
        })
        .collect();
    parts.into_iter().sum()
}

/// Where each block of parameters starts in `theta` (the order of `Params::free`).
struct Offsets {
    a: usize,
    b: usize,
    c: usize,
    d: usize,
    bias: usize,
    e: usize,
    f: usize,
}

impl Offsets {
    fn of(p: &Params) -> Offsets {
        let a = 0;
        let b = a + p.a.len();
        let c = b + p.b.len();
        let d = c + p.c.len();
        let bias = d + p.d.len();
        let e = bias + p.bias.len();
        let f = e + p.e.len();
        Offsets {
            a,
            b,
            c,
            d,
            bias,
            e,
            f,
        }
    }
}

/// One window's rows into `acc`; false when its run diverges.
fn window(p: &Params, mono: &Monomials, settle: usize, (u, y): &Data, acc: &mut Acc) -> bool {
    let (nx, ni, no, nt) = (p.nx, p.ni, p.no, mono.len());
    let ur: Vec<&[f64]> = u.iter().map(|c| &c[..]).collect();
    let yr: Vec<&[f64]> = y.iter().map(|c| &c[..]).collect();
    let Some(mut x) = p.initial_state(mono, &ur, &yr, settle) else {
        return false;
    };
    let o = Offsets::of(p);
    let np = o.f + p.f.len();
    let n = yr.first().map_or(0, |c| c.len());
    let (mut s, mut s_next) = (vec![0.0; nx * np], vec![0.0; nx * np]);
    let mut v = vec![0.0; nx + ni];
    let (mut z, mut jz) = (vec![0.0; nt], vec![0.0; nt * nx]);
    let mut m = vec![0.0; nx];
    let mut row = vec![0.0; np];
    let mut next = vec![0.0; nx];
    let mut uk = vec![0.0; ni];
    for k in 0..n {
        v[..nx].copy_from_slice(&x);
        for q in 0..ni {
            v[nx + q] = ur[q][k];
        }
        uk.copy_from_slice(&v[nx..]);
        mono.eval_with_jacobian(&mut v, nx, &mut z, &mut jz);
        for j in 0..no {
            let mut yj =
                p.bias[j] + dot(&p.c[j * nx..(j + 1) * nx], &x) + dot(&p.f[j * nt..(j + 1) * nt], &z);
            if p.has_d {
                yj += dot(&p.d[j * ni..(j + 1) * ni], &uk);
            }
            if !(yj.abs() < DIVERGED) {
                return false;
            }
            if k < settle {
                continue;
            }
            // (C + F dz/dx) row j, through S; then the direct terms.
            for i in 0..nx {
                m[i] = p.c[j * nx + i] + (0..nt).map(|t| p.f[j * nt + t] * jz[t * nx + i]).sum::<f64>();
            }
            combine(&m, &s, np, &mut row);
            for i in 0..nx {
                row[o.c + j * nx + i] += x[i];
            }
            if p.has_d {
                for q in 0..ni {
                    row[o.d + j * ni + q] += uk[q];
                }
            }
            row[o.bias + j] += 1.0;
            for t in 0..nt {
                row[o.f + j * nt + t] += z[t];
            }
            acc.push(&row, yj - yr[j][k]);
        }
        for i in 0..nx {
            let xi = dot(&p.a[i * nx..(i + 1) * nx], &x)
                + dot(&p.b[i * ni..(i + 1) * ni], &uk)
                + dot(&p.e[i * nt..(i + 1) * nt], &z);
            if !(xi.abs() < DIVERGED) {
                return false;
            }
            next[i] = xi.max(p.x_lo[i]).min(p.x_hi[i]);
            let out = &mut s_next[i * np..(i + 1) * np];
            if next[i] != xi {
                // Held at a bound: the state does not move with the parameters.
                out.iter_mut().for_each(|d| *d = 0.0);
                continue;
            }
            for l in 0..nx {
                m[l] = p.a[i * nx + l] + (0..nt).map(|t| p.e[i * nt + t] * jz[t * nx + l]).sum::<f64>();
            }
            combine(&m, &s, np, out);
            for l in 0..nx {
                out[o.a + i * nx + l] += x[l];
            }
            for q in 0..ni {
                out[o.b + i * ni + q] += uk[q];
            }
            for t in 0..nt {
                out[o.e + i * nt + t] += z[t];
            }
        }
        x.copy_from_slice(&next);
        std::mem::swap(&mut s, &mut s_next);
    }
    true
}

/// `out = sum_i m_i S[i, :]` (S: rows of `np`).
fn combine(m: &[f64], s: &[f64], np: usize, out: &mut [f64]) {
    out.iter_mut().for_each(|d| *d = 0.0);
    for (i, &mi) in m.iter().enumerate() {
        if mi != 0.0 {
            for (o, si) in out.iter_mut().zip(&s[i * np..(i + 1) * np]) {
                *o += mi * si;
            }
        }
    }
}
