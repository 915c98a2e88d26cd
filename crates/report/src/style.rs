//! How plots look, the same in every plot of a run: one colour per role (a controller, a
//! baseline, a set-point, a limit) whatever the plot, legend marks drawn as their series
//! are (dashed or solid), and the legend in the corner where it hides the least data.

use plotters::prelude::*;

/// Colours of the lines that are not a baseline, a reference or a limit, in order: the
/// Okabe-Ito palette (Okabe and Ito 2008, "Color Universal Design"), chosen so that the
/// colours of a plot stay apart for readers with any of the three colour-vision
/// deficiencies (checked by the tests below).
const PALETTE: [RGBColor; 4] = [
    RGBColor(0, 114, 178),   // blue
    RGBColor(0, 158, 115),   // bluish green
    RGBColor(204, 121, 167), // reddish purple
    RGBColor(86, 180, 233),  // sky blue
];
/// Every baseline (the PI, the ARX model): orange in every plot.
pub const BASELINE: RGBColor = RGBColor(230, 159, 0);
/// Set-points and references.
pub const REFERENCE: RGBColor = RGBColor(40, 40, 40);
/// Limits (P_min, a bound): vermillion, always dashed.
pub const LIMIT: RGBColor = RGBColor(213, 94, 0);

/// A second baseline (another tuning of the same classical controller): bluish green.
pub const SECOND_BASELINE: RGBColor = RGBColor(0, 158, 115);

/// The role a series' label says it has.
fn role_color(label: &str) -> Option<RGBColor> {
    if label.contains("second baseline") {
        Some(SECOND_BASELINE)
    } else if label.contains("baseline") {
        Some(BASELINE)
    } else if label.contains("set-point") || label.contains("reference") {
        Some(REFERENCE)
    } else if label == "P_min"
        || label.contains("limit")
        || label.contains("bound")
        || label.ends_with(" floor")
    {
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
        // A second baseline has its own colour, drawn before the adaptive controller,
        // which keeps the first plain colour.
        let three = colors([
            "p_line (cascade PI baseline)",
            "p_line (second baseline: cascade PI, nominal-optimal tuning)",
            "p_line (RHONN adaptive)",
        ]);
        assert_eq!(
            (three[0], three[1], three[2]),
            (BASELINE, SECOND_BASELINE, pressure[1])
        );
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

    /// CIE L*a*b* of an sRGB colour as a reader with normal vision, one of the three
    /// colour-vision deficiencies (Machado, Oliveira and Fernandes 2009, severity 1,
    /// applied in linear RGB) or in greyscale (relative luminance) sees it.
    fn seen_lab(c: RGBColor, vision: &str) -> [f64; 3] {
        let lin = |v: u8| {
            let v = v as f64 / 255.0;
            if v <= 0.04045 {
                v / 12.92
            } else {
                ((v + 0.055) / 1.055).powf(2.4)
            }
        };
        let l = [lin(c.0), lin(c.1), lin(c.2)];
        let m: [[f64; 3]; 3] = match vision {
            "protanopia" => [
                [0.152286, 1.052583, -0.204868],
                [0.114503, 0.786281, 0.099216],
                [-0.003882, -0.048116, 1.051998],
            ],
            "deuteranopia" => [
                [0.367322, 0.860646, -0.227968],
                [0.280085, 0.672501, 0.047413],
                [-0.011820, 0.042940, 0.968881],
            ],
            "tritanopia" => [
                [1.255528, -0.076749, -0.178779],
                [-0.078411, 0.930809, 0.147602],
                [0.004733, 0.691367, 0.303900],
            ],
            "grey" => [[0.2126, 0.7152, 0.0722]; 3],
            _ => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        };
        let s: Vec<f64> = m
            .iter()
            .map(|r| (r[0] * l[0] + r[1] * l[1] + r[2] * l[2]).clamp(0.0, 1.0))
            .collect();
        let xyz = [
            (0.4124 * s[0] + 0.3576 * s[1] + 0.1805 * s[2]) / 0.95047,
            0.2126 * s[0] + 0.7152 * s[1] + 0.0722 * s[2],
            (0.0193 * s[0] + 0.1192 * s[1] + 0.9505 * s[2]) / 1.08883,
        ];
        let f = |t: f64| {
            if t > 0.008856 {
                t.cbrt()
            } else {
                7.787 * t + 16.0 / 116.0
            }
        };
        let [fx, fy, fz] = xyz.map(f);
        [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
    }

    fn delta_e(a: RGBColor, b: RGBColor, vision: &str) -> f64 {
        let (p, q) = (seen_lab(a, vision), seen_lab(b, vision));
        ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
    }

    /// The colours that share a plot stay apart (CIE76 distance at least 15, where 2.3
    /// is a just-noticeable difference) for normal vision and for each colour-vision
    /// deficiency: the two series of the palette that plots draw together (controller
    /// and model, measured and predicted), the baseline, the reference and the limit.
    /// In greyscale the controller under test and its baseline stay apart (the
    /// reference and the limits are dashed there, so their style tells them apart).
    #[test]
    fn the_colours_stay_apart_for_colour_blind_readers_and_in_grey() {
        let solid = [PALETTE[0], PALETTE[1], BASELINE];
        let all = [PALETTE[0], PALETTE[1], BASELINE, REFERENCE, LIMIT];
        for vision in ["normal", "protanopia", "deuteranopia", "tritanopia"] {
            for (i, a) in all.iter().enumerate() {
                for b in &all[i + 1..] {
                    let d = delta_e(*a, *b, vision);
                    assert!(d >= 15.0, "{vision}: {a:?} and {b:?} only {d:.1} apart");
                }
            }
        }
        let d = delta_e(solid[0], solid[2], "grey");
        assert!(d >= 20.0, "grey: controller and baseline only {d:.1} apart");
        // The old palette (matplotlib's tab10) fails: its green and orange are 5 apart
        // for protanopia.
        let (green, orange) = (RGBColor(44, 160, 44), RGBColor(255, 127, 14));
        assert!(delta_e(green, orange, "protanopia") < 15.0);
    }
}
