//! The three models of a benchmark row, each trained on train only and run free on every
//! test set: rhonn's default fit, rhonn's default online identifier, the ARX of lags by
//! cross-validation. All three are scored on the same samples of each test set: from the end
//! of its start-up window, which is all a model sees of its outputs (a model that needs
//! more past outputs is given the window's first sample held before it:
//! `data::within_window`); without a window, from every model's first genuine prediction.

use super::{Benchmark, Published};
use crate::data::{within_window, Record};
use crate::error::Result;
use crate::ident::bank::BankSelection;
use crate::ident::{predict_records, OnlineModel};
use crate::sysid::{self, FittedModel};
use serde::Serialize;
use std::time::Instant;

/// One model's free run on one test set.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct TestScore {
    /// The test set's label.
    pub test: String,
    /// Per output, the RMS error from `scored_from` on (data units).
    pub rmse: Vec<f64>,
    /// Per output, the free run (the measurement repeated before the model's first
    /// prediction).
    #[serde(skip)]
    pub prediction: Vec<Vec<f64>>,
}

/// One model of a row.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct MethodResult {
    /// `rhonn fit (default)` (`rhonn fit (--model)` with a given model), `rhonn identify
    /// (default)` or `ARX (lags by CV)`.
    pub method: String,
    /// Its structure, in words.
    pub structure: String,
    /// Wall time of its training \[s\] (selection included).
    pub train_time_s: f64,
    /// Per test set.
    pub tests: Vec<TestScore>,
}

/// What a benchmark gives (`summary.json` of `rhonn benchmark`, per benchmark).
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct BenchmarkOutcome {
    /// Its folder's name.
    pub name: String,
    /// What the system is.
    pub title: String,
    /// Its reference paper.
    pub reference: String,
    /// Output columns.
    pub outputs: Vec<String>,
    /// Units of the columns.
    pub units: std::collections::BTreeMap<String, String>,
    /// Per test set: its label, the first sample scored (the end of the start-up window;
    /// without one, the latest first prediction of the three models) and the published
    /// figures.
    pub test_sets: Vec<TestSet>,
    /// The three models.
    pub methods: Vec<MethodResult>,
    /// How rhonn identify's default picked its model on train (every candidate's
    /// prequential figures and the final check), as `rhonn identify`'s `selection`.
    pub online_selection: BankSelection,
    /// What the user must know, each led by the method it concerns (rhonn fit's
    /// selection: every structure worse than the mean on the folds; rhonn identify's: every
    /// candidate worse than the mean in its final check).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// rhonn's default model, trained on train (`NAME/model.json`).
    #[serde(skip)]
    pub fitted: FittedModel,
    /// rhonn's default online model, frozen after train (`NAME/online/model.json`).
    #[serde(skip)]
    pub online: OnlineModel,
}

/// A test set's protocol as scored.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct TestSet {
    /// Its label.
    pub label: String,
    /// The first sample scored.
    pub scored_from: usize,
    /// Samples scored.
    pub samples: usize,
    /// The published figures.
    pub published: Vec<Published>,
}

/// Per output, the RMS error of `pred` against `r` from sample `from` on.
fn rmse_from(r: &Record, pred: &[Vec<f64>], from: usize) -> Vec<f64> {
    r.outputs
        .iter()
        .zip(pred)
        .map(|(y, p)| crate::metrics::rms_error(&y[from..], &p[from..]))
        .collect()
}

/// A fitted model's free run: its columns and its first prediction.
fn fitted_run(m: &FittedModel) -> impl Fn(&Record) -> Result<(Vec<Vec<f64>>, usize)> + '_ {
    move |r: &Record| sysid::predict(m, r, None).map(|p| (p.outputs, p.first))
}

