//! Monte Carlo campaigns over the thesis's parameter tolerances (beta, mu_1, mu_2 +-20 %,
//! Q_0 +-10 %, demand slew +-10 %): each run's draw depends only on the campaign's seed
//! and the run's index, so a campaign gives the same rows whatever the thread count and
//! however it is sharded. A scenario's `[campaign]` section overrides a parameter's
//! distribution (uniform, truncated normal, fixed) and range. `rhonn campaign` adds the
//! files, the resume and the merge.

use super::run::{run_full, Summary};
use super::scenario::ScenarioSpec;
use super::trace::NoRecorder;
use crate::error::{invalid, Result};
use crate::signal::SignalSpec;
use rand::{Rng, SeedableRng};
use rand_distr::{Distribution as _, StandardNormal};
use serde::{Deserialize, Serialize};

/// The uncertain parameters a pump campaign draws: the pump's tolerance table.
pub use crate::plant::pump::PARAMETERS as TOLERANCES;

/// The scenario's values of the uncertain parameters (display units, [`TOLERANCES`] order).
pub fn base_values(spec: &ScenarioSpec) -> [f64; 5] {
    let p = &spec.plant;
    [p.beta_mpa, p.mu_1, p.mu_2, p.q_0_dm3_s, p.qdot_max_dm3_s2]
}

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
    /// The plan of `spec`: its `[campaign]` overrides, the thesis's tolerances elsewhere.
    /// Every bad entry is an error naming `campaign.<key>.<field>`, the value and what is
    /// allowed.
    pub fn of(spec: &ScenarioSpec) -> Result<Plan> {
        let base = base_values(spec);
        let none = CampaignSpec::default();
        let entries = spec.campaign.as_ref().unwrap_or(&none).entries();
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

/// The scenario of one run: the plant's uncertain parameters set to `values` (display
/// units); the slew's ratio to the scenario's value scales the demand trapezoids' slew
/// too. The noise and PRBS seeds are the scenario's, so runs differ only by their
/// parameters.
pub fn apply(spec: &ScenarioSpec, values: &[f64; 5]) -> ScenarioSpec {
    let mut s = spec.clone();
    let slew_ratio = values[4] / spec.plant.qdot_max_dm3_s2;
    s.plant.beta_mpa = values[0];
    s.plant.mu_1 = values[1];
    s.plant.mu_2 = values[2];
    s.plant.q_0_dm3_s = values[3];
    s.plant.qdot_max_dm3_s2 = values[4];
    if let Some(SignalSpec::Trapezoids { slew_per_s, .. }) = s.demand_dm3_s.as_mut() {
        *slew_per_s *= slew_ratio;
    }
    s
}

/// The names of the figures a run of `spec` reports, in `runs.csv` order.
pub fn figure_names(spec: &ScenarioSpec) -> Vec<String> {
    let mut v: Vec<String> = [
        "p_line_min_mpa",
        "p_line_max_mpa",
        "final_p_line_mpa",
        "stroke_max_mm",
        "time_below_p_min_after_1s_s",
    ]
    .map(String::from)
    .to_vec();
    if spec.controller.is_some() {
        v.extend(
            [
                "ise_mpa2_s",
                "max_abs_deviation_settled_mpa",
                "time_current_saturated_s",
                "iae_mpa_s",
                "within_1pct_percent",
            ]
            .map(String::from),
        );
    }
    if matches!(
        spec.controller,
        Some(super::scenario::ControllerSpec::RhonnAdaptive { .. })
    ) {
        v.extend(
            [
                "baseline_ise_mpa2_s",
                "baseline_max_abs_deviation_settled_mpa",
                "baseline_time_below_p_min_after_1s_s",
                "baseline_iae_mpa_s",
                "baseline_within_1pct_percent",
                "w_norm_max",
                "w1_distance_max",
            ]
            .map(String::from),
        );
    }
    if let Some(id) = &spec.identifier {
        for s in &id.states {
            v.push(format!("{s}_training_fit_percent"));
            v.push(format!("{s}_training_rms_error"));
        }
    }
    v
}

/// The figures of a run, in [`figure_names`] order.
pub fn figure_values(summary: &Summary) -> Vec<f64> {
    let f = &summary.figures;
    let mut v = vec![
        f.p_line_min_mpa,
        f.p_line_max_mpa,
        f.final_p_line_mpa,
        f.stroke_max_mm,
        f.time_below_p_min_after_1s_s,
    ];
    if let Some(r) = &f.regulation {
        v.extend([
            r.ise_mpa2_s,
            r.max_abs_deviation_settled_mpa,
            r.time_current_saturated_s,
            r.iae_mpa_s,
            r.within_1pct_percent,
        ]);
    }
    if let Some(c) = &summary.control {
        let b = &c.baseline.figures;
        let rb = b.regulation.as_ref();
        v.extend([
            rb.map_or(f64::NAN, |r| r.ise_mpa2_s),
            rb.map_or(f64::NAN, |r| r.max_abs_deviation_settled_mpa),
            b.time_below_p_min_after_1s_s,
            rb.map_or(f64::NAN, |r| r.iae_mpa_s),
            rb.map_or(f64::NAN, |r| r.within_1pct_percent),
            c.adaptive.w_norm_max,
            c.adaptive.w1_distance_max,
        ]);
    }
    if let Some(id) = &summary.identification {
        for s in &id.training {
            v.push(s.fit_percent);
            v.push(s.rms_error);
        }
    }
    v
}

/// One run's row: its index, parameter values, and figures or the reason it failed.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRow {
    /// Run index.
    pub index: u64,
    /// The drawn parameter values (display units, [`TOLERANCES`] order).
    pub values: [f64; 5],
    /// Figures, or the error's message.
    pub outcome: Result<Vec<f64>, String>,
}

