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
use crate::{write_json, Error};
use rayon::prelude::*;
use rhonn::experiment::campaign::{draw_parameters, quantile_sorted, FigureStats};
use rhonn::experiment::{nominal_plant_parameters, run_plant_scenario, PlantScenarioSpec};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::Path;
use std::sync::Mutex;
use std::time::Instant;

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
        Err(_) => r.extend(std::iter::repeat("NaN".to_string()).take(n_fig)),
    }
    r
}

/// The plant's parameters a campaign draws, their values in the scenario (nominal unless it
/// sets them) and their tolerances.
#[allow(clippy::type_complexity)]
fn drawn_parameters(
    spec: &PlantScenarioSpec,
) -> Result<(&'static [rhonn::plant::Parameter], Vec<f64>, Vec<f64>)> {
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
    spec: &PlantScenarioSpec,
    o: &CampaignOptions,
    dir: &Path,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<CampaignOutcome> {
    let (params, base, tol) = drawn_parameters(spec)?;
    let nominal = run_plant_scenario(spec, None)?;
    let fig_names: Vec<String> = nominal.summary.figures().into_iter().map(|(n, _)| n).collect();
    let varying = tol.iter().filter(|t| **t > 0.0).count() as u32;
    let runs = if o.corners { 1u64 << varying } else { o.runs };
    if runs == 0 || runs > 10_000_000 {
        return Err(err(format!(
            "--runs {runs} is not allowed: give a number in [1, 10000000]"
        )));
    }
    let [k, m] = o.shard;
    let indices = [runs * (k - 1) / m, runs * k / m];
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
    let io = |what: &str, p: &Path, e: std::io::Error| {
        err(format!(
            "cannot {what} {}: {}",
            p.display(),
            rhonn::error::path_problem(p, &e)
        ))
    };
    std::fs::create_dir_all(dir).map_err(|e| io("create the folder", dir, e))?;
    let meta = dir.join("campaign.json");
    let partial = dir.join("runs.partial.csv");
    let mut header = vec!["run".to_string(), "status".to_string()];
    header.extend(params.iter().map(|p| p.name.to_string()));
    header.extend(fig_names.iter().cloned());
    let mut notes = Vec::new();
    let mut done: Vec<(u64, Vec<String>)> = Vec::new();
    if meta.exists() {
        let text = std::fs::read_to_string(&meta).map_err(|e| io("read", &meta, e))?;
        let old: PlantCampaignFile = serde_json::from_str(&text).map_err(|e| {
            err(format!(
                "{} is not a campaign file of a plant scenario: {e}",
                meta.display()
            ))
        })?;
        if old != file {
            return Err(err(format!(
                "{} holds another campaign (scenario, seed, runs, sampling or shard differ): give another --out",
                dir.display()
            )));
        }
        if partial.exists() {
            let mut rd = csv::ReaderBuilder::new()
                .flexible(true)
                .from_path(&partial)
                .map_err(|e| err(format!("cannot read {}: {e}", partial.display())))?;
            for rec in rd.records() {
                // A row cut by an interruption (wrong length, or unreadable) is run again.
                let Ok(rec) = rec else { continue };
                let fields: Vec<String> = rec.iter().map(String::from).collect();
                if fields.len() == header.len() {
                    if let Ok(i) = fields[0].parse::<u64>() {
                        done.push((i, fields));
                    }
                }
            }
            notes.push(format!("resuming: {} runs already done", done.len()));
        } else if dir.join("runs.csv").exists() {
            return Ok(CampaignOutcome {
                scenario: spec.name.clone(),
                dir: dir.to_path_buf(),
                runs: 0,
                failed: 0,
                already_complete: true,
                notes,
            });
        }
    } else {
        let text = serde_json::to_string_pretty(&file).map_err(|e| err(e.to_string()))?;
        let tmp = dir.join(".campaign.json.tmp");
        std::fs::write(&tmp, text + "\n").map_err(|e| io("write", &tmp, e))?;
        std::fs::rename(&tmp, &meta).map_err(|e| io("write", &meta, e))?;
    }
    // Rewrite the partial file with the rows kept (drops a cut row), then append.
    {
        let mut w = csv::Writer::from_path(&partial)
            .map_err(|e| err(format!("cannot write {}: {e}", partial.display())))?;
        w.write_record(&header).map_err(|e| err(e.to_string()))?;
        for (_, r) in &done {
            w.write_record(r).map_err(|e| err(e.to_string()))?;
        }
        w.flush().map_err(|e| io("write", &partial, e))?;
    }
    let job = Job {
        spec,
        o,
        base: &base,
        tol: &tol,
        n_fig: fig_names.len(),
        partial: &partial,
    };
    run_missing(&job, indices, &mut done, progress)?;
    done.sort_by_key(|(i, _)| *i);
    finish(&job, dir, &header, &done, &fig_names, notes)
}

/// What every run of a campaign shares.
struct Job<'a> {
    spec: &'a PlantScenarioSpec,
    o: &'a CampaignOptions,
    base: &'a [f64],
    tol: &'a [f64],
    n_fig: usize,
    partial: &'a Path,
}

