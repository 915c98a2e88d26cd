//! What `rhonn fit` tells a user about their data before and while it fits: warnings
//! that name the problem and the option to try, `--resample`, `--units`.

use crate::util;

use util::{rhonn, stderr};

/// A Duffing oscillator (x'' + 0.2 x' + x + x^3 = u, u a new uniform draw every 0.5 s)
/// integrated at 1 ms and written every `every` ms, 100 s.
fn duffing(path: &std::path::Path, every_ms: usize) {
    let mut s = String::from("t,u,y\n");
    let (mut x, mut v, mut u) = (0.0f64, 0.0f64, 0.0f64);
    let mut seed = 7u64;
    for k in 0..=100_000usize {
        if k % 500 == 0 {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            u = (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
        }
        if k % every_ms == 0 {
            s.push_str(&format!("{:.3},{u:.6},{x:.6}\n", k as f64 * 1e-3));
        }
        let a = u - 0.2 * v - x - x * x * x;
        v += a * 1e-3;
        x += v * 1e-3;
    }
    std::fs::write(path, s).unwrap();
}

fn fit_percent(stdout: &str, label: &str) -> f64 {
    let line = stdout.lines().find(|l| l.contains(label)).unwrap();
    let f = line.split("fit ").nth(1).unwrap().trim_end_matches(" %");
    f.parse().unwrap()
}

#[test]
fn fast_sampled_data_is_warned_about_and_resample_fixes_it() {
    let d = tempfile::tempdir().unwrap();
    duffing(&d.path().join("duffing.csv"), 10);
    let args = [
        "fit",
        "--data",
        "duffing.csv",
        "--inputs",
        "u",
        "--outputs",
        "y",
        "--units",
        "y=m,u=N",
        // The fixed structure the warning's advice is measured with (selection, the
        // default, would pick its own lags).
        "--select",
        "none",
    ];
    let o = rhonn(d.path(), &[&args[..], &["--out", "a"]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("warning: output `y` changes slowly"), "{e}");
    // The value the warning advises.
    let advised = e
        .split("`--resample ")
        .nth(1)
        .and_then(|r| r.split('`').next())
        .unwrap()
        .to_string();
    let dt: f64 = advised.parse().unwrap();
    assert!((0.05..0.2).contains(&dt), "{advised}");
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(out.contains("rms error") && out.contains(" m, fit"), "{out}");
    // --units reaches the plots' axes.
    let svg = std::fs::read_to_string(d.path().join("a/training.svg")).unwrap();
    assert!(svg.contains("y [m]"), "the training plot's axis has no unit");
    let slow = fit_percent(&out, "free run (training data)");
    // The advice taken: no warning, and the free-run fit far better.
    let o = rhonn(
        d.path(),
        &[&args[..], &["--resample", &advised, "--out", "b"]].concat(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    let resampled = fit_percent(&out, "free run (training data)");
    eprintln!(
        "Duffing free-run fit on its training record: 10 ms {slow:.1} %, resampled to {advised} s {resampled:.1} %"
    );
    assert!(resampled > slow + 30.0, "{slow} -> {resampled}");
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("b/model.json")).unwrap()).unwrap();
    assert!((m["model"]["sample_time_s"].as_f64().unwrap() - dt).abs() < 1e-12);
    assert_eq!(m["units"]["y"], "m");
    // predict reads the units from the model and puts the record on the model's grid.
    let o = rhonn(
        d.path(),
        &[
            "predict",
            "--model",
            "b/model.json",
            "--data",
            "duffing.csv",
            "--out",
            "p",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(String::from_utf8_lossy(&o.stdout).contains(" m, fit"));
    let note = format!("predicting on the model's grid of {advised} s");
    assert!(stderr(&o).contains(&note), "{}", stderr(&o));
}

#[test]
fn suspicious_columns_are_warned_about_and_bad_options_refused() {
    let d = tempfile::tempdir().unwrap();
    duffing(&d.path().join("r.csv"), 100);
    let mut flat = String::from("t,u,c,y\n");
    for l in std::fs::read_to_string(d.path().join("r.csv"))
        .unwrap()
        .lines()
        .skip(1)
    {
        let f: Vec<&str> = l.split(',').collect();
        flat.push_str(&format!("{},{},1.5,{}\n", f[0], f[1], f[2]));
    }
    std::fs::write(d.path().join("r.csv"), flat).unwrap();
    let warn = |inputs: &str, outputs: &str| {
        // A folder per call: another model into a folder that holds one is refused.
        let out = format!("m-{}", inputs.replace(',', "-"));
        let o = rhonn(
            d.path(),
            &[
                "fit",
                "--data",
                "r.csv",
                "--inputs",
                inputs,
                "--outputs",
                outputs,
                // The warnings do not depend on the structure: the fixed one is quicker
                // than a selection.
                "--select",
                "none",
                "--out",
                &out,
            ],
        );
        stderr(&o)
    };
    assert!(warn("t,u", "y").contains("`t` is the time column"));
    assert!(warn("u,c", "y").contains("input `c` is constant"));
    assert!(warn("u,y", "y").contains("`y` is both an input and an output"));
    assert!(!warn("u", "y").contains("warning"));
    for (opt, val, want) in [
        ("--units", "y", "COLUMN=UNIT"),
        (
            "--units",
            "q=V",
            "column `q`, which is not among the inputs and outputs (u, y)",
        ),
        ("--resample", "0", "--resample 0 is not allowed"),
        ("--resample", "500", "give a shorter --resample"),
    ] {
        let o = rhonn(
            d.path(),
            &[
                "fit",
                "--data",
                "r.csv",
                "--inputs",
                "u",
                "--outputs",
                "y",
                opt,
                val,
                "--out",
                "x",
            ],
        );
        assert_eq!(o.status.code(), Some(2), "{opt} {val}");
        assert!(stderr(&o).contains(want), "{opt} {val}: {}", stderr(&o));
        assert!(!d.path().join("x").exists());
    }
}

/// An output that nothing the selection tries predicts better than its training mean on
/// the folds (here noise with a slow drift, which the input does not drive): `rhonn fit`
/// says so naming the output, keeps it in summary.json and model.json, and `rhonn predict`
/// repeats it; the model saved is the best of what was tried.
#[test]
fn an_output_no_candidate_predicts_better_than_its_mean_is_said_by_fit_and_predict() {
    use std::fmt::Write;
    let d = tempfile::tempdir().unwrap();
    let mut csv = String::from("t,u,y\n");
    let mut s = 12345u64;
    for k in 0..600 {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let noise = (s >> 33) as f64 / (1u64 << 31) as f64 - 0.5;
        let u = ((k / 7) % 5) as f64 - 2.0;
        writeln!(csv, "{k},{u},{}", noise + 0.1 * k as f64 / 600.0).unwrap();
    }
    std::fs::write(d.path().join("n.csv"), csv).unwrap();
    let fit = [
        "fit",
        "--data",
        "n.csv",
        "--inputs",
        "u",
        "--outputs",
        "y",
        "--out",
        "f",
    ];
    let o = rhonn(d.path(), &fit);
    let e = stderr(&o);
    assert!(o.status.success(), "{e}");
    assert!(
        e.contains("warning: output `y`: no candidate, the ARX included, beat predicting its training mean on every fold"),
        "{e}"
    );
    let read = |p: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.path().join(p)).unwrap()).unwrap()
    };
    let s = read("f/summary.json");
    assert_eq!(
        s["selection"]["no_better_than_mean"],
        serde_json::json!(["y"]),
        "{}",
        s["selection"]
    );
    let best = s["selection"]["candidates"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|c| c["output_scores"][0].as_f64())
        .fold(f64::INFINITY, f64::min);
    let mean = s["selection"]["mean_scores"][0].as_f64().unwrap();
    assert!(best.is_finite() && mean.is_finite(), "{best} {mean}");
    assert_eq!(
        read("f/model.json")["no_better_than_mean"],
        serde_json::json!(["y"])
    );
    let o = rhonn(
        d.path(),
        &[
            "predict",
            "--model",
            "f/model.json",
            "--data",
            "n.csv",
            "--out",
            "p",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("this prediction of `y` is no better than a constant"),
        "{}",
        stderr(&o)
    );
    let report = std::fs::read_to_string(d.path().join("f/report.html")).unwrap();
    assert!(
        report.contains("warning: output `y`"),
        "the report says it at the top"
    );
}

/// Messages read as sentences and figures keep their significant digits: "an ARX model",
/// "1 sample", "on 1 record" (no "(s)"), a small RMS error not printed as 0.0000,
/// `--resample -1` refused by rhonn (not taken for an option), and a fit into a folder holding another model is refused
/// unless `--force` (then it says what it replaces, with both fits).
#[test]
fn fit_messages_read_as_sentences_and_keep_significant_digits() {
    let d = tempfile::tempdir().unwrap();
    let est = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("data/cascaded-tanks/estimation.csv");
    // The tanks' output scaled by 1e-5: an RMS error of about 1e-5.
    let text = std::fs::read_to_string(&est).unwrap();
    let mut small = String::from("t,u,y\n");
    for line in text.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|c| c.parse().unwrap()).collect();
        small.push_str(&format!("{},{},{}\n", v[0], v[1], v[2] * 1e-5));
    }
    std::fs::write(d.path().join("small.csv"), small).unwrap();
    std::fs::write(d.path().join("arx.toml"), "kind = \"arx\"\nna = 1\nnb = 1\n").unwrap();
    let fit_with = |spec: Option<&str>, out: &str, force: bool| {
        let mut a = vec![
            "fit",
            "--data",
            "small.csv",
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--out",
            out,
        ];
        if let Some(s) = spec {
            a.extend(["--model", s]);
        }
        if force {
            a.push("--force");
        }
        rhonn(d.path(), &a)
    };
    let fit = |spec: Option<&str>, out: &str| fit_with(spec, out, false);
    let o = fit(Some("arx.toml"), "f");
    let (out, err) = (String::from_utf8_lossy(&o.stdout).into_owned(), stderr(&o));
    assert!(o.status.success(), "{err}");
    // Counts agree with their nouns: "1 record", never "record(s)".
    assert!(
        out.contains("fitted an ARX model with 3 features per output on 1 record\n"),
        "{out}"
    );
    assert!(!out.contains("(s)") && !err.contains("(s)"), "{out}{err}");
    assert!(err.contains("the model looks back 1 sample (4 s)"), "{err}");
    let line = out
        .lines()
        .find(|l| l.contains("free run (training data)"))
        .unwrap();
    let rms: f64 = line
        .split("rms error ")
        .nth(1)
        .unwrap()
        .split(',')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(rms > 1e-6 && !line.contains("rms error 0.0000"), "{line}");
    // The same fit again: the same model, nothing to say.
    let o = fit(Some("arx.toml"), "f");
    assert!(
        o.status.success() && !stderr(&o).contains("replacing"),
        "{}",
        stderr(&o)
    );
    // Another structure into the same folder: refused before anything is written, with
    // both fits; with --force it is replaced and says so.
    std::fs::write(d.path().join("arx2.toml"), "kind = \"arx\"\nna = 2\nnb = 2\n").unwrap();
    let model = d.path().join("f/model.json");
    let before = std::fs::read(&model).unwrap();
    let o = fit(Some("arx2.toml"), "f");
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("model.json holds another model")
            && err.contains(" before, ")
            && err.contains("give --force to replace it"),
        "{err}"
    );
    assert_eq!(std::fs::read(&model).unwrap(), before, "the earlier model stays");
    let o = fit_with(Some("arx2.toml"), "f", true);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("note: replacing")
            && err.contains("model.json of an earlier fit")
            && err.contains(" before, "),
        "{err}"
    );
    assert_ne!(std::fs::read(&model).unwrap(), before);
    let o = rhonn(
        d.path(),
        &[
            "fit",
            "--data",
            "small.csv",
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--resample",
            "-1",
            "--out",
            "g",
        ],
    );
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("--resample -1 is not allowed"), "{err}");
}

