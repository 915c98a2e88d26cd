//! `rhonn identify` as one library call on records in memory: the model (given, or chosen
//! online by the bank), its passes over the records, the frozen model's validation on other
//! records beside the offline ARX, and every figure and finding of its `summary.json`. The
//! command reads the files and writes the folder; nothing of the result is computed there.
//! Above both identifiers: the online one (`ident`) learns, the offline one (`sysid`) gives
//! the ARX baseline.

pub mod compare;

use crate::data::Record;
use crate::error::Error;
use crate::ident::bank::select_per_output;
use crate::ident::{
    identify_records_scaled, predict_records, sample_time, OnlineModel, OnlineRun, OnlineSpec,
};
use crate::metrics;
use compare::compare_with_arx;
use serde::Serialize;
use std::collections::BTreeMap;

/// Frozen-weight predictions on validation records.
#[derive(Debug, Clone)]
pub struct Validation {
    /// The records.
    pub records: Vec<Record>,
    /// Free run, per record and sample, per output.
    pub free_run: Vec<Vec<Vec<f64>>>,
    /// K samples ahead, when asked.
    pub ahead: Option<(usize, Vec<Vec<Vec<f64>>>)>,
}

/// Figures of a validation, per output.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct ValidationFigures {
    /// Output.
    pub output: String,
    /// Free run: RMS error (output units) and fit \[%\] over every validation record.
    pub free_run_rms_error: f64,
    /// Free-run fit \[%\]; left out for a constant output (undefined).
    #[serde(skip_serializing_if = "crate::metrics::undefined")]
    pub free_run_fit_percent: f64,
    /// K.
    pub horizon: Option<usize>,
    /// K samples ahead: RMS error, from sample K of each record on.
    pub ahead_rms_error: Option<f64>,
    /// K-step fit \[%\].
    pub ahead_fit_percent: Option<f64>,
}

/// `summary.json`.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct IdentifySummary {
    /// The model's settings as used.
    #[schemars(with = "serde_json::Value")]
    pub model: OnlineSpec,
    /// Records identified on.
    pub records: Vec<String>,
    /// Sample time \[s\].
    pub sample_time_s: f64,
    /// Terms per neuron.
    pub terms_per_neuron: usize,
    /// The terms, in the order of each neuron's weights (weights.csv's `w_<output>_<k>`,
    /// model.json's `weights`).
    pub terms: Vec<String>,
    /// Online figures over the final pass.
    pub online: Vec<crate::ident::OnlineFigures>,
    /// Final weight norm per neuron.
    pub final_weight_norms: Vec<f64>,
    /// Largest weight norm per neuron in each pass.
    pub max_weight_norm_per_pass: Vec<Vec<f64>>,
    /// Frozen-weight validation.
    pub validation: Vec<ValidationFigures>,
    /// Findings in words.
    pub findings: Vec<String>,
    /// Without `--model`: the online selection (every candidate's prequential figures).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub selection: Option<crate::ident::bank::BankSelection>,
    /// With validation records: the offline ARX (lags by cross-validation on the training
    /// records) beside the frozen online model, per record and output.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub baseline_arx: Option<compare::ArxBaseline>,
    /// `--units`: the columns' units (the figures are in them).
    #[serde(skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub units: std::collections::BTreeMap<String, String>,
}

/// Figures of validation predictions.
pub fn validation_figures(v: &Validation, outputs: &[String]) -> Vec<ValidationFigures> {
    (0..outputs.len())
        .map(|j| {
            let gather = |p: &[Vec<Vec<f64>>], from: usize| {
                let (mut y, mut yh) = (Vec::new(), Vec::new());
                for (r, pr) in v.records.iter().zip(p) {
                    y.extend_from_slice(&r.outputs[j][from.min(r.len())..]);
                    yh.extend(pr[from.min(r.len())..].iter().map(|e| e[j]));
                }
                (metrics::rms_error(&y, &yh), metrics::fit_percent(&y, &yh))
            };
            let (fr, ff) = gather(&v.free_run, 0);
            let ahead = v.ahead.as_ref().map(|(k, p)| (*k, gather(p, *k)));
            ValidationFigures {
                output: outputs[j].clone(),
                free_run_rms_error: fr,
                free_run_fit_percent: ff,
                horizon: ahead.map(|a| a.0),
                ahead_rms_error: ahead.map(|a| a.1 .0),
                ahead_fit_percent: ahead.map(|a| a.1 .1),
            }
        })
        .collect()
}

