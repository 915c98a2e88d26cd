//! `rhonn identify` from the command line: the files it writes, its figures on the
//! measured cascaded tanks, and clear errors for bad recordings.

use crate::util;

use std::path::{Path, PathBuf};
use util::{files_in, rhonn, stderr};

fn repo() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

#[test]
fn tanks_identified_online_then_frozen_writes_every_file_and_the_figures_of_the_readme() {
    let d = tempfile::tempdir().unwrap();
    let data = repo().join("data/cascaded-tanks");
    let o = rhonn(
        d.path(),
        &[
            "identify",
            "--data",
            data.join("estimation.csv").to_str().unwrap(),
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--model",
            repo().join("models/tanks-online.toml").to_str().unwrap(),
            "--validate",
            data.join("validation.csv").to_str().unwrap(),
            "--steps-ahead",
            "10",
            "--out",
            "id",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        files_in(&d.path().join("id")),
        [
            "estimate.csv",
            "estimate.svg",
            "model.json",
            "report.html",
            "residual_histogram.svg",
            "residuals.svg",
            "rhonn-manifest.json",
            "summary.json",
            "validation.csv",
            "validation.svg",
            "validation_residuals.svg",
            "weights.csv",
            "weights.svg"
        ]
    );
    // The validation plot's legend carries the fits of summary.json.
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("id/summary.json")).unwrap()).unwrap();
    let val = std::fs::read_to_string(d.path().join("id/validation.svg")).unwrap();
    let v = &summary["validation"][0];
    for (key, text) in [
        ("free_run_fit_percent", "y free run (frozen weights, fit"),
        ("ahead_fit_percent", "y 10 samples ahead (fit"),
    ] {
        let fit = v[key].as_f64().unwrap();
        assert!(
            val.contains(&format!("{text} {fit:.1} %)")),
            "{key} {fit:.1} not in the legend"
        );
    }
    // The residual plots: the autocorrelation and the input cross-correlation, each with
    // its 99 % band, for the online estimate and for the frozen model's free run.
    for f in ["residuals.svg", "validation_residuals.svg"] {
        let svg = std::fs::read_to_string(d.path().join("id").join(f)).unwrap();
        assert!(svg.contains("y: autocorrelation of the residuals"), "{f}");
        assert!(
            svg.contains("y: cross-correlation of input u and the residuals"),
            "{f}"
        );
        assert_eq!(svg.matches("99 % band of white noise").count(), 2, "{f}");
    }
    let est = std::fs::read_to_string(d.path().join("id/estimate.csv")).unwrap();
    assert!(est.starts_with("record,t,y,y_hat\n"), "{}", &est[..40]);
    assert_eq!(est.lines().count(), 1 + 1024);
    let w = std::fs::read_to_string(d.path().join("id/weights.csv")).unwrap();
    assert!(
        w.starts_with("record,t,w_norm_y,error_energy,w_y_0,"),
        "{}",
        &w[..60]
    );
    let v = std::fs::read_to_string(d.path().join("id/validation.csv")).unwrap();
    assert!(v.starts_with("record,t,y,y_free_run,y_10_ahead\n"));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("id/summary.json")).unwrap()).unwrap();
    // README figures: online fit 94.1 % over the last half, validation free run 1.73 V,
    // 10 samples ahead 0.87 V (ARX(2,2) free run: 0.709 V).
    let online = s["online"][0]["fit_percent_last_half"].as_f64().unwrap();
    assert!((online - 94.1).abs() < 0.1, "{online}");
    let free = s["validation"][0]["free_run_rms_error"].as_f64().unwrap();
    assert!((free - 1.728).abs() < 0.01, "{free}");
    let ahead = s["validation"][0]["ahead_rms_error"].as_f64().unwrap();
    assert!((ahead - 0.874).abs() < 0.01, "{ahead}");
    assert!(!s["findings"].as_array().unwrap().is_empty());
    // Every weight is listed (28 terms <= 50), and named in the summary.
    let terms = term_names(&s);
    assert_eq!(terms.len(), s["terms_per_neuron"].as_u64().unwrap() as usize);
    assert_eq!(w.lines().next().unwrap().split(',').count(), 4 + terms.len());
    assert!(
        terms.contains(&"tanh(y)*u") && terms.contains(&"u[filter 40 s]") && terms.contains(&"1"),
        "{terms:?}"
    );
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("id/model.json")).unwrap()).unwrap();
    assert_eq!(m["kind"], "online-rhonn");
    assert_eq!(
        m["weights"][0].as_array().unwrap().len(),
        s["terms_per_neuron"].as_u64().unwrap() as usize
    );
    let val = data.join("validation.csv").to_str().unwrap().to_string();
    // `rhonn predict` runs the online model: the same figures as the validation above.
    for (steps, key) in [(None, "free_run_rms_error"), (Some("10"), "ahead_rms_error")] {
        let mut args = vec![
            "predict",
            "--model",
            "id/model.json",
            "--data",
            &val,
            "--out",
            "p",
        ];
        if let Some(k) = steps {
            args.extend(["--steps-ahead", k]);
        }
        std::fs::remove_dir_all(d.path().join("p")).ok();
        let o = rhonn(d.path(), &args);
        assert!(o.status.success(), "{}", stderr(&o));
        let p: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.path().join("p/summary.json")).unwrap()).unwrap();
        let rms = p["figures"][0]["rms_error"].as_f64().unwrap();
        assert!(
            (rms - s["validation"][0][key].as_f64().unwrap()).abs() < 1e-12,
            "{key}: {rms}"
        );
        assert_eq!(
            files_in(&d.path().join("p")),
            [
                "prediction.csv",
                "prediction.svg",
                "report.html",
                "rhonn-manifest.json",
                "summary.json"
            ]
        );
    }
    // A hand-edited model: a weight vector too short, a weight that is not a number.
    let text = std::fs::read_to_string(d.path().join("id/model.json")).unwrap();
    let mut bad: serde_json::Value = serde_json::from_str(&text).unwrap();
    bad["weights"][0].as_array_mut().unwrap().pop();
    std::fs::write(d.path().join("short.json"), bad.to_string()).unwrap();
    let o = rhonn(
        d.path(),
        &["predict", "--model", "short.json", "--data", &val, "--out", "q"],
    );
    assert!(
        !o.status.success() && stderr(&o).contains("`weights`"),
        "{}",
        stderr(&o)
    );
    let mut bad: serde_json::Value = serde_json::from_str(&text).unwrap();
    bad["weights"][0][2] = serde_json::Value::String("NaN".into());
    std::fs::write(d.path().join("nan.json"), bad.to_string()).unwrap();
    let o = rhonn(
        d.path(),
        &["predict", "--model", "nan.json", "--data", &val, "--out", "q"],
    );
    assert!(
        !o.status.success() && stderr(&o).contains("nan.json"),
        "{}",
        stderr(&o)
    );
    assert!(!d.path().join("q").exists());
}

