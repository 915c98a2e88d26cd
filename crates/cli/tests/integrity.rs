//! Issue 33's cases, one test each, through the real binary: hostile values that hung,
//! panicked or wrote NaN with exit 0, data changed without a word, valid data refused, stale
//! files in a reused folder, and errors that pointed the wrong way.

use crate::util;

use std::path::{Path, PathBuf};
use util::{files_in, rhonn, stderr};

fn data(name: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("data/cascaded-tanks")
        .join(name)
}

fn model(name: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("models")
        .join(name)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `validation.csv` with a function applied to its rows (header excluded).
fn edited(dir: &Path, name: &str, f: impl Fn(&mut Vec<Vec<String>>)) -> PathBuf {
    let text = std::fs::read_to_string(data("validation.csv")).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().to_string();
    let mut rows: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    f(&mut rows);
    let mut out = header + "\n";
    for r in rows {
        out += &(r.join(",") + "\n");
    }
    let p = dir.join(name);
    std::fs::write(&p, out).unwrap();
    p
}

fn identify(dir: &Path, spec: &str, validate: Option<&Path>, out: &str) -> std::process::Output {
    let (est, m) = (data("estimation.csv"), model(spec));
    let mut a = vec![
        "identify",
        "--data",
        s(&est),
        "--inputs",
        "u",
        "--outputs",
        "y",
        "--model",
        s(&m),
    ];
    if let Some(v) = validate {
        a.extend(["--validate", s(v)]);
    }
    a.extend(["--out", out]);
    rhonn(dir, &a)
}

#[test]
fn a_huge_cell_is_named_instead_of_hanging_the_plots() {
    let d = tempfile::tempdir().unwrap();
    let bad = edited(d.path(), "bad.csv", |r| r[99][2] = "1.7e308".into());
    let o = identify(d.path(), "tanks-online-lagged.toml", Some(&bad), "o");
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("bad.csv, line 101, column `y`: `1.7e308`"),
        "{}",
        stderr(&o)
    );
    assert!(!d.path().join("o").exists());
}

fn lagged_model(d: &Path) -> serde_json::Value {
    let o = identify(d, "tanks-online-lagged.toml", None, "m");
    assert!(o.status.success(), "{}", stderr(&o));
    serde_json::from_str(&std::fs::read_to_string(d.join("m/model.json")).unwrap()).unwrap()
}

fn predict(d: &Path, m: &serde_json::Value, out: &str) -> std::process::Output {
    std::fs::write(d.join("edited.json"), serde_json::to_string_pretty(m).unwrap()).unwrap();
    let v = data("validation.csv");
    rhonn(
        d,
        &["predict", "--model", "edited.json", "--data", s(&v), "--out", out],
    )
}

