//! Monte Carlo campaigns over the thesis's parameter tolerances (beta, mu_1, mu_2 +-20 %,
//! Q_0 +-10 %, demand slew +-10 %): each run's draw depends only on the campaign's seed
//! and the run's index, so a campaign gives the same rows whatever the thread count and
//! however it is sharded. A scenario's `[campaign]` section overrides a parameter's
//! distribution (uniform, truncated normal, fixed) and range. `rhonn campaign` adds the
//! files, the resume and the merge.

use super::pump_run::{run_full, Summary};
use super::pump_settings::PumpSettings;
use super::scenario::ScenarioSpec;
use super::trace::NoRecorder;
use crate::error::Result;
use crate::signal::SignalSpec;
use serde::Serialize;

pub use super::campaign_plan::*;

/// A pump scenario made ready for a campaign: its settings read once (`[plant] kind =
/// "pump"`) and its plan (the `[campaign]` distributions over the thesis's tolerances).
/// What a campaign's files need of the scenario is asked of it, so that every door holds
/// the one format's [`ScenarioSpec`].
#[derive(Debug, Clone, PartialEq)]
pub struct PumpCampaign {
    spec: PumpSettings,
    plan: Plan,
}

impl PumpCampaign {
    /// The campaign of a pump scenario, checked (`pump_settings` runs the runner's checks);
    /// `None` for any other plant's.
    pub fn of(scenario: &ScenarioSpec) -> Result<Option<PumpCampaign>> {
        let Some(spec) = scenario.pump_settings()? else {
            return Ok(None);
        };
        Ok(Some(PumpCampaign {
            plan: Plan::of(&spec)?,
            spec,
        }))
    }

    /// The scenario's name.
    pub fn name(&self) -> &str {
        &self.spec.name
    }

    /// Its plan: each uncertain parameter's distribution.
    pub fn plan(&self) -> Plan {
        self.plan.clone()
    }

    /// The scenario's values of the uncertain parameters (display units, [`TOLERANCES`] order).
    pub fn base_values(&self) -> [f64; 5] {
        base_values(&self.spec)
    }

    /// The scenario as its runner reads it, in the one format (`campaign.json`'s copy):
    /// parameters at the thesis's values left out, defaults written out.
    pub fn scenario(&self) -> ScenarioSpec {
        super::pump_scenario::raise(&self.spec)
    }

    /// The scenario of a run with the uncertain parameters at `values` ([`TOLERANCES`]
    /// order, display units; those not given keep the scenario's), named `name` (a worst
    /// run's file).
    pub fn run_scenario(&self, values: &[f64], name: String, description: String) -> ScenarioSpec {
        let mut v = self.base_values();
        for (a, b) in v.iter_mut().zip(values) {
            *a = *b;
        }
        let mut run = apply(&self.spec, &v);
        run.name = name;
        run.description = description;
        super::pump_scenario::raise(&run)
    }

    /// The names of the figures a run reports, in `runs.csv` order.
    pub fn figure_names(&self) -> Vec<String> {
        figure_names(&self.spec)
    }

    /// The envelope's time grid: `(stride, times [s])` ([`ENVELOPE_POINTS`] at most).
    pub fn envelope_grid(&self) -> (usize, Vec<f64>) {
        envelope_grid(&self.spec)
    }

    /// Run `index` of the campaign of `seed` (with `traces`, its pressures on the
    /// envelope's grid too).
    pub fn run_one(
        &self,
        seed: u64,
        index: u64,
        sampling: Sampling,
        traces: bool,
    ) -> (RunRow, Option<RunTraces>) {
        run_one(&self.spec, &self.plan, seed, index, sampling, traces)
    }

    /// The set-point on `grid` \[MPa\] (None for an open-loop scenario).
    pub fn setpoint_mpa(&self, grid: &[f64]) -> Result<Option<Vec<f64>>> {
        let sc = self.spec.check()?;
        Ok(sc.drive.setpoint().map(|sp| {
            grid.iter()
                .map(|&t| sp.eval(t) / crate::units::PA_PER_MPA)
                .collect()
        }))
    }

    /// P_min \[MPa\].
    pub fn p_min_mpa(&self) -> f64 {
        self.spec.plant.p_min_mpa
    }

    /// The kind of the adaptive controller's baseline, `"pi"` or `"cascade-pi"` (None
    /// without an adaptive controller).
    pub fn adaptive_baseline_kind(&self) -> Option<&'static str> {
        self.spec.adaptive_baseline_kind()
    }
}

