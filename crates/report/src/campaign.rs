//! The files of a Monte Carlo campaign (`rhonn campaign`, `rhonn merge`).
//!
//! `DIR/campaign.json` says what the campaign is (scenario, seed, runs, sampling, shard);
//! finished runs are appended to `DIR/runs.partial.csv` and flushed one by one, so an
//! interrupted campaign loses nothing and `rhonn campaign` with the same arguments
//! resumes it; at the end `DIR/runs.csv` holds every row sorted by run index (the same
//! bytes whatever the thread count or sharding) and `DIR/summary.json` the statistics.

pub use crate::campaign_options::{on_threads, CampaignOptions, CampaignOutcome, Progress};
use crate::campaign_plots::{envelope_files, histograms};
use crate::Error;
use rayon::prelude::*;
use rhonn::experiment::campaign::{
    envelope_grid, figure_names, run_one, statistics, Envelope, FigureStats, Plan, RunRow, RunTraces,
    Sampling, TOLERANCES,
};
use rhonn::experiment::ScenarioSpec;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

type Result<T, E = Error> = std::result::Result<T, E>;

// The CSV written into memory buffers in `finish`: an error there is a formatting one.
impl From<csv::Error> for Error {
    fn from(e: csv::Error) -> Self {
        Error::Campaign(format!("CSV: {e}"))
    }
}

/// Return a campaign error with a formatted message.
macro_rules! bail {
    ($($t:tt)*) => {
        return Err(Error::Campaign(format!($($t)*)))
    };
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

/// Context for an input/output error on a path: what was tried, and what the path is
/// (missing, a directory, not writable), from [`rhonn::error::path_problem`].
trait IoCtx<T> {
    fn at(self, verb: &str, path: &Path) -> Result<T>;
}

impl<T> IoCtx<T> for std::io::Result<T> {
    fn at(self, verb: &str, path: &Path) -> Result<T> {
        self.map_err(|e| {
            Error::Campaign(format!(
                "cannot {verb} {}: {}",
                path.display(),
                rhonn::error::path_problem(path, &e)
            ))
        })
    }
}

/// What a campaign folder holds in `campaign.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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
fn header(spec: &ScenarioSpec) -> Vec<String> {
    let mut h = vec!["run".to_string()];
    h.extend(TOLERANCES.iter().map(|t| t.name.to_string()));
    h.push("status".into());
    h.push("error".into());
    h.extend(figure_names(spec));
    h
}

/// `traces.csv`'s header: the run, the series, then the envelope grid's times [s].
fn traces_header(spec: &ScenarioSpec) -> Vec<String> {
    let mut h = vec!["run".to_string(), "series".to_string()];
    h.extend(envelope_grid(spec).1.iter().map(|t| t.to_string()));
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

fn record(spec: &ScenarioSpec, r: &RunRow) -> Vec<String> {
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
            v.extend(figure_names(spec).iter().map(|_| String::new()));
        }
    }
    v
}

/// A run's row, its CSV fields, and its trace rows (kept as read, so that a merge or a
/// resume writes the same bytes).
pub(crate) type Row = (RunRow, Vec<String>, Vec<Vec<String>>);

/// Read the rows of a `runs.csv` or `runs.partial.csv` (the header must match).
fn read_rows(path: &Path, spec: &ScenarioSpec, notes: &mut Vec<String>) -> Result<Vec<Row>> {
    let mut rd = csv::ReaderBuilder::new()
        .flexible(false)
        .from_path(path)
        .ctx(|| format!("cannot read {}", path.display()))?;
    let want = header(spec);
    let got: Vec<String> = rd
        .headers()
        .ctx(|| format!("cannot read {}", path.display()))?
        .iter()
        .map(String::from)
        .collect();
    if got != want {
        bail!(
            "{}: the header does not match this campaign's scenario",
            path.display()
        );
    }
    let mut rows = Vec::new();
    for (line, rec) in rd.records().enumerate() {
        let Ok(rec) = rec else {
            // A row cut by an interruption: everything before it counts.
            notes.push(format!(
                "warning: {} line {}: an incomplete row is ignored",
                path.display(),
                line + 2
            ));
            break;
        };
        let num = |s: &str| s.parse::<f64>();
        let index: u64 = rec[0]
            .parse()
            .ctx(|| format!("{} line {}", path.display(), line + 2))?;
        let mut values = [0.0; 5];
        for (j, vj) in values.iter_mut().enumerate() {
            *vj = num(&rec[1 + j]).ctx(|| format!("{} line {}", path.display(), line + 2))?;
        }
        let outcome = match &rec[6] {
            "ok" => Ok((8..rec.len())
                .map(|k| num(&rec[k]))
                .collect::<Result<Vec<_>, _>>()
                .ctx(|| format!("{} line {}", path.display(), line + 2))?),
            _ => Err(rec[7].to_string()),
        };
        rows.push((
            RunRow {
                index,
                values,
                outcome,
            },
            rec.iter().map(String::from).collect(),
            Vec::new(),
        ));
    }
    Ok(rows)
}

