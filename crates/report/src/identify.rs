//! The files of `rhonn identify`: estimate.csv, weights.csv, validation.csv,
//! summary.json, model.json and plots, all or nothing.

use crate::{write_json, OutputSet, Result, Series, TimePlot};
use rhonn::data::Record;
use rhonn::experiment::{Column, Trace};
use rhonn::ident::{OnlineModel, OnlineRun};
pub use rhonn::identification::{
    online_prediction_figures, validation_figures, IdentifySummary, ValidationFigures,
};
use rhonn::identification::{OnlinePredictionFigures, Validation};
use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Write everything of an identification into `dir`.
#[allow(clippy::too_many_arguments)]
pub fn write_identify(
    dir: &Path,
    run: &OnlineRun,
    records: &[Record],
    outputs: &[String],
    model: &OnlineModel,
    summary: &IdentifySummary,
    validation: Option<&Validation>,
) -> Result<Vec<PathBuf>> {
    let mut set = OutputSet::new(dir)?;
    set.write("estimate.csv", |w| estimate_csv(w, run, records, outputs))?;
    set.write("weights.csv", |w| weights_csv(w, run, records, outputs))?;
    if let Some(v) = validation {
        set.write("validation.csv", |w| validation_csv(w, v, outputs))?;
    }
    set.write("summary.json", |w| write_json(w, summary))?;
    set.write("model.json", |w| write_json(w, model))?;
    let (est, wts) = plots(run, records, outputs, &summary.units);
    set.write("estimate.svg", |w| w.write_all(est.as_bytes()))?;
    set.write("weights.svg", |w| w.write_all(wts.as_bytes()))?;
    // The online estimate's residuals over the last half of the final pass (the first
    // half is learning, as for the summary's figures), and the frozen model's free run
    // on the validation records.
    let (all, est) = joined(records, &run.estimates, outputs.len());
    let half = all.len() / 2;
    let acf = crate::residuals::plot_residuals(&all, &est, half, &model.inputs, outputs);
    set.write("residuals.svg", |w| w.write_all(acf.as_bytes()))?;
    let hist = crate::residuals::residual_histograms(&all, &est, half, outputs);
    set.write("residual_histogram.svg", |w| w.write_all(hist.as_bytes()))?;
    if let Some(v) = validation {
        let svg = validation_plot(v, outputs, &summary.units);
        set.write("validation.svg", |w| w.write_all(svg.as_bytes()))?;
        let (vj, vest) = joined(&v.records, &v.free_run, outputs.len());
        let acf = crate::residuals::plot_residuals(&vj, &vest, 0, &model.inputs, outputs);
        set.write("validation_residuals.svg", |w| w.write_all(acf.as_bytes()))?;
    }
    set.commit()
}

/// The records laid end to end as one, and the per-output estimates `est` (per record,
/// per sample, per output) over them.
fn joined(records: &[Record], est: &[Vec<Vec<f64>>], n_out: usize) -> (Record, Vec<Vec<f64>>) {
    let n_in = records.first().map_or(0, |r| r.inputs.len());
    let record = Record {
        source: records
            .iter()
            .map(|r| r.source.as_str())
            .collect::<Vec<_>>()
            .join(", "),
        t: joined_times(records),
        inputs: (0..n_in)
            .map(|i| records.iter().flat_map(|r| r.inputs[i].iter().copied()).collect())
            .collect(),
        outputs: (0..n_out).map(|j| measured(records, j)).collect(),
    };
    (record, (0..n_out).map(|j| flat(est, j)).collect())
}

/// A column of a table.
fn col(name: impl Into<String>, values: Vec<f64>) -> Column {
    Column {
        name: name.into(),
        unit: "",
        values,
    }
}

/// `record` (each record's index) and `t` over records laid end to end.
fn record_columns(records: &[Record]) -> Vec<Column> {
    let index = records
        .iter()
        .enumerate()
        .flat_map(|(i, r)| std::iter::repeat_n(i as f64, r.len()));
    vec![
        col("record", index.collect()),
        col("t", records.iter().flat_map(|r| r.t.iter().copied()).collect()),
    ]
}

/// Column `j` of per-record, per-sample vectors, records laid end to end.
fn flat(v: &[Vec<Vec<f64>>], j: usize) -> Vec<f64> {
    v.iter().flatten().map(|e| e[j]).collect()
}

/// Output `j` of the records, laid end to end.
fn measured(records: &[Record], j: usize) -> Vec<f64> {
    records
        .iter()
        .flat_map(|r| r.outputs[j].iter().copied())
        .collect()
}

fn estimate_csv(
    w: &mut dyn Write,
    run: &OnlineRun,
    records: &[Record],
    outputs: &[String],
) -> std::io::Result<()> {
    let mut columns = record_columns(records);
    for (j, o) in outputs.iter().enumerate() {
        columns.push(col(o.clone(), measured(records, j)));
        columns.push(col(format!("{o}_hat"), flat(&run.estimates, j)));
    }
    crate::write_trace_csv(w, &Trace { columns })
}