/// A column whose name ends in a unit (`_V`, `_pa`, `_mm`) gets that unit without
/// `--units`, and the console says it was read from the name; `--units` overrides it.
#[test]
fn units_are_read_from_the_column_names_and_units_overrides_them() {
    let d = tempfile::tempdir().unwrap();
    let mut s = String::from("t,u_heater_V,y_level_mm\n");
    for k in 0..300 {
        let u = if (k / 25) % 2 == 0 { 1.0 } else { -1.0 };
        s.push_str(&format!("{k},{u},{}\n", (k as f64 * 0.1).sin() + 0.5 * u));
    }
    std::fs::write(d.path().join("d.csv"), s).unwrap();
    let args = [
        "fit",
        "--data",
        "d.csv",
        "--inputs",
        "u_heater_V",
        "--outputs",
        "y_level_mm",
        "--select",
        "none",
    ];
    let o = rhonn(d.path(), &[&args[..], &["--out", "a"]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("units read from the column names: `u_heater_V` in V, `y_level_mm` in mm"),
        "{e}"
    );
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(out.contains(" mm, fit"), "{out}");
    let model: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("a/model.json")).unwrap()).unwrap();
    assert_eq!(model["units"]["y_level_mm"], "mm");
    // --units for one column: that one as given, the other still from its name.
    let o = rhonn(
        d.path(),
        &[&args[..], &["--units", "y_level_mm=m", "--out", "b"]].concat(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("`u_heater_V` in V") && !e.contains("`y_level_mm` in"),
        "{e}"
    );
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(out.contains(" m, fit"), "{out}");
}

