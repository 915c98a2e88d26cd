//! The files of a Monte Carlo campaign (`rhonn campaign`, `rhonn merge`).
//!
//! `DIR/campaign.json` says what the campaign is (scenario, seed, runs, sampling, shard);
//! finished runs are appended to `DIR/runs.partial.csv` and flushed one by one, so an
//! interrupted campaign loses nothing and `rhonn campaign` with the same arguments
//! resumes it; at the end `DIR/runs.csv` holds every row sorted by run index (the same
//! bytes whatever the thread count or sharding) and `DIR/summary.json` the statistics.

pub use crate::campaign_options::{on_threads, CampaignOptions, CampaignOutcome, Progress};
use crate::campaign_plots::envelope_files;
use crate::campaign_runner::{self, CampaignKind, Done, Runs};
use crate::worst_runs::{Candidate, Ranker};
use crate::Error;
use rhonn::experiment::campaign::{
    Envelope, FigureStats, Plan, PumpCampaign, RunRow, RunTraces, Sampling, TOLERANCES,
};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

type Result<T, E = Error> = std::result::Result<T, E>;

// The CSV written into memory buffers in `finish`: an error there is a formatting one.
impl From<csv::Error> for Error {
    fn from(e: csv::Error) -> Self {
        Error::Campaign(format!("CSV: {e}"))
    }
}

/// `.ctx(|| what)`: an error of any kind as a campaign error saying `what: error`.
trait Ctx<T> {
    fn ctx(self, what: impl FnOnce() -> String) -> Result<T>;
}

impl<T, E: std::fmt::Display> Ctx<T> for std::result::Result<T, E> {
    fn ctx(self, what: impl FnOnce() -> String) -> Result<T> {
        self.map_err(|e| Error::Campaign(format!("{}: {e}", what())))
    }
}

/// What a campaign folder holds in `campaign.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct CampaignFile {
    /// The scenario as run (TOML), so that a merge can check it.
    pub scenario_toml: String,
    /// Scenario name.
    pub scenario: String,
    /// Seed.
    pub seed: u64,
    /// Runs of the whole campaign.
    pub runs: u64,
    /// `random` (each parameter from its distribution) or `corners`.
    pub sampling: String,
    /// The pressure traces of runs with index below this are kept for the envelope.
    pub envelope_runs: u64,
    /// This folder's shard `[k, m]` (1-based k).
    pub shard: [u64; 2],
    /// Run indices of this shard: `[first, end)`.
    pub indices: [u64; 2],
}

/// `runs.csv`'s header for a scenario.
fn header(spec: &PumpCampaign) -> Vec<String> {
    let mut h = vec!["run".to_string()];
    h.extend(TOLERANCES.iter().map(|t| t.name.to_string()));
    h.push("status".into());
    h.push("error".into());
    h.extend(spec.figure_names());
    h
}

/// `traces.csv`'s header: the run, the series, then the envelope grid's times [s].
fn traces_header(spec: &PumpCampaign) -> Vec<String> {
    let mut h = vec!["run".to_string(), "series".to_string()];
    h.extend(spec.envelope_grid().1.iter().map(|t| t.to_string()));
    h
}

/// A run's trace rows (MPa, 0.1 kPa resolution: the envelope is computed from these
/// strings, so a fresh, a resumed and a merged campaign give the same bytes).
fn trace_records(index: u64, tr: &RunTraces) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    for (name, v) in [("p_line", &tr.p_line), ("p_line_pi", &tr.p_line_pi)] {
        if v.is_empty() {
            continue;
        }
        let mut r = vec![index.to_string(), name.to_string()];
        r.extend(v.iter().map(|x| format!("{x:.4}")));
        out.push(r);
    }
    out
}

fn record(spec: &PumpCampaign, r: &RunRow) -> Vec<String> {
    let mut v = vec![r.index.to_string()];
    v.extend(r.values.iter().map(|x| x.to_string()));
    match &r.outcome {
        Ok(figs) => {
            v.push("ok".into());
            v.push(String::new());
            v.extend(figs.iter().map(|x| x.to_string()));
        }
        Err(e) => {
            v.push("failed".into());
            v.push(e.clone());
            v.extend(spec.figure_names().iter().map(|_| String::new()));
        }
    }
    v
}