fn identify_err(dir: &Path, file: &str, text: &str) -> String {
    std::fs::write(dir.join(file), text).unwrap();
    let o = rhonn(
        dir,
        &[
            "identify",
            "--data",
            file,
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--out",
            "bad",
        ],
    );
    assert!(!o.status.success(), "accepted {text:?}");
    assert!(!dir.join("bad").exists(), "half-written output for {text:?}");
    stderr(&o)
}

#[test]
fn bad_recordings_name_the_file_line_and_column_and_write_nothing() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let e = identify_err(p, "nan.csv", "t,u,y\n0,1,2\n1,NaN,2\n2,1,2\n");
    assert!(e.contains("nan.csv, line 3, column `u`"), "{e}");
    let e = identify_err(p, "text.csv", "t,u,y\n0,1,2\n1,1,high\n2,1,2\n");
    assert!(
        e.contains("text.csv, line 3, column `y`") && e.contains("`high`"),
        "{e}"
    );
    let e = identify_err(p, "missing.csv", "t,u,z\n0,1,2\n1,1,2\n");
    assert!(e.contains("missing.csv") && e.contains("no column `y`"), "{e}");
    let e = identify_err(p, "back.csv", "t,u,y\n0,1,2\n2,1,2\n1,1,2\n");
    assert!(e.contains("back.csv, line 4, column `t`"), "{e}");
    // Missing rows, more than the one rule for gaps fills (1 % of the samples).
    let e = identify_err(p, "gap.csv", "t,u,y\n0,1,2\n1,1,3\n3,1,2\n4,1,3\n5,1,2\n");
    assert!(
        e.contains("gap.csv, column `t`: 1 samples missing") && e.contains("at most 1 %"),
        "{e}"
    );
    let e = identify_err(p, "one.csv", "t,u,y\n0,1,2\n");
    assert!(e.contains("one.csv") && e.contains("1 data rows"), "{e}");
}

