//! The trade between tracking and actuator activity (issue: an adaptive controller must not
//! buy its IAE with the valve): each controller setting run on a pump scenario, scored by
//! IAE and by the current's total variation, and the front of the settings no other beats
//! on both. The cascade PI's gains and the adaptive controller's closed-loop pole are the
//! knobs swept (`examples/control_front.rs` of this crate prints and plots them).

use crate::tuning::{grid, with_cascade_pi};
use rayon::prelude::*;
use rhonn::control::LoopSpec;
use rhonn::experiment::{CascadePiGainsMpa, ScenarioSpec, NOMINAL_OPTIMAL};

/// One setting's run.
#[derive(Debug, Clone, PartialEq)]
pub struct FrontPoint {
    /// `cascade-pi` or `rhonn-adaptive`.
    pub controller: &'static str,
    /// Its setting in words (`kp 0.3 mm/MPa, ti 0.07 s, b 0.8, g 8`; `lambda 100 1/s`).
    pub setting: String,
    /// IAE \[MPa s\] (infinite when the run failed).
    pub iae_mpa_s: f64,
    /// Total variation of the solenoid current over the control instants \[A\] (infinite
    /// when the run failed).
    pub current_total_variation_a: f64,
    /// Share of the run within 1 % of the set-point \[%\].
    pub within_1pct_percent: f64,
}

fn point(controller: &'static str, setting: String, spec: &ScenarioSpec) -> FrontPoint {
    // The front reads the controller's own figures: a second baseline would only cost a run.
    let mut spec = spec.clone();
    if let Some(c) = &mut spec.control {
        c.second_baseline = None;
    }
    let r = spec
        .run_summary()
        .ok()
        .and_then(|s| s.control)
        .and_then(|c| c.into_iter().next());
    FrontPoint {
        controller,
        setting,
        iae_mpa_s: r.as_ref().map_or(f64::INFINITY, |r| r.iae),
        current_total_variation_a: r.as_ref().map_or(f64::INFINITY, |r| r.input_total_variation),
        within_1pct_percent: r.as_ref().map_or(0.0, |r| r.within_1pct_percent),
    }
}

/// The cascade PI gain sets the front is drawn from (1,540): kp 0.1-3 mm/MPa, ti 0.03-0.3
/// s, set-point weight 0.2-1, stroke gain 1-8.
pub fn cascade_grid() -> Vec<CascadePiGainsMpa> {
    grid(
        &[0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0],
        &[0.03, 0.05, 0.07, 0.1, 0.15, 0.2, 0.3],
        &[0.2, 0.4, 0.6, 0.8, 1.0],
        &[1.0, 2.0, 4.0, 8.0],
    )
}

/// Each cascade PI gain set of `gains` as the only controller of `spec` (an adaptive
/// scenario: its set-points, demand, noise, seed and plant), on every core.
pub fn cascade_points(spec: &ScenarioSpec, gains: &[CascadePiGainsMpa]) -> Vec<FrontPoint> {
    gains
        .par_iter()
        .map(|g| {
            let setting = format!(
                "kp {} mm/MPa, ti {} s, b {}, g {}",
                g.kp_mm_per_mpa, g.ti_s, g.setpoint_weight, g.stroke_gain
            );
            point("cascade-pi", setting, &with_cascade_pi(spec, *g))
        })
        .collect()
}

impl FrontPoint {
    /// Whether this run beats `other`: a lower IAE at no more current total variation (how
    /// the adaptive controller is judged against the nominal-optimal cascade PI).
    pub fn beats(&self, other: &FrontPoint) -> bool {
        self.iae_mpa_s < other.iae_mpa_s && self.current_total_variation_a <= other.current_total_variation_a
    }
}

/// The nominal-optimal cascade PI on each of `cases` (a name and an adaptive scenario, e.g.
/// the robustness study's), on every core: the baseline each case's adaptive run is judged
/// against.
pub fn nominal_optimal_points(cases: &[(String, ScenarioSpec)]) -> Vec<FrontPoint> {
    let pi = cases
        .iter()
        .map(|(n, s)| (n.clone(), with_cascade_pi(s, NOMINAL_OPTIMAL)))
        .collect();
    points("cascade-pi", pi)
}

/// How many of `runs` beat the run of the same index in `baselines` ([`FrontPoint::beats`]).
pub fn wins(runs: &[FrontPoint], baselines: &[FrontPoint]) -> usize {
    runs.iter().zip(baselines).filter(|(a, b)| a.beats(b)).count()
}

/// Each of `variants` (a setting in words and its scenario) run for `controller`, on every
/// core.
pub fn points(controller: &'static str, variants: Vec<(String, ScenarioSpec)>) -> Vec<FrontPoint> {
    variants
        .into_par_iter()
        .map(|(setting, s)| point(controller, setting, &s))
        .collect()
}

/// `spec`'s adaptive controller with its closed-loop pole set to each of `lambdas_per_s`
/// (the rest of its settings as they are), on every core. A scenario without an adaptive
/// controller gives no points.
pub fn adaptive_points(spec: &ScenarioSpec, lambdas_per_s: &[f64]) -> Vec<FrontPoint> {
    lambdas_per_s
        .par_iter()
        .filter_map(|&l| {
            let mut s = spec.clone();
            match s.control.as_mut().map(|c| &mut c.controller) {
                Some(LoopSpec::PumpRhonnAdaptive(a)) => a.lambda_per_s = Some(l),
                _ => return None,
            }
            Some(point("rhonn-adaptive", format!("lambda {l} 1/s"), &s))
        })
        .collect()
}

/// Indices of the points no other point beats on both IAE and current total variation
/// (lower is better on both; a failed run is never on it), by increasing total variation.
pub fn pareto(points: &[FrontPoint]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..points.len())
        .filter(|&k| points[k].iae_mpa_s.is_finite() && points[k].current_total_variation_a.is_finite())
        .collect();
    idx.sort_by(|&a, &b| {
        let (p, q) = (&points[a], &points[b]);
        p.current_total_variation_a
            .total_cmp(&q.current_total_variation_a)
            .then(p.iae_mpa_s.total_cmp(&q.iae_mpa_s))
    });
    let mut front = Vec::new();
    let mut best = f64::INFINITY;
    for k in idx {
        if points[k].iae_mpa_s < best {
            best = points[k].iae_mpa_s;
            front.push(k);
        }
    }
    front
}

/// The lowest IAE among `points` whose current total variation is at most `tv_a` (None:
/// every such point failed, or none moves the current that little).
pub fn best_iae_within(points: &[FrontPoint], tv_a: f64) -> Option<&FrontPoint> {
    points
        .iter()
        .filter(|p| p.current_total_variation_a <= tv_a && p.iae_mpa_s.is_finite())
        .min_by(|a, b| a.iae_mpa_s.total_cmp(&b.iae_mpa_s))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(iae: f64, tv: f64) -> FrontPoint {
        FrontPoint {
            controller: "x",
            setting: String::new(),
            iae_mpa_s: iae,
            current_total_variation_a: tv,
            within_1pct_percent: 0.0,
        }
    }

    #[test]
    fn the_front_keeps_the_points_nothing_beats_on_both() {
        let pts = [
            p(10.0, 100.0),
            p(12.0, 50.0),
            p(11.0, 120.0),
            p(9.0, 300.0),
            p(f64::INFINITY, 1.0),
        ];
        assert_eq!(pareto(&pts), [1, 0, 3]);
        assert_eq!(best_iae_within(&pts, 110.0).unwrap().iae_mpa_s, 10.0);
        assert!(best_iae_within(&pts, 40.0).is_none());
    }
}
