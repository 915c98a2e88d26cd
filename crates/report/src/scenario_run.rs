//! A scenario's run on either runner (`rhonn::experiment::ScenarioRun`) written, printed
//! and given to Python the same way: the one place of this crate that tells the pump's
//! runner from the generic one.

use crate::Result;
use rhonn::experiment::{PlantRunOutput, RunOutput, ScenarioRun};
use std::path::{Path, PathBuf};

/// Write the run's folder (trajectory.csv, summary.json, plots; all or nothing); returns
/// the files.
pub fn write_scenario_run(dir: &Path, run: &ScenarioRun) -> Result<Vec<PathBuf>> {
    match run {
        ScenarioRun::Pump { trace, output, .. } => crate::write_run(dir, trace, output),
        ScenarioRun::Plant(o) => crate::write_plant_run(dir, o),
    }
}

/// summary.json's content as compact JSON text.
pub fn summary_json(run: &ScenarioRun) -> Result<String> {
    match run {
        ScenarioRun::Pump { output, .. } => serde_json::to_string(&output.summary),
        ScenarioRun::Plant(o) => serde_json::to_string(&o.summary),
    }
    .map_err(|e| crate::Error::Input(format!("cannot write the summary as JSON: {e}")))
}

/// The figures `rhonn run` prints.
pub fn run_lines(run: &ScenarioRun) -> Vec<String> {
    match run {
        ScenarioRun::Pump { output, .. } => pump_lines(output),
        ScenarioRun::Plant(o) => plant_lines(o),
    }
}

fn pump_lines(output: &RunOutput) -> Vec<String> {
    let summary = &output.summary;
    let f = &summary.figures;
    let mut lines = Vec::new();
    let l = &mut lines;
    l.push(format!(
        "{}: {} s simulated, {} samples",
        summary.scenario_name(),
        f.duration_s,
        f.samples
    ));
    l.push(format!(
        "  line pressure: final {:.3} MPa, min {:.3} MPa, max {:.3} MPa; below P_min for {:.3} s ({:.3} s after the first second)",
        f.final_p_line_mpa, f.p_line_min_mpa, f.p_line_max_mpa, f.time_below_p_min_s, f.time_below_p_min_after_1s_s
    ));
    l.push(format!(
        "  stroke: final {:.4} mm, max {:.4} mm",
        f.final_stroke_mm, f.stroke_max_mm
    ));
    if let Some(r) = &f.regulation {
        l.push(format!(
            "  regulation: max |p - p_ref| {:.3} MPa ({:.3} MPa from 1 s after each set-point change), ISE {:.3} MPa^2 s, current saturated {:.3} s",
            r.max_abs_deviation_mpa, r.max_abs_deviation_settled_mpa, r.ise_mpa2_s, r.time_current_saturated_s
        ));
        l.push(format!(
            "  actuator activity: the current moved {} A in all (total variation; RMS change per control period {} A), switching between 0 and its maximum {} s",
            rhonn::metrics::sig(r.current_total_variation_a, 4),
            rhonn::metrics::sig(r.current_rms_change_per_sample_a, 3),
            rhonn::metrics::sig(r.time_current_switching_s, 3)
        ));
    }
    if let Some(id) = &summary.identification {
        l.extend(id.to_string().lines().map(|line| format!("  {line}")));
    }
    if let Some(c) = &summary.control {
        l.push(format!(
            "  RHONN adaptive vs the baseline {}{} on an identical plant:",
            c.baseline.describe(),
            c.second_baseline.as_ref().map_or(String::new(), |b| format!(
                " and the second baseline {}, its {} tuning",
                b.describe(),
                b.tuning.unwrap_or("second")
            ))
        ));
        l.extend(c.findings.iter().map(|line| format!("    {line}")));
        l.push(format!(
            "    weights: |W| max {:.1}, |W_1 - centre| max {:.2} within the ball's radius {:.2}, {} projections",
            c.adaptive.w_norm_max, c.adaptive.w1_distance_max, c.adaptive.w1_ball_radius, c.adaptive.projections
        ));
        if let (Some(lag_ms), Some(ratio)) = (c.adaptive.actuator_lag_ms, c.adaptive.pilot_flow_ratio) {
            l.push(format!(
                "    actuator identified online: lag {} ms, pilot valve flow {} x the nominal valve's",
                rhonn::metrics::sig(lag_ms, 3),
                rhonn::metrics::sig(ratio, 3)
            ));
        }
    }
    let s = &summary.solver;
    l.push(format!(
        "  solver: {} rhs evaluations, {} accepted and {} rejected steps, {} events",
        s.rhs_evaluations, s.accepted_steps, s.rejected_steps, s.events
    ));
    lines
}

fn plant_lines(output: &PlantRunOutput) -> Vec<String> {
    let mut lines = Vec::new();
    let s = &output.summary;
    lines.push(format!(
        "{}: {} s simulated, plant {}",
        s.scenario, output.duration_s, s.plant
    ));
    for f in s.identification.iter().flatten() {
        let mut line = format!(
            "  {}: online (second half) rms error {:.3} {}, fit {:.1} %",
            f.state, f.training_rms_error, f.unit, f.training_fit_percent
        );
        match (f.validation_rms_error, f.validation_fit_percent, f.series_parallel_fit_percent) {
            (Some(r), Some(p), Some(sp)) => {
                line += &format!(
                    "; frozen on the training inputs: series-parallel fit {sp:.1} %, free run rms error {r:.3} {}, fit {p:.1} %",
                    f.unit
                )
            }
            (Some(r), Some(p), None) => {
                line += &format!(
                    "; frozen, free run on the validation inputs: rms error {r:.3} {}, fit {p:.1} %",
                    f.unit
                )
            }
            _ => {}
        }
        lines.push(line);
    }
    if let (Some(c), Some((state, unit))) = (&s.control, s.regulated) {
        for f in c {
            lines.push(format!(
                "  {:<14} {state}: IAE {:.1} {unit} s, ISE {:.0} {unit}^2 s, final error {:.3} {unit}, input saturated {:.0} s",
                f.controller, f.iae, f.ise, f.final_error, f.time_input_saturated_s
            ));
        }
    }
    lines.extend(s.findings.iter().map(|f| format!("  finding: {f}")));
    lines
}

/// `rhonn campaign` on a scenario into `dir` (resumes a folder left by
/// an interrupted one): the pump's campaign (its tolerances, envelopes) or a plant's.
pub fn run_scenario_campaign(
    sc: &rhonn::experiment::ScenarioSpec,
    o: &crate::campaign::CampaignOptions,
    dir: &Path,
    progress: &(dyn Fn(crate::campaign::Progress) + Sync),
) -> Result<crate::campaign::CampaignOutcome> {
    match rhonn::experiment::campaign::PumpCampaign::of(sc)? {
        Some(spec) => crate::campaign::run_campaign(&spec, o, dir, progress),
        None => crate::plant_campaign::run_plant_campaign(sc, o, dir, progress),
    }
}
