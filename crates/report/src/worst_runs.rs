//! A pump campaign's worst runs: the runs that failed and those with the largest value of
//! the campaign's key figure, each with its drawn parameters, written as a scenario file
//! (`worst-run-<index>.toml`: the campaign's scenario with the run's parameters) that
//! `rhonn run` reruns with every plot.

use rhonn::experiment::campaign::{PumpCampaign, RunRow, TOLERANCES};
use serde::Serialize;

/// How many runs are listed.
pub const WORST: usize = 5;

/// One listed run.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
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

/// One run as the ranking sees it: index, drawn parameter values, its key figure (None:
/// no key figure), and why it failed.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    /// Run index.
    pub index: u64,
    /// The drawn parameter values (display units, in the order of their names).
    pub values: Vec<f64>,
    /// The key figure's value.
    pub value: Option<f64>,
    /// Why it failed (None: it finished).
    pub error: Option<String>,
}

/// The ranking of a campaign's runs, one run at a time and in any order: the failed runs
/// first (the lowest indices), then the worst key figures (the largest when
/// `larger_is_worse`, else the smallest; None: no key figure, failed runs only), ties by
/// index; at most [`WORST`]. It keeps at most [`WORST`] of each, not every run.
#[derive(Debug, Clone)]
pub struct Ranker {
    larger_is_worse: Option<bool>,
    failed: Vec<Candidate>,
    worst: Vec<Candidate>,
}

impl Ranker {
    /// An empty ranking.
    pub fn new(larger_is_worse: Option<bool>) -> Self {
        Ranker {
            larger_is_worse,
            failed: Vec::new(),
            worst: Vec::new(),
        }
    }

    /// One more run.
    pub fn add(&mut self, c: Candidate) {
        if c.error.is_some() {
            self.failed.push(c);
            self.failed.sort_by_key(|c| c.index);
            self.failed.truncate(WORST);
            return;
        }
        let Some(larger) = self.larger_is_worse else {
            return;
        };
        if !c.value.is_some_and(f64::is_finite) {
            return;
        }
        let badness = |r: &Candidate| {
            let v = r.value.unwrap_or(f64::NAN);
            if larger {
                v
            } else {
                -v
            }
        };
        self.worst.push(c);
        self.worst
            .sort_by(|a, b| badness(b).total_cmp(&badness(a)).then(a.index.cmp(&b.index)));
        self.worst.truncate(WORST);
    }

    /// The failed runs, then the worst, at most [`WORST`] in all.
    pub fn ranked(self) -> Vec<Candidate> {
        let mut out = self.failed;
        let rest = WORST - out.len();
        out.extend(self.worst.into_iter().take(rest));
        out
    }
}

/// The ranked runs of a campaign over scenario `name`, each described with its
/// parameters' `names` and written as the scenario `scenario_toml(run, description)` gives
/// (the campaign's scenario with the run's parameters, named and described).
fn list(
    name: &str,
    names: &[&str],
    ranked: &[Candidate],
    scenario_toml: impl Fn(&Candidate, String) -> Result<String, toml::ser::Error>,
) -> Result<Vec<(WorstRun, String)>, toml::ser::Error> {
    let mut out = Vec::new();
    for c in ranked {
        let parameters = names
            .iter()
            .zip(&c.values)
            .map(|(n, v)| format!("{n}={}", significant(*v)))
            .collect::<Vec<_>>()
            .join(", ");
        let description = format!("run {} of a campaign over {name}: {parameters}", c.index);
        let file = format!("worst-run-{}.toml", c.index);
        let text = format!(
            "# Run {} of a campaign over `{name}`: its scenario with the run's drawn parameters.\n# Rerun with every plot, from the campaign's folder: rhonn run {file}\n{}",
            c.index,
            scenario_toml(c, description)?
        );
        out.push((
            WorstRun {
                run: c.index,
                value: c.value,
                error: c.error.clone(),
                parameters,
                rerun: format!("rhonn run {file}"),
                file,
            },
            text,
        ));
    }
    Ok(out)
}

/// A pump campaign's run as the ranking by the key figure `key` ([`key_figure`]) sees it.
pub fn pump_candidate(r: &RunRow, key: Option<(usize, &str)>) -> Candidate {
    Candidate {
        index: r.index,
        values: r.values.to_vec(),
        value: match (&r.outcome, key) {
            (Ok(v), Some((i, _))) => Some(v[i]),
            _ => None,
        },
        error: r.outcome.as_ref().err().cloned(),
    }
}

/// The worst runs of a pump campaign (`ranked` by [`Ranker`] with larger worse), with
/// their scenario files' text.
pub fn describe(
    spec: &PumpCampaign,
    ranked: &[Candidate],
) -> Result<Vec<(WorstRun, String)>, toml::ser::Error> {
    let param_names: Vec<&str> = TOLERANCES.iter().map(|p| p.name).collect();
    list(spec.name(), &param_names, ranked, |c, description| {
        let name = format!("{}-run-{}", spec.name(), c.index);
        toml::to_string(&spec.run_scenario(&c.values, name, description))
    })
}

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

/// [`describe`] for a plant campaign (`ranked` by [`Ranker`]): the scenario with the
/// plant's parameters set to the run's.
pub fn describe_plant(
    spec: &rhonn::experiment::ScenarioSpec,
    param_names: &[&str],
    ranked: &[Candidate],
) -> Result<Vec<(WorstRun, String)>, toml::ser::Error> {
    list(&spec.name, param_names, ranked, |c, description| {
        let mut run_spec = spec.clone();
        run_spec.name = format!("{}-run-{}", spec.name, c.index);
        run_spec.description = description;
        for (n, v) in param_names.iter().zip(&c.values) {
            run_spec.plant.parameters.insert((*n).to_string(), *v);
        }
        toml::to_string(&run_spec)
    })
}

/// `v` with 6 significant digits.
fn significant(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return v.to_string();
    }
    if v.abs() < 1e-3 || v.abs() >= 1e6 {
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
        let rows = [
            row(0, Ok(vec![1.0, 3.0])),
            row(1, Err("diverged".to_string())),
            row(2, Ok(vec![9.0, 5.0])),
            row(3, Ok(vec![0.5, f64::NAN])),
        ];
        let sc = rhonn::experiment::preset::load_any("control-adaptive").unwrap();
        let spec = PumpCampaign::of(&sc).unwrap().unwrap();
        let key = key_figure(&names);
        assert_eq!(key.map(|(_, k)| k), Some("iae_mpa_s"));
        let mut ranker = Ranker::new(Some(true));
        // In any order: the same ranking.
        for r in rows.iter().rev() {
            ranker.add(pump_candidate(r, key));
        }
        let w = describe(&spec, &ranker.ranked()).unwrap();
        assert_eq!(w.iter().map(|(r, _)| r.run).collect::<Vec<_>>(), [1, 2, 0]);
        assert_eq!(significant(0.0), "0");
        assert_eq!(significant(1439.5071749), "1439.51");
        assert_eq!(significant(6.635e-5), "6.63500e-5");
    }
}