/// The pump's reading of a `runs.csv` row: the drawn values, and the figures or the
/// failure.
fn parse_row(index: u64, rec: &[String]) -> std::result::Result<RunRow, String> {
    let num = |s: &str| s.parse::<f64>().map_err(|e| e.to_string());
    if rec.len() < 8 {
        return Err(format!("{} fields, at least 8 expected", rec.len()));
    }
    let mut values = [0.0; 5];
    for (j, vj) in values.iter_mut().enumerate() {
        *vj = num(&rec[1 + j])?;
    }
    let outcome = match rec[6].as_str() {
        "ok" => Ok((8..rec.len())
            .map(|k| num(&rec[k]))
            .collect::<std::result::Result<Vec<_>, _>>()?),
        _ => Err(rec[7].to_string()),
    };
    Ok(RunRow {
        index,
        values,
        outcome,
    })
}

/// The envelope of the kept traces, per series, from their CSV fields.
fn envelopes(runs: &Runs, points: usize) -> Vec<(String, Envelope, usize)> {
    let mut out = Vec::new();
    for name in ["p_line", "p_line_pi"] {
        let traces: Vec<Vec<f64>> = runs
            .traces()
            .filter(|t| t.get(1).map(String::as_str) == Some(name))
            .map(|t| t[2..].iter().map(|x| x.parse().unwrap_or(f64::NAN)).collect())
            .collect();
        if traces.is_empty() {
            continue;
        }
        let refs: Vec<&[f64]> = traces.iter().map(Vec::as_slice).collect();
        out.push((name.to_string(), Envelope::of(&refs, points), traces.len()));
    }
    out
}

/// What one pass over the runs gives: the failure reasons with how many runs gave each
/// (in the order of their first run), the runs that finished, and the worst runs.
struct Tally {
    failures: Vec<(String, usize)>,
    ok: usize,
    ranked: Vec<Candidate>,
}

fn tally(names: &[String], runs: &Runs) -> Result<Tally> {
    let key = crate::worst_runs::key_figure(names);
    let mut ranker = Ranker::new(key.map(|_| true));
    let mut failures: std::collections::HashMap<String, (u64, usize)> = Default::default();
    let mut ok = 0;
    runs.for_each(|index, fields, _| {
        let r = parse_row(index, fields).map_err(Error::Campaign)?;
        match &r.outcome {
            Ok(_) => ok += 1,
            Err(e) => {
                let f = failures.entry(e.clone()).or_insert((index, 0));
                f.0 = f.0.min(index);
                f.1 += 1;
            }
        }
        ranker.add(crate::worst_runs::pump_candidate(&r, key));
        Ok(())
    })?;
    let mut failures: Vec<(String, (u64, usize))> = failures.into_iter().collect();
    failures.sort_by_key(|(_, (first, _))| *first);
    Ok(Tally {
        failures: failures.into_iter().map(|(m, (_, n))| (m, n)).collect(),
        ok,
        ranked: ranker.ranked(),
    })
}

/// What `summary.json` holds.
#[derive(Debug, Serialize, schemars::JsonSchema)]
struct CampaignSummary<'a> {
    campaign: &'a CampaignFile,
    /// Runs that finished.
    runs_ok: usize,
    /// Runs that failed (their figures NaN in runs.csv).
    runs_failed: usize,
    /// Failure reasons and how many runs gave each.
    failures: Vec<(String, usize)>,
    /// The parameters' distributions as drawn.
    plan: Plan,
    figures: Vec<FigureStats>,
    /// Runs whose pressure traces make the envelope, per series.
    envelope_runs: Vec<(String, usize)>,
    /// The failed runs and those with the largest key figure, each with its scenario file.
    worst_runs: Vec<crate::worst_runs::WorstRun>,
    /// The worst runs in words.
    findings: Vec<String>,
}

