//! The one campaign runner, for every scenario: `campaign.json` written first (or
//! checked, when the folder holds a campaign already), the partial files rewritten from
//! their complete rows, every missing run made in parallel and appended to
//! `runs.partial.csv` (its traces first to `traces.partial.csv`) and flushed, so that an
//! interrupted campaign resumes where it stopped; and `rhonn merge`'s reading of finished
//! shards. What a run is, what its row holds and how the folder is finished is the
//! [`CampaignKind`]'s (`plant.rs`).

use super::options::{CampaignOutcome, Progress};
use rayon::prelude::*;
use rhonn_report::campaign_rows::RowFormat;
pub(super) use rhonn_report::campaign_rows::{io_err, Runs};
use rhonn_report::Error;
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

type Result<T, E = Error> = std::result::Result<T, E>;

fn err(msg: String) -> Error {
    Error::Campaign(msg)
}

/// One run as it was just made: what the campaign's files get of it.
#[derive(Debug, Clone)]
pub(super) struct Done {
    /// Its `runs.csv` fields.
    pub fields: Vec<String>,
    /// Its `traces.csv` rows.
    pub traces: Vec<Vec<String>>,
    /// Whether the run failed.
    pub failed: bool,
}

/// What differs between the campaigns of the two scenario formats.
pub(super) trait CampaignKind: Sync + Sized {
    /// The kind's reading of a row.
    type Row;
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
    fn wants_traces(&self, _index: u64, _failed: bool) -> bool {
        false
    }
    /// Make run `index`.
    fn run(&self, index: u64) -> Done;
    /// Write the finished folder from every run (read back from `runs`, one at a time).
    fn finish(&self, dir: &Path, runs: &Runs, notes: Vec<String>) -> Result<CampaignOutcome>;
}

