//! The figures of a pump run, accumulated step by step on the solver's dense output:
//! the summary's types and the accumulator.

use super::ident_figures::{IdentReport, GAUSS};
use super::integrated::Integrated;
use super::scenario::{ScenarioSpec, SolverSettings};
use crate::plant::{P_LINE, STROKE};
use crate::signal::Signal;
use crate::units::*;
use rhonn_ode::Dopri5;
use serde::Serialize;

/// Deviations from the set-point are judged this long after each set-point change
/// (the start counts as one) for `max_abs_deviation_settled_mpa` \[s\].
pub const SETTLE_S: f64 = 1.0;

/// Solver settings and counters of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
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
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Regulation {
    /// max |p_line - p_ref| over the run \[MPa\].
    pub max_abs_deviation_mpa: f64,
    /// max |p_line - p_ref| from 1 s after each set-point change on \[MPa\].
    pub max_abs_deviation_settled_mpa: f64,
    /// Integral of (p_line - p_ref)^2 over the run \[MPa^2 s\].
    pub ise_mpa2_s: f64,
    /// Time with the current at 0 or at its maximum \[s\].
    pub time_current_saturated_s: f64,
    /// Whether every signal stayed bounded: pressure and stroke within their limits,
    /// the controller's output finite and in range, and (adaptive) every weight inside
    /// its projection ball (a non-finite value stops the run with an error instead).
    pub signals_bounded: bool,
}

/// The figures of a run (display units, named with their unit).
#[derive(Debug, Clone, PartialEq, Serialize)]
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
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    /// rhonn's version.
    pub rhonn_version: &'static str,
    /// The scenario as run.
    pub scenario: ScenarioSpec,
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
}

/// The PI baseline of an adaptive run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BaselineReport {
    /// Its kind (`pi`).
    pub controller: &'static str,
    /// Proportional gain \[A/MPa\].
    pub kp_a_per_mpa: f64,
    /// Integral time \[s\].
    pub ti_s: f64,
    /// Its run's figures.
    pub figures: Figures,
}

/// The adaptive controller against its baseline.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ControlReport {
    /// The adaptive controller's weights.
    pub adaptive: AdaptiveReport,
    /// The baseline.
    pub baseline: BaselineReport,
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

/// The run's figures, accumulated step by step on the solver's dense output, so that
/// they do not depend on the output interval: time-weighted figures are integrated
/// with 3-point Gauss-Legendre quadrature on each step (split where the set-point has a
/// breakpoint, at 1 s, and where a settling window ends), the time below P_min from
/// the located crossings, extremes from the step ends and the Gauss points.
pub(super) struct Accumulator<'a> {
    p_limit: f64,
    pub(super) p_max: f64,
    pub(super) x_max: f64,
    i_max: f64,
    setpoint: Option<&'a Signal>,
    /// Times where an interval must be split, sorted; `cursor` is the next one.
    splits: Vec<f64>,
    cursor: usize,
    /// Set-point breakpoints (sorted) for the settling windows.
    changes: Vec<f64>,
    p_lo: f64,
    p_hi: f64,
    x_hi: f64,
    below: f64,
    below_after_1s: f64,
    ise: f64,
    max_dev: f64,
    max_dev_settled: f64,
    saturated: f64,
}

impl<'a> Accumulator<'a> {
    pub(super) fn new(p_limit: f64, i_max: f64, setpoint: Option<&'a Signal>, t_end: f64) -> Self {
        let mut changes = vec![0.0];
        let mut splits = vec![1.0];
        if let Some(sp) = setpoint {
            let mut t = 0.0;
            loop {
                let b = sp.next_breakpoint(t);
                if !(b < t_end) {
                    break;
                }
                changes.push(b);
                t = b;
            }
            for &c in &changes {
                splits.push(c);
                splits.push(c + SETTLE_S);
            }
        }
        splits.retain(|&v| v > 0.0 && v < t_end);
        splits.sort_by(f64::total_cmp);
        splits.dedup();
        Accumulator {
            p_limit,
            p_max: f64::INFINITY,
            x_max: f64::INFINITY,
            i_max,
            setpoint,
            splits,
            cursor: 0,
            changes,
            p_lo: f64::INFINITY,
            p_hi: f64::NEG_INFINITY,
            x_hi: f64::NEG_INFINITY,
            below: 0.0,
            below_after_1s: 0.0,
            ise: 0.0,
            max_dev: 0.0,
            max_dev_settled: 0.0,
            saturated: 0.0,
        }
    }

    /// Account for the last step `[t_prev, t]` of `solver`.
    pub(super) fn add_step<S: Integrated>(&mut self, solver: &Dopri5<S>) {
        let (t0, t1) = (solver.t_prev(), solver.t());
        if !(t1 > t0) {
            return;
        }
        while self.cursor < self.splits.len() && self.splits[self.cursor] <= t0 {
            self.cursor += 1;
        }
        let mut a = t0;
        let mut k = self.cursor;
        while k < self.splits.len() && self.splits[k] < t1 {
            self.add_interval(solver, a, self.splits[k]);
            a = self.splits[k];
            k += 1;
        }
        self.add_interval(solver, a, t1);
    }

