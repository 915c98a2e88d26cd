//! The real `rhonn` binary in a temporary folder: files written, exit codes, error text.

mod util;

use std::path::Path;
use std::process::Command;
use util::{files_in, rhonn, stderr};

#[test]
fn run_thesis_ch3_writes_csv_summary_and_plots() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["run", "thesis-ch3"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = d.path().join("out/thesis-ch3");
    assert_eq!(
        files_in(&out),
        [
            "inputs.svg",
            "pressure.svg",
            "stroke.svg",
            "summary.json",
            "trajectory.csv"
        ]
    );
    let csv = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], "t,p_line,stroke,current,demand");
    assert!(lines[1].starts_with("0,2000000,0,0,0"), "{}", lines[1]);
    assert!(lines.last().unwrap().starts_with("40,"));
    assert_eq!(lines.len(), 40_002);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["scenario"]["name"], "thesis-ch3");
    assert!(summary["solver"]["rhs_evaluations"].as_u64().unwrap() > 100);
    assert_eq!(summary["figures"]["p_line_max_mpa"], 25.0);
    let svg = std::fs::read_to_string(out.join("pressure.svg")).unwrap();
    assert!(svg.contains("line pressure [MPa]") && svg.contains("time [s]"));
    let svg = std::fs::read_to_string(out.join("stroke.svg")).unwrap();
    assert!(svg.contains("stroke [mm]"));
}

#[test]
fn regulated_run_has_set_point_and_regulation_figures() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["run", "regulated-pi", "--out", "reg"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(d.path().join("reg/trajectory.csv")).unwrap();
    assert!(csv.starts_with("t,p_line,stroke,current,demand,p_ref,p_meas\n"));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("reg/summary.json")).unwrap()).unwrap();
    let r = &s["figures"]["regulation"];
    assert!(r["ise_mpa2_s"].as_f64().unwrap() > 0.0);
    assert!(r["max_abs_deviation_mpa"].as_f64().unwrap() > 0.0);
    // After the start-up the pressure stays in the model's valid range.
    assert_eq!(s["figures"]["time_below_p_min_after_1s_s"], 0.0);
}

#[test]
fn unknown_scenario_is_a_clear_error_and_writes_nothing() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["run", "thesis-ch4"]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("unknown scenario `thesis-ch4`")
            && e.contains("thesis-ch3, regulated-pi, thesis-ch5, pump-identify, pump-validate"),
        "{e}"
    );
    assert!(files_in(d.path()).is_empty());
}

#[test]
fn bad_scenario_files_name_the_field_value_and_range() {
    let d = tempfile::tempdir().unwrap();
    let shipped = rhonn(d.path(), &["show", "thesis-ch3"]);
    assert!(shipped.status.success());
    let text = String::from_utf8(shipped.stdout).unwrap();

    let cases = [
        (
            text.replace("duration_s = 40.0", "duration_s = -1.0"),
            "`duration_s` = -1 is not allowed: a number in (0, 1e6] s",
        ),
        (
            text.replace("[initial]", "[initial]\nbeta_mpa = 3"),
            "unknown field `beta_mpa`",
        ),
        (
            text.replace("p_line_mpa = 2.0", "p_line_mpa = 30.0"),
            "`initial.p_line_mpa` = 30 is not allowed: a pressure in [0, 25] MPa",
        ),
        (
            text.replace("[25.0, 0.8]", "[5.0, 0.8]"),
            "`current_a.points[2][0]` = 5",
        ),
        (
            text.replace("duration_s = 40.0", "duration_s = \"forty\""),
            "invalid type",
        ),
        (
            format!("{text}\n[demand_dm3_s]\nkind = \"trapezoids\"\nslew_per_s = 3.0\npulses = []\n"),
            "`demand_dm3_s.slew_per_s` = 3 is not allowed: at most 2",
        ),
    ];
    assert_bad_scenarios(d.path(), &cases);
}
/// Run each bad scenario text; each must fail with exit code 2, an error containing its
/// expected text, and no output folder.
fn assert_bad_scenarios(d: &Path, cases: &[(String, &str)]) {
    for (k, (toml, expected)) in cases.iter().enumerate() {
        let f = d.join(format!("bad{k}.toml"));
        std::fs::write(&f, toml).unwrap();
        let o = rhonn(d, &["run", f.to_str().unwrap(), "--out", "o"]);
        assert_eq!(o.status.code(), Some(2), "case {k}");
        let e = stderr(&o);
        assert!(e.contains(expected), "case {k}: expected `{expected}` in:\n{e}");
        assert!(!d.join("o").exists(), "case {k} wrote output");
    }
}

