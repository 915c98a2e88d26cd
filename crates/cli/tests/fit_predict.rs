//! `rhonn fit` and `rhonn predict` from the command line: files, figures against the ARX
//! baseline, bad data, cascade models, and the measured benchmarks (cascaded tanks, pump).

use crate::util;

use std::path::Path;
use util::{files_in, rhonn, stderr};

/// A small nonlinear record: y(k) = 0.6 y(k-1) + 0.3 u(k-1) + 0.3 tanh(y(k-1)) u(k-1).
fn write_record(path: &Path, seed: u64, n: usize) {
    let mut s = seed;
    let mut text = String::from("t,u,y\n");
    let (mut y, mut u) = (0.0f64, 0.0f64);
    for k in 0..n {
        if k % 9 == 0 {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            u = ((s >> 33) as f64 / (1u64 << 31) as f64) * 2.0 - 1.0;
        }
        text.push_str(&format!("{},{},{}\n", k as f64 * 0.5, u, y));
        y = 0.6 * y + 0.3 * u + 0.3 * y.tanh() * u;
    }
    std::fs::write(path, text).unwrap();
}

/// The files `rhonn predict` writes for a model of `rhonn fit`.
const PREDICTION_FILES: [&str; 8] = [
    "prediction.csv",
    "prediction.svg",
    "prediction_zoom.svg",
    "report.html",
    "residual_histogram.svg",
    "residuals.svg",
    "rhonn-manifest.json",
    "summary.json",
];
#[test]
fn fit_then_predict_on_unseen_data_writes_model_prediction_and_figures() {
    let d = tempfile::tempdir().unwrap();
    write_record(&d.path().join("train.csv"), 1, 600);
    write_record(&d.path().join("train2.csv"), 3, 300);
    write_record(&d.path().join("val.csv"), 2, 400);
    let o = rhonn(
        d.path(),
        &[
            "fit",
            "--data",
            "train.csv",
            "--data",
            "train2.csv",
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--out",
            "m",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        files_in(&d.path().join("m")),
        [
            "model.json",
            "report.html",
            "rhonn-manifest.json",
            "summary.json",
            "training_0.svg",
            "training_1.svg"
        ]
    );
    let o = rhonn(
        d.path(),
        &[
            "predict",
            "--model",
            "m/model.json",
            "--data",
            "val.csv",
            "--out",
            "p",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(files_in(&d.path().join("p")), PREDICTION_FILES);
    let csv = std::fs::read_to_string(d.path().join("p/prediction.csv")).unwrap();
    assert!(csv.starts_with("t,y,y_hat,y_hat_arx\n"));
    assert_eq!(csv.lines().count(), 401);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("p/summary.json")).unwrap()).unwrap();
    let fit = s["outputs"][0]["fit_percent"].as_f64().unwrap();
    let arx = s["baseline_arx"][0]["fit_percent"].as_f64().unwrap();
    assert!(fit > 90.0 && fit > arx, "rhonn {fit} %, arx {arx} %");
    assert!(s["outputs"][0]["nrmse"].as_f64().unwrap() > 0.0);
    // One step ahead, from the measured outputs.
    let o = rhonn(
        d.path(),
        &[
            "predict",
            "--model",
            "m/model.json",
            "--data",
            "val.csv",
            "--out",
            "p1",
            "--steps-ahead",
            "1",
        ],
    );
    assert!(o.status.success());
    let s1: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("p1/summary.json")).unwrap()).unwrap();
    // The least-squares ARX baseline, the best one-step predictor of its structure, tracks
    // better one step ahead than in free run. The chosen model was trained on its free-run
    // error (a polynomial RHONN here), so its one-step error need not be the lower of its
    // two (0.001926 against 0.001884 RMS when written): it must stay as near-perfect.
    let arx1 = s1["baseline_arx"][0]["fit_percent"].as_f64().unwrap();
    assert!(arx1 > arx + 10.0, "ARX one step {arx1} %, free run {arx} %");
    assert!(s1["outputs"][0]["fit_percent"].as_f64().unwrap() > 99.0, "{s1}");
    assert_eq!(s1["steps_ahead"], 1);
    // A model.json whose sample time leaves the data too few samples on its grid: the error
    // names the key, readably (found by a mutation run: 1e300 was written out in 301 digits).
    let text = std::fs::read_to_string(d.path().join("m/model.json")).unwrap();
    let mut j: serde_json::Value = serde_json::from_str(&text).unwrap();
    j["model"]["sample_time_s"] = serde_json::json!(1e300);
    // The baseline's with it: the two were fitted together (an edit of one alone is refused).
    j["baseline"]["sample_time_s"] = serde_json::json!(1e300);
    std::fs::write(d.path().join("big.json"), j.to_string()).unwrap();
    let o = rhonn(
        d.path(),
        &[
            "predict", "--model", "big.json", "--data", "val.csv", "--out", "pb",
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("model.sample_time_s = 1e300 s") && e.len() < 400,
        "{e}"
    );
    assert!(!d.path().join("pb").exists());
    // A grid of nanoseconds: refused naming the key, not a crash filling the memory (found
    // by a mutation run: 8e11 samples were allocated), from the model and from --resample.
    j["model"]["sample_time_s"] = serde_json::json!(1e-9);
    j["baseline"]["sample_time_s"] = j["model"]["sample_time_s"].clone();
    std::fs::write(d.path().join("fine.json"), j.to_string()).unwrap();
    let o = rhonn(
        d.path(),
        &[
            "predict",
            "--model",
            "fine.json",
            "--data",
            "val.csv",
            "--out",
            "pf",
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("`model.sample_time_s` = 1e-9 is not allowed"),
        "{}",
        stderr(&o)
    );
    let args = [
        "fit",
        "--data",
        "val.csv",
        "--inputs",
        "u",
        "--outputs",
        "y",
        "--out",
        "fr",
    ];
    let o = rhonn(d.path(), &[&args[..], &["--resample", "1e-9"]].concat());
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("`--resample` = 1e-9 is not allowed"),
        "{}",
        stderr(&o)
    );
    assert!(!d.path().join("pf").exists() && !d.path().join("fr").exists());
}