#[test]
fn hostile_online_models_are_refused_by_field_not_run_into_nan() {
    let d = tempfile::tempdir().unwrap();
    let m = lagged_model(d.path());
    for (field, value, named) in [
        ("y_scale", 5e-324, "scaling.y_scale[0]"),
        ("y_scale", 1e308, "scaling.y_scale[0]"),
        ("u_offset", 1e300, "scaling.u_offset[0]"),
    ] {
        let mut bad = m.clone();
        bad["scaling"][field][0] = serde_json::json!(value);
        let o = predict(d.path(), &bad, "p");
        assert_eq!(o.status.code(), Some(2), "{field} = {value}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("edited.json") && stderr(&o).contains(named),
            "{}",
            stderr(&o)
        );
        assert!(!d.path().join("p").exists());
    }
    // A weight so large: the lagged structure holds its estimate within its bounds, so
    // either it predicts finite numbers or it is refused; never NaN with exit 0.
    let mut bad = m.clone();
    bad["weights"][0][0] = serde_json::json!(1e308);
    let o = predict(d.path(), &bad, "w");
    if o.status.success() {
        let csv = std::fs::read_to_string(d.path().join("w/prediction.csv")).unwrap();
        assert!(
            !csv.to_lowercase().contains("nan") && !csv.contains("inf"),
            "{csv}"
        );
    } else {
        assert!(files_in(&d.path().join("w")).is_empty());
    }
    // A truncated file: where the JSON breaks, not a missing field.
    let text = serde_json::to_string_pretty(&m).unwrap();
    std::fs::write(d.path().join("cut.json"), &text[..text.len() / 2]).unwrap();
    let v = data("validation.csv");
    let o = rhonn(
        d.path(),
        &["predict", "--model", "cut.json", "--data", s(&v), "--out", "p"],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("cut.json is not JSON") && stderr(&o).contains("line"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_cascade_weight_that_overflows_is_refused_and_nothing_is_written() {
    let d = tempfile::tempdir().unwrap();
    let spec = d.path().join("cascade.toml");
    std::fs::write(
        &spec,
        "structure = \"cascade\"\nepochs = 1\ncascade = { starts = 2 }\n",
    )
    .unwrap();
    let est = data("estimation.csv");
    let o = rhonn(
        d.path(),
        &[
            "identify",
            "--data",
            s(&est),
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--model",
            s(&spec),
            "--out",
            "c",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let mut m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("c/model.json")).unwrap()).unwrap();
    let n = m["weights"][0].as_array().unwrap().len();
    m["weights"][0][n - 1] = serde_json::json!(1.7e308);
    let o = predict(d.path(), &m, "p");
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("edited.json") && stderr(&o).contains("not finite"),
        "{}",
        stderr(&o)
    );
    assert!(files_in(&d.path().join("p")).is_empty());
}

#[test]
fn an_inverted_output_range_is_an_error_not_a_panic() {
    let d = tempfile::tempdir().unwrap();
    let est = data("estimation.csv");
    let o = rhonn(
        d.path(),
        &[
            "fit",
            "--data",
            s(&est),
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--select",
            "none",
            "--out",
            "f",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let mut m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("f/model.json")).unwrap()).unwrap();
    m["baseline"]["output_range"][0] = serde_json::json!([10.0, 2.9116]);
    let o = predict(d.path(), &m, "p");
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("baseline.output_range[0]"), "{}", stderr(&o));
    m["baseline"]["output_range"][0] = serde_json::json!([2.0, 10.0]);
    m["model"]["output_range"][0] = serde_json::json!([10.0, 2.9116]);
    let o = predict(d.path(), &m, "p");
    assert!(stderr(&o).contains("model.output_range[0]"), "{}", stderr(&o));
}

#[test]
fn a_constant_output_is_predicted_with_its_fit_left_undefined() {
    let d = tempfile::tempdir().unwrap();
    let m = lagged_model(d.path());
    let c = edited(d.path(), "const.csv", |r| {
        r.iter_mut().for_each(|row| row[2] = "5.0".into())
    });
    std::fs::write(d.path().join("m.json"), serde_json::to_string(&m).unwrap()).unwrap();
    let o = rhonn(
        d.path(),
        &["predict", "--model", "m.json", "--data", s(&c), "--out", "p"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let sum: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("p/summary.json")).unwrap()).unwrap();
    let f = &sum["figures"][0];
    assert!(f["rms_error"].as_f64().unwrap().is_finite(), "{sum}");
    assert!(f.get("fit_percent").is_none(), "{sum}");
    // Identifying a constant output names the column.
    let o = rhonn(
        d.path(),
        &[
            "identify",
            "--data",
            s(&c),
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--out",
            "i",
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("const.csv: output `y`") && stderr(&o).contains("constant 5"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_pump_noise_beyond_reason_is_refused_by_name() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["show", "regulated-pi"]);
    let text = String::from_utf8_lossy(&o.stdout).replace("p_line = 0.0", "p_line = 1e308");
    std::fs::write(d.path().join("noisy.toml"), text).unwrap();
    let o = rhonn(d.path(), &["run", "noisy.toml", "--out", "r"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("noisy.toml") && stderr(&o).contains("measurement.noise_std.p_line"),
        "{}",
        stderr(&o)
    );
    // duration_s beyond the output limit names duration_s.
    let o = rhonn(d.path(), &["show", "tanks-control"]);
    let text = String::from_utf8_lossy(&o.stdout).replace("duration_s = 2400.0", "duration_s = 1e9");
    std::fs::write(d.path().join("long.toml"), text).unwrap();
    let o = rhonn(d.path(), &["run", "long.toml", "--out", "r"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("long.toml") && stderr(&o).contains("`duration_s, output_interval_s`"),
        "{}",
        stderr(&o)
    );
}

fn arx_weights(d: &Path, file: &Path, out: &str) -> (Vec<f64>, serde_json::Value, String) {
    let spec = d.join("arx.toml");
    std::fs::write(&spec, "kind = \"arx\"\nna = 2\nnb = 2\nnk = 1\n").unwrap();
    let o = rhonn(
        d,
        &[
            "fit",
            "--data",
            s(file),
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--model",
            s(&spec),
            "--out",
            out,
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join(out).join("model.json")).unwrap()).unwrap();
    let w = m["model"]["weights"][0]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let sum: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join(out).join("summary.json")).unwrap()).unwrap();
    (w, sum, stderr(&o))
}

#[test]
fn times_rounded_to_a_microsecond_are_uniform_and_a_gap_is_reported() {
    let d = tempfile::tempdir().unwrap();
    // A step of 4/1024 s printed to 1e-6 s (up to 1.3e-4 of the step off the grid), as
    // benchmark files are: the same model as with exact times.
    let exact = edited(d.path(), "exact.csv", |r| {
        r.iter_mut()
            .enumerate()
            .for_each(|(k, row)| row[0] = format!("{}", k as f64 * 4.0 / 1024.0))
    });
    let rounded = edited(d.path(), "rounded.csv", |r| {
        r.iter_mut()
            .enumerate()
            .for_each(|(k, row)| row[0] = format!("{:.6}", k as f64 * 4.0 / 1024.0))
    });
    let (we, _, _) = arx_weights(d.path(), &exact, "e");
    let (wr, sum, err) = arx_weights(d.path(), &rounded, "r");
    assert_eq!(we, wr);
    assert!(
        sum.get("regridded").is_none() && !err.contains("not uniform"),
        "{err}"
    );
    // A missing row is a change: said on stderr and in summary.json.
    let gap = edited(d.path(), "gap.csv", |r| {
        r.remove(500);
    });
    let (_, sum, err) = arx_weights(d.path(), &gap, "g");
    assert!(err.contains("gap.csv: the times are not uniform"), "{err}");
    let g = &sum["regridded"][0];
    assert_eq!(g["rows_in"], 1023);
    assert_eq!(g["rows_out"], 1024);
    assert!(g["outputs_interpolated"].as_u64().unwrap() >= 1, "{sum}");
}

#[test]
fn a_reused_folder_keeps_no_stale_file_and_a_file_as_out_is_refused_first() {
    let d = tempfile::tempdir().unwrap();
    let v = data("validation.csv");
    let o = identify(d.path(), "tanks-online-lagged.toml", Some(&v), "st");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(files_in(&d.path().join("st")).contains(&"validation.csv".to_string()));
    let o = identify(d.path(), "tanks-online-lagged.toml", None, "st");
    assert!(o.status.success(), "{}", stderr(&o));
    let files = files_in(&d.path().join("st"));
    assert!(!files.iter().any(|f| f.starts_with("validation")), "{files:?}");
    assert!(
        stderr(&o).contains("removed") && stderr(&o).contains("validation.csv"),
        "{}",
        stderr(&o)
    );
    let html = std::fs::read_to_string(d.path().join("st/report.html")).unwrap();
    assert!(!html.contains("validation.svg"));
    // A file where the folder should be: refused before any work, nothing changed.
    std::fs::write(d.path().join("afile"), "x").unwrap();
    let o = identify(d.path(), "tanks-online-lagged.toml", None, "afile");
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("afile") && stderr(&o).contains("not a folder"),
        "{}",
        stderr(&o)
    );
    assert!(
        !stderr(&o).contains("identifying"),
        "refused before the work: {}",
        stderr(&o)
    );
}

#[test]
fn a_missing_row_is_filled_and_said_and_an_infinite_bias_is_named() {
    let d = tempfile::tempdir().unwrap();
    // One row fewer: `t` moves by 8 s where the record samples every 4 s. `identify`
    // follows `rhonn fit`'s one rule for gaps (issue 56; it refused such a file before):
    // one missing sample of 1,024 is filled by interpolation, and said.
    let gap = edited(d.path(), "gap.csv", |r| {
        r.remove(500);
    });
    let o = rhonn(
        d.path(),
        &[
            "identify",
            "--data",
            s(&gap),
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--model",
            s(&model("tanks-online-lagged.toml")),
            "--out",
            "g",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("gap.csv: the times are not uniform") && e.contains("1 output values interpolated"),
        "{e}"
    );
    // A PI's bias must be a finite number within its loop's output range.
    let o = rhonn(d.path(), &["show", "tanks-control"]);
    let text = String::from_utf8_lossy(&o.stdout).replace(
        "inner = { kind = \"pi\", state = \"h1\", kp = 0.2, ti_s = 10.0 }",
        "inner = { kind = \"pi\", state = \"h1\", kp = 0.2, ti_s = 10.0, bias = inf }",
    );
    assert!(text.contains("bias = inf"));
    std::fs::write(d.path().join("bias.toml"), text).unwrap();
    let o = rhonn(d.path(), &["run", "bias.toml", "--out", "b"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("bias.toml") && stderr(&o).contains("control.baseline.inner.bias"),
        "{}",
        stderr(&o)
    );
}

/// Arguments at their extremes, found by hand after the mutation sweep (which mutates files,
/// not arguments): a steps-ahead past every record panicked `predict`, `identify` and the
/// selection (an index overflow); 100,000 campaign threads ran past a minute. Each is now a
/// refusal naming the argument, exit 2, nothing written.
#[test]
fn arguments_at_their_extremes_are_refused_not_a_panic_or_a_hang() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let (est, val) = (data("estimation.csv"), data("validation.csv"));
    let huge = u64::MAX.to_string();
    let fit = rhonn(
        p,
        &[
            "fit",
            "--data",
            s(&est),
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--model",
            s(&model("cascaded-tanks.toml")),
            "--out",
            "m",
        ],
    );
    assert!(fit.status.success(), "{}", stderr(&fit));
    let cases: [(Vec<&str>, &str); 4] = [
        (
            vec![
                "predict",
                "--model",
                "m/model.json",
                "--data",
                s(&val),
                "--steps-ahead",
                &huge,
                "--out",
                "o",
            ],
            "at least 18446744073709551615 are needed",
        ),
        (
            vec![
                "identify",
                "--data",
                s(&est),
                "--inputs",
                "u",
                "--outputs",
                "y",
                "--validate",
                s(&val),
                "--steps-ahead",
                &huge,
                "--out",
                "o",
            ],
            "`steps_ahead` = 18446744073709551615 is not allowed",
        ),
        (
            vec![
                "fit",
                "--data",
                s(&est),
                "--inputs",
                "u",
                "--outputs",
                "y",
                "--select-steps-ahead",
                &huge,
                "--out",
                "o",
            ],
            "`--select-steps-ahead` = 18446744073709551615 is not allowed",
        ),
        (
            vec![
                "campaign",
                "tanks-control",
                "--runs",
                "3",
                "--threads",
                "100000",
                "--out",
                "o",
            ],
            "threads = 100000 is not allowed: give at most 1024",
        ),
    ];
    for (args, want) in cases {
        let o = rhonn(p, &args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(want), "{args:?}: {}", stderr(&o));
        assert!(!p.join("o").exists(), "{args:?} wrote its folder");
    }
}

/// An endless input (found by hand: `rhonn run /dev/zero` and `rhonn fit --data /dev/zero`
/// read until the machine killed them): refused with the file named, exit 2.
#[cfg(unix)]
#[test]
fn an_endless_input_file_is_refused_not_read_for_ever() {
    let d = tempfile::tempdir().unwrap();
    let cases: [(&[&str], &str); 3] = [
        (
            &["run", "/dev/zero", "--out", "o"],
            "cannot read /dev/zero: more than 256 MiB",
        ),
        (
            &[
                "fit",
                "--data",
                "/dev/zero",
                "--inputs",
                "u",
                "--outputs",
                "y",
                "--out",
                "o",
            ],
            "/dev/zero: cannot read: a line longer than 1 MiB",
        ),
        (
            &[
                "predict",
                "--model",
                "/dev/zero",
                "--data",
                "/dev/zero",
                "--out",
                "o",
            ],
            "cannot read /dev/zero: more than 256 MiB",
        ),
    ];
    for (args, want) in cases {
        let o = rhonn(d.path(), args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(want), "{args:?}: {}", stderr(&o));
        assert!(!d.path().join("o").exists());
    }
}

/// A column named twice (`--inputs u,u` fitted a model of two identical inputs without a
/// word): refused by `fit` and `identify`, naming it.
#[test]
fn a_column_named_twice_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let est = data("estimation.csv");
    for cmd in ["fit", "identify"] {
        for (ins, outs, want) in [
            ("u,u", "y", "inputs name `u` twice"),
            ("u", "y,y", "outputs name `y` twice"),
        ] {
            let o = rhonn(
                d.path(),
                &[
                    cmd,
                    "--data",
                    s(&est),
                    "--inputs",
                    ins,
                    "--outputs",
                    outs,
                    "--out",
                    "o",
                ],
            );
            assert_eq!(o.status.code(), Some(2), "{cmd} {ins} {outs}: {}", stderr(&o));
            assert!(stderr(&o).contains(want), "{cmd}: {}", stderr(&o));
            assert!(!d.path().join("o").exists());
        }
    }
}

/// Issue 56: one rule for gaps in every command. A jump of 3.9e7 s splits the record in
/// `fit` and `identify` (no value made up across it; before: 9,751,024 rows, 99.99 %
/// interpolated) and is refused by `predict`, which runs over one record; 100 rows
/// removed (10 % of the samples) are refused by all three with the count; a
/// `--resample` 4,000 times finer than the data is refused at once.
#[test]
fn a_long_gap_splits_the_record_and_many_missing_rows_are_refused_in_every_command() {
    let d = tempfile::tempdir().unwrap();
    let jump = edited(d.path(), "jump.csv", |r| {
        for row in r.iter_mut().skip(600) {
            row[0] = format!("{}", row[0].parse::<f64>().unwrap() + 3.9e7);
        }
    });
    let removed = edited(d.path(), "removed.csv", |r| {
        let kept: Vec<Vec<String>> = r
            .iter()
            .enumerate()
            .filter(|(k, _)| k % 10 != 5)
            .map(|(_, x)| x.clone())
            .collect();
        *r = kept;
    });
    let fit = |data: &Path, out: &str, extra: &[&str]| {
        let mut a = vec![
            "fit",
            "--data",
            s(data),
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--select",
            "none",
            "--out",
            out,
        ];
        a.extend(extra);
        rhonn(d.path(), &a)
    };
    let identify = |data: &Path, out: &str| {
        rhonn(
            d.path(),
            &[
                "identify",
                "--data",
                s(data),
                "--inputs",
                "u",
                "--outputs",
                "y",
                "--model",
                s(&model("tanks-online-lagged.toml")),
                "--out",
                out,
            ],
        )
    };
    let o = fit(&jump, "fj", &[]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("jump.csv: split into 2 records at 1 gap of more than"),
        "{}",
        stderr(&o)
    );
    let sum: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("fj/summary.json")).unwrap()).unwrap();
    assert_eq!(
        sum["training"]["free_run"].as_array().unwrap().len(),
        2,
        "two records"
    );
    let o = identify(&jump, "ij");
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stderr(&o).contains("split into 2 records"), "{}", stderr(&o));
    let o = rhonn(
        d.path(),
        &[
            "predict",
            "--model",
            "fj/model.json",
            "--data",
            s(&jump),
            "--out",
            "pj",
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("predict each part as its own file"),
        "{}",
        stderr(&o)
    );
    assert!(!d.path().join("pj").exists());
    for o in [
        fit(&removed, "fr", &[]),
        identify(&removed, "ir"),
        rhonn(
            d.path(),
            &[
                "predict",
                "--model",
                "fj/model.json",
                "--data",
                s(&removed),
                "--out",
                "pr",
            ],
        ),
    ] {
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains("removed.csv, column `t`: 102 samples missing in 102 short gaps")
                && e.contains("at most 1 %"),
            "{e}"
        );
    }
    let o = fit(&data("estimation.csv"), "fs", &["--resample", "0.001"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("10 times its 1024 rows"), "{}", stderr(&o));
    for out in ["fr", "ir", "pr", "fs"] {
        assert!(!d.path().join(out).exists(), "{out} written");
    }
}

