//! `rhonn run`, `rhonn reproduce`, `rhonn bench` and `rhonn show`: scenarios.

use super::{context, Outcome};
use crate::{Error, Result};
use rhonn::experiment::{preset, run_full, PlantScenarioSpec, Trace};
use std::path::{Path, PathBuf};

/// The scenarios `rhonn reproduce` runs, in order: the thesis's chapters 3 and 5, the
/// PI baseline and RHONN adaptive control.
pub const REPRODUCED: [&str; 4] = ["thesis-ch3", "thesis-ch5", "regulated-pi", "control-adaptive"];

/// `rhonn run`: run a scenario (a shipped name or a TOML file, of any plant) and write its
/// folder (`out`, default `out/<name>`).
pub fn run(scenario: &str, out: Option<PathBuf>) -> Result<Outcome> {
    // A scenario read from a file: every error names the file.
    if Path::new(scenario).is_file() {
        return run_named(scenario, out).map_err(context(format!("in the scenario file {scenario}")));
    }
    run_named(scenario, out)
}

fn run_named(scenario: &str, out: Option<PathBuf>) -> Result<Outcome> {
    let spec = match preset::load_any(scenario)? {
        preset::AnyScenario::Pump(spec) => spec,
        preset::AnyScenario::Plant(spec) => return run_plant(&spec, out),
    };
    let sc = spec.check()?;
    let mut o = Outcome::default();
    o.notes
        .extend(sc.warnings.iter().map(|w| format!("warning: {w}")));
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&spec.name));
    crate::folder::check_writable(&dir)?;
    let mut trace = Trace::default();
    let output = run_full(&sc, &mut trace)?;
    let summary = &output.summary;
    o.files = crate::write_run(&dir, &trace, &output).map_err(written(&spec.name))?;
    o.files.push(crate::write_report(&dir)?);
    let f = &summary.figures;
    let l = &mut o.lines;
    l.push(format!(
        "{}: {} s simulated, {} samples",
        spec.name, f.duration_s, f.samples
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
            "  RHONN adaptive vs the baseline {} on an identical plant:",
            c.baseline.describe()
        ));
        l.extend(c.findings.iter().map(|line| format!("    {line}")));
        l.push(format!(
            "    weights: |W| max {:.1}, |W_1 - centre| max {:.2} within the ball's radius {:.2}, {} projections",
            c.adaptive.w_norm_max, c.adaptive.w1_distance_max, c.adaptive.w1_ball_radius, c.adaptive.projections
        ));
    }
    let s = &summary.solver;
    l.push(format!(
        "  solver: {} rhs evaluations, {} accepted and {} rejected steps, {} events",
        s.rhs_evaluations, s.accepted_steps, s.rejected_steps, s.events
    ));
    super::finish_folder(&dir, &mut o)?;
    Ok(o)
}

/// The error of a run whose files could not be written.
fn written(name: &str) -> impl FnOnce(Error) -> Error {
    context(format!(
        "scenario `{name}` ran, but its outputs could not be written"
    ))
}

/// Write a plant run's folder as `rhonn run` does: trajectory.csv, summary.json, plots and
/// report.html, all or nothing; an earlier run's files this run does not write are removed
/// (a note each). Your own plant: `rhonn::experiment::run_plant_scenario_on`, then this
/// (`examples/custom_plant.rs`).
pub fn save_plant_run(dir: &Path, output: &rhonn::experiment::PlantRunOutput) -> Result<Outcome> {
    crate::folder::check_writable(dir)?;
    let mut o = Outcome {
        files: crate::write_plant_run(dir, output).map_err(written(&output.summary.scenario))?,
        ..Outcome::default()
    };
    o.files.push(crate::write_report(dir)?);
    super::finish_folder(dir, &mut o)?;
    Ok(o)
}

