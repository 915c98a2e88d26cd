//! `rhonn fit` and `rhonn predict`: offline models of recordings.

use super::fit_args::FitArgs;
use super::{context, read_text, unit_of, Outcome};
use rhonn::any_model::{AnyModel, AnyPrediction, ModelFileError};
use rhonn::data::Record;
use rhonn::metrics::count;
use rhonn::sysid::select::SelectOptions;
use rhonn::sysid::{parse_spec_file, FitStructure, ModelSpec, RecordFigures};
use rhonn_report::{Error, Result};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What `rhonn fit` takes.
#[derive(Debug, Clone, Default)]
pub struct FitRequest {
    /// The training recordings (CSV with `t` and the named columns).
    pub data: Vec<PathBuf>,
    /// Input columns.
    pub inputs: Vec<String>,
    /// Output columns.
    pub outputs: Vec<String>,
    /// A model spec (TOML); None: the default structure.
    pub model: Option<PathBuf>,
    /// `--resample`: the uniform grid's interval \[s\] (None: each record's median).
    pub resample_s: Option<f64>,
    /// `--time-column`: the column holding the time \[s\] (None: `t`).
    pub time_column: Option<String>,
    /// `--units`: `COLUMN=UNIT` pairs.
    pub units: Vec<String>,
    /// `--select auto`: choose the structure by cross-validation on the training records
    /// (None: the spec of `model`, or the default structure).
    pub select: Option<rhonn::sysid::select::SelectOptions>,
    /// The output folder.
    pub out: PathBuf,
    /// `--force`: replace a different model already in `out` (else that is refused,
    /// nothing written).
    pub force: bool,
}

/// `--units COL=UNIT,...` (every column named must be an input or an output), and for each
/// other input and output the unit its name ends in (`rhonn::units::from_column_name`:
/// `y_outlet_temp_V` in V); the note that says which units were read from names.
pub fn parse_units(
    pairs: &[String],
    inputs: &[String],
    outputs: &[String],
) -> Result<(BTreeMap<String, String>, Option<String>)> {
    let mut map = given_units(pairs, inputs, outputs)?;
    let mut read = Vec::new();
    for col in inputs.iter().chain(outputs) {
        if let (false, Some(u)) = (map.contains_key(col), rhonn::units::from_column_name(col)) {
            map.insert(col.clone(), u.to_string());
            read.push(format!("`{col}` in {u}"));
        }
    }
    let note = (!read.is_empty()).then(|| {
        format!(
            "note: units read from the column names: {} (--units COLUMN=UNIT gives others)",
            read.join(", ")
        )
    });
    Ok((map, note))
}

fn given_units(pairs: &[String], inputs: &[String], outputs: &[String]) -> Result<BTreeMap<String, String>> {
    let mut map = BTreeMap::new();
    for p in pairs {
        let (col, unit) = p
            .split_once('=')
            .filter(|(c, u)| !c.trim().is_empty() && !u.trim().is_empty())
            .ok_or_else(|| {
                Error::Input(format!(
                    "--units `{p}` is not allowed: give COLUMN=UNIT pairs separated by commas, e.g. --units u=V,y=mm"
                ))
            })?;
        let col = col.trim();
        if !inputs.iter().chain(outputs).any(|c| c == col) {
            let all: Vec<&str> = inputs.iter().chain(outputs).map(String::as_str).collect();
            return Err(Error::Input(format!(
                "--units names column `{col}`, which is not among the inputs and outputs ({})",
                all.join(", ")
            )));
        }
        map.insert(col.to_string(), unit.trim().to_string());
    }
    Ok(map)
}

/// Read recordings and put each on a uniform grid (`resample_s`, else its own interval,
/// `Record::sample_interval`); each must keep at least `min_rows` samples.
pub fn read_data(
    paths: &[PathBuf],
    inputs: &[String],
    outputs: &[String],
    min_rows: usize,
    resample_s: Option<f64>,
) -> Result<Vec<Record>> {
    Ok(read_data_regridded((paths, "t"), inputs, outputs, min_rows, resample_s)?.records)
}

/// Records read and put on their grids, and what that changed.
#[derive(Debug, Default)]
pub struct ReadData {
    /// The records, on their grids: a file split at its long gaps is several.
    pub records: Vec<Record>,
    /// What putting each on its grid changed (nothing for a record already uniform to
    /// within `rhonn::data::TIME_JITTER` of its step).
    pub regridded: Vec<rhonn::data::Regrid>,
    /// What the rule for gaps did (`rhonn::data::Record::split_at_gaps`), and parts too
    /// short to use that were left out, as notes.
    pub notes: Vec<String>,
}