/// Per output, a prediction's figures (`rhonn predict` on an online model).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct OnlinePredictionFigures {
    /// Output.
    pub output: String,
    /// RMS error (output units), from sample K on (K steps ahead) or over all samples.
    pub rms_error: f64,
    /// Fit \[%\]; left out for a constant output (undefined).
    #[serde(skip_serializing_if = "crate::metrics::undefined")]
    pub fit_percent: f64,
    /// Normalised RMS error (by the output's range); left out for a constant output.
    #[serde(skip_serializing_if = "crate::metrics::undefined")]
    pub nrmse: f64,
}

/// Figures of `pred` against `record`'s outputs, from sample `first` on.
pub fn online_prediction_figures(
    record: &Record,
    pred: &[Vec<f64>],
    outputs: &[String],
    first: usize,
) -> Vec<OnlinePredictionFigures> {
    (0..outputs.len())
        .map(|j| {
            let y = &record.outputs[j][first.min(record.len())..];
            let yh: Vec<f64> = pred[first.min(record.len())..].iter().map(|e| e[j]).collect();
            OnlinePredictionFigures {
                output: outputs[j].clone(),
                rms_error: metrics::rms_error(y, &yh),
                fit_percent: metrics::fit_percent(y, &yh),
                nrmse: metrics::nrmse(y, &yh),
            }
        })
        .collect()
}

/// What an identification is asked for.
#[derive(Debug, Clone, Default)]
pub struct IdentifyPlan {
    /// Input names.
    pub inputs: Vec<String>,
    /// Output names.
    pub outputs: Vec<String>,
    /// The model's settings; None: chosen online by the bank.
    pub given: Option<OnlineSpec>,
    /// Passes over the records (overrides the spec's `epochs`).
    pub epochs: Option<usize>,
    /// Validation K samples ahead as well as in free run.
    pub steps_ahead: Option<usize>,
    /// The columns' units, carried into the summary.
    pub units: BTreeMap<String, String>,
}

/// What an identification gives.
#[derive(Debug, Clone)]
pub struct Identification {
    /// `summary.json`.
    pub summary: IdentifySummary,
    /// The passes: the identifier, its estimates and figures.
    pub run: OnlineRun,
    /// The frozen model (`model.json`).
    pub model: OnlineModel,
    /// The frozen model's predictions on the validation records.
    pub validation: Option<Validation>,
    /// The records learned, where the guard split the ones given (a glitch skipped, a gap
    /// restarted over: `crate::ident::guard::screen`); None: the records given, as they were.
    pub learned: Option<Vec<Record>>,
    /// What the guard skipped or restarted over (also among the summary's findings).
    pub guard_notes: Vec<String>,
}

/// Where an identification failed: the online passes (the model's or the data's), the
/// validation records, or the ARX baseline.
#[derive(Debug, Clone)]
pub enum IdentifyError {
    /// Choosing the model or learning the records.
    Online(Error),
    /// The validation records (their sample time) or the frozen model's run on them.
    Validation(Error),
    /// The offline ARX baseline.
    Baseline(Error),
}