/// `rhonn run` for a plant scenario (`[plant] kind`).
fn run_plant(spec: &PlantScenarioSpec, out: Option<PathBuf>) -> Result<Outcome> {
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&spec.name));
    crate::folder::check_writable(&dir)?;
    let output = rhonn::experiment::run_plant_scenario(spec, None)?;
    let mut o = save_plant_run(&dir, &output)?;
    let s = &output.summary;
    o.lines.push(format!(
        "{}: {} s simulated, plant {}",
        spec.name, spec.duration_s, s.plant
    ));
    for f in s.identification.iter().flatten() {
        let mut line = format!(
            "  {}: online (second half) rms error {:.3} {}, fit {:.1} %",
            f.state, f.training_rms_error, f.unit, f.training_fit_percent
        );
        if let (Some(r), Some(p)) = (f.validation_rms_error, f.validation_fit_percent) {
            line += &format!(
                "; frozen, free run on the validation inputs: rms error {r:.3} {}, fit {p:.1} %",
                f.unit
            );
        }
        o.lines.push(line);
    }
    if let (Some(c), Some((state, unit))) = (&s.control, s.regulated) {
        for f in c {
            o.lines.push(format!(
                "  {:<14} {state}: IAE {:.1} {unit} s, ISE {:.0} {unit}^2 s, final error {:.3} {unit}, input saturated {:.0} s",
                f.controller, f.iae, f.ise, f.final_error, f.time_input_saturated_s
            ));
        }
    }
    o.lines
        .extend(s.findings.iter().map(|f| format!("  finding: {f}")));
    Ok(o)
}

/// `rhonn bench`: time each scenario (default [`REPRODUCED`]) for about `seconds`; a table,
/// or JSON.
/// `rhonn bench`: time each scenario (`progress(k, n, name)` before the k-th of n starts,
/// for a progress line; it is not called inside the timings).
pub fn bench(
    names: &[String],
    json: bool,
    seconds: f64,
    out: Option<&Path>,
    compare: Option<&Path>,
    progress: &dyn Fn(usize, usize, &str),
) -> Result<Outcome> {
    if !(seconds.is_finite() && seconds > 0.0 && seconds <= 3600.0) {
        return Err(Error::Input(format!(
            "--seconds {seconds} is not allowed: give a time in (0, 3600] s"
        )));
    }
    // The comparison file is read before the timings, so a bad one fails at once.
    let compared = match (out, compare) {
        (_, None) => Vec::new(),
        (Some(_), Some(p)) => crate::bench_report::read_compared(p)?,
        (None, Some(_)) => {
            return Err(Error::Input(
                "--compare needs --out DIR (the comparison is drawn in DIR/bench.svg)".into(),
            ))
        }
    };
    let default = REPRODUCED.map(String::from);
    let names: &[String] = if names.is_empty() { &default } else { names };
    let mut all = Vec::new();
    let mut o = Outcome::default();
    for (k, name) in names.iter().enumerate() {
        progress(k + 1, names.len(), name);
        let budget = std::time::Duration::from_secs_f64(seconds);
        let b = match preset::load_any(name)? {
            preset::AnyScenario::Pump(spec) => rhonn::experiment::bench(&spec.check()?, budget)?,
            preset::AnyScenario::Plant(spec) => rhonn::experiment::bench_plant(&spec, budget)?,
        };
        if !json {
            if all.is_empty() {
                o.lines.push(format!(
                    "{:<16} {:>14} {:>16} {:>22}",
                    "scenario", "median [ms]", "rhs evaluations", "runs/s on all cores"
                ));
            }
            o.lines.push(format!(
                "{:<16} {:>14.4} {:>16} {:>15.0} ({} threads)",
                b.scenario,
                b.median_s * 1e3,
                b.rhs_evaluations.map_or("-".to_string(), |n| n.to_string()),
                b.runs_per_s_all_cores,
                b.threads
            ));
        }
        all.push(b);
    }
    if json {
        o.lines
            .push(serde_json::to_string_pretty(&all).map_err(|e| Error::Input(e.to_string()))?);
    }
    if let Some(dir) = out {
        o.files = crate::bench_report::write_bench(dir, &all, &compared)?;
    }
    Ok(o)
}

/// `rhonn show`: a scenario's TOML (a shipped one as shipped).
pub fn show(scenario: &str) -> Result<String> {
    let spec = preset::load_any(scenario)?;
    Ok(
        match (preset::SHIPPED.iter().find(|(n, _)| *n == scenario), spec) {
            (Some((_, text)), _) => text.to_string(),
            (None, preset::AnyScenario::Pump(spec)) => spec.to_toml(),
            (None, preset::AnyScenario::Plant(_)) => super::read_text(Path::new(scenario))?,
        },
    )
}