fn weights_csv(
    w: &mut dyn Write,
    run: &OnlineRun,
    records: &[Record],
    outputs: &[String],
) -> std::io::Result<()> {
    let mut columns = record_columns(records);
    for (j, o) in outputs.iter().enumerate() {
        columns.push(col(format!("w_norm_{o}"), flat(&run.weight_norms, j)));
    }
    // 1/2 sum of squared normalised errors: the part of the laws' Lyapunov function that
    // can be measured.
    let sc = run.identifier.scaling();
    let est = run.estimates.iter().flatten();
    let energy = est
        .zip(records.iter().flat_map(|r| (0..r.len()).map(move |k| (r, k))))
        .map(|(e, (r, k))| {
            (0..outputs.len())
                .map(|j| 0.5 * ((e[j] - r.outputs[j][k]) / sc.y_scale[j]).powi(2))
                .sum()
        })
        .collect();
    columns.push(col("error_energy", energy));
    if run.weights.first().is_some_and(|r| !r.is_empty()) {
        // One column per weight, `w_<output>_<k>`, in the weight vectors' order (a
        // `per-output` structure's own parts are `w_<output>_own_<k>`).
        let lengths = run.identifier.weight_lengths();
        let mut at = 0;
        for (label, l) in run.identifier.weight_labels(outputs).iter().zip(lengths) {
            for k in 0..l {
                columns.push(col(format!("w_{label}_{k}"), flat(&run.weights, at + k)));
            }
            at += l;
        }
    }
    crate::write_trace_csv(w, &Trace { columns })
}

fn validation_csv(w: &mut dyn Write, v: &Validation, outputs: &[String]) -> std::io::Result<()> {
    let mut columns = record_columns(&v.records);
    for (j, o) in outputs.iter().enumerate() {
        columns.push(col(o.clone(), measured(&v.records, j)));
        columns.push(col(format!("{o}_free_run"), flat(&v.free_run, j)));
        if let Some((k, p)) = &v.ahead {
            columns.push(col(format!("{o}_{k}_ahead"), flat(p, j)));
        }
    }
    crate::write_trace_csv(w, &Trace { columns })
}

/// Times of records laid end to end (each record's own times, shifted to follow the
/// previous one).
fn joined_times(records: &[Record]) -> Vec<f64> {
    let mut t = Vec::new();
    let mut shift = 0.0;
    for r in records {
        let t0 = r.t[0];
        t.extend(r.t.iter().map(|x| x - t0 + shift));
        shift = t.last().copied().unwrap_or(0.0) + r.median_interval();
    }
    t
}

/// An output's axis label, with the unit given by `--units`.
fn axis(o: &str, units: &std::collections::BTreeMap<String, String>) -> String {
    units.get(o).map_or(o.to_string(), |u| format!("{o} [{u}]"))
}

fn plots(
    run: &OnlineRun,
    records: &[Record],
    outputs: &[String],
    units: &std::collections::BTreeMap<String, String>,
) -> (String, String) {
    let t = joined_times(records);
    let panels: Vec<TimePlot> = outputs
        .iter()
        .enumerate()
        .map(|(j, o)| TimePlot {
            title: format!("online identification (final pass): {o}"),
            y_label: axis(o, units),
            t: t.clone(),
            series: vec![
                Series::solid(
                    format!("{o} measured"),
                    records.iter().flat_map(|r| r.outputs[j].clone()).collect(),
                ),
                Series::solid(
                    format!("{o} online estimate"),
                    run.estimates.iter().flatten().map(|e| e[j]).collect(),
                ),
            ],
        })
        .collect();
    // The online error against its band (twice the final RMS error; the summary's
    // `converged_s` is the time from which it stays inside).
    let mut panels = panels;
    for (j, o) in outputs.iter().enumerate() {
        let e: Vec<f64> = run
            .estimates
            .iter()
            .flatten()
            .zip(records.iter().flat_map(|r| r.outputs[j].iter()))
            .map(|(est, y)| est[j] - y)
            .collect();
        let mut series = vec![Series::solid(format!("{o}_hat - {o}"), e.clone())];
        if let Some(f) = run.figures.get(j) {
            let b = f.band;
            series.push(Series::dashed(format!("band +-{b:.4} (limit)"), vec![b; e.len()]));
            series.push(Series::dashed("-band (limit)", vec![-b; e.len()]));
        }
        panels.push(TimePlot {
            title: format!("online error (final pass): {o}"),
            y_label: format!("{o}_hat - {o}"),
            t: t.clone(),
            series,
        });
    }
    let weights = TimePlot {
        title: "weight norms (final pass)".into(),
        y_label: "|w_i| (normalised units)".into(),
        t,
        series: outputs
            .iter()
            .enumerate()
            .map(|(j, o)| {
                Series::solid(
                    format!("|w| of {o}'s neuron"),
                    run.weight_norms.iter().flatten().map(|n| n[j]).collect(),
                )
            })
            .collect(),
    };
    (
        TimePlot::render(&panels, 900, 380),
        TimePlot::render(&[weights], 900, 380),
    )
}

