//! `rhonn identify --stream`: learn a live stream of CSV lines (standard input, or a file
//! that grows with `--follow`), one sample at a time (`rhonn::ident::Stream`); print the
//! estimate and the running prequential error every `every` samples; at the end of the
//! input (or when `stop` says so: Ctrl-C) freeze and write `model.json` and `summary.json`.
//! A malformed line is reported with its line number; the stream stops there (the model
//! learned so far is saved) or skips it, as `on_error` says.

use super::identify::read_spec;
use super::{in_folder, Outcome};
use rhonn::ident::{OnlineModel, Stream, StreamSummary};
use rhonn_report::{DataError, Error, OutputSet, Result};
use std::io::BufRead;
use std::path::PathBuf;

/// What a malformed line does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum OnError {
    /// Stop the stream there: the model learned so far is saved, and the command fails.
    #[default]
    Stop,
    /// Say so on stderr and go on with the next line.
    Skip,
}

/// What `rhonn identify --stream` takes.
#[derive(Debug, Clone, Default)]
pub struct StreamRequest {
    /// Where the samples come from, for messages ("standard input" or the file).
    pub source: String,
    /// Input columns.
    pub inputs: Vec<String>,
    /// Output columns.
    pub outputs: Vec<String>,
    /// The column holding the time \[s\] (None: `t`).
    pub time_column: Option<String>,
    /// The online model's spec (TOML); None: the bank chooses online.
    pub model: Option<PathBuf>,
    /// The stream's length, when known: the bank then judges it as `rhonn identify --data`
    /// judges a file of that length.
    pub samples: Option<usize>,
    /// Print a line every this many samples (at least 1).
    pub every: usize,
    /// What a malformed line does.
    pub on_error: OnError,
    /// The output folder.
    pub out: PathBuf,
    /// Replace a different model.json in `out`.
    pub force: bool,
}

/// The columns a stream reads: their names (the time's, the inputs', the outputs') and
/// positions in the header, and the header's width.
struct Columns {
    names: Vec<String>,
    at: Vec<usize>,
    width: usize,
}

/// The columns of the header line.
fn columns(req: &StreamRequest, header: &str) -> Result<Columns> {
    let heads: Vec<&str> = header.split(',').map(str::trim).collect();
    let names: Vec<String> = std::iter::once(req.time_column.clone().unwrap_or_else(|| "t".into()))
        .chain(req.inputs.iter().cloned())
        .chain(req.outputs.iter().cloned())
        .collect();
    let at = names
        .iter()
        .map(|c| {
            heads.iter().position(|h| h == c).ok_or_else(|| {
                Error::from(DataError::MissingColumn {
                    file: req.source.clone(),
                    column: c.clone(),
                    available: heads.join(", "),
                })
            })
        })
        .collect::<Result<_>>()?;
    Ok(Columns {
        names,
        at,
        width: heads.len(),
    })
}

/// One line's time, inputs and outputs, or what is wrong with it.
fn sample(
    req: &StreamRequest,
    (line, text): (u64, &str),
    cols: &Columns,
) -> Result<(f64, Vec<f64>, Vec<f64>)> {
    let cells: Vec<&str> = text.split(',').map(str::trim).collect();
    if cells.len() != cols.width {
        return Err(Error::Input(format!(
            "{}, line {line}: {} fields where the header has {}",
            req.source,
            cells.len(),
            cols.width
        )));
    }
    let mut v = Vec::with_capacity(cols.at.len());
    for (k, &i) in cols.at.iter().enumerate() {
        let Some(x) = rhonn_report::cell_value(cells[i]) else {
            return Err(DataError::BadCell {
                file: req.source.clone(),
                line,
                column: cols.names[k].clone(),
                value: cells[i].to_string(),
            }
            .into());
        };
        v.push(x);
    }
    let ni = req.inputs.len();
    Ok((v[0], v[1..1 + ni].to_vec(), v[1 + ni..].to_vec()))
}

