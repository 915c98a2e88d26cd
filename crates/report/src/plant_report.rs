//! What `rhonn run` writes for a plant scenario (`[plant] kind`, the pump included):
//! `trajectory.csv` (SI, one column per state, input, estimate or reference),
//! `validation.csv` (a frozen model's free run), `summary.json`, and plots in display
//! units: `states.svg` (each state; measured and estimated, or both controllers with the
//! set-point), `inputs.svg`, `errors.svg` (an identification's estimation errors),
//! `validation.svg`, and for an adaptive controller `weights.svg` (its weights against the
//! ball's radius).

use crate::atomic::OutputSet;
use crate::plot::{Series, TimePlot};
use crate::{write_json, Result};
use rhonn::experiment::{PlantColumn, PlantRunOutput};
use std::io::Write;
use std::path::{Path, PathBuf};

fn write_columns(w: &mut dyn Write, cols: &[PlantColumn]) -> std::io::Result<()> {
    let mut wr = csv::Writer::from_writer(w);
    wr.write_record(cols.iter().map(|c| c.name.as_str()))?;
    let n = cols.first().map_or(0, |c| c.values.len());
    for k in 0..n {
        wr.write_record(cols.iter().map(|c| format!("{:e}", c.values[k])))?;
    }
    wr.flush()
}

/// One panel per quantity among `cols` (time first), the series of that quantity in it.
fn panels(title: &str, cols: &[PlantColumn], keep: impl Fn(&PlantColumn) -> bool) -> Vec<TimePlot> {
    let t = cols[0].values.clone();
    let mut out: Vec<(&str, TimePlot)> = Vec::new();
    for c in cols[1..].iter().filter(|c| keep(c)) {
        let q = &c.quantity;
        let series = Series {
            label: label(&c.name),
            y: c.values.iter().map(|v| q.to_display(*v)).collect(),
            dashed: c.name.ends_with("_ref")
                || c.name.ends_with("_ref_baseline")
                || c.name.starts_with("w1_ball_radius"),
        };
        match out.iter_mut().find(|(name, _)| *name == q.name) {
            Some((_, p)) => p.series.push(series),
            None => out.push((
                q.name,
                TimePlot {
                    title: format!("{title}: {}", q.description),
                    y_label: format!("{} [{}]", q.name, q.display_unit),
                    t: t.clone(),
                    series: vec![series],
                },
            )),
        }
    }
    out.into_iter().map(|(_, p)| p).collect()
}

/// Time and each identified state's online estimation error, `<state>_hat - <state>` (the
/// thesis's error figures: how fast the identifier converges); only time without estimates.
fn estimation_errors(cols: &[PlantColumn]) -> Vec<PlantColumn> {
    let mut out = vec![cols[0].clone()];
    for c in cols {
        let Some(base) = c.name.strip_suffix("_hat") else {
            continue;
        };
        if let Some(y) = cols.iter().find(|d| d.name == base) {
            out.push(PlantColumn {
                name: format!("{base}_hat - {base}"),
                quantity: c.quantity,
                values: c.values.iter().zip(&y.values).map(|(h, v)| h - v).collect(),
                input: false,
            });
        }
    }
    out
}

/// Legend labels that say the role (and so get the role's colour).
fn label(name: &str) -> String {
    if let Some(rest) = name.strip_prefix("w1_ball_radius") {
        format!(
            "ball radius (bound){}",
            if rest.is_empty() { "" } else { " (baseline)" }
        )
    } else if let Some(base) = name.strip_suffix("_ref_baseline") {
        format!("{base} set-point (baseline)")
    } else if let Some(base) = name.strip_suffix("_baseline") {
        format!("{base} (baseline)")
    } else if let Some(base) = name.strip_suffix("_ref") {
        format!("{base} set-point")
    } else if let Some(base) = name.strip_suffix("_hat_series_parallel") {
        format!("{base} series-parallel (frozen)")
    } else if let Some(base) = name.strip_suffix("_hat_parallel") {
        format!("{base} free run (frozen)")
    } else if let Some(base) = name.strip_suffix("_hat") {
        format!("{base} estimated")
    } else {
        name.to_string()
    }
}

/// Write a plant scenario's outputs into `dir`, all or nothing; returns the files.
pub fn write_plant_run(dir: &Path, output: &PlantRunOutput) -> Result<Vec<PathBuf>> {
    let name = &output.summary.scenario;
    let mut set = OutputSet::new(dir)?;
    set.write("trajectory.csv", |w| write_columns(w, &output.trajectory))?;
    set.write("summary.json", |w| write_json(w, &output.summary))?;
    if let Some(model) = &output.model {
        set.write("weights.json", |w| write_json(w, model))?;
    }
    let is_in = |c: &PlantColumn| c.input;
    let is_weight = |c: &PlantColumn| {
        rhonn::experiment::WEIGHT_QUANTITIES
            .iter()
            .any(|q| q.name == c.quantity.name)
    };
    // What a noisy sensor measured, and an adaptive controller's model of the regulated
    // state, are in trajectory.csv; the plot shows the true states.
    let is_measured = |c: &PlantColumn| c.name.contains("_measured") || c.name.contains("_model");
    let mut plots = vec![
        (
            "states.svg",
            TimePlot::render(
                &panels(name, &output.trajectory, |c| {
                    !is_in(c) && !is_weight(c) && !is_measured(c)
                }),
                900,
                380,
            ),
        ),
        (
            "inputs.svg",
            TimePlot::render(&panels(name, &output.trajectory, is_in), 900, 380),
        ),
    ];
    let errors = estimation_errors(&output.trajectory);
    if errors.len() > 1 {
        let title = format!("{name}: the online estimate's error");
        plots.push((
            "errors.svg",
            TimePlot::render(&panels(&title, &errors, |_| true), 900, 380),
        ));
    }
    if output.trajectory.iter().any(is_weight) {
        plots.push((
            "weights.svg",
            TimePlot::render(&panels(name, &output.trajectory, is_weight), 900, 300),
        ));
    }
    if let Some(v) = &output.validation {
        set.write("validation.csv", |w| write_columns(w, v))?;
        let same_data = v.iter().any(|c| c.name.ends_with("_hat_series_parallel"));
        let title = if same_data {
            format!("{name} (frozen weights on the training inputs)")
        } else {
            format!("{name} (frozen weights, free run)")
        };
        plots.push((
            "validation.svg",
            TimePlot::render(&panels(&title, v, |c| !is_in(c)), 900, 380),
        ));
    }
    for (file, svg) in plots {
        set.write(file, |w| w.write_all(svg.as_bytes()))?;
    }
    set.commit()
}