/// [`read_data`], and what it changed ([`ReadData`]): each file split at its gaps of
/// more than `rhonn::data::MAX_FILLED_GAP` missing samples (refused with more than
/// `rhonn::data::MAX_FILLED_SHARE` of its samples missing in shorter gaps), each part put
/// on the grid of `resample_s` or its own interval; a part shorter than `min_rows` is left
/// out (said), a file with no part that long is an error.
pub fn read_data_regridded(
    (paths, time): (&[PathBuf], &str),
    inputs: &[String],
    outputs: &[String],
    min_rows: usize,
    resample_s: Option<f64>,
) -> Result<ReadData> {
    rhonn::data::check_names(inputs, outputs)?;
    if let Some(dt) = resample_s {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(Error::Input(format!(
                "--resample {dt} is not allowed: give a sample time in seconds, finite and > 0"
            )));
        }
    }
    let mut out = ReadData::default();
    for p in paths {
        let r = rhonn_report::read_record_timed(p, time, inputs, outputs, min_rows)?;
        let dt = resample_s.unwrap_or_else(|| r.sample_interval());
        let (parts, split) = r.split_at_gaps()?;
        out.notes.extend(split.map(|s| s.to_string()));
        let field = if resample_s.is_some() {
            "--resample"
        } else {
            "the sample time"
        };
        let mut kept = 0;
        for part in parts {
            let (u, change) = part.regrid(dt, field)?;
            if u.len() < min_rows {
                out.notes.push(format!(
                    "{}: left out, {} samples on the grid of {} s where the model needs at least {min_rows}",
                    u.source,
                    u.len(),
                    rhonn::metrics::sig(dt, 6)
                ));
                continue;
            }
            out.regridded.extend(change);
            out.records.push(u);
            kept += 1;
        }
        if kept == 0 {
            return Err(Error::Input(format!(
                "{}: no part of at least {min_rows} samples on the grid of {} s, which the model needs{}",
                p.display(),
                rhonn::metrics::sig(dt, 6),
                if resample_s.is_some() {
                    ": give a shorter --resample"
                } else {
                    ""
                }
            )));
        }
    }
    Ok(out)
}

/// The structure a fit of `n_outputs` outputs takes, and the fewest samples a record
/// needs for it: chosen by cross-validation (`select`), else a spec's (`spec`: its TOML
/// text and what names it in errors; None: the default structure). `rhonn fit` and
/// Python's `rhonn.fit`.
pub fn fit_structure<'a>(
    select: Option<&'a SelectOptions>,
    spec: Option<(&str, &str)>,
    n_outputs: usize,
) -> Result<(FitStructure<'a>, usize)> {
    Ok(match select {
        None => {
            let specs = match spec {
                Some((text, source)) => model_specs(Some(text), source)?,
                None => model_specs(None, "")?,
            };
            let max_lag = specs.iter().map(|s| s.max_lag()).max().unwrap_or(0);
            (FitStructure::Given(specs), max_lag + 2)
        }
        Some(opts) => (
            FitStructure::Select(opts),
            rhonn::sysid::select::min_samples(n_outputs, opts),
        ),
    })
}

/// What a fit of recordings in memory gives: the model, summary.json's text (as `rhonn
/// fit` writes it) and the warnings `rhonn fit` prints.
pub type FittedInMemory = (AnyModel, String, Vec<String>);

/// `rhonn fit` on recordings already in memory (Python's `rhonn.fit`): the structure
/// chosen by cross-validation or `spec`'s (its TOML text and what names it; None: the
/// default structure), as `args` ask by the rules of `fit_args`. Errors name the
/// arguments as Python does.
pub fn fit_in_memory(
    recs: &[Record],
    inputs: &[String],
    outputs: &[String],
    spec: Option<(&str, &str)>,
    args: super::fit_args::FitArgs,
) -> Result<FittedInMemory> {
    let door = &super::fit_args::PYTHON;
    let opts = FitArgs {
        model_given: spec.is_some(),
        ..args
    }
    .selection(door)?;
    let (structure, _) = fit_structure(opts.as_ref(), spec, outputs.len())?;
    let run =
        rhonn::sysid::fit_records(structure, recs, inputs, outputs, &|_| {}).map_err(|e| door.rename(e))?;
    let summary = serde_json::to_string(&run.summary)
        .map_err(|e| Error::Input(format!("cannot write the summary as JSON: {e}")))?;
    let mut notes: Vec<String> = run.data_warnings.iter().map(|w| door.data_warning(w)).collect();
    notes.extend(run.selection_warnings);
    Ok((AnyModel::Fitted(Box::new(run.fitted)), summary, notes))
}