/// `rhonn identify --stream`: learn the lines of `input` (a header, then one sample a
/// line) until its end or `stop()`, printing through `print` and saying each skipped line
/// through `warn` as it comes (a live stream may run for hours before its end); write the
/// folder. Returns the outcome, and the error that stopped the stream (with
/// `OnError::Stop`) after the model learned until then was written. A stream that stopped
/// before anything could be saved fails with the line that stopped it and why nothing was.
pub fn identify_stream(
    req: &StreamRequest,
    input: &mut dyn BufRead,
    print: &mut dyn FnMut(&str),
    warn: &mut dyn FnMut(&str),
    stop: &dyn Fn() -> bool,
) -> Result<(Outcome, Option<Error>)> {
    let spec = req.model.as_deref().map(read_spec).transpose()?;
    let mut stream = Stream::new(req.inputs.clone(), req.outputs.clone(), spec, req.samples)
        .map_err(|e| Error::Input(format!("{}: {e}", req.source)))?;
    let mut header = String::new();
    if input
        .read_line(&mut header)
        .map_err(|e| Error::Input(format!("{}: {e}", req.source)))?
        == 0
    {
        return Err(Error::Input(format!("{}: no header line", req.source)));
    }
    let cols = columns(req, header.trim_end())?;
    let hat: Vec<String> = req
        .outputs
        .iter()
        .map(|y| format!("{y}_hat,{y}_prequential_rms"))
        .collect();
    print(&format!("t,{}", hat.join(",")));
    let (mut line_no, mut stopped, mut skipped) = (1u64, None, 0usize);
    let mut text = String::new();
    while !stop() {
        text.clear();
        let n = input
            .read_line(&mut text)
            .map_err(|e| Error::Input(format!("{}: {e}", req.source)))?;
        if n == 0 {
            break;
        }
        line_no += 1;
        if text.trim().is_empty() {
            continue;
        }
        let step = sample(req, (line_no, text.trim_end()), &cols).and_then(|(t, u, y)| {
            let s = stream
                .push(t, &u, &y)
                .map_err(|e| Error::Input(format!("{}, line {line_no}: {e}", req.source)))?;
            Ok((t, s))
        });
        match (step, req.on_error) {
            (Ok((t, Some(s))), _) if (line_no - 1) % req.every.max(1) as u64 == 0 => {
                let cells: Vec<String> = s
                    .estimate
                    .iter()
                    .zip(&s.prequential_rms)
                    .map(|(e, r)| format!("{e},{r}"))
                    .collect();
                print(&format!("{t},{}", cells.join(",")));
            }
            (Ok(_), _) => {}
            (Err(e), OnError::Skip) => {
                skipped += 1;
                warn(&format!("warning: skipped: {e}"));
            }
            (Err(e), OnError::Stop) => {
                stopped = Some(e);
                break;
            }
        }
    }
    let (model, summary) = stream.finish().map_err(|e| {
        let e = format!("{}: {e}", req.source);
        Error::Input(match &stopped {
            Some(line) => format!(
                "{line}; the stream stopped there (--on-error stop) and nothing was written: what it learned before cannot be saved ({e})"
            ),
            None => e,
        })
    })?;
    let mut o = write_folder(req, &model, &summary)?;
    if skipped > 0 {
        let lines = rhonn::metrics::count(skipped, "malformed line");
        o.notes
            .insert(0, format!("note: {lines} skipped (each said above)"));
    }
    Ok((o, stopped))
}

/// The stream's folder: the frozen model and the summary, and what to say of them.
fn write_folder(req: &StreamRequest, model: &OnlineModel, summary: &StreamSummary) -> Result<Outcome> {
    let inputs: Vec<PathBuf> = req.model.iter().cloned().collect();
    in_folder(
        &req.out,
        (&inputs, rhonn_report::folder::writes::IDENTIFY),
        req.force,
        |stage| {
            let mut set = OutputSet::new(stage)?;
            set.write("summary.json", |w| rhonn_report::write_json(w, &summary))?;
            set.write("model.json", |w| rhonn_report::write_json(w, &model))?;
            let files = set.commit()?;
            let rms: Vec<String> = summary
                .outputs
                .iter()
                .zip(&summary.prequential_rms_error)
                .map(|(y, r)| format!("{y}: prequential RMS error {}", rhonn::metrics::sig(*r, 4)))
                .collect();
            Ok(Outcome {
                notes: summary.notes.iter().map(|n| format!("note: {n}")).collect(),
                lines: vec![format!(
                    "{} samples every {} s, frozen: {}",
                    summary.samples,
                    rhonn::metrics::sig(summary.sample_time_s, 4),
                    rms.join("; ")
                )],
                files,
            })
        },
    )
}
