//! A campaign's worst runs: the runs that failed and those with the largest value of
//! the campaign's key figure, each with its drawn parameters, written as a scenario file
//! (`worst-run-<index>.toml`: the campaign's scenario with the run's parameters) that
//! `rhonn run` reruns with every plot.

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

/// The figure a plant campaign's runs are ranked by, and whether larger is worse: the
/// controller's IAE (larger is worse), else the first validation fit (smaller is worse).
pub fn plant_key_figure(names: &[String]) -> Option<(usize, bool)> {
    names
        .iter()
        .position(|n| n.starts_with("controller_iae_"))
        .map(|k| (k, true))
        .or_else(|| {
            names
                .iter()
                .position(|n| n.ends_with("validation_fit_percent"))
                .map(|k| (k, false))
        })
}

/// The worst runs of a campaign (`ranked` by [`Ranker`]), with their scenario files' text:
/// the campaign's scenario with the plant's parameters set to the run's draw.
pub fn describe_plant(
    spec: &rhonn::experiment::ScenarioSpec,
    param_names: &[&str],
    ranked: &[Candidate],
) -> Result<Vec<(WorstRun, String)>, toml::ser::Error> {
    list(&spec.name, param_names, ranked, |c, description| {
        // The draw as it ran (a slew parameter's input scaled); a plant kind the
        // campaign ran with is known, so the fallback is the parameters alone.
        let mut run_spec = rhonn::experiment::drawn_scenario(spec, &c.values).unwrap_or_else(|_| {
            let mut s = spec.clone();
            for (n, v) in param_names.iter().zip(&c.values) {
                s.plant.parameters.insert((*n).to_string(), *v);
            }
            s
        });
        run_spec.name = format!("{}-run-{}", spec.name, c.index);
        run_spec.description = description;
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
        let names: Vec<String> = ["controller_ise_mpa2_s", "controller_iae_mpa_s"]
            .map(String::from)
            .to_vec();
        let sc = rhonn::experiment::preset::load_any("control-adaptive").unwrap();
        let params = rhonn::experiment::nominal_plant_parameters("pump").unwrap();
        let param_names: Vec<&str> = params.iter().map(|p| p.name).collect();
        let nominal: Vec<f64> = params.iter().map(|p| p.nominal).collect();
        let key = plant_key_figure(&names);
        assert_eq!(key, Some((1, true)));
        let run = |index, value: Option<f64>, error: Option<&str>| Candidate {
            index,
            values: nominal.clone(),
            value,
            error: error.map(String::from),
        };
        let runs = [
            run(0, Some(3.0), None),
            run(1, None, Some("diverged")),
            run(2, Some(5.0), None),
            run(3, Some(f64::NAN), None),
        ];
        let mut ranker = Ranker::new(Some(true));
        // In any order: the same ranking.
        for r in runs.iter().rev() {
            ranker.add(r.clone());
        }
        let w = describe_plant(&sc, &param_names, &ranker.ranked()).unwrap();
        assert_eq!(w.iter().map(|(r, _)| r.run).collect::<Vec<_>>(), [1, 2, 0]);
        assert_eq!(significant(0.0), "0");
        assert_eq!(significant(1439.5071749), "1439.51");
        assert_eq!(significant(6.635e-5), "6.63500e-5");
    }
}
