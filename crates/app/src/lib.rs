//! Each command of `rhonn` as one library call: read the inputs a user names, run, write
//! the output folder, and say what happened in [`Outcome`] (lines for stdout, notes and
//! warnings for stderr, the files written). The binary parses arguments and prints an
//! `Outcome`; the Python package and tests call the same functions.

#![deny(missing_docs)]

pub mod any_model;
mod benchmark;
pub mod campaign;
mod corpus;
mod fit;
pub mod fit_args;
mod identify;
mod identify_stream;
mod reproduce;
mod run;

pub use benchmark::{benchmark, figure, BenchmarkRequest, Row};
pub use corpus::{corpus, CorpusRequest};
pub use fit::{
    fit, fit_in_memory, fit_structure, fit_with_progress, model_specs, parse_units, predict, read_data,
    read_data_regridded, FitRequest, ReadData,
};
pub use identify::{identify, online_spec, IdentifyRequest};
pub use identify_stream::{identify_stream, OnError, StreamRequest};
pub use reproduce::reproduce;
pub use run::{bench, run, run_scenario, save_plant_run, save_scenario_run, show, REPRODUCED};

use campaign::CampaignOutcome;
use std::path::{Path, PathBuf};

/// What a command did, to be shown to its user.
#[derive(Debug, Clone, Default)]
pub struct Outcome {
    /// Lines for stderr (warnings and notes, each with its `warning:` or `note:`).
    pub notes: Vec<String>,
    /// Lines for stdout: the figures.
    pub lines: Vec<String>,
    /// The files written.
    pub files: Vec<PathBuf>,
}

impl Outcome {
    /// Print: the notes to stderr, the lines to stdout, then one `  wrote FILE` per file.
    pub fn print(&self) {
        self.print_to(&mut |l| println!("{l}"));
    }

    /// As [`Outcome::print`], with the lines and files through `out` (a stream's command
    /// keeps standard output for its samples and prints these to stderr).
    pub fn print_to(&self, out: &mut dyn FnMut(&str)) {
        for n in &self.notes {
            eprintln!("{n}");
        }
        for l in &self.lines {
            out(l);
        }
        for f in &self.files {
            out(&format!("  wrote {}", f.display()));
        }
    }

    /// Append another outcome (a command made of several).
    pub fn extend(&mut self, other: Outcome) {
        self.notes.extend(other.notes);
        self.lines.extend(other.lines);
        self.files.extend(other.files);
    }
}

/// TOML text of a JSON object: a scenario or a model spec given as a Python dict, read
/// then as the file it would be.
pub fn toml_of_json(json: &str) -> rhonn_report::Result<String> {
    let bad =
        |e: &dyn std::fmt::Display| rhonn_report::Error::Input(format!("cannot be written as TOML: {e}"));
    let v: serde_json::Value =
        serde_json::from_str(json).map_err(|e| rhonn_report::Error::Input(format!("not JSON: {e}")))?;
    let t = toml::Value::try_from(v).map_err(|e| bad(&e))?;
    toml::to_string(&t).map_err(|e| bad(&e))
}

/// `rhonn campaign` and Python's `rhonn.campaign`: `sc`'s Monte Carlo campaign into `dir`
/// (resuming a folder an interrupted one left) on `threads` worker threads (None: every
/// core; 0 is refused with the door's own words `zero`), then its `report.html`; what to
/// tell the user.
pub fn campaign(
    sc: &rhonn::experiment::ScenarioSpec,
    opts: &campaign::CampaignOptions,
    dir: &Path,
    (threads, zero): (Option<usize>, &str),
    progress: &(dyn Fn(campaign::Progress) + Sync),
) -> rhonn_report::Result<Outcome> {
    let outcome = campaign::on_threads(threads, zero, || {
        campaign::run_scenario_campaign(sc, opts, dir, progress)
    })?;
    campaign_report(&outcome)
}

/// What a campaign (run, resumed or merged) tells its user, after writing its
/// `report.html`.
pub fn campaign_report(o: &CampaignOutcome) -> rhonn_report::Result<Outcome> {
    let mut out = campaign_outcome(o);
    out.files.push(rhonn_report::write_report(&o.dir)?);
    Ok(out)
}

/// `rhonn report DIR`: (re)build a folder's `report.html` from its files. A folder with a
/// manifest (`rhonn_report::folder`) is checked whole and from one run first, and its report is
/// committed with its files again (linked, not copied), so it shows only that run's.
pub fn report(dir: &Path) -> rhonn_report::Result<Outcome> {
    let listed = if dir.is_dir() {
        rhonn_report::folder::check_whole(dir)?
    } else {
        None
    };
    let Some(manifest) = listed else {
        let _lock = dir
            .is_dir()
            .then(|| rhonn_report::folder::FolderLock::acquire(dir))
            .transpose()?;
        return Ok(Outcome {
            files: vec![rhonn_report::write_report(dir)?],
            ..Outcome::default()
        });
    };
    let w = rhonn_report::folder::Writing::begin(dir, &[], &[], true)?;
    manifest.verify_except(dir, &["model.json"])?;
    for e in manifest.files.iter().filter(|e| e.path != "report.html") {
        let (from, to) = (dir.join(&e.path), w.stage().join(&e.path));
        let io = |err: std::io::Error| rhonn_report::Error::File {
            message: rhonn::error::path_problem(&to, &err),
            path: to.clone(),
        };
        if let Some(parent) = to.parent() {
            std::fs::create_dir_all(parent).map_err(io)?;
        }
        if std::fs::hard_link(&from, &to).is_err() {
            std::fs::copy(&from, &to).map_err(io)?;
        }
    }
    commit(w, Outcome::default())
}

