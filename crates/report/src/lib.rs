/*!
Files of rhonn runs: `trajectory.csv` (SI columns), `summary.json`, and SVG plots in
display units (MPa, mm, A, dm^3/s). Every file of a run is first written under a
temporary name in the output folder and renamed only when all of them are complete
([`OutputSet`]), so a failed run leaves no half-written file.

```no_run
use rhonn::experiment::preset;
let run = preset::load_any("thesis-ch3")?.run()?;
rhonn_report::write_scenario_run(std::path::Path::new("out/thesis-ch3"), &run)?;
# Ok::<(), Box<dyn std::error::Error>>(())
```
*/
#![deny(missing_docs)]

mod atomic;
pub mod bench_report;
pub mod benchmark_data;
pub mod benchmark_file;
pub mod campaign_file;
pub mod campaign_rows;
pub mod corpus_file;
mod csv_out;
mod data_in;
pub mod fields;
pub mod folder;
pub mod glossary;
mod html;
pub mod identify;
pub mod plant_envelope;
mod plant_report;
mod plot;
mod prediction;
mod residuals;
pub mod scenario_run;
pub mod style;
pub mod worst_runs;

pub use atomic::OutputSet;
pub use csv_out::write_trace_csv;
pub use data_in::{cell_value, csv_header, read_record, read_record_timed, DataError};
pub use html::{write_report, write_report_as};
pub use plant_report::write_plant_run;
pub use plot::{bin_counts, Band, EnvelopePlot, Histogram, Series, TimePlot};
pub use prediction::{plot_prediction, prediction_trace, write_prediction};
pub use residuals::plot_residuals;
pub use scenario_run::write_scenario_run;

use std::path::{Path, PathBuf};

/// Errors while writing outputs.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The output folder cannot be created or written.
    #[error("cannot write to output folder {path}: {message}")]
    Folder {
        /// The folder.
        path: PathBuf,
        /// What the system said.
        message: String,
    },
    /// A campaign's files are inconsistent, or a step of it failed; the message names
    /// the file.
    #[error("{0}")]
    Campaign(String),
    /// An error of the model library (a scenario, a run).
    #[error(transparent)]
    Rhonn(#[from] rhonn::Error),
    /// A user's argument or file is not allowed; the message names it, the value and
    /// what is allowed.
    #[error("{0}")]
    Input(String),
    /// A data file is not readable as a recording.
    #[error(transparent)]
    Data(#[from] DataError),
    /// A step of a command failed: which step, and why (`source`).
    #[error("{context}")]
    Context {
        /// The step.
        context: String,
        /// Why.
        #[source]
        source: Box<Error>,
    },
    /// A file cannot be written.
    #[error("cannot write {path}: {message}")]
    File {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

impl Error {
    /// Its kind (a step's: its cause's).
    pub fn kind(&self) -> rhonn::ErrorKind {
        use rhonn::ErrorKind as K;
        match self {
            Error::Rhonn(e) => e.kind(),
            Error::Input(_) | Error::Data(_) => K::Input,
            Error::Context { source, .. } => source.kind(),
            Error::Folder { .. } | Error::File { .. } => K::Io,
            Error::Campaign(_) => K::Failed,
        }
    }

    /// The message with its causes, `step: cause` (as the command line prints them).
    pub fn message(&self) -> String {
        match self {
            Error::Context { context, source } => format!("{context}: {}", source.message()),
            e => e.to_string(),
        }
    }
}

/// Result alias.
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// `v` as pretty JSON with a final newline, as every JSON file of rhonn is written.
pub fn write_json(w: &mut dyn std::io::Write, v: &impl serde::Serialize) -> std::io::Result<()> {
    serde_json::to_writer_pretty(&mut *w, v).map_err(std::io::Error::other)?;
    writeln!(w)
}

/// Write what `rhonn fit` writes into `dir`: `model.json` (the fitted model, as
/// `rhonn predict` reads it), `summary.json`, and `training.svg` (measured against the
/// model's free run on each training record, `training_free_run`, beside the ARX
/// baseline's), all or nothing; returns the files.
pub fn write_fit(
    dir: &Path,
    fitted: &rhonn::sysid::FittedModel,
    summary: &rhonn::sysid::FitSummary,
    training_free_run: &[rhonn::sysid::Prediction],
) -> Result<Vec<PathBuf>> {
    let mut set = OutputSet::new(dir)?;
    set.write("model.json", |w| write_json(w, fitted))?;
    set.write("summary.json", |w| write_json(w, summary))?;
    for (k, p) in training_free_run.iter().enumerate() {
        let svg = plot_prediction(fitted, p);
        let name = if training_free_run.len() == 1 {
            "training.svg".to_string()
        } else {
            format!("training_{k}.svg")
        };
        set.write(&name, |w| w.write_all(svg.as_bytes()))?;
    }
    set.commit()
}