    /// `[a, b]` lies in one step, one set-point segment and one settling window.
    pub(super) fn add_interval<S: Integrated>(&mut self, solver: &Dopri5<S>, a: f64, b: f64) {
        let h = b - a;
        if !(h > 0.0) {
            return;
        }
        let prm = &solver.system().pump().params;
        let (dp, dx) = (solver.dense_component(P_LINE), solver.dense_component(STROKE));
        // The interpolant of a step that ends on a bound may pass it by a hair.
        let state = |t: f64| {
            let th = solver.theta_of(t);
            [dp.at(th).clamp(0.0, prm.p_max), dx.at(th).clamp(0.0, prm.x_max)]
        };
        let mid = 0.5 * (a + b);
        let seg = self.setpoint.map(|sp| (sp, sp.segment(mid)));
        let settled = seg.is_some() && {
            let last_change = self
                .changes
                .iter()
                .rev()
                .find(|&&c| c <= mid)
                .copied()
                .unwrap_or(0.0);
            mid >= last_change + SETTLE_S
        };
        let mut pts = [(a, 0.0); 5];
        let xa = state(a);
        pts[0] = (a, xa[P_LINE]);
        // Extremes in locals (the same comparisons in the same order), stored once.
        let mut x_hi = self.x_hi;
        for (j, (node, _)) in GAUSS.iter().enumerate() {
            let t = a + node * h;
            let x = state(t);
            pts[j + 1] = (t, x[P_LINE]);
            x_hi = x_hi.max(x[STROKE]);
        }
        let xb = state(b);
        pts[4] = (b, xb[P_LINE]);
        self.x_hi = x_hi.max(xb[STROKE]).max(xa[STROKE]);
        let (mut p_lo, mut p_hi) = (self.p_lo, self.p_hi);
        for &(_, p) in &pts {
            p_lo = p_lo.min(p);
            p_hi = p_hi.max(p);
        }
        (self.p_lo, self.p_hi) = (p_lo, p_hi);
        for &(t, p) in &pts {
            if let Some((sp, sg)) = seg {
                let dev = mpa((p - sp.eval_in(sg, t)).abs());
                self.max_dev = self.max_dev.max(dev);
                if settled {
                    self.max_dev_settled = self.max_dev_settled.max(dev);
                }
            }
        }
        if let Some((sp, sg)) = seg {
            self.ise += h * GAUSS
                .iter()
                .zip(&pts[1..4])
                .map(|((_, w), &(t, p))| w * mpa(p - sp.eval_in(sg, t)).powi(2))
                .sum::<f64>();
            let i = solver.system().pump().current_at(mid);
            if i <= 0.0 || i >= self.i_max {
                self.saturated += h;
            }
        }
        // Time below P_min: the sub-intervals between the five points, with the
        // crossings located by bisection on the dense output.
        let mut below = 0.0;
        for w in pts.windows(2) {
            let ((ta, pa), (tb, pb)) = (w[0], w[1]);
            let (ba, bb) = (pa < self.p_limit, pb < self.p_limit);
            if ba && bb {
                below += tb - ta;
            } else if ba != bb {
                let (mut lo, mut hi) = (ta, tb);
                while hi - lo > 1e-10 * (1.0 + hi.abs()) {
                    let m = 0.5 * (lo + hi);
                    if (state(m)[P_LINE] < self.p_limit) == ba {
                        lo = m;
                    } else {
                        hi = m;
                    }
                }
                let tc = 0.5 * (lo + hi);
                below += if ba { tc - ta } else { tb - tc };
            }
        }
        self.below += below;
        if a >= 1.0 {
            self.below_after_1s += below;
        }
    }

    pub(super) fn figures(
        &self,
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
            p_line_min_mpa: mpa(self.p_lo),
            p_line_max_mpa: mpa(self.p_hi),
            stroke_max_mm: mm(self.x_hi),
            time_below_p_min_s: self.below,
            time_below_p_min_after_1s_s: self.below_after_1s,
            regulation: regulated.then_some(Regulation {
                max_abs_deviation_mpa: self.max_dev,
                max_abs_deviation_settled_mpa: self.max_dev_settled,
                ise_mpa2_s: self.ise,
                time_current_saturated_s: self.saturated,
                signals_bounded: self.p_lo >= 0.0
                    && self.p_hi <= self.p_max * (1.0 + 1e-12)
                    && self.x_hi <= self.x_max * (1.0 + 1e-12),
            }),
        }
    }
}

/// What a run of the adaptive controller reports of its weights.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct AdaptiveReport {
    /// Largest |W| over the run (MPa/s units).
    pub w_norm_max: f64,
    /// |W| at the end.
    pub w_norm_final: f64,
    /// Largest |W_1 - centre| after the identification phase (MPa/(s mm) units).
    pub w1_distance_max: f64,
    /// Radius of W_1's ball.
    pub w1_ball_radius: f64,
    /// W_1 at the end.
    pub w1_final: Vec<f64>,
    /// Identifier substeps that ended with a projection.
    pub projections: u64,
    /// Radius of W's ball (around 0).
    pub w_bound: f64,
}
