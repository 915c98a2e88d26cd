//! The one campaign runner, for every scenario: `campaign.json` written first (or
//! checked, when the folder holds a campaign already), the partial files rewritten from
//! their complete rows, every missing run made in parallel and appended to
//! `runs.partial.csv` (its traces first to `traces.partial.csv`) and flushed, so that an
//! interrupted campaign resumes where it stopped; and `rhonn merge`'s reading of finished
//! shards. What a run is, what its row holds and how the folder is finished is the
//! [`CampaignKind`]'s: `campaign.rs` (the pump's runner) and `plant_campaign.rs`.

use crate::campaign_options::{CampaignOutcome, Progress};
use crate::Error;
use rayon::prelude::*;
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

type Result<T, E = Error> = std::result::Result<T, E>;

fn err(msg: String) -> Error {
    Error::Campaign(msg)
}

/// An input/output error on `path`: what was tried and what the path is.
pub(crate) fn io_err(verb: &str, path: &Path, e: std::io::Error) -> Error {
    err(format!(
        "cannot {verb} {}: {}",
        path.display(),
        rhonn::error::path_problem(path, &e)
    ))
}

/// One finished run as the campaign's files hold it.
#[derive(Debug, Clone)]
pub(crate) struct Done<R> {
    /// What the kind reads of the row (parsed figures, or nothing).
    pub row: R,
    /// Its run index.
    pub index: u64,
    /// Its `runs.csv` fields, as written (a resume or a merge writes the same bytes).
    pub fields: Vec<String>,
    /// Its `traces.csv` rows, as written.
    pub traces: Vec<Vec<String>>,
    /// Whether the run failed.
    pub failed: bool,
}

/// What differs between the campaigns of the two scenario formats.
pub(crate) trait CampaignKind: Sync + Sized {
    /// What a run's row gives the kind's `finish`.
    type Row: Send;
    /// `campaign.json`'s content.
    type File: Serialize + DeserializeOwned + PartialEq + Clone;
    /// What `campaign.json` is, in an error ("a campaign file").
    const FILE_IS: &'static str;
    /// The campaign's `campaign.json`.
    fn file(&self) -> &Self::File;
    /// `file` as one whole campaign (shard 1/1, every index): what a merge writes.
    fn whole(file: &Self::File) -> Self::File;
    /// The runs of the whole campaign `file` describes.
    fn runs(file: &Self::File) -> u64;
    /// The campaign of a finished folder's `campaign.json` (a merge's).
    fn from_file(file: &Self::File) -> Result<Self>;
    /// The scenario's name.
    fn scenario(&self) -> &str;
    /// `runs.csv`'s header.
    fn header(&self) -> Vec<String>;
    /// `traces.csv`'s header, if the campaign keeps traces.
    fn traces_header(&self) -> Option<Vec<String>>;
    /// The kind's reading of a row's fields (an error in words).
    fn parse(&self, index: u64, fields: &[String]) -> std::result::Result<(Self::Row, bool), String>;
    /// Whether a finished run should have traces (one without is run again on resume).
    fn wants_traces(&self, _done: &Done<Self::Row>) -> bool {
        false
    }
    /// Make run `index`.
    fn run(&self, index: u64) -> Done<Self::Row>;
    /// Write the finished folder from every run, sorted by index.
    fn finish(&self, dir: &Path, rows: Vec<Done<Self::Row>>, notes: Vec<String>) -> Result<CampaignOutcome>;
}

fn write_json_atomic(path: &Path, value: &impl Serialize) -> Result<()> {
    let text = serde_json::to_string_pretty(value).map_err(|e| err(format!("{}: {e}", path.display())))?;
    let tmp = path.with_file_name(format!(
        ".{}.tmp",
        path.file_name()
            .map_or("campaign.json".into(), |n| n.to_string_lossy())
    ));
    std::fs::write(&tmp, text + "\n").map_err(|e| io_err("write", &tmp, e))?;
    std::fs::rename(&tmp, path).map_err(|e| err(format!("cannot write {}: {e}", path.display())))
}

fn read_file<C: CampaignKind>(meta: &Path) -> Result<C::File> {
    let text = std::fs::read_to_string(meta).map_err(|e| io_err("read", meta, e))?;
    serde_json::from_str(&text).map_err(|e| err(format!("{} is not {}: {e}", meta.display(), C::FILE_IS)))
}

