//! `rhonn identify` (online RHONN identification of recordings) and `rhonn predict` with
//! its model.

use super::{context, read_text, Outcome};
use rhonn::any_model::{AnyModel, AnyPrediction};
use rhonn::ident::{OnlineModel, OnlineSpec};
use rhonn_report::identify::{write_identify, IdentifySummary};
use rhonn_report::{Error, Result};
use std::path::{Path, PathBuf};

/// What `rhonn identify` takes.
#[derive(Debug, Clone, Default)]
pub struct IdentifyRequest {
    /// The recordings to learn from, in order (CSV with `t` and the named columns).
    pub data: Vec<PathBuf>,
    /// Input columns.
    pub inputs: Vec<String>,
    /// Output columns.
    pub outputs: Vec<String>,
    /// The online model's spec (TOML); None: the defaults.
    pub model: Option<PathBuf>,
    /// Passes over the recordings (overrides the spec's `epochs`).
    pub epochs: Option<usize>,
    /// Recordings the frozen model is validated on.
    pub validate: Vec<PathBuf>,
    /// Validation K samples ahead as well as in free run.
    pub steps_ahead: Option<usize>,
    /// `--units`: `COLUMN=UNIT` pairs, printed with the figures.
    pub units: Vec<String>,
    /// `--time-column`: the column holding the time \[s\] (None: `t`).
    pub time_column: Option<String>,
    /// The output folder.
    pub out: PathBuf,
    /// Replace a different model.json in `out`.
    pub force: bool,
}

