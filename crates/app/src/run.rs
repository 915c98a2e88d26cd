//! `rhonn run`, `rhonn reproduce`, `rhonn bench` and `rhonn show`: scenarios.

use super::{context, Outcome};
use rhonn::experiment::preset;
use rhonn_report::{Error, Result};
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

/// Run the shipped scenario `name` into `dir` as `rhonn run` does: the run and what
/// writing it told (`rhonn reproduce`).
pub(super) fn run_scenario_into_dir(
    name: &str,
    dir: &Path,
) -> Result<(rhonn::experiment::PlantRunOutput, Outcome)> {
    let sc = preset::load_any(name)?;
    let (run, o) = run_scenario_from(&sc, Some(dir), &[])?;
    Ok((run, o.unwrap_or_default()))
}

fn run_named(scenario: &str, out: Option<PathBuf>) -> Result<Outcome> {
    let sc = preset::load_any(scenario)?;
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&sc.name));
    let file = Path::new(scenario);
    let inputs: Vec<PathBuf> = file.is_file().then(|| file.to_path_buf()).into_iter().collect();
    Ok(run_scenario_from(&sc, Some(&dir), &inputs)?.1.unwrap_or_default())
}

/// Run `sc` and, given `out`, write its folder as `rhonn run` does (the folder checked and
/// locked before the run): the run, and what writing it told (`rhonn run`, Python's
/// `rhonn.run`).
pub fn run_scenario(
    sc: &rhonn::experiment::ScenarioSpec,
    out: Option<&Path>,
) -> Result<(rhonn::experiment::PlantRunOutput, Option<Outcome>)> {
    run_scenario_from(sc, out, &[])
}

fn run_scenario_from(
    sc: &rhonn::experiment::ScenarioSpec,
    out: Option<&Path>,
    inputs: &[PathBuf],
) -> Result<(rhonn::experiment::PlantRunOutput, Option<Outcome>)> {
    let writing = out
        .map(|dir| {
            rhonn_report::folder::Writing::begin(dir, inputs, rhonn_report::folder::writes::RUN, false)
        })
        .transpose()?;
    let run = sc.run()?;
    let written = match writing {
        Some(w) => {
            let o = scenario_run_into(w.stage(), &sc.name, &run)?;
            Some(super::commit(w, o)?)
        }
        None => None,
    };
    Ok((run, written))
}

/// Write a scenario run's folder as `rhonn run` does ([`run_scenario`]): its files and
/// `report.html` as a whole (`rhonn_report::folder`); the scenario's warnings and the figures
/// `rhonn run` prints.
pub fn save_scenario_run(dir: &Path, name: &str, run: &rhonn::experiment::PlantRunOutput) -> Result<Outcome> {
    super::in_folder(dir, (&[], rhonn_report::folder::writes::RUN), false, |stage| {
        scenario_run_into(stage, name, run)
    })
}

fn scenario_run_into(stage: &Path, name: &str, run: &rhonn::experiment::PlantRunOutput) -> Result<Outcome> {
    let mut o = Outcome::default();
    o.notes
        .extend(run.summary.warnings.iter().map(|w| format!("warning: {w}")));
    o.files = rhonn_report::write_scenario_run(stage, run).map_err(written(name))?;
    o.lines = rhonn_report::scenario_run::run_lines(run);
    Ok(o)
}

/// The error of a run whose files could not be written.
fn written(name: &str) -> impl FnOnce(Error) -> Error {
    context(format!(
        "scenario `{name}` ran, but its outputs could not be written"
    ))
}

/// Write a plant run's folder as `rhonn run` does: trajectory.csv, summary.json, plots and
/// report.html, as a whole (`rhonn_report::folder`). Your own plant:
/// `rhonn::experiment::run_plant_scenario_on`, then this (`crates/cli/examples/custom_plant.rs`).
pub fn save_plant_run(dir: &Path, output: &rhonn::experiment::PlantRunOutput) -> Result<Outcome> {
    super::in_folder(dir, (&[], rhonn_report::folder::writes::RUN), false, |stage| {
        let o = Outcome {
            files: rhonn_report::write_plant_run(stage, output).map_err(written(&output.summary.scenario))?,
            ..Outcome::default()
        };
        Ok(o)
    })
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
        (Some(_), Some(p)) => rhonn_report::bench_report::read_compared(p)?,
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
    match out {
        Some(dir) => {
            let inputs: Vec<PathBuf> = compare.iter().map(|p| p.to_path_buf()).collect();
            super::in_folder(
                dir,
                (&inputs, rhonn_report::folder::writes::BENCH),
                false,
                |stage| {
                    o.files = rhonn_report::bench_report::write_bench(stage, &all, &compared)?;
                    Ok(o)
                },
            )
        }
        None => Ok(o),
    }
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