#[test]
fn a_bad_model_spec_names_the_key() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("r.csv"), "t,u,y\n0,1,2\n1,0,2\n2,1,3\n").unwrap();
    std::fs::write(d.path().join("m.toml"), "filters_s = [-4.0]\n").unwrap();
    let o = rhonn(
        d.path(),
        &[
            "identify",
            "--data",
            "r.csv",
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--model",
            "m.toml",
            "--out",
            "x",
        ],
    );
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("model.filters_s[0]") && stderr(&o).contains("-4"),
        "{}",
        stderr(&o)
    );
    std::fs::write(d.path().join("m.toml"), "gains = 1.0\n").unwrap();
    let o = rhonn(
        d.path(),
        &[
            "identify",
            "--data",
            "r.csv",
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--model",
            "m.toml",
            "--out",
            "x",
        ],
    );
    assert!(!o.status.success());
    assert!(stderr(&o).contains("gains"), "{}", stderr(&o));
    assert!(!d.path().join("x").exists());
}

/// A filtered-regressor model (least squares) frozen after `rhonn identify` runs the
/// validation record as `rhonn predict` of its saved model.json does: both start its
/// filters at rest for the first sample, not with what training left in them (which
/// model.json does not hold). Before, the two disagreed (0.864 V and 0.750 V).
#[test]
fn a_least_squares_model_validates_as_its_saved_model_predicts() {
    let d = tempfile::tempdir().unwrap();
    let data = repo().join("data/cascaded-tanks");
    std::fs::write(
        d.path().join("ls.toml"),
        "filters_s = [40.0]\na_per_s = 0.01\nepochs = 2\nlaw = { kind = \"filtered-regressor-ls\", p0 = [10.0] }\n",
    )
    .unwrap();
    let (est, val) = (data.join("estimation.csv"), data.join("validation.csv"));
    let (est, val) = (est.to_str().unwrap(), val.to_str().unwrap());
    let o = rhonn(
        d.path(),
        &[
            "identify",
            "--data",
            est,
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--model",
            "ls.toml",
            "--validate",
            val,
            "--out",
            "id",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = rhonn(
        d.path(),
        &["predict", "--model", "id/model.json", "--data", val, "--out", "p"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let read = |f: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.path().join(f)).unwrap()).unwrap()
    };
    let validated = read("id/summary.json")["validation"][0]["free_run_rms_error"]
        .as_f64()
        .unwrap();
    let predicted = read("p/summary.json")["figures"][0]["rms_error"]
        .as_f64()
        .unwrap();
    assert!(validated.is_finite() && validated < 5.0, "{validated}");
    assert!(
        (validated - predicted).abs() < 1e-12,
        "identify {validated}, predict {predicted}"
    );
}

/// The `terms` of an identify summary.json.
fn term_names(s: &serde_json::Value) -> Vec<&str> {
    s["terms"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t.as_str().unwrap())
        .collect()
}

/// An online structure on the cascaded tanks through the commands: `rhonn identify` of
/// `spec` on estimation.csv validated on validation.csv (free run and 10 samples ahead),
/// ARX(2,2) fitted by `rhonn fit` on the same file and run free, and `rhonn predict` of
/// the identified model.json, which must give the validation's figures. Returns the
/// summary, the free-run and 10-ahead RMS errors and the ARX's.
fn tanks_online(spec: &str) -> (serde_json::Value, f64, f64, f64) {
    let d = tempfile::tempdir().unwrap();
    let data = repo().join("data/cascaded-tanks");
    let (est, val) = (data.join("estimation.csv"), data.join("validation.csv"));
    let (est, val) = (est.to_str().unwrap(), val.to_str().unwrap());
    let spec = repo().join(spec);
    let o = rhonn(
        d.path(),
        &[
            "identify",
            "--data",
            est,
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--model",
            spec.to_str().unwrap(),
            "--validate",
            val,
            "--steps-ahead",
            "10",
            "--out",
            "id",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let read = |f: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.path().join(f)).unwrap()).unwrap()
    };
    let s = read("id/summary.json");
    let free = s["validation"][0]["free_run_rms_error"].as_f64().unwrap();
    let ahead = s["validation"][0]["ahead_rms_error"].as_f64().unwrap();
    std::fs::write(d.path().join("arx.toml"), "kind = \"arx\"\nna = 2\nnb = 2\n").unwrap();
    let o = rhonn(
        d.path(),
        &[
            "fit",
            "--model",
            "arx.toml",
            "--data",
            est,
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--out",
            "arx",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    for (model, out, steps) in [
        ("arx/model.json", "pa", None),
        ("id/model.json", "p", None),
        ("id/model.json", "p10", Some("10")),
    ] {
        let mut args = vec!["predict", "--model", model, "--data", val, "--out", out];
        if let Some(k) = steps {
            args.extend(["--steps-ahead", k]);
        }
        let o = rhonn(d.path(), &args);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let arx = read("pa/summary.json")["outputs"][0]["rms_error"]
        .as_f64()
        .unwrap();
    let p = read("p/summary.json")["figures"][0]["rms_error"]
        .as_f64()
        .unwrap();
    let p10 = read("p10/summary.json")["figures"][0]["rms_error"]
        .as_f64()
        .unwrap();
    assert!(
        (p - free).abs() < 1e-12 && (p10 - ahead).abs() < 1e-12,
        "{p} {p10}"
    );
    if s["model"]["structure"] == "cascade" {
        // A hand-edited cascade whose output offset (its last weight) is 1e300: finite and
        // valid, but its free run's error overflows. Refused, nothing written (it was
        // written with a null error and exit 0).
        let mut m = read("id/model.json");
        let w = m["weights"][0].as_array_mut().unwrap();
        *w.last_mut().unwrap() = serde_json::json!(1e300);
        std::fs::write(d.path().join("huge.json"), m.to_string()).unwrap();
        let o = rhonn(
            d.path(),
            &["predict", "--model", "huge.json", "--data", val, "--out", "q"],
        );
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{e}");
        assert!(e.contains("huge.json") && e.contains("not finite"), "{e}");
        assert!(!d.path().join("q").exists());
    }
    (s, free, ahead, arx)
}

/// The lagged structure on the cascaded tanks (`models/tanks-online-lagged.toml`): the
/// README's figures, below the ARX(2,2) free run fitted in the same test, with its
/// terms named by lag, and `rhonn predict` of its model.json giving the validation's
/// figures.
#[test]
fn tanks_lagged_online_model_runs_free_below_arx_and_predicts_as_validated() {
    let (s, free, ahead, arx) = tanks_online("models/tanks-online-lagged.toml");
    // README figures: free run 0.641 V, 10 samples ahead 0.277 V.
    assert!((free - 0.641).abs() < 0.01, "{free}");
    assert!((ahead - 0.277).abs() < 0.01, "{ahead}");
    let terms = term_names(&s);
    assert!(
        terms.contains(&"y[k-3]") && terms.contains(&"tanh(y[k-1])*u[k-2]") && terms.contains(&"1"),
        "{terms:?}"
    );
    assert_eq!(s["model"]["structure"], "lagged");
    assert!(free < arx, "online lagged {free} V, ARX(2,2) {arx} V");
}

/// The cascade structure on the cascaded tanks (`models/tanks-online-cascade.toml`):
/// identified online on estimation.csv, frozen, it runs free on validation.csv within the
/// issue's goal (0.35 V) and far below ARX(2,2); the README's figures; its parameters
/// named; `rhonn predict` of its model.json giving the validation's figures.
#[test]
fn tanks_cascade_online_model_runs_free_within_the_goal() {
    let (s, free, ahead, arx) = tanks_online("models/tanks-online-cascade.toml");
    eprintln!("online cascade: free run {free} V, 10 ahead {ahead} V, ARX(2,2) {arx} V");
    assert!(free < 0.35, "free run {free} V");
    assert!(free < 0.6 * arx, "online cascade {free} V, ARX(2,2) {arx} V");
    // README figures: free run 0.243 V, 10 samples ahead 0.180 V.
    assert!((free - 0.243).abs() < 0.01, "{free}");
    assert!((ahead - 0.180).abs() < 0.01, "{ahead}");
    assert_eq!(s["model"]["structure"], "cascade");
    let terms = term_names(&s);
    assert_eq!(
        terms,
        ["b[u]", "k1", "k2", "alpha1", "alpha2", "g1", "o1", "xmax1", "xmax2", "c"]
    );
}

/// The Wiener-Hammerstein structure on the cascaded tanks (fitted on the first 600
/// samples, then its polynomial learned by recursive least squares): `rhonn predict` of
/// its model.json gives the validation's figures (free run and 10 ahead), it runs free
/// below the ARX(2,2), its parameters are named; with the default window (5,000 samples,
/// more than the file's 1,024) it is refused, naming the window, and nothing is written.
#[test]
fn tanks_wiener_hammerstein_online_model_predicts_as_validated_and_a_long_window_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let spec = d.path().join("wh.toml");
    std::fs::write(
        &spec,
        "structure = \"wiener-hammerstein\"\nblock = { poles = 2, degree = 3, window = 600 }\noutput_margin = 0.5\n",
    )
    .unwrap();
    let (s, free, ahead, arx) = tanks_online(spec.to_str().unwrap());
    eprintln!("online wiener-hammerstein: free run {free} V, 10 ahead {ahead} V, ARX(2,2) {arx} V");
    assert!(free < arx, "online wiener-hammerstein {free} V, ARX(2,2) {arx} V");
    assert_eq!(s["model"]["structure"], "wiener-hammerstein");
    let terms = term_names(&s);
    assert!(
        terms.starts_with(&["u mean", "u deviation", "y mean", "y deviation"]) && terms.contains(&"c[3]"),
        "{terms:?}"
    );
    std::fs::write(d.path().join("long.toml"), "structure = \"wiener-hammerstein\"\n").unwrap();
    let est = repo().join("data/cascaded-tanks/estimation.csv");
    let o = rhonn(
        d.path(),
        &[
            "identify",
            "--data",
            est.to_str().unwrap(),
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--model",
            "long.toml",
            "--out",
            "long",
        ],
    );
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("window of 5000 samples (`block.window`)") && e.contains("learned 1024 samples"),
        "{e}"
    );
    assert!(!d.path().join("long").exists());
}

#[test]
fn without_a_model_the_bank_picks_online_and_beats_the_offline_arx_on_the_tanks() {
    let d = tempfile::tempdir().unwrap();
    let data = repo().join("data/cascaded-tanks");
    let (est, val) = (data.join("estimation.csv"), data.join("validation.csv"));
    let o = rhonn(
        d.path(),
        &[
            "identify",
            "--data",
            est.to_str().unwrap(),
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--validate",
            val.to_str().unwrap(),
            "--units",
            "u=V,y=V",
            "--out",
            "o",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("o/summary.json")).unwrap()).unwrap();
    let sel = &s["selection"];
    let cands = sel["candidates"].as_array().unwrap();
    assert!(cands.len() >= 8, "{sel}");
    // Every candidate's prequential figures are listed; the winner has the lowest free-run one.
    let chosen = sel["chosen"].as_u64().unwrap() as usize;
    let best = cands
        .iter()
        .filter_map(|c| c["free_run_nrmse"].as_f64())
        .fold(f64::INFINITY, f64::min);
    assert_eq!(cands[chosen]["free_run_nrmse"].as_f64().unwrap(), best);
    assert!(cands
        .iter()
        .any(|c| c["name"].as_str().unwrap().starts_with("recursive ARX")));
    // The offline ARX (lags by cross-validation on estimation.csv) beside it, per record.
    let b = &s["baseline_arx"]["records"][0];
    let (online, arx) = (
        b["online_rms_error"].as_f64().unwrap(),
        b["arx_rms_error"].as_f64().unwrap(),
    );
    assert!(online < arx, "online {online} V, ARX {arx} V");
    // The README's figure (the winner, the cascade, trained for its 8 passes): 0.2368 V,
    // within 1.5 x rhonn fit's default (0.222 V); both scored from sample 5, after the 5
    // outputs the cascade's free run reads (the ARX's 4 lags would allow sample 4).
    assert_eq!(b["from_sample"].as_u64(), Some(5), "{b}");
    assert!((online - 0.2368).abs() < 0.01, "{online}");
    // Normalised by the warm-up window (the first half of estimation.csv), said so.
    assert_eq!(sel["warmup"].as_u64(), Some(512), "{sel}");
    assert!(online < 1.5 * 0.222, "{online}");
    let findings = s["findings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap())
        .collect::<Vec<_>>()
        .join("\n");
    assert!(
        findings.contains("online selection:") && findings.contains("below the offline ARX"),
        "{findings}"
    );
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("offline ARX (na"), "{out}");
    // The console names the winner, then its margin over the best recursive ARX.
    let winner = cands[chosen]["name"].as_str().unwrap();
    let first = out.lines().next().unwrap_or("");
    assert!(
        first.starts_with(&format!(
            "online selection: {winner} of {} candidates won",
            cands.len()
        )),
        "{out}"
    );
    assert!(
        out.contains("lower prequential free-run error than the best recursive ARX"),
        "{out}"
    );
    // --units as in fit: on the figures, in summary.json and on the plots' axes.
    assert!(out.contains(" V, fit") && s["units"]["y"] == "V", "{out}");
    for svg in ["estimate.svg", "validation.svg"] {
        let text = std::fs::read_to_string(d.path().join("o").join(svg)).unwrap();
        assert!(text.contains("y [V]"), "{svg} has no unit on its axis");
    }
}

/// One spec for `fit` and `identify` where their kinds overlap: a `fit` ARX spec given to
/// `identify` is the recursive ARX of the same lags; a `fit` spec with an offline-only
/// key is refused naming it; an `identify` lagged spec given to `fit` is the same lagged
/// RHONN; the continuous-time neurons, online only, are refused by `fit` saying so.
#[test]
fn a_spec_of_fit_works_in_identify_and_the_reverse_or_names_the_keys_that_differ() {
    let d = tempfile::tempdir().unwrap();
    let est = repo().join("data/cascaded-tanks/estimation.csv");
    let est = est.to_str().unwrap();
    let run = |cmd: &str, spec: &str, text: Option<&str>, out: &str| {
        let path = d.path().join(spec);
        if let Some(t) = text {
            std::fs::write(&path, t).unwrap();
        }
        let p = path.to_str().unwrap().to_string();
        rhonn(
            d.path(),
            &[
                cmd,
                "--data",
                est,
                "--inputs",
                "u",
                "--outputs",
                "y",
                "--model",
                &p,
                "--out",
                out,
            ],
        )
    };
    let o = run(
        "identify",
        "arx.toml",
        Some("kind = \"arx\"\nna = 4\nnb = 4\n"),
        "a",
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("a/model.json")).unwrap()).unwrap();
    assert_eq!(m["model"]["structure"], "lagged");
    assert_eq!(
        (m["model"]["lags"]["na"].as_u64(), m["model"]["degree"].as_u64()),
        (Some(4), Some(1))
    );
    // 4 output lags, 4 input lags and the constant: an ARX.
    assert_eq!(m["weights"][0].as_array().unwrap().len(), 9);
    let o = run(
        "identify",
        "sim.toml",
        Some("na = 3\nlaw = \"simulation-error\"\nridge = 1e-4\n"),
        "b",
    );
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("sim.toml") && e.contains("law = \"simulation-error\"") && e.contains("ridge = 0.0001"),
        "{e}"
    );
    assert!(!d.path().join("b").exists());
    let lagged = repo().join("models/tanks-online-lagged.toml");
    std::fs::copy(&lagged, d.path().join("lagged.toml")).unwrap();
    let o = run("fit", "lagged.toml", None, "c");
    assert!(o.status.success(), "{}", stderr(&o));
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("c/model.json")).unwrap()).unwrap();
    let spec = &m["model"]["spec"];
    assert_eq!(
        (spec["kind"].as_str(), spec["na"].as_u64(), spec["nb"].as_u64()),
        (Some("rhonn"), Some(3), Some(2)),
        "{spec}"
    );
    std::fs::copy(
        repo().join("models/tanks-online.toml"),
        d.path().join("cont.toml"),
    )
    .unwrap();
    let o = run("fit", "cont.toml", None, "e");
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("cont.toml") && e.contains("online only"), "{e}");
}