/// Run (or resume) the campaign `c` over run indices `indices` in `dir`; `progress` is
/// called after every run. Returns the finished folder's outcome (already complete: a
/// folder whose `runs.csv` is written and whose partial file is gone).
pub(crate) fn run<C: CampaignKind>(
    c: &C,
    indices: [u64; 2],
    dir: &Path,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<CampaignOutcome> {
    std::fs::create_dir_all(dir).map_err(|e| io_err("create the folder", dir, e))?;
    // One campaign writes a folder at a time (a second is refused, not interleaved).
    let _lock = crate::folder::FolderLock::acquire(dir)?;
    let mut notes = Vec::new();
    let meta = dir.join("campaign.json");
    let partial = dir.join("runs.partial.csv");
    let partial_tr = dir.join("traces.partial.csv");
    let mut done: Vec<Done<C::Row>> = Vec::new();
    if meta.exists() {
        if read_file::<C>(&meta)? != *c.file() {
            return Err(err(format!(
                "{} holds another campaign (scenario, seed, runs, sampling, envelope runs or shard differ): give another --out",
                dir.display()
            )));
        }
        if partial.exists() {
            done = read_rows(c, &partial, &mut notes)?;
            attach_traces(c, &partial_tr, &mut done)?;
            // A run whose traces were lost is run again.
            done.retain(|d| !c.wants_traces(d) || !d.traces.is_empty());
            notes.push(format!("resuming: {} runs already done", done.len()));
        } else if dir.join("runs.csv").exists() {
            return Ok(CampaignOutcome {
                scenario: c.scenario().to_string(),
                dir: dir.to_path_buf(),
                runs: 0,
                failed: 0,
                already_complete: true,
                notes,
            });
        }
    } else {
        write_json_atomic(&meta, c.file())?;
    }
    rewrite_partial(c, &partial, &partial_tr, &done)?;
    let have: std::collections::HashSet<u64> = done.iter().map(|d| d.index).collect();
    let todo: Vec<u64> = (indices[0]..indices[1]).filter(|i| !have.contains(i)).collect();
    let new_rows = run_missing(c, &todo, &partial, &partial_tr, progress)?;
    done.extend(new_rows);
    done.sort_by_key(|d| d.index);
    c.finish(dir, done, notes)
}

/// Write the partial files afresh with the rows kept (a row cut by a kill is dropped).
fn rewrite_partial<C: CampaignKind>(
    c: &C,
    partial: &Path,
    partial_tr: &Path,
    done: &[Done<C::Row>],
) -> Result<()> {
    fn csv_err(p: &Path) -> impl Fn(csv::Error) -> Error + '_ {
        move |e| err(format!("cannot write {}: {e}", p.display()))
    }
    let mut w = csv::Writer::from_path(partial).map_err(csv_err(partial))?;
    w.write_record(c.header()).map_err(csv_err(partial))?;
    for d in done {
        w.write_record(&d.fields).map_err(csv_err(partial))?;
    }
    w.flush().map_err(|e| io_err("write", partial, e))?;
    if let Some(h) = c.traces_header() {
        let mut wt = csv::Writer::from_path(partial_tr).map_err(csv_err(partial_tr))?;
        wt.write_record(h).map_err(csv_err(partial_tr))?;
        for t in done.iter().flat_map(|d| &d.traces) {
            wt.write_record(t).map_err(csv_err(partial_tr))?;
        }
        wt.flush().map_err(|e| io_err("write", partial_tr, e))?;
    }
    Ok(())
}

/// The partial files open for appending, and the runs counted so far.
struct Appender {
    w: csv::Writer<std::fs::File>,
    wt: Option<csv::Writer<std::fs::File>>,
    n: usize,
    failed: usize,
    err: Option<std::io::Error>,
}