/// What a campaign (run, resumed or merged) tells its user.
pub fn campaign_outcome(o: &CampaignOutcome) -> Outcome {
    let line = if o.already_complete {
        format!("campaign already complete in {}", o.dir.display())
    } else {
        format!(
            "campaign {}: {} runs, {} failed; wrote {}",
            o.scenario,
            o.runs,
            o.failed,
            o.dir.join("runs.csv").display()
        )
    };
    Outcome {
        notes: o.notes.clone(),
        lines: vec![line],
        files: Vec::new(),
    }
}

/// Run `f` into output folder `dir` as a whole (`rhonn_report::folder::Writing`): the folder
/// checked, locked and its interrupted commit finished before the work; `f` writes into the
/// staging folder it is given (`report.html` is rendered there after it); then the set is
/// committed in one step. `inputs`: this run's input files (never overwritten nor
/// removed), `writes`: the names it may write (`rhonn_report::folder::writes`); `force`: a
/// different `model.json`, or a file no earlier run's manifest lists, may be replaced.
pub(crate) fn in_folder(
    dir: &Path,
    (inputs, writes): (&[PathBuf], &[&str]),
    force: bool,
    f: impl FnOnce(&Path) -> rhonn_report::Result<Outcome>,
) -> rhonn_report::Result<Outcome> {
    let w = rhonn_report::folder::Writing::begin(dir, inputs, writes, force)?;
    let o = f(w.stage())?;
    commit(w, o)
}

/// Its `report.html`, rendered in the staging folder of `w` as the last file of `o`.
fn with_report(w: &rhonn_report::folder::Writing, mut o: Outcome) -> rhonn_report::Result<Outcome> {
    o.files.push(rhonn_report::write_report_as(w.stage(), w.dir())?);
    Ok(o)
}

/// Commit a writing whose files `o` names (at their staged paths), its `report.html`
/// rendered last: they move into the output folder, and `o` names them there, with the
/// notes of the commit.
pub(crate) fn commit(w: rhonn_report::folder::Writing, o: Outcome) -> rhonn_report::Result<Outcome> {
    let mut o = with_report(&w, o)?;
    let (stage, dir) = (w.stage().to_path_buf(), w.dir().to_path_buf());
    let c = w.commit()?;
    for f in &mut o.files {
        if let Ok(rel) = f.strip_prefix(&stage) {
            *f = dir.join(rel);
        }
    }
    // Messages name the folder the user gave, never the staging folder.
    let (from, to) = (stage.display().to_string(), dir.display().to_string());
    for l in o.lines.iter_mut().chain(o.notes.iter_mut()) {
        if l.contains(&from) {
            *l = l.replace(&from, &to);
        }
    }
    o.notes.extend(c.notes);
    Ok(o)
}

/// "in the model spec FILE" when `e` is about a setting of the spec (`model.*`) read from
/// `spec`: the context both `fit` and `identify` give such an error.
pub(crate) fn spec_blame(e: &rhonn::Error, spec: Option<&Path>) -> Option<String> {
    match (e, spec) {
        (rhonn::Error::Invalid { value, .. }, Some(p)) if value.field.starts_with("model.") => {
            Some(format!("in the model spec {}", p.display()))
        }
        _ => None,
    }
}

/// A fit in percent, or why it is undefined (a constant measured output).
pub(crate) fn percent(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.1} %")
    } else {
        "undefined (the measured output is constant)".into()
    }
}

/// A normalised error, or why it is undefined (a constant measured output).
pub(crate) fn ratio(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.4}")
    } else {
        "undefined".into()
    }
}

/// A file's text, or an error naming the file and what the system said.
pub(crate) fn read_text(p: &Path) -> rhonn_report::Result<String> {
    rhonn::error::read_text(p).map_err(|e| {
        rhonn_report::Error::Input(format!(
            "cannot read {}: {}",
            p.display(),
            rhonn::error::path_problem(p, &e)
        ))
    })
}

/// An error that says in which step of a command `source` happened.
pub(crate) fn context(what: impl Into<String>) -> impl FnOnce(rhonn_report::Error) -> rhonn_report::Error {
    let context = what.into();
    move |e| rhonn_report::Error::Context {
        context,
        source: Box::new(e),
    }
}

/// A model's refusal of a record (its sample time, its length, its run) named with the data
/// file and the model file.
pub(crate) fn predicting(data: &Path, model: &Path) -> impl FnOnce(rhonn::Error) -> rhonn_report::Error {
    let what = format!("predicting {} with the model {}", data.display(), model.display());
    move |e| context(what)(e.into())
}

/// " V" for a column with a unit, else "".
pub(crate) fn unit_of(units: &std::collections::BTreeMap<String, String>, col: &str) -> String {
    units.get(col).map_or(String::new(), |u| format!(" {u}"))
}

/// The Rust code blocks of the user guides (which call `rhonn`, `rhonn-report` and this
/// crate), compiled by `cargo test --doc` so that what a user copies builds (those that
/// read or write files are compiled, not run).
#[cfg(doctest)]
mod guides {
    #[doc = include_str!("../../../docs/guides/library.md")]
    struct Library;
    #[doc = include_str!("../../../docs/guides/identify.md")]
    struct Identify;
}
