//! `rhonn bench --out DIR`: the timing table as `summary.json`, `bench.svg` (bars of the
//! median time of one run and of the runs per second on every core, and with
//! `--compare FILE` the figures of another tool measured beside rhonn, such as
//! `bench/scipy_ch5.py --json FILE` writes) and `report.html`.

use crate::{OutputSet, Result};
use plotters::prelude::*;
use rhonn::experiment::BenchFigures;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// One measurement of a comparison file: a tool's median time of one run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Compared {
    /// What was run (e.g. "thesis-ch5 training").
    pub run: String,
    /// Which tool ("scipy solve_ivp(RK45)", "rhonn").
    pub tool: String,
    /// Median (or best) wall time of one run \[s\].
    pub median_s: f64,
    /// Right-hand-side evaluations of one run, when counted.
    pub rhs_evaluations: Option<u64>,
}

/// Read a comparison file (a JSON list of [`Compared`]); errors name the file.
pub fn read_compared(path: &Path) -> Result<Vec<Compared>> {
    let text = rhonn::error::read_text(path).map_err(|e| crate::Error::File {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let v: Vec<Compared> = serde_json::from_str(&text).map_err(|e| {
        crate::Error::Input(format!(
            "{}: not a comparison file ({e}): give a JSON list of {{\"run\", \"tool\", \"median_s\", \"rhs_evaluations\"}} as `bench/scipy_ch5.py --json FILE` writes",
            path.display()
        ))
    })?;
    if let Some(c) = v.iter().find(|c| !(c.median_s.is_finite() && c.median_s > 0.0)) {
        return Err(crate::Error::Input(format!(
            "{}: median_s = {} for {} ({}) is not allowed: a time > 0 s",
            path.display(),
            c.median_s,
            c.run,
            c.tool
        )));
    }
    Ok(v)
}

/// `rhonn bench`'s `summary.json`.
#[derive(Serialize, schemars::JsonSchema)]
struct BenchSummary<'a> {
    /// rhonn's version.
    rhonn_version: &'static str,
    /// Each scenario's timing.
    bench: &'a [BenchFigures],
    /// The same scenarios timed by other tools (`--compare`), beside rhonn's.
    compared: &'a [Compared],
    /// What the figures say, in words.
    findings: Vec<String>,
}

/// The schema of `summary.json` (`fields`).
pub(crate) fn schema() -> serde_json::Value {
    schemars::schema_for!(BenchSummary<'static>).to_value()
}

/// Write `summary.json`, `bench.svg` and `report.html` into `dir`.
pub fn write_bench(dir: &Path, figures: &[BenchFigures], compared: &[Compared]) -> Result<Vec<PathBuf>> {
    let mut findings: Vec<String> = figures
        .iter()
        .map(|b| {
            format!(
                "{}: {:.3} ms per run on one core, {:.0} runs/s on {} threads",
                b.scenario,
                b.median_s * 1e3,
                b.runs_per_s_all_cores,
                b.threads
            )
        })
        .collect();
    let mut runs: Vec<&str> = compared.iter().map(|c| c.run.as_str()).collect();
    runs.dedup();
    for run in runs {
        let of = |tool: &str| compared.iter().find(|c| c.run == run && c.tool.starts_with(tool));
        if let (Some(r), Some(o)) = (
            of("rhonn"),
            compared
                .iter()
                .find(|c| c.run == run && !c.tool.starts_with("rhonn")),
        ) {
            findings.push(format!(
                "{run}: {} {:.3} ms, rhonn {:.3} ms: {:.0}x (measured side by side, from the comparison file)",
                o.tool,
                o.median_s * 1e3,
                r.median_s * 1e3,
                o.median_s / r.median_s
            ));
        }
    }
    let summary = BenchSummary {
        rhonn_version: env!("CARGO_PKG_VERSION"),
        bench: figures,
        compared,
        findings,
    };
    let svg = bars(figures, compared);
    let mut set = OutputSet::new(dir)?;
    set.write("summary.json", |w| crate::write_json(w, &summary))?;
    set.write("bench.svg", |w| w.write_all(svg.as_bytes()))?;
    let files = set.commit()?;
    Ok(files)
}

/// A bar: its label, value and colour.
type Bar = (String, f64, RGBColor);

/// A horizontal bar panel: labels and values, the axis label with its unit.
fn bar_panel(
    area: &DrawingArea<SVGBackend, plotters::coord::Shift>,
    title: &str,
    x_label: &str,
    bars: &[Bar],
) -> std::result::Result<(), Box<dyn std::error::Error>> {
    // Room on the right of the longest bar for its label.
    let max = bars.iter().map(|b| b.1).fold(0.0, f64::max).max(1e-12) * 1.6;
    let n = bars.len().max(1);
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(10)
        .build_cartesian_2d(0.0..max, 0.0..n as f64)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .x_label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .y_labels(0)
        .disable_y_mesh()
        .draw()?;
    for (i, (label, v, color)) in bars.iter().enumerate() {
        let y = (n - 1 - i) as f64;
        chart.draw_series(std::iter::once(Rectangle::new(
            [(0.0, y + 0.2), (*v, y + 0.8)],
            color.filled(),
        )))?;
        let value = if *v >= 100.0 {
            format!("{v:.0}")
        } else {
            format!("{v:.3}")
        };
        chart.draw_series(std::iter::once(Text::new(
            format!("  {label}: {value}"),
            (*v, y + 0.62),
            ("sans-serif", 13),
        )))?;
    }
    Ok(())
}

/// `bench.svg`.
fn bars(figures: &[BenchFigures], compared: &[Compared]) -> String {
    let blue = crate::style::colors(["rhonn"])[0];
    let mut panels: Vec<(String, String, Vec<Bar>)> = vec![
        (
            "rhonn bench: one run on one core (median)".into(),
            "time per run [ms]".into(),
            figures
                .iter()
                .map(|b| (b.scenario.clone(), b.median_s * 1e3, blue))
                .collect(),
        ),
        (
            "rhonn bench: runs per second on every core".into(),
            "runs per second".into(),
            figures
                .iter()
                .map(|b| {
                    (
                        format!("{} ({} threads)", b.scenario, b.threads),
                        b.runs_per_s_all_cores,
                        blue,
                    )
                })
                .collect(),
        ),
    ];
    if !compared.is_empty() {
        let one_run = compared.iter().all(|c| c.run == compared[0].run);
        let title = if one_run {
            format!("measured side by side: {}", compared[0].run)
        } else {
            "measured side by side (comparison file)".into()
        };
        panels.push((
            title,
            "time per run [ms]".into(),
            compared
                .iter()
                .map(|c| {
                    let color = if c.tool.starts_with("rhonn") {
                        blue
                    } else {
                        crate::style::BASELINE
                    };
                    let label = if one_run {
                        c.tool.clone()
                    } else {
                        format!("{}: {}", c.run, c.tool)
                    };
                    (label, c.median_s * 1e3, color)
                })
                .collect(),
        ));
    }
    let mut svg = String::new();
    {
        let heights: Vec<u32> = panels.iter().map(|p| 90 + 34 * p.2.len() as u32).collect();
        let root = SVGBackend::with_string(&mut svg, (900, heights.iter().sum())).into_drawing_area();
        let _ = root.fill(&WHITE);
        let mut rest = root;
        for (p, h) in panels.iter().zip(&heights) {
            let (top, bottom) = rest.split_vertically(*h);
            let _ = bar_panel(&top, &p.0, &p.1, &p.2);
            rest = bottom;
        }
        let _ = rest.present();
    }
    svg
}
