//! A model kind added by the recipe of docs/ARCHITECTURE.md ("How to add"): `mean`, the
//! smallest kind (`models/mean.rs`, `sysid/mean.rs`, a `Kind` variant, a line in each
//! registry), reached from a spec file through every door of the command: `rhonn fit
//! --model`, its model.json, `rhonn predict` free run and K steps ahead, the check of a
//! stored model, and the online identifier's refusal. (`shape.rs` checks every registered
//! kind is its two files; Python's `test_fit.py` fits the same kind.)

use crate::util;

use std::path::Path;
use util::{rhonn, stderr, stdout};

/// Column `col` of a CSV with a header (every row parsed).
fn column(path: &Path, col: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let i = lines.next().unwrap().split(',').position(|h| h == col).unwrap();
    lines
        .map(|l| l.split(',').nth(i).unwrap().parse().unwrap())
        .collect()
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn a_kind_added_by_the_recipe_runs_through_fit_predict_and_the_checks() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let (est, val) = (
        root.join("data/cascaded-tanks/estimation.csv"),
        root.join("data/cascaded-tanks/validation.csv"),
    );
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("mean.toml"), "kind = \"mean\"\n").unwrap();
    let data = |p: &Path| p.to_str().unwrap().to_string();
    let fit = |extra: &[&str]| {
        let mut a = vec!["fit", "--inputs", "u", "--outputs", "y", "--model", "mean.toml"];
        a.extend_from_slice(extra);
        rhonn(d.path(), &a)
    };
    let o = fit(&["--data", &data(&est), "--out", "fit"]);
    assert!(o.status.success(), "{}", stderr(&o));

    // The model is the training mean; on its training record a fit of 0 % and an RMS
    // error of the output's (population) standard deviation.
    let y = column(&est, "y");
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let std = (y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / y.len() as f64).sqrt();
    let model = json(&d.path().join("fit/model.json"));
    let stored = model["model"]["weights"][0][0].as_f64().unwrap();
    assert!(
        (stored - mean).abs() < 1e-12 * mean.abs(),
        "{stored} against {mean}"
    );
    assert_eq!(model["model"]["spec"]["kind"], "mean");
    let s = json(&d.path().join("fit/summary.json"));
    let train = &s["training"]["free_run"][0]["outputs"][0];
    assert!(
        (train["rms_error"].as_f64().unwrap() - std).abs() < 1e-9 * std,
        "{train}"
    );
    assert!(train["fit_percent"].as_f64().unwrap().abs() < 1e-9, "{train}");
    // Its ARX baseline takes the spec's na and nb (the defaults here), and says so: the
    // kind has no lags of its own for the baseline to share.
    assert_eq!(
        s["baseline_arx"]["chosen_as"], "the spec's na and nb: this kind has no lags",
        "{}",
        s["baseline_arx"]
    );
    assert!(
        stdout(&o).contains("ARX baseline (na 2 nb 2 nk 1, the spec's na and nb: this kind has no lags)"),
        "{}",
        stdout(&o)
    );

    // `rhonn predict`, free run and K steps ahead: the mean at every sample, scored from
    // the first sample on.
    for (out, k) in [("val", None), ("val3", Some("3"))] {
        let mut a = vec!["predict", "--model", "fit/model.json", "--out", out];
        let v = data(&val);
        a.extend_from_slice(&["--data", &v]);
        if let Some(k) = k {
            a.extend_from_slice(&["--steps-ahead", k]);
        }
        let o = rhonn(d.path(), &a);
        assert!(o.status.success(), "{}", stderr(&o));
        let yhat = column(&d.path().join(out).join("prediction.csv"), "y_hat");
        assert_eq!(yhat.len(), column(&val, "y").len());
        assert!(
            yhat.iter().all(|v| *v == stored),
            "{out}: not the mean at every sample"
        );
        let p = json(&d.path().join(out).join("summary.json"));
        assert_eq!(
            p["outputs"][0]["samples"].as_u64().unwrap() as usize,
            yhat.len(),
            "{p}"
        );
    }

    // A stored model of the kind is checked by its own rules: one finite mean per output.
    let mut bad = model.clone();
    bad["model"]["weights"][0] = serde_json::json!([1.0, 2.0]);
    std::fs::write(d.path().join("bad.json"), bad.to_string()).unwrap();
    let o = rhonn(
        d.path(),
        &[
            "predict",
            "--model",
            "bad.json",
            "--data",
            &data(&val),
            "--out",
            "bad",
        ],
    );
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("model.weights") && stderr(&o).contains("one vector of one value"),
        "{}",
        stderr(&o)
    );
    assert!(
        !d.path().join("bad").exists(),
        "nothing written for a refused model"
    );

    // The online identifier learns the lagged and cascade kinds only, and says so.
    let o = rhonn(
        d.path(),
        &[
            "identify",
            "--data",
            &data(&est),
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--model",
            "mean.toml",
            "--out",
            "id",
        ],
    );
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("kind = \"mean\" has no online counterpart"),
        "{}",
        stderr(&o)
    );
}
