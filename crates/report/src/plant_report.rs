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

/// The columns as CSV, each value the shortest decimal that reads back as it (as every
/// table rhonn writes).
fn write_columns(w: &mut dyn Write, cols: &[PlantColumn]) -> std::io::Result<()> {
    let mut wr = csv::Writer::from_writer(w);
    wr.write_record(cols.iter().map(|c| c.name.as_str()))?;
    let n = cols.first().map_or(0, |c| c.values.len());
    let mut buf = crate::csv_out::ryu_like::Buf::default();
    for k in 0..n {
        for c in cols {
            wr.write_field(buf.format(c.values[k]))?;
        }
        wr.write_record(None::<&[u8]>)?;
    }
    wr.flush()
}

/// One panel per quantity among `cols` (time first), the series of that quantity in it,
/// each labelled by `names` ([`Labels`]), with the plant's floor on its state's panel.
fn panels(
    title: &str,
    cols: &[PlantColumn],
    names: &Labels,
    keep: impl Fn(&PlantColumn) -> bool,
) -> Vec<TimePlot> {
    let t = cols[0].values.clone();
    let mut out: Vec<(&str, TimePlot)> = Vec::new();
    for c in cols[1..].iter().filter(|c| keep(c)) {
        let q = &c.quantity;
        let series = Series {
            label: names.of(&c.name, cols),
            y: c.values.iter().map(|v| q.to_display(*v)).collect(),
            dashed: c.name.ends_with("_ref")
                || c.name.contains("_ref_")
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
    if let Some((state, q, floor)) = names.floor {
        if let Some((_, p)) = out.iter_mut().find(|(name, _)| *name == state) {
            let n = p.t.len();
            p.series.push(Series::dashed(
                format!("{state} floor"),
                vec![q.to_display(floor); n],
            ));
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

/// An adaptive controller's identifier error energy 1/2 (y^ - y)^2 for each `<y>_model`
/// column (display units): the measurable part of its laws' Lyapunov function, one panel
/// each.
fn error_energy(name: &str, cols: &[PlantColumn]) -> Vec<TimePlot> {
    let mut out = Vec::new();
    for m in cols {
        let Some(y) = m
            .name
            .strip_suffix("_model")
            .and_then(|b| cols.iter().find(|c| c.name == b))
        else {
            continue;
        };
        let q = &y.quantity;
        let energy = m
            .values
            .iter()
            .zip(&y.values)
            .map(|(a, b)| 0.5 * (q.to_display(*a) - q.to_display(*b)).powi(2))
            .collect();
        out.push(TimePlot {
            title: format!(
                "{name}: identifier's error energy 1/2 ({0}^ - {0})^2 (Lyapunov function, measurable part)",
                y.name
            ),
            y_label: format!("[{}^2]", q.display_unit),
            t: cols[0].values.clone(),
            series: vec![Series::solid(format!("1/2 ({0}^ - {0})^2", y.name), energy)],
        });
    }
    out
}

/// What legend labels name: the loops that ran (the controller under test, its baseline
/// and second baseline, by kind and tuning) and the plant's floor.
struct Labels {
    loops: Vec<(String, Option<String>)>,
    floor: Option<(&'static str, rhonn::plant::Quantity, f64)>,
}

impl Labels {
    fn of_run(output: &PlantRunOutput) -> Self {
        let loops = output.summary.control.iter().flatten();
        Labels {
            loops: loops
                .map(|f| (f.controller.to_string(), f.tuning.map(String::from)))
                .collect(),
            floor: output.floor,
        }
    }

    /// The legend label of column `name` among `cols`, saying its role (and so getting
    /// the role's colour: see `style::colors`).
    fn of(&self, name: &str, cols: &[PlantColumn]) -> String {
        let kind = |i: usize| self.loops.get(i).map_or("", |(k, _)| k.as_str());
        let reference =
            |base: &str, role: &str| base.strip_suffix("_ref").map(|b| format!("{b} set-point{role}"));
        if let Some(rest) = name.strip_prefix("w1_ball_radius") {
            format!(
                "ball radius (bound){}",
                if rest.is_empty() { "" } else { " (baseline)" }
            )
        } else if let Some(base) = name.strip_suffix("_second_baseline") {
            reference(base, " (second baseline)").unwrap_or_else(|| match self.loops.get(2) {
                Some((k, Some(t))) => format!("{base} (second baseline: {k}, {t} tuning)"),
                _ => format!("{base} (second baseline: {})", kind(2)),
            })
        } else if let Some(base) = name.strip_suffix("_baseline") {
            reference(base, " (baseline)").unwrap_or_else(|| format!("{base} ({} baseline)", kind(1)))
        } else if let Some(r) = reference(name, "") {
            r
        } else if let Some(base) = name.strip_suffix("_hat_series_parallel") {
            format!("{base} series-parallel (frozen)")
        } else if let Some(base) = name.strip_suffix("_hat_parallel") {
            format!("{base} free run (frozen)")
        } else if let Some(base) = name.strip_suffix("_hat") {
            format!("{base} estimated")
        } else if cols.iter().any(|c| c.name == format!("{name}_baseline")) {
            // The controller under test's column beside its baseline's.
            format!("{name} ({})", kind(0))
        } else {
            name.to_string()
        }
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
    let names = Labels::of_run(output);
    let mut plots = vec![
        (
            "states.svg",
            TimePlot::render(
                &panels(name, &output.trajectory, &names, |c| {
                    !is_in(c) && !is_weight(c) && !is_measured(c)
                }),
                900,
                380,
            ),
        ),
        (
            "inputs.svg",
            TimePlot::render(&panels(name, &output.trajectory, &names, is_in), 900, 380),
        ),
    ];
    let errors = estimation_errors(&output.trajectory);
    if errors.len() > 1 {
        let title = format!("{name}: the online estimate's error");
        plots.push((
            "errors.svg",
            TimePlot::render(
                &panels(
                    &title,
                    &errors,
                    &Labels {
                        floor: None,
                        ..Labels::of_run(output)
                    },
                    |_| true,
                ),
                900,
                380,
            ),
        ));
    }
    if output.trajectory.iter().any(is_weight) {
        let mut weights = panels(name, &output.trajectory, &names, is_weight);
        weights.extend(error_energy(name, &output.trajectory));
        plots.push(("weights.svg", TimePlot::render(&weights, 900, 300)));
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
            TimePlot::render(&panels(&title, v, &names, |c| !is_in(c)), 900, 380),
        ));
    }
    for (file, svg) in plots {
        set.write(file, |w| w.write_all(svg.as_bytes()))?;
    }
    set.commit()
}
