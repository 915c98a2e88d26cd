//! A campaign lists its worst runs with their drawn parameters and a scenario file per
//! run; `rhonn run` of that file reruns the run: the same figures as in runs.csv.

use crate::util;

use util::{rhonn, stderr};

#[test]
fn the_worst_runs_rerun_with_the_figures_of_the_campaign() {
    let d = tempfile::tempdir().unwrap();
    let preset = rhonn(d.path(), &["show", "control-adaptive"]);
    let text = String::from_utf8_lossy(&preset.stdout).replace("duration_s = 60.0", "duration_s = 6.0");
    std::fs::write(d.path().join("short.toml"), text).unwrap();
    let o = rhonn(
        d.path(),
        &[
            "campaign",
            "short.toml",
            "--runs",
            "12",
            "--seed",
            "4",
            "--out",
            "c",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("c/summary.json")).unwrap()).unwrap();
    let worst = summary["worst_runs"].as_array().unwrap();
    assert_eq!(worst.len(), 5);
    // Ranked by the adaptive controller's IAE, largest first, and each is the runs.csv row's.
    let runs = std::fs::read_to_string(d.path().join("c/runs.csv")).unwrap();
    let header: Vec<&str> = runs.lines().next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == "controller_iae_mpa_s").unwrap();
    let mut iae: Vec<(u64, f64)> = runs
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[0].parse().unwrap(), f[col].parse().unwrap())
        })
        .collect();
    iae.sort_by(|a, b| b.1.total_cmp(&a.1));
    for (w, (run, value)) in worst.iter().zip(&iae) {
        assert_eq!(w["run"].as_u64().unwrap(), *run);
        assert_eq!(w["value"].as_f64().unwrap(), *value);
    }
    let findings = summary["findings"].as_array().unwrap();
    assert!(
        findings[0].as_str().unwrap().contains("rhonn run worst-run-"),
        "{findings:?}"
    );
    // The worst run, rerun from its file, gives its figure to the last bit.
    let first = &worst[0];
    let o = rhonn(
        &d.path().join("c"),
        &["run", first["file"].as_str().unwrap(), "--out", "../rerun"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let rerun: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("rerun/summary.json")).unwrap()).unwrap();
    assert_eq!(
        rerun["control"][0]["iae"].as_f64().unwrap(),
        first["value"].as_f64().unwrap()
    );
}

#[test]
fn a_tank_campaigns_worst_run_reruns_with_its_figure() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(
        d.path(),
        &[
            "campaign",
            "tanks-control",
            "--runs",
            "6",
            "--seed",
            "2",
            "--out",
            "t",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("t/summary.json")).unwrap()).unwrap();
    let worst = summary["worst_runs"].as_array().unwrap();
    assert_eq!(worst.len(), 5);
    let values: Vec<f64> = worst.iter().map(|w| w["value"].as_f64().unwrap()).collect();
    assert!(values.windows(2).all(|p| p[0] >= p[1]), "{values:?}");
    let o = rhonn(
        &d.path().join("t"),
        &["run", worst[0]["file"].as_str().unwrap(), "--out", "../rerun"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let rerun: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("rerun/summary.json")).unwrap()).unwrap();
    assert_eq!(rerun["control"][0]["iae"].as_f64().unwrap(), values[0]);
}