#[test]
fn bad_data_names_file_line_and_column_and_writes_nothing() {
    let d = tempfile::tempdir().unwrap();
    let cases = [
        (
            "t,u,y\n0,1,2\n1,x,3\n",
            "bad.csv, line 3, column `u`: `x` is not a number: give a number with a decimal point",
        ),
        (
            "t,u\n0,1\n1,2\n",
            "bad.csv: no column `y` in the header (columns: t, u)",
        ),
        (
            "t,u,y\n0,1,2\n2,1,2\n1,1,2\n",
            "bad.csv, line 4, column `t`: time 1 does not increase (previous 2)",
        ),
        (
            "t,u,y\n0,1,inf\n",
            "line 2, column `y`: `inf` is not a finite number",
        ),
        ("t,u,y\n0,1,2\n1,1,2\n", "bad.csv: 2 data rows; at least"),
    ];
    for (k, (text, expected)) in cases.iter().enumerate() {
        std::fs::write(d.path().join("bad.csv"), text).unwrap();
        let o = rhonn(
            d.path(),
            &[
                "fit",
                "--data",
                "bad.csv",
                "--inputs",
                "u",
                "--outputs",
                "y",
                "--out",
                "m",
            ],
        );
        assert_eq!(o.status.code(), Some(2), "case {k}");
        assert!(
            stderr(&o).contains(expected),
            "case {k}: expected `{expected}` in:\n{}",
            stderr(&o)
        );
        assert!(!d.path().join("m").exists(), "case {k} wrote output");
    }
    let o = rhonn(
        d.path(),
        &[
            "predict",
            "--model",
            "nope.json",
            "--data",
            "bad.csv",
            "--out",
            "p",
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("cannot read nope.json"));
}

/// A `cascade` model (continuous-time RHONN with hidden states): bad structures are
/// clear errors naming the key; it runs free, and a K-step prediction is refused with
/// nothing written.
#[test]
fn cascade_models_run_free_and_bad_cascade_specs_are_clear_errors() {
    let d = tempfile::tempdir().unwrap();
    write_record(&d.path().join("train.csv"), 1, 300);
    let fit = |spec: &str, outputs: &str| {
        std::fs::write(d.path().join("c.toml"), spec).unwrap();
        rhonn(
            d.path(),
            &[
                "fit",
                "--data",
                "train.csv",
                "--inputs",
                "u",
                "--outputs",
                outputs,
                "--model",
                "c.toml",
                "--out",
                "m",
            ],
        )
    };
    for (spec, outputs, expected) in [
        (
            "kind = \"cascade\"\nneurons = 9\n",
            "y",
            "`model.neurons` = 9 is not allowed: an integer in [1, 4]",
        ),
        (
            "kind = \"cascade\"\nsettle = 1\n",
            "y",
            "`model.settle` = 1 is not allowed: an integer in [2, 1000]",
        ),
        (
            // 2,000 starts ran for minutes on a short record (the mutation harness's hang).
            "kind = \"cascade\"\nstarts = 2000\n",
            "y",
            "`model.starts` = 2000 is not allowed: an integer in [1, 256]",
        ),
        (
            "kind = \"cascade\"\ninput_filters_s = [10.0]\n",
            "y",
            "`model.input_filters_s`",
        ),
        (
            "kind = \"cascade\"\n",
            "y,u",
            "exactly one output for a `cascade` model",
        ),
        (
            "kind = \"cascade\"\nlaw = \"rls\"\n",
            "y",
            "`model.law` = rls is not allowed: simulation-error",
        ),
    ] {
        let o = fit(spec, outputs);
        assert_eq!(o.status.code(), Some(2), "{spec}");
        assert!(
            stderr(&o).contains(expected),
            "expected `{expected}` in:\n{}",
            stderr(&o)
        );
        assert!(!d.path().join("m").exists(), "{spec} wrote output");
    }
    let o = fit("kind = \"cascade\"\nstarts = 2\nepochs = 5\n", "y");
    assert!(o.status.success(), "{}", stderr(&o));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("m/summary.json")).unwrap()).unwrap();
    let one = s["training"]["one_step"][0]["outputs"][0]["rms_error"]
        .as_f64()
        .unwrap();
    let free = s["training"]["free_run"][0]["outputs"][0]["rms_error"]
        .as_f64()
        .unwrap();
    assert!(one > 0.0 && free > 0.0);
    let predict = |extra: &[&str]| {
        let mut args = vec![
            "predict",
            "--model",
            "m/model.json",
            "--data",
            "train.csv",
            "--out",
            "p",
        ];
        args.extend_from_slice(extra);
        rhonn(d.path(), &args)
    };
    for extra in [&[][..], &["--steps-ahead", "3"][..]] {
        let o = predict(extra);
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(files_in(&d.path().join("p")), PREDICTION_FILES);
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.path().join("p/summary.json")).unwrap()).unwrap();
        assert_eq!(
            s["steps_ahead"].as_u64(),
            extra.get(1).map(|k| k.parse().unwrap())
        );
        std::fs::remove_dir_all(d.path().join("p")).unwrap();
    }
}

