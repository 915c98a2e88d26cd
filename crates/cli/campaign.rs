//! `rhonn campaign` and `rhonn merge`: the files of a Monte Carlo campaign.
//!
//! `DIR/campaign.json` says what the campaign is (scenario, seed, runs, sampling, shard);
//! finished runs are appended to `DIR/runs.partial.csv` and flushed one by one, so an
//! interrupted campaign loses nothing and `rhonn campaign` with the same arguments
//! resumes it; at the end `DIR/runs.csv` holds every row sorted by run index (the same
//! bytes whatever the thread count or sharding) and `DIR/summary.json` the statistics.

use anyhow::{bail, Context, Result};
use rayon::prelude::*;
use rhonn::experiment::campaign::{
    figure_names, run_one, statistics, FigureStats, RunRow, Sampling, TOLERANCES,
};
use rhonn::experiment::{preset, ScenarioSpec};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

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
    /// `uniform` or `corners`.
    pub sampling: String,
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

/// The scenario's values of the uncertain parameters (display units, [`TOLERANCES`] order).
fn base_values(spec: &ScenarioSpec) -> [f64; 5] {
    let p = &spec.plant;
    [p.beta_mpa, p.mu_1, p.mu_2, p.q_0_dm3_s, p.qdot_max_dm3_s2]
}

/// The parameter values of a run (display units, as the scenario's `[plant]` keys).
fn parameter_values(spec: &ScenarioSpec, f: &[f64; 5]) -> [f64; 5] {
    let mut v = base_values(spec);
    for (x, fj) in v.iter_mut().zip(f) {
        *x *= fj;
    }
    v
}

fn record(spec: &ScenarioSpec, r: &RunRow) -> Vec<String> {
    let mut v = vec![r.index.to_string()];
    v.extend(parameter_values(spec, &r.factors).iter().map(|x| x.to_string()));
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

/// A run's row and its CSV fields (kept as read, so that a merge or a resume writes the
/// same bytes).
type Row = (RunRow, Vec<String>);

/// Read the rows of a `runs.csv` or `runs.partial.csv` (the header must match).
fn read_rows(path: &Path, spec: &ScenarioSpec) -> Result<Vec<Row>> {
    let mut rd = csv::ReaderBuilder::new()
        .flexible(false)
        .from_path(path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    let want = header(spec);
    let got: Vec<String> = rd.headers()?.iter().map(String::from).collect();
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
            eprintln!(
                "warning: {} line {}: an incomplete row is ignored",
                path.display(),
                line + 2
            );
            break;
        };
        let num = |s: &str| s.parse::<f64>();
        let index: u64 = rec[0]
            .parse()
            .with_context(|| format!("{} line {}", path.display(), line + 2))?;
        let mut factors = [1.0; 5];
        for (j, (fj, base)) in factors.iter_mut().zip(base_values(spec)).enumerate() {
            *fj = num(&rec[1 + j])? / base;
        }
        let outcome = match &rec[6] {
            "ok" => Ok((8..rec.len())
                .map(|k| num(&rec[k]))
                .collect::<Result<Vec<_>, _>>()
                .with_context(|| format!("{} line {}", path.display(), line + 2))?),
            _ => Err(rec[7].to_string()),
        };
        rows.push((
            RunRow {
                index,
                factors,
                outcome,
            },
            rec.iter().map(String::from).collect(),
        ));
    }
    Ok(rows)
}

/// What `summary.json` holds.
#[derive(Debug, Serialize)]
struct CampaignSummary<'a> {
    campaign: &'a CampaignFile,
    runs_ok: usize,
    runs_failed: usize,
    /// Failure reasons and how many runs gave each.
    failures: Vec<(String, usize)>,
    figures: Vec<FigureStats>,
}