/// Issue 56: a file with one glitch (y = 1e10 at row 500) is learned as the clean file is,
/// the glitch skipped and said, and the ARX baseline is not poisoned by it either.
#[test]
fn a_glitch_in_a_recording_is_skipped_and_said_not_learned() {
    let d = tempfile::tempdir().unwrap();
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let text = std::fs::read_to_string(root.join("data/cascaded-tanks/estimation.csv")).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let mut cells: Vec<String> = lines[501].split(',').map(str::to_string).collect();
    cells[2] = "1e10".into();
    lines[501] = cells.join(",");
    std::fs::write(d.path().join("glitch.csv"), lines.join("\n") + "\n").unwrap();
    let rms = |data: &Path, out: &str| {
        let o = rhonn(
            d.path(),
            &[
                "identify",
                "--data",
                data.to_str().unwrap(),
                "--model",
                root.join("models/tanks-online-lagged.toml").to_str().unwrap(),
                "--validate",
                root.join("data/cascaded-tanks/validation.csv").to_str().unwrap(),
                "--inputs",
                "u",
                "--outputs",
                "y",
                "--out",
                out,
            ],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.path().join(out).join("summary.json")).unwrap())
                .unwrap();
        let frozen = s["validation"][0]["free_run_rms_error"].as_f64().unwrap();
        let arx = s["baseline_arx"]["records"][0]["arx_rms_error"].as_f64();
        (frozen, arx, stderr(&o))
    };
    let (clean, clean_arx, e) = rms(&root.join("data/cascaded-tanks/estimation.csv"), "clean");
    assert!(!e.contains("skipped"), "{e}");
    let (glitched, glitched_arx, e) = rms(&d.path().join("glitch.csv"), "glitched");
    assert!(e.contains("t = 2000 s was skipped") && e.contains("1e10"), "{e}");
    assert!((glitched / clean - 1.0).abs() <= 0.05, "{clean} vs {glitched}");
    let (a, b) = (clean_arx.unwrap(), glitched_arx.unwrap());
    assert!(b < 2.0 * a, "the ARX baseline learned the glitch: {a} vs {b}");
}

