//! `rhonn fit` as a library call: train the structures of a spec file on records and
//! report the training figures beside the ARX baseline's.

use super::{
    ensure_finite_figures, fit_ensemble, fit_own_structures, FittedModel, Model, ModelSpec, OutputFigures,
};
use crate::data::Record;
use crate::error::Result;
use serde::Serialize;

/// The figures of one model on one record.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct RecordFigures {
    /// The record's source (file name).
    pub data: String,
    /// One entry per output.
    pub outputs: Vec<OutputFigures>,
}

/// One step ahead and free run, on every training record.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct TrainingFigures {
    /// One step ahead.
    pub one_step: Vec<RecordFigures>,
    /// Free run.
    pub free_run: Vec<RecordFigures>,
}

/// An ensemble member's structure and size.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct MemberSummary {
    /// Its structure.
    #[schemars(with = "serde_json::Value")]
    pub model: ModelSpec,
    /// Features per output.
    pub features: usize,
    /// High-order terms.
    pub high_order_terms: usize,
}

/// An output a structure of its own predicts (the selection's `by_output`).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct OutputStructureSummary {
    /// The output.
    pub output: String,
    /// Its structure (an ensemble's first member).
    #[schemars(with = "serde_json::Value")]
    pub model: ModelSpec,
    /// Its members (1: a single structure).
    pub members: usize,
    /// Features per output, over every member.
    pub features: usize,
}

/// The ARX baseline's size and training figures.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct BaselineSummary {
    /// Its lags, e.g. `na 4 nb 4 nk 1`.
    pub structure: String,
    /// Why this ARX: `same lags` as a lagged model (an ARX or a lagged RHONN), `the spec's
    /// na and nb: this kind has no lags` for the others (their defaults unless the spec
    /// gives them), or
    /// `best ARX on the folds` of a selection.
    pub chosen_as: &'static str,
    /// Features per output.
    pub features: usize,
    /// One step ahead on every record.
    pub one_step: Vec<RecordFigures>,
    /// Free run on every record.
    pub free_run: Vec<RecordFigures>,
}

/// What `rhonn fit` writes to `summary.json`.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct FitSummary {
    /// rhonn's version.
    pub rhonn_version: &'static str,
    /// The (first member's) structure.
    #[schemars(with = "serde_json::Value")]
    pub model: ModelSpec,
    /// Features per output.
    pub features: usize,
    /// High-order terms.
    pub high_order_terms: usize,
    /// Sampling interval \[s\].
    pub sample_time_s: f64,
    /// The model's (an ensemble's mean's) figures on the training records.
    pub training: TrainingFigures,
    /// An ensemble's members.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub members: Option<Vec<MemberSummary>>,
    /// The outputs a structure of their own predicts (the training figures are the
    /// composite model's).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub by_output: Vec<OutputStructureSummary>,
    /// The ARX baseline: the best ARX on the folds of a selection, else the ARX with the
    /// model's lags (`chosen_as` says which).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub baseline_arx: Option<BaselineSummary>,
    /// A `pump` model's parameters by name, SI (the estimated ones and the fixed ones).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub parameters: Option<std::collections::BTreeMap<String, f64>>,
    /// How the structure was chosen (`--select auto`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub selection: Option<super::select::Selection>,
    /// Records whose times were not uniform and were put on a grid: what that changed.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub regridded: Vec<crate::data::Regrid>,
}

/// The figures of `predict` on every record; an error when any is not finite.
fn figures_on(
    m: &Model,
    predict: impl Fn(&Record) -> Result<(Vec<Vec<f64>>, usize)>,
    recs: &[Record],
) -> Result<Vec<RecordFigures>> {
    recs.iter()
        .map(|r| {
            let (p, first) = predict(r)?;
            let outputs = m.figures(r, &p, first);
            ensure_finite_figures(&outputs, &r.source)?;
            Ok(RecordFigures {
                data: r.source.clone(),
                outputs,
            })
        })
        .collect()
}