/// Attach the rows of a `traces.csv` or `traces.partial.csv` (if it exists) to their
/// runs; rows of runs not in `rows` are dropped (a kill between the two files).
fn attach_traces(path: &Path, spec: &ScenarioSpec, rows: &mut [Row]) -> Result<()> {
    if !path.exists() {
        return Ok(());
    }
    let mut rd = csv::ReaderBuilder::new()
        .flexible(false)
        .from_path(path)
        .ctx(|| format!("cannot read {}", path.display()))?;
    let got: Vec<String> = rd
        .headers()
        .ctx(|| format!("cannot read {}", path.display()))?
        .iter()
        .map(String::from)
        .collect();
    if got != traces_header(spec) {
        bail!(
            "{}: the header does not match this campaign's scenario",
            path.display()
        );
    }
    let at: std::collections::HashMap<u64, usize> =
        rows.iter().enumerate().map(|(k, r)| (r.0.index, k)).collect();
    for rec in rd.records() {
        let Ok(rec) = rec else { break };
        let Ok(index) = rec[0].parse::<u64>() else { break };
        if let Some(&k) = at.get(&index) {
            rows[k].2.push(rec.iter().map(String::from).collect());
        }
    }
    Ok(())
}

/// The envelope of the kept traces, per series, from their CSV fields.
fn envelopes(rows: &[Row], points: usize) -> Vec<(String, Envelope, usize)> {
    let mut out = Vec::new();
    for name in ["p_line", "p_line_pi"] {
        let traces: Vec<Vec<f64>> = rows
            .iter()
            .flat_map(|r| r.2.iter())
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

/// What `summary.json` holds.
#[derive(Debug, Serialize)]
struct CampaignSummary<'a> {
    campaign: &'a CampaignFile,
    runs_ok: usize,
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

/// Write `runs.csv` (sorted) and `summary.json` atomically, then drop the partial file.
fn finish(
    dir: &Path,
    file: &CampaignFile,
    spec: &ScenarioSpec,
    mut rows: Vec<Row>,
    notes: Vec<String>,
) -> Result<CampaignOutcome> {
    rows.sort_by_key(|r| r.0.index);
    let mut buf = Vec::new();
    {
        let mut w = csv::Writer::from_writer(&mut buf);
        w.write_record(header(spec))?;
        for (_, rec, _) in &rows {
            w.write_record(rec)?;
        }
        w.flush().map_err(csv::Error::from)?;
    }
    let (_, grid) = envelope_grid(spec);
    let env = envelopes(&rows, grid.len());
    let env_files = envelope_files(
        spec,
        &file.scenario,
        traces_header(spec),
        rows.iter().flat_map(|r| r.2.iter()),
        &grid,
        &env,
    )?;
    let envelope_runs = env.iter().map(|(n, _, k)| (n.clone(), *k)).collect();
    let rows: Vec<RunRow> = rows.into_iter().map(|r| r.0).collect();
    let names = figure_names(spec);
    let mut failures: Vec<(String, usize)> = Vec::new();
    for r in &rows {
        if let Err(e) = &r.outcome {
            match failures.iter_mut().find(|(m, _)| m == e) {
                Some((_, n)) => *n += 1,
                None => failures.push((e.clone(), 1)),
            }
        }
    }
    let ok = rows.iter().filter(|r| r.outcome.is_ok()).count();
    let (key, worst) = crate::worst_runs::describe(spec, &names, &rows)
        .map_err(|e| Error::Campaign(format!("cannot write a worst run's scenario: {e}")))?;
    let worst_runs: Vec<_> = worst.iter().map(|(w, _)| w.clone()).collect();
    let worst_files: Vec<String> = worst.iter().map(|(w, _)| w.file.clone()).collect();
    let summary = CampaignSummary {
        campaign: file,
        runs_ok: ok,
        runs_failed: rows.len() - ok,
        failures,
        plan: Plan::of(spec)?,
        figures: statistics(&names, &rows),
        envelope_runs,
        findings: crate::worst_runs::findings(key, &worst_runs),
        worst_runs,
    };
    let mut out = crate::OutputSet::new(dir)?;
    out.write("runs.csv", |w| w.write_all(&buf))?;
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
    let svg = histograms(&names, &rows, &file.scenario);
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
        runs: rows.len(),
        failed: rows.len() - ok,
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

/// Write the partial files afresh with the rows already done.
fn rewrite_partial(
    spec: &ScenarioSpec,
    partial: &Path,
    partial_tr: &Path,
    done: &[Row],
) -> std::result::Result<(), csv::Error> {
    let mut w = csv::Writer::from_path(partial)?;
    w.write_record(header(spec))?;
    let mut wt = csv::Writer::from_path(partial_tr)?;
    wt.write_record(traces_header(spec))?;
    for (_, rec, tr) in done {
        w.write_record(rec)?;
        for t in tr {
            wt.write_record(t)?;
        }
    }
    w.flush().map_err(csv::Error::from)?;
    wt.flush()?;
    Ok(())
}

/// The partial files open for appending, and the runs counted so far.
struct Appender {
    w: csv::Writer<std::fs::File>,
    wt: csv::Writer<std::fs::File>,
    n: usize,
    failed: usize,
    err: Option<std::io::Error>,
}

impl Appender {
    fn open(partial: &Path, partial_tr: &Path) -> Result<Self> {
        let append = |p: &Path| -> Result<csv::Writer<std::fs::File>> {
            let f = std::fs::OpenOptions::new()
                .append(true)
                .open(p)
                .ctx(|| format!("cannot append to {}", p.display()))?;
            Ok(csv::WriterBuilder::new().has_headers(false).from_writer(f))
        };
        Ok(Appender {
            w: append(partial)?,
            wt: append(partial_tr)?,
            n: 0,
            failed: 0,
            err: None,
        })
    }
}

/// Run (or resume) the campaign `o` of the scenario `spec` in the folder `dir`:
/// `campaign.json` first, each finished run appended to `runs.partial.csv` (and its
/// traces to `traces.partial.csv`) and flushed, then `runs.csv`, `summary.json`,
/// `histograms.svg` and the envelope's files, all or nothing. The same call on the same
/// folder resumes an interrupted campaign. `progress` is called after every run.
pub fn run_campaign(
    spec: &ScenarioSpec,
    o: &CampaignOptions,
    dir: &Path,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<CampaignOutcome> {
    let spec = spec.clone();
    spec.check()?;
    let plan = Plan::of(&spec)?;
    let sampling = if o.corners {
        Sampling::Corners
    } else {
        Sampling::Random
    };
    let runs = if o.corners { plan.corner_runs() } else { o.runs };
    if runs == 0 || runs > 10_000_000 {
        bail!("--runs {runs} is not allowed: give a number in [1, 10000000]");
    }
    let [k, m] = o.shard;
    let indices = [runs * (k - 1) / m, runs * k / m];
    let file = CampaignFile {
        scenario_toml: spec.to_toml(),
        scenario: spec.name.clone(),
        seed: o.seed,
        runs,
        sampling: if o.corners { "corners" } else { "random" }.into(),
        envelope_runs: o.envelope_runs,
        shard: o.shard,
        indices,
    };
    std::fs::create_dir_all(dir).at("create the folder", dir)?;
    let mut notes = Vec::new();
    let meta = dir.join("campaign.json");
    let partial = dir.join("runs.partial.csv");
    let partial_tr = dir.join("traces.partial.csv");
    let mut done: Vec<Row> = Vec::new();
    let wants_traces = |r: &RunRow| r.index < o.envelope_runs && r.outcome.is_ok();
    if meta.exists() {
        let text = std::fs::read_to_string(&meta).at("read", &meta)?;
        let old: CampaignFile =
            serde_json::from_str(&text).ctx(|| format!("{} is not a campaign file", meta.display()))?;
        if old != file {
            bail!(
                "{} holds another campaign (scenario, seed, runs, sampling, envelope runs or shard differ): give another --out",
                dir.display()
            );
        }
        if partial.exists() {
            done = read_rows(&partial, &spec, &mut notes)?;
            attach_traces(&partial_tr, &spec, &mut done)?;
            // A run whose traces were lost is run again.
            done.retain(|r| !wants_traces(&r.0) || !r.2.is_empty());
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
        let text = serde_json::to_string_pretty(&file).ctx(|| "campaign.json".into())?;
        let tmp = dir.join(".campaign.json.tmp");
        std::fs::write(&tmp, text + "\n").at("write", &tmp)?;
        std::fs::rename(&tmp, &meta).ctx(|| format!("cannot write {}", meta.display()))?;
    }
    let finished: std::collections::HashSet<u64> = done.iter().map(|r| r.0.index).collect();
    let todo: Vec<u64> = (indices[0]..indices[1])
        .filter(|i| !finished.contains(i))
        .collect();
    // Rewrite the partial files from their complete rows (a row cut by a kill is
    // dropped), then append each finished run, its traces first, and flush.
    rewrite_partial(&spec, &partial, &partial_tr, &done)
        .ctx(|| format!("cannot write {}", partial.display()))?;
    let start = Instant::now();
    let total = todo.len();
    let state = Mutex::new(Appender::open(&partial, &partial_tr)?);
    let new_rows: Vec<Row> = todo
        .par_iter()
        .map(|&i| {
            let (row, tr) = run_one(&spec, &plan, o.seed, i, sampling, i < o.envelope_runs);
            let rec = record(&spec, &row);
            let trs = tr.map(|t| trace_records(i, &t)).unwrap_or_default();
            let mut guard = state.lock().expect("no panic while holding the lock");
            let p = &mut *guard;
            let mut res = Ok(());
            for t in &trs {
                res = res.and(p.wt.write_record(t).map_err(std::io::Error::other));
            }
            res = res
                .and_then(|_| p.wt.flush())
                .and_then(|_| p.w.write_record(&rec).map_err(std::io::Error::other))
                .and_then(|_| p.w.flush());
            if let Err(e) = res {
                p.err.get_or_insert(e);
            }
            p.n += 1;
            p.failed += row.outcome.is_err() as usize;
            progress(Progress {
                scenario: &spec.name,
                done: p.n,
                total,
                failed: p.failed,
                elapsed_s: start.elapsed().as_secs_f64(),
            });
            (row, rec, trs)
        })
        .collect();
    let p = state.into_inner().expect("no panic while holding the lock");
    if let Some(e) = p.err {
        return Err(e).ctx(|| format!("cannot append to {}", partial.display()));
    }
    done.extend(new_rows);
    finish(dir, &file, &spec, done, notes)
}

/// Combine finished shard folders of one campaign into the folder `out` (`rhonn merge`).
pub fn merge_campaigns(dirs: &[PathBuf], out: &Path) -> Result<CampaignOutcome> {
    if dirs.is_empty() {
        bail!("give at least one campaign folder to merge");
    }
    if crate::plant_campaign::is_plant_campaign(&dirs[0]) {
        return crate::plant_campaign::merge_plant_campaigns(dirs, out);
    }
    let mut files = Vec::new();
    for d in dirs {
        let meta = d.join("campaign.json");
        let f: CampaignFile = serde_json::from_str(&std::fs::read_to_string(&meta).at("read", &meta)?)
            .ctx(|| format!("{} is not a campaign file", meta.display()))?;
        if !d.join("runs.csv").exists() {
            bail!("{} is not finished (no runs.csv): resume it first", d.display());
        }
        files.push(f);
    }
    let first = &files[0];
    for (d, f) in dirs.iter().zip(&files) {
        if (&f.scenario_toml, f.seed, f.runs, &f.sampling, f.envelope_runs)
            != (
                &first.scenario_toml,
                first.seed,
                first.runs,
                &first.sampling,
                first.envelope_runs,
            )
        {
            bail!(
                "{} is a different campaign from {}",
                d.display(),
                dirs[0].display()
            );
        }
    }
    let spec = ScenarioSpec::from_toml(&first.scenario_toml, "campaign.json")?;
    let mut rows = Vec::new();
    let mut notes = Vec::new();
    for d in dirs {
        let mut r = read_rows(&d.join("runs.csv"), &spec, &mut notes)?;
        attach_traces(&d.join("traces.csv"), &spec, &mut r)?;
        rows.extend(r);
    }
    rows.sort_by_key(|r| r.0.index);
    for w in rows.windows(2) {
        if w[0].0.index == w[1].0.index {
            bail!("run {} appears twice among the shards", w[0].0.index);
        }
    }
    if rows.len() as u64 != first.runs {
        bail!(
            "the shards hold {} of the campaign's {} runs: some shard is missing",
            rows.len(),
            first.runs
        );
    }
    let file = CampaignFile {
        shard: [1, 1],
        indices: [0, first.runs],
        ..first.clone()
    };
    finish(out, &file, &spec, rows, notes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn a_campaign_is_a_library_call_that_reports_progress_and_resumes() {
        let d = tempfile::tempdir().unwrap();
        let mut spec = rhonn::experiment::preset::load("thesis-ch3").unwrap();
        spec.duration_s = 0.5;
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