/// The model structures of a spec's TOML text (one, or an ensemble's `[[members]]`),
/// checked; None: the default structure. `source` names the spec in errors.
pub fn model_specs(text: Option<&str>, source: &str) -> Result<Vec<ModelSpec>> {
    let specs = match text {
        None => vec![ModelSpec::default()],
        // An online spec of the same model (`rhonn identify`'s lagged or cascade
        // structure) is read as the offline one, or refused naming the keys that differ.
        Some(text) => {
            parse_spec_file(text).or_else(|e| match rhonn::ident::shared_spec::fit_from_online(text) {
                Some(Ok(spec)) => Ok(vec![spec]),
                Some(Err(why)) => Err(Error::Input(format!("cannot read model spec {source}: {why}"))),
                None => Err(Error::Input(format!("cannot read model spec {source}: {e}"))),
            })?
        }
    };
    for (k, spec) in specs.iter().enumerate() {
        let at = match (specs.len() > 1, source.is_empty()) {
            (true, false) => format!("in the model spec {source}, members[{k}]"),
            (true, true) => format!("in members[{k}]"),
            (false, false) => format!("in the model spec {source}"),
            (false, true) => "in the model spec".to_string(),
        };
        spec.check().map_err(|e| context(at)(e.into()))?;
    }
    Ok(specs)
}

/// `rhonn fit`: fit the structure of `req.model` (or the default) to the recordings and
/// write `model.json` and `summary.json` into `req.out`.
pub fn fit(req: &FitRequest) -> Result<Outcome> {
    fit_with_progress(req, &|_| {})
}

/// [`fit`], telling `progress` a line per candidate structure of a selection.
pub fn fit_with_progress(req: &FitRequest, progress: &(dyn Fn(&str) + Sync)) -> Result<Outcome> {
    let inputs: Vec<PathBuf> = req.data.iter().chain(&req.model).cloned().collect();
    super::in_folder(
        &req.out,
        (&inputs, rhonn_report::folder::writes::FIT),
        req.force,
        |stage| fit_into(req, stage, progress),
    )
}

/// A structure the spec allows key by key but not as a whole is the spec file's error.
fn spec_error(e: rhonn::Error, req: &FitRequest) -> Error {
    match super::spec_blame(&e, req.model.as_deref()) {
        Some(whose) => context(whose)(e.into()),
        None => e.into(),
    }
}

/// The structure `req` names (its spec file read, or the selection's settings) and the
/// rows a record needs for it.
fn structure_of(req: &FitRequest) -> Result<(rhonn::sysid::FitStructure<'_>, usize)> {
    if req.select.is_some() && req.model.is_some() {
        return Err(Error::Input(super::fit_args::both_name_the_structure(
            &super::fit_args::COMMAND_LINE,
        )));
    }
    let spec = match &req.model {
        Some(p) => Some((read_text(p)?, p.display().to_string())),
        None => None,
    };
    let spec = spec.as_ref().map(|(t, s)| (t.as_str(), s.as_str()));
    fit_structure(req.select.as_ref(), spec, req.outputs.len())
}

