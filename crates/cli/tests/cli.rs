//! The real `rhonn` binary in a temporary folder: files written, exit codes, error text.

use crate::util;

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
            "report.html",
            "rhonn-manifest.json",
            "states.svg",
            "summary.json",
            "trajectory.csv"
        ]
    );
    let csv = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], "t,current,demand,p_line,stroke");
    assert!(lines[1].starts_with("0,0,0,2000000,0"), "{}", lines[1]);
    assert!(lines.last().unwrap().starts_with("40,"));
    assert_eq!(lines.len(), 40_002);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["scenario"], "thesis-ch3");
    assert!(summary["solver"]["rhs_evaluations"].as_u64().unwrap() > 100);
    let p = summary["open_loop"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["state"] == "p_line")
        .unwrap();
    assert_eq!(p["max_value"], 25.0);
    assert!(summary["floor"]["time_below_s"].as_f64().unwrap() > 1.0);
    let svg = std::fs::read_to_string(out.join("states.svg")).unwrap();
    assert!(svg.contains("p_line [MPa]") && svg.contains("stroke [mm]") && svg.contains("time [s]"));
}

#[test]
fn regulated_run_has_set_point_and_regulation_figures() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["run", "regulated-pi", "--out", "reg"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(d.path().join("reg/trajectory.csv")).unwrap();
    assert!(
        csv.starts_with("t,p_line_ref,demand,p_line,stroke,current,p_line_measured\n"),
        "{}",
        csv.lines().next().unwrap()
    );
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("reg/summary.json")).unwrap()).unwrap();
    let r = &s["control"][0];
    assert!(r["ise"].as_f64().unwrap() > 0.0);
    assert!(r["max_abs_deviation"].as_f64().unwrap() > 0.0);
    // After the start-up the pressure stays in the model's valid range.
    assert_eq!(r["time_below_floor_after_settle_s"], 0.0);
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
            "`duration_s` = -1 is not allowed: finite and > 0",
        ),
        (
            text.replace("kind = \"pump\"", "kind = \"pump\"\nbeta = 3"),
            "`plant.beta` = 3 is not allowed: a parameter of the pump: kind, initial, ",
        ),
        (
            text.replace("initial = [2.0, 0.0]", "initial = [30.0, 0.0]"),
            "`plant.initial[0] (p_line, MPa)` = 30 is not allowed: a value in [0, 25] MPa (line pressure P_l",
        ),
        (
            text.replace("[25.0, 0.8]", "[5.0, 0.8]"),
            "`input.current.points[2][0]` = 5",
        ),
        (
            text.replace("output_interval_s = 0.001", "output_interval_s = 60.0"),
            "`output_interval_s` = 60 is not allowed: at most duration_s = 40 s: at least one output sample",
        ),
        (
            text.replace("duration_s = 40.0", "duration_s = \"forty\""),
            "invalid type",
        ),
        (
            format!("{text}\n[input.demand]\nkind = \"trapezoids\"\nslew_per_s = 3.0\npulses = []\n"),
            "`input.demand.slew_per_s` = 3 is not allowed: at most 2",
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
        "states.svg",
        "errors.svg",
        "validation.svg",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let csv = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    assert!(csv.starts_with("t,current,demand,p_line,p_line_hat,stroke,stroke_hat\n"));
    let val = std::fs::read_to_string(out.join("validation.csv")).unwrap();
    assert!(val.starts_with(
        "t,current,demand,p_line,p_line_hat_series_parallel,p_line_hat_parallel,stroke,stroke_hat_series_parallel,stroke_hat_parallel\n"
    ), "{}", val.lines().next().unwrap());
    let w: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("weights.json")).unwrap()).unwrap();
    assert_eq!(w["states"], serde_json::json!(["p_line", "stroke"]));
    assert_eq!(w["weights"].as_array().unwrap().len(), 2);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let figs = s["identification"].as_array().unwrap();
    assert_eq!(figs.len(), 2);
    assert!(figs[0].get("final_weight_norm").is_some());
    for mode in ["training", "series_parallel", "free_run"] {
        for key in ["rms_error", "fit_percent", "convergence_time_s"] {
            assert!(figs[0]["whole_run"][mode].get(key).is_some(), "{mode}.{key}");
        }
    }
}