/// Write `runs.csv` (sorted) and `summary.json` atomically, then drop the partial file.
fn finish(dir: &Path, file: &CampaignFile, spec: &ScenarioSpec, mut rows: Vec<Row>) -> Result<()> {
    rows.sort_by_key(|r| r.0.index);
    let mut buf = Vec::new();
    {
        let mut w = csv::Writer::from_writer(&mut buf);
        w.write_record(header(spec))?;
        for (_, rec) in &rows {
            w.write_record(rec)?;
        }
        w.flush()?;
    }
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
    let summary = CampaignSummary {
        campaign: file,
        runs_ok: ok,
        runs_failed: rows.len() - ok,
        failures,
        figures: statistics(&names, &rows),
    };
    let mut out = rhonn_report::OutputSet::new(dir)?;
    out.write("runs.csv", |w| w.write_all(&buf))?;
    out.write("summary.json", |w| {
        serde_json::to_writer_pretty(&mut *w, &summary).map_err(std::io::Error::other)?;
        writeln!(w)
    })?;
    out.write("campaign.json", |w| {
        serde_json::to_writer_pretty(&mut *w, file).map_err(std::io::Error::other)?;
        writeln!(w)
    })?;
    // Histograms of the figures that judge a controller (or every figure otherwise).
    let key = |n: &str| {
        [
            "ise_mpa2_s",
            "max_abs_deviation_settled_mpa",
            "time_below_p_min_after_1s_s",
            "pi_ise_mpa2_s",
            "pi_max_abs_deviation_settled_mpa",
            "pi_time_below_p_min_after_1s_s",
        ]
        .contains(&n)
            || n.ends_with("fit_percent")
    };
    let any_key = names.iter().any(|n| key(n));
    let panels: Vec<rhonn_report::Histogram> = names
        .iter()
        .enumerate()
        .filter(|(_, n)| !any_key || key(n))
        .map(|(k, n)| rhonn_report::Histogram {
            title: format!("{}: {n}", file.scenario),
            x_label: n.clone(),
            values: rows
                .iter()
                .filter_map(|r| r.outcome.as_ref().ok().map(|f| f[k]))
                .collect(),
        })
        .collect();
    let svg = rhonn_report::Histogram::render(&panels, 3, 30);
    out.write("histograms.svg", |w| w.write_all(svg.as_bytes()))?;
    out.commit()?;
    let partial = dir.join("runs.partial.csv");
    if partial.exists() {
        std::fs::remove_file(&partial)?;
    }
    println!(
        "campaign {}: {} runs, {} failed; wrote {}",
        file.scenario,
        rows.len(),
        rows.len() - ok,
        dir.join("runs.csv").display()
    );
    Ok(())
}