/// Run every index of `indices` not in `done`, in parallel, appending each finished row
/// to the partial file (flushed), and add the rows to `done`.
fn run_missing(
    job: &Job,
    indices: [u64; 2],
    done: &mut Vec<(u64, Vec<String>)>,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<()> {
    let io = |what: &str, p: &Path, e: std::io::Error| {
        err(format!(
            "cannot {what} {}: {}",
            p.display(),
            rhonn::error::path_problem(p, &e)
        ))
    };
    let f = std::fs::OpenOptions::new()
        .append(true)
        .open(job.partial)
        .map_err(|e| io("write", job.partial, e))?;
    let writer = Mutex::new(csv::Writer::from_writer(f));
    let have: std::collections::HashSet<u64> = done.iter().map(|(i, _)| *i).collect();
    let todo: Vec<u64> = (indices[0]..indices[1]).filter(|i| !have.contains(i)).collect();
    let counter = Mutex::new((0usize, 0usize));
    let start = Instant::now();
    let new_rows: Vec<Result<(u64, Vec<String>)>> = todo
        .par_iter()
        .map(|&i| {
            let values = draw_parameters(job.base, job.tol, job.o.seed, i, job.o.corners);
            let outcome = run_plant_scenario(job.spec, Some(&values))
                .map(|out| {
                    out.summary
                        .figures()
                        .into_iter()
                        .map(|(_, v)| v)
                        .collect::<Vec<f64>>()
                })
                .map_err(|e| e.to_string());
            let r = row(i, &values, &outcome, job.n_fig);
            {
                let mut w = writer.lock().map_err(|_| err("a worker panicked".into()))?;
                w.write_record(&r)
                    .map_err(|e| err(format!("cannot write {}: {e}", job.partial.display())))?;
                w.flush().map_err(|e| io("write", job.partial, e))?;
            }
            let (d, fl) = {
                let mut c = counter.lock().map_err(|_| err("a worker panicked".into()))?;
                c.0 += 1;
                c.1 += usize::from(outcome.is_err());
                *c
            };
            progress(Progress {
                scenario: &job.spec.name,
                done: d,
                total: todo.len(),
                failed: fl,
                elapsed_s: start.elapsed().as_secs_f64(),
            });
            Ok((i, r))
        })
        .collect();
    drop(writer);
    for r in new_rows {
        done.push(r?);
    }
    Ok(())
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
    job: &Job,
    dir: &Path,
    header: &[String],
    rows: &[(u64, Vec<String>)],
    fig_names: &[String],
    notes: Vec<String>,
) -> Result<CampaignOutcome> {
    let (spec, n_params, envelope_runs) = (job.spec, job.base.len(), job.o.envelope_runs);
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
    spec: &PlantScenarioSpec,
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

/// Each shard's `campaign.json`, the shared header of their `runs.csv` and every row.
#[allow(clippy::type_complexity)]
fn read_shards(
    dirs: &[std::path::PathBuf],
) -> Result<(
    Vec<PlantCampaignFile>,
    Option<Vec<String>>,
    Vec<(u64, Vec<String>)>,
)> {
    let mut files = Vec::new();
    let mut rows: Vec<(u64, Vec<String>)> = Vec::new();
    let mut header: Option<Vec<String>> = None;
    for d in dirs {
        let meta = d.join("campaign.json");
        let text = std::fs::read_to_string(&meta).map_err(|e| {
            err(format!(
                "cannot read {}: {}",
                meta.display(),
                rhonn::error::path_problem(&meta, &e)
            ))
        })?;
        let f: PlantCampaignFile = serde_json::from_str(&text).map_err(|e| {
            err(format!(
                "{} is not a campaign file of a plant scenario: {e}",
                meta.display()
            ))
        })?;
        let runs_csv = d.join("runs.csv");
        if !runs_csv.exists() {
            return Err(err(format!(
                "{} is not finished (no runs.csv): resume it first",
                d.display()
            )));
        }
        let mut rd = csv::Reader::from_path(&runs_csv)
            .map_err(|e| err(format!("cannot read {}: {e}", runs_csv.display())))?;
        let h: Vec<String> = rd
            .headers()
            .map_err(|e| err(format!("cannot read {}: {e}", runs_csv.display())))?
            .iter()
            .map(String::from)
            .collect();
        if header.as_ref().is_some_and(|first| *first != h) {
            return Err(err(format!(
                "{} has other columns than {}",
                runs_csv.display(),
                dirs[0].display()
            )));
        }
        for (line, rec) in rd.records().enumerate() {
            let rec = rec.map_err(|e| err(format!("{} line {}: {e}", runs_csv.display(), line + 2)))?;
            let fields: Vec<String> = rec.iter().map(String::from).collect();
            let i = fields[0].parse::<u64>().map_err(|_| {
                err(format!(
                    "{} line {}: run `{}` is not an index",
                    runs_csv.display(),
                    line + 2,
                    fields[0]
                ))
            })?;
            rows.push((i, fields));
        }
        header.get_or_insert(h);
        files.push(f);
    }
    Ok((files, header, rows))
}

/// Combine the finished shard folders of one plant campaign into `out` (`rhonn merge`):
/// the same `runs.csv`, `summary.json`, plots and worst runs as the unsharded campaign.
pub fn merge_plant_campaigns(dirs: &[std::path::PathBuf], out: &Path) -> Result<CampaignOutcome> {
    let (files, header, mut rows) = read_shards(dirs)?;
    let Some(first) = files.first().cloned() else {
        return Err(err("give at least one campaign folder to merge".into()));
    };
    for (d, f) in dirs.iter().zip(&files) {
        let same = (&f.scenario_toml, f.seed, f.runs, &f.sampling, f.envelope_runs)
            == (
                &first.scenario_toml,
                first.seed,
                first.runs,
                &first.sampling,
                first.envelope_runs,
            );
        if !same {
            return Err(err(format!(
                "{} is a different campaign from {}",
                d.display(),
                dirs[0].display()
            )));
        }
    }
    rows.sort_by_key(|(i, _)| *i);
    if let Some(w) = rows.windows(2).find(|w| w[0].0 == w[1].0) {
        return Err(err(format!("run {} appears twice among the shards", w[0].0)));
    }
    if rows.len() as u64 != first.runs {
        return Err(err(format!(
            "the shards hold {} of the campaign's {} runs: some shard is missing",
            rows.len(),
            first.runs
        )));
    }
    let spec = PlantScenarioSpec::from_toml(&first.scenario_toml, "campaign.json")?;
    let (params, base, tol) = drawn_parameters(&spec)?;
    let header = header.unwrap_or_default();
    let fig_names: Vec<String> = header.iter().skip(2 + params.len()).cloned().collect();
    let o = CampaignOptions {
        runs: first.runs,
        seed: first.seed,
        shard: [1, 1],
        corners: first.sampling == "corners",
        envelope_runs: first.envelope_runs,
    };
    std::fs::create_dir_all(out).map_err(|e| {
        err(format!(
            "cannot create {}: {}",
            out.display(),
            rhonn::error::path_problem(out, &e)
        ))
    })?;
    let file = PlantCampaignFile {
        shard: [1, 1],
        indices: [0, first.runs],
        ..first
    };
    let text = serde_json::to_string_pretty(&file).map_err(|e| err(e.to_string()))?;
    let mut set = OutputSet::new(out)?;
    set.write("campaign.json", |w| w.write_all((text + "\n").as_bytes()))?;
    set.commit()?;
    let job = Job {
        spec: &spec,
        o: &o,
        base: &base,
        tol: &tol,
        n_fig: fig_names.len(),
        partial: &out.join("runs.partial.csv"),
    };
    finish(&job, out, &header, &rows, &fig_names, Vec::new())
}