/// Points of the envelope's time grid (at most).
pub const ENVELOPE_POINTS: usize = 600;

/// The envelope's time grid of a scenario: every `stride`-th output sample, so that the
/// grid has at most [`ENVELOPE_POINTS`] points. Returns `(stride, times [s])`.
pub fn envelope_grid(spec: &ScenarioSpec) -> (usize, Vec<f64>) {
    let n_out = (spec.duration_s / (spec.output_interval_ms / 1000.0))
        .round()
        .max(1.0) as u64;
    let samples = n_out as usize + 1;
    let stride = samples.div_ceil(ENVELOPE_POINTS).max(1);
    let times = (0..=n_out)
        .step_by(stride)
        .map(|k| {
            if k >= n_out {
                spec.duration_s
            } else {
                k as f64 * spec.output_interval_ms / 1000.0
            }
        })
        .collect();
    (stride, times)
}

/// A run's pressure on the envelope grid \[MPa\]: `p_line`, and in adaptive runs the PI
/// baseline's `p_line_pi`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RunTraces {
    /// Line pressure \[MPa\].
    pub p_line: Vec<f64>,
    /// The PI baseline's line pressure \[MPa\] (adaptive runs; empty otherwise).
    pub p_line_pi: Vec<f64>,
}

/// Keeps the pressures of the samples it is given (every `stride`-th output sample), up
/// to `points` of them; needs no validation runs' samples.
struct PressureSampler {
    stride: usize,
    points: usize,
    traces: RunTraces,
}

impl super::trace::Recorder for PressureSampler {
    fn record(&mut self, s: &super::trace::Sample) {
        if self.traces.p_line.len() < self.points {
            self.traces.p_line.push(s.p_line / crate::units::PA_PER_MPA);
            if let Some(b) = &s.baseline {
                self.traces.p_line_pi.push(b.p_line / crate::units::PA_PER_MPA);
            }
        }
    }
    fn stride(&self) -> u64 {
        self.stride as u64
    }
    fn wants_validation(&self) -> bool {
        false
    }
}

/// Run index `index` of a campaign over `spec` with parameters drawn from `plan`;
/// with `traces`, also the run's pressure on the [`envelope_grid`] (successful runs).
pub fn run_one(
    spec: &ScenarioSpec,
    plan: &Plan,
    seed: u64,
    index: u64,
    sampling: Sampling,
    traces: bool,
) -> (RunRow, Option<RunTraces>) {
    let values = draw(plan, seed, index, sampling);
    let sc = apply(spec, &values).check();
    let (outcome, tr) = if traces {
        let (stride, grid) = envelope_grid(spec);
        let mut rec = PressureSampler {
            stride,
            points: grid.len(),
            traces: RunTraces::default(),
        };
        let out = sc.and_then(|sc| run_full(&sc, &mut rec));
        let ok = out.is_ok();
        (out.map(|o| figure_values(&o.summary)), ok.then_some(rec.traces))
    } else {
        let out = sc.and_then(|sc| run_full(&sc, &mut NoRecorder));
        (out.map(|o| figure_values(&o.summary)), None)
    };
    (
        RunRow {
            index,
            values,
            outcome: outcome.map_err(|e| e.to_string()),
        },
        tr,
    )
}