/// Learn `records` online as `plan` says, then (with `validation` records, sampled as the
/// training ones) validate the frozen model beside the offline ARX of `sysid::best_arx`.
pub fn identify(
    records: &[Record],
    validation: &[Record],
    plan: &IdentifyPlan,
) -> Result<Identification, IdentifyError> {
    use IdentifyError as E;
    let outputs = &plan.outputs;
    crate::data::check_tiny(records, &plan.inputs, outputs).map_err(E::Online)?;
    // Glitches skipped and gaps restarted over, as in a session (`crate::ident::guard`).
    let (learned, guard_notes) =
        crate::ident::guard::screen(records, sample_time(records).map_err(E::Online)?);
    let records: &[Record] = learned.as_deref().unwrap_or(records);
    let (mut spec, bank) = match &plan.given {
        Some(s) => (s.clone(), None),
        None => {
            let sel = select_per_output(records, outputs).map_err(E::Online)?;
            (sel.chosen_spec(), Some(sel))
        }
    };
    if let Some(e) = plan.epochs {
        spec.epochs = e;
    }
    let warmup = bank.as_ref().map(|b| b.warmup);
    let run = identify_records_scaled(&spec, records, outputs, warmup).map_err(E::Online)?;
    let validation = validate(&run, records, validation, plan.steps_ahead).map_err(E::Validation)?;
    let dt = sample_time(records).map_err(E::Online)?;
    let final_norms = run
        .identifier
        .weights()
        .iter()
        .map(|w| w.iter().map(|x| x * x).sum::<f64>().sqrt())
        .collect();
    let vfig = validation
        .as_ref()
        .map(|v| validation_figures(v, outputs))
        .unwrap_or_default();
    let baseline = match &validation {
        None => None,
        Some(v) => {
            let (arx, _) = crate::sysid::best_arx(records, &plan.inputs, outputs).map_err(E::Baseline)?;
            let reads = crate::ident::outputs_read_in_free_run(&spec);
            Some(compare_with_arx(&v.records, (&v.free_run, reads), &arx, outputs).map_err(E::Validation)?)
        }
    };
    let summary = IdentifySummary {
        model: spec.clone(),
        records: records.iter().map(|r| r.source.clone()).collect(),
        sample_time_s: dt,
        terms_per_neuron: run.identifier.n_terms(),
        terms: run.identifier.term_names(outputs, &plan.inputs),
        online: run.figures.clone(),
        final_weight_norms: final_norms,
        max_weight_norm_per_pass: run.max_norm_per_pass.clone(),
        findings: guard_notes
            .iter()
            .cloned()
            .chain(bank.iter().flat_map(|b| b.findings()))
            .chain(findings(&run, &vfig))
            .chain(baseline.iter().flat_map(|b| b.findings()))
            .collect(),
        selection: bank,
        baseline_arx: baseline,
        validation: vfig,
        units: plan.units.clone(),
    };
    let model = OnlineModel::of(&run.identifier, spec, &plan.inputs, outputs, dt);
    Ok(Identification {
        summary,
        run,
        model,
        validation,
        learned,
        guard_notes,
    })
}

/// `rhonn identify`'s default on `records` without validation or figures: the bank
/// chooses (a bank per output beside the joint one), the winner is trained for its passes
/// with the bank's warm-up scaling and frozen (`rhonn benchmark`'s and `rhonn corpus`'s
/// online model).
pub fn online_default(
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
) -> crate::Result<(OnlineModel, crate::ident::bank::BankSelection)> {
    let sel = select_per_output(records, outputs)?;
    let spec = sel.chosen_spec();
    let run = identify_records_scaled(&spec, records, outputs, Some(sel.warmup))?;
    let dt = sample_time(records)?;
    Ok((OnlineModel::of(&run.identifier, spec, inputs, outputs, dt), sel))
}

/// Sources as a comma-separated list, for messages.
fn sources(records: &[Record]) -> String {
    records
        .iter()
        .map(|r| r.source.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}

/// The frozen model run free (and K samples ahead) on the validation records, which must
/// be sampled as the training records are.
fn validate(
    run: &OnlineRun,
    records: &[Record],
    vrec: &[Record],
    steps_ahead: Option<usize>,
) -> crate::Result<Option<Validation>> {
    if vrec.is_empty() {
        return Ok(None);
    }
    let (vdt, dt) = (sample_time(vrec)?, sample_time(records)?);
    if (vdt - dt).abs() > 0.01 * dt {
        return Err(Error::Argument(format!(
            "{} samples every {} s, but the training records ({}) every {} s: give validation records with the same sample time (is one `t` column in milliseconds?)",
            sources(vrec),
            crate::metrics::sig(vdt, 6),
            sources(records),
            crate::metrics::sig(dt, 6)
        )));
    }
    let mut id = run.identifier.clone();
    let free_run = predict_records(&mut id, vrec, None)?;
    let ahead = match steps_ahead {
        Some(k) => Some((k, predict_records(&mut id, vrec, Some(k))?)),
        None => None,
    };
    Ok(Some(Validation {
        records: vrec.to_vec(),
        free_run,
        ahead,
    }))
}

/// What the numbers mean, in words.
fn findings(run: &OnlineRun, v: &[ValidationFigures]) -> Vec<String> {
    let mut out = Vec::new();
    for f in &run.figures {
        out.push(match f.converged_s {
            Some(t) => format!(
                "{}: the online error stays within +-{} (twice its final RMS) from {} s of the final pass on (a band of the tracking error, not a claim that the system is learnt: the validation below says how the frozen model runs free)",
                f.output,
                crate::metrics::sig(f.band, 4),
                crate::metrics::sig(t, 6)
            ),
            None => format!(
                "{}: the online error leaves the band +-{} until the end of the final pass",
                f.output,
                crate::metrics::sig(f.band, 4)
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