#[test]
fn unwritable_output_folder_is_an_error_and_leaves_nothing() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("afile"), "x").unwrap();
    let o = rhonn(d.path(), &["run", "thesis-ch3", "--out", "afile/sub"]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("cannot write to output folder afile/sub"), "{e}");
    assert_eq!(files_in(d.path()), ["afile"]);
}

#[test]
fn scenarios_lists_every_shipped_scenario_with_a_description() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["scenarios"]);
    assert!(o.status.success());
    let s = String::from_utf8(o.stdout).unwrap();
    assert!(s.lines().any(|l| l.starts_with("thesis-ch3") && l.len() > 30));
    assert!(s.lines().any(|l| l.starts_with("regulated-pi") && l.len() > 30));
}

#[test]
fn help_says_what_run_writes_and_in_which_units() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["run", "--help"]);
    let s = String::from_utf8(o.stdout).unwrap();
    for needle in [
        "trajectory.csv",
        "summary.json",
        "p_line [Pa]",
        "[MPa]",
        "stroke [mm]",
    ] {
        assert!(s.contains(needle), "{needle} missing from help");
    }
}

#[test]
fn thesis_ch5_writes_estimates_weights_validation_and_identification_plots() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["run", "thesis-ch5", "--out", "ch5"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = d.path().join("ch5");
    for f in [
        "weights.json",
        "validation.csv",
        "ident_errors.svg",
        "ident_states.svg",
        "ident_zoom.svg",
        "validation.svg",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let csv = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    assert!(csv.starts_with("t,p_line,stroke,current,demand,p_line_hat,stroke_hat\n"));
    let val = std::fs::read_to_string(out.join("validation.csv")).unwrap();
    assert!(val.starts_with(
        "t,p_line,p_line_hat_series_parallel,p_line_hat_parallel,stroke,stroke_hat_series_parallel,stroke_hat_parallel\n"
    ));
    let w: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("weights.json")).unwrap()).unwrap();
    assert_eq!(w["states"], serde_json::json!(["p_line", "stroke"]));
    assert_eq!(w["weights"].as_array().unwrap().len(), 2);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    for mode in ["training", "series_parallel", "parallel"] {
        let figs = s["identification"][mode].as_array().unwrap();
        assert_eq!(figs.len(), 2, "{mode}");
        for key in [
            "rms_error",
            "fit_percent",
            "convergence_time_s",
            "final_weight_norm",
        ] {
            assert!(figs[0].get(key).is_some(), "{mode}.{key}");
        }
    }
    let zoom = std::fs::read_to_string(out.join("ident_zoom.svg")).unwrap();
    assert!(zoom.contains("first 0.12 s") && zoom.contains("first 1.2 s"));
}

#[test]
fn reproduce_runs_every_thesis_scenario() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["reproduce", "--out", "r"]);
    assert!(o.status.success(), "{}", stderr(&o));
    for name in ["thesis-ch3", "thesis-ch5", "regulated-pi", "control-adaptive"] {
        assert!(
            d.path().join("r").join(name).join("summary.json").is_file(),
            "{name}"
        );
    }
    // The adaptive run holds both controllers: CSV columns, summary figures, plots.
    let dir = d.path().join("r").join("control-adaptive");
    let csv = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    for col in [
        "p_line",
        "p_line_pi",
        "current",
        "current_pi",
        "p_ref",
        "stroke_ref",
        "w_norm",
        "w1_norm",
    ] {
        assert!(header.split(',').any(|c| c == col), "{col} in {header}");
    }
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    for who in [&s["figures"], &s["control"]["baseline"]["figures"]] {
        let r = &who["regulation"];
        for key in [
            "ise_mpa2_s",
            "max_abs_deviation_settled_mpa",
            "time_current_saturated_s",
        ] {
            assert!(r[key].as_f64().is_some(), "{key}");
        }
        assert_eq!(r["signals_bounded"], serde_json::Value::Bool(true));
        assert!(who["time_below_p_min_after_1s_s"].as_f64().is_some());
    }
    let weights = std::fs::read_to_string(dir.join("weights.svg")).unwrap();
    assert!(weights.contains("MPa/(s mm)"));
    let pressure = std::fs::read_to_string(dir.join("pressure.svg")).unwrap();
    assert!(pressure.contains("PI baseline") && pressure.contains("RHONN adaptive"));
}

