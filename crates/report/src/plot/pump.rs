//! The pump's run and identification figures: pressure and stroke against their
//! set-points and bounds, the adaptive controller's weights, the identifier's estimates.

use super::{Series, TimePlot};
use rhonn::experiment::{Summary, Trace};
use rhonn::units::*;

/// The adaptive controller's weights against their bounds and its identifier's error
/// energy, one panel each (none for other runs): |W| (projected onto a ball of radius
/// `w_bound`, far off this scale), |W_1|, |W_1 - centre| against the ball's radius (the
/// projection keeps it inside; the centre moves to the identified W_1 when the
/// identification phase ends), and 1/2 (p^ - p)^2, the measurable part of the
/// identifier's Lyapunov function.
fn weight_plots(trace: &Trace, name: &str, t: &[f64]) -> Vec<TimePlot> {
    let (Some(w), Some(w1)) = (trace.column("w_norm"), trace.column("w1_norm")) else {
        return Vec::new();
    };
    let panel = |title: &str, y_label: &str, series: Vec<Series>| TimePlot {
        title: format!("{name}: {title}"),
        y_label: y_label.into(),
        t: t.to_vec(),
        series,
    };
    let mut out = vec![
        panel(
            "adaptive weights, w_norm",
            "|W| (drift) [MPa/s]",
            vec![Series::solid("w_norm", w.to_vec())],
        ),
        panel(
            "adaptive weights, w1_norm",
            "|W_1| (gain) [MPa/(s mm)]",
            vec![Series::solid("w1_norm", w1.to_vec())],
        ),
    ];
    if let (Some(d), Some(r)) = (trace.column("w1_distance"), trace.column("w1_ball_radius")) {
        out.push(panel(
            "gain weights against their ball",
            "[MPa/(s mm)]",
            vec![
                Series::solid("|W_1 - centre|", d.to_vec()),
                Series::dashed("ball radius (bound)", r.to_vec()),
            ],
        ));
    }
    if let (Some(ph), Some(p)) = (trace.column("p_line_model"), trace.column("p_line")) {
        let energy = ph
            .iter()
            .zip(p)
            .map(|(a, b)| 0.5 * ((a - b) / PA_PER_MPA).powi(2))
            .collect();
        out.push(panel(
            "identifier's error energy 1/2 (p^ - p)^2 (Lyapunov function, measurable part)",
            "[MPa^2]",
            vec![Series::solid("1/2 (p^ - p)^2", energy)],
        ));
    }
    out
}

/// The stroke panel's series: the stroke (the adaptive controller's), its reference, and
/// the baselines' strokes.
fn stroke_series(
    col: &dyn Fn(&str, f64) -> Option<Vec<f64>>,
    adaptive: bool,
    base: &str,
    second: Option<&str>,
) -> Vec<Series> {
    let mut x_series = vec![Series::solid(
        if adaptive {
            "stroke (RHONN adaptive)"
        } else {
            "stroke"
        },
        col("stroke", M_PER_MM).unwrap_or_default(),
    )];
    let stroke_base = format!("stroke ({base})");
    let stroke_second = format!("stroke ({})", second.unwrap_or(""));
    for (c, label) in [
        ("stroke_ref", "stroke reference x_d"),
        ("stroke_pi", stroke_base.as_str()),
        ("stroke_pi2", stroke_second.as_str()),
    ] {
        if let Some(y) = col(c, M_PER_MM) {
            x_series.push(Series {
                label: label.into(),
                y,
                dashed: c == "stroke_ref",
            });
        }
    }
    x_series
}

