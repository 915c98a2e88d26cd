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
//! Each law is one file implementing [`LearningLaw`] (continuous time for the identifier
//! integrated with a plant, sampled for `rhonn fit` and sampled loops): [`gradient`],
//! [`least_squares`]; the robust modifications [`sigma`] (switching, smooth) and
//! [`projection`] (onto a ball) act on a gradient step. The filtered-error and
//! filtered-regressor structures (how the regressor phi is formed from z) are the
//! identifier's ([`Structure`]). Adding a law: one file implementing [`LearningLaw`], a
//! [`Rule`] variant with its arm in `Rule::law`, a [`LawSpec`] variant (its TOML form) with
//! its arm in [`LawSpec::check`], and its test.
//!
//! Reference: Kosmatopoulos, Polycarpou, Christodoulou, Ioannou, IEEE TNN 6(2), 1995;
//! Rovithakis, Christodoulou, *Adaptive Control with RHONNs*, 2000; Ioannou, Sun,
//! *Robust Adaptive Control*, 1996.

use crate::error::{invalid, Result};
use serde::{Deserialize, Serialize};

mod gain;
pub mod gradient;
pub mod least_squares;
pub mod projection;
pub mod sigma;
#[cfg(test)]
mod test_sign_error;
pub use gain::{Gain, GainSpec};
pub use gradient::Gradient;
pub use least_squares::LeastSquares;
#[cfg(test)]
use test_sign_error::SignError;

/// The dot product of two equal-length slices (`rhonn_core::law::dot`).
#[inline(always)]
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    rhonn_core::law::dot(a, b)
}

/// A learning law: how one neuron's weights move given its regressor `phi` and its error
/// `e = estimate - measurement` (every law descends `e^2`). A law may keep states of
/// its own per neuron (a covariance); `work` is scratch of the regressor's length.
pub trait LearningLaw {
    /// The law's name.
    fn name(&self) -> &'static str;
    /// States per neuron besides the weights, for `l` regressor terms.
    fn law_states(&self, _l: usize) -> usize {
        0
    }
    /// Set (or reset) neuron `neuron`'s law states.
    fn init(&self, _neuron: usize, _l: usize, _states: &mut [f64]) {}
    /// Continuous time: `dw/dt` and the law states' derivative.
    #[allow(clippy::too_many_arguments)]
    fn derivative(
        &self,
        neuron: usize,
        phi: &[f64],
        e: f64,
        states: &[f64],
        dw: &mut [f64],
        dstates: &mut [f64],
        work: &mut [f64],
    );
    /// Sampled: one update of the weights and the law states for one sample.
    fn update(&self, neuron: usize, phi: &[f64], e: f64, w: &mut [f64], states: &mut [f64], work: &mut [f64]);
    /// Neuron `neuron`'s gain Gamma, for a law that has one (a gradient law: the sigma
    /// modifications act through it); None by default.
    fn gain(&self, _neuron: usize) -> Option<&Gain> {
        None
    }
    /// Every neuron's scalar gain, when each is one (the identifier's fast paths); None
    /// by default.
    fn scalar_gains(&self) -> Option<Vec<f64>> {
        None
    }
    /// A bound on how fast neuron `neuron`'s weights move per unit error and regressor,
    /// from its law states (`l` regressor terms): the online identifier's substeps
    /// follow it.
    fn rate(&self, neuron: usize, states: &[f64], l: usize) -> f64;
}

/// The learning laws a scenario can name, each one file.
#[derive(Debug, Clone, PartialEq)]
pub enum Rule {
    /// [`gradient`].
    Gradient(Gradient),
    /// [`least_squares`].
    LeastSquares(LeastSquares),
    /// `test_sign_error` (tests only).
    #[cfg(test)]
    TestSignError(SignError),
}

impl Rule {
    /// The law: the registry's one arm per law.
    fn law(&self) -> &dyn LearningLaw {
        match self {
            Rule::Gradient(g) => g,
            Rule::LeastSquares(l) => l,
            #[cfg(test)]
            Rule::TestSignError(s) => s,
        }
    }
}

impl LearningLaw for Rule {
    fn name(&self) -> &'static str {
        self.law().name()
    }
    fn law_states(&self, l: usize) -> usize {
        self.law().law_states(l)
    }
    fn init(&self, neuron: usize, l: usize, states: &mut [f64]) {
        self.law().init(neuron, l, states)
    }
    #[inline]
    fn derivative(
        &self,
        i: usize,
        phi: &[f64],
        e: f64,
        s: &[f64],
        dw: &mut [f64],
        ds: &mut [f64],
        work: &mut [f64],
    ) {
        self.law().derivative(i, phi, e, s, dw, ds, work)
    }
    fn update(&self, i: usize, phi: &[f64], e: f64, w: &mut [f64], s: &mut [f64], work: &mut [f64]) {
        self.law().update(i, phi, e, w, s, work)
    }
    fn gain(&self, i: usize) -> Option<&Gain> {
        self.law().gain(i)
    }
    fn scalar_gains(&self) -> Option<Vec<f64>> {
        self.law().scalar_gains()
    }
    fn rate(&self, i: usize, states: &[f64], l: usize) -> f64 {
        self.law().rate(i, states, l)
    }
}

