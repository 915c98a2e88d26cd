//! A pump campaign's plan: the `[campaign]` section of a scenario (each uncertain
//! parameter's distribution and range), checked into a [`Plan`], and the draw of run k,
//! which depends only on the campaign's seed and k. Knows nothing of scenarios beyond
//! the section and the values it is centred on.

use crate::error::{invalid, Result};
use rand::{Rng, SeedableRng};
use rand_distr::{Distribution as _, StandardNormal};
use serde::{Deserialize, Serialize};

/// The uncertain parameters a pump campaign draws: the pump's tolerance table.
pub use crate::plant::pump::CAMPAIGN_PARAMETERS as TOLERANCES;

/// How a parameter is drawn, as written in the scenario's `[campaign]` section.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DistributionKind {
    /// Uniform over the range (default).
    #[default]
    Uniform,
    /// Normal around the scenario's value, truncated to the range.
    Normal,
    /// Not drawn: the scenario's value in every run.
    Fixed,
}

/// One parameter's distribution in the scenario file (units of the `[plant]` key).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ParamDistSpec {
    /// `uniform` (default), `normal` or `fixed`.
    pub distribution: DistributionKind,
    /// Range as a relative half-width around the scenario's value (default: the
    /// thesis's tolerance); exclusive with `min`/`max`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub relative: Option<f64>,
    /// Lower end of the range, in the key's unit (with `max`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min: Option<f64>,
    /// Upper end of the range, in the key's unit (with `min`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max: Option<f64>,
    /// `normal`: standard deviation as a fraction of the scenario's value (default: a
    /// third of the range's half-width over the value).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub std_relative: Option<f64>,
}

/// A scenario's `[campaign]` section: overrides of the uncertain parameters'
/// distributions; a parameter left out keeps uniform within the thesis's tolerance.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CampaignSpec {
    /// Bulk modulus \[MPa\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub beta_mpa: Option<ParamDistSpec>,
    /// Pilot valve flow coefficient mu_1.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mu_1: Option<ParamDistSpec>,
    /// Pilot valve flow coefficient mu_2.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mu_2: Option<ParamDistSpec>,
    /// Lubricating flow \[dm^3/s\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub q_0_dm3_s: Option<ParamDistSpec>,
    /// Largest demand slew \[dm^3/s^2\] (scales the demand trapezoids' slew too).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub qdot_max_dm3_s2: Option<ParamDistSpec>,
}

impl CampaignSpec {
    fn entries(&self) -> [Option<&ParamDistSpec>; 5] {
        [
            self.beta_mpa.as_ref(),
            self.mu_1.as_ref(),
            self.mu_2.as_ref(),
            self.q_0_dm3_s.as_ref(),
            self.qdot_max_dm3_s2.as_ref(),
        ]
    }
}

/// A checked distribution of one parameter (display units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "distribution", rename_all = "kebab-case")]
pub enum Distribution {
    /// Uniform on `[min, max]`.
    Uniform {
        /// Lower end.
        min: f64,
        /// Upper end.
        max: f64,
    },
    /// Normal(`mean`, `std`) truncated to `[min, max]` (drawn by rejection).
    Normal {
        /// Mean (the scenario's value).
        mean: f64,
        /// Standard deviation.
        std: f64,
        /// Lower end.
        min: f64,
        /// Upper end.
        max: f64,
    },
    /// Always `value`.
    Fixed {
        /// The scenario's value.
        value: f64,
    },
}

impl Distribution {
    /// The range `[min, max]` (a point for `Fixed`).
    pub fn range(&self) -> (f64, f64) {
        match *self {
            Distribution::Uniform { min, max } | Distribution::Normal { min, max, .. } => (min, max),
            Distribution::Fixed { value } => (value, value),
        }
    }

    fn sample(&self, rng: &mut rand_chacha::ChaCha8Rng) -> f64 {
        match *self {
            Distribution::Uniform { min, max } => {
                let (c, hw) = (0.5 * (min + max), 0.5 * (max - min));
                c + hw * rng.gen_range(-1.0..=1.0)
            }
            Distribution::Normal { mean, std, min, max } => loop {
                let z: f64 = StandardNormal.sample(rng);
                let v = mean + std * z;
                if (min..=max).contains(&v) {
                    return v;
                }
            },
            Distribution::Fixed { value } => value,
        }
    }
}

/// The checked distributions of a campaign's uncertain parameters ([`TOLERANCES`] order).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Plan {
    /// One per parameter.
    pub params: [Distribution; 5],
}

