//! Each command of `rhonn` as one library call: read the inputs a user names, run, write
//! the output folder, and say what happened in [`Outcome`] (lines for stdout, notes and
//! warnings for stderr, the files written). The binary parses arguments and prints an
//! `Outcome`; the Python package and tests call the same functions.

mod benchmark;
mod fit;
mod identify;
mod run;

pub use benchmark::{benchmark, figure, BenchmarkRequest, Row};
pub use fit::{
    fit, fit_in_memory, fit_structure, fit_with_progress, model_specs, parse_units, predict, read_data,
    FitRequest,
};
pub use identify::{identify, online_spec, IdentifyRequest};
pub use run::{bench, run, run_scenario, save_plant_run, save_scenario_run, show, REPRODUCED};

use crate::campaign::CampaignOutcome;
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
        for n in &self.notes {
            eprintln!("{n}");
        }
        for l in &self.lines {
            println!("{l}");
        }
        for f in &self.files {
            println!("  wrote {}", f.display());
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
pub fn toml_of_json(json: &str) -> crate::Result<String> {
    let bad = |e: &dyn std::fmt::Display| crate::Error::Input(format!("cannot be written as TOML: {e}"));
    let v: serde_json::Value =
        serde_json::from_str(json).map_err(|e| crate::Error::Input(format!("not JSON: {e}")))?;
    let t = toml::Value::try_from(v).map_err(|e| bad(&e))?;
    toml::to_string(&t).map_err(|e| bad(&e))
}

/// `rhonn campaign` and Python's `rhonn.campaign`: `sc`'s Monte Carlo campaign into `dir`
/// (resuming a folder an interrupted one left) on `threads` worker threads (None: every
/// core; 0 is refused with the door's own words `zero`), then its `report.html`; what to
/// tell the user.
pub fn campaign(
    sc: &rhonn::experiment::ScenarioSpec,
    opts: &crate::campaign::CampaignOptions,
    dir: &Path,
    (threads, zero): (Option<usize>, &str),
    progress: &(dyn Fn(crate::campaign::Progress) + Sync),
) -> crate::Result<Outcome> {
    let outcome = crate::campaign::on_threads(threads, zero, || {
        crate::scenario_run::run_scenario_campaign(sc, opts, dir, progress)
    })?;
    campaign_report(&outcome)
}

/// What a campaign (run, resumed or merged) tells its user, after writing its
/// `report.html`.
pub fn campaign_report(o: &CampaignOutcome) -> crate::Result<Outcome> {
    let mut out = campaign_outcome(o);
    out.files.push(crate::write_report(&o.dir)?);
    Ok(out)
}

/// `rhonn report DIR`: (re)build a folder's `report.html` from its files.
pub fn report(dir: &Path) -> crate::Result<Outcome> {
    Ok(Outcome {
        files: vec![crate::write_report(dir)?],
        ..Outcome::default()
    })
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

/// Check `dir` before the work of `f` (writable, or creatable), run `f`, then remove the
/// run files of an earlier run in `dir` that `f` did not write (`crate::folder`), saying
/// so in a note.
pub(crate) fn in_folder(dir: &Path, f: impl FnOnce() -> crate::Result<Outcome>) -> crate::Result<Outcome> {
    crate::folder::check_writable(dir)?;
    let mut o = f()?;
    finish_folder(dir, &mut o)?;
    Ok(o)
}

/// Remove the run files of an earlier run that `o` did not write into `dir`; when any
/// went, `report.html` (which shows the folder's plots) is written again without them.
pub(crate) fn finish_folder(dir: &Path, o: &mut Outcome) -> crate::Result<()> {
    let removed = crate::folder::remove_stale(dir, &o.files);
    for r in &removed {
        o.notes.push(format!(
            "note: removed {} (an earlier run's file, which this run does not write)",
            r.display()
        ));
    }
    if !removed.is_empty() && o.files.iter().any(|f| f.ends_with("report.html")) {
        crate::write_report(dir)?;
    }
    Ok(())
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
pub(crate) fn read_text(p: &Path) -> crate::Result<String> {
    rhonn::error::read_text(p).map_err(|e| {
        crate::Error::Input(format!(
            "cannot read {}: {}",
            p.display(),
            rhonn::error::path_problem(p, &e)
        ))
    })
}

/// An error that says in which step of a command `source` happened.
pub(crate) fn context(what: impl Into<String>) -> impl FnOnce(crate::Error) -> crate::Error {
    let context = what.into();
    move |e| crate::Error::Context {
        context,
        source: Box::new(e),
    }
}

/// " V" for a column with a unit, else "".
pub(crate) fn unit_of(units: &std::collections::BTreeMap<String, String>, col: &str) -> String {
    units.get(col).map_or(String::new(), |u| format!(" {u}"))
}