/// Train every structure of `specs` (one: a single model; several: an ensemble) on
/// `records` (uniformly sampled at one interval) and measure it, one step ahead and in
/// free run, on the same records, beside the ARX baseline with the same lags.
pub fn train(
    specs: &[ModelSpec],
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
) -> Result<(FittedModel, FitSummary)> {
    train_beside(specs, None, records, inputs, outputs)
}

/// What `rhonn fit` and Python's `rhonn.fit` both do once the structure is known: train
/// `specs` beside the baseline a structure selection names (its best ARX on the folds: an
/// honest linear tuning, not the ARX with the chosen structure's lags), or, without a
/// selection, the ARX with the same lags; the summary carries the selection.
pub fn train_selected(
    specs: &[ModelSpec],
    selection: Option<super::select::Selection>,
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
) -> Result<(FittedModel, FitSummary)> {
    let baseline = selection.as_ref().map(|s| s.candidates[s.best_arx].model.clone());
    let own = selection
        .as_ref()
        .map_or_else(Vec::new, super::select::Selection::own_structures);
    let (mut fitted, mut summary) =
        train_composite(specs, &own, baseline.as_ref(), records, inputs, outputs)?;
    if let Some(s) = &selection {
        fitted.no_better_than_mean = s.no_better_than_mean.clone();
    }
    summary.selection = selection;
    Ok((fitted, summary))
}

/// The structure of a fit: given (one, or an ensemble's members), or selected by
/// cross-validation over the candidates.
#[derive(Debug, Clone)]
pub enum FitStructure<'a> {
    /// These structures.
    Given(Vec<ModelSpec>),
    /// The selection's choice.
    Select(&'a super::select::SelectOptions),
}

/// What a fit of records in memory gives: the model, its summary, and what the doors
/// print or hand over (`rhonn fit` prefixes and prints them, Python's `Model.warnings`
/// keeps the warnings).
#[derive(Debug, Clone)]
pub struct FitRun {
    /// The fitted model.
    pub fitted: FittedModel,
    /// Its summary (the selection included).
    pub summary: FitSummary,
    /// The structures trained.
    pub specs: Vec<ModelSpec>,
    /// The selection's findings in words (empty without a selection).
    pub selection_findings: Vec<String>,
    /// The selection's warnings.
    pub selection_warnings: Vec<String>,
    /// The data's warnings for the structure (none for the grey-box pump model, which has
    /// no lags), each door wording its advice (`DataWarning::worded`).
    pub data_warnings: Vec<super::DataWarning>,
}

/// `rhonn fit` and Python's `rhonn.fit` on records already read: the structure (given, or
/// selected), the data's warnings, and [`train_selected`] beside the selection's best
/// ARX.
/// A record shorter than the structure needs is an error naming it (its `source`).
pub fn fit_records(
    structure: FitStructure<'_>,
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
    progress: &(dyn Fn(&str) + Sync),
) -> Result<FitRun> {
    crate::data::check_names(inputs, outputs)?;
    crate::data::check_tiny(records, inputs, outputs)?;
    let needed = match &structure {
        FitStructure::Given(specs) => specs.iter().map(|s| s.max_lag()).max().unwrap_or(0) + 2,
        FitStructure::Select(opts) => super::select::min_samples(outputs.len(), opts),
    };
    if let Some(r) = records.iter().find(|r| r.len() < needed) {
        return Err(crate::Error::Argument(format!(
            "{} has {} samples; the model needs at least {needed}",
            r.source,
            r.len()
        )));
    }
    let (specs, selection) = match structure {
        FitStructure::Given(specs) => (specs, None),
        FitStructure::Select(opts) => {
            let sel = super::select::select(records, inputs, outputs, opts, progress);
            crate::cancel::check()?;
            let sel = sel?;
            (sel.chosen_specs(), Some(sel))
        }
    };
    let (selection_findings, selection_warnings) = selection.as_ref().map_or((Vec::new(), Vec::new()), |s| {
        (s.findings.clone(), s.warnings.clone())
    });
    let max_lag = specs.iter().map(|s| s.max_lag()).max().unwrap_or(0);
    let sample_s = records.first().map_or(0.0, |r| r.sample_interval());
    let data_warnings = match specs.first().map(|s| super::model_kind(s.kind)) {
        Some(k) if !k.data_warnings_apply() => Vec::new(),
        _ => super::data_warnings(records, inputs, outputs, max_lag, sample_s),
    };
    let trained = train_selected(&specs, selection, records, inputs, outputs);
    crate::cancel::check()?;
    let (fitted, summary) = trained?;
    Ok(FitRun {
        fitted,
        summary,
        specs,
        selection_findings,
        selection_warnings,
        data_warnings,
    })
}

