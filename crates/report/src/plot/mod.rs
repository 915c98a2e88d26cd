//! SVG plots in display units, one file per kind: against time (here: `Series`,
//! `TimePlot`; what a run draws is `plant_report.rs`'s), `histogram.rs`, `envelope.rs` (a
//! campaign's spread).

mod envelope;
mod histogram;

pub use envelope::{Band, EnvelopePlot};
pub use histogram::{bin_counts, Histogram};

use plotters::prelude::*;

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

#[cfg(test)]
mod tests;
