//! The tracking-against-activity front of the pump's controllers
//! ([`crate::front`]): `front.csv` (every setting run) and `front.svg` (IAE
//! against the current's total variation, both axes logarithmic; the cascade PI's settings
//! in the baseline's orange with their front as a line, the adaptive settings in blue, the
//! named ones labelled).

use crate::front::{pareto, FrontPoint};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use rhonn_report::style::{BASELINE, REFERENCE};
use rhonn_report::{OutputSet, Result};

use std::path::{Path, PathBuf};

const ADAPTIVE: RGBColor = RGBColor(0, 114, 178);

/// The plot: `cascade` and `adaptive` points, the cascade's front, and `named` adaptive
/// points labelled.
pub fn front_svg(cascade: &[FrontPoint], adaptive: &[FrontPoint], named: &[(String, FrontPoint)]) -> String {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 560)).into_drawing_area();
        root.fill(&WHITE).expect("filling an SVG string");
        // A layout error leaves the plot blank, as for the other plots.
        let _ = draw(&root, cascade, adaptive, named);
        root.present().expect("presenting an SVG string");
    }
    svg
}

fn draw<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    cascade: &[FrontPoint],
    adaptive: &[FrontPoint],
    named: &[(String, FrontPoint)],
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    let ok = |p: &&FrontPoint| p.iae_mpa_s.is_finite() && p.current_total_variation_a.is_finite();
    let all: Vec<&FrontPoint> = cascade.iter().chain(adaptive).filter(ok).collect();
    let span = |f: &dyn Fn(&FrontPoint) -> f64| {
        let lo = all.iter().map(|p| f(p)).fold(f64::INFINITY, f64::min).max(1e-6);
        let hi = all.iter().map(|p| f(p)).fold(0.0, f64::max).max(lo * 10.0);
        (lo / 1.3, hi * 1.3)
    };
    let (x0, x1) = span(&|p| p.current_total_variation_a);
    let (y0, y1) = span(&|p| p.iae_mpa_s);
    let mut chart = ChartBuilder::on(area)
        .caption(
            "pump, control-adaptive's nominal plant: tracking against valve activity",
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(65)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .light_line_style(WHITE)
        .x_desc("total variation of the solenoid current over the run [A]")
        .y_desc("IAE [MPa s]")
        .x_label_formatter(&|v| rhonn::metrics::sig(*v, 3).to_string())
        .y_label_formatter(&|v| rhonn::metrics::sig(*v, 3).to_string())
        .draw()
        .map_err(|e| e.to_string())?;
    let pts = |v: &[FrontPoint]| -> Vec<(f64, f64)> {
        v.iter()
            .filter(|p| ok(p))
            .map(|p| (p.current_total_variation_a, p.iae_mpa_s))
            .collect()
    };
    chart
        .draw_series(
            pts(cascade)
                .into_iter()
                .map(|p| Circle::new(p, 2, BASELINE.mix(0.5).filled())),
        )
        .map_err(|e| e.to_string())?
        .label("cascade PI baseline, one gain set each")
        .legend(|(x, y)| Circle::new((x + 8, y), 3, BASELINE.filled()));
    let front: Vec<(f64, f64)> = pareto(cascade)
        .into_iter()
        .map(|k| (cascade[k].current_total_variation_a, cascade[k].iae_mpa_s))
        .collect();
    chart
        .draw_series(LineSeries::new(front, BASELINE.stroke_width(2)))
        .map_err(|e| e.to_string())?
        .label("cascade PI baseline's front (nothing beats these on both)")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BASELINE.stroke_width(2)));
    chart
        .draw_series(
            pts(adaptive)
                .into_iter()
                .map(|p| Circle::new(p, 3, ADAPTIVE.filled())),
        )
        .map_err(|e| e.to_string())?
        .label("RHONN adaptive, one setting each")
        .legend(|(x, y)| Circle::new((x + 8, y), 3, ADAPTIVE.filled()));
    // Labels of named points alternate above-left, above-right and below-right, so that
    // neighbours do not print over each other.
    let offsets = [(-8, -22), (8, -22), (8, 8)];
    for (k, (name, p)) in named.iter().filter(|(_, p)| ok(&p)).enumerate() {
        let at = (p.current_total_variation_a, p.iae_mpa_s);
        let (dx, dy) = offsets[k % offsets.len()];
        let font = ("sans-serif", 13).into_font().color(&REFERENCE);
        let font = if dx < 0 {
            font.pos(Pos::new(HPos::Right, VPos::Top))
        } else {
            font
        };
        chart
            .draw_series([
                EmptyElement::at(at) + Circle::new((0, 0), 6, ADAPTIVE.stroke_width(2)),
                EmptyElement::at(at) + Circle::new((0, 0), 1, ADAPTIVE.filled()),
            ])
            .map_err(|e| e.to_string())?;
        chart
            .draw_series([EmptyElement::at(at) + Text::new(name.clone(), (dx, dy), font)])
            .map_err(|e| e.to_string())?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.3))
        .draw()
        .map_err(|e| e.to_string())
}

/// Write `front.csv` (every point: controller, setting, IAE, total variation, share within
/// 1 %, whether it is on its controller's front) and `front.svg` into `dir`, all or
/// nothing; returns the files.
pub fn write_front(
    dir: &Path,
    cascade: &[FrontPoint],
    adaptive: &[FrontPoint],
    named: &[(String, FrontPoint)],
) -> Result<Vec<PathBuf>> {
    let mut set = OutputSet::new(dir)?;
    set.write("front.csv", |w| {
        writeln!(
            w,
            "controller,setting,iae_mpa_s,current_total_variation_a,within_1pct_percent,on_front"
        )?;
        for group in [cascade, adaptive] {
            let front = pareto(group);
            for (k, p) in group.iter().enumerate() {
                writeln!(
                    w,
                    "{},\"{}\",{},{},{},{}",
                    p.controller,
                    p.setting,
                    p.iae_mpa_s,
                    p.current_total_variation_a,
                    p.within_1pct_percent,
                    front.contains(&k)
                )?;
            }
        }
        Ok(())
    })?;
    let svg = front_svg(cascade, adaptive, named);
    set.write("front.svg", |w| w.write_all(svg.as_bytes()))?;
    set.commit()
}
