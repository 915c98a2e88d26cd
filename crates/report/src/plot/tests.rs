//! Tests of `plot.rs`: histograms, legends, set-points over traces, axes.

use super::histogram::axis_with_unit;
use super::*;

/// A set-point (dashed) is drawn over the trace that follows it, whatever their order.
#[test]
fn dashed_set_points_are_drawn_over_solid_traces() {
    let t: Vec<f64> = (0..50).map(f64::from).collect();
    let p = TimePlot {
        title: "x".into(),
        y_label: "y".into(),
        t: t.clone(),
        series: vec![
            Series::dashed("set-point", t.clone()),
            Series::solid("level", t.clone()),
        ],
    };
    let svg = TimePlot::render(&[p], 400, 300);
    let hex = |c: RGBColor| format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2);
    let c = crate::style::colors(["set-point", "level"]);
    let (dashed, solid) = (hex(c[0]), hex(c[1]));
    let first = |h: &str| svg.to_uppercase().find(&h.to_uppercase()).unwrap_or(usize::MAX);
    assert!(
        first(&solid) < first(&dashed),
        "the set-point is drawn first: hidden under the trace"
    );
}

#[test]
fn histogram_axes_have_units_few_ticks_and_whole_counts() {
    assert_eq!(axis_with_unit("iae_mpa_s"), "iae_mpa_s [MPa s]");
    assert_eq!(axis_with_unit("ise_mpa2_s"), "ise_mpa2_s [MPa^2 s]");
    assert_eq!(
        axis_with_unit("controller_iae_mm_s"),
        "controller_iae_mm_s [mm s]"
    );
    assert_eq!(
        axis_with_unit("baseline_ise_mm2_s"),
        "baseline_ise_mm2_s [mm^2 s]"
    );
    assert_eq!(
        axis_with_unit("controller_input_total_variation"),
        "controller_input_total_variation"
    );
    let values: Vec<f64> = (0..200).map(|k| 550_000.0 + 500.0 * f64::from(k)).collect();
    let svg = Histogram::render(&[Histogram::new("x", "max_abs_deviation_mpa", &values, 20)], 1);
    assert!(svg.contains("max_abs_deviation_mpa [MPa]") && svg.contains("number of runs"));
    assert!(
        !svg.contains("550000.0") && !svg.contains(".5<"),
        "fixed-decimal ticks"
    );
}

#[test]
fn bins_count_every_value_once() {
    let (lo, hi, c) = bin_counts(&[0.0, 0.5, 1.0, 1.0, f64::NAN, 0.26], 4);
    assert_eq!((lo, hi), (0.0, 1.0));
    assert_eq!(c, vec![1, 1, 1, 2]);
    let svg = Histogram::render(&[Histogram::new("ISE", "ISE [MPa^2 s]", &[1.0, 2.0, 2.5], 10)], 1);
    assert!(svg.contains("ISE [MPa^2 s]") && svg.contains("runs"));
}

#[test]
fn extreme_values_give_a_plot_not_a_hang() {
    // Plotters' tick search looped for ever on these (issue 33): each must render.
    for (t, y) in [
        (vec![0.0, 1.0, 2.0], vec![0.0, 1.7e308, 1.0]),
        (vec![0.0, 1.0, 2.0], vec![-1.7e308, 1.7e308, 0.0]),
        (vec![0.0, 1.0, 2.0], vec![f64::MAX, f64::MAX, f64::MAX]),
        (vec![0.0, 1.0, 2.0], vec![5e-324, 0.0, -5e-324]),
        (vec![0.0, 1e300, 1.7e308], vec![1.0, 2.0, 3.0]),
        (vec![1e15, 1e15, 1e15], vec![1.0, 2.0, 3.0]),
    ] {
        let p = TimePlot {
            title: "extreme".into(),
            y_label: "y [V]".into(),
            t: t.clone(),
            series: vec![Series::solid("y", y.clone())],
        };
        let svg = TimePlot::render(&[p], 400, 200);
        assert!(svg.contains("<svg"), "{t:?} {y:?}");
        let h = Histogram::new("h", "y [V]", &y, 10);
        assert!(Histogram::render(&[h], 1).contains("<svg"));
    }
    assert_eq!(safe_axis((-1.0, 2.5)), (-1.0, 2.5));
    assert_eq!(safe_axis((f64::NEG_INFINITY, f64::NAN)), (-1e300, 0.0));
}

#[test]
fn decimation_keeps_extremes() {
    let t: Vec<f64> = (0..10_000).map(|k| k as f64).collect();
    let mut y = vec![0.0; 10_000];
    y[5_000] = 7.0;
    let d = decimate(&t, &y, 100);
    assert!(d.len() <= 201);
    assert!(d.iter().any(|&(_, v)| v == 7.0));
}

#[test]
fn an_svg_has_axis_labels_with_units() {
    let p = TimePlot {
        title: "x".into(),
        y_label: "line pressure [MPa]".into(),
        t: vec![0.0, 1.0, 2.0],
        series: vec![Series::solid("p", vec![1.0, 2.0, 1.5])],
    };
    let svg = TimePlot::render(&[p], 400, 300);
    assert!(svg.starts_with("<svg"));
    assert!(svg.contains("line pressure [MPa]") && svg.contains("time [s]"));
}