/// The cascaded tanks benchmark with the shipped model structure (chosen on
/// estimation.csv alone): the free-run RMS error on validation.csv is below the
/// polynomial NARX's published 0.41 V (the issue's target) and below the ARX baseline by
/// a wide margin. The data ships in the repository (data/cascaded-tanks); a missing
/// file is a failure, never a skip.
#[test]
fn cascaded_tanks_free_run_beats_narx_and_arx_on_validation() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let data = root.join("data/cascaded-tanks");
    for f in ["estimation.csv", "validation.csv"] {
        assert!(
            data.join(f).is_file(),
            "{} is missing from the repository",
            data.join(f).display()
        );
    }
    let d = tempfile::tempdir().unwrap();
    let est = data.join("estimation.csv");
    let val = data.join("validation.csv");
    let spec = root.join("models/cascaded-tanks.toml");
    let o = rhonn(
        d.path(),
        &[
            "fit",
            "--data",
            est.to_str().unwrap(),
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--model",
            spec.to_str().unwrap(),
            "--out",
            "m",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    // (How often a long fit prints signs of life depends on how long it takes: nothing
    // here is asserted on the machine's speed.)
    let o = rhonn(
        d.path(),
        &[
            "predict",
            "--model",
            "m/model.json",
            "--data",
            val.to_str().unwrap(),
            "--out",
            "p",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("p/summary.json")).unwrap()).unwrap();
    let rms = s["outputs"][0]["rms_error"].as_f64().unwrap();
    let arx = s["baseline_arx"][0]["rms_error"].as_f64().unwrap();
    eprintln!("cascaded tanks free-run RMS error on validation: RHONN {rms:.4} V, ARX {arx:.4} V");
    assert!(rms < 0.41, "RHONN {rms} V");
    assert!(rms < 0.5 * arx, "RHONN {rms} V, ARX {arx} V");
}

/// The pump with the shipped model structure (models/pump.toml, the grey box, chosen on
/// pump-identify alone): trained on pump-identify, it predicts pump-validate's measured
/// pressure 10 steps (50 ms) ahead at the README's 97.7 % (pinned within 0.5 points),
/// far ahead of the ARX baseline with the same lags; on the stress records it never saw
/// it holds within 3 points of that. The direct RHONN predictor (models/pump-direct.toml)
/// stays above 80 % and ahead of its ARX.
#[test]
fn pump_model_predicts_the_validation_record_10_steps_ahead() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let d = tempfile::tempdir().unwrap();
    // Run rhonn in d; it must succeed.
    let ok = |args: &[&str]| {
        let o = rhonn(d.path(), args);
        assert!(o.status.success(), "{}", stderr(&o));
        o
    };
    // 10 steps ahead with the trained model on `data` into `out`: (model fit, ARX fit, run).
    let predict = |data: &str, out: &str| {
        let o = ok(&[
            "predict",
            "--model",
            "m/model.json",
            "--data",
            data,
            "--out",
            out,
            "--steps-ahead",
            "10",
        ]);
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.path().join(out).join("summary.json")).unwrap())
                .unwrap();
        let fit = s["outputs"][0]["fit_percent"].as_f64().unwrap();
        let arx = s["baseline_arx"][0]["fit_percent"].as_f64().unwrap();
        (fit, arx, o)
    };
    for sc in ["pump-identify", "pump-validate"] {
        ok(&["run", sc, "--out", sc]);
    }
    let fit_model = |spec: &str| -> String {
        let spec = root.join(spec);
        stderr(&ok(&[
            "fit",
            "--data",
            "pump-identify/trajectory.csv",
            "--inputs",
            "current,demand",
            "--outputs",
            "p_line_measured",
            "--model",
            spec.to_str().unwrap(),
            "--out",
            "m",
            // One folder for both structures: each replaces the other.
            "--force",
        ]))
    };
    // The direct predictor drifts to its output bound in free run, and `fit` says so.
    let e = fit_model("models/pump-direct.toml");
    assert!(
        e.contains("warning: the model's free run on") && e.contains("reaches the bound"),
        "{e}"
    );
    let (fit, arx, _) = predict("pump-validate/trajectory.csv", "p");
    eprintln!("pump, 10 steps ahead on pump-validate: direct RHONN fit {fit:.2} %, ARX {arx:.2} %");
    assert!(fit >= 80.0 && fit > arx, "direct RHONN fit {fit} %, ARX {arx} %");
    let e = fit_model("models/pump.toml");
    assert!(!e.contains("reaches the bound"), "{e}");
    let (fit, arx, _) = predict("pump-validate/trajectory.csv", "p");
    eprintln!("pump, 10 steps ahead on pump-validate: grey box fit {fit:.2} %, ARX {arx:.2} %");
    assert!((fit - 98.0).abs() < 0.5, "grey box fit {fit} %");
    assert!(fit > arx + 10.0, "grey box fit {fit} %, ARX {arx} %");
    // rhonn's own SI columns are plotted in display units.
    let svg = std::fs::read_to_string(d.path().join("p/prediction.svg")).unwrap();
    assert!(svg.contains("p_line_measured [MPa]"), "no MPa axis");
    // The same record written every 1 ms is put on the model's 5 ms grid, with a note:
    // the same prediction.
    let o = ok(&["show", "pump-validate"]);
    let toml = String::from_utf8(o.stdout)
        .unwrap()
        .replace("output_interval_s = 0.005", "output_interval_s = 0.001");
    assert!(toml.contains("output_interval_s = 0.001"));
    std::fs::write(d.path().join("v1.toml"), toml).unwrap();
    ok(&["run", "v1.toml", "--out", "v1"]);
    let (fit1, _, o) = predict("v1/trajectory.csv", "p1");
    assert!(
        stderr(&o).contains("is sampled every 0.001 s; predicting on the model's grid of 0.005 s"),
        "{}",
        stderr(&o)
    );
    assert!(
        (fit1 - fit).abs() < 0.05,
        "1 ms record {fit1} %, 5 ms record {fit} %"
    );
    // Records with excitations and noise the model never saw (scenarios/stress): within
    // 3 points of pump-validate's fit and ahead of the ARX baseline on each.
    for (k, name) in ["stress-multisine", "stress-noise", "stress-nodither"]
        .iter()
        .enumerate()
    {
        let sc = root.join(format!("scenarios/stress/{name}.toml"));
        ok(&["run", sc.to_str().unwrap(), "--out", name]);
        let (fit_s, arx, _) = predict(&format!("{name}/trajectory.csv"), &format!("s{k}"));
        eprintln!("{name}: grey box fit {fit_s:.2} %, ARX {arx:.2} %");
        assert!(
            (fit_s - fit).abs() < 3.0 && fit_s > arx,
            "{name}: grey box {fit_s} %, pump-validate {fit} %, ARX {arx} %"
        );
    }
}

