//! Each command of `rhonn` as a library call (what the binary and the Python package call).

use rhonn_app::{self as commands, FitRequest};
use rhonn_report::Error;
use std::path::PathBuf;

fn tanks(file: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/cascaded-tanks")
        .join(file)
}

fn names(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

#[test]
fn fit_then_predict_as_library_calls() {
    let dir = tempfile::tempdir().unwrap();
    let req = FitRequest {
        data: vec![tanks("estimation.csv")],
        inputs: names(&["u"]),
        outputs: names(&["y"]),
        units: names(&["y=V"]),
        out: dir.path().join("fit"),
        ..FitRequest::default()
    };
    let o = commands::fit(&req).unwrap();
    assert!(o.lines[0].starts_with("fitted a"), "{:?}", o.lines);
    assert!(o
        .lines
        .iter()
        .any(|l| l.contains("ARX baseline (na 2 nb 2 nk 1, same lags), free run") && l.contains(" V, fit")));
    let model = dir.path().join("fit/model.json");
    assert!(o.files.contains(&model) && model.exists());
    let p = commands::predict(
        &model,
        (&tanks("validation.csv"), "t"),
        &dir.path().join("pred"),
        Some(10),
        None,
    )
    .unwrap();
    assert!(
        p.lines[0].starts_with("y (10 steps ahead): rms error"),
        "{:?}",
        p.lines
    );
    assert!(dir.path().join("pred/prediction.csv").exists());
    // Its summary and report say in words how it compares with the mean and the baseline.
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("pred/summary.json")).unwrap())
            .unwrap();
    let f = s["findings"][0].as_str().unwrap();
    assert!(
        f.starts_with("y (10 steps ahead): fit ")
            && f.contains("predicting the mean")
            && f.contains("x the baseline's"),
        "{f}"
    );
    let html = std::fs::read_to_string(dir.path().join("pred/report.html")).unwrap();
    assert!(html.contains("x the baseline"), "no findings in the report");
}

#[test]
fn bad_arguments_are_input_errors_naming_the_argument() {
    let dir = tempfile::tempdir().unwrap();
    let req = FitRequest {
        data: vec![tanks("estimation.csv")],
        inputs: names(&["u"]),
        outputs: names(&["y"]),
        units: names(&["z=V"]),
        out: dir.path().join("fit"),
        ..FitRequest::default()
    };
    match commands::fit(&req) {
        Err(Error::Input(m)) => assert!(m.contains("--units names column `z`"), "{m}"),
        other => panic!("expected an input error, got {other:?}"),
    }
    assert!(
        !dir.path().join("fit").exists(),
        "nothing written for a refused fit"
    );
    let req = FitRequest {
        resample_s: Some(-1.0),
        units: Vec::new(),
        ..req
    };
    assert!(matches!(commands::fit(&req), Err(Error::Input(m)) if m.contains("--resample -1")));
    let e = commands::predict(
        &dir.path().join("none.json"),
        (&tanks("validation.csv"), "t"),
        dir.path(),
        None,
        None,
    );
    assert!(matches!(e, Err(Error::Input(m)) if m.contains("none.json")));
    assert!(
        matches!(commands::bench(&[], false, 0.0, None, None, &|_, _, _| {}), Err(Error::Input(m)) if m.contains("--seconds 0"))
    );
    // A comparison file: needs --out, and a bad one is refused (naming it) before any timing.
    let cmp = dir.path().join("cmp.json");
    std::fs::write(
        &cmp,
        r#"[{"run": "x", "tool": "scipy", "median_s": -1, "rhs_evaluations": null}]"#,
    )
    .unwrap();
    let b = |out: Option<&std::path::Path>| {
        commands::bench(&["thesis-ch3".into()], false, 1.0, out, Some(&cmp), &|_, _, _| {
            panic!("timed before the comparison file was checked")
        })
    };
    assert!(matches!(b(None), Err(Error::Input(m)) if m.contains("--compare needs --out")));
    assert!(
        matches!(b(Some(dir.path())), Err(Error::Input(m)) if m.contains("cmp.json") && m.contains("median_s = -1"))
    );
    std::fs::write(&cmp, "[1, 2]").unwrap();
    assert!(
        matches!(b(Some(dir.path())), Err(Error::Input(m)) if m.contains("cmp.json") && m.contains("not a comparison file"))
    );
    assert!(!dir.path().join("summary.json").exists(), "nothing written");
}

#[test]
fn run_and_show_a_shipped_scenario() {
    let dir = tempfile::tempdir().unwrap();
    let o = commands::run("tanks-identify", Some(dir.path().join("t"))).unwrap();
    assert!(o.lines[0].starts_with("tanks-identify:"), "{:?}", o.lines);
    assert!(dir.path().join("t/summary.json").exists());
    assert!(commands::show("thesis-ch3").unwrap().contains("[input.current]"));
    assert!(commands::show("no-such-scenario").is_err());
}