/// The identifier's view of a law ([`rhonn_core::ident::NeuronLaw`]): the same
/// derivative, the gain the sigma laws use, and a bound on the gain for the online
/// identifier's substeps.
impl rhonn_core::ident::NeuronLaw<f64> for Rule {
    fn law_states(&self, l: usize) -> usize {
        LearningLaw::law_states(self, l)
    }
    #[inline]
    fn derivative(
        &self,
        i: usize,
        phi: &[f64],
        e: f64,
        s: &[f64],
        dw: &mut [f64],
        ds: &mut [f64],
        work: &mut [f64],
    ) {
        LearningLaw::derivative(self, i, phi, e, s, dw, ds, work)
    }
    #[inline]
    fn gain(&self, i: usize) -> Option<rhonn_core::law::Gain<'_, f64>> {
        LearningLaw::gain(self, i).map(Gain::as_core)
    }
    fn rate(&self, i: usize, states: &[f64], l: usize) -> f64 {
        LearningLaw::rate(self, i, states, l)
    }
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
    /// Filtered error with the sign-error law (tests only: `test_sign_error`).
    #[cfg(test)]
    TestSignError {
        /// Gain per neuron.
        gamma: Vec<f64>,
    },
}

/// How a neuron's regressor and model state are formed, and the robust modification of a
/// gradient law ([`sigma`]): the core's ([`rhonn_core::ident`]).
pub use rhonn_core::ident::{Robust, Structure};

/// A checked law for `n` neurons and `L` terms.
#[derive(Debug, Clone, PartialEq)]
pub struct Law {
    /// Its name in scenario files.
    pub name: &'static str,
    /// How the regressor is formed.
    pub structure: Structure,
    /// The weight update.
    pub rule: Rule,
    /// Robust modification (gradient laws).
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
        let gradient = |g: &[GainSpec]| -> Result<Rule> { Ok(Rule::Gradient(Gradient { gamma: gains(g)? })) };
        let base = |name, structure, rule| Law {
            name,
            structure,
            rule,
            robust: Robust::None,
            m: vec![],
            sigma: vec![],
        };
        Ok(match self {
            LawSpec::FilteredError { gamma } => {
                base("filtered-error", Structure::FilteredError, gradient(gamma)?)
            }
            LawSpec::FilteredRegressorGradient { gamma } => base(
                "filtered-regressor-gradient",
                Structure::FilteredRegressor,
                gradient(gamma)?,
            ),
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
                base(
                    "filtered-regressor-ls",
                    Structure::FilteredRegressor,
                    Rule::LeastSquares(LeastSquares {
                        p0: p0.clone(),
                        floor,
                    }),
                )
            }
            LawSpec::SigmaSwitching { gamma, m, sigma } => {
                robust(m, sigma)?;
                Law {
                    robust: Robust::Switching,
                    m: m.clone(),
                    sigma: sigma.clone(),
                    ..base("sigma-switching", Structure::FilteredError, gradient(gamma)?)
                }
            }
            LawSpec::SigmaSmooth { gamma, m, sigma } => {
                robust(m, sigma)?;
                Law {
                    robust: Robust::Smooth,
                    m: m.clone(),
                    sigma: sigma.clone(),
                    ..base("sigma-smooth", Structure::FilteredError, gradient(gamma)?)
                }
            }
            #[cfg(test)]
            LawSpec::TestSignError { gamma } => {
                positive(
                    per_neuron(gamma, n, &format!("{field}.gamma"))?,
                    &format!("{field}.gamma"),
                )?;
                let rule = Rule::TestSignError(SignError { gamma: gamma.clone() });
                base("test-sign-error", Structure::FilteredError, rule)
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
        l.rule.gain(0).unwrap().apply(&[1.0, 3.0], &mut out);
        assert_eq!(out, [2.0, 6.0]);
        let pd = GainSpec::Matrix(vec![vec![2.0, 1.0], vec![1.0, 2.0]]);
        let l = LawSpec::FilteredError { gamma: vec![pd] }
            .check(1, 2, "identifier.law")
            .unwrap();
        l.rule.gain(0).unwrap().apply(&[1.0, 1.0], &mut out);
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