#[test]
fn bad_adaptive_controller_settings_are_clear_errors() {
    let d = tempfile::tempdir().unwrap();
    let shipped = String::from_utf8(rhonn(d.path(), &["show", "control-adaptive"]).stdout).unwrap();
    let cases = [
        (
            shipped.replace("ball_fraction = 0.5", "ball_fraction = 1.0"),
            "`controller.ball_fraction` = 1 is not allowed: a number in (0, 1)",
        ),
        (
            shipped.replace("lambda_per_s = 100.0", "lambda_per_s = -1.0"),
            "`controller.lambda_per_s` = -1 is not allowed: a finite number > 0",
        ),
        (
            shipped.replace("baseline_ti_s = 0.15", "baseline_ti_s = 0.0"),
            "`controller.baseline_ti_s` = 0 is not allowed: a number > 0",
        ),
        (
            shipped.replace(
                "[measurement]",
                "[plant]\ntransport_delay_periods = 5000\n\n[measurement]",
            ),
            "`plant.transport_delay_periods` = 5000 is not allowed: an integer in [0, 1000]",
        ),
    ];
    for (k, (text, expected)) in cases.iter().enumerate() {
        assert_ne!(text, &shipped, "case {k} did not change the scenario");
        let path = d.path().join(format!("bad{k}.toml"));
        std::fs::write(&path, text).unwrap();
        let o = rhonn(d.path(), &["run", path.to_str().unwrap(), "--out", "o"]);
        assert_eq!(o.status.code(), Some(2), "case {k}");
        assert!(stderr(&o).contains(expected), "case {k}: {}", stderr(&o));
        assert!(!d.path().join("o").exists(), "case {k} wrote outputs");
    }
}

#[test]
fn bad_identifier_sections_are_clear_errors() {
    let d = tempfile::tempdir().unwrap();
    let shipped = String::from_utf8(rhonn(d.path(), &["show", "thesis-ch5"]).stdout).unwrap();
    let cases = [
        (
            shipped.replace("a = [120.0, 41.0]", "a = [120.0]"),
            "`identifier.a` = 1 values is not allowed: one per state (2)",
        ),
        (
            shipped.replace("gamma = [1e4, 30.0]", "gamma = [1e4, -30.0]"),
            "`identifier.law.gamma[1]` = -30",
        ),
        (
            shipped.replace("terms = [[[0, 1]], [[1, 1]]]", "terms = [[[0, 1]], [[5, 1]]]"),
            "`identifier.terms[1][0][0]` = 5",
        ),
        (
            shipped.replace("kind = \"sigma-switching\"", "kind = \"sigma-switchin\""),
            "unknown variant `sigma-switchin`",
        ),
        (
            shipped.replace(
                "states = [\"p_line\", \"stroke\"]",
                "states = [\"p_line\", \"flow\"]",
            ),
            "`identifier.states[1]` = \"flow\"",
        ),
    ];
    assert_bad_scenarios(d.path(), &cases);
}

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
    assert_eq!(files_in(&d.path().join("m")), ["model.json", "summary.json"]);
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
    assert_eq!(
        files_in(&d.path().join("p")),
        ["prediction.csv", "prediction.svg", "summary.json"]
    );
    let csv = std::fs::read_to_string(d.path().join("p/prediction.csv")).unwrap();
    assert!(csv.starts_with("t,y,y_hat,y_hat_arx\n"));
    assert_eq!(csv.lines().count(), 401);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("p/summary.json")).unwrap()).unwrap();
    let fit = s["outputs"][0]["fit_percent"].as_f64().unwrap();
    let arx = s["baseline_arx"][0]["fit_percent"].as_f64().unwrap();
    assert!(fit > 90.0 && fit > arx, "rhonn {fit} %, arx {arx} %");
    assert!(s["outputs"][0]["nrmse"].as_f64().unwrap() > 0.0);
    // One step ahead tracks better than the free run.
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
    assert!(s1["outputs"][0]["fit_percent"].as_f64().unwrap() >= fit);
    assert_eq!(s1["steps_ahead"], 1);
}