/// The validation against the measurements, the fit of each prediction in its legend
/// (the same figure as summary.json's `validation`).
fn validation_plot(
    v: &Validation,
    outputs: &[String],
    units: &std::collections::BTreeMap<String, String>,
) -> String {
    let t = joined_times(&v.records);
    let figures = validation_figures(v, outputs);
    let panels: Vec<TimePlot> = outputs
        .iter()
        .enumerate()
        .map(|(j, o)| {
            let mut series = vec![
                Series::solid(
                    format!("{o} measured"),
                    v.records.iter().flat_map(|r| r.outputs[j].clone()).collect(),
                ),
                Series::solid(
                    format!(
                        "{o} free run (frozen weights, fit {:.1} %)",
                        figures[j].free_run_fit_percent
                    ),
                    v.free_run.iter().flatten().map(|e| e[j]).collect(),
                ),
            ];
            if let Some((k, p)) = &v.ahead {
                series.push(Series::solid(
                    format!(
                        "{o} {k} samples ahead (fit {:.1} %)",
                        figures[j].ahead_fit_percent.unwrap_or(f64::NAN)
                    ),
                    p.iter().flatten().map(|e| e[j]).collect(),
                ));
            }
            TimePlot {
                title: format!("validation: {o}"),
                y_label: axis(o, units),
                t: t.clone(),
                series,
            }
        })
        .collect();
    TimePlot::render(&panels, 900, 380)
}

/// `rhonn predict`'s `summary.json` for an online model.
#[derive(Serialize, schemars::JsonSchema)]
struct Summary<'a> {
    /// The model file.
    model: &'a str,
    /// Its online structure (`kind`).
    kind: &'a str,
    /// The record predicted.
    data: &'a str,
    /// `free run`, `1 step ahead` or `K steps ahead`.
    mode: String,
    /// Samples at the start of the record that set the model's state before it predicts
    /// (`--init-window`); left out when not given.
    #[serde(skip_serializing_if = "Option::is_none")]
    init_window: Option<usize>,
    /// Per output: the prediction's figures.
    figures: &'a [OnlinePredictionFigures],
    /// What the figures say, in words.
    findings: Vec<String>,
}

/// The schema of an online model's prediction `summary.json` (`fields`).
pub(crate) fn prediction_schema() -> serde_json::Value {
    schemars::schema_for!(Summary<'static>).to_value()
}

/// `rhonn predict` on an online model: prediction.csv (t, per output `<name>` and
/// `<name>_hat`), summary.json and prediction.svg.
pub fn write_online_prediction(
    dir: &Path,
    model: &OnlineModel,
    model_path: &str,
    record: &Record,
    pred: &[Vec<f64>],
    (steps_ahead, init_window): (Option<usize>, Option<usize>),
    figures: &[OnlinePredictionFigures],
) -> Result<Vec<PathBuf>> {
    let mode = rhonn::metrics::prediction_mode(steps_ahead);
    let mut set = OutputSet::new(dir)?;
    set.write("prediction.csv", |w| {
        let mut columns = vec![col("t", record.t.clone())];
        for (j, o) in model.outputs.iter().enumerate() {
            columns.push(col(o.clone(), record.outputs[j].clone()));
            columns.push(col(format!("{o}_hat"), pred.iter().map(|e| e[j]).collect()));
        }
        crate::write_trace_csv(w, &Trace { columns })
    })?;
    let summary = Summary {
        model: model_path,
        kind: &model.kind,
        data: &record.source,
        mode: mode.clone(),
        init_window,
        figures,
        findings: figures
            .iter()
            .filter(|f| f.fit_percent.is_finite())
            .map(|f| {
                format!(
                    "{} ({mode}): fit {:.1} % ({})",
                    f.output,
                    f.fit_percent,
                    if f.fit_percent < 0.0 {
                        "worse than predicting the mean"
                    } else {
                        "better than predicting the mean"
                    }
                )
            })
            .collect(),
    };
    set.write("summary.json", |w| write_json(w, &summary))?;
    let t = record.t.clone();
    let panels: Vec<TimePlot> = model
        .outputs
        .iter()
        .enumerate()
        .map(|(j, o)| TimePlot {
            title: format!("{}: {o}, online RHONN ({mode})", record.source),
            y_label: o.clone(),
            t: t.clone(),
            series: vec![
                Series::solid(format!("{o} measured"), record.outputs[j].clone()),
                Series::solid(format!("{o} predicted"), pred.iter().map(|e| e[j]).collect()),
            ],
        })
        .collect();
    let svg = TimePlot::render(&panels, 900, 380);
    set.write("prediction.svg", |w| w.write_all(svg.as_bytes()))?;
    set.commit()
}