fn fit_into(req: &FitRequest, stage: &Path, progress: &(dyn Fn(&str) + Sync)) -> Result<Outcome> {
    let (inputs, outputs) = (&req.inputs, &req.outputs);
    let (units, units_note) = parse_units(&req.units, inputs, outputs)?;
    let mut o = Outcome::default();
    o.notes.extend(units_note);
    let (structure, min_rows) = structure_of(req)?;
    let ReadData {
        records: recs,
        regridded,
        notes: gap_notes,
    } = read_data_regridded(
        (&req.data, req.time_column.as_deref().unwrap_or("t")),
        inputs,
        outputs,
        min_rows,
        req.resample_s,
    )?;
    let run = rhonn::sysid::fit_records(structure, &recs, inputs, outputs, progress)
        .map_err(|e| spec_error(super::fit_args::COMMAND_LINE.rename(e), req))?;
    o.notes
        .extend(run.selection_findings.iter().map(|f| format!("selection: {f}")));
    o.notes
        .extend(run.selection_warnings.iter().map(|w| format!("warning: {w}")));
    for g in &regridded {
        o.notes.push(format!("note: {g}"));
    }
    o.notes.extend(gap_notes.iter().map(|n| format!("note: {n}")));
    let door = &super::fit_args::COMMAND_LINE;
    o.notes.extend(
        run.data_warnings
            .iter()
            .map(|w| format!("warning: {}", door.data_warning(w))),
    );
    let (specs, mut fitted, mut summary) = (run.specs, run.fitted, run.summary);
    let grey = specs[0].kind == rhonn::sysid::Kind::Pump;
    summary.regridded = regridded;
    fitted.units = units;
    // The free run on each training record, for the plots (at most 8 records drawn).
    let training: Vec<_> = recs
        .iter()
        .take(8)
        .map(|r| rhonn::sysid::predict(&fitted, r, None))
        .collect::<rhonn::Result<_>>()?;
    bound_warnings(&fitted, &training, &mut o);
    if let Some(n) = replaced_note(&req.out, &fitted, &summary, req.force)? {
        o.notes.push(n);
    }
    o.files = rhonn_report::write_fit(stage, &fitted, &summary, &training)?;
    o.lines
        .extend(fitted_lines(&specs[0], &fitted, &summary, recs.len()));
    if grey {
        // An integrating line drifts in free run: the K-step figure is the one to read.
        let k = specs[0].horizon;
        let kstep: Vec<RecordFigures> = recs
            .iter()
            .map(|r| {
                let p = rhonn::sysid::predict(&fitted, r, Some(k))?;
                Ok(RecordFigures {
                    data: r.source.clone(),
                    outputs: p.figures,
                })
            })
            .collect::<rhonn::Result<_>>()?;
        training_lines(
            &mut o,
            &kstep,
            &format!("{k} steps ahead (training data)"),
            &fitted.units,
        );
    }
    training_lines(
        &mut o,
        &summary.training.free_run,
        "free run (training data)",
        &fitted.units,
    );
    if let Some(b) = &summary.baseline_arx {
        let label = format!("ARX baseline ({}, {}), free run", b.structure, b.chosen_as);
        training_lines(&mut o, &b.free_run, &label, &fitted.units);
    }
    Ok(o)
}

/// What was fitted, in words: the model (its kind and size, an ensemble's members, the
/// grey box's estimates) on `n_records` records, and each output with a structure of its own.
fn fitted_lines(
    spec: &rhonn::sysid::ModelSpec,
    fitted: &rhonn::sysid::FittedModel,
    summary: &rhonn::sysid::FitSummary,
    n_records: usize,
) -> Vec<String> {
    let grey = spec.kind == rhonn::sysid::Kind::Pump;
    let mut lines = Vec::new();
    lines.push(if grey {
        format!(
            "fitted the pump's grey-box model on {}; estimated: {}",
            count(n_records, "record"),
            rhonn::sysid::pump_grey::describe_estimates(&fitted.model)
        )
    } else if fitted.members.is_empty() {
        format!(
            "fitted {} model with {} on {}",
            spec.kind.with_article(),
            size(spec.kind, fitted.model.n_features()),
            count(n_records, "record")
        )
    } else {
        format!(
            "fitted an ensemble of {} models ({}) on {}",
            1 + fitted.members.len(),
            fitted
                .all_members()
                .map(|m| format!(
                    "{} with {}",
                    m.spec.kind.with_article(),
                    size(m.spec.kind, m.n_features())
                ))
                .collect::<Vec<_>>()
                .join("; "),
            count(n_records, "record")
        )
    });
    for own in &summary.by_output {
        lines.push(format!(
            "  output `{}` from a structure of its own: {} {}with {}",
            own.output,
            own.model.kind.with_article(),
            if own.members > 1 {
                format!("ensemble of {} ", own.members)
            } else {
                String::new()
            },
            size(own.model.kind, own.features)
        ));
    }
    lines
}

/// The size `n` of a model of `kind` in words: a lagged model's features per output (its
/// weights on each output), any other kind's parameters.
fn size(kind: rhonn::sysid::Kind, n: usize) -> String {
    if kind.is_lagged() {
        count(n, "feature") + " per output"
    } else {
        count(n, "parameter")
    }
}

