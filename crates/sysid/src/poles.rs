//! Polynomials by their roots, for the training of models with linear filters: the roots
//! of a polynomial, the polynomial of given roots, and a denominator's unstable poles
//! reflected inside the unit circle (MATLAB's `polystab`). The Wiener-Hammerstein training
//! splits its best linear approximation's poles and zeros with them; it and the state-space
//! training start from a stable linear model through [`stabilised`].

use crate::models::wiener_hammerstein::Filter;
use nalgebra::{Complex, DMatrix};

/// Roots of `c[0] z^n + c[1] z^(n-1) + ... + c[n]` (leading zeros dropped).
pub(crate) fn roots(c: &[f64]) -> Vec<Complex<f64>> {
    let scale = c.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let start = c.iter().position(|v| v.abs() > 1e-9 * scale).unwrap_or(c.len());
    let c = &c[start..];
    let n = c.len().saturating_sub(1);
    if n == 0 {
        return vec![];
    }
    let comp = DMatrix::from_fn(n, n, |i, j| {
        if i == 0 {
            -c[j + 1] / c[0]
        } else if i == j + 1 {
            1.0
        } else {
            0.0
        }
    });
    comp.complex_eigenvalues().iter().copied().collect()
}

/// Denominator coefficients `a` (without the leading 1) with every pole `r` on or outside
/// the unit circle moved to `1 / conj(r)`, at most 0.99 in magnitude; `a` itself when
/// stable.
pub(crate) fn stabilised(a: &[f64]) -> Vec<f64> {
    let f = Filter {
        b: Vec::new(),
        a: a.to_vec(),
    };
    if f.is_stable() {
        return a.to_vec();
    }
    let mut den = vec![1.0];
    den.extend(a);
    let inside: Vec<Complex<f64>> = roots(&den)
        .into_iter()
        .map(|r| {
            let m = r.norm();
            if m < 1.0 {
                r
            } else {
                r / (m * m).max(m / 0.99)
            }
        })
        .collect();
    let mut out = poly(&inside)[1..].to_vec();
    out.resize(a.len(), 0.0);
    out
}

/// Real coefficients `[1, p_1, ..., p_n]` of `prod (z - r_i)`.
pub(crate) fn poly(roots: &[Complex<f64>]) -> Vec<f64> {
    let mut c = vec![Complex::new(1.0, 0.0)];
    for r in roots {
        let mut next = vec![Complex::new(0.0, 0.0); c.len() + 1];
        for (i, ci) in c.iter().enumerate() {
            next[i] += ci;
            next[i + 1] -= ci * r;
        }
        c = next;
    }
    c.iter().map(|v| v.re).collect()
}