/// Parse `K/M`.
pub fn parse_shard(s: &str) -> Result<[u64; 2]> {
    let bad = || anyhow::anyhow!("--shard {s:?} is not allowed: give K/M with 1 <= K <= M, e.g. 2/4");
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

/// `rhonn campaign`.
pub fn cmd_campaign(
    scenario: &str,
    runs: u64,
    seed: u64,
    shard: [u64; 2],
    corners: bool,
    out: Option<PathBuf>,
) -> Result<()> {
    let spec = preset::load(scenario)?;
    spec.check()?;
    let sampling = if corners {
        Sampling::Corners
    } else {
        Sampling::Uniform
    };
    let runs = if corners { 1 << TOLERANCES.len() } else { runs };
    if runs == 0 || runs > 10_000_000 {
        bail!("--runs {runs} is not allowed: give a number in [1, 10000000]");
    }
    let [k, m] = shard;
    let indices = [runs * (k - 1) / m, runs * k / m];
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(format!("campaign-{}", spec.name)));
    let file = CampaignFile {
        scenario_toml: spec.to_toml(),
        scenario: spec.name.clone(),
        seed,
        runs,
        sampling: if corners { "corners" } else { "uniform" }.into(),
        shard,
        indices,
    };
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let meta = dir.join("campaign.json");
    let partial = dir.join("runs.partial.csv");
    let mut done: Vec<Row> = Vec::new();
    if meta.exists() {
        let old: CampaignFile = serde_json::from_str(&std::fs::read_to_string(&meta)?)
            .with_context(|| format!("{} is not a campaign file", meta.display()))?;
        if old != file {
            bail!(
                "{} holds another campaign (scenario, seed, runs, sampling or shard differ): give another --out",
                dir.display()
            );
        }
        if partial.exists() {
            done = read_rows(&partial, &spec)?;
            eprintln!("resuming: {} runs already done", done.len());
        } else if dir.join("runs.csv").exists() {
            println!("campaign already complete in {}", dir.display());
            return Ok(());
        }
    } else {
        let text = serde_json::to_string_pretty(&file)?;
        let tmp = dir.join(".campaign.json.tmp");
        std::fs::write(&tmp, text + "\n")?;
        std::fs::rename(&tmp, &meta)?;
    }
    let finished: std::collections::HashSet<u64> = done.iter().map(|r| r.0.index).collect();
    let todo: Vec<u64> = (indices[0]..indices[1])
        .filter(|i| !finished.contains(i))
        .collect();
    // Rewrite the partial file from its complete rows (a row cut by a kill is dropped),
    // then append each finished run and flush it.
    {
        let mut w = csv::Writer::from_path(&partial)?;
        w.write_record(header(&spec))?;
        for (_, rec) in &done {
            w.write_record(rec)?;
        }
        w.flush()?;
    }
    let writer = std::fs::OpenOptions::new().append(true).open(&partial)?;
    struct Progress {
        w: csv::Writer<std::fs::File>,
        n: usize,
        failed: usize,
        last: Instant,
        err: Option<std::io::Error>,
    }
    let start = Instant::now();
    let total = todo.len();
    let state = Mutex::new(Progress {
        w: csv::WriterBuilder::new().has_headers(false).from_writer(writer),
        n: 0,
        failed: 0,
        last: start,
        err: None,
    });
    let new_rows: Vec<Row> = todo
        .par_iter()
        .map(|&i| {
            let row = run_one(&spec, seed, i, sampling);
            let rec = record(&spec, &row);
            let mut p = state.lock().expect("no panic while holding the lock");
            let res =
                p.w.write_record(&rec)
                    .map_err(std::io::Error::other)
                    .and_then(|_| p.w.flush());
            if let Err(e) = res {
                p.err.get_or_insert(e);
            }
            p.n += 1;
            p.failed += row.outcome.is_err() as usize;
            if p.last.elapsed().as_secs_f64() >= 1.0 || p.n == total {
                p.last = Instant::now();
                let rate = p.n as f64 / start.elapsed().as_secs_f64();
                eprintln!(
                    "campaign {}: {}/{} runs, {} failed, {:.1} runs/s, ETA {:.0} s",
                    spec.name,
                    p.n,
                    total,
                    p.failed,
                    rate,
                    (total - p.n) as f64 / rate.max(1e-9)
                );
            }
            (row, rec)
        })
        .collect();
    if let Some(e) = state.into_inner().expect("no panic while holding the lock").err {
        return Err(e).context(format!("cannot append to {}", partial.display()));
    }
    done.extend(new_rows);
    finish(&dir, &file, &spec, done)
}

/// `rhonn merge`: combine shard folders into one campaign.
pub fn cmd_merge(dirs: &[PathBuf], out: &Path) -> Result<()> {
    if dirs.is_empty() {
        bail!("give at least one campaign folder to merge");
    }
    let mut files = Vec::new();
    for d in dirs {
        let meta = d.join("campaign.json");
        let f: CampaignFile = serde_json::from_str(
            &std::fs::read_to_string(&meta).with_context(|| format!("cannot read {}", meta.display()))?,
        )
        .with_context(|| format!("{} is not a campaign file", meta.display()))?;
        if !d.join("runs.csv").exists() {
            bail!("{} is not finished (no runs.csv): resume it first", d.display());
        }
        files.push(f);
    }
    let first = &files[0];
    for (d, f) in dirs.iter().zip(&files) {
        if (&f.scenario_toml, f.seed, f.runs, &f.sampling)
            != (&first.scenario_toml, first.seed, first.runs, &first.sampling)
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
    for d in dirs {
        rows.extend(read_rows(&d.join("runs.csv"), &spec)?);
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
    finish(out, &file, &spec, rows)
}
