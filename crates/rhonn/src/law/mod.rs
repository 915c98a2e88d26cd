//! Learning laws of the RHONN identifier (pump-model.md section 2, thesis 4.4.1).
//!
//! | law | states per neuron | weight update |
//! |---|---|---|
//! | `filtered-error` | x_i, w_i | dw_i = -Gamma_i z e_i |
//! | `filtered-regressor-gradient` | zeta_i, w_i | dzeta_i = -a_i zeta_i + z, x_i = w_i^T zeta_i, dw_i = -Gamma_i zeta_i e_i |
//! | `filtered-regressor-ls` | zeta_i, w_i, P_i | dw_i = -P_i zeta_i e_i, dP_i = -P_i zeta_i zeta_i^T P_i (stopped while trace P_i < floor) |
//! | `sigma-switching` | x_i, w_i | filtered-error, plus -sigma_i Gamma_i w_i while \|w_i\| > M_i (thesis eq. 4.9) |
//! | `sigma-smooth` | x_i, w_i | the three-case law after eq. 4.9: on \|w_i\| = M_i the weight slides on the sphere while -sigma w^T Gamma w <= w^T Gamma z e <= 0 |
//!
//! Each applies to every neuron of a network whose identified states are measured
//! (series-parallel: z from the measured states). The switching laws' discontinuity
//! \|w_i\| = M_i is an event of the solver, not a source of chatter.
//!
//! Reference: Kosmatopoulos, Polycarpou, Christodoulou, Ioannou, IEEE TNN 6(2), 1995;
//! Rovithakis, Christodoulou, *Adaptive Control with RHONNs*, 2000; Ioannou, Sun,
//! *Robust Adaptive Control*, 1996.

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
        match self {
            Gain::Scalar(g) => {
                for (o, x) in out.iter_mut().zip(v) {
                    *o = g * x;
                }
            }
            Gain::Matrix(m) => {
                let l = v.len();
                for r in 0..l {
                    out[r] = (0..l).map(|c| m[r * l + c] * v[c]).sum();
                }
            }
        }
    }

    fn check(spec: &GainSpec, l: usize, field: &str) -> Result<Gain> {
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

/// A learning law as a scenario writes it (`kind` names it). Per-neuron lists have one
/// entry per identified state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum LawSpec {
    /// dw_i = -Gamma_i z e_i.
    FilteredError {
        /// Gain per neuron.
        gamma: Vec<GainSpec>,
    },
    /// Filtered regressor with the gradient law.
    FilteredRegressorGradient {
        /// Gain per neuron.
        gamma: Vec<GainSpec>,
    },
    /// Filtered regressor with least squares.
    FilteredRegressorLs {
        /// P_i(0) = p0_i I per neuron.
        p0: Vec<f64>,
        /// The covariance stops shrinking while trace(P_i) < floor * L (default 1e-6 * p0).
        #[serde(default)]
        floor: Option<Vec<f64>>,
    },
    /// Filtered error with switching sigma-modification (thesis eq. 4.9).
    SigmaSwitching {
        /// Gain per neuron.
        gamma: Vec<GainSpec>,
        /// Radius M_i per neuron.
        m: Vec<f64>,
        /// Leakage sigma_i per neuron.
        sigma: Vec<f64>,
    },
    /// Filtered error with the smooth three-case sigma-modification (after eq. 4.9).
    SigmaSmooth {
        /// Gain per neuron.
        gamma: Vec<GainSpec>,
        /// Radius M_i per neuron.
        m: Vec<f64>,
        /// Leakage sigma_i per neuron.
        sigma: Vec<f64>,
    },
}

/// The structure a law gives each neuron's states.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Structure {
    /// \[x_i, w_i\].
    FilteredError,
    /// \[zeta_i, w_i\].
    FilteredRegressor,
    /// \[zeta_i, w_i, P_i\].
    LeastSquares,
}

/// Robust modification.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Robust {
    /// None.
    None,
    /// Switching sigma-modification.
    Switching,
    /// Smooth three-case variant.
    Smooth,
}

/// A checked law for `n` neurons and `L` terms.
#[derive(Debug, Clone, PartialEq)]
pub struct Law {
    /// Its name in scenario files.
    pub name: &'static str,
    /// State structure.
    pub structure: Structure,
    /// Gains per neuron (gradient laws).
    pub gamma: Vec<Gain>,
    /// P_i(0) scale per neuron (least squares).
    pub p0: Vec<f64>,
    /// Covariance floor per neuron (least squares).
    pub floor: Vec<f64>,
    /// Robust modification.
    pub robust: Robust,
    /// Radii M_i.
    pub m: Vec<f64>,
    /// Leakages sigma_i.
    pub sigma: Vec<f64>,
}