/// The schema of `summary.json` (`fields`).
pub(crate) fn schema() -> serde_json::Value {
    schemars::schema_for!(CampaignSummary<'static>).to_value()
}

/// Write `runs.csv` (sorted) and `summary.json` atomically, then drop the partial file.
fn finish(
    dir: &Path,
    file: &CampaignFile,
    spec: &PumpCampaign,
    runs: &Runs,
    notes: Vec<String>,
) -> Result<CampaignOutcome> {
    let (_, grid) = spec.envelope_grid();
    let env = envelopes(runs, grid.len());
    let env_files = envelope_files(
        spec,
        &file.scenario,
        traces_header(spec),
        runs.traces(),
        &grid,
        &env,
    )?;
    let envelope_runs = env.iter().map(|(n, _, k)| (n.clone(), *k)).collect();
    let names = spec.figure_names();
    let Tally { failures, ok, ranked } = tally(&names, runs)?;
    let key = crate::worst_runs::key_figure(&names);
    let worst = crate::worst_runs::describe(spec, &ranked)
        .map_err(|e| Error::Campaign(format!("cannot write a worst run's scenario: {e}")))?;
    let worst_runs: Vec<_> = worst.iter().map(|(w, _)| w.clone()).collect();
    let worst_files: Vec<String> = worst.iter().map(|(w, _)| w.file.clone()).collect();
    // Figures follow the run, its 5 drawn values, its status and its error.
    let shown = |name: &str| crate::campaign_plots::shown(&names, name);
    let (stats, panels) = crate::campaign_rows::figure_statistics(runs, (&names, 8), &file.scenario, shown)?;
    let n = runs.len();
    let summary = CampaignSummary {
        campaign: file,
        runs_ok: ok,
        runs_failed: n - ok,
        failures,
        plan: spec.plan(),
        figures: stats,
        envelope_runs,
        findings: crate::worst_runs::findings(key.map(|(_, k)| k), &worst_runs),
        worst_runs,
    };
    let mut out = crate::OutputSet::new(dir)?;
    out.write("runs.csv", |w| runs.write_csv(&header(spec), w))?;
    out.write("summary.json", |w| {
        serde_json::to_writer_pretty(&mut *w, &summary).map_err(std::io::Error::other)?;
        writeln!(w)
    })?;
    out.write("campaign.json", |w| {
        serde_json::to_writer_pretty(&mut *w, file).map_err(std::io::Error::other)?;
        writeln!(w)
    })?;
    for (w, text) in &worst {
        out.write(&w.file, |f| f.write_all(text.as_bytes()))?;
    }
    let svg = crate::Histogram::render(&panels, 3);
    out.write("histograms.svg", |w| w.write_all(svg.as_bytes()))?;
    if let Some((traces_buf, env_buf, svg)) = env_files {
        out.write("traces.csv", |w| w.write_all(&traces_buf))?;
        out.write("envelope.csv", |w| w.write_all(&env_buf))?;
        out.write("envelope.svg", |w| w.write_all(svg.as_bytes()))?;
    }
    out.commit()?;
    crate::worst_runs::remove_stale(dir, &worst_files)?;
    for name in ["runs.partial.csv", "traces.partial.csv"] {
        let partial = dir.join(name);
        if partial.exists() {
            std::fs::remove_file(&partial).ctx(|| format!("cannot remove {}", partial.display()))?;
        }
    }
    Ok(CampaignOutcome {
        scenario: file.scenario.clone(),
        dir: dir.to_path_buf(),
        runs: n,
        failed: n - ok,
        already_complete: false,
        notes,
    })
}

/// Parse a shard `K/M` (1 <= K <= M).
pub fn parse_shard(s: &str) -> Result<[u64; 2]> {
    let bad = || {
        Error::Campaign(format!(
            "--shard {s:?} is not allowed: give K/M with 1 <= K <= M, e.g. 2/4"
        ))
    };
    let (k, m) = s.split_once('/').ok_or_else(bad)?;
    let (k, m): (u64, u64) = (
        k.trim().parse().map_err(|_| bad())?,
        m.trim().parse().map_err(|_| bad())?,
    );
    if k == 0 || m == 0 || k > m {
        return Err(bad());
    }
    Ok([k, m])
}

/// Run (or resume) the campaign `o` of the scenario `spec` in the folder `dir`:
/// `campaign.json` first, each finished run appended to `runs.partial.csv` (and its
/// traces to `traces.partial.csv`) and flushed, then `runs.csv`, `summary.json`,
/// `histograms.svg` and the envelope's files, all or nothing. The same call on the same
/// folder resumes an interrupted campaign. `progress` is called after every run.
pub fn run_campaign(
    spec: &PumpCampaign,
    o: &CampaignOptions,
    dir: &Path,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<CampaignOutcome> {
    let spec = spec.clone();
    let runs = if o.corners {
        spec.plan().corner_runs()
    } else {
        o.runs
    };
    let indices = o.shard_indices(runs)?;
    let file = CampaignFile {
        scenario_toml: spec.scenario().to_toml(),
        scenario: spec.name().to_string(),
        seed: o.seed,
        runs,
        sampling: if o.corners { "corners" } else { "random" }.into(),
        envelope_runs: o.envelope_runs,
        shard: o.shard,
        indices,
    };
    let c = PumpKind {
        sampling: if o.corners {
            Sampling::Corners
        } else {
            Sampling::Random
        },
        spec,
        file,
    };
    campaign_runner::run(&c, indices, dir, progress)
}

/// A campaign of a pump scenario (its own runner).
struct PumpKind {
    spec: PumpCampaign,
    file: CampaignFile,
    sampling: Sampling,
}

impl CampaignKind for PumpKind {
    type Row = RunRow;
    type File = CampaignFile;
    const FILE_IS: &'static str = "a campaign file";
    fn file(&self) -> &CampaignFile {
        &self.file
    }
    fn whole(f: &CampaignFile) -> CampaignFile {
        CampaignFile {
            shard: [1, 1],
            indices: [0, f.runs],
            ..f.clone()
        }
    }
    fn runs(f: &CampaignFile) -> u64 {
        f.runs
    }
    fn from_file(f: &CampaignFile) -> Result<Self> {
        let written = rhonn::experiment::ScenarioSpec::from_toml(&f.scenario_toml, "campaign.json")?;
        let spec = PumpCampaign::of(&written)?.ok_or_else(|| {
            Error::Campaign(format!(
                "campaign.json: its scenario `{}` is not the pump's (plant.kind {:?})",
                written.name, written.plant.kind
            ))
        })?;
        Ok(PumpKind {
            spec,
            file: f.clone(),
            sampling: if f.sampling == "corners" {
                Sampling::Corners
            } else {
                Sampling::Random
            },
        })
    }
    fn scenario(&self) -> &str {
        self.spec.name()
    }
    fn header(&self) -> Vec<String> {
        header(&self.spec)
    }
    fn traces_header(&self) -> Option<Vec<String>> {
        Some(traces_header(&self.spec))
    }
    fn parse(&self, index: u64, fields: &[String]) -> std::result::Result<(RunRow, bool), String> {
        let row = parse_row(index, fields)?;
        let failed = row.outcome.is_err();
        Ok((row, failed))
    }
    fn wants_traces(&self, index: u64, failed: bool) -> bool {
        index < self.file.envelope_runs && !failed
    }
    fn run(&self, i: u64) -> Done {
        let keep = i < self.file.envelope_runs;
        let (row, tr) = self.spec.run_one(self.file.seed, i, self.sampling, keep);
        Done {
            fields: record(&self.spec, &row),
            traces: tr.map(|t| trace_records(i, &t)).unwrap_or_default(),
            failed: row.outcome.is_err(),
        }
    }
    fn finish(&self, dir: &Path, runs: &Runs, notes: Vec<String>) -> Result<CampaignOutcome> {
        finish(dir, &self.file, &self.spec, runs, notes)
    }
}

/// Combine finished shard folders of one campaign into the folder `out` (`rhonn merge`).
pub fn merge_campaigns(dirs: &[PathBuf], out: &Path) -> Result<CampaignOutcome> {
    if dirs
        .first()
        .is_some_and(|d| crate::plant_campaign::is_plant_campaign(d))
    {
        return crate::plant_campaign::merge_plant_campaigns(dirs, out);
    }
    campaign_runner::merge::<PumpKind>(dirs, out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn a_campaign_is_a_library_call_that_reports_progress_and_resumes() {
        let d = tempfile::tempdir().unwrap();
        let mut sc = rhonn::experiment::preset::load_any("thesis-ch3").unwrap();
        sc.duration_s = 0.5;
        let spec = PumpCampaign::of(&sc).unwrap().unwrap();
        let o = CampaignOptions {
            runs: 6,
            seed: 2,
            shard: [1, 1],
            corners: false,
            envelope_runs: 0,
        };
        let calls = AtomicUsize::new(0);
        let out = run_campaign(&spec, &o, d.path(), &|p| {
            calls.fetch_add(1, Ordering::Relaxed);
            assert!(p.done <= p.total && p.total == 6);
        })
        .unwrap();
        assert_eq!((out.runs, out.failed, out.already_complete), (6, 0, false));
        assert_eq!(calls.load(Ordering::Relaxed), 6);
        let rows = std::fs::read_to_string(d.path().join("runs.csv")).unwrap();
        assert_eq!(rows.lines().count(), 7);
        let again = run_campaign(&spec, &o, d.path(), &|_| panic!("nothing to run")).unwrap();
        assert!(again.already_complete);
        // Another campaign in the same folder is refused, naming the folder.
        let other = CampaignOptions { seed: 3, ..o };
        let e = run_campaign(&spec, &other, d.path(), &|_| {})
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("holds another campaign") && e.contains(&d.path().display().to_string()),
            "{e}"
        );
    }
}
