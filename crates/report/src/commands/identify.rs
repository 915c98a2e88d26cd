//! `rhonn identify` (online RHONN identification of recordings) and `rhonn predict` with
//! its model.

use super::{context, read_text, Outcome};
use crate::identify::{validation_figures, write_identify, IdentifySummary, Validation};
use crate::{Error, Result};
use rhonn::ident::{predict_records, OnlineModel, OnlineSpec};
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
    /// The output folder.
    pub out: PathBuf,
}

/// Paths as a comma-separated list, for messages.
fn list(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

fn read_spec(p: &Path) -> Result<OnlineSpec> {
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
    super::in_folder(&a.out, || identify_into(a))
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

fn identify_into(a: &IdentifyRequest) -> Result<Outcome> {
    let given = a.model.as_deref().map(read_spec).transpose()?;
    let units = super::parse_units(&a.units, &a.inputs, &a.outputs)?;
    if a.steps_ahead == Some(0) {
        return Err(Error::Input(
            "--steps-ahead 0 is not allowed: give K >= 1 samples".into(),
        ));
    }
    let records = read_all(a, &a.data)?;
    let (mut spec, bank) = choose_spec(a, given, &records)?;
    if let Some(e) = a.epochs {
        spec.epochs = e;
    }
    let warmup = bank.as_ref().map(|b| b.warmup);
    let run = rhonn::ident::identify_records_scaled(&spec, &records, &a.outputs, warmup)
        .map_err(|e| identification_error(e, a))?;
    let validation = validate(a, &run, &records)?;
    let dt = rhonn::ident::sample_time(&records)?;
    let weights = run.identifier.weights();
    let final_norms: Vec<f64> = weights
        .iter()
        .map(|w| w.iter().map(|x| x * x).sum::<f64>().sqrt())
        .collect();
    let vfig = validation
        .as_ref()
        .map(|v| validation_figures(v, &a.outputs))
        .unwrap_or_default();
    let baseline = arx_baseline(a, &records, validation.as_ref())?;
    let summary = IdentifySummary {
        model: spec.clone(),
        records: records.iter().map(|r| r.source.clone()).collect(),
        sample_time_s: dt,
        terms_per_neuron: run.identifier.n_terms(),
        terms: run.identifier.term_names(&a.outputs, &a.inputs),
        online: run.figures.clone(),
        final_weight_norms: final_norms,
        max_weight_norm_per_pass: run.max_norm_per_pass.clone(),
        findings: bank
            .iter()
            .flat_map(|b| b.findings())
            .chain(findings(&run, &vfig))
            .chain(baseline.iter().flat_map(|b| b.findings()))
            .collect(),
        selection: bank,
        baseline_arx: baseline,
        validation: vfig,
        units,
    };
    let model = OnlineModel::of(&run.identifier, spec, &a.inputs, &a.outputs, dt);
    let files = write_identify(
        &a.out,
        &run,
        &records,
        &a.outputs,
        &model,
        &summary,
        validation.as_ref(),
    )?;
    let mut o = Outcome {
        files,
        ..Outcome::default()
    };
    o.files.push(crate::write_report(&a.out)?);
    o.lines = console_lines(&summary);
    Ok(o)
}

/// The records of `paths`, with `a`'s columns.
fn read_all(a: &IdentifyRequest, paths: &[PathBuf]) -> Result<Vec<rhonn::data::Record>> {
    paths
        .iter()
        .map(|p| crate::read_record(p, &a.inputs, &a.outputs, 2).map_err(Error::from))
        .collect()
}

/// The spec given, or, without one, the winner of the bank of candidates run online over
/// the records (`rhonn::ident::bank`), with the bank's figures.
fn choose_spec(
    a: &IdentifyRequest,
    given: Option<OnlineSpec>,
    records: &[rhonn::data::Record],
) -> Result<(OnlineSpec, Option<rhonn::ident::bank::BankSelection>)> {
    match given {
        Some(s) => Ok((s, None)),
        None => {
            let total = records.iter().map(|r| r.len()).sum();
            let cands = rhonn::ident::bank::default_candidates(a.outputs.len(), total);
            let sel = rhonn::ident::bank::select(cands, records, &a.outputs)
                .map_err(|e| identification_error(e, a))?;
            Ok((sel.chosen_spec().clone(), Some(sel)))
        }
    }
}

/// The frozen model run free (and K samples ahead) on the --validate records, which must
/// be sampled as the training records are.
fn validate(
    a: &IdentifyRequest,
    run: &rhonn::ident::OnlineRun,
    records: &[rhonn::data::Record],
) -> Result<Option<Validation>> {
    if a.validate.is_empty() {
        return Ok(None);
    }
    let vrec = read_all(a, &a.validate)?;
    let (vdt, dt) = (
        rhonn::ident::sample_time(&vrec)?,
        rhonn::ident::sample_time(records)?,
    );
    if (vdt - dt).abs() > 0.01 * dt {
        return Err(Error::Input(format!(
            "{} samples every {} s, but the training records ({}) every {} s: give validation records with the same sample time (is one `t` column in milliseconds?)",
            list(&a.validate),
            rhonn::metrics::sig(vdt, 6),
            list(&a.data),
            rhonn::metrics::sig(dt, 6)
        )));
    }
    let mut id = run.identifier.clone();
    let free_run = predict_records(&mut id, &vrec, None)?;
    let ahead = match a.steps_ahead {
        Some(k) => Some((k, predict_records(&mut id, &vrec, Some(k))?)),
        None => None,
    };
    Ok(Some(Validation {
        records: vrec,
        free_run,
        ahead,
    }))
}

/// The offline ARX (lags by cross-validation on the records) beside the frozen model on
/// each validation record.
fn arx_baseline(
    a: &IdentifyRequest,
    records: &[rhonn::data::Record],
    validation: Option<&Validation>,
) -> Result<Option<rhonn::ident::compare::ArxBaseline>> {
    let Some(v) = validation else { return Ok(None) };
    let (arx, _) = rhonn::sysid::best_arx(records, &a.inputs, &a.outputs)
        .map_err(|e| context("the ARX baseline")(e.into()))?;
    Ok(Some(rhonn::ident::compare::compare_with_arx(
        &v.records,
        &v.free_run,
        &arx,
        &a.outputs,
    )?))
}

/// The figures for the console: the online fit, then per validation record and output
/// the frozen free run beside the offline ARX, then K samples ahead.
fn console_lines(summary: &IdentifySummary) -> Vec<String> {
    let mut lines = Vec::new();
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

/// What the numbers mean, in words.
fn findings(run: &rhonn::ident::OnlineRun, v: &[crate::identify::ValidationFigures]) -> Vec<String> {
    let mut out = Vec::new();
    for f in &run.figures {
        out.push(match f.converged_s {
            Some(t) => format!(
                "{}: the online error stays within +-{} (twice its final RMS) from {} s of the final pass on (a band of the tracking error, not a claim that the system is learnt: the validation below says how the frozen model runs free)",
                f.output,
                rhonn::metrics::sig(f.band, 4),
                rhonn::metrics::sig(t, 6)
            ),
            None => format!(
                "{}: the online error leaves the band +-{} until the end of the final pass",
                f.output,
                rhonn::metrics::sig(f.band, 4)
            ),
        });
    }
    let passes = &run.max_norm_per_pass;
    if passes.len() > 1 {
        let (first, last) = (&passes[0], &passes[passes.len() - 1]);
        for (i, (a, b)) in first.iter().zip(last).enumerate() {
            out.push(format!(
                "neuron {i}: largest weight norm {a:.3} in the first pass, {b:.3} in the last"
            ));
        }
    }
    for f in v {
        if f.free_run_fit_percent < 0.0 {
            out.push(format!("{}: the frozen model's free run is worse than the validation mean (fit {:.1} %): use K-step prediction or more passes", f.output, f.free_run_fit_percent));
        }
    }
    out
}

/// `rhonn predict` with a `model.json` written by `rhonn identify`.
pub(super) fn predict_online(
    model_path: &Path,
    text: &str,
    data: &Path,
    out: &Path,
    steps: Option<usize>,
) -> Result<Outcome> {
    let m: OnlineModel = super::parse_json(text, model_path, "a valid online model")?;
    let mut id = m
        .identifier()
        .map_err(|e| context(format!("{} is not a valid model", model_path.display()))(e.into()))?;
    let rec = crate::read_record(data, &m.inputs, &m.outputs, 2)?;
    let recs = std::slice::from_ref(&rec);
    rhonn::ident::sample_time(recs)?;
    let pred = predict_records(&mut id, recs, steps)
        .map_err(|e| {
            context(format!(
                "predicting {} with the model {}",
                data.display(),
                model_path.display()
            ))(e.into())
        })?
        .remove(0);
    let figures = crate::identify::online_prediction_figures(&rec, &pred, &m.outputs, steps.unwrap_or(0));
    let files = crate::identify::write_online_prediction(
        out,
        &m,
        &model_path.display().to_string(),
        &rec,
        &pred,
        steps,
        &figures,
    )?;
    let mut o = Outcome {
        files,
        ..Outcome::default()
    };
    o.files.push(crate::write_report(out)?);
    let mode = steps.map_or("free run".to_string(), |k| format!("{k} steps ahead"));
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
