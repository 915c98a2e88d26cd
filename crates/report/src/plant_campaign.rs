//! Monte Carlo campaigns of a plant scenario (`[plant] kind`, the pump too): each run draws
//! every parameter of the plant's table uniformly within its tolerance (or takes a
//! corner of the box) from a generator seeded by (seed, run index) alone, runs the
//! scenario, and records its figures ([`rhonn::experiment::PlantSummary::figures`]).
//!
//! The files and their rules are those of the pump's campaigns: `campaign.json` first,
//! each finished run appended and flushed to `runs.partial.csv` (rerunning the same
//! command resumes), then `runs.csv` sorted by run index and `summary.json`, all or
//! nothing, with `histograms.svg` (one histogram per figure). No envelope plot yet: that
//! one is the pump's pressure.

use crate::atomic::OutputSet;
use crate::campaign_options::{CampaignOptions, CampaignOutcome, Progress};
use crate::campaign_runner::{self, CampaignKind, Done};
use crate::{write_json, Error};
use rhonn::experiment::campaign::{draw_parameters, quantile_sorted, FigureStats};
use rhonn::experiment::{nominal_plant_parameters, run_plant_scenario, ScenarioSpec};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::Path;

type Result<T, E = Error> = std::result::Result<T, E>;

fn err(msg: String) -> Error {
    Error::Campaign(msg)
}

/// What `campaign.json` holds for a plant campaign.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct PlantCampaignFile {
    scenario_toml: String,
    scenario: String,
    plant: String,
    seed: u64,
    runs: u64,
    sampling: String,
    shard: [u64; 2],
    indices: [u64; 2],
    /// Runs (by index) whose traces make the envelope; absent in campaigns of older
    /// versions (then the default).
    #[serde(default = "default_envelope_runs")]
    envelope_runs: u64,
}

fn default_envelope_runs() -> u64 {
    1000
}

/// One row of `runs.csv`: index, status, parameters, figures (NaN when failed).
fn row(
    index: u64,
    values: &[f64],
    outcome: &std::result::Result<Vec<f64>, String>,
    n_fig: usize,
) -> Vec<String> {
    let mut r = vec![index.to_string()];
    r.push(match outcome {
        Ok(_) => "ok".into(),
        Err(e) => format!("failed: {}", e.replace(['\n', ','], " ")),
    });
    r.extend(values.iter().map(|v| format!("{v:e}")));
    match outcome {
        Ok(f) => r.extend(f.iter().map(|v| format!("{v:e}"))),
        Err(_) => r.extend(std::iter::repeat_n("NaN".to_string(), n_fig)),
    }
    r
}

/// The plant's parameters a campaign draws, their values in the scenario (nominal unless it
/// sets them) and their tolerances.
#[allow(clippy::type_complexity)]
fn drawn_parameters(spec: &ScenarioSpec) -> Result<(&'static [rhonn::plant::Parameter], Vec<f64>, Vec<f64>)> {
    let params = nominal_plant_parameters(&spec.plant.kind)?;
    let base = params
        .iter()
        .map(|p| spec.plant.parameters.get(p.name).copied().unwrap_or(p.nominal))
        .collect();
    let tol = params.iter().map(|p| p.tolerance).collect();
    Ok((params, base, tol))
}

