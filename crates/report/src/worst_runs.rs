//! A pump campaign's worst runs: the runs that failed and those with the largest value of
//! the campaign's key figure, each with its drawn parameters, written as a scenario file
//! (`worst-run-<index>.toml`: the campaign's scenario with the run's parameters) that
//! `rhonn run` reruns with every plot.

use rhonn::experiment::campaign::{apply, RunRow, TOLERANCES};
use rhonn::experiment::ScenarioSpec;
use serde::Serialize;

/// How many runs are listed.
pub const WORST: usize = 5;

/// One listed run.
#[derive(Debug, Clone, Serialize)]
pub struct WorstRun {
    /// Run index.
    pub run: u64,
    /// The key figure's value (None: the run failed).
    pub value: Option<f64>,
    /// Why it failed.
    pub error: Option<String>,
    /// The drawn parameters, `name=value` in display units.
    pub parameters: String,
    /// The scenario file of this run.
    pub file: String,
    /// The command that reruns it, from the campaign's folder (summary.json names no
    /// folder, so that sharded, merged and resumed campaigns write the same file).
    pub rerun: String,
}

/// The figure a campaign's runs are ranked by: the controller's IAE, else its ISE, else
/// the time below P_min after the first second (larger is worse for each).
pub fn key_figure(names: &[String]) -> Option<(usize, &'static str)> {
    ["iae_mpa_s", "ise_mpa2_s", "time_below_p_min_after_1s_s"]
        .into_iter()
        .find_map(|k| names.iter().position(|n| n == k).map(|i| (i, k)))
}

/// The failed runs first, then the largest key figures; at most [`WORST`].
pub fn worst<'a>(names: &[String], rows: &'a [RunRow]) -> (Option<&'static str>, Vec<&'a RunRow>) {
    let key = key_figure(names);
    let mut failed: Vec<&RunRow> = rows.iter().filter(|r| r.outcome.is_err()).collect();
    failed.truncate(WORST);
    let mut ok: Vec<(&RunRow, f64)> = match key {
        Some((i, _)) => rows
            .iter()
            .filter_map(|r| r.outcome.as_ref().ok().map(|v| (r, v[i])))
            .filter(|(_, v)| v.is_finite())
            .collect(),
        None => Vec::new(),
    };
    ok.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.index.cmp(&b.0.index)));
    let rest = WORST - failed.len();
    failed.extend(ok.into_iter().take(rest).map(|(r, _)| r));
    (key.map(|(_, k)| k), failed)
}

