//! Histograms: how many values fall in each of equal bins.

use super::{safe_axis, FIRST};
use plotters::prelude::*;

/// A histogram panel: how many values fall in each of its equal bins (the values
/// themselves are not kept: a campaign's panels are made one figure at a time).
#[derive(Debug, Clone)]
pub struct Histogram {
    /// Caption.
    pub title: String,
    /// X axis label, with unit.
    pub x_label: String,
    /// The bins' span `(lo, hi)` and their counts ([`bin_counts`]).
    pub bins: (f64, f64, Vec<usize>),
}

impl Histogram {
    /// The panel of `values` (non-finite ones are left out) over `bins` equal bins.
    pub fn new(title: impl Into<String>, x_label: impl Into<String>, values: &[f64], bins: usize) -> Self {
        Histogram {
            title: title.into(),
            x_label: x_label.into(),
            bins: bin_counts(values, bins),
        }
    }
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
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let (lo, hi, counts) = (h.bins.0, h.bins.1, &h.bins.2);
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
    let w = (hi - lo) / counts.len().max(1) as f64;
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
    const UNITS: [(&str, &str); 11] = [
        ("_mpa2_s", "MPa^2 s"),
        ("_mm2_s", "mm^2 s"),
        ("_mm_s", "mm s"),
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
    pub fn render(panels: &[Histogram], cols: usize) -> String {
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
                let _ = draw_histogram(area, h);
            }
            root.present().expect("presenting an SVG string");
        }
        svg
    }
}
