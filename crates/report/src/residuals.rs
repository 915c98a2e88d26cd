//! Residual analysis of a prediction, as MATLAB's `resid`: the autocorrelation of each
//! output's residuals and the cross-correlation of each input with them, against the
//! 99 % confidence band of white noise (+-2.576 / sqrt(N)). A model that has caught the
//! dynamics leaves residuals inside the band at every lag but 0.

use plotters::prelude::*;

/// Largest lag drawn \[samples\].
pub const MAX_LAG: usize = 25;

/// The 99 % band of the correlation of N samples of white noise.
pub fn band_99(n: usize) -> f64 {
    2.576 / (n.max(1) as f64).sqrt()
}

/// Normalised autocorrelation of `e` at lags 0..=max_lag (lag 0 is 1).
pub fn autocorrelation(e: &[f64], max_lag: usize) -> Vec<f64> {
    let n = e.len();
    let mean = e.iter().sum::<f64>() / n.max(1) as f64;
    let d: Vec<f64> = e.iter().map(|v| v - mean).collect();
    let var: f64 = d.iter().map(|v| v * v).sum();
    (0..=max_lag.min(n.saturating_sub(1)))
        .map(|k| {
            if var > 0.0 {
                d[..n - k].iter().zip(&d[k..]).map(|(a, b)| a * b).sum::<f64>() / var
            } else {
                0.0
            }
        })
        .collect()
}

/// Normalised cross-correlation of `u` with `e` at lags -max_lag..=max_lag (`u` leading
/// `e` at positive lags).
pub fn cross_correlation(u: &[f64], e: &[f64], max_lag: usize) -> Vec<(i64, f64)> {
    let n = u.len().min(e.len());
    let centred = |x: &[f64]| {
        let m = x[..n].iter().sum::<f64>() / n.max(1) as f64;
        x[..n].iter().map(|v| v - m).collect::<Vec<f64>>()
    };
    let (du, de) = (centred(u), centred(e));
    let norm = (du.iter().map(|v| v * v).sum::<f64>() * de.iter().map(|v| v * v).sum::<f64>()).sqrt();
    let lag = max_lag.min(n.saturating_sub(1)) as i64;
    (-lag..=lag)
        .map(|k| {
            let s: f64 = (0..n as i64)
                .filter_map(|t| {
                    let j = t + k;
                    (j >= 0 && j < n as i64).then(|| du[t as usize] * de[j as usize])
                })
                .sum();
            (k, if norm > 0.0 { s / norm } else { 0.0 })
        })
        .collect()
}

/// One panel: stems at each lag, the band dashed.
fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    points: &[(i64, f64)],
    band: f64,
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let lo = points.iter().map(|p| p.1).fold(-band, f64::min).min(-0.2) * 1.1;
    let hi = points.iter().map(|p| p.1).fold(band, f64::max).max(0.2) * 1.1;
    let (k0, k1) = (
        points.first().map_or(0, |p| p.0) as f64 - 0.5,
        points.last().map_or(1, |p| p.0) as f64 + 0.5,
    );
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(36)
        .y_label_area_size(56)
        .build_cartesian_2d(k0..k1, lo..hi)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .x_desc("lag [samples]")
        .y_desc("correlation [-]")
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(|e| e.to_string())?;
    let blue = RGBColor(31, 119, 180);
    chart
        .draw_series(
            points
                .iter()
                .map(|&(k, v)| PathElement::new(vec![(k as f64, 0.0), (k as f64, v)], blue.stroke_width(2))),
        )
        .map_err(|e| e.to_string())?
        .label("correlation")
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], blue.stroke_width(2)));
    let red = RGBColor(214, 39, 40);
    for (j, b) in [band, -band].into_iter().enumerate() {
        let s = chart
            .draw_series(DashedLineSeries::new(
                vec![(k0, b), (k1, b)],
                6,
                4,
                red.stroke_width(1),
            ))
            .map_err(|e| e.to_string())?;
        if j == 0 {
            s.label("99 % band of white noise")
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], red.stroke_width(1)));
        }
    }
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.85))
        // Where the stems leave room: below the axis when they mostly point up.
        .position(if points.iter().map(|p| p.1).sum::<f64>() > 0.0 {
            SeriesLabelPosition::LowerRight
        } else {
            SeriesLabelPosition::UpperRight
        })
        .draw()
        .map_err(|e| e.to_string())
}