#[test]
fn bad_data_names_file_line_and_column_and_writes_nothing() {
    let d = tempfile::tempdir().unwrap();
    let cases = [
        (
            "t,u,y\n0,1,2\n1,x,3\n",
            "bad.csv, line 3, column `u`: `x` is not a finite number",
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
        assert_eq!(
            files_in(&d.path().join("p")),
            ["prediction.csv", "prediction.svg", "summary.json"]
        );
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
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
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
    let started = std::time::Instant::now();
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
    // A fit over a second shows signs of life (here, not a terminal: a line every 5 s).
    if started.elapsed().as_secs_f64() > 2.0 {
        assert!(
            stderr(&o).contains("fitting on 1 record(s): 1 s so far"),
            "{}",
            stderr(&o)
        );
    }
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

/// The pump with the shipped model structure (chosen on pump-identify alone): trained
/// on pump-identify, it predicts pump-validate's measured pressure 10 steps (50 ms)
/// ahead with a fit of at least 80 %, better than the ARX baseline with the same lags.
#[test]
fn pump_model_predicts_the_validation_record_10_steps_ahead() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
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
    let spec = root.join("models/pump.toml");
    ok(&[
        "fit",
        "--data",
        "pump-identify/trajectory.csv",
        "--inputs",
        "current,demand",
        "--outputs",
        "p_meas",
        "--model",
        spec.to_str().unwrap(),
        "--out",
        "m",
    ]);
    let (fit, arx, _) = predict("pump-validate/trajectory.csv", "p");
    eprintln!("pump, 10 steps ahead on pump-validate: RHONN fit {fit:.2} %, ARX {arx:.2} %");
    assert!(fit >= 80.0, "RHONN fit {fit} %");
    assert!(fit > arx, "RHONN fit {fit} %, ARX {arx} %");
    // rhonn's own SI columns are plotted in display units.
    let svg = std::fs::read_to_string(d.path().join("p/prediction.svg")).unwrap();
    assert!(svg.contains("p_meas [MPa]"), "no MPa axis");
    // The same record written every 1 ms is put on the model's 5 ms grid, with a note:
    // the same prediction.
    let o = ok(&["show", "pump-validate"]);
    let toml = String::from_utf8(o.stdout)
        .unwrap()
        .replace("output_interval_ms = 5.0", "output_interval_ms = 1.0");
    assert!(toml.contains("output_interval_ms = 1.0"));
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
    // Records with excitations and noise the model never saw (scenarios/stress): the
    // RHONN stays ahead of its ARX baseline and above 75 % 10 steps ahead on each.
    for (k, name) in ["stress-multisine", "stress-noise", "stress-nodither"]
        .iter()
        .enumerate()
    {
        let sc = root.join(format!("scenarios/stress/{name}.toml"));
        ok(&["run", sc.to_str().unwrap(), "--out", name]);
        let (fit, arx, _) = predict(&format!("{name}/trajectory.csv"), &format!("s{k}"));
        eprintln!("{name}: RHONN fit {fit:.2} %, ARX {arx:.2} %");
        assert!(fit > 75.0 && fit > arx, "{name}: RHONN {fit} %, ARX {arx} %");
    }
}

#[test]
fn bench_prints_json_figures_per_scenario() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["bench", "thesis-ch3", "--json", "--seconds", "0.05"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let b = &v.as_array().unwrap()[0];
    assert_eq!(b["scenario"], "thesis-ch3");
    for key in ["median_s", "runs_per_s_all_cores"] {
        assert!(b[key].as_f64().unwrap() > 0.0, "{key}");
    }
    assert!(b["rhs_evaluations"].as_u64().unwrap() > 1000);
    let o = rhonn(d.path(), &["bench", "--seconds", "0"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("--seconds 0 is not allowed: give a time in (0, 3600] s"),
        "{}",
        stderr(&o)
    );
}

fn read(p: std::path::PathBuf) -> String {
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn a_campaign_is_the_same_on_one_thread_sharded_and_merged() {
    let d = tempfile::tempdir().unwrap();
    let base = ["campaign", "thesis-ch3", "--runs", "40", "--seed", "5"];
    let ok = |args: &[&str]| {
        let o = rhonn(d.path(), args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    };
    ok(&[&base[..], &["--out", "all"]].concat());
    ok(&[&base[..], &["--threads", "1", "--out", "one"]].concat());
    for k in 1..=3 {
        let shard = format!("{k}/3");
        let out = format!("s{k}");
        ok(&[&base[..], &["--shard", &shard, "--out", &out]].concat());
    }
    ok(&["merge", "s1", "s2", "s3", "--out", "merged"]);
    let all = read(d.path().join("all/runs.csv"));
    assert_eq!(all.lines().count(), 41);
    assert!(all
        .lines()
        .next()
        .unwrap()
        .starts_with("run,beta_mpa,mu_1,mu_2,q_0_dm3_s,qdot_max_dm3_s2,status"));
    assert_eq!(
        all,
        read(d.path().join("one/runs.csv")),
        "thread count changed runs.csv"
    );
    assert_eq!(
        all,
        read(d.path().join("merged/runs.csv")),
        "merge differs from the unsharded run"
    );
    assert_eq!(
        read(d.path().join("all/summary.json")),
        read(d.path().join("merged/summary.json"))
    );
    // The envelope: kept traces and their quantiles, the same whatever the threads and shards.
    for f in ["traces.csv", "envelope.csv"] {
        let a = read(d.path().join("all").join(f));
        assert_eq!(a, read(d.path().join("one").join(f)), "{f}: thread count");
        assert_eq!(a, read(d.path().join("merged").join(f)), "{f}: merge");
    }
    assert_eq!(read(d.path().join("all/traces.csv")).lines().count(), 41);
    let env = read(d.path().join("all/envelope.csv"));
    assert!(
        env.starts_with("t,p_line_min_mpa,p_line_q05_mpa,p_line_median_mpa,p_line_q95_mpa,p_line_max_mpa\n")
    );
    let rows: Vec<Vec<f64>> = env
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    assert!(
        rows.len() > 300 && rows.len() <= 600,
        "{} envelope points",
        rows.len()
    );
    assert!(rows
        .iter()
        .all(|r| r[1] <= r[2] && r[2] <= r[3] && r[3] <= r[4] && r[4] <= r[5]));
    // thesis-ch3 ends at 0.8 A held then ramped down: the runs spread out (beta, mu differ).
    assert!(
        rows.iter().any(|r| r[5] - r[1] > 0.1),
        "the envelope has no width"
    );
    assert!(read(d.path().join("all/envelope.svg")).contains("<svg"));
    ok(&[&base[..], &["--envelope-runs", "7", "--out", "seven"]].concat());
    assert_eq!(read(d.path().join("seven/traces.csv")).lines().count(), 8);
    assert_eq!(read(d.path().join("seven/runs.csv")), all);
    ok(&[&base[..], &["--envelope-runs", "0", "--out", "none"]].concat());
    assert!(!d.path().join("none/envelope.svg").exists());
    // The draws differ between runs and stay within the tolerances.
    let betas: Vec<f64> = all
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    assert!(betas.iter().all(|b| (960.0..=1440.0).contains(b)));
    assert!(betas.windows(2).any(|w| w[0] != w[1]));
    // An incomplete merge is refused.
    let o = rhonn(d.path(), &["merge", "s1", "s3", "--out", "bad"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("some shard is missing"), "{}", stderr(&o));
    let o = rhonn(d.path(), &[&base[..], &["--shard", "4/3", "--out", "x"]].concat());
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("--shard \"4/3\" is not allowed"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_killed_campaign_resumes_to_the_same_runs_csv() {
    let d = tempfile::tempdir().unwrap();
    let args = [
        "campaign",
        "regulated-pi",
        "--runs",
        "200",
        "--seed",
        "9",
        "--threads",
        "1",
    ];
    let o = rhonn(d.path(), &[&args[..], &["--out", "full"]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    // Start the same campaign elsewhere and kill it once some runs are on disk.
    let mut child = Command::new(env!("CARGO_BIN_EXE_rhonn"))
        .args([&args[..], &["--out", "cut"]].concat())
        .current_dir(d.path())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let partial = d.path().join("cut/runs.partial.csv");
    let t0 = std::time::Instant::now();
    loop {
        let n = std::fs::read_to_string(&partial)
            .map(|s| s.lines().count())
            .unwrap_or(0);
        if n > 5 || t0.elapsed().as_secs() > 60 {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let done_before = std::fs::read_to_string(&partial)
        .map(|s| s.lines().count())
        .unwrap_or(0);
    assert!(
        !d.path().join("cut/runs.csv").exists(),
        "the campaign finished before the kill"
    );
    assert!(done_before > 1, "nothing was flushed before the kill");
    let o = rhonn(d.path(), &[&args[..], &["--out", "cut"]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("resuming"), "{}", stderr(&o));
    for f in ["runs.csv", "traces.csv", "envelope.csv", "summary.json"] {
        assert_eq!(
            read(d.path().join("full").join(f)),
            read(d.path().join("cut").join(f)),
            "{f} differs after the resume"
        );
    }
    assert!(!partial.exists());
    assert!(!d.path().join("cut/traces.partial.csv").exists());
}

fn read_preset(name: &str) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_rhonn"))
        .args(["show", name])
        .output()
        .unwrap();
    assert!(o.status.success());
    String::from_utf8(o.stdout).unwrap()
}

#[test]
fn a_scenario_file_overrides_the_campaign_distributions() {
    let d = tempfile::tempdir().unwrap();
    let toml = read_preset("thesis-ch3").replace("name = \"thesis-ch3\"", "name = \"ch3-campaign\"")
        + r#"
[campaign]
beta_mpa = { min = 1000.0, max = 1100.0 }
mu_1 = { distribution = "normal", std_relative = 0.05, relative = 0.1 }
q_0_dm3_s = { distribution = "fixed" }
qdot_max_dm3_s2 = { distribution = "fixed" }
"#;
    std::fs::write(d.path().join("c.toml"), &toml).unwrap();
    let o = rhonn(d.path(), &["campaign", "c.toml", "--corners", "--out", "corners"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let runs = read(d.path().join("corners/runs.csv"));
    let rows: Vec<Vec<String>> = runs
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    // Three parameters vary: 2^3 corners; the fixed ones keep the scenario's values.
    assert_eq!(rows.len(), 8);
    let col = |j: usize| {
        rows.iter()
            .map(|r| r[j].parse::<f64>().unwrap())
            .collect::<Vec<_>>()
    };
    assert!(col(1).iter().all(|b| *b == 1000.0 || *b == 1100.0));
    assert!(
        col(2)
            .iter()
            .all(|m| ((m / 78e-6 - 1.0).abs() - 0.1).abs() < 1e-9),
        "{:?}",
        col(2)
    );
    assert!(
        col(4).iter().all(|q| *q == 0.13) && col(5).iter().all(|q| *q == 2.0),
        "{runs}"
    );
    let summary = read(d.path().join("corners/summary.json"));
    assert!(summary.contains("\"distribution\": \"normal\""), "{summary}");
    let o = rhonn(
        d.path(),
        &["campaign", "c.toml", "--runs", "30", "--out", "random"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let runs = read(d.path().join("random/runs.csv"));
    for l in runs.lines().skip(1) {
        let v: Vec<f64> = l.split(',').take(6).map(|x| x.parse().unwrap()).collect();
        assert!(
            (1000.0..=1100.0).contains(&v[1]) && (v[2] / 78e-6 - 1.0).abs() <= 0.1 + 1e-12,
            "{l}"
        );
    }
    // A bad entry names its field and value; nothing is written.
    let bad = toml.replace("std_relative = 0.05", "std_relative = -1.0");
    std::fs::write(d.path().join("bad.toml"), bad).unwrap();
    let o = rhonn(d.path(), &["campaign", "bad.toml", "--runs", "3", "--out", "bad"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("campaign.mu_1.std_relative") && stderr(&o).contains("-1"),
        "{}",
        stderr(&o)
    );
    assert!(!d.path().join("bad").exists());
}
