//! The figures of a pump run, accumulated step by step on the solver's dense output
//! (`regulation::Tracker`, any plant's): the summary's types.

pub use super::adaptive_report::AdaptiveReport;
use super::pump_ident_figures::IdentReport;
use super::pump_settings::{PumpSettings, SolverSettings};
use super::regulation::Tracker;
use crate::plant::{P_LINE, STROKE};
use crate::units::*;
use serde::Serialize;

pub use crate::plant::pump::SETTLE_S;

/// Solver settings and counters of a run.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct SolverReport {
    /// Settings.
    #[serde(flatten)]
    pub settings: SolverSettings,
    /// Right-hand-side evaluations (including event location).
    pub rhs_evaluations: u64,
    /// Accepted steps.
    pub accepted_steps: u64,
    /// Rejected steps.
    pub rejected_steps: u64,
    /// Events located (valve switching, bounds reached and left).
    pub events: u64,
    /// Steps landed on input breakpoints and control instants.
    pub breakpoints: u64,
}

/// Figures of a regulated run (display units).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Regulation {
    /// max |p_line - p_ref| over the run \[MPa\].
    pub max_abs_deviation_mpa: f64,
    /// max |p_line - p_ref| from 1 s after each set-point change on \[MPa\].
    pub max_abs_deviation_settled_mpa: f64,
    /// Integral of (p_line - p_ref)^2 over the run \[MPa^2 s\].
    pub ise_mpa2_s: f64,
    /// Time with the current at 0 or at its maximum \[s\].
    pub time_current_saturated_s: f64,
    /// Integral of |p_line - p_ref| over the run \[MPa s\].
    pub iae_mpa_s: f64,
    /// max |p - p_ref| from 0.1 s after each set-point change on \[MPa\].
    pub max_abs_deviation_after_0_1s_mpa: f64,
    /// Time with |p - p_ref| within 1 % of p_ref \[s\] (on the dense output, five points
    /// per solver step, crossings interpolated linearly).
    pub time_within_1pct_s: f64,
    /// Share of the run within 1 % of the set-point \[%\].
    pub within_1pct_percent: f64,
    /// Overshoot of each set-point step beyond its new value within the step's first
    /// second, in % of the step (0 when the pressure does not pass it).
    pub overshoot_percent: Vec<f64>,
    /// Whether every signal stayed bounded: pressure and stroke within their limits,
    /// the controller's output finite and in range, and (adaptive) every weight inside
    /// its projection ball (a non-finite value stops the run with an error instead).
    pub signals_bounded: bool,
    /// Sum of the applied current's changes over the control instants \[A\].
    pub current_total_variation_a: f64,
    /// RMS of the applied current's change per control period \[A\].
    pub current_rms_change_per_sample_a: f64,
    /// Time at 0 or the maximum current reached from the other bound within
    /// `activity::SWITCH_WINDOW` control periods (bang-bang) \[s\].
    pub time_current_switching_s: f64,
}

/// The figures of a run (display units, named with their unit).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Figures {
    /// Simulated time \[s\].
    pub duration_s: f64,
    /// Output samples.
    pub samples: usize,
    /// P_l at the end \[MPa\].
    pub final_p_line_mpa: f64,
    /// x at the end \[mm\].
    pub final_stroke_mm: f64,
    /// Lowest P_l \[MPa\].
    pub p_line_min_mpa: f64,
    /// Highest P_l \[MPa\].
    pub p_line_max_mpa: f64,
    /// Largest stroke \[mm\].
    pub stroke_max_mm: f64,
    /// Time with P_l below P_min, where the model is not valid \[s\].
    pub time_below_p_min_s: f64,
    /// Time with P_l below P_min after the first second \[s\].
    pub time_below_p_min_after_1s_s: f64,
    /// Regulated runs only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub regulation: Option<Regulation>,
}

/// What `summary.json` holds.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Summary {
    /// rhonn's version.
    pub rhonn_version: &'static str,
    /// The scenario as run, in the one scenario format.
    #[serde(serialize_with = "super::pump_scenario::serialize_raised")]
    #[schemars(with = "serde_json::Value")]
    pub(crate) scenario: PumpSettings,
    /// Solver settings and counters.
    pub solver: SolverReport,
    /// The run's figures.
    pub figures: Figures,
    /// Identified runs: per state and mode, RMS error, fit, convergence, weights.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub identification: Option<IdentReport>,
    /// Adaptive runs: the adaptive controller's weights, the PI baseline's figures
    /// (its plant is identical and sees the same noise) and the comparison.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub control: Option<ControlReport>,
    /// Warnings (also printed by the command).
    pub warnings: Vec<String>,
    /// A regulated run's figures in words (an adaptive run compares in `control`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub findings: Vec<String>,
}

