//! A scenario's run (`rhonn::experiment::PlantRunOutput`, whatever the plant) written,
//! printed and given to Python the same way.

use crate::Result;
use rhonn::experiment::{IdentStateFigures, LoopFigures, PlantRunOutput, PlantSummary};
use rhonn::metrics::sig;
use std::path::{Path, PathBuf};

/// Write the run's folder (trajectory.csv, summary.json, plots; all or nothing); returns
/// the files.
pub fn write_scenario_run(dir: &Path, run: &PlantRunOutput) -> Result<Vec<PathBuf>> {
    crate::write_plant_run(dir, run)
}

/// summary.json's content as compact JSON text.
pub fn summary_json(run: &PlantRunOutput) -> Result<String> {
    serde_json::to_string(&run.summary)
        .map_err(|e| crate::Error::Input(format!("cannot write the summary as JSON: {e}")))
}

/// The figures `rhonn run` prints.
pub fn run_lines(output: &PlantRunOutput) -> Vec<String> {
    let mut lines = Vec::new();
    let s = &output.summary;
    lines.push(format!(
        "{}: {} s simulated, plant {}",
        s.scenario,
        sig(output.duration_s, 6),
        s.plant
    ));
    if let Some(f) = &s.floor {
        lines.push(format!(
            "  {}: below the plant's floor ({} {u}) for {} s ({} s after the first {} s)",
            f.state,
            sig(f.floor, 4),
            sig(f.time_below_s, 4),
            sig(f.time_below_after_settle_s, 4),
            sig(f.settle_s, 3),
            u = f.unit
        ));
    }
    lines.extend(s.identification.iter().flatten().map(ident_line));
    if let (Some(c), Some((state, unit))) = (&s.control, s.regulated) {
        lines.extend(c.iter().flat_map(|f| loop_lines(f, state, unit)));
    }
    lines.extend(s.findings.iter().map(|f| format!("  finding: {f}")));
    lines.push(solver_line(s));
    lines
}

/// One identified state's figures: while learning and frozen, and its convergence.
fn ident_line(f: &IdentStateFigures) -> String {
    let mut line = format!(
        "  {}: online (second half) rms error {} {u}, fit {:.1} %",
        f.state,
        sig(f.training_rms_error, 4),
        f.training_fit_percent,
        u = f.unit
    );
    match (f.validation_rms_error, f.validation_fit_percent, f.series_parallel_fit_percent) {
        (Some(r), Some(p), Some(sp)) => {
            line += &format!(
                "; frozen on the training inputs: series-parallel fit {sp:.1} %, free run rms error {} {}, fit {p:.1} %",
                sig(r, 4),
                f.unit
            )
        }
        (Some(r), Some(p), None) => {
            line += &format!(
                "; frozen, free run on the validation inputs: rms error {} {}, fit {p:.1} %",
                sig(r, 4),
                f.unit
            )
        }
        _ => {}
    }
    let t = &f.whole_run.training;
    line += &match t.convergence_time_s {
        Some(c) => format!(
            "; its error within +-{} {} (1 % of the range) from {} s on",
            sig(t.convergence_band, 3),
            f.unit,
            sig(c, 3)
        ),
        None => format!(
            "; its error leaves +-{} {} (1 % of the range) until the end",
            sig(t.convergence_band, 3),
            f.unit
        ),
    };
    line
}

/// One loop's tracking and activity, and an adaptive controller's weights.
fn loop_lines(f: &LoopFigures, state: &str, unit: &str) -> Vec<String> {
    let mut v = vec![format!(
        "  {:<14} {state}: IAE {} {unit} s, ISE {} {unit}^2 s, within 1 % {} % of the run, final error {} {unit}, input saturated {} s",
        f.label(),
        sig(f.iae, 4),
        sig(f.ise, 4),
        sig(f.within_1pct_percent, 3),
        sig(f.final_error, 3),
        sig(f.time_input_saturated_s, 3)
    )];
    if let Some(a) = &f.adaptive {
        v.push(format!(
            "  {:<14} weights: |W| max {}, |W_1 - centre| max {} within the ball's radius {}, {} projections",
            "",
            sig(a.w_norm_max, 3),
            sig(a.w1_distance_max, 3),
            sig(a.w1_ball_radius, 3),
            a.projections
        ));
        if let (Some(lag_ms), Some(ratio)) = (a.actuator_lag_ms, a.pilot_flow_ratio) {
            v.push(format!(
                "  {:<14} actuator identified online: lag {} ms, pilot valve flow {} x the nominal valve's",
                "",
                sig(lag_ms, 3),
                sig(ratio, 3)
            ));
        }
    }
    v
}

fn solver_line(s: &PlantSummary) -> String {
    let v = &s.solver;
    format!(
        "  solver: {} rhs evaluations, {} accepted and {} rejected steps, {} events",
        v.rhs_evaluations, v.accepted_steps, v.rejected_steps, v.events
    )
}