/// Options that would do nothing are refused or warned about, never ignored.
#[test]
fn steps_ahead_without_validation_is_refused_and_an_output_as_input_is_warned() {
    let d = tempfile::tempdir().unwrap();
    let est = repo().join("data/cascaded-tanks/estimation.csv");
    let est = est.to_str().unwrap();
    let spec = repo().join("models/tanks-online.toml");
    let args = |extra: &[&'static str], io: [&'static str; 2]| {
        let mut a = vec!["identify", "--data", est, "--inputs", io[0], "--outputs", io[1]];
        a.extend_from_slice(&["--model", spec.to_str().unwrap()]);
        a.extend_from_slice(extra);
        a.iter().map(|s| s.to_string()).collect::<Vec<String>>()
    };
    let run = |a: Vec<String>| rhonn(d.path(), &a.iter().map(String::as_str).collect::<Vec<_>>());
    let o = run(args(&["--steps-ahead", "5", "--out", "k"], ["u", "y"]));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("--steps-ahead 5") && err.contains("--validate"),
        "{err}"
    );
    assert!(!d.path().join("k").exists());
    let o = run(args(&["--out", "same"], ["y", "y"]));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("warning: `y` is both an input and an output"),
        "{}",
        stderr(&o)
    );
}

/// Two outputs of different nature side by side, as CSV: `y1` a linear lag of `u1`, `y2`
/// a nonlinear system driven by `u2` (steps every 9 and 13 samples, from `seed`).
pub(crate) fn two_outputs_csv(path: &Path, n: usize, seed: u64) {
    let mut s = seed;
    let mut next = move || {
        // A small linear congruential generator: the test needs varied steps, not quality.
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((s >> 33) as f64 / (1u64 << 31) as f64) * 2.0 - 1.0
    };
    let (mut y1, mut y2, mut u1, mut u2) = (0.0_f64, 0.0_f64, 0.0, 0.0);
    let mut text = String::from("t,u1,u2,y1,y2\n");
    for k in 0..n {
        if k % 13 == 0 {
            u1 = next();
        }
        if k % 9 == 0 {
            u2 = 2.0 * next();
        }
        text.push_str(&format!("{},{u1},{u2},{y1},{y2}\n", k as f64 * 0.1));
        y1 = 0.9 * y1 + 0.2 * u1;
        y2 = 0.8 * y2 + 0.3 * u2 + 0.4 * u2 * (2.0 * y2).tanh();
    }
    std::fs::write(path, text).unwrap();
}