/// The scenario's values of the uncertain parameters (display units, [`TOLERANCES`] order).
pub(crate) fn base_values(spec: &PumpSettings) -> [f64; 5] {
    spec.uncertain_values()
}

impl Plan {
    /// The plan of `spec`: its `[campaign]` overrides, the thesis's tolerances elsewhere
    /// ([`Plan::new`] over [`TOLERANCES`]).
    pub(crate) fn of(spec: &PumpSettings) -> Result<Plan> {
        let params: Vec<Uncertain> = TOLERANCES
            .iter()
            .zip(spec.uncertain_values())
            .map(|(t, value)| Uncertain {
                name: t.name,
                value,
                tolerance: t.tolerance,
            })
            .collect();
        Plan::new(spec.campaign.as_ref(), &params)
    }
}

/// The scenario of one run: the plant's uncertain parameters set to `values` (display
/// units); the slew's ratio to the scenario's value scales the demand trapezoids' slew
/// too. The noise and PRBS seeds are the scenario's, so runs differ only by their
/// parameters.
pub(crate) fn apply(spec: &PumpSettings, values: &[f64; 5]) -> PumpSettings {
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
pub(crate) fn figure_names(spec: &PumpSettings) -> Vec<String> {
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
                "current_total_variation_a",
            ]
            .map(String::from),
        );
    }
    let adaptive = spec
        .controller
        .as_ref()
        .filter(|c| matches!(c.controller, crate::control::LoopSpec::PumpRhonnAdaptive(_)));
    if adaptive.is_some() {
        v.extend(
            [
                "baseline_ise_mpa2_s",
                "baseline_max_abs_deviation_settled_mpa",
                "baseline_time_below_p_min_after_1s_s",
                "baseline_iae_mpa_s",
                "baseline_within_1pct_percent",
                "baseline_current_total_variation_a",
                "w_norm_max",
                "w1_distance_max",
            ]
            .map(String::from),
        );
    }
    if adaptive.is_some_and(|c| c.second_baseline.is_some()) {
        v.extend(SECOND_BASELINE_FIGURES.map(String::from));
    }
    if let Some(id) = &spec.identifier {
        for s in &id.states {
            v.push(format!("{s}_training_fit_percent"));
            v.push(format!("{s}_training_rms_error"));
        }
    }
    v
}

/// The second baseline's figures a campaign records.
const SECOND_BASELINE_FIGURES: [&str; 5] = [
    "second_baseline_ise_mpa2_s",
    "second_baseline_time_below_p_min_after_1s_s",
    "second_baseline_iae_mpa_s",
    "second_baseline_within_1pct_percent",
    "second_baseline_current_total_variation_a",
];

/// The figures of a run, in [`PumpCampaign::figure_names`] order.
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
            r.current_total_variation_a,
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
            rb.map_or(f64::NAN, |r| r.current_total_variation_a),
            c.adaptive.w_norm_max,
            c.adaptive.w1_distance_max,
        ]);
        if let Some(b) = &c.second_baseline {
            let r = b.figures.regulation.as_ref();
            v.extend([
                r.map_or(f64::NAN, |r| r.ise_mpa2_s),
                b.figures.time_below_p_min_after_1s_s,
                r.map_or(f64::NAN, |r| r.iae_mpa_s),
                r.map_or(f64::NAN, |r| r.within_1pct_percent),
                r.map_or(f64::NAN, |r| r.current_total_variation_a),
            ]);
        }
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
pub(crate) fn envelope_grid(spec: &PumpSettings) -> (usize, Vec<f64>) {
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
pub(crate) fn run_one(
    spec: &PumpSettings,
    plan: &Plan,
    seed: u64,
    index: u64,
    sampling: Sampling,
    traces: bool,
) -> (RunRow, Option<RunTraces>) {
    let mut values = [0.0; 5];
    values.copy_from_slice(&draw(plan, seed, index, sampling));
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
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
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
            let v: Vec<f64> = rows
                .iter()
                .filter_map(|r| r.outcome.as_ref().ok().map(|f| f[k]))
                .collect();
            figure_stats(name, v)
        })
        .collect()
}

/// One figure's statistics over the values of the runs that finished, in any order
/// (the non-finite ones are left out; quantiles by [`quantile_sorted`], the mean summed
/// in ascending order: the same figures whatever order the runs came in).
pub fn figure_stats(name: &str, mut v: Vec<f64>) -> FigureStats {
    v.retain(|x| x.is_finite());
    v.sort_by(f64::total_cmp);
    let q = |p: f64| quantile_sorted(&v, p);
    FigureStats {
        figure: name.to_string(),
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
}

#[cfg(test)]
#[path = "campaign_tests.rs"]
mod tests;