/// The grey-box pump model (`kind = "pump"`) identifies parameters it does not start
/// at: on a pump-identify record of a pump whose bulk modulus, leakage and pilot flow
/// coefficient are off the thesis's table (within its tolerances), `rhonn fit` with
/// models/pump.toml starts from the table and recovers each within 2 %; the model
/// predicts that pump 10 steps ahead above 95 %.
#[test]
fn pump_grey_box_recovers_perturbed_parameters() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let d = tempfile::tempdir().unwrap();
    let ok = |args: &[&str]| {
        let o = rhonn(d.path(), args);
        assert!(o.status.success(), "{}", stderr(&o));
        o
    };
    let shown = String::from_utf8(ok(&["show", "pump-identify"]).stdout).unwrap();
    assert!(!shown.contains("beta_mpa"), "{shown}");
    let toml = shown
        .replace("name = \"pump-identify\"", "name = \"off-table\"")
        .replace(
            "kind = \"pump\"",
            "kind = \"pump\"\nbeta_mpa = 1000.0\nq_0_dm3_s = 0.14\nmu_1 = 9.0e-5",
        );
    std::fs::write(d.path().join("off.toml"), toml).unwrap();
    ok(&["run", "off.toml", "--out", "off"]);
    let spec = root.join("models/pump.toml");
    ok(&[
        "fit",
        "--data",
        "off/trajectory.csv",
        "--inputs",
        "current,demand",
        "--outputs",
        "p_line_measured",
        "--model",
        spec.to_str().unwrap(),
        "--out",
        "m",
    ]);
    // summary.json names every parameter (SI); model.json stores them in the same order.
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("m/summary.json")).unwrap()).unwrap();
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("m/model.json")).unwrap()).unwrap();
    assert_eq!(s["parameters"].as_object().unwrap().len(), 18);
    for (name, j, truth) in [("beta", 1, 1.0e9), ("q_0", 5, 0.14e-3), ("mu_1", 7, 9.0e-5)] {
        let v = s["parameters"][name].as_f64().unwrap();
        assert_eq!(v, m["model"]["weights"][0][j].as_f64().unwrap(), "{name}");
        let rel = v / truth - 1.0;
        eprintln!("{name}: fitted {v} (truth {truth}), {:+.3} %", 100.0 * rel);
        assert!(rel.abs() < 0.02, "{name}: fitted {v}, truth {truth}");
    }
    assert_eq!(
        s["parameters"]["mu_2"].as_f64(),
        Some(7.8e-5),
        "mu_2 is not estimated"
    );
    ok(&[
        "predict",
        "--model",
        "m/model.json",
        "--data",
        "off/trajectory.csv",
        "--out",
        "p",
        "--steps-ahead",
        "10",
    ]);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("p/summary.json")).unwrap()).unwrap();
    let fit = s["outputs"][0]["fit_percent"].as_f64().unwrap();
    assert!(fit > 95.0, "10 steps ahead: {fit} %");
}