/// How the rows of the campaign `c` read.
fn format_of<C: CampaignKind>(c: &C) -> RowFormat<'_> {
    RowFormat {
        header: c.header(),
        failed: Box::new(|index, fields| c.parse(index, fields).map(|(_, failed)| failed)),
        traces_header: c.traces_header(),
    }
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
pub(super) fn run<C: CampaignKind>(
    c: &C,
    indices: [u64; 2],
    dir: &Path,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<CampaignOutcome> {
    std::fs::create_dir_all(dir).map_err(|e| io_err("create the folder", dir, e))?;
    // One campaign writes a folder at a time (a second is refused, not interleaved).
    let _lock = rhonn_report::folder::FolderLock::acquire(dir)?;
    let mut notes = Vec::new();
    let format = format_of(c);
    let meta = dir.join("campaign.json");
    let partial = dir.join("runs.partial.csv");
    let partial_tr = dir.join("traces.partial.csv");
    let mut kept: Option<Runs> = None;
    if meta.exists() {
        if read_file::<C>(&meta)? != *c.file() {
            return Err(err(format!(
                "{} holds another campaign (scenario, seed, runs, sampling, envelope runs or shard differ): give another --out",
                dir.display()
            )));
        }
        if partial.exists() {
            let mut runs = Runs::scan(
                &format,
                vec![partial.clone()],
                indices,
                "in the partial file",
                &mut notes,
            )?;
            runs.attach_traces(&format, &partial_tr)?;
            // A run whose traces were lost is run again.
            runs.drop_runs_without_traces(|index, failed| c.wants_traces(index, failed));
            notes.push(format!("resuming: {} runs already done", runs.len()));
            kept = Some(runs);
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
    rewrite_partial(c, &partial, &partial_tr, kept.as_ref())?;
    let todo: Vec<u64> = (indices[0]..indices[1])
        .filter(|&i| !kept.as_ref().is_some_and(|r| r.has(i)))
        .collect();
    drop(kept);
    run_missing(c, &todo, &partial, &partial_tr, progress)?;
    let mut runs = Runs::scan(&format, vec![partial], indices, "in the partial file", &mut notes)?;
    runs.attach_traces(&format, &partial_tr)?;
    if !runs.complete() {
        return Err(err(format!(
            "{} holds {} of this campaign's {} runs after the run: run the same command again to resume",
            dir.display(),
            runs.len(),
            indices[1] - indices[0]
        )));
    }
    c.finish(dir, &runs, notes)
}

/// Write the partial files afresh with the rows kept (a row cut by a kill is dropped),
/// through temporary files renamed over them.
fn rewrite_partial<C: CampaignKind>(
    c: &C,
    partial: &Path,
    partial_tr: &Path,
    kept: Option<&Runs>,
) -> Result<()> {
    let tmp = |p: &Path| p.with_extension("csv.tmp");
    let write = |p: &Path, f: &dyn Fn(&mut dyn std::io::Write) -> std::io::Result<()>| -> Result<()> {
        let t = tmp(p);
        let file = std::fs::File::create(&t).map_err(|e| io_err("write", &t, e))?;
        let mut w = std::io::BufWriter::new(file);
        f(&mut w)
            .and_then(|_| std::io::Write::flush(&mut w))
            .map_err(|e| io_err("write", &t, e))?;
        std::fs::rename(&t, p).map_err(|e| io_err("write", p, e))
    };
    write(partial, &|w| match kept {
        Some(r) => r.write_csv(&c.header(), w),
        None => csv_header(&c.header(), w),
    })?;
    if let Some(h) = c.traces_header() {
        write(partial_tr, &|w| {
            let mut wt = csv::Writer::from_writer(w);
            wt.write_record(&h)?;
            for t in kept.into_iter().flat_map(|r| r.traces()) {
                wt.write_record(t)?;
            }
            wt.flush()
        })?;
    }
    Ok(())
}

/// A CSV file's header line.
fn csv_header(header: &[String], w: &mut dyn std::io::Write) -> std::io::Result<()> {
    let mut c = csv::Writer::from_writer(w);
    c.write_record(header)?;
    c.flush()
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
) -> Result<()> {
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
    // Nothing of a run is kept here: its row is in the partial file, read back at the end.
    todo.par_iter().for_each(|&i| {
        // A stop asked for (`rhonn::cancel`, Python's Ctrl-C): no run more; those done
        // are in the partial file, which a later call resumes.
        if rhonn::cancel::requested() {
            return;
        }
        let d = c.run(i);
        let Ok(mut guard) = state.lock() else {
            return;
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
    });
    rhonn::cancel::check()?;
    let p = state
        .into_inner()
        .map_err(|_| err("a campaign worker panicked".into()))?;
    if let Some(e) = p.err {
        return Err(err(format!("cannot append to {}: {e}", partial.display())));
    }
    Ok(())
}

/// Combine finished shard folders of one campaign of kind `C` into `out` (`rhonn
/// merge`): the same files as the unsharded campaign.
pub(super) fn merge<C: CampaignKind>(dirs: &[PathBuf], out: &Path) -> Result<CampaignOutcome> {
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
    let mut notes = Vec::new();
    let files = dirs.iter().map(|d| d.join("runs.csv")).collect();
    let format = format_of(&c);
    let mut runs = Runs::scan(
        &format,
        files,
        [0, C::runs(&whole)],
        "among the shards",
        &mut notes,
    )?;
    for d in dirs {
        runs.attach_traces(&format, &d.join("traces.csv"))?;
    }
    if !runs.complete() {
        return Err(err(format!(
            "the shards hold {} of the campaign's {} runs: some shard is missing",
            runs.len(),
            C::runs(&whole)
        )));
    }
    std::fs::create_dir_all(out).map_err(|e| io_err("create", out, e))?;
    let _lock = rhonn_report::folder::FolderLock::acquire(out)?;
    write_json_atomic(&out.join("campaign.json"), c.file())?;
    c.finish(out, &runs, notes)
}
