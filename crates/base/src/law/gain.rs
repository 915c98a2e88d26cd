//! Learning gains: a scalar or a symmetric positive definite matrix, as a scenario
//! writes it ([`GainSpec`]) and checked ([`Gain`]).

use crate::error::{invalid, Result};
use serde::{Deserialize, Serialize};

/// A learning gain as a scenario writes it: a scalar or a symmetric positive definite
/// matrix (L x L).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum GainSpec {
    /// gamma I.
    Scalar(f64),
    /// A full matrix, rows.
    Matrix(Vec<Vec<f64>>),
}

/// A checked gain.
#[derive(Debug, Clone, PartialEq)]
pub enum Gain {
    /// gamma I.
    Scalar(f64),
    /// Row-major L x L, symmetric positive definite.
    Matrix(Vec<f64>),
}

impl Gain {
    /// out = Gain v.
    #[inline]
    pub fn apply(&self, v: &[f64], out: &mut [f64]) {
        self.as_core().apply(v, out)
    }

    /// The gain borrowed as `rhonn_core`'s laws take it.
    #[inline]
    pub fn as_core(&self) -> rhonn_core::law::Gain<'_, f64> {
        match self {
            Gain::Scalar(g) => rhonn_core::law::Gain::Scalar(*g),
            Gain::Matrix(m) => rhonn_core::law::Gain::Matrix(m),
        }
    }

    pub(crate) fn check(spec: &GainSpec, l: usize, field: &str) -> Result<Gain> {
        match spec {
            GainSpec::Scalar(g) => {
                if g.is_finite() && *g > 0.0 {
                    Ok(Gain::Scalar(*g))
                } else {
                    Err(invalid(
                        field,
                        g,
                        "a gain > 0, or an L x L symmetric positive definite matrix",
                    ))
                }
            }
            GainSpec::Matrix(rows) => {
                if rows.len() != l || rows.iter().any(|r| r.len() != l) {
                    return Err(invalid(
                        field,
                        format!("{} rows", rows.len()),
                        format!("a {l} x {l} matrix (L = {l} terms)"),
                    ));
                }
                let m: Vec<f64> = rows.iter().flatten().copied().collect();
                for r in 0..l {
                    for c in 0..l {
                        if !m[r * l + c].is_finite()
                            || (m[r * l + c] - m[c * l + r]).abs() > 1e-12 * m[r * l + c].abs().max(1.0)
                        {
                            return Err(invalid(
                                format!("{field}[{r}][{c}]"),
                                m[r * l + c],
                                "a finite, symmetric matrix",
                            ));
                        }
                    }
                }
                if !cholesky_ok(&m, l) {
                    return Err(invalid(
                        field,
                        "the matrix",
                        "positive definite (its Cholesky factorisation fails)",
                    ));
                }
                Ok(Gain::Matrix(m))
            }
        }
    }
}

/// Whether a symmetric matrix is positive definite (Cholesky; L is small, so a few
/// lines here beat a linear-algebra dependency).
fn cholesky_ok(m: &[f64], l: usize) -> bool {
    let mut c = vec![0.0; l * l];
    for j in 0..l {
        let mut d = m[j * l + j];
        for k in 0..j {
            d -= c[j * l + k] * c[j * l + k];
        }
        if !(d > 0.0) {
            return false;
        }
        let d = d.sqrt();
        c[j * l + j] = d;
        for i in j + 1..l {
            let mut s = m[i * l + j];
            for k in 0..j {
                s -= c[i * l + k] * c[j * l + k];
            }
            c[i * l + j] = s / d;
        }
    }
    true
}