/// Run (or resume) a campaign of the plant scenario `spec` in `dir` (see the module).
pub fn run_plant_campaign(
    spec: &ScenarioSpec,
    o: &CampaignOptions,
    dir: &Path,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<CampaignOutcome> {
    let (params, base, tol) = drawn_parameters(spec)?;
    let varying = tol.iter().filter(|t| **t > 0.0).count() as u32;
    let runs = if o.corners { 1u64 << varying } else { o.runs };
    let nominal = run_plant_scenario(spec, None)?;
    let fig_names: Vec<String> = nominal.summary.figures().into_iter().map(|(n, _)| n).collect();
    let indices = o.shard_indices(runs)?;
    let file = PlantCampaignFile {
        scenario_toml: spec.to_toml(),
        scenario: spec.name.clone(),
        plant: spec.plant.kind.clone(),
        seed: o.seed,
        runs,
        sampling: if o.corners { "corners" } else { "random" }.into(),
        shard: o.shard,
        indices,
        envelope_runs: o.envelope_runs,
    };
    let c = PlantCampaign {
        spec: spec.clone(),
        n_params: params.len(),
        base,
        tol,
        fig_names,
        file,
    };
    campaign_runner::run(&c, indices, dir, progress)
}

/// A campaign of a plant scenario: what every run shares.
struct PlantCampaign {
    spec: ScenarioSpec,
    file: PlantCampaignFile,
    n_params: usize,
    base: Vec<f64>,
    tol: Vec<f64>,
    fig_names: Vec<String>,
}

impl CampaignKind for PlantCampaign {
    type Row = ();
    type File = PlantCampaignFile;
    const FILE_IS: &'static str = "a campaign file of a plant scenario";
    fn file(&self) -> &PlantCampaignFile {
        &self.file
    }
    fn whole(f: &PlantCampaignFile) -> PlantCampaignFile {
        PlantCampaignFile {
            shard: [1, 1],
            indices: [0, f.runs],
            ..f.clone()
        }
    }
    fn runs(f: &PlantCampaignFile) -> u64 {
        f.runs
    }
    fn from_file(f: &PlantCampaignFile) -> Result<Self> {
        let spec = ScenarioSpec::from_toml(&f.scenario_toml, "campaign.json")?;
        let (params, base, tol) = drawn_parameters(&spec)?;
        let nominal = run_plant_scenario(&spec, None)?;
        Ok(PlantCampaign {
            fig_names: nominal.summary.figures().into_iter().map(|(n, _)| n).collect(),
            n_params: params.len(),
            spec,
            file: f.clone(),
            base,
            tol,
        })
    }
    fn scenario(&self) -> &str {
        &self.spec.name
    }
    fn header(&self) -> Vec<String> {
        let mut header = vec!["run".to_string(), "status".to_string()];
        if let Ok(params) = nominal_plant_parameters(&self.spec.plant.kind) {
            header.extend(params.iter().map(|p| p.name.to_string()));
        }
        header.extend(self.fig_names.iter().cloned());
        header
    }
    fn traces_header(&self) -> Option<Vec<String>> {
        None
    }
    fn parse(&self, _index: u64, fields: &[String]) -> std::result::Result<((), bool), String> {
        match fields.get(1) {
            Some(status) => Ok(((), status != "ok")),
            None => Err("no status".into()),
        }
    }
    fn run(&self, i: u64) -> Done<()> {
        let values = draw_parameters(
            &self.base,
            &self.tol,
            self.file.seed,
            i,
            self.file.sampling == "corners",
        );
        let outcome = run_plant_scenario(&self.spec, Some(&values))
            .map(|out| {
                out.summary
                    .figures()
                    .into_iter()
                    .map(|(_, v)| v)
                    .collect::<Vec<f64>>()
            })
            .map_err(|e| e.to_string());
        Done {
            row: (),
            index: i,
            fields: row(i, &values, &outcome, self.fig_names.len()),
            traces: Vec::new(),
            failed: outcome.is_err(),
        }
    }
    fn finish(&self, dir: &Path, rows: Vec<Done<()>>, notes: Vec<String>) -> Result<CampaignOutcome> {
        let rows: Vec<(u64, Vec<String>)> = rows.into_iter().map(|d| (d.index, d.fields)).collect();
        finish(self, dir, &self.header(), &rows, &self.fig_names, notes)
    }
}

/// Each figure's finite values over the runs that finished (read once), and their
/// statistics.
fn figure_statistics(
    rows: &[(u64, Vec<String>)],
    fig_names: &[String],
    n_params: usize,
) -> (Vec<Vec<f64>>, Vec<FigureStats>) {
    let values: Vec<Vec<f64>> = (0..fig_names.len())
        .map(|k| {
            rows.iter()
                .filter(|(_, r)| r[1] == "ok")
                .filter_map(|(_, r)| r[2 + n_params + k].parse::<f64>().ok())
                .filter(|x| x.is_finite())
                .collect()
        })
        .collect();
    let stats: Vec<FigureStats> = fig_names
        .iter()
        .zip(&values)
        .map(|(name, v)| {
            let mut v = v.clone();
            v.sort_by(f64::total_cmp);
            let q = |p: f64| quantile_sorted(&v, p);
            FigureStats {
                figure: name.clone(),
                min: q(0.0),
                q05: q(0.05),
                median: q(0.5),
                q95: q(0.95),
                max: q(1.0),
                mean: if v.is_empty() {
                    f64::NAN
                } else {
                    v.iter().sum::<f64>() / v.len() as f64
                },
            }
        })
        .collect();
    (values, stats)
}

fn finish(
    job: &PlantCampaign,
    dir: &Path,
    header: &[String],
    rows: &[(u64, Vec<String>)],
    fig_names: &[String],
    notes: Vec<String>,
) -> Result<CampaignOutcome> {
    let (spec, n_params, envelope_runs) = (&job.spec, job.n_params, job.file.envelope_runs);
    let failed = rows.iter().filter(|(_, r)| r[1] != "ok").count();
    let (values, stats) = figure_statistics(rows, fig_names, n_params);
    #[derive(Serialize)]
    struct Summary<'a> {
        scenario: &'a str,
        plant: &'a str,
        runs: usize,
        failed: usize,
        figures: Vec<FigureStats>,
        worst_runs: Vec<crate::worst_runs::WorstRun>,
        findings: Vec<String>,
        /// Runs whose traces make the envelope, per series (as the pump's campaigns).
        envelope_runs: Vec<(String, usize)>,
    }
    let envelope = crate::plant_envelope::plant_envelope(spec, rows, n_params, envelope_runs)?;
    let envelope_counts: Vec<(String, usize)> = match (&envelope, &spec.control) {
        (Some(e), Some(c)) => vec![
            (c.output.clone(), e.runs),
            (format!("{}_baseline", c.output), e.runs),
        ],
        _ => Vec::new(),
    };
    let worst = worst_runs(spec, rows, fig_names, n_params)?;
    let worst_list: Vec<_> = worst.iter().map(|(w, _)| w.clone()).collect();
    let worst_files: Vec<String> = worst.iter().map(|(w, _)| w.file.clone()).collect();
    let key = crate::worst_runs::plant_key_figure(fig_names).map(|(k, _)| fig_names[k].as_str());
    let mut set = OutputSet::new(dir)?;
    for (w, text) in &worst {
        set.write(&w.file, |f| f.write_all(text.as_bytes()))?;
    }
    set.write("runs.csv", |w| {
        let mut c = csv::Writer::from_writer(w);
        c.write_record(header)?;
        for (_, r) in rows {
            c.write_record(r)?;
        }
        c.flush()
    })?;
    let summary = Summary {
        scenario: &spec.name,
        plant: &spec.plant.kind,
        runs: rows.len(),
        failed,
        figures: stats,
        findings: crate::worst_runs::findings(key, &worst_list),
        worst_runs: worst_list,
        envelope_runs: envelope_counts,
    };
    set.write("summary.json", |w: &mut dyn Write| write_json(w, &summary))?;
    // One histogram per figure over the runs that finished.
    let panels: Vec<crate::Histogram> = fig_names
        .iter()
        .zip(values)
        .map(|(name, values)| crate::Histogram {
            title: format!("{}: {name}", spec.name),
            x_label: name.clone(),
            values,
        })
        .collect();
    let svg = crate::Histogram::render(&panels, 3, 30);
    set.write("histograms.svg", |w| w.write_all(svg.as_bytes()))?;
    if let Some(env) = &envelope {
        set.write("envelope.csv", |w| w.write_all(&env.csv))?;
        set.write("envelope.svg", |w| w.write_all(env.svg.as_bytes()))?;
    }
    set.commit()?;
    crate::worst_runs::remove_stale(dir, &worst_files)?;
    let partial = dir.join("runs.partial.csv");
    if partial.exists() {
        std::fs::remove_file(&partial).map_err(|e| {
            err(format!(
                "cannot remove {}: {}",
                partial.display(),
                rhonn::error::path_problem(&partial, &e)
            ))
        })?;
    }
    Ok(CampaignOutcome {
        scenario: spec.name.clone(),
        dir: dir.to_path_buf(),
        runs: rows.len(),
        failed,
        already_complete: false,
        notes,
    })
}

