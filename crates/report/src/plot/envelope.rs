//! Envelope plots: a quantity's spread over a campaign's runs against time.

use super::{draw_legend, safe_axis, time_chart, Series};
use crate::style::{colors, legend_mark};
use plotters::prelude::*;

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