/// The parameter values of run `index` of a plant campaign (display units, the plant's
/// order): each `base` value times `1 + tol U(-1, 1)` from the run's own generator, or
/// with `corners` the corner `index` of the box (bit k high: the k-th varying parameter
/// at its upper end).
pub fn draw_parameters(base: &[f64], tol: &[f64], seed: u64, index: u64, corners: bool) -> Vec<f64> {
    if corners {
        let mut bit = 0;
        return base
            .iter()
            .zip(tol)
            .map(|(b, t)| {
                if *t == 0.0 {
                    return *b;
                }
                let high = (index >> bit) & 1 == 1;
                bit += 1;
                b * (1.0 + if high { *t } else { -*t })
            })
            .collect();
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(run_seed(seed, index));
    base.iter()
        .zip(tol)
        .map(|(b, t)| b * (1.0 + t * (2.0 * rng.gen::<f64>() - 1.0)))
        .collect()
}

/// Type-7 quantile (linear interpolation between order statistics, numpy's default) of
/// sorted `v`; NaN when `v` is empty.
pub fn quantile_sorted(v: &[f64], p: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let h = p * (v.len() - 1) as f64;
    let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
    v[lo] + (h - lo as f64) * (v[hi] - v[lo])
}

/// The envelope of several traces on one grid: per point min, 5 % quantile, median,
/// 95 % quantile, max.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Envelope {
    /// Smallest value per point.
    pub min: Vec<f64>,
    /// 5 % quantile per point.
    pub q05: Vec<f64>,
    /// Median per point.
    pub median: Vec<f64>,
    /// 95 % quantile per point.
    pub q95: Vec<f64>,
    /// Largest value per point.
    pub max: Vec<f64>,
}

impl Envelope {
    /// The envelope of `traces` (each as long as the grid; shorter ones count where they
    /// have values).
    pub fn of(traces: &[&[f64]], points: usize) -> Envelope {
        let mut e = Envelope::default();
        let mut col = Vec::with_capacity(traces.len());
        for k in 0..points {
            col.clear();
            col.extend(
                traces
                    .iter()
                    .filter_map(|t| t.get(k))
                    .copied()
                    .filter(|x| x.is_finite()),
            );
            col.sort_by(f64::total_cmp);
            e.min.push(quantile_sorted(&col, 0.0));
            e.q05.push(quantile_sorted(&col, 0.05));
            e.median.push(quantile_sorted(&col, 0.5));
            e.q95.push(quantile_sorted(&col, 0.95));
            e.max.push(quantile_sorted(&col, 1.0));
        }
        e
    }
}

/// Distribution of one figure over the successful runs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FigureStats {
    /// Figure name.
    pub figure: String,
    /// Smallest value.
    pub min: f64,
    /// 5 % quantile.
    pub q05: f64,
    /// Median.
    pub median: f64,
    /// 95 % quantile.
    pub q95: f64,
    /// Largest value.
    pub max: f64,
    /// Mean.
    pub mean: f64,
}

/// Per figure statistics over `rows` (failed runs left out; NaN values left out).
pub fn statistics(names: &[String], rows: &[RunRow]) -> Vec<FigureStats> {
    names
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let mut v: Vec<f64> = rows
                .iter()
                .filter_map(|r| r.outcome.as_ref().ok().map(|f| f[k]))
                .filter(|x| x.is_finite())
                .collect();
            v.sort_by(f64::total_cmp);
            let q = |p: f64| quantile_sorted(&v, p);
            FigureStats {
                figure: name.clone(),
                min: q(0.0),
                q05: q(0.05),
                median: q(0.5),
                q95: q(0.95),
                max: q(1.0),
                mean: if v.is_empty() {
                    f64::NAN
                } else {
                    v.iter().sum::<f64>() / v.len() as f64
                },
            }
        })
        .collect()
}

#[cfg(test)]
#[path = "campaign_tests.rs"]
mod tests;