/// With several outputs each output has its own bank: an output whose own winner runs
/// free better than the joint winner takes it, model.json holds the `per-output`
/// structure, weights.csv names its weights, and `rhonn predict` gives the validation's
/// figures.
#[test]
fn two_outputs_of_different_nature_each_get_their_own_structure_and_predict_as_validated() {
    let d = tempfile::tempdir().unwrap();
    two_outputs_csv(&d.path().join("two.csv"), 3000, 3);
    two_outputs_csv(&d.path().join("val.csv"), 1500, 4);
    let io = ["--inputs", "u1,u2", "--outputs", "y1,y2"];
    let mut args = vec![
        "identify",
        "--data",
        "two.csv",
        "--validate",
        "val.csv",
        "--out",
        "id",
    ];
    args.extend(io);
    let o = rhonn(d.path(), &args);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(out.contains("from a structure of its own"), "{out}");
    let read = |f: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.path().join(f)).unwrap()).unwrap()
    };
    let (s, m) = (read("id/summary.json"), read("id/model.json"));
    let by = s["selection"]["by_output"].as_array().unwrap();
    let names: Vec<&str> = by.iter().map(|o| o["output"].as_str().unwrap()).collect();
    assert_eq!(names, ["y1", "y2"]);
    let own: Vec<usize> = (0..2).filter(|&j| by[j]["own"].as_bool().unwrap()).collect();
    assert!(!own.is_empty(), "{by:?}");
    assert_eq!(m["model"]["structure"], "per-output");
    let parts = m["model"]["per_output"]["own"].as_array().unwrap();
    assert_eq!(
        parts
            .iter()
            .map(|p| p["output"].as_u64().unwrap() as usize)
            .collect::<Vec<_>>(),
        own
    );
    assert_eq!(m["own_y_bounds"].as_array().unwrap().len(), own.len());
    let header = std::fs::read_to_string(d.path().join("id/weights.csv")).unwrap();
    let header = header.lines().next().unwrap().to_string();
    // (Weights are listed one by one only when they are few: then each part's are.)
    if header.contains("w_y1_0") {
        for j in &own {
            assert!(header.contains(&format!("w_y{}_own_0", j + 1)), "{header}");
        }
    }
    let o = rhonn(
        d.path(),
        &[
            "predict",
            "--model",
            "id/model.json",
            "--data",
            "val.csv",
            "--out",
            "p",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let p = read("p/summary.json");
    for j in 0..2 {
        let validated = s["validation"][j]["free_run_rms_error"].as_f64().unwrap();
        let predicted = p["figures"][j]["rms_error"].as_f64().unwrap();
        assert!(
            (validated - predicted).abs() <= 1e-12 * validated.abs().max(1e-12),
            "y{}: identify {validated}, predict {predicted}",
            j + 1
        );
    }
}