/// When `dir` holds an earlier fit's model that differs from `fitted`: without `force` an
/// error (nothing written) that gives both free-run fits on the first training record, so
/// that no model is replaced silently; with it, a note saying what is replaced. The same
/// model again (a rerun) passes without a word.
fn replaced_note(
    dir: &Path,
    fitted: &rhonn::sysid::FittedModel,
    summary: &rhonn::sysid::FitSummary,
    force: bool,
) -> Result<Option<String>> {
    let old = dir.join("model.json");
    let Ok(text) = std::fs::read_to_string(&old) else {
        return Ok(None);
    };
    let same = serde_json::from_str::<serde_json::Value>(&text)
        .ok()
        .zip(serde_json::to_value(fitted).ok())
        .is_some_and(|(a, b)| a == b);
    if same {
        return Ok(None);
    }
    let first_fit =
        |v: &serde_json::Value| v["training"]["free_run"][0]["outputs"][0]["fit_percent"].as_f64();
    let before = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .and_then(|v| first_fit(&v));
    let now = summary
        .training
        .free_run
        .first()
        .and_then(|r| r.outputs.first())
        .map(|o| o.fit_percent);
    let fits = match (before, now) {
        (Some(b), Some(n)) => format!(
            " (free-run fit on the first training record: {} before, {} now)",
            super::percent(b),
            super::percent(n)
        ),
        _ => String::new(),
    };
    if !force {
        return Err(Error::Input(format!(
            "{} holds another model{fits}: nothing written; give --force to replace it, or another --out",
            old.display()
        )));
    }
    Ok(Some(format!(
        "note: replacing {} of an earlier fit{fits}",
        old.display()
    )))
}

/// The frozen model's stability check: a warning for each free run that reaches the bound
/// of the output range.
fn bound_warnings(
    fitted: &rhonn::sysid::FittedModel,
    training: &[rhonn::sysid::Prediction],
    o: &mut Outcome,
) {
    for p in training {
        if let Some((name, t)) =
            rhonn::sysid::free_run_at_bound(&fitted.model, &p.record, &p.outputs, p.first)
        {
            o.notes.push(format!(
                "warning: the model's free run on {} reaches the bound its output `{name}` is held in \
                 (the training range widened by output_margin) at t = {} s: it drifts or is unstable \
                 in free run; judge it K steps ahead (rhonn predict --steps-ahead K), or let rhonn fit \
                 select a structure (no --model)",
                p.record.source,
                rhonn::metrics::sig(t, 6)
            ));
        }
    }
}

fn training_lines(o: &mut Outcome, figures: &[RecordFigures], label: &str, units: &BTreeMap<String, String>) {
    for rec in figures {
        for f in &rec.outputs {
            o.lines.push(format!(
                "  {label}: {} {}: rms error {}{}, fit {}",
                rec.data,
                f.output,
                rhonn::metrics::sig(f.rms_error, 4),
                unit_of(units, &f.output),
                super::percent(f.fit_percent)
            ));
        }
    }
}

/// `rhonn predict`: predict a recording with a `model.json` of `rhonn fit` or of
/// `rhonn identify`, free run (seeing only the first `window` outputs when given) or
/// `steps` ahead, and write the prediction into `out`. The data's time \[s\] is in the
/// column `time` (`t` unless `--time-column` names another).
pub fn predict(
    model: &Path,
    (data, time): (&Path, &str),
    out: &Path,
    steps: Option<usize>,
    window: Option<usize>,
) -> Result<Outcome> {
    let inputs = [model.to_path_buf(), data.to_path_buf()];
    super::in_folder(
        out,
        (&inputs, rhonn_report::folder::writes::PREDICT),
        false,
        |stage| predict_into(model, (data, time), stage, steps, window),
    )
}

/// The model's folder checked whole (`rhonn_report::folder::check_whole`); a note when the model
/// file was edited since its run wrote it.
fn edited_note(model: &Path) -> Result<Option<String>> {
    let Some(folder) = model.parent().filter(|p| p.is_dir()) else {
        return Ok(None);
    };
    let listed = rhonn_report::folder::check_whole(folder)
        .map_err(context(format!("the model's folder of {}", model.display())))?;
    let name = model.file_name().map(|n| n.to_string_lossy().into_owned());
    Ok(match (listed, name) {
        (Some(m), Some(name)) if m.files.iter().any(|e| e.path == name) && !m.holds(folder, &name) => {
            Some(format!(
                "note: {} was edited since the run that wrote it ({}): predicting with it as it is now",
                model.display(),
                folder.join(rhonn_report::folder::MANIFEST).display()
            ))
        }
        _ => None,
    })
}

