//! SVG plots against time, in display units.

use plotters::prelude::*;
use rhonn::experiment::{Summary, Trace};
use rhonn::units::*;

/// A line on a plot.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// Values (display units), one per time.
    pub y: Vec<f64>,
    /// Dashed (references, limits) or solid.
    pub dashed: bool,
}

impl Series {
    /// A solid line (a signal).
    pub fn solid(label: impl Into<String>, y: Vec<f64>) -> Self {
        Series {
            label: label.into(),
            y,
            dashed: false,
        }
    }

    /// A dashed line (a reference or a limit).
    pub fn dashed(label: impl Into<String>, y: Vec<f64>) -> Self {
        Series {
            label: label.into(),
            y,
            dashed: true,
        }
    }
}

/// One panel: series against a shared time axis.
#[derive(Debug, Clone)]
pub struct TimePlot {
    /// Caption.
    pub title: String,
    /// Y axis label, with unit.
    pub y_label: String,
    /// Times \[s\].
    pub t: Vec<f64>,
    /// Lines.
    pub series: Vec<Series>,
}

use crate::style::{colors, legend_corner, legend_mark};

/// The first colour of the palette (histograms).
const FIRST: RGBColor = RGBColor(31, 119, 180);

/// Keep at most about `2 * buckets` points, the minimum and maximum of each bucket,
/// so that spikes survive.
fn decimate(t: &[f64], y: &[f64], buckets: usize) -> Vec<(f64, f64)> {
    let n = t.len().min(y.len());
    if n <= 2 * buckets {
        return t.iter().copied().zip(y.iter().copied()).collect();
    }
    let per = n.div_ceil(buckets);
    let mut out = Vec::with_capacity(2 * buckets + 1);
    for start in (0..n).step_by(per) {
        let end = (start + per).min(n);
        let (mut imin, mut imax) = (start, start);
        for k in start..end {
            if y[k] < y[imin] {
                imin = k;
            }
            if y[k] > y[imax] {
                imax = k;
            }
        }
        let (a, b) = if imin <= imax { (imin, imax) } else { (imax, imin) };
        out.push((t[a], y[a]));
        if b != a {
            out.push((t[b], y[b]));
        }
    }
    out
}

type TimeChart<'a, DB> = ChartContext<
    'a,
    DB,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// An axis range plotters can lay out. Its tick search loops for ever on a range that is
/// not finite or whose span overflows (a value of 1.7e308 in a recording did), so an axis
/// stays within +-1e300 and spans at least 1e-9 of its magnitude; an ordinary range
/// comes back unchanged.
pub(crate) fn safe_axis((lo, hi): (f64, f64)) -> (f64, f64) {
    const LIMIT: f64 = 1e300;
    let clamp = |v: f64| if v.is_nan() { 0.0 } else { v.clamp(-LIMIT, LIMIT) };
    let (a, b) = (clamp(lo), clamp(hi));
    let (lo, hi) = (a.min(b), a.max(b));
    let min_span = 1e-9 * lo.abs().max(hi.abs()).max(1e-290);
    if hi - lo < min_span {
        (lo - min_span, hi + min_span)
    } else {
        (lo, hi)
    }
}

/// A captioned chart of time [s] against `y_label` on `[t0, t1] x [lo, hi]`, with its mesh.
fn time_chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    y_label: &str,
    (t0, t1): (f64, f64),
    (lo, hi): (f64, f64),
) -> Result<TimeChart<'a, DB>, String>
where
    DB::ErrorType: 'static,
{
    let (t0, t1) = safe_axis((t0, t1));
    let (lo, hi) = safe_axis((lo, hi));
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(t0..t1, lo..hi)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc("time [s]")
        .y_desc(y_label)
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(|e| e.to_string())?;
    Ok(chart)
}