/// rhonn fit's default: the structure selected by cross-validation on train, trained
/// beside the selection's best ARX; or, given `model` (a spec's structures and its name),
/// that structure trained on train as `rhonn fit --model` trains it.
fn fit_default(
    b: &Benchmark,
    model: Option<(&[sysid::ModelSpec], &str)>,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<(FittedModel, String, f64, Vec<String>)> {
    let (ins, outs) = (&b.spec.inputs, &b.spec.outputs);
    let start = Instant::now();
    let opts = sysid::select::SelectOptions::default();
    let structure = match model {
        Some((specs, _)) => sysid::FitStructure::Given(specs.to_vec()),
        None => sysid::FitStructure::Select(&opts),
    };
    let run = sysid::fit_records(structure, &b.train, ins, outs, progress)?;
    let structure = match (&run.summary.selection, model) {
        (_, Some((_, name))) => name.to_string(),
        (Some(sel), None) => sel.chosen_name(),
        (None, None) => String::new(),
    };
    Ok((
        run.fitted,
        structure,
        start.elapsed().as_secs_f64(),
        run.selection_warnings,
    ))
}

/// rhonn identify's default on the benchmark's training records, timed.
fn online_default(b: &Benchmark) -> Result<(OnlineModel, BankSelection, f64)> {
    let start = Instant::now();
    let (model, sel) = crate::identification::online_default(&b.train, &b.spec.inputs, &b.spec.outputs)?;
    Ok((model, sel, start.elapsed().as_secs_f64()))
}

/// Run the benchmark: the three models on train, each run free on every test set.
/// `progress` hears a line per stage.
pub fn run(b: &Benchmark, progress: &(dyn Fn(&str) + Sync)) -> Result<BenchmarkOutcome> {
    run_with(b, None, progress)
}

/// [`run`] with rhonn fit's model given (`rhonn benchmark --model SPEC.toml`): the spec's
/// structures and the name the table gives them, in place of the selection's choice.
pub fn run_with(
    b: &Benchmark,
    model: Option<(&[sysid::ModelSpec], &str)>,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<BenchmarkOutcome> {
    b.check()?;
    let (ins, outs) = (&b.spec.inputs, &b.spec.outputs);
    progress(&format!(
        "{}: rhonn fit ({})",
        b.name,
        if model.is_some() {
            "the given model"
        } else {
            "structure selected on train"
        }
    ));
    let named = |l: &str| progress(&format!("{}: rhonn fit: {l}", b.name));
    let (fitted, fit_structure, fit_s, warnings) = fit_default(b, model, &named)?;
    progress(&format!("{}: rhonn identify (online selection)", b.name));
    let (online, online_selection, online_s) = online_default(b)?;
    let online_structure = online_selection.chosen_name();
    let warnings: Vec<String> = warnings
        .iter()
        .map(|w| format!("rhonn fit: {w}"))
        .chain(
            online_selection
                .warnings
                .iter()
                .map(|w| format!("rhonn identify: {w}")),
        )
        .collect();
    progress(&format!("{}: ARX, lags by cross-validation", b.name));
    let start = Instant::now();
    let (arx, arx_sel) = sysid::best_arx(&b.train, ins, outs)?;
    let arx_s = start.elapsed().as_secs_f64();
    let mut id = online.identifier()?;
    let lag = crate::ident::outputs_read_in_free_run(&online.model);
    let mut runs: [Vec<Vec<Vec<f64>>>; 3] = Default::default();
    let mut test_sets = Vec::new();
    // A start-up window (skip > 0) is a state-initialisation window: each model sees only
    // its outputs, and all are scored from its end. Without one, each model measures what
    // it needs and all are scored from the latest first prediction.
    let window = (b.spec.skip > 0).then_some(b.spec.skip);
    for (t, r) in b.spec.test.iter().zip(&b.tests) {
        let mut online_run = |r: &Record| -> Result<(Vec<Vec<f64>>, usize)> {
            let o = predict_records(&mut id, std::slice::from_ref(r), None)?.remove(0);
            let cols = (0..outs.len())
                .map(|j| o.iter().map(|s| s[j]).collect())
                .collect();
            Ok((cols, lag))
        };
        let (f, a, o) = match window {
            Some(w) => (
                within_window(r, w, fitted_run(&fitted))?,
                within_window(r, w, fitted_run(&arx))?,
                within_window(r, w, online_run)?,
            ),
            None => (fitted_run(&fitted)(r)?, fitted_run(&arx)(r)?, online_run(r)?),
        };
        let ((f, f_first), (a, a_first), (o, o_first)) = (f, a, o);
        let from = b.spec.skip.max(f_first).max(a_first).max(o_first);
        test_sets.push(TestSet {
            label: t.label.clone(),
            scored_from: from,
            samples: r.len().saturating_sub(from),
            published: t.published.clone(),
        });
        runs[0].push(f);
        runs[1].push(o);
        runs[2].push(a);
    }
    let arx_structure = arx_sel.candidates[arx_sel.best_arx].name.clone();
    let timed = [
        (fit_structure, fit_s),
        (online_structure, online_s),
        (arx_structure, arx_s),
    ];
    let methods = method_results(b, model.is_some(), timed, runs, &test_sets);
    Ok(BenchmarkOutcome {
        name: b.name.clone(),
        title: b.spec.title.clone(),
        reference: b.spec.reference.clone(),
        outputs: outs.clone(),
        units: b.spec.units.clone(),
        test_sets,
        methods,
        online_selection,
        warnings,
        fitted,
        online,
    })
}

/// Each method's row of the table: its name, structure and training time (`timed`, in the
/// order rhonn fit, rhonn identify, ARX) and its predictions of each test set scored.
fn method_results(
    b: &Benchmark,
    model_given: bool,
    timed: [(String, f64); 3],
    runs: [Vec<Vec<Vec<f64>>>; 3],
    test_sets: &[TestSet],
) -> Vec<MethodResult> {
    let fit = if model_given {
        "rhonn fit (--model)"
    } else {
        "rhonn fit (default)"
    };
    [fit, "rhonn identify (default)", "ARX (lags by CV)"]
        .into_iter()
        .zip(timed)
        .zip(runs)
        .map(|((method, (structure, s)), preds)| MethodResult {
            method: method.into(),
            structure,
            train_time_s: s,
            tests: preds
                .into_iter()
                .zip(b.tests.iter().zip(test_sets))
                .map(|(p, (r, ts))| TestScore {
                    test: ts.label.clone(),
                    rmse: rmse_from(r, &p, ts.scored_from),
                    prediction: p,
                })
                .collect(),
        })
        .collect()
}