/// `--steps-ahead` and `--init-window` checked by the library's rules, named as flags.
fn check_prediction_options(steps: Option<usize>, window: Option<usize>) -> Result<()> {
    rhonn::sysid::check_prediction_options(steps, window).map_err(|e| {
        e.with_field_named("steps_ahead", "--steps-ahead")
            .with_field_named("init_window", "--init-window")
            .into()
    })
}

/// A line per output: the prediction's figures, and the ARX baseline's beside them.
fn figure_lines(fitted: &rhonn::sysid::FittedModel, p: &rhonn::sysid::Prediction) -> Vec<String> {
    let mut lines = Vec::new();
    let mode = p.mode();
    for (j, f) in p.figures.iter().enumerate() {
        let unit = unit_of(&fitted.units, &f.output);
        let mut line = format!(
            "{} ({mode}): rms error {}{unit}, fit {}, nrmse {}",
            f.output,
            rhonn::metrics::sig(f.rms_error, 4),
            super::percent(f.fit_percent),
            super::ratio(f.nrmse)
        );
        if let (Some((_, fb)), Some(b)) = (&p.baseline, &fitted.baseline) {
            line += &format!(
                "; ARX baseline ({}): rms error {}{unit}, fit {}",
                b.spec.lags_name(),
                rhonn::metrics::sig(fb[j].rms_error, 4),
                super::percent(fb[j].fit_percent)
            );
        }
        lines.push(line);
    }
    lines
}

fn predict_into(
    model: &Path,
    (data, time): (&Path, &str),
    out: &Path,
    steps: Option<usize>,
    window: Option<usize>,
) -> Result<Outcome> {
    let edited = edited_note(model)?;
    let text = read_text(model)?;
    check_prediction_options(steps, window)?;
    // A file that is no JSON at all is named with the line and column where it breaks,
    // before its kind is asked; a refused check is the context of what refused it.
    let any = AnyModel::parse(&text, &model.display().to_string()).map_err(|e| match e {
        ModelFileError::Invalid { source_name, source } => {
            context(format!("{source_name} is not a valid model"))(source.into())
        }
        other => Error::Input(other.to_string()),
    })?;
    let fitted = match &any {
        AnyModel::Online(m) => {
            let mut o = super::identify::predict_online(model, &any, m, (data, time), out, (steps, window))?;
            o.notes.splice(0..0, edited);
            return Ok(o);
        }
        AnyModel::Fitted(f) => f,
    };
    let m = &fitted.model;
    let needed = any.samples_needed(steps);
    let ReadData {
        records: recs,
        regridded,
        notes: gap_notes,
    } = read_data_regridded((&[data.to_path_buf()], time), &m.inputs, &m.outputs, needed, None)?;
    if recs.len() > 1 || !gap_notes.is_empty() {
        return Err(Error::Input(format!(
            "{}: {}; a prediction runs over one record: predict each part as its own file",
            data.display(),
            gap_notes.join("; ")
        )));
    }
    let AnyPrediction::Fitted(p) = any
        .predict_with(&recs[0], steps, window)
        .map_err(super::predicting(data, model))?
    else {
        unreachable!("a fitted model's prediction")
    };
    let mut o = Outcome {
        notes: edited.into_iter().collect(),
        ..Outcome::default()
    };
    for g in &regridded {
        o.notes.push(format!("note: {g}"));
    }
    for name in &fitted.no_better_than_mean {
        o.notes.push(format!(
            "warning: {} says that for output `{name}` no structure its fit tried ran free on the training folds better than the training mean: this prediction of `{name}` is no better than a constant",
            model.display()
        ));
    }
    for w in p.range_warnings() {
        o.notes.push(format!("warning: {w}"));
    }
    if let Some(dt) = p.resampled_from_s {
        // Intervals read off decimal times carry float noise: shown to the nanosecond.
        let ns = |v: f64| (v * 1e9).round() / 1e9;
        o.notes.push(format!(
            "note: {} is sampled every {} s; predicting on the model's grid of {} s ({} samples)",
            data.display(),
            ns(dt),
            ns(m.sample_time_s),
            p.record.len()
        ));
    }
    o.files = rhonn_report::write_prediction(out, fitted, &p, &model.display().to_string())?;
    o.lines.extend(figure_lines(fitted, &p));
    Ok(o)
}