/// Issue 56: model.json's fields are all read or refused: a newer or unreadable
/// `rhonn_version`, a baseline whose signals or grid an edit moved away from the model's,
/// and a file far larger than any model (refused before it is parsed).
#[test]
fn a_model_file_s_version_baseline_and_size_are_checked_not_ignored() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(
        d.path(),
        &[
            "fit",
            "--data",
            s(&data("estimation.csv")),
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--select",
            "none",
            "--out",
            "m",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("m/model.json")).unwrap()).unwrap();
    let refused = |m: &serde_json::Value, want: &[&str]| {
        let o = predict(d.path(), m, "p");
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        let e = stderr(&o);
        assert!(want.iter().all(|w| e.contains(w)), "{want:?}: {e}");
        assert!(!d.path().join("p").exists());
    };
    for (v, want) in [
        ("99.0.0", "written by a newer rhonn"),
        ("0.2.0", "written by a newer rhonn"),
        ("banana", "MAJOR.MINOR.PATCH"),
    ] {
        let mut e = m.clone();
        e["rhonn_version"] = v.into();
        refused(&e, &["rhonn_version", want]);
    }
    for (field, value) in [
        ("sample_time_s", serde_json::json!(8.0)),
        ("inputs", serde_json::json!(["v"])),
        ("outputs", serde_json::json!(["z"])),
    ] {
        let mut e = m.clone();
        e["baseline"][field] = value;
        refused(&e, &["baseline", "the model's own"]);
    }
    let mut e = m.clone();
    e["padding"] = serde_json::json!("x".repeat(17 << 20));
    refused(&e, &["at most 16 MB"]);
    let o = predict(d.path(), &m, "ok");
    assert!(o.status.success(), "{}", stderr(&o));
}