#[test]
fn reproduce_runs_every_thesis_scenario() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["reproduce", "--out", "r"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // The console leads with what was reproduced, a line per scenario, the expected
    // failure (the frozen identifier's free run) said as expected on its own line, and the
    // thesis's convergence figure beside rhonn's.
    let stdout = String::from_utf8_lossy(&o.stdout);
    let lines: Vec<&str> = stdout.lines().collect();
    assert!(lines[0].starts_with("reproduced"), "{stdout}");
    for (k, name) in ["thesis-ch3", "thesis-ch5", "regulated-pi", "control-adaptive"]
        .iter()
        .enumerate()
    {
        assert!(lines[k + 1].starts_with(&format!("  {name}: ")), "{stdout}");
    }
    let ch5 = lines[2];
    assert!(
        ch5.contains("as expected of it") && ch5.contains("-328 % (p_line)"),
        "{ch5}"
    );
    assert!(
        ch5.contains("from 0.056 s (the thesis, figure 5.5: about 0.08 s)"),
        "{ch5}"
    );
    assert!(lines[4].contains("IAE 10.8 MPa s against 83.2"), "{}", lines[4]);
    // Every figure line of a frozen model's fit says it is frozen.
    assert!(
        lines
            .iter()
            .filter(|l| l.contains("fit -"))
            .all(|l| l.contains("frozen")),
        "{stdout}"
    );
    for name in ["thesis-ch3", "thesis-ch5", "regulated-pi", "control-adaptive"] {
        assert!(
            d.path().join("r").join(name).join("summary.json").is_file(),
            "{name}"
        );
    }
    // The adaptive run holds every controller: CSV columns, summary figures, plots.
    let dir = d.path().join("r").join("control-adaptive");
    let csv = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    for col in [
        "p_line",
        "p_line_baseline",
        "p_line_second_baseline",
        "current",
        "current_baseline",
        "p_line_ref",
        "stroke_ref",
        "p_line_model",
        "w_norm",
        "w1_norm",
    ] {
        assert!(header.split(',').any(|c| c == col), "{col} in {header}");
    }
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let loops = s["control"].as_array().unwrap();
    assert_eq!(loops.len(), 3);
    for r in loops {
        for key in [
            "ise",
            "iae",
            "max_abs_deviation_settled",
            "max_abs_deviation_early",
            "time_input_saturated_s",
            "time_within_1pct_s",
            "within_1pct_percent",
            "time_below_floor_after_settle_s",
        ] {
            assert!(r[key].as_f64().is_some(), "{key}");
        }
        assert_eq!(
            r["overshoot_percent"].as_array().map(Vec::len),
            Some(4),
            "one per set-point step"
        );
        assert_eq!(r["states_bounded"], serde_json::Value::Bool(true));
    }
    assert_eq!(loops[1]["controller"], "cascade-pi");
    assert_eq!(loops[2]["tuning"], "nominal-optimal");
    let weights = std::fs::read_to_string(dir.join("weights.svg")).unwrap();
    assert!(weights.contains("ball radius (bound)"));
    // The projection holds: |W_1 - centre| never leaves the ball (trajectory.csv).
    let traj = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    let head: Vec<&str> = traj.lines().next().unwrap().split(',').collect();
    let (d, r) = (
        head.iter().position(|h| *h == "w1_distance").unwrap(),
        head.iter().position(|h| *h == "w1_ball_radius").unwrap(),
    );
    let mut closest = f64::INFINITY;
    for line in traj.lines().skip(1) {
        let f: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        assert!(f[d] <= f[r] * (1.0 + 1e-12), "{line}");
        closest = closest.min(f[r] - f[d]);
    }
    assert!(closest.is_finite());
    let states = std::fs::read_to_string(dir.join("states.svg")).unwrap();
    assert!(states.contains("p_line (cascade-pi baseline)") && states.contains("p_line set-point"));
}

