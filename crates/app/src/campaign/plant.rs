//! Monte Carlo campaigns of a plant scenario (`[plant] kind`, the pump too): each run draws
//! every parameter of the plant's table uniformly within its tolerance (or takes a
//! corner of the box) from a generator seeded by (seed, run index) alone, runs the
//! scenario, and records its figures ([`rhonn::experiment::PlantSummary::figures`]).
//!
//! The files and their rules are those of the pump's campaigns: `campaign.json` first,
//! each finished run appended and flushed to `runs.partial.csv` (rerunning the same
//! command resumes), then `runs.csv` sorted by run index and `summary.json`, all or
//! nothing, with `histograms.svg` (one histogram per figure) and the envelope of the
//! runs below `--envelope-runs` (`envelope.csv`, `envelope.svg`: see `plant_envelope`).

use super::options::{CampaignOptions, CampaignOutcome, Progress};
use super::runner::{self, CampaignKind, Done, Runs};
use rhonn::experiment::campaign::{draw, Plan, Sampling};
use rhonn::experiment::{
    campaign_plan, nominal_plant_parameters, run_plant_scenario, run_plant_summary, ScenarioSpec,
};
use rhonn_report::campaign_file::CampaignSummary;
use rhonn_report::plant_envelope::EnvelopeSeries;
use rhonn_report::worst_runs::{self, Ranker};
use rhonn_report::{write_json, Error, OutputSet};
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

/// `rhonn campaign` on a scenario into `dir` (resumes a folder left by an interrupted
/// one), whatever its plant (see the module).
pub fn run_scenario_campaign(
    spec: &ScenarioSpec,
    o: &CampaignOptions,
    dir: &Path,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<CampaignOutcome> {
    let plan = campaign_plan(spec)?;
    let runs = if o.corners { plan.corner_runs() } else { o.runs };
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
        envelope: EnvelopeSeries::of(spec, &nominal)?,
        spec: spec.clone(),
        n_params: plan.params.len(),
        plan,
        fig_names,
        file,
    };
    runner::run(&c, indices, dir, progress)
}