/// The worst runs of the campaign's rows (see `worst_runs::describe_plant`).
fn worst_runs(
    spec: &ScenarioSpec,
    rows: &[(u64, Vec<String>)],
    fig_names: &[String],
    n_params: usize,
) -> Result<Vec<(crate::worst_runs::WorstRun, String)>> {
    let params = nominal_plant_parameters(&spec.plant.kind)?;
    let names: Vec<&str> = params.iter().map(|p| p.name).collect();
    let key = crate::worst_runs::plant_key_figure(fig_names);
    let runs: Vec<crate::worst_runs::Candidate> = rows
        .iter()
        .map(|(i, r)| crate::worst_runs::Candidate {
            index: *i,
            values: r[2..2 + n_params]
                .iter()
                .map(|v| v.parse().unwrap_or(f64::NAN))
                .collect(),
            value: key.and_then(|(k, _)| r[2 + n_params + k].parse::<f64>().ok()),
            error: (r[1] != "ok").then(|| r[1].trim_start_matches("failed: ").to_string()),
        })
        .collect();
    crate::worst_runs::describe_plant(spec, &names, key.map(|(_, larger)| larger), &runs)
        .map_err(|e| err(format!("cannot write a worst run's scenario: {e}")))
}

/// Whether the campaign folder `dir` holds a plant scenario's campaign (its
/// `campaign.json` names a plant).
pub fn is_plant_campaign(dir: &Path) -> bool {
    std::fs::read_to_string(dir.join("campaign.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .is_some_and(|v| v.get("plant").is_some())
}

/// Combine the finished shard folders of one plant campaign into `out` (`rhonn merge`):
/// the same `runs.csv`, `summary.json`, plots and worst runs as the unsharded campaign.
pub fn merge_plant_campaigns(dirs: &[std::path::PathBuf], out: &Path) -> Result<CampaignOutcome> {
    campaign_runner::merge::<PlantCampaign>(dirs, out)
}