#[test]
fn bad_adaptive_controller_settings_are_clear_errors() {
    let d = tempfile::tempdir().unwrap();
    let shipped = String::from_utf8(rhonn(d.path(), &["show", "control-adaptive"]).stdout).unwrap();
    let cases = [
        (
            shipped.replace("ball_fraction = 0.5", "ball_fraction = 1.0"),
            "`control.controller.ball_fraction` = 1 is not allowed: a number in (0, 1)",
        ),
        (
            shipped.replace("lambda_per_s = 100.0", "lambda_per_s = -1.0"),
            "`control.controller.lambda_per_s` = -1 is not allowed: a finite number > 0",
        ),
        (
            shipped.replace("ti_s = 0.07", "ti_s = 0.0"),
            "`control.baseline.ti_s` = 0 is not allowed: finite and > 0",
        ),
        (
            shipped.replace("kind = \"pump-cascade-pi\"", "kind = \"pid\""),
            "unknown variant `pid`, expected one of `pi`, `rhonn-indirect`, `cascade`, `pump-rhonn-adaptive`, `pump-cascade-pi`",
        ),
        (
            shipped.replace("setpoint_weight = 0.8", "setpoint_weight = 1.5"),
            "`control.baseline.setpoint_weight` = 1.5 is not allowed: a number in [0, 1]",
        ),
        (
            shipped.replace("stroke_gain = 8.0", "stroke_gain = 8.0\nkp = 0.15"),
            "unknown field `kp`, expected one of `state`, `kp_mm_per_mpa`",
        ),
        (
            shipped.replace("integral_per_s2 = 1000.0", "integral_per_s2 = -1.0"),
            "`control.controller.integral_per_s2` = -1 is not allowed: a finite number >= 0",
        ),
        (
            shipped.replace("actuator_memory_s = 5.0", "actuator_memory_s = -5"),
            "`control.controller.actuator_memory_s` = -5 is not allowed: a finite number >= 0",
        ),
        (
            shipped.replace("lag_scale_s = 0.04", "lag_scale_s = inf"),
            "`control.controller.lag_scale_s` = inf is not allowed: a finite number >= 0",
        ),
        (
            shipped.replace("period_s = 0.005", "period_s = 0.005\ndelay_periods = 200000"),
            "`control.delay_periods` = 200000 is not allowed: a whole number of control periods from 0 to 100000",
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
        (
            // Refused at once (it stepped for about 20 s before its solver gave up).
            shipped.replace("a = [120.0, 41.0]", "a = [1e9, 41.0]"),
            "`identifier.a[0]` = 1000000000 is not allowed: at most 825000 1/s for a run of duration_s = 40 s",
        ),
    ];
    assert_bad_scenarios(d.path(), &cases);
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
        .starts_with("run,status,beta_mpa,mu_1,mu_2,q_0_dm3_s,qdot_max_dm3_s2,"));
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
    let kept = |dir: &str| {
        let v: serde_json::Value =
            serde_json::from_str(&read(d.path().join(dir).join("summary.json"))).unwrap();
        v["envelope_runs"][0][1].as_u64().unwrap()
    };
    assert_eq!(kept("all"), 40);
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
    assert_eq!(kept("seven"), 7);
    assert_eq!(read(d.path().join("seven/traces.csv")).lines().count(), 8);
    assert_eq!(read(d.path().join("seven/runs.csv")), all);
    ok(&[&base[..], &["--envelope-runs", "0", "--out", "none"]].concat());
    assert!(!d.path().join("none/envelope.svg").exists());
    // The draws differ between runs and stay within the tolerances.
    let betas: Vec<f64> = all
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(2).unwrap().parse().unwrap())
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
    // More shards than runs: a shard would run nothing, so it is refused before a folder.
    let few = ["campaign", "tanks-control", "--runs", "3", "--seed", "1"];
    let o = rhonn(
        d.path(),
        &[&few[..], &["--shard", "2/10", "--out", "empty"]].concat(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("give M at most 3"), "{}", stderr(&o));
    assert!(!d.path().join("empty").exists());
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
    let header: Vec<&str> = runs.lines().next().unwrap().split(',').collect();
    let at = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<String>> = runs
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    // Three parameters vary: 2^3 corners; the fixed ones keep the scenario's values.
    assert_eq!(rows.len(), 8);
    let col = |name: &str| {
        rows.iter()
            .map(|r| r[at(name)].parse::<f64>().unwrap())
            .collect::<Vec<_>>()
    };
    assert!(col("beta_mpa").iter().all(|b| *b == 1000.0 || *b == 1100.0));
    assert!(
        col("mu_1")
            .iter()
            .all(|m| ((m / 78e-6 - 1.0).abs() - 0.1).abs() < 1e-9),
        "{:?}",
        col("mu_1")
    );
    assert!(
        col("q_0_dm3_s").iter().all(|q| *q == 0.13) && col("qdot_max_dm3_s2").iter().all(|q| *q == 2.0),
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
        let v: Vec<&str> = l.split(',').collect();
        let (beta, mu_1): (f64, f64) = (v[at("beta_mpa")].parse().unwrap(), v[at("mu_1")].parse().unwrap());
        assert!(
            (1000.0..=1100.0).contains(&beta) && (mu_1 / 78e-6 - 1.0).abs() <= 0.1 + 1e-12,
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