/// Make the runs `todo` in parallel, appending each to the partial files (its traces
/// first) and flushing.
fn run_missing<C: CampaignKind>(
    c: &C,
    todo: &[u64],
    partial: &Path,
    partial_tr: &Path,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<Vec<Done<C::Row>>> {
    let append = |p: &Path| -> Result<csv::Writer<std::fs::File>> {
        let f = std::fs::OpenOptions::new()
            .append(true)
            .open(p)
            .map_err(|e| err(format!("cannot append to {}: {e}", p.display())))?;
        Ok(csv::WriterBuilder::new().has_headers(false).from_writer(f))
    };
    let state = Mutex::new(Appender {
        w: append(partial)?,
        wt: c.traces_header().map(|_| append(partial_tr)).transpose()?,
        n: 0,
        failed: 0,
        err: None,
    });
    let start = Instant::now();
    let rows: Vec<Done<C::Row>> = todo
        .par_iter()
        .filter_map(|&i| {
            // A stop asked for (`rhonn::cancel`, Python's Ctrl-C): no run more; those done
            // are in the partial file, which a later call resumes.
            if rhonn::cancel::requested() {
                return None;
            }
            let d = c.run(i);
            let Ok(mut guard) = state.lock() else {
                return Some(d);
            };
            let p = &mut *guard;
            let mut res = Ok(());
            if let Some(wt) = &mut p.wt {
                for t in &d.traces {
                    res = res.and(wt.write_record(t).map_err(std::io::Error::other));
                }
                res = res.and_then(|_| wt.flush());
            }
            res = res
                .and_then(|_| p.w.write_record(&d.fields).map_err(std::io::Error::other))
                .and_then(|_| p.w.flush());
            if let Err(e) = res {
                p.err.get_or_insert(e);
            }
            p.n += 1;
            p.failed += usize::from(d.failed);
            progress(Progress {
                scenario: c.scenario(),
                done: p.n,
                total: todo.len(),
                failed: p.failed,
                elapsed_s: start.elapsed().as_secs_f64(),
            });
            Some(d)
        })
        .collect();
    rhonn::cancel::check()?;
    let p = state
        .into_inner()
        .map_err(|_| err("a campaign worker panicked".into()))?;
    if let Some(e) = p.err {
        return Err(err(format!("cannot append to {}: {e}", partial.display())));
    }
    Ok(rows)
}

/// A reader of the CSV file `path`, whose header must be `want`.
fn reader(path: &Path, want: &[String]) -> Result<csv::Reader<std::fs::File>> {
    let mut rd = csv::ReaderBuilder::new()
        .flexible(false)
        .from_path(path)
        .map_err(|e| err(format!("cannot read {}: {e}", path.display())))?;
    let got: Vec<String> = rd
        .headers()
        .map_err(|e| err(format!("cannot read {}: {e}", path.display())))?
        .iter()
        .map(String::from)
        .collect();
    if got != want {
        return Err(err(format!(
            "{}: the header does not match this campaign's scenario",
            path.display()
        )));
    }
    Ok(rd)
}

/// The rows of a `runs.csv` or `runs.partial.csv` (its header must be the campaign's); a
/// row cut by an interruption ends the reading, with a warning.
fn read_rows<C: CampaignKind>(c: &C, path: &Path, notes: &mut Vec<String>) -> Result<Vec<Done<C::Row>>> {
    let mut rd = reader(path, &c.header())?;
    let mut rows = Vec::new();
    for (line, rec) in rd.records().enumerate() {
        let Ok(rec) = rec else {
            notes.push(format!(
                "warning: {} line {}: an incomplete row is ignored",
                path.display(),
                line + 2
            ));
            break;
        };
        let fields: Vec<String> = rec.iter().map(String::from).collect();
        let at = |e: String| err(format!("{} line {}: {e}", path.display(), line + 2));
        let index = fields[0]
            .parse::<u64>()
            .map_err(|_| at(format!("run `{}` is not an index", fields[0])))?;
        let (row, failed) = c.parse(index, &fields).map_err(at)?;
        rows.push(Done {
            row,
            index,
            fields,
            traces: Vec::new(),
            failed,
        });
    }
    Ok(rows)
}

/// Attach the rows of a `traces.csv` or `traces.partial.csv` (if the campaign keeps
/// traces and the file exists) to their runs; rows of runs not in `rows` are dropped (a
/// kill between the two files).
fn attach_traces<C: CampaignKind>(c: &C, path: &Path, rows: &mut [Done<C::Row>]) -> Result<()> {
    let Some(header) = c.traces_header() else {
        return Ok(());
    };
    if !path.exists() {
        return Ok(());
    }
    let mut rd = reader(path, &header)?;
    let at: std::collections::HashMap<u64, usize> =
        rows.iter().enumerate().map(|(k, r)| (r.index, k)).collect();
    for rec in rd.records() {
        let Ok(rec) = rec else { break };
        let Ok(index) = rec[0].parse::<u64>() else { break };
        if let Some(&k) = at.get(&index) {
            rows[k].traces.push(rec.iter().map(String::from).collect());
        }
    }
    Ok(())
}

/// Combine finished shard folders of one campaign of kind `C` into `out` (`rhonn
/// merge`): the same files as the unsharded campaign.
pub(crate) fn merge<C: CampaignKind>(dirs: &[PathBuf], out: &Path) -> Result<CampaignOutcome> {
    let Some(first_dir) = dirs.first() else {
        return Err(err("give at least one campaign folder to merge".into()));
    };
    let mut files = Vec::new();
    for d in dirs {
        let f = read_file::<C>(&d.join("campaign.json"))?;
        if !d.join("runs.csv").exists() {
            return Err(err(format!(
                "{} is not finished (no runs.csv): resume it first",
                d.display()
            )));
        }
        files.push(f);
    }
    let whole = C::whole(&files[0]);
    for (d, f) in dirs.iter().zip(&files) {
        if C::whole(f) != whole {
            return Err(err(format!(
                "{} is a different campaign from {}",
                d.display(),
                first_dir.display()
            )));
        }
    }
    let c = C::from_file(&whole)?;
    let (mut rows, mut notes) = (Vec::new(), Vec::new());
    for d in dirs {
        let mut r = read_rows(&c, &d.join("runs.csv"), &mut notes)?;
        attach_traces(&c, &d.join("traces.csv"), &mut r)?;
        rows.extend(r);
    }
    rows.sort_by_key(|d| d.index);
    if let Some(w) = rows.windows(2).find(|w| w[0].index == w[1].index) {
        return Err(err(format!("run {} appears twice among the shards", w[0].index)));
    }
    if rows.len() as u64 != C::runs(&whole) {
        return Err(err(format!(
            "the shards hold {} of the campaign's {} runs: some shard is missing",
            rows.len(),
            C::runs(&whole)
        )));
    }
    std::fs::create_dir_all(out).map_err(|e| io_err("create", out, e))?;
    let _lock = crate::folder::FolderLock::acquire(out)?;
    write_json_atomic(&out.join("campaign.json"), c.file())?;
    c.finish(out, rows, notes)
}