/// Extreme numbers are printed with significant digits, and an undefined fit in words: a
/// record sampled every 1e-300 s (a unit mistake) whose output is 1e-310 at most gave a
/// warning holding a time of 300 digits and `fit NaN %`. (An output that small is now
/// refused, `a_column_too_small_to_square_is_refused_naming_it`; an output of zeros takes
/// the same path to the bound warning and the undefined fit.)
#[test]
fn extreme_numbers_are_printed_with_significant_digits_and_no_nan() {
    let d = tempfile::tempdir().unwrap();
    let mut s = String::from("t,u,y\n");
    for k in 0..300 {
        let u = (k as f64 * 0.1).sin();
        s.push_str(&format!("{:e},{u},0\n", k as f64 * 1e-300));
    }
    std::fs::write(d.path().join("tiny.csv"), s).unwrap();
    let o = rhonn(
        d.path(),
        &[
            "fit",
            "--data",
            "tiny.csv",
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
    let all = format!("{}{}", String::from_utf8_lossy(&o.stdout), stderr(&o));
    assert!(
        all.contains("e-300 s:"),
        "the bound warning names its time: {all}"
    );
    for word in all.split_whitespace() {
        assert!(word.len() <= 40, "a word of {} characters: {word}", word.len());
    }
    assert!(!all.contains("NaN"), "{all}");
}

/// A newcomer's own data: a two-tank system with a saturating upper tank (driven from 0
/// to 10 V, it overflows at its 300 mm rim), simulated open loop by `rhonn run`, sampled
/// at 2 s and written with times in seconds, and the same in milliseconds. In seconds no
/// command warns of anything; in milliseconds `fit` and `identify` each say the one
/// thing to do, and `fit` fits the same model either way (its lags count samples).
#[test]
fn a_newcomer_s_tanks_at_2_s_and_in_ms_get_no_wrong_hint() {
    let d = tempfile::tempdir().unwrap();
    let scenario = "name = \"newcomer\"\nduration_s = 7200.0\noutput_interval_s = 2.0\n\
                    [plant]\nkind = \"tanks\"\ninitial = [50.0, 50.0]\n[input]\n\
                    voltage = { kind = \"aprbs\", start_s = 0.0, end_s = 7200.0, hold_s = 80.0, \
                    ramp_s = 2.0, low = 0.0, high = 10.0, seed = 5 }\n";
    std::fs::write(d.path().join("newcomer.toml"), scenario).unwrap();
    let o = rhonn(d.path(), &["run", "newcomer.toml", "--out", "sim"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(d.path().join("sim/trajectory.csv")).unwrap();
    let (mut s, mut ms) = (
        String::from("t,pump_V,level_mm\n"),
        String::from("t,pump_V,level_mm\n"),
    );
    let mut top = 0.0f64;
    for line in text.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        let (t, u, h1, h2) = (v[0], v[1], v[2], v[3]);
        top = top.max(h1);
        s.push_str(&format!("{t},{u},{:.4}\n", h2 * 1e3));
        ms.push_str(&format!("{},{u},{:.4}\n", (t * 1e3).round(), h2 * 1e3));
    }
    assert!(top >= 0.2999, "the upper tank never filled: {top} m");
    std::fs::write(d.path().join("tanks_s.csv"), s).unwrap();
    std::fs::write(d.path().join("tanks_ms.csv"), ms).unwrap();
    let warnings = |o: &std::process::Output| -> Vec<String> {
        assert!(o.status.success(), "{}", stderr(o));
        stderr(o)
            .lines()
            .filter(|l| l.starts_with("warning"))
            .map(String::from)
            .collect()
    };
    let mut fits = Vec::new();
    for command in ["fit", "identify"] {
        for unit in ["s", "ms"] {
            let data = format!("tanks_{unit}.csv");
            let out = format!("{command}-{unit}");
            let cols = ["--inputs", "pump_V", "--outputs", "level_mm"];
            let o = rhonn(
                d.path(),
                &[&[command, "--data", &data, "--out", &out][..], &cols[..]].concat(),
            );
            let w = warnings(&o);
            if unit == "s" {
                assert!(w.is_empty(), "{command} in seconds: {w:?}");
            } else {
                assert_eq!(w.len(), 1, "{command} in ms: {w:?}");
                assert!(
                    w[0].contains("the sample time is 2 s") && w[0].contains("divide it by 1,000"),
                    "{command}: {w:?}"
                );
            }
            if command == "fit" {
                let stdout = String::from_utf8_lossy(&o.stdout).replace(&data, "DATA");
                fits.push(
                    stdout
                        .lines()
                        .filter(|l| l.contains("fit "))
                        .map(String::from)
                        .collect::<Vec<_>>(),
                );
            }
        }
    }
    assert!(!fits[0].is_empty() && fits[0] == fits[1], "{fits:?}");
}

/// "A column of subnormal values (1e-310) fits as a constant (`rms error 0`)": a signal
/// whose largest magnitude is below 1e-150 (not all zeros) is refused by `fit` and
/// `identify`, naming the file, the column and its largest value, and nothing is written;
/// an all-zero column and one of 1e-100 are read as they are.
#[test]
fn a_column_too_small_to_square_is_refused_naming_it() {
    let d = tempfile::tempdir().unwrap();
    let write = |name: &str, scale: f64| {
        let mut s = String::from("t,u,y\n");
        let mut y = 0.0;
        for k in 0..400 {
            let u = ((k * 7919) % 200) as f64 / 100.0 - 1.0;
            y = 0.9 * y + 0.1 * u;
            s.push_str(&format!("{k},{:e},{y}\n", u * scale));
        }
        std::fs::write(d.path().join(name), s).unwrap();
    };
    write("tiny.csv", 1e-310);
    for command in ["fit", "identify"] {
        let o = rhonn(
            d.path(),
            &[
                command,
                "--data",
                "tiny.csv",
                "--inputs",
                "u",
                "--outputs",
                "y",
                "--out",
                command,
            ],
        );
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{command}: {e}");
        assert!(
            e.contains("tiny.csv: column `u`: its largest magnitude is 1e-310, below 1e-150"),
            "{command}: {e}"
        );
        assert!(!d.path().join(command).exists(), "{command} wrote a folder");
    }
    for (name, scale) in [("zeros.csv", 0.0), ("small.csv", 1e-100)] {
        write(name, scale);
        let o = rhonn(
            d.path(),
            &[
                "fit",
                "--data",
                name,
                "--inputs",
                "u",
                "--outputs",
                "y",
                "--out",
                name,
            ],
        );
        assert!(!stderr(&o).contains("below 1e-150"), "{name}: {}", stderr(&o));
    }
}

/// A first command on one's own data without --inputs or --outputs: the file's columns are
/// listed beside clap's message (exit 2, nothing written); for `identify` too.
#[test]
fn missing_inputs_or_outputs_list_the_files_columns() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("mine.csv"), "t,valve_V,flow_m3_s\n0,1,2\n0.1,1,2\n").unwrap();
    for args in [
        &["fit", "--data", "mine.csv", "--out", "o"][..],
        &["identify", "--data=mine.csv", "--inputs", "valve_V", "--out", "o"][..],
    ] {
        let o = rhonn(d.path(), args);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{e}");
        assert!(e.contains("--outputs <OUTPUTS>"), "{e}");
        assert!(
            e.contains(
                "the columns of mine.csv: t, valve_V, flow_m3_s; give --inputs and --outputs from them"
            ),
            "{e}"
        );
        assert!(!d.path().join("o").exists());
    }
    // No hint where the file cannot be read (the missing argument is the message).
    let o = rhonn(d.path(), &["fit", "--data", "none.csv", "--out", "o"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(!stderr(&o).contains("the columns of"), "{}", stderr(&o));
}