impl Summary {
    /// The scenario's name.
    pub fn scenario_name(&self) -> &str {
        &self.scenario.name
    }

    /// The scenario as run, in the one format (what summary.json echoes).
    pub fn scenario(&self) -> super::ScenarioSpec {
        super::pump_scenario::raise(&self.scenario)
    }

    /// The plant's lowest allowed line pressure, P_min \[MPa\].
    pub fn p_min_mpa(&self) -> f64 {
        self.scenario.plant.p_min_mpa
    }
}

/// A regulated run's tracking and its actuator's activity, in words.
pub(super) fn regulation_findings(controller: &str, r: &Regulation) -> Vec<String> {
    let sig = crate::metrics::sig;
    vec![
        format!(
            "{controller}: the line pressure stays within 1 % of the set-point {} % of the run; IAE {} MPa s; largest deviation from 1 s after each set-point change {} MPa",
            sig(r.within_1pct_percent, 3),
            sig(r.iae_mpa_s, 4),
            sig(r.max_abs_deviation_settled_mpa, 3)
        ),
        format!(
            "{controller}: the current moved {} A in all (RMS change per control period {} A), at 0 or its maximum {} s, switching between them {} s",
            sig(r.current_total_variation_a, 4),
            sig(r.current_rms_change_per_sample_a, 3),
            sig(r.time_current_saturated_s, 3),
            sig(r.time_current_switching_s, 3)
        ),
    ]
}

/// The baseline of an adaptive run.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct BaselineReport {
    /// Its kind (`cascade-pi` or `pi`).
    pub controller: &'static str,
    /// Its tuning's name (`nominal-optimal`, `robust`), for a second baseline.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tuning: Option<&'static str>,
    /// The PI's proportional gain \[A/MPa\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kp_a_per_mpa: Option<f64>,
    /// The cascade PI's outer proportional gain \[mm/MPa\].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kp_mm_per_mpa: Option<f64>,
    /// Integral time \[s\].
    pub ti_s: f64,
    /// The cascade PI's set-point weight.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub setpoint_weight: Option<f64>,
    /// The cascade PI's stroke gain.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stroke_gain: Option<f64>,
    /// Its run's figures.
    pub figures: Figures,
}

impl BaselineReport {
    /// The baseline's settings, as the scenario gives them, and its figures.
    pub fn of(b: &super::pump_controllers::PumpLoop, figures: Figures) -> Self {
        use crate::control::LoopSpec;
        let mut r = BaselineReport {
            controller: b.name(),
            tuning: None,
            kp_a_per_mpa: None,
            kp_mm_per_mpa: None,
            ti_s: 0.0,
            setpoint_weight: None,
            stroke_gain: None,
            figures,
        };
        match &b.controller {
            LoopSpec::Pi(l) => {
                r.kp_a_per_mpa = Some(l.kp);
                r.ti_s = l.ti_s;
            }
            LoopSpec::PumpCascadePi(l) => {
                r.kp_mm_per_mpa = Some(l.kp_mm_per_mpa);
                r.ti_s = l.ti_s;
                r.setpoint_weight = Some(l.setpoint_weight);
                r.stroke_gain = Some(l.stroke_gain);
            }
            _ => {}
        }
        r
    }

    /// Its gains in words, e.g. `cascade-pi (kp 1 mm/MPa, ti 0.2 s, b 0.6, g 2)`.
    pub fn describe(&self) -> String {
        match (self.kp_a_per_mpa, self.kp_mm_per_mpa) {
            (Some(kp), _) => format!("{} (kp {kp} A/MPa, ti {} s)", self.controller, self.ti_s),
            (None, Some(kp)) => format!(
                "{} (kp {kp} mm/MPa, ti {} s, b {}, g {})",
                self.controller,
                self.ti_s,
                self.setpoint_weight.unwrap_or(1.0),
                self.stroke_gain.unwrap_or(0.0)
            ),
            (None, None) => self.controller.to_string(),
        }
    }
}

/// The adaptive controller against its baseline.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct ControlReport {
    /// The adaptive controller's weights.
    pub adaptive: AdaptiveReport,
    /// The baseline.
    pub baseline: BaselineReport,
    /// The second baseline (`second_baseline`), when run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub second_baseline: Option<BaselineReport>,
    /// One line per figure: which controller did better, with both numbers.
    pub findings: Vec<String>,
}