/// The legend box, in the corner where it hides the fewest of `points` (data
/// coordinates) of a plot on `[t0, t1] x [lo, hi]`, for `labels`.
fn draw_legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut TimeChart<'a, DB>,
    points: &[(f64, f64)],
    (t0, t1): (f64, f64),
    (lo, hi): (f64, f64),
    labels: &[&str],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let (w_px, h_px) = chart.plotting_area().dim_in_pixel();
    let chars = labels.iter().map(|l| l.chars().count()).max().unwrap_or(0);
    // The box plotters draws: a 20 px mark and text of about 7 px per character, a row
    // of about 20 px per label, plus margins.
    let box_w = ((40.0 + 7.0 * chars as f64) / w_px.max(1) as f64).min(1.0);
    let box_h = ((10.0 + 20.0 * labels.len() as f64) / h_px.max(1) as f64).min(1.0);
    let frac: Vec<(f64, f64)> = points
        .iter()
        .map(|(t, y)| ((t - t0) / (t1 - t0), (y - lo) / (hi - lo)))
        .collect();
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.85))
        .position(legend_corner(&frac, box_w, box_h))
        .draw()
        .map_err(|e| e.to_string())
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    p: &TimePlot,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let t0 = p.t.first().copied().unwrap_or(0.0);
    let t1 = p.t.last().copied().unwrap_or(1.0).max(t0 + 1e-9);
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for s in &p.series {
        for &v in &s.y {
            if v.is_finite() {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
    }
    if !lo.is_finite() {
        (lo, hi) = (0.0, 1.0);
    }
    let pad = ((hi - lo) * 0.05).max(1e-9 * hi.abs().max(1.0));
    let (lo, hi) = safe_axis((lo - pad, hi + pad));
    let (t0, t1) = safe_axis((t0, t1));
    let mut chart = time_chart(area, &p.title, &p.y_label, (t0, t1), (lo, hi))?;
    let labels: Vec<&str> = p.series.iter().map(|s| s.label.as_str()).collect();
    let mut all_points = Vec::new();
    // Dashed lines (set-points, references, limits) are drawn over the solid ones, so
    // that a trace that follows its set-point does not hide it; colours stay by label.
    let colored: Vec<_> = p.series.iter().zip(colors(labels.iter().copied())).collect();
    let solid_first = colored
        .iter()
        .filter(|(s, _)| !s.dashed)
        .chain(colored.iter().filter(|(s, _)| s.dashed));
    for &(s, color) in solid_first {
        // Points beyond a clamped axis (+-1e300) are drawn on its edge: plotters' pixel
        // arithmetic overflows on them (a panic in a debug build, a line drawn elsewhere
        // in a release one). Within the axes, as every ordinary point is, nothing moves.
        let in_box = |(t, y): (f64, f64)| (t.clamp(t0, t1), if y.is_finite() { y.clamp(lo, hi) } else { y });
        let pts: Vec<(f64, f64)> = decimate(&p.t, &s.y, 2000).into_iter().map(in_box).collect();
        all_points.extend(pts.iter().copied().filter(|(_, y)| y.is_finite()));
        let width = if s.dashed { 1 } else { 2 };
        let style = ShapeStyle {
            color: color.to_rgba(),
            filled: false,
            stroke_width: width,
        };
        let anno = if s.dashed {
            chart
                .draw_series(DashedLineSeries::new(pts, 6, 4, style))
                .map_err(|e| e.to_string())?
        } else {
            chart
                .draw_series(LineSeries::new(pts, style))
                .map_err(|e| e.to_string())?
        };
        anno.label(s.label.as_str())
            .legend(legend_mark!(color, s.dashed, width));
    }
    draw_legend(&mut chart, &all_points, (t0, t1), (lo, hi), &labels)
}

impl TimePlot {
    /// Render panels stacked vertically into one SVG document.
    pub fn render(panels: &[TimePlot], width: u32, panel_height: u32) -> String {
        let mut svg = String::new();
        {
            let h = panel_height * panels.len().max(1) as u32;
            let root = SVGBackend::with_string(&mut svg, (width, h)).into_drawing_area();
            root.fill(&WHITE).expect("filling an SVG string");
            let areas = root.split_evenly((panels.len().max(1), 1));
            for (area, p) in areas.iter().zip(panels) {
                // Drawing into a String cannot fail for I/O reasons; a layout error
                // (e.g. a degenerate range) leaves that panel blank.
                let _ = draw_panel(area, p);
            }
            root.present().expect("presenting an SVG string");
        }
        svg
    }
}

/// A histogram panel: how many values fall in each of `bins` equal bins.
#[derive(Debug, Clone)]
pub struct Histogram {
    /// Caption.
    pub title: String,
    /// X axis label, with unit.
    pub x_label: String,
    /// The values (non-finite ones are left out).
    pub values: Vec<f64>,
}

/// Bin edges and counts of `values` over `bins` equal bins spanning their range.
pub fn bin_counts(values: &[f64], bins: usize) -> (f64, f64, Vec<usize>) {
    let v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if v.is_empty() {
        return (0.0, 1.0, vec![0; bins]);
    }
    let hi = if hi > lo {
        hi
    } else {
        lo + 1e-9_f64.max(lo.abs() * 1e-9)
    };
    let mut counts = vec![0; bins];
    for x in v {
        let k = (((x - lo) / (hi - lo)) * bins as f64) as usize;
        counts[k.min(bins - 1)] += 1;
    }
    (lo, hi, counts)
}

fn draw_histogram<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    h: &Histogram,
    bins: usize,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let (lo, hi, counts) = bin_counts(&h.values, bins);
    let (lo, hi) = safe_axis((lo, hi));
    let top = counts.iter().copied().max().unwrap_or(1).max(1) as f64 * 1.05;
    let mut chart = ChartBuilder::on(area)
        .caption(&h.title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(lo..hi, 0.0..top)
        .map_err(|e| e.to_string())?;
    // Few ticks with significant digits (long fixed-decimal labels ran into each other),
    // whole counts on the count axis.
    let x_fmt = |v: &f64| rhonn::metrics::sig(*v, 3);
    let y_fmt = |v: &f64| format!("{v:.0}");
    chart
        .configure_mesh()
        .x_desc(axis_with_unit(&h.x_label))
        .y_desc("number of runs")
        .x_labels(5)
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(|e| e.to_string())?;
    let w = (hi - lo) / bins as f64;
    chart
        .draw_series(counts.iter().enumerate().map(|(k, &c)| {
            let x0 = lo + k as f64 * w;
            Rectangle::new([(x0, 0.0), (x0 + w, c as f64)], FIRST.mix(0.7).filled())
        }))
        .map_err(|e| e.to_string())?;
    Ok(())
}

/// A figure's name with the unit its suffix names, for an axis: `iae_mpa_s` reads
/// `iae_mpa_s [MPa s]`; a name without a known suffix stays as it is.
pub(crate) fn axis_with_unit(name: &str) -> String {
    const UNITS: [(&str, &str); 9] = [
        ("_mpa2_s", "MPa^2 s"),
        ("_mpa_s", "MPa s"),
        ("_mpa", "MPa"),
        ("_mm", "mm"),
        ("_percent", "%"),
        ("_a", "A"),
        ("_ms", "ms"),
        ("_s", "s"),
        ("_v", "V"),
    ];
    match UNITS.iter().find(|(suffix, _)| name.ends_with(suffix)) {
        Some((_, unit)) => format!("{name} [{unit}]"),
        None => name.to_string(),
    }
}

impl Histogram {
    /// Render panels in a grid of `cols` columns into one SVG document.
    pub fn render(panels: &[Histogram], cols: usize, bins: usize) -> String {
        let cols = cols.max(1);
        let rows = panels.len().div_ceil(cols).max(1);
        let mut svg = String::new();
        {
            let root =
                SVGBackend::with_string(&mut svg, (450 * cols as u32, 300 * rows as u32)).into_drawing_area();
            root.fill(&WHITE).expect("filling an SVG string");
            let areas = root.split_evenly((rows, cols));
            for (area, h) in areas.iter().zip(panels) {
                // As for time plots: a layout error leaves that panel blank.
                let _ = draw_histogram(area, h, bins);
            }
            root.present().expect("presenting an SVG string");
        }
        svg
    }
}

/// One quantity's spread over a campaign's runs.
#[derive(Debug, Clone)]
pub struct Band {
    /// Legend label of the median.
    pub label: String,
    /// Per-point quantiles (display units).
    pub envelope: rhonn::experiment::campaign::Envelope,
}

/// An envelope plot: for each band, min to max shaded lightly, 5 % to 95 % darker, the
/// median as a line; dashed reference lines on top.
#[derive(Debug, Clone)]
pub struct EnvelopePlot {
    /// Caption.
    pub title: String,
    /// Y axis label, with unit.
    pub y_label: String,
    /// Times \[s\].
    pub t: Vec<f64>,
    /// Bands.
    pub bands: Vec<Band>,
    /// Dashed lines (set-point, limits).
    pub lines: Vec<Series>,
}

fn draw_envelope<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    p: &EnvelopePlot,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let t0 = p.t.first().copied().unwrap_or(0.0);
    let t1 = p.t.last().copied().unwrap_or(1.0).max(t0 + 1e-9);
    let finite = |v: &[f64]| v.iter().copied().filter(|x| x.is_finite()).collect::<Vec<_>>();
    let mut all: Vec<f64> = Vec::new();
    for b in &p.bands {
        all.extend(finite(&b.envelope.min));
        all.extend(finite(&b.envelope.max));
    }
    for s in &p.lines {
        all.extend(finite(&s.y));
    }
    let lo = all.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = all.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = if lo.is_finite() { (lo, hi) } else { (0.0, 1.0) };
    let pad = ((hi - lo) * 0.05).max(1e-9 * hi.abs().max(1.0));
    let (t0, t1) = safe_axis((t0, t1));
    let (lo, hi) = safe_axis((lo - pad, hi + pad));
    let (pad, lo, hi) = (0.0, lo, hi);
    let mut chart = time_chart(area, &p.title, &p.y_label, (t0, t1), (lo - pad, hi + pad))?;
    let area_of = |lower: &[f64], upper: &[f64]| {
        let mut pts: Vec<(f64, f64)> = p.t.iter().copied().zip(upper.iter().copied()).collect();
        pts.extend(p.t.iter().copied().zip(lower.iter().copied()).rev());
        pts.retain(|(_, y)| y.is_finite());
        pts
    };
    let band_labels: Vec<&str> = p.bands.iter().map(|b| b.label.as_str()).collect();
    let band_colors = colors(band_labels.iter().copied());
    let line_labels: Vec<&str> = p.lines.iter().map(|s| s.label.as_str()).collect();
    let line_colors = colors(line_labels.iter().copied());
    for (b, &color) in p.bands.iter().zip(&band_colors) {
        let e = &b.envelope;
        chart
            .draw_series(std::iter::once(Polygon::new(
                area_of(&e.min, &e.max),
                color.mix(0.15).filled(),
            )))
            .map_err(|e| e.to_string())?;
        chart
            .draw_series(std::iter::once(Polygon::new(
                area_of(&e.q05, &e.q95),
                color.mix(0.3).filled(),
            )))
            .map_err(|e| e.to_string())?;
    }
    let mut all_points = Vec::new();
    let mut legend_labels = Vec::new();
    for (b, &color) in p.bands.iter().zip(&band_colors) {
        all_points.extend(p.t.iter().copied().zip(b.envelope.max.iter().copied()));
        all_points.extend(p.t.iter().copied().zip(b.envelope.min.iter().copied()));
        let label = format!("{} (median; 5-95 %, min-max shaded)", b.label);
        legend_labels.push(label.clone());
        let pts: Vec<(f64, f64)> =
            p.t.iter()
                .copied()
                .zip(b.envelope.median.iter().copied())
                .collect();
        chart
            .draw_series(LineSeries::new(pts, color.stroke_width(2)))
            .map_err(|e| e.to_string())?
            .label(label)
            .legend(legend_mark!(color, false, 2));
    }
    for (s, &color) in p.lines.iter().zip(&line_colors) {
        let pts: Vec<(f64, f64)> = p.t.iter().copied().zip(s.y.iter().copied()).collect();
        all_points.extend(pts.iter().copied());
        legend_labels.push(s.label.clone());
        chart
            .draw_series(DashedLineSeries::new(pts, 6, 4, color.stroke_width(1)))
            .map_err(|e| e.to_string())?
            .label(s.label.as_str())
            .legend(legend_mark!(color, true, 1));
    }
    all_points.retain(|(_, y)| y.is_finite());
    let labels: Vec<&str> = legend_labels.iter().map(String::as_str).collect();
    draw_legend(&mut chart, &all_points, (t0, t1), (lo - pad, hi + pad), &labels)
}

impl EnvelopePlot {
    /// Render into one SVG document.
    pub fn render(&self, width: u32, height: u32) -> String {
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
            root.fill(&WHITE).expect("filling an SVG string");
            // As for time plots: a layout error leaves the plot blank.
            let _ = draw_envelope(&root, self);
            root.present().expect("presenting an SVG string");
        }
        svg
    }
}

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

#[cfg(test)]
#[path = "plot_tests.rs"]
mod tests;
