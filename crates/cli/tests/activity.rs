//! Actuator activity in every controlled run: the figures are there for the controller and
//! its baseline, consistent with each other (switching is part of saturation, which is part
//! of the run), agree with the trajectory's input column, and the findings compare them.

use crate::util;

use util::{rhonn, stderr};

fn summary(dir: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

#[test]
fn a_plant_control_run_reports_its_input_activity_beside_the_baseline() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["run", "tanks-control", "--out", "t"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = summary(&d.path().join("t"));
    let duration = 2400.0;
    for f in s["control"].as_array().unwrap() {
        let tv = f["input_total_variation"].as_f64().unwrap();
        let rms = f["input_rms_change_per_sample"].as_f64().unwrap();
        let sat = f["time_input_saturated_s"].as_f64().unwrap();
        let sw = f["time_input_switching_s"].as_f64().unwrap();
        assert!(tv > 0.0 && rms > 0.0 && rms <= tv, "{f}");
        assert!(sw <= sat && sat <= duration, "{f}");
    }
    // The controller's total variation is that of the trajectory's input column (the
    // command held over each control period; the file is written every period).
    let mut rd = csv::Reader::from_path(d.path().join("t/trajectory.csv")).unwrap();
    let h = rd.headers().unwrap().clone();
    let col = h
        .iter()
        .position(|c| c == "voltage")
        .unwrap_or_else(|| panic!("{h:?}"));
    let u: Vec<f64> = rd.records().map(|r| r.unwrap()[col].parse().unwrap()).collect();
    let tv: f64 = u.windows(2).map(|w| (w[1] - w[0]).abs()).sum();
    let reported = s["control"][0]["input_total_variation"].as_f64().unwrap();
    assert!(
        (tv - reported).abs() <= 1e-6 * reported.max(1.0),
        "{tv} {reported}"
    );
    let findings = s["findings"].to_string();
    assert!(
        findings.contains("the input moved") && findings.contains("for the baseline"),
        "{findings}"
    );
}

#[test]
fn the_pumps_adaptive_run_reports_the_currents_activity_for_both_controllers() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["run", "control-adaptive", "--out", "c"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("rhonn-adaptive: the input moved") && out.contains("for the baseline cascade-pi"),
        "{out}"
    );
    let s = summary(&d.path().join("c"));
    let (r, b) = (&s["control"][0], &s["control"][1]);
    let tv = r["input_total_variation"].as_f64().unwrap();
    assert!(
        tv > 0.0 && b["input_total_variation"].as_f64().unwrap() > 0.0,
        "{r}"
    );
    assert!(r["time_input_switching_s"].as_f64().unwrap() <= r["time_input_saturated_s"].as_f64().unwrap());
}

/// A PI-regulated pump run (no comparison) says in words how it tracked and how much its
/// current moved, in summary.json and in its report.
#[test]
fn a_regulated_run_has_findings_in_its_summary_and_report() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["run", "regulated-pi", "--out", "r"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = summary(&d.path().join("r"));
    let f = s["findings"].to_string();
    assert!(
        f.contains("pi: IAE") && f.contains("within 1 % of the set-point"),
        "{f}"
    );
    assert!(f.contains("pi: the input moved"), "{f}");
    let html = std::fs::read_to_string(d.path().join("r/report.html")).unwrap();
    assert!(
        html.contains("<li>pi: the input moved"),
        "no findings in the report"
    );
}