/// A campaign of a plant scenario: what every run shares.
struct PlantCampaign {
    spec: ScenarioSpec,
    file: PlantCampaignFile,
    n_params: usize,
    plan: Plan,
    fig_names: Vec<String>,
    envelope: Option<EnvelopeSeries>,
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
        let plan = campaign_plan(&spec)?;
        let nominal = run_plant_scenario(&spec, None)?;
        Ok(PlantCampaign {
            fig_names: nominal.summary.figures().into_iter().map(|(n, _)| n).collect(),
            envelope: EnvelopeSeries::of(&spec, &nominal)?,
            n_params: plan.params.len(),
            spec,
            file: f.clone(),
            plan,
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
        self.envelope.as_ref().map(|e| e.header())
    }
    fn wants_traces(&self, index: u64, failed: bool) -> bool {
        self.envelope.is_some() && index < self.file.envelope_runs && !failed
    }
    fn parse(&self, _index: u64, fields: &[String]) -> std::result::Result<((), bool), String> {
        match fields.get(1) {
            Some(status) => Ok(((), status != "ok")),
            None => Err("no status".into()),
        }
    }
    fn run(&self, i: u64) -> Done {
        let sampling = if self.file.sampling == "corners" {
            Sampling::Corners
        } else {
            Sampling::Random
        };
        let values = draw(&self.plan, self.file.seed, i, sampling);
        // A loop's figures are on the solver's dense output: a run outside the envelope
        // needs no samples (`run_plant_summary`, the same figures to the bit). An open
        // loop's or an identification's are read at the samples.
        let traced = i < self.file.envelope_runs && self.envelope.is_some();
        let is_loop = self.spec.control.is_some() && self.spec.identifier.is_none();
        let (summary, traces) = if traced || !is_loop {
            let run = run_plant_scenario(&self.spec, Some(&values));
            let traces = match (&run, &self.envelope) {
                (Ok(out), Some(e)) if traced => e.rows(i, out),
                _ => Vec::new(),
            };
            (run.map(|out| out.summary), traces)
        } else {
            (run_plant_summary(&self.spec, Some(&values)), Vec::new())
        };
        let outcome = summary
            .map(|summary| {
                summary
                    .figures()
                    .into_iter()
                    .map(|(_, v)| v)
                    .collect::<Vec<f64>>()
            })
            .map_err(|e| e.to_string());
        Done {
            fields: row(i, &values, &outcome, self.fig_names.len()),
            traces,
            failed: outcome.is_err(),
        }
    }
    fn finish(&self, dir: &Path, runs: &Runs, notes: Vec<String>) -> Result<CampaignOutcome> {
        finish(self, dir, runs, notes)
    }
}

/// One pass over the runs: the worst runs (see `worst_runs::describe_plant`).
fn worst(job: &PlantCampaign, runs: &Runs) -> Result<Vec<(worst_runs::WorstRun, String)>> {
    let (spec, n_params, fig_names) = (&job.spec, job.n_params, &job.fig_names);
    let params = nominal_plant_parameters(&spec.plant.kind)?;
    let names: Vec<&str> = params.iter().map(|p| p.name).collect();
    let key = worst_runs::plant_key_figure(fig_names);
    let mut ranker = Ranker::new(key.map(|(_, larger)| larger));
    runs.for_each(|index, r, failed| {
        let values: Vec<f64> = r[2..2 + n_params]
            .iter()
            .map(|v| v.parse().unwrap_or(f64::NAN))
            .collect();
        ranker.add(worst_runs::Candidate {
            index,
            values,
            value: key.and_then(|(k, _)| r[2 + n_params + k].parse::<f64>().ok()),
            error: failed.then(|| r[1].trim_start_matches("failed: ").to_string()),
        });
        Ok(())
    })?;
    worst_runs::describe_plant(spec, &names, &ranker.ranked())
        .map_err(|e| err(format!("cannot write a worst run's scenario: {e}")))
}

fn finish(job: &PlantCampaign, dir: &Path, runs: &Runs, notes: Vec<String>) -> Result<CampaignOutcome> {
    let spec = &job.spec;
    let (n, failed) = (runs.len(), runs.failed());
    // Figures follow the run, its status and its drawn values.
    let first = 2 + job.n_params;
    let (stats, panels) =
        rhonn_report::campaign_rows::figure_statistics(runs, (&job.fig_names, first), &spec.name, |_| true)?;
    let worst = worst(job, runs)?;
    let envelope = match &job.envelope {
        Some(e) => e.envelope(runs.traces())?,
        None => None,
    };
    let envelope_counts: Vec<(String, usize)> = envelope
        .iter()
        .flat_map(|e| e.series.iter().map(|n| (n.clone(), e.runs)))
        .collect();
    let worst_list: Vec<_> = worst.iter().map(|(w, _)| w.clone()).collect();
    let worst_files: Vec<String> = worst.iter().map(|(w, _)| w.file.clone()).collect();
    let fig_names = &job.fig_names;
    let key = worst_runs::plant_key_figure(fig_names).map(|(k, _)| fig_names[k].as_str());
    let mut set = OutputSet::new(dir)?;
    for (w, text) in &worst {
        set.write(&w.file, |f| f.write_all(text.as_bytes()))?;
    }
    set.write("runs.csv", |w| runs.write_csv(&job.header(), w))?;
    let summary = CampaignSummary {
        scenario: &spec.name,
        plant: &spec.plant.kind,
        runs: n,
        failed,
        plan: &job.plan,
        figures: stats,
        findings: worst_runs::findings(key, &worst_list),
        worst_runs: worst_list,
        envelope_runs: envelope_counts,
    };
    set.write("summary.json", |w: &mut dyn Write| write_json(w, &summary))?;
    // One histogram per figure over the runs that finished.
    let svg = rhonn_report::Histogram::render(&panels, 3);
    set.write("histograms.svg", |w| w.write_all(svg.as_bytes()))?;
    if let (Some(env), Some(series)) = (&envelope, &job.envelope) {
        set.write("traces.csv", |w| {
            let mut wt = csv::Writer::from_writer(w);
            wt.write_record(series.header())?;
            for t in runs.traces() {
                wt.write_record(t)?;
            }
            wt.flush()
        })?;
        set.write("envelope.csv", |w| w.write_all(&env.csv))?;
        set.write("envelope.svg", |w| w.write_all(env.svg.as_bytes()))?;
    }
    set.commit()?;
    worst_runs::remove_stale(dir, &worst_files)?;
    for name in ["runs.partial.csv", "traces.partial.csv"] {
        let partial = dir.join(name);
        if partial.exists() {
            std::fs::remove_file(&partial).map_err(|e| {
                err(format!(
                    "cannot remove {}: {}",
                    partial.display(),
                    rhonn::error::path_problem(&partial, &e)
                ))
            })?;
        }
    }
    Ok(CampaignOutcome {
        scenario: spec.name.clone(),
        dir: dir.to_path_buf(),
        runs: n,
        failed,
        already_complete: false,
        notes,
    })
}

/// Combine the finished shard folders of one plant campaign into `out` (`rhonn merge`):
/// the same `runs.csv`, `summary.json`, plots and worst runs as the unsharded campaign.
pub fn merge_plant_campaigns(dirs: &[std::path::PathBuf], out: &Path) -> Result<CampaignOutcome> {
    runner::merge::<PlantCampaign>(dirs, out)
}