impl ControlReport {
    /// Whether the adaptive controller has a lower ISE and a lower settled maximum
    /// deviation than the baseline, and no more time below P_min after the start.
    pub fn adaptive_better(&self, adaptive: &Figures) -> bool {
        let (a, b) = (
            adaptive.regulation.as_ref(),
            self.baseline.figures.regulation.as_ref(),
        );
        match (a, b) {
            (Some(a), Some(b)) => {
                a.ise_mpa2_s < b.ise_mpa2_s
                    && a.max_abs_deviation_settled_mpa < b.max_abs_deviation_settled_mpa
                    && adaptive.time_below_p_min_after_1s_s
                        <= self.baseline.figures.time_below_p_min_after_1s_s
            }
            _ => false,
        }
    }
}

/// One line per figure of an adaptive run against its baseline `base`: both numbers and
/// which is better.
pub(super) fn comparison(fa: &Figures, fb: &Figures, base: &str) -> Vec<String> {
    let (Some(ra), Some(rb)) = (&fa.regulation, &fb.regulation) else {
        return Vec::new();
    };
    let line = |what: &str, va: f64, vb: f64, unit: &str, lower_better: bool| {
        let verdict = if va == vb {
            "equal".to_string()
        } else if (va < vb) == lower_better {
            "adaptive better".to_string()
        } else {
            format!("{base} better")
        };
        format!("{what}: adaptive {va:.3} {unit}, {base} {vb:.3} {unit} ({verdict})")
    };
    let over = |r: &Regulation| r.overshoot_percent.iter().fold(0.0f64, |a, &b| a.max(b));
    vec![
        line("IAE", ra.iae_mpa_s, rb.iae_mpa_s, "MPa s", true),
        line("ISE", ra.ise_mpa2_s, rb.ise_mpa2_s, "MPa^2 s", true),
        line(
            "max |p - p_ref| from 0.1 s after each set-point change",
            ra.max_abs_deviation_after_0_1s_mpa,
            rb.max_abs_deviation_after_0_1s_mpa,
            "MPa",
            true,
        ),
        line(
            "max |p - p_ref| from 1 s after each set-point change",
            ra.max_abs_deviation_settled_mpa,
            rb.max_abs_deviation_settled_mpa,
            "MPa",
            true,
        ),
        line(
            "largest overshoot of a set-point step",
            over(ra),
            over(rb),
            "%",
            true,
        ),
        line(
            "share of the run within 1 % of the set-point",
            ra.within_1pct_percent,
            rb.within_1pct_percent,
            "%",
            false,
        ),
        line(
            "time below P_min after the first second",
            fa.time_below_p_min_after_1s_s,
            fb.time_below_p_min_after_1s_s,
            "s",
            true,
        ),
        line(
            "time with the current saturated",
            ra.time_current_saturated_s,
            rb.time_current_saturated_s,
            "s",
            true,
        ),
        line(
            "actuator activity: total variation of the applied current",
            ra.current_total_variation_a,
            rb.current_total_variation_a,
            "A",
            true,
        ),
        line(
            "actuator activity: RMS change of the current per control period",
            ra.current_rms_change_per_sample_a,
            rb.current_rms_change_per_sample_a,
            "A",
            true,
        ),
        line(
            "time switching the current between 0 and its maximum",
            ra.time_current_switching_s,
            rb.time_current_switching_s,
            "s",
            true,
        ),
    ]
}

/// The pump's figures from its run's [`Tracker`] (pressure, stroke, current): the
/// accumulator of every plant, here in MPa and mm.
pub(super) fn figures_of(
    acc: &Tracker,
    duration_s: f64,
    samples: usize,
    last: [f64; 2],
    regulated: bool,
) -> Figures {
    Figures {
        duration_s,
        samples,
        final_p_line_mpa: mpa(last[P_LINE]),
        final_stroke_mm: mm(last[STROKE]),
        p_line_min_mpa: mpa(acc.lo[P_LINE]),
        p_line_max_mpa: mpa(acc.hi[P_LINE]),
        stroke_max_mm: mm(acc.hi[STROKE]),
        time_below_p_min_s: acc.below,
        time_below_p_min_after_1s_s: acc.below_after_settle,
        regulation: regulated.then_some(Regulation {
            max_abs_deviation_mpa: acc.max_dev,
            max_abs_deviation_settled_mpa: acc.max_dev_settled,
            ise_mpa2_s: acc.ise,
            time_current_saturated_s: acc.saturated,
            iae_mpa_s: acc.iae,
            max_abs_deviation_after_0_1s_mpa: acc.max_dev_0_1,
            time_within_1pct_s: acc.within,
            within_1pct_percent: 100.0 * acc.within / duration_s,
            overshoot_percent: acc.steps.iter().map(|s| s.3).collect(),
            signals_bounded: acc.states_bounded(),
            // Set from the control instants' commands by the run (pump_loop).
            current_total_variation_a: 0.0,
            current_rms_change_per_sample_a: 0.0,
            time_current_switching_s: 0.0,
        }),
    }
}