/// The key figure's name and the listed runs, each with its scenario file's text.
pub type Listed = (Option<&'static str>, Vec<(WorstRun, String)>);

/// The listed runs, with their scenario files' names and text.
pub fn describe(spec: &ScenarioSpec, names: &[String], rows: &[RunRow]) -> Result<Listed, toml::ser::Error> {
    let (key, runs) = worst(names, rows);
    let key_index = key.and_then(|k| names.iter().position(|n| n == k));
    let mut out = Vec::new();
    for r in runs {
        let mut run_spec = apply(spec, &r.values);
        run_spec.name = format!("{}-run-{}", spec.name, r.index);
        run_spec.description = format!(
            "run {} of a campaign over {}: {}",
            r.index,
            spec.name,
            params(&r.values)
        );
        let file = format!("worst-run-{}.toml", r.index);
        let text = format!(
            "# Run {} of a campaign over `{}`: its scenario with the run's drawn parameters.\n# Rerun with every plot, from the campaign's folder: rhonn run {file}\n{}",
            r.index,
            spec.name,
            toml::to_string(&run_spec)?
        );
        out.push((
            WorstRun {
                run: r.index,
                value: match (&r.outcome, key_index) {
                    (Ok(v), Some(i)) => Some(v[i]),
                    _ => None,
                },
                error: r.outcome.as_ref().err().cloned(),
                parameters: params(&r.values),
                rerun: format!("rhonn run {file}"),
                file,
            },
            text,
        ));
    }
    Ok((key, out))
}

/// One run of a plant campaign as [`describe_plant`] ranks it: index, drawn parameter
/// values (the plant's order), the key figure (None: failed or not finite), the error.
pub type PlantRun = (u64, Vec<f64>, Option<f64>, Option<String>);

/// The figure a plant campaign's runs are ranked by, and whether larger is worse: the
/// controller's IAE (larger is worse), else the first validation fit (smaller is worse).
pub fn plant_key_figure(names: &[String]) -> Option<(usize, bool)> {
    names
        .iter()
        .position(|n| n == "controller_iae")
        .map(|k| (k, true))
        .or_else(|| {
            names
                .iter()
                .position(|n| n.ends_with("validation_fit_percent"))
                .map(|k| (k, false))
        })
}

/// [`describe`] for a plant campaign: the failed runs, then the largest key figures, each
/// with the scenario (the plant's parameters set to the run's) as TOML.
pub fn describe_plant(
    spec: &rhonn::experiment::PlantScenarioSpec,
    param_names: &[&str],
    larger_is_worse: Option<bool>,
    runs: &[PlantRun],
) -> Result<Vec<(WorstRun, String)>, toml::ser::Error> {
    let mut failed: Vec<&PlantRun> = runs.iter().filter(|r| r.3.is_some()).collect();
    failed.truncate(WORST);
    let mut ok: Vec<&PlantRun> = runs
        .iter()
        .filter(|r| r.3.is_none() && r.2.is_some_and(f64::is_finite))
        .collect();
    if let Some(larger) = larger_is_worse {
        let badness = |r: &PlantRun| {
            if larger {
                r.2.unwrap_or(0.0)
            } else {
                -r.2.unwrap_or(0.0)
            }
        };
        ok.sort_by(|a, b| badness(b).total_cmp(&badness(a)).then(a.0.cmp(&b.0)));
        failed.extend(ok.into_iter().take(WORST - failed.len()));
    }
    let mut out = Vec::new();
    for (index, values, value, error) in failed {
        let described = param_names
            .iter()
            .zip(values)
            .map(|(n, v)| format!("{n}={}", significant(*v)))
            .collect::<Vec<_>>()
            .join(", ");
        let mut run_spec = spec.clone();
        run_spec.name = format!("{}-run-{index}", spec.name);
        run_spec.description = format!("run {index} of a campaign over {}: {described}", spec.name);
        for (n, v) in param_names.iter().zip(values) {
            run_spec.plant.parameters.insert((*n).to_string(), *v);
        }
        let file = format!("worst-run-{index}.toml");
        let text = format!(
            "# Run {index} of a campaign over `{}`: its scenario with the run's drawn parameters.\n# Rerun with every plot, from the campaign's folder: rhonn run {file}\n{}",
            spec.name,
            toml::to_string(&run_spec)?
        );
        out.push((
            WorstRun {
                run: *index,
                value: *value,
                error: error.clone(),
                parameters: described,
                rerun: format!("rhonn run {file}"),
                file,
            },
            text,
        ));
    }
    Ok(out)
}

fn params(values: &[f64; 5]) -> String {
    TOLERANCES
        .iter()
        .zip(values)
        .map(|(p, v)| format!("{}={}", p.name, significant(*v)))
        .collect::<Vec<_>>()
        .join(", ")
}

/// `v` with 6 significant digits.
fn significant(v: f64) -> String {
    if v != 0.0 && (v.abs() < 1e-3 || v.abs() >= 1e6) {
        format!("{v:.5e}")
    } else {
        let digits = (5 - v.abs().log10().floor() as i32).clamp(0, 9) as usize;
        let s = format!("{v:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    }
}

/// Findings in words for the report.
pub fn findings(key: Option<&str>, runs: &[WorstRun]) -> Vec<String> {
    runs.iter()
        .map(|w| match (&w.error, w.value, key) {
            (Some(e), _, _) => format!(
                "run {} failed ({e}); {}; rerun in the campaign's folder: {}",
                w.run, w.parameters, w.rerun
            ),
            (None, Some(v), Some(k)) => format!(
                "worst runs by {k}: run {} with {v:.4}; {}; rerun in the campaign's folder: {}",
                w.run, w.parameters, w.rerun
            ),
            _ => format!(
                "run {}: {}; rerun in the campaign's folder: {}",
                w.run, w.parameters, w.rerun
            ),
        })
        .collect()
}

/// Remove `worst-run-*.toml` files of an earlier campaign in `dir` that this one did not
/// list.
pub fn remove_stale(dir: &std::path::Path, listed: &[String]) -> crate::Result<()> {
    let entries = std::fs::read_dir(dir).map_err(|e| crate::Error::File {
        path: dir.to_path_buf(),
        message: e.to_string(),
    })?;
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().to_string();
        let ours = name.starts_with("worst-run-") && name.ends_with(".toml");
        if ours && !listed.contains(&name) {
            std::fs::remove_file(e.path()).map_err(|err| crate::Error::File {
                path: e.path(),
                message: err.to_string(),
            })?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_listed_worst_run_files_stay_and_failed_runs_come_first() {
        let d = tempfile::tempdir().unwrap();
        for f in ["worst-run-1.toml", "worst-run-2.toml", "other.toml"] {
            std::fs::write(d.path().join(f), "").unwrap();
        }
        remove_stale(d.path(), &["worst-run-2.toml".to_string()]).unwrap();
        let mut left: Vec<String> = std::fs::read_dir(d.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
            .collect();
        left.sort();
        assert_eq!(left, ["other.toml", "worst-run-2.toml"]);
        let names: Vec<String> = ["ise_mpa2_s", "iae_mpa_s"].map(String::from).to_vec();
        let row = |index, outcome| RunRow {
            index,
            values: [0.0; 5],
            outcome,
        };
        let rows = vec![
            row(0, Ok(vec![1.0, 3.0])),
            row(1, Err("diverged".to_string())),
            row(2, Ok(vec![9.0, 5.0])),
            row(3, Ok(vec![0.5, f64::NAN])),
        ];
        let (key, w) = worst(&names, &rows);
        assert_eq!(key, Some("iae_mpa_s"));
        assert_eq!(w.iter().map(|r| r.index).collect::<Vec<_>>(), [1, 2, 0]);
    }
}
