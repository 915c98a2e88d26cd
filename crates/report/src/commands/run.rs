//! `rhonn run`, `rhonn reproduce`, `rhonn bench` and `rhonn show`: scenarios.

use super::{context, Outcome};
use crate::{Error, Result};
use rhonn::experiment::preset;
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
    let sc = preset::load_any(scenario)?;
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&sc.name));
    Ok(run_scenario(&sc, Some(&dir))?.1.unwrap_or_default())
}

/// Run `sc` and, given `out`, write its folder as `rhonn run` does (the folder checked
/// before the run): the run, and what writing it told (`rhonn run`, Python's `rhonn.run`).
pub fn run_scenario(
    sc: &rhonn::experiment::ScenarioSpec,
    out: Option<&Path>,
) -> Result<(rhonn::experiment::ScenarioRun, Option<Outcome>)> {
    if let Some(dir) = out {
        crate::folder::check_writable(dir)?;
    }
    let run = sc.run()?;
    let written = out
        .map(|dir| save_scenario_run(dir, &sc.name, &run))
        .transpose()?;
    Ok((run, written))
}

/// Write a scenario run's folder as `rhonn run` does ([`run_scenario`]; the caller checks
/// `crate::folder::check_writable` before it runs): its files all or nothing, `report.html`, an earlier run's files this run does not
/// write removed (a note each); the scenario's warnings and the figures `rhonn run` prints.
pub fn save_scenario_run(dir: &Path, name: &str, run: &rhonn::experiment::ScenarioRun) -> Result<Outcome> {
    let mut o = Outcome::default();
    o.notes
        .extend(run.warnings().iter().map(|w| format!("warning: {w}")));
    o.files = crate::write_scenario_run(dir, run).map_err(written(name))?;
    o.files.push(crate::write_report(dir)?);
    o.lines = crate::scenario_run::run_lines(run);
    super::finish_folder(dir, &mut o)?;
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
            "--seconds {} is not allowed: give a time in (0, 3600] s",
            rhonn::metrics::sig(seconds, 6)
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
        let b = preset::load_any(name)?.bench(budget)?;
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
    // Read (and checked) first: a file that is not a scenario is an error here too.
    preset::load_any(scenario)?;
    Ok(match preset::SHIPPED.iter().find(|(n, _)| *n == scenario) {
        Some((_, text)) => text.to_string(),
        None => super::read_text(Path::new(scenario))?,
    })
}