fn per_neuron<'a, T>(v: &'a [T], n: usize, field: &str) -> Result<&'a [T]> {
    if v.len() == n {
        Ok(v)
    } else {
        Err(invalid(
            field,
            format!("{} values", v.len()),
            format!("one per identified state ({n})"),
        ))
    }
}

fn positive(v: &[f64], field: &str) -> Result<()> {
    for (i, x) in v.iter().enumerate() {
        if !(x.is_finite() && *x > 0.0) {
            return Err(invalid(format!("{field}[{i}]"), x, "a finite number > 0"));
        }
    }
    Ok(())
}

impl LawSpec {
    /// Validate for `n` neurons and `l` terms; errors name `field.<key>`.
    pub fn check(&self, n: usize, l: usize, field: &str) -> Result<Law> {
        let gains = |g: &[GainSpec]| -> Result<Vec<Gain>> {
            per_neuron(g, n, &format!("{field}.gamma"))?
                .iter()
                .enumerate()
                .map(|(i, s)| Gain::check(s, l, &format!("{field}.gamma[{i}]")))
                .collect()
        };
        let robust = |m: &[f64], s: &[f64]| -> Result<()> {
            positive(per_neuron(m, n, &format!("{field}.m"))?, &format!("{field}.m"))?;
            positive(
                per_neuron(s, n, &format!("{field}.sigma"))?,
                &format!("{field}.sigma"),
            )
        };
        let base = Law {
            name: "",
            structure: Structure::FilteredError,
            gamma: vec![],
            p0: vec![],
            floor: vec![],
            robust: Robust::None,
            m: vec![],
            sigma: vec![],
        };
        Ok(match self {
            LawSpec::FilteredError { gamma } => Law {
                name: "filtered-error",
                gamma: gains(gamma)?,
                ..base
            },
            LawSpec::FilteredRegressorGradient { gamma } => Law {
                name: "filtered-regressor-gradient",
                structure: Structure::FilteredRegressor,
                gamma: gains(gamma)?,
                ..base
            },
            LawSpec::FilteredRegressorLs { p0, floor } => {
                positive(per_neuron(p0, n, &format!("{field}.p0"))?, &format!("{field}.p0"))?;
                let floor = match floor {
                    Some(f) => {
                        positive(
                            per_neuron(f, n, &format!("{field}.floor"))?,
                            &format!("{field}.floor"),
                        )?;
                        f.clone()
                    }
                    None => p0.iter().map(|p| 1e-6 * p).collect(),
                };
                Law {
                    name: "filtered-regressor-ls",
                    structure: Structure::LeastSquares,
                    p0: p0.clone(),
                    floor,
                    ..base
                }
            }
            LawSpec::SigmaSwitching { gamma, m, sigma } => {
                robust(m, sigma)?;
                Law {
                    name: "sigma-switching",
                    gamma: gains(gamma)?,
                    robust: Robust::Switching,
                    m: m.clone(),
                    sigma: sigma.clone(),
                    ..base
                }
            }
            LawSpec::SigmaSmooth { gamma, m, sigma } => {
                robust(m, sigma)?;
                Law {
                    name: "sigma-smooth",
                    gamma: gains(gamma)?,
                    robust: Robust::Smooth,
                    m: m.clone(),
                    sigma: sigma.clone(),
                    ..base
                }
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gains_are_checked() {
        let l = LawSpec::FilteredError {
            gamma: vec![GainSpec::Scalar(2.0)],
        }
        .check(1, 2, "identifier.law")
        .unwrap();
        let mut out = [0.0; 2];
        l.gamma[0].apply(&[1.0, 3.0], &mut out);
        assert_eq!(out, [2.0, 6.0]);
        let pd = GainSpec::Matrix(vec![vec![2.0, 1.0], vec![1.0, 2.0]]);
        let l = LawSpec::FilteredError { gamma: vec![pd] }
            .check(1, 2, "identifier.law")
            .unwrap();
        l.gamma[0].apply(&[1.0, 1.0], &mut out);
        assert_eq!(out, [3.0, 3.0]);
        let not_pd = GainSpec::Matrix(vec![vec![1.0, 2.0], vec![2.0, 1.0]]);
        let e = LawSpec::FilteredError { gamma: vec![not_pd] }
            .check(1, 2, "identifier.law")
            .unwrap_err();
        assert!(e.to_string().contains("positive definite"), "{e}");
        let e = LawSpec::FilteredError {
            gamma: vec![GainSpec::Scalar(1.0)],
        }
        .check(2, 2, "identifier.law")
        .unwrap_err();
        assert!(e.to_string().contains("`identifier.law.gamma` = 1 values"), "{e}");
        let e = LawSpec::SigmaSwitching {
            gamma: vec![GainSpec::Scalar(1.0)],
            m: vec![-1.0],
            sigma: vec![0.1],
        }
        .check(1, 2, "identifier.law")
        .unwrap_err();
        assert!(e.to_string().contains("`identifier.law.m[0]` = -1"), "{e}");
    }
}