/// A `pump` model reads SI: a pressure column in MPa is refused with the column, the
/// file and what to do, and nothing is written.
#[test]
fn pump_grey_box_refuses_a_pressure_in_mpa() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let d = tempfile::tempdir().unwrap();
    let mut text = String::from("t,current,demand,p_mpa\n");
    for k in 0..400 {
        text.push_str(&format!(
            "{},0.3,0.0005,{}\n",
            k as f64 * 0.005,
            10.0 + (k as f64 * 0.1).sin()
        ));
    }
    std::fs::write(d.path().join("mpa.csv"), text).unwrap();
    let spec = root.join("models/pump.toml");
    let o = rhonn(
        d.path(),
        &[
            "fit",
            "--data",
            "mpa.csv",
            "--inputs",
            "current,demand",
            "--outputs",
            "p_mpa",
            "--model",
            spec.to_str().unwrap(),
            "--out",
            "m",
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("p_mpa") && e.contains("mpa.csv") && e.contains("multiply MPa by 1e6"),
        "{e}"
    );
    assert!(!d.path().join("m").exists());
}

/// A system the project never modelled, as CSV: `n` samples of a Wiener-Hammerstein
/// chain (`inputs = 1`) or of a bilinear two-input system (`inputs = 2`),
/// `rhonn::sysid::benchmarks`.
fn write_unseen(path: &Path, seed: u64, n: usize, inputs: usize) {
    use rhonn::sysid::benchmarks::{bilinear, to_csv, wiener_hammerstein};
    let r = if inputs == 1 {
        wiener_hammerstein(seed, n)
    } else {
        bilinear(seed, n)
    };
    std::fs::write(path, to_csv(&r)).unwrap();
}