impl Plan {
    /// The plan of a scenario's `[campaign]` section around its values `base` of the
    /// uncertain parameters (display units, [`TOLERANCES`] order): the section's
    /// overrides, the thesis's tolerances elsewhere. Every bad entry is an error naming
    /// `campaign.<key>.<field>`, the value and what is allowed.
    pub fn new(campaign: Option<&CampaignSpec>, base: [f64; 5]) -> Result<Plan> {
        let none = CampaignSpec::default();
        let entries = campaign.unwrap_or(&none).entries();
        let mut params = [Distribution::Fixed { value: 0.0 }; 5];
        for (j, t) in TOLERANCES.iter().enumerate() {
            let b = base[j];
            let field = |f: &str| format!("campaign.{}.{f}", t.name);
            let default = ParamDistSpec::default();
            let e = entries[j].unwrap_or(&default);
            if e.distribution == DistributionKind::Fixed {
                if e.relative.is_some() || e.min.is_some() || e.max.is_some() || e.std_relative.is_some() {
                    return Err(invalid(
                        field("distribution"),
                        "\"fixed\" with a range or std_relative",
                        "`fixed` alone (the scenario's value is used)",
                    ));
                }
                params[j] = Distribution::Fixed { value: b };
                continue;
            }
            let (min, max) = match (e.relative, e.min, e.max) {
                (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
                    return Err(invalid(
                        field("relative"),
                        e.relative.unwrap_or_default(),
                        "either `relative` or `min` and `max`, not both",
                    ))
                }
                (r, None, None) => {
                    let r = r.unwrap_or(t.tolerance);
                    if !(r.is_finite() && r > 0.0 && r < 1.0) {
                        return Err(invalid(field("relative"), r, "a fraction in (0, 1)"));
                    }
                    (b * (1.0 - r), b * (1.0 + r))
                }
                (None, Some(lo), Some(hi)) => {
                    if !(lo.is_finite() && lo > 0.0) {
                        return Err(invalid(
                            field("min"),
                            lo,
                            format!("a number > 0 in the unit of plant.{}", t.name),
                        ));
                    }
                    if !(hi.is_finite() && hi > lo) {
                        return Err(invalid(field("max"), hi, format!("a finite number > min = {lo}")));
                    }
                    (lo, hi)
                }
                (None, lo, _) => {
                    let (f, v) = if lo.is_some() {
                        ("max", "missing")
                    } else {
                        ("min", "missing")
                    };
                    return Err(invalid(field(f), v, "`min` and `max` together"));
                }
            };
            params[j] = match e.distribution {
                DistributionKind::Uniform => {
                    if let Some(s) = e.std_relative {
                        return Err(invalid(
                            field("std_relative"),
                            s,
                            "only with distribution = \"normal\"",
                        ));
                    }
                    Distribution::Uniform { min, max }
                }
                DistributionKind::Normal => {
                    if !(min..=max).contains(&b) {
                        return Err(invalid(
                            field("min"),
                            min,
                            format!("a range [min, max] = [{min}, {max}] that holds the scenario's value plant.{} = {b} (the normal's mean)", t.name),
                        ));
                    }
                    let s = e.std_relative.unwrap_or((max - min) / (6.0 * b));
                    if !(s.is_finite() && s > 0.0 && s <= 1.0) {
                        return Err(invalid(field("std_relative"), s, "a fraction in (0, 1]"));
                    }
                    Distribution::Normal {
                        mean: b,
                        std: s * b,
                        min,
                        max,
                    }
                }
                DistributionKind::Fixed => unreachable!("handled above"),
            };
        }
        Ok(Plan { params })
    }

    /// Parameters that vary (not fixed, range wider than a point).
    pub fn varying(&self) -> Vec<usize> {
        (0..5)
            .filter(|&j| {
                let (lo, hi) = self.params[j].range();
                hi > lo
            })
            .collect()
    }

    /// Runs of a full-factorial corner campaign: 2 to the number of varying parameters.
    pub fn corner_runs(&self) -> u64 {
        1 << self.varying().len()
    }
}

/// How the runs' parameters are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sampling {
    /// Each parameter from its distribution.
    Random,
    /// Every corner of the ranges' box: bit k of the run index picks the lower (0) or
    /// upper (1) end of the k-th varying parameter.
    Corners,
}

/// The seed of run `index` of a campaign seeded `seed` (SplitMix64 of both): a run's
/// draw depends on nothing else.
pub fn run_seed(seed: u64, index: u64) -> u64 {
    let mut z = seed
        ^ index
            .wrapping_mul(0x9e37_79b9_7f4a_7c15)
            .wrapping_add(0x6a09_e667_f3bc_c909);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The parameter values of run `index` (display units, [`TOLERANCES`] order). Each
/// parameter draws from its own stream of the run's generator, so changing one
/// parameter's distribution leaves the others' draws as they were.
pub fn draw(plan: &Plan, seed: u64, index: u64, sampling: Sampling) -> [f64; 5] {
    let mut v = [0.0; 5];
    match sampling {
        Sampling::Random => {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(run_seed(seed, index));
            for (j, (vj, d)) in v.iter_mut().zip(&plan.params).enumerate() {
                rng.set_stream(j as u64);
                rng.set_word_pos(0);
                *vj = d.sample(&mut rng);
            }
        }
        Sampling::Corners => {
            for (j, d) in plan.params.iter().enumerate() {
                v[j] = d.range().0;
            }
            for (bit, j) in plan.varying().into_iter().enumerate() {
                let (lo, hi) = plan.params[j].range();
                v[j] = if index >> bit & 1 == 1 { hi } else { lo };
            }
        }
    }
    v
}