/// Paths as a comma-separated list, for messages.
fn list(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

pub(super) fn read_spec(p: &Path) -> Result<OnlineSpec> {
    online_spec(&read_text(p)?, &p.display().to_string())
}

/// An online model's settings from TOML; `source` names them in errors. A `rhonn fit`
/// spec of the same model is read as its online structure
/// (`rhonn::ident::shared_spec`), or refused naming the keys that differ.
pub fn online_spec(text: &str, source: &str) -> Result<OnlineSpec> {
    toml::from_str::<OnlineSpec>(text).or_else(|e| match rhonn::ident::shared_spec::online_from_fit(text) {
        Some(Ok(spec)) => Ok(spec),
        Some(Err(why)) => Err(Error::Input(format!("cannot read model spec {source}: {why}"))),
        None => Err(Error::Input(format!("cannot read model spec {source}: {e}"))),
    })
}

/// `rhonn identify`: learn the recordings online, validate the frozen model, write the
/// folder.
pub fn identify(a: &IdentifyRequest) -> Result<Outcome> {
    let inputs: Vec<PathBuf> = a
        .data
        .iter()
        .chain(&a.validate)
        .chain(&a.model)
        .cloned()
        .collect();
    super::in_folder(
        &a.out,
        (&inputs, rhonn_report::folder::writes::IDENTIFY),
        a.force,
        |stage| identify_into(a, stage),
    )
}

/// An identification's error, named by whose it is: a setting of the spec is the spec
/// file's; anything else is the data's (with the spec named).
fn identification_error(e: rhonn::Error, a: &IdentifyRequest) -> Error {
    let of_spec = matches!(&e, rhonn::Error::Invalid { value, .. } if value.field.starts_with("model."));
    let whose = match super::spec_blame(&e, a.model.as_deref()) {
        Some(whose) => whose,
        None if of_spec => "in the default model spec (give a spec with --model)".to_string(),
        None => format!(
            "online identification of {} with {}",
            list(&a.data),
            a.model
                .as_ref()
                .map_or("the default model spec".to_string(), |p| format!(
                    "the model spec {}",
                    p.display()
                ))
        ),
    };
    context(whose)(e.into())
}

fn identify_into(a: &IdentifyRequest, stage: &Path) -> Result<Outcome> {
    use rhonn::identification::{identify, IdentifyError, IdentifyPlan};
    let given = a.model.as_deref().map(read_spec).transpose()?;
    let (units, units_note) = super::parse_units(&a.units, &a.inputs, &a.outputs)?;
    rhonn::sysid::check_prediction_options(a.steps_ahead, None)
        .map_err(|e| Error::from(e.with_field_named("steps_ahead", "--steps-ahead")))?;
    if let (Some(k), true) = (a.steps_ahead, a.validate.is_empty()) {
        return Err(Error::Input(format!(
            "--steps-ahead {k} judges the frozen model {k} samples ahead on the --validate records, and none is given: add --validate FILE, or leave --steps-ahead out"
        )));
    }
    let read = read_all(a, &a.data)?;
    let vread = read_all(a, &a.validate)?;
    let (records, vrec) = (read.records, vread.records);
    let read_notes: Vec<String> = (read.regridded.iter().map(ToString::to_string))
        .chain(read.notes)
        .chain(vread.regridded.iter().map(ToString::to_string))
        .chain(vread.notes)
        .map(|n| format!("note: {n}"))
        .collect();
    let plan = IdentifyPlan {
        inputs: a.inputs.clone(),
        outputs: a.outputs.clone(),
        given,
        epochs: a.epochs,
        steps_ahead: a.steps_ahead,
        units,
    };
    let id = identify(&records, &vrec, &plan).map_err(|e| match e {
        IdentifyError::Online(e) => identification_error(e, a),
        IdentifyError::Validation(e) => e.into(),
        IdentifyError::Baseline(e) => context("the ARX baseline")(e.into()),
    })?;
    let files = write_identify(
        stage,
        &id.run,
        id.learned.as_deref().unwrap_or(&records),
        &a.outputs,
        &id.model,
        &id.summary,
        id.validation.as_ref(),
    )?;
    let mut warnings = rhonn::sysid::signal_warnings(&records, &a.inputs, &a.outputs);
    // Times in milliseconds read as seconds, as `rhonn fit` says it (the records are on
    // their uniform grid here).
    let sample_s = records.first().and_then(|r| Some(r.t.get(1)? - r.t.first()?));
    let ms = sample_s.and_then(|s| rhonn::sysid::milliseconds_hint(&records, s));
    warnings.extend(ms.map(|w| super::fit_args::COMMAND_LINE.data_warning(&w)));
    let mut o = Outcome {
        files,
        notes: units_note
            .into_iter()
            .chain(read_notes)
            .chain(id.guard_notes.iter().map(|n| format!("note: {n}")))
            .chain(warnings.iter().map(|w| format!("warning: {w}")))
            .collect(),
        ..Outcome::default()
    };
    o.lines = console_lines(&id.summary);
    Ok(o)
}

/// The records of `paths` under the one rule for gaps and grids (`rhonn fit`'s,
/// [`super::read_data_regridded`]), and its notes.
fn read_all(a: &IdentifyRequest, paths: &[PathBuf]) -> Result<super::ReadData> {
    if paths.is_empty() {
        return Ok(super::ReadData::default());
    }
    super::read_data_regridded(
        (paths, a.time_column.as_deref().unwrap_or("t")),
        &a.inputs,
        &a.outputs,
        2,
        None,
    )
}

/// The figures for the console: the online selection's winner and margin (when it chose),
/// the online fit, then per validation record and output the frozen free run beside the
/// offline ARX, then K samples ahead.
fn console_lines(summary: &IdentifySummary) -> Vec<String> {
    // The bank's winner and its margin over the best recursive ARX, first.
    let mut lines: Vec<String> = summary.selection.iter().flat_map(|s| s.findings()).collect();
    let unit = |col: &str| super::unit_of(&summary.units, col);
    for f in &summary.online {
        lines.push(format!(
            "{}: online (last half of the final pass) RMS error {}{}, fit {}",
            f.output,
            rhonn::metrics::sig(f.rms_error_last_half, 4),
            unit(&f.output),
            super::percent(f.fit_percent_last_half)
        ));
    }
    if let Some(b) = &summary.baseline_arx {
        for c in &b.records {
            lines.push(format!(
                "{} on {}: frozen, free run (from sample {}): RMS error {}{u}, fit {}; offline ARX ({}): RMS error {}{u}, fit {}",
                c.output,
                c.record,
                c.from_sample,
                rhonn::metrics::sig(c.online_rms_error, 4),
                super::percent(c.online_fit_percent),
                b.structure,
                rhonn::metrics::sig(c.arx_rms_error, 4),
                super::percent(c.arx_fit_percent),
                u = unit(&c.output)
            ));
        }
    }
    for v in &summary.validation {
        if let (Some(k), Some(r), Some(f)) = (v.horizon, v.ahead_rms_error, v.ahead_fit_percent) {
            lines.push(format!(
                "{}: {k} samples ahead, over every validation record: RMS error {}{}, fit {}",
                v.output,
                rhonn::metrics::sig(r, 4),
                unit(&v.output),
                super::percent(f)
            ));
        }
    }
    lines
}

/// `rhonn predict` with a `model.json` written by `rhonn identify`.
pub(super) fn predict_online(
    model_path: &Path,
    any: &AnyModel,
    m: &OnlineModel,
    (data, time): (&Path, &str),
    out: &Path,
    (steps, window): (Option<usize>, Option<usize>),
) -> Result<Outcome> {
    let needed = any.samples_needed(steps);
    let rec = rhonn_report::read_record_timed(data, time, &m.inputs, &m.outputs, needed)?;
    rhonn::ident::sample_time(std::slice::from_ref(&rec))?;
    let AnyPrediction::Online { rows: pred, figures } = any
        .predict_with(&rec, steps, window)
        .map_err(super::predicting(data, model_path))?
    else {
        unreachable!("an online model's prediction")
    };
    let files = rhonn_report::identify::write_online_prediction(
        out,
        m,
        &model_path.display().to_string(),
        &rec,
        &pred,
        (steps, window),
        &figures,
    )?;
    let mut o = Outcome {
        files,
        ..Outcome::default()
    };
    let mode = rhonn::metrics::prediction_mode(steps);
    for f in &figures {
        o.lines.push(format!(
            "{} ({mode}): rms error {}, fit {}, nrmse {}",
            f.output,
            rhonn::metrics::sig(f.rms_error, 4),
            super::percent(f.fit_percent),
            super::ratio(f.nrmse)
        ));
    }
    Ok(o)
}