/// `rhonn fit` with its defaults (structure selection) on two systems the project never
/// saw, 5,000 samples to train and 5,000 to test: no failure, a free run on the test
/// record at least as good as the ARX baseline it prints beside it, and the selection in
/// summary.json and on stderr.
#[test]
fn default_fit_on_unseen_systems_is_never_worse_than_arx() {
    let d = tempfile::tempdir().unwrap();
    for (inputs, cols) in [(1, "u"), (2, "u1,u2")] {
        write_unseen(&d.path().join("train.csv"), 10 + inputs as u64, 5000, inputs);
        write_unseen(&d.path().join("test.csv"), 20 + inputs as u64, 5000, inputs);
        let o = rhonn(
            d.path(),
            &[
                "fit",
                "--data",
                "train.csv",
                "--inputs",
                cols,
                "--outputs",
                "y",
                "--out",
                "m",
            ],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let e = stderr(&o);
        assert!(e.contains("selection: chose "), "{e}");
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.path().join("m/summary.json")).unwrap()).unwrap();
        let sel = &s["selection"];
        let chosen = sel["chosen"].as_u64().unwrap() as usize;
        let best_arx = sel["best_arx"].as_u64().unwrap() as usize;
        let score = |i: usize| sel["candidates"][i]["score"].as_f64().unwrap();
        assert!(score(chosen) <= score(best_arx), "{sel}");
        // The baseline beside the model is the selection's best ARX, fitted on all the
        // training data, not the ARX with the chosen model's lags.
        let arx_spec = &sel["candidates"][best_arx]["model"];
        let m: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.path().join("m/model.json")).unwrap()).unwrap();
        if chosen != best_arx {
            for key in ["kind", "na", "nb", "nk"] {
                assert_eq!(
                    m["baseline"]["spec"][key], arx_spec[key],
                    "{key}: {}",
                    m["baseline"]["spec"]
                );
            }
            assert_eq!(s["baseline_arx"]["chosen_as"], "best ARX on the folds");
            let lags = format!("na {} nb {} nk 1", arx_spec["na"], arx_spec["nb"]);
            let out = String::from_utf8_lossy(&o.stdout);
            assert!(
                out.contains(&format!("ARX baseline ({lags}, best ARX on the folds), free run")),
                "{out}"
            );
        } else {
            assert!(m["baseline"].is_null(), "{}", m["baseline"]);
        }
        let o = rhonn(
            d.path(),
            &[
                "predict",
                "--model",
                "m/model.json",
                "--data",
                "test.csv",
                "--out",
                "p",
            ],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        let p: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.path().join("p/summary.json")).unwrap()).unwrap();
        let fit = p["outputs"][0]["fit_percent"].as_f64().unwrap();
        let arx = p["baseline_arx"][0]["fit_percent"].as_f64().unwrap_or(fit);
        eprintln!(
            "{inputs} input(s): chose {}, free run on the test record {fit:.1} %, ARX baseline {arx:.1} %",
            sel["candidates"][chosen]["name"]
        );
        assert!(fit >= arx, "{inputs} input(s): model {fit} %, ARX {arx} %");
        std::fs::remove_dir_all(d.path().join("m")).unwrap();
        std::fs::remove_dir_all(d.path().join("p")).unwrap();
    }
}

