//! A campaign's plan, for any plant: the `[campaign]` section of a scenario (a parameter's
//! distribution and range by its `[plant]` key), checked against the parameters a plant
//! draws ([`Uncertain`]: the pump's tolerance table, another plant's parameter table)
//! into a [`Plan`], and the draw of run k, which depends only on the campaign's seed and
//! k. Knows nothing of scenarios beyond the section and the values it is centred on.

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

impl ParamDistSpec {
    /// Uniform within the parameter's stated tolerance.
    const DEFAULT: ParamDistSpec = ParamDistSpec {
        distribution: DistributionKind::Uniform,
        relative: None,
        min: None,
        max: None,
        std_relative: None,
    };
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

/// A scenario's `[campaign]` section: overrides of the drawn parameters' distributions,
/// each by its `[plant]` key (`beta_mpa = { relative = 0.1 }`); a parameter left out keeps
/// uniform within the plant's stated tolerance (fixed when it states none).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(transparent)]
pub struct CampaignSpec(pub std::collections::BTreeMap<String, ParamDistSpec>);

/// A parameter a campaign may draw: its `[plant]` key, the scenario's value (display
/// units) and the plant's stated relative tolerance (0: none).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Uncertain<'a> {
    /// The `[plant]` key.
    pub name: &'a str,
    /// The scenario's value, display units.
    pub value: f64,
    /// Relative half-width of the stated tolerance band (0: none, not drawn by default).
    pub tolerance: f64,
}

/// A checked distribution of one parameter (display units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
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

/// The checked distributions of a campaign's parameters (the order of the plant's
/// [`Uncertain`] list).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Plan {
    /// One per parameter.
    pub params: Vec<Distribution>,
}

impl Plan {
    /// The plan of a scenario's `[campaign]` section over the parameters `params`: the
    /// section's overrides, each parameter's stated tolerance elsewhere. Every bad entry
    /// is an error naming `campaign.<key>.<field>`, the value and what is allowed; a key
    /// that is no drawn parameter names the plant's.
    pub fn new(campaign: Option<&CampaignSpec>, params: &[Uncertain]) -> Result<Plan> {
        let none = CampaignSpec::default();
        let entries = &campaign.unwrap_or(&none).0;
        if let Some(k) = entries
            .keys()
            .find(|k| !params.iter().any(|p| p.name == k.as_str()))
        {
            let names: Vec<&str> = params.iter().map(|p| p.name).collect();
            return Err(invalid(
                format!("campaign.{k}"),
                "a parameter",
                format!("one of the plant's parameters: {}", names.join(", ")),
            ));
        }
        let params = params
            .iter()
            .map(|t| distribution(t, entries.get(t.name)))
            .collect::<Result<_>>()?;
        Ok(Plan { params })
    }

    /// Parameters that vary (not fixed, range wider than a point).
    pub fn varying(&self) -> Vec<usize> {
        (0..self.params.len())
            .filter(|&j| {
                let (lo, hi) = self.params[j].range();
                hi > lo
            })
            .collect()
    }

    /// Runs of a full-factorial corner campaign: 2 to the number of varying parameters
    /// (`u64::MAX` past 63 of them, which the campaign's bound on runs refuses).
    pub fn corner_runs(&self) -> u64 {
        u32::try_from(self.varying().len())
            .ok()
            .and_then(|k| 1u64.checked_shl(k))
            .unwrap_or(u64::MAX)
    }
}

/// The distribution of parameter `t` by its `[campaign]` entry `e` (None: uniform within
/// its stated tolerance, fixed without one).
fn distribution(t: &Uncertain, e: Option<&ParamDistSpec>) -> Result<Distribution> {
    let b = t.value;
    let field = |f: &str| format!("campaign.{}.{f}", t.name);
    let Some(e) = e.or((t.tolerance > 0.0).then_some(&ParamDistSpec::DEFAULT)) else {
        return Ok(Distribution::Fixed { value: b });
    };
    if e.distribution == DistributionKind::Fixed {
        if e.relative.is_some() || e.min.is_some() || e.max.is_some() || e.std_relative.is_some() {
            return Err(invalid(
                field("distribution"),
                "\"fixed\" with a range or std_relative",
                "`fixed` alone (the scenario's value is used)",
            ));
        }
        return Ok(Distribution::Fixed { value: b });
    }
    let (min, max) = match (e.relative, e.min, e.max) {
        (Some(_), Some(_), _) | (Some(_), _, Some(_)) => {
            return Err(invalid(
                field("relative"),
                e.relative.unwrap_or_default(),
                "either `relative` or `min` and `max`, not both",
            ))
        }
        (None, None, None) if t.tolerance == 0.0 => {
            return Err(invalid(
                field("relative"),
                "missing",
                format!(
                    "a fraction in (0, 1), or `min` and `max` (plant.{} states no tolerance)",
                    t.name
                ),
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
            let f = if lo.is_some() { "max" } else { "min" };
            return Err(invalid(field(f), "missing", "`min` and `max` together"));
        }
    };
    Ok(match e.distribution {
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
        DistributionKind::Fixed => Distribution::Fixed { value: b },
    })
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

/// The parameter values of run `index` (display units, the plan's order). Each
/// parameter draws from its own stream of the run's generator, so changing one
/// parameter's distribution leaves the others' draws as they were.
pub fn draw(plan: &Plan, seed: u64, index: u64, sampling: Sampling) -> Vec<f64> {
    let mut v = vec![0.0; plan.params.len()];
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
