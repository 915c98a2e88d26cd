//! How plots look, the same in every plot of a run: one colour per role (a controller, a
//! baseline, a set-point, a limit) whatever the plot, legend marks drawn as their series
//! are (dashed or solid), and the legend in the corner where it hides the least data.

use plotters::prelude::*;

/// Colours of the lines that are not a baseline, a reference or a limit, in order.
const PALETTE: [RGBColor; 5] = [
    RGBColor(31, 119, 180),  // blue
    RGBColor(44, 160, 44),   // green
    RGBColor(148, 103, 189), // purple
    RGBColor(140, 86, 75),   // brown
    RGBColor(23, 190, 207),  // teal
];
/// Every baseline (the PI, the ARX model): orange in every plot.
pub const BASELINE: RGBColor = RGBColor(255, 127, 14);
/// Set-points and references.
pub const REFERENCE: RGBColor = RGBColor(40, 40, 40);
/// Limits (P_min, a bound).
pub const LIMIT: RGBColor = RGBColor(214, 39, 40);

/// The role a series' label says it has.
fn role_color(label: &str) -> Option<RGBColor> {
    if label.contains("baseline") {
        Some(BASELINE)
    } else if label.contains("set-point") || label.contains("reference") {
        Some(REFERENCE)
    } else if label == "P_min" || label.contains("limit") || label.contains("bound") {
        Some(LIMIT)
    } else {
        None
    }
}

/// The colours of series with these labels, in order: a baseline, a reference and a
/// limit by their role, every other series by its rank among the others, so that the
/// controller under test is the same blue in every plot of a run.
pub fn colors<'a>(labels: impl IntoIterator<Item = &'a str>) -> Vec<RGBColor> {
    let mut plain = 0;
    labels
        .into_iter()
        .map(|l| {
            role_color(l).unwrap_or_else(|| {
                plain += 1;
                PALETTE[(plain - 1) % PALETTE.len()]
            })
        })
        .collect()
}

/// The legend's mark for a series, as two segments relative to the label's anchor: two
/// dashes for a dashed series, one line (split in two) for a solid one, so that the
/// legend shows each series as it is drawn.
pub fn legend_segments(dashed: bool) -> [[(i32, i32); 2]; 2] {
    if dashed {
        [[(0, 0), (8, 0)], [(12, 0), (20, 0)]]
    } else {
        [[(0, 0), (10, 0)], [(10, 0), (20, 0)]]
    }
}

/// The legend mark of a series of `color`, `dashed` or not, `width` pixels wide (a
/// closure for plotters' `legend`).
macro_rules! legend_mark {
    ($color:expr, $dashed:expr, $width:expr) => {{
        let (color, segs) = ($color, $crate::style::legend_segments($dashed));
        let width: u32 = $width;
        move |(x, y): (i32, i32)| {
            EmptyElement::at((x, y))
                + PathElement::new(segs[0].to_vec(), color.stroke_width(width))
                + PathElement::new(segs[1].to_vec(), color.stroke_width(width))
        }
    }};
}
pub(crate) use legend_mark;

/// The corner for a legend of `box_w` x `box_h` (fractions of the plot's width and height)
/// that covers the fewest of `points` (fractions, x to the right, y up); the upper right
/// on a tie.
pub fn legend_corner(points: &[(f64, f64)], box_w: f64, box_h: f64) -> SeriesLabelPosition {
    let corners = [
        (SeriesLabelPosition::UpperRight, 1.0 - box_w, 1.0 - box_h),
        (SeriesLabelPosition::UpperLeft, 0.0, 1.0 - box_h),
        (SeriesLabelPosition::LowerRight, 1.0 - box_w, 0.0),
        (SeriesLabelPosition::LowerLeft, 0.0, 0.0),
    ];
    let covered = |x0: f64, y0: f64| {
        points
            .iter()
            .filter(|(x, y)| *x >= x0 && *x <= x0 + box_w && *y >= y0 && *y <= y0 + box_h)
            .count()
    };
    let mut best = (usize::MAX, SeriesLabelPosition::UpperRight);
    for (pos, x0, y0) in corners {
        let c = covered(x0, y0);
        if c < best.0 {
            best = (c, pos);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_role_keeps_its_colour_whatever_the_order() {
        let pressure = colors([
            "p_line (PI baseline)",
            "p_line (RHONN adaptive)",
            "set-point",
            "P_min",
        ]);
        let current = colors(["current (RHONN adaptive)", "current (PI baseline)"]);
        assert_eq!(pressure[0], current[1]);
        assert_eq!(pressure[1], current[0]);
        assert_eq!(pressure[0], BASELINE);
        assert_eq!((pressure[2], pressure[3]), (REFERENCE, LIMIT));
        let p = colors(["y", "y_hat (free run)", "ARX baseline"]);
        assert!(p[0] != p[1] && p[2] == BASELINE);
    }

    #[test]
    fn the_legend_goes_where_it_hides_the_least() {
        // Data along the top: the legend goes to a lower corner.
        let top: Vec<(f64, f64)> = (0..100).map(|k| (k as f64 / 100.0, 0.95)).collect();
        assert!(matches!(
            legend_corner(&top, 0.3, 0.2),
            SeriesLabelPosition::LowerRight
        ));
        // Data rising to the upper right: upper left.
        let rising: Vec<(f64, f64)> = (0..100).map(|k| (k as f64 / 100.0, k as f64 / 100.0)).collect();
        assert!(matches!(
            legend_corner(&rising, 0.3, 0.2),
            SeriesLabelPosition::UpperLeft
        ));
        assert!(matches!(
            legend_corner(&[], 0.3, 0.2),
            SeriesLabelPosition::UpperRight
        ));
    }
}