/// The plots of a run: `pressure.svg` (line pressure, set-point, P_min), `stroke.svg`,
/// `inputs.svg` (current and demand); adaptive runs show the baseline beside the
/// adaptive controller in each, the stroke reference, and `weights.svg` (the adaptive
/// weights' norms). Returns `(file name, SVG)`.
pub fn plot_run(trace: &Trace, summary: &Summary) -> Vec<(String, String)> {
    let t = trace.column("t").unwrap_or(&[]).to_vec();
    let col = |name: &str, k: f64| {
        trace
            .column(name)
            .map(|v| v.iter().map(|x| x / k).collect::<Vec<_>>())
    };
    let name = summary.scenario_name();
    let p_min = summary.p_min_mpa();
    let adaptive = trace.column("p_line_pi").is_some();
    // The baseline by name: "cascade PI baseline" or "PI baseline".
    let base = match summary.control.as_ref().map(|c| c.baseline.controller) {
        Some("cascade-pi") => "cascade PI baseline",
        _ => "PI baseline",
    };
    let mut p_series = vec![Series::solid(
        if adaptive {
            "p_line (RHONN adaptive)"
        } else {
            "p_line"
        },
        col("p_line", PA_PER_MPA).unwrap_or_default(),
    )];
    if let Some(p) = col("p_line_pi", PA_PER_MPA) {
        // Drawn first, so that the adaptive controller's line lies on top.
        p_series.insert(0, Series::solid(format!("p_line ({base})"), p));
    }
    // A second baseline (a named cascade PI tuning), its own colour, drawn under the
    // adaptive controller's line.
    let second = summary
        .control
        .as_ref()
        .and_then(|c| c.second_baseline.as_ref())
        .map(|b| {
            format!(
                "second baseline: cascade PI, {} tuning",
                b.tuning.unwrap_or("other")
            )
        });
    if let (Some(label), Some(p)) = (&second, col("p_line_pi2", PA_PER_MPA)) {
        let at = p_series.len() - 1;
        p_series.insert(at, Series::solid(format!("p_line ({label})"), p));
    }
    if let Some(r) = col("p_ref", PA_PER_MPA) {
        p_series.push(Series::dashed("set-point", r));
    }
    p_series.push(Series::dashed("P_min", vec![p_min; t.len()]));
    let pressure = TimePlot {
        title: format!("{name}: line pressure"),
        y_label: "line pressure [MPa]".into(),
        t: t.clone(),
        series: p_series,
    };
    let stroke = TimePlot {
        title: format!("{name}: pump stroke"),
        y_label: "stroke [mm]".into(),
        t: t.clone(),
        series: Vec::new(),
    };
    let mut i_series = vec![Series::solid(
        if adaptive {
            "current (RHONN adaptive)"
        } else {
            "current"
        },
        col("current", 1.0).unwrap_or_default(),
    )];
    if let Some(i) = col("current_pi", 1.0) {
        i_series.push(Series::solid(format!("current ({base})"), i));
    }
    if let (Some(label), Some(i)) = (&second, col("current_pi2", 1.0)) {
        i_series.insert(0, Series::solid(format!("current ({label})"), i));
    }
    let current = TimePlot {
        title: format!("{name}: solenoid current"),
        y_label: "current [A]".into(),
        t: t.clone(),
        series: i_series,
    };
    let x_series = stroke_series(&col, adaptive, base, second.as_deref());
    let weights = weight_plots(trace, name, &t);
    let demand = TimePlot {
        title: format!("{name}: demanded flow"),
        y_label: "demand [dm^3/s]".into(),
        t,
        series: vec![Series::solid(
            "demand",
            col("demand", M3_PER_DM3).unwrap_or_default(),
        )],
    };
    let stroke = TimePlot {
        series: x_series,
        ..stroke
    };
    let mut out = vec![
        ("pressure.svg".into(), TimePlot::render(&[pressure], 900, 450)),
        ("stroke.svg".into(), TimePlot::render(&[stroke], 900, 450)),
        (
            "inputs.svg".into(),
            TimePlot::render(&[current, demand], 900, 330),
        ),
    ];
    if !weights.is_empty() {
        out.push(("weights.svg".into(), TimePlot::render(&weights, 900, 300)));
    }
    out
}