/// [`train`] beside the ARX structure `baseline` (a structure selection's best ARX on the
/// folds) instead of the ARX with the same lags; None: the same lags.
pub fn train_beside(
    specs: &[ModelSpec],
    baseline: Option<&ModelSpec>,
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
) -> Result<(FittedModel, FitSummary)> {
    train_composite(specs, &[], baseline, records, inputs, outputs)
}

/// [`train_beside`] with the outputs `own` names predicted by structures of their own.
fn train_composite(
    specs: &[ModelSpec],
    own: &[(String, Vec<ModelSpec>)],
    baseline: Option<&ModelSpec>,
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
) -> Result<(FittedModel, FitSummary)> {
    let mut fitted = fit_ensemble(specs, records, inputs, outputs, baseline)?;
    fit_own_structures(&mut fitted, own, records, inputs, outputs)?;
    let m = &fitted.model;
    let summary = FitSummary {
        regridded: Vec::new(),
        rhonn_version: env!("CARGO_PKG_VERSION"),
        model: m.spec.clone(),
        features: m.n_features(),
        high_order_terms: m.terms.len(),
        sample_time_s: m.sample_time_s,
        training: TrainingFigures {
            one_step: figures_on(m, |r| fitted.predict(r, Some(1)), records)?,
            free_run: figures_on(m, |r| fitted.predict(r, None), records)?,
        },
        members: (!fitted.members.is_empty()).then(|| {
            fitted
                .all_members()
                .map(|m| MemberSummary {
                    model: m.spec.clone(),
                    features: m.n_features(),
                    high_order_terms: m.terms.len(),
                })
                .collect()
        }),
        by_output: fitted
            .by_output
            .iter()
            .map(|o| OutputStructureSummary {
                output: o.output.clone(),
                model: o.model.spec.clone(),
                members: 1 + o.members.len(),
                features: o.all_members().map(Model::n_features).sum(),
            })
            .collect(),
        baseline_arx: match &fitted.baseline {
            Some(b) => Some(BaselineSummary {
                structure: b.spec.lags_name(),
                chosen_as: match (baseline.is_some(), m.spec.kind) {
                    (true, _) => "best ARX on the folds",
                    (false, super::Kind::Arx | super::Kind::Rhonn) => "same lags",
                    (false, _) => "the spec's na and nb: this kind has no lags",
                },
                features: b.n_features(),
                one_step: figures_on(b, |r| b.predict(r, Some(1)), records)?,
                free_run: figures_on(b, |r| b.predict(r, None), records)?,
            }),
            None => None,
        },
        parameters: super::model_kind(m.spec.kind).named_parameters(m),
        selection: None,
    };
    Ok((fitted, summary))
}

/// The best ARX by `rhonn fit`'s selection (3-fold cross-validation, free run, lags 1 to
/// 8), trained on every record: the offline baseline `rhonn identify` reports beside its
/// online model. Returns the model and the selection among the ARX structures.
pub fn best_arx(
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
) -> Result<(FittedModel, super::select::Selection)> {
    use super::select::{candidates, select_from, SelectOptions};
    let opts = SelectOptions {
        cascade: false,
        ensembles: false,
        ..SelectOptions::default()
    };
    let list: Vec<(String, ModelSpec)> = candidates(outputs.len(), false)
        .into_iter()
        .filter(|(_, s)| s.kind == super::Kind::Arx)
        .collect();
    let sel = select_from(list, records, inputs, outputs, &opts, &|_| {})?;
    // The best ARX of the outputs together (with several outputs each output's own best ARX
    // may differ: the baseline is one MIMO ARX, as MATLAB's `arx` fits).
    let best = &sel.candidates[sel.best_arx].model;
    let (fitted, _) = train(std::slice::from_ref(best), records, inputs, outputs)?;
    Ok((fitted, sel))
}