/// A panel: title, (lag, correlation) points, the band's half-width.
type Panel = (String, Vec<(i64, f64)>, f64);

/// `residuals.svg`: per output, the residuals' autocorrelation, then per input (at most
/// three) their cross-correlation with the input; residuals from sample `first` on.
pub fn plot_residuals(
    record: &rhonn::data::Record,
    predicted: &[Vec<f64>],
    first: usize,
    inputs: &[String],
    outputs: &[String],
) -> String {
    let mut panels: Vec<Panel> = Vec::new();
    for (j, name) in outputs.iter().enumerate() {
        let e: Vec<f64> = record.outputs[j]
            .iter()
            .zip(&predicted[j])
            .skip(first)
            .map(|(y, yh)| y - yh)
            .collect();
        let band = band_99(e.len());
        let acf = autocorrelation(&e, MAX_LAG)
            .into_iter()
            .enumerate()
            .map(|(k, v)| (k as i64, v))
            .collect();
        panels.push((format!("{name}: autocorrelation of the residuals"), acf, band));
        for (i, u) in inputs.iter().enumerate().take(3) {
            let ccf = cross_correlation(&record.inputs[i][first.min(record.len())..], &e, MAX_LAG);
            panels.push((
                format!("{name}: cross-correlation of input {u} and the residuals"),
                ccf,
                band,
            ));
        }
    }
    let mut svg = String::new();
    {
        let height = 300 * panels.len().max(1) as u32;
        let root = SVGBackend::with_string(&mut svg, (900, height)).into_drawing_area();
        let _ = root.fill(&WHITE);
        for (area, (title, pts, band)) in root.split_evenly((panels.len().max(1), 1)).iter().zip(&panels) {
            if let Err(e) = panel(area, title, pts, *band) {
                let _ = area.draw(&Text::new(
                    format!("cannot draw: {e}"),
                    (10, 10),
                    ("sans-serif", 14),
                ));
            }
        }
        let _ = root.present();
    }
    svg
}

/// `residual_histogram.svg`: the distribution of each output's residuals (from sample
/// `first` on).
pub fn residual_histograms(
    record: &rhonn::data::Record,
    predicted: &[Vec<f64>],
    first: usize,
    outputs: &[String],
) -> String {
    let panels: Vec<crate::Histogram> = outputs
        .iter()
        .enumerate()
        .map(|(j, name)| {
            let residuals: Vec<f64> = record.outputs[j]
                .iter()
                .zip(&predicted[j])
                .skip(first)
                .map(|(y, yh)| y - yh)
                .collect();
            crate::Histogram::new(
                format!("{name}: residuals (measured - predicted)"),
                format!("{name} - {name}_hat"),
                &residuals,
                40,
            )
        })
        .collect();
    crate::Histogram::render(&panels, 2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_noise_stays_in_the_band_and_a_delayed_copy_shows_at_its_lag() {
        // A deterministic pseudo-random sequence (LCG), centred.
        let mut x = 12345u64;
        let e: Vec<f64> = (0..4000)
            .map(|_| {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            })
            .collect();
        let acf = autocorrelation(&e, 25);
        assert!((acf[0] - 1.0).abs() < 1e-12);
        let band = band_99(e.len());
        assert!(acf[1..].iter().filter(|v| v.abs() > band).count() <= 2, "{acf:?}");
        // u leads e by 3 samples: the cross-correlation peaks at lag +3.
        let u: Vec<f64> = (0..4000)
            .map(|t| if t + 3 < 4000 { e[t + 3] } else { 0.0 })
            .collect();
        let ccf = cross_correlation(&e, &u, 10);
        let peak = ccf.iter().max_by(|a, b| a.1.total_cmp(&b.1)).unwrap();
        assert_eq!(peak.0, -3, "{ccf:?}");
        assert!(peak.1 > 0.9);
    }
}