/// `--select auto` and `--model` together are refused; `--select none` keeps the old
/// default structure (a RHONN with na = nb = 2) and writes no selection.
#[test]
fn select_options_are_checked() {
    let d = tempfile::tempdir().unwrap();
    write_record(&d.path().join("r.csv"), 1, 300);
    std::fs::write(d.path().join("arx.toml"), "kind = \"arx\"\n").unwrap();
    let base = [
        "fit",
        "--data",
        "r.csv",
        "--inputs",
        "u",
        "--outputs",
        "y",
        "--out",
        "m",
    ];
    let with = |extra: &[&str]| {
        let mut a: Vec<&str> = base.to_vec();
        a.extend_from_slice(extra);
        rhonn(d.path(), &a)
    };
    let o = with(&["--select", "auto", "--model", "arx.toml"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--select auto and --model"), "{}", stderr(&o));
    let o = with(&["--select", "none", "--budget", "5"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("--select-steps-ahead and --budget apply to the selection only (--select auto,"),
        "{}",
        stderr(&o)
    );
    let o = with(&["--select-steps-ahead", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("--select-steps-ahead 0 is not allowed"),
        "{}",
        stderr(&o)
    );
    let o = with(&["--budget", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--budget 0 is not allowed"), "{}", stderr(&o));
    // More steps than the record: the library's check, named by the command line's flag.
    let o = with(&["--select-steps-ahead", "300"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("`--select-steps-ahead` = 300"),
        "{}",
        stderr(&o)
    );
    let o = with(&["--select", "none"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("m/summary.json")).unwrap()).unwrap();
    assert!(s.get("selection").is_none());
    assert_eq!(s["model"]["na"], 2);
    assert_eq!(s["model"]["kind"], "rhonn");
}

/// `rhonn::sysid::pump_grey::estimate_states`: the filter of a `pump` model with the
/// table's parameters follows the simulated true state of pump-validate (its `p_line` and
/// `stroke` columns) to within a fraction of the sensor noise and of a micrometre, after
/// its first 12 s; it refuses a model of another kind.
#[test]
fn pump_filter_estimates_follow_the_true_state() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["run", "pump-validate", "--out", "v"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let path = d.path().join("v/trajectory.csv");
    let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    let (u, y) = (names(&["current", "demand"]), names(&["p_line_measured"]));
    let r = rhonn_report::read_record(&path, &u, &y, 100).unwrap();
    let truth = rhonn_report::read_record(&path, &u, &names(&["p_line", "stroke"]), 100).unwrap();
    let mut spec =
        rhonn::sysid::parse_spec_file(&std::fs::read_to_string(root.join("models/pump.toml")).unwrap())
            .unwrap()
            .remove(0);
    spec.pump.estimate.clear();
    let m = rhonn::sysid::fit_with_baseline(&spec, std::slice::from_ref(&r), &u, &y).unwrap();
    let est = rhonn::sysid::pump_grey::estimate_states(&m.model, &r).unwrap();
    assert_eq!(est.len(), r.len());
    let rms = |c: usize| {
        let e: Vec<f64> = (2400..est.len())
            .map(|k| est[k][c] - truth.outputs[c][k])
            .collect();
        (e.iter().map(|v| v * v).sum::<f64>() / e.len() as f64).sqrt()
    };
    let (p_err_mpa, x_err_um) = (rms(0) / 1e6, rms(1) * 1e6);
    eprintln!("filter error: pressure {p_err_mpa:.4} MPa, stroke {x_err_um:.2} um RMS");
    // The sensor noise is 0.05 MPa; the stroke spans 0-24 mm.
    assert!(p_err_mpa < 0.05, "pressure error {p_err_mpa} MPa");
    assert!(x_err_um < 2.0, "stroke error {x_err_um} um");
    let mut arx = spec.clone();
    arx.kind = rhonn::sysid::Kind::Arx;
    arx.na = 2;
    arx.nb = 2;
    arx.output_lag_start = 1;
    let a = rhonn::sysid::fit_with_baseline(&arx, std::slice::from_ref(&r), &u, &y).unwrap();
    let e = rhonn::sysid::pump_grey::estimate_states(&a.model, &r).unwrap_err();
    assert!(e.to_string().contains("a `pump` model"), "{e}");
}

/// `rhonn predict --init-window N`: a model of 6 lags run free seeing only the first 3
/// measured outputs; what the file holds after them changes nothing; scored from sample 3
/// on (said in summary.json); a window with K steps ahead, of 0 or of the whole record is
/// refused.
#[test]
fn a_free_run_from_a_state_initialisation_window_sees_only_its_outputs() {
    let d = tempfile::tempdir().unwrap();
    write_record(&d.path().join("train.csv"), 1, 400);
    write_record(&d.path().join("test.csv"), 2, 120);
    std::fs::write(d.path().join("arx.toml"), "kind = \"arx\"\nna = 6\nnb = 6\n").unwrap();
    let fit = [
        "fit",
        "--data",
        "train.csv",
        "--inputs",
        "u",
        "--outputs",
        "y",
        "--model",
        "arx.toml",
        "--out",
        "m",
    ];
    assert!(rhonn(d.path(), &fit).status.success());
    let predict = |data: &str, out: &str, extra: &[&str]| {
        let mut a = vec!["predict", "--model", "m/model.json", "--data", data, "--out", out];
        a.extend_from_slice(extra);
        rhonn(d.path(), &a)
    };
    let o = predict("test.csv", "p", &["--init-window", "3"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("p/summary.json")).unwrap()).unwrap();
    assert_eq!(summary["init_window"], 3);
    assert_eq!(summary["outputs"][0]["samples"], 117);
    // Outputs 3..6 of the file, which the model's lags reach without a window, changed.
    let text = std::fs::read_to_string(d.path().join("test.csv")).unwrap();
    let changed: String = text
        .lines()
        .enumerate()
        .map(|(i, l)| match i {
            4..=6 => format!("{},9.0\n", l.rsplit_once(',').unwrap().0),
            _ => format!("{l}\n"),
        })
        .collect();
    std::fs::write(d.path().join("changed.csv"), changed).unwrap();
    let o = predict("changed.csv", "q", &["--init-window", "3"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let hat = |dir: &str| -> Vec<String> {
        let t = std::fs::read_to_string(d.path().join(dir).join("prediction.csv")).unwrap();
        t.lines()
            .skip(7)
            .map(|l| l.split(',').nth(2).unwrap().to_string())
            .collect()
    };
    assert_eq!(hat("p"), hat("q"));
    // Without the window the model measures them: its free run differs.
    let o = predict("changed.csv", "r", &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_ne!(hat("p"), hat("r"));
    for (extra, says) in [
        (
            &["--init-window", "3", "--steps-ahead", "2"][..],
            "`--init-window` = 3 is not allowed: a free run's window",
        ),
        (&["--init-window", "0"][..], "`--init-window` = 0 is not allowed"),
        (
            &["--init-window", "120"][..],
            "`init_window for test.csv` = 120 is not allowed",
        ),
    ] {
        let o = predict("test.csv", "x", extra);
        assert_eq!(o.status.code(), Some(2));
        assert!(stderr(&o).contains(says), "{}", stderr(&o));
        assert!(!d.path().join("x").exists());
    }
}

/// `--time-column NAME` reads the time from another column than `t`: `fit`, `predict` and
/// `identify` give the models and figures they give on the same file with `t`; without the
/// option, a file whose time column is `time` is refused with a message that names it.
#[test]
fn a_time_column_of_another_name_is_read_with_time_column() {
    let d = tempfile::tempdir().unwrap();
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    for f in ["estimation.csv", "validation.csv"] {
        let text = std::fs::read_to_string(root.join("data/cascaded-tanks").join(f)).unwrap();
        std::fs::write(d.path().join(f), &text).unwrap();
        let renamed = text.replacen("t,u,y", "time,u,y", 1);
        std::fs::write(d.path().join(format!("time_{f}")), renamed).unwrap();
    }
    let spec = "kind = \"arx\"\nna = 2\nnb = 2\n";
    std::fs::write(d.path().join("arx.toml"), spec).unwrap();
    let fit = |data: &str, out: &str, time: Option<&str>| {
        let mut a = vec![
            "fit",
            "--data",
            data,
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--model",
            "arx.toml",
        ];
        a.extend(["--select", "none", "--out", out]);
        a.extend(time.iter().flat_map(|t| ["--time-column", *t]));
        rhonn(d.path(), &a)
    };
    let o = fit("time_estimation.csv", "refused", None);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("no column `t`") && stderr(&o).contains("--time-column time"),
        "{}",
        stderr(&o)
    );
    for (data, out, time) in [
        ("estimation.csv", "a", None),
        ("time_estimation.csv", "b", Some("time")),
    ] {
        let o = fit(data, out, time);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let model = |dir: &str| std::fs::read_to_string(d.path().join(dir).join("model.json")).unwrap();
    assert_eq!(model("a"), model("b"));
    let p = rhonn(
        d.path(),
        &[
            "predict",
            "--model",
            "b/model.json",
            "--data",
            "time_validation.csv",
            "--time-column",
            "time",
            "--out",
            "pb",
        ],
    );
    assert!(p.status.success(), "{}", stderr(&p));
    let p = rhonn(
        d.path(),
        &[
            "predict",
            "--model",
            "a/model.json",
            "--data",
            "validation.csv",
            "--out",
            "pa",
        ],
    );
    assert!(p.status.success(), "{}", stderr(&p));
    let summary = |dir: &str| std::fs::read_to_string(d.path().join(dir).join("summary.json")).unwrap();
    let (pa, pb) = (summary("pa"), summary("pb"));
    let figures = |s: &str| {
        s.lines()
            .filter(|l| l.contains("rms_error"))
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    assert!(
        !figures(&pa).is_empty() && figures(&pa) == figures(&pb),
        "{pa}\n{pb}"
    );
    let i = rhonn(
        d.path(),
        &[
            "identify",
            "--data",
            "time_estimation.csv",
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--time-column",
            "time",
            "--out",
            "ib",
        ],
    );
    assert!(i.status.success(), "{}", stderr(&i));
}
