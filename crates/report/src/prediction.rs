//! What `rhonn predict` writes: `prediction.csv`, `summary.json`, `prediction.svg`.

use crate::plot::{Series, TimePlot};
use crate::{write_json, OutputSet, Result};
use rhonn::experiment::{Column, Trace};
use rhonn::sysid::{FittedModel, Prediction};
use std::path::{Path, PathBuf};

/// A conversion from SI to a display unit.
type ToDisplay = fn(f64) -> f64;

/// The display unit of a column `rhonn run` writes in SI (`trajectory.csv`): pressures in
/// Pa are shown in MPa, strokes in m in mm, flows in m^3/s in dm^3/s. None for any other
/// column (measured data keeps its own units).
fn display_unit(column: &str) -> Option<(ToDisplay, &'static str)> {
    use rhonn::units::{dm3_s, mm, mpa};
    // A baseline's column as its controller's, a measured one as the state.
    let base = ["_pi", "_second_baseline", "_baseline"]
        .iter()
        .find_map(|s| column.strip_suffix(s))
        .unwrap_or(column);
    let base = base.strip_suffix("_measured").unwrap_or(base);
    match base {
        "p_line" | "p_meas" | "p_ref" | "p_line_ref" | "p_line_model" => Some((mpa, "MPa")),
        "stroke" | "stroke_ref" => Some((mm, "mm")),
        "demand" => Some((dm3_s, "dm^3/s")),
        _ => None,
    }
}

/// The columns of `prediction.csv`: `t`, then per output the measurement, the
/// prediction (`<y>_hat`) and the baseline's (`<y>_hat_arx`).
pub fn prediction_trace(fitted: &FittedModel, p: &Prediction) -> Trace {
    let r = &p.record;
    let mut trace = Trace::default();
    let col = |name: String, values: Vec<f64>| Column {
        name,
        unit: "",
        values,
    };
    trace.columns.push(col("t".into(), r.t.clone()));
    for (j, name) in fitted.model.outputs.iter().enumerate() {
        trace.columns.push(col(name.clone(), r.outputs[j].clone()));
        trace
            .columns
            .push(col(format!("{name}_hat"), p.outputs[j].clone()));
        if let Some((pb, _)) = &p.baseline {
            trace.columns.push(col(format!("{name}_hat_arx"), pb[j].clone()));
        }
    }
    trace
}

/// Measured and predicted, one panel per output (rhonn's SI columns in display units).
pub fn plot_prediction(fitted: &FittedModel, p: &Prediction) -> String {
    let r = &p.record;
    let mode = p.mode();
    let plots: Vec<TimePlot> = fitted
        .model
        .outputs
        .iter()
        .enumerate()
        .map(|(j, name)| {
            // The pump's SI columns in display units; else the unit given with --units.
            let (to_display, y_label): (ToDisplay, String) =
                match (display_unit(name), fitted.units.get(name)) {
                    (Some((f, unit)), _) => (f, format!("{name} [{unit}]")),
                    (None, Some(unit)) => (|v| v, format!("{name} [{unit}]")),
                    (None, None) => (|v| v, name.clone()),
                };
            let scaled = |v: &[f64]| v.iter().map(|&x| to_display(x)).collect::<Vec<f64>>();
            let mut series = vec![
                Series {
                    label: name.clone(),
                    y: scaled(&r.outputs[j]),
                    dashed: false,
                },
                Series {
                    label: format!("{name}_hat ({mode}, fit {:.1} %)", p.figures[j].fit_percent),
                    y: scaled(&p.outputs[j]),
                    dashed: true,
                },
            ];
            if let (Some((pb, fb)), Some(b)) = (&p.baseline, &fitted.baseline) {
                series.push(Series {
                    label: format!(
                        "ARX baseline {} (fit {:.1} %)",
                        b.spec.lags_name(),
                        fb[j].fit_percent
                    ),
                    y: scaled(&pb[j]),
                    dashed: true,
                });
            }
            TimePlot {
                title: format!("{name}: measured and predicted, {mode}"),
                y_label,
                t: r.t.clone(),
                series,
            }
        })
        .collect();
    TimePlot::render(&plots, 900, 380)
}

/// `prediction_zoom.svg`: the prediction around its largest error (100 samples either
/// side of it, over every output), where a whole long record drawn at once is a band.
pub fn plot_zoom(fitted: &FittedModel, p: &Prediction) -> String {
    let n = p.record.len();
    let err_at = |k: usize| {
        (0..p.outputs.len())
            .map(|j| (p.outputs[j][k] - p.record.outputs[j][k]).abs())
            .fold(0.0f64, f64::max)
    };
    let worst = (p.first.min(n)..n)
        .max_by(|&a, &b| err_at(a).total_cmp(&err_at(b)))
        .unwrap_or(0);
    let (a, b) = (worst.saturating_sub(100), (worst + 101).min(n));
    let cut = |v: &[f64]| v[a..b].to_vec();
    let zoomed = Prediction {
        record: rhonn::data::Record {
            source: p.record.source.clone(),
            t: cut(&p.record.t),
            inputs: p.record.inputs.iter().map(|c| cut(c)).collect(),
            outputs: p.record.outputs.iter().map(|c| cut(c)).collect(),
        },
        outputs: p.outputs.iter().map(|c| cut(c)).collect(),
        baseline: p
            .baseline
            .as_ref()
            .map(|(pb, fb)| (pb.iter().map(|c| cut(c)).collect(), fb.clone())),
        first: p.first.saturating_sub(a),
        ..p.clone()
    };
    plot_prediction(fitted, &zoomed).replace(": measured and predicted, ", ": around the largest error, ")
}

/// Write `prediction.csv`, `summary.json` (naming the model's source `model`) and
/// `prediction.svg` into `dir`, all or nothing; returns the files written.
pub fn write_prediction(
    dir: &Path,
    fitted: &FittedModel,
    p: &Prediction,
    model: &str,
) -> Result<Vec<PathBuf>> {
    let trace = prediction_trace(fitted, p);
    let svg = plot_prediction(fitted, p);
    let mut set = OutputSet::new(dir)?;
    set.write("prediction.csv", |w| crate::write_trace_csv(w, &trace))?;
    set.write("summary.json", |w| write_json(w, &p.summary(model)))?;
    set.write("prediction.svg", |w| w.write_all(svg.as_bytes()))?;
    let residuals = crate::residuals::plot_residuals(
        &p.record,
        &p.outputs,
        p.first,
        &fitted.model.inputs,
        &fitted.model.outputs,
    );
    set.write("residuals.svg", |w| w.write_all(residuals.as_bytes()))?;
    let hist = crate::residuals::residual_histograms(&p.record, &p.outputs, p.first, &fitted.model.outputs);
    set.write("residual_histogram.svg", |w| w.write_all(hist.as_bytes()))?;
    let zoom = plot_zoom(fitted, p);
    set.write("prediction_zoom.svg", |w| w.write_all(zoom.as_bytes()))?;
    set.commit()
}