/// Plots of an identified run: `ident_errors.svg` (the two errors), `ident_states.svg`
/// (actual and identified, both states), `ident_zoom.svg` (the thesis's zooms: the
/// first 0.12 s of the pressure error and the first 1.2 s of the pressure) and
/// `validation.svg` (frozen weights, series-parallel and parallel). Empty for runs
/// without an identifier.
pub fn plot_identification(
    trace: &Trace,
    validation: Option<&Trace>,
    summary: &Summary,
) -> Vec<(String, String)> {
    let name = summary.scenario_name();
    let Some(t) = trace.column("t") else { return vec![] };
    let mut out = Vec::new();
    let mut errors = Vec::new();
    let mut states = Vec::new();
    let mut zoom = Vec::new();
    let mut val = Vec::new();
    for (col, label, unit, k) in [
        ("p_line", "line pressure", "MPa", PA_PER_MPA),
        ("stroke", "stroke", "mm", M_PER_MM),
    ] {
        let hat = format!("{col}_hat");
        let (Some(y), Some(yh)) = (trace.column(col), trace.column(&hat)) else {
            continue;
        };
        let y: Vec<f64> = y.iter().map(|v| v / k).collect();
        let yh: Vec<f64> = yh.iter().map(|v| v / k).collect();
        let e: Vec<f64> = y.iter().zip(&yh).map(|(a, b)| b - a).collect();
        // The convergence band of the training (its figures' `convergence_band`).
        let band = summary
            .identification
            .as_ref()
            .and_then(|r| r.training.iter().find(|f| f.state == col))
            .map(|f| f.convergence_band);
        let mut err_series = vec![Series::solid("error", e.clone())];
        if let Some(b) = band {
            err_series.push(Series::dashed(
                format!("convergence band +-{b:.4} {unit} (limit)"),
                vec![b; e.len()],
            ));
            err_series.push(Series::dashed("-band (limit)", vec![-b; e.len()]));
        }
        errors.push(TimePlot {
            title: format!("{name}: identification error of the {label}"),
            y_label: format!("{col}_hat - {col} [{unit}]"),
            t: t.to_vec(),
            series: err_series,
        });
        states.push(TimePlot {
            title: format!("{name}: {label}, actual and identified"),
            y_label: format!("{label} [{unit}]"),
            t: t.to_vec(),
            series: vec![
                Series::solid(col, y.clone()),
                Series::dashed(hat.clone(), yh.clone()),
            ],
        });
        if col == "p_line" {
            let n1 = t.iter().take_while(|&&v| v <= 0.12 + 1e-12).count();
            zoom.push(TimePlot {
                title: format!("{name}: pressure error, first 0.12 s"),
                y_label: "p_line_hat - p_line [MPa]".into(),
                t: t[..n1].to_vec(),
                series: vec![Series::solid("error", e[..n1].to_vec())],
            });
            let n2 = t.iter().take_while(|&&v| v <= 1.2 + 1e-12).count();
            zoom.push(TimePlot {
                title: format!("{name}: line pressure, first 1.2 s"),
                y_label: "line pressure [MPa]".into(),
                t: t[..n2].to_vec(),
                series: vec![
                    Series::solid("p_line", y[..n2].to_vec()),
                    Series::dashed("p_line_hat", yh[..n2].to_vec()),
                ],
            });
        }
        if let Some(v) = validation {
            if let (Some(vt), Some(vy), Some(sp), Some(par)) = (
                v.column("t"),
                v.column(col),
                v.column(&format!("{col}_hat_series_parallel")),
                v.column(&format!("{col}_hat_parallel")),
            ) {
                let sc = |s: &[f64]| s.iter().map(|x| x / k).collect::<Vec<_>>();
                val.push(TimePlot {
                    title: format!("{name}: {label}, frozen weights"),
                    y_label: format!("{label} [{unit}]"),
                    t: vt.to_vec(),
                    series: vec![
                        Series::solid(col, sc(vy)),
                        Series::dashed("series-parallel", sc(sp)),
                        Series::dashed("parallel (free run)", sc(par)),
                    ],
                });
            }
        }
    }
    if errors.is_empty() {
        return out;
    }
    out.push(("ident_errors.svg".into(), TimePlot::render(&errors, 900, 330)));
    out.push(("ident_states.svg".into(), TimePlot::render(&states, 900, 330)));
    out.push(("ident_zoom.svg".into(), TimePlot::render(&zoom, 900, 330)));
    if !val.is_empty() {
        out.push(("validation.svg".into(), TimePlot::render(&val, 900, 330)));
    }
    out
}
