//! The second plant from the command line: `tanks-identify` and `tanks-control` run,
//! list, show, bench and campaign (with resume) from the scenario alone.

use crate::util;

use util::{files_in, rhonn, stderr};

fn json(path: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn tanks_scenarios_are_listed_and_run_like_the_pumps() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["scenarios"]);
    let list = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(
        list.contains("tanks-identify") && list.contains("tanks-control"),
        "{list}"
    );
    let o = rhonn(d.path(), &["run", "tanks-identify"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let dir = d.path().join("out/tanks-identify");
    assert_eq!(
        files_in(&dir),
        [
            "errors.svg",
            "inputs.svg",
            "report.html",
            "rhonn-manifest.json",
            "states.svg",
            "summary.json",
            "trajectory.csv",
            "validation.csv",
            "validation.svg",
            "weights.json"
        ]
    );
    let traj = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    assert_eq!(traj.lines().next().unwrap(), "t,voltage,h1,h1_hat,h2,h2_hat");
    assert_eq!(traj.lines().count(), 6002);
    let s = json(&dir.join("summary.json"));
    for st in s["identification"].as_array().unwrap() {
        let (tr, va) = (
            st["training_fit_percent"].as_f64().unwrap(),
            st["validation_fit_percent"].as_f64().unwrap(),
        );
        eprintln!("{}: online fit {tr:.1} %, frozen free run {va:.1} %", st["state"]);
        assert!(tr > 90.0 && va > 50.0, "{st}");
    }
    let o = rhonn(d.path(), &["run", "tanks-control"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let dir = d.path().join("out/tanks-control");
    assert_eq!(
        files_in(&dir),
        [
            "inputs.svg",
            "report.html",
            "rhonn-manifest.json",
            "states.svg",
            "summary.json",
            "trajectory.csv",
            "weights.svg"
        ]
    );
    let s = json(&dir.join("summary.json"));
    let c = s["control"].as_array().unwrap();
    assert_eq!(
        (c[0]["controller"].as_str(), c[1]["controller"].as_str()),
        (Some("rhonn-cascade"), Some("pi-cascade"))
    );
    for f in c {
        // Both regulate: the final error is under 2 mm on a 220 mm set-point.
        assert!(f["final_error"].as_f64().unwrap().abs() < 2.0, "{f}");
        assert!(f["iae"].as_f64().unwrap() > 0.0);
    }
    let header = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    let header = header.lines().next().unwrap();
    assert_eq!(
        header,
        "t,h2_ref,h1,h2,voltage,h1_ref,h2_model,w_norm,w1_norm,w1_distance,w1_ball_radius,h1_baseline,h2_baseline,voltage_baseline,h1_ref_baseline"
    );
    // The adaptive controller's projection holds at every instant; its weights plot
    // shows the gain weights against the ball's radius.
    let traj = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    let header: Vec<&str> = traj.lines().next().unwrap().split(',').collect();
    let at = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (dist, radius) = (at("w1_distance"), at("w1_ball_radius"));
    for line in traj.lines().skip(1) {
        let f: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        assert!(f[dist] <= f[radius] * (1.0 + 1e-9), "{line}");
    }
    let weights = std::fs::read_to_string(dir.join("weights.svg")).unwrap();
    assert!(weights.contains("ball radius (bound)"));
    // show prints the shipped file; bench times it.
    let o = rhonn(d.path(), &["show", "tanks-control"]);
    assert!(String::from_utf8_lossy(&o.stdout).contains("kind = \"tanks\""));
    let o = rhonn(
        d.path(),
        &["bench", "tanks-control", "--seconds", "0.05", "--json"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let b: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(b[0]["median_s"].as_f64().unwrap() > 0.0 && b[0]["rhs_evaluations"].as_u64().unwrap() > 0);
}

#[test]
fn a_tanks_campaign_of_200_runs_finishes_and_resumes_to_the_same_bytes() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(
        d.path(),
        &[
            "campaign",
            "tanks-control",
            "--runs",
            "200",
            "--seed",
            "4",
            "--out",
            "c",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let dir = d.path().join("c");
    let files = files_in(&dir);
    assert_eq!(
        files[..8],
        [
            "campaign.json",
            "envelope.csv",
            "envelope.svg",
            "histograms.svg",
            "report.html",
            "runs.csv",
            "summary.json",
            "traces.csv"
        ]
    );
    // The five worst runs' scenarios.
    assert_eq!(files.len(), 13, "{files:?}");
    assert!(files[8..]
        .iter()
        .all(|f| f.starts_with("worst-run-") && f.ends_with(".toml")));
    // The envelope of both controllers' lower level over the 200 runs, with the set-point;
    // each band's median within its min-max at every instant.
    let env = std::fs::read_to_string(dir.join("envelope.csv")).unwrap();
    let head: Vec<&str> = env.lines().next().unwrap().split(',').collect();
    assert_eq!((head[1], head[11]), ("h2_min_mm", "h2_ref_mm"));
    for line in env.lines().skip(1) {
        let f: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        for b in [1, 6] {
            assert!(f[b] <= f[b + 2] && f[b + 2] <= f[b + 4], "{line}");
        }
    }
    assert!(env.lines().count() > 100);
    assert_eq!(
        json(&dir.join("summary.json"))["envelope_runs"][0][1].as_u64(),
        Some(200)
    );
    let full = std::fs::read_to_string(dir.join("runs.csv")).unwrap();
    assert_eq!(full.lines().count(), 201);
    let s = json(&dir.join("summary.json"));
    assert_eq!((s["runs"].as_u64(), s["failed"].as_u64()), (Some(200), Some(0)));
    // Interrupted after `kept` runs, the next row cut to `cut` of its bytes: the same
    // command resumes, runs the others (and the cut one), and writes the same bytes.
    let lines: Vec<&str> = full.lines().collect();
    let traces = std::fs::read_to_string(dir.join("traces.csv")).unwrap();
    let resume = |kept: usize, cut: usize| {
        let mut partial = lines[..kept + 1].join("\n");
        partial.push('\n');
        partial.push_str(&lines[kept + 1][..cut]);
        std::fs::write(dir.join("runs.partial.csv"), partial).unwrap();
        std::fs::remove_file(dir.join("runs.csv")).unwrap();
        // The kept runs' traces, as the killed campaign had flushed them.
        let done: String = traces
            .lines()
            .enumerate()
            .filter(|(k, l)| *k == 0 || l.split(',').next().unwrap().parse::<usize>().unwrap() < kept)
            .map(|(_, l)| format!("{l}\n"))
            .collect();
        std::fs::write(dir.join("traces.partial.csv"), done).unwrap();
        let args = [
            "campaign",
            "tanks-control",
            "--runs",
            "200",
            "--seed",
            "4",
            "--out",
            "c",
        ];
        let o = rhonn(d.path(), &args);
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(std::fs::read_to_string(dir.join("runs.csv")).unwrap(), full);
        assert!(!dir.join("runs.partial.csv").exists() && !dir.join("traces.partial.csv").exists());
        assert_eq!(std::fs::read_to_string(dir.join("traces.csv")).unwrap(), traces);
        stderr(&o)
    };
    let e = resume(70, 20);
    assert!(e.contains("resuming: 70 runs already done"), "{e}");
    assert_eq!(std::fs::read_to_string(dir.join("envelope.csv")).unwrap(), env);
    // Cut inside its last figure, a row keeps its number of fields but not its line
    // break: it is run again, not kept with a shortened number.
    let e = resume(40, lines[41].len() - 2);
    assert!(
        e.contains("its last row was cut and is ignored") && e.contains("resuming: 40 runs already done"),
        "{e}"
    );
    // Another seed into the same folder is refused.
    let o = rhonn(
        d.path(),
        &[
            "campaign",
            "tanks-control",
            "--runs",
            "200",
            "--seed",
            "5",
            "--out",
            "c",
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("holds another campaign"), "{}", stderr(&o));
}

/// A tank campaign run as 3 shards and merged with `rhonn merge` writes the same runs,
/// summary and envelope as the unsharded campaign; an incomplete set of shards is refused.
#[test]
fn tank_campaign_shards_merge_to_the_unsharded_campaign() {
    let d = tempfile::tempdir().unwrap();
    let run = |extra: &[&str], out: &str| {
        let mut a = vec![
            "campaign",
            "tanks-control",
            "--runs",
            "30",
            "--seed",
            "9",
            "--out",
            out,
        ];
        a.extend_from_slice(extra);
        let o = rhonn(d.path(), &a);
        assert!(o.status.success(), "{}", stderr(&o));
    };
    run(&[], "whole");
    for k in 1..=3 {
        run(&["--shard", &format!("{k}/3")], &format!("s{k}"));
    }
    let o = rhonn(d.path(), &["merge", "s1", "s2", "s3", "--out", "merged"]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in ["runs.csv", "summary.json", "envelope.csv", "campaign.json"] {
        assert_eq!(
            std::fs::read_to_string(d.path().join("merged").join(f)).unwrap(),
            std::fs::read_to_string(d.path().join("whole").join(f)).unwrap(),
            "{f}"
        );
    }
    assert_eq!(
        files_in(&d.path().join("merged")),
        files_in(&d.path().join("whole"))
    );
    let o = rhonn(d.path(), &["merge", "s1", "s3", "--out", "part"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("some shard is missing"), "{}", stderr(&o));
}

#[test]
fn bad_tanks_scenarios_name_the_field() {
    let d = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(concat!(
        concat!(env!("CARGO_MANIFEST_DIR"), "/../.."),
        "/scenarios/tanks-control.toml"
    ))
    .unwrap();
    for (from, to, want) in [
        ("kind = \"tanks\"", "kind = \"boiler\"", "plant.kind"),
        (
            "initial = [50.0, 50.0]",
            "initial = [50.0, 50.0]\noutlet_9_mm2 = 3.0",
            "plant.outlet_9_mm2",
        ),
        ("initial = [50.0, 50.0]", "initial = [50.0]", "plant.initial"),
        ("output = \"h2\"", "output = \"h3\"", "control.output"),
        ("input = \"voltage\"", "input = \"current\"", "control.input"),
        ("period_s = 1.0", "period_s = 0.0", "control.period_s"),
        // Nanoseconds: refused before the run, not after the solver's step budget.
        (
            "period_s = 1.0",
            "period_s = 0.000000001",
            "control.period_s` = 1e-9 is not allowed: at most 1,000,000 control periods",
        ),
        (
            "lambda_per_s = 0.05",
            "lambda_per_s = -1.0",
            "control.controller.outer.lambda_per_s",
        ),
        // Found by a mutation run: a gain guess near the largest float wrote inf with exit 0.
        (
            "gain0 = 5.0",
            "gain0 = -1.7e308",
            "control.controller.outer.gain0` = -1.7e308 is not allowed",
        ),
        (
            "kp = 8.0, ti_s = 30.0",
            "kp = 8.0, ti_s = 0.0",
            "control.baseline.outer.ti_s",
        ),
        (
            "inner_range = [0.0, 290.0]           #",
            "inner_range = [290.0, 0.0]           #",
            "control.controller.inner_range",
        ),
    ] {
        assert!(text.contains(from), "{from}");
        std::fs::write(d.path().join("s.toml"), text.replace(from, to)).unwrap();
        let o = rhonn(d.path(), &["run", "s.toml"]);
        assert_eq!(o.status.code(), Some(2), "{to}");
        assert!(stderr(&o).contains(want), "{to}: {}", stderr(&o));
        assert_eq!(files_in(d.path()), ["s.toml"], "{to}");
    } // Found by the mutation sweep: a validation of 1e9 s ran until the solver's step
      // budget failed it, naming no setting.
    let ident = std::fs::read_to_string(concat!(
        concat!(env!("CARGO_MANIFEST_DIR"), "/../.."),
        "/scenarios/tanks-identify.toml"
    ))
    .unwrap();
    let long = ident.replace(
        "[validation]\nduration_s = 3000.0",
        "[validation]\nduration_s = 1e9",
    );
    assert_ne!(long, ident);
    std::fs::write(d.path().join("s.toml"), long).unwrap();
    let o = rhonn(d.path(), &["run", "s.toml"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("`validation.duration_s` = 1000000000 is not allowed"),
        "{}",
        stderr(&o)
    );
    assert_eq!(files_in(d.path()), ["s.toml"]);
}

/// `[campaign]` on the tanks, as on the pump: a parameter fixed, another drawn in a range
/// of its own, the rest within their stated tolerance; `summary.json` gives the plan; a
/// key that is no parameter of the tanks is refused naming them.
#[test]
fn a_tank_campaign_draws_as_its_campaign_section_says() {
    let d = tempfile::tempdir().unwrap();
    let shipped = String::from_utf8(rhonn(d.path(), &["show", "tanks-control"]).stdout).unwrap();
    let text = format!(
        "{shipped}\n[campaign]\noutlet_1_mm2 = {{ distribution = \"fixed\" }}\narea_2_cm2 = {{ min = 100.0, max = 110.0 }}\n"
    );
    std::fs::write(d.path().join("c.toml"), &text).unwrap();
    let o = rhonn(d.path(), &["campaign", "c.toml", "--runs", "12", "--out", "c"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let runs = std::fs::read_to_string(d.path().join("c/runs.csv")).unwrap();
    let head: Vec<&str> = runs.lines().next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let (outlet, area2, area1) = (col("outlet_1_mm2"), col("area_2_cm2"), col("area_1_cm2"));
    let mut areas = Vec::new();
    for line in runs.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let v = |k: usize| f[k].parse::<f64>().unwrap();
        assert_eq!(v(outlet), 40.0, "{line}");
        assert!((100.0..=110.0).contains(&v(area2)), "{line}");
        assert!((v(area1) / 154.0 - 1.0).abs() <= 0.02 + 1e-12, "{line}");
        areas.push(v(area2));
    }
    assert!(areas.windows(2).any(|w| w[0] != w[1]), "area_2_cm2 is drawn");
    let s = json(&d.path().join("c/summary.json"));
    assert_eq!(
        s["plan"]["params"][col("outlet_1_mm2") - 2]["distribution"],
        "fixed"
    );
    // A key that is no parameter of the tanks: refused by `run` and by `campaign`, naming them.
    std::fs::write(
        d.path().join("bad.toml"),
        format!("{shipped}\n[campaign]\nbeta_mpa = {{ relative = 0.1 }}\n"),
    )
    .unwrap();
    for args in [
        &["run", "bad.toml", "--out", "r"][..],
        &["campaign", "bad.toml", "--runs", "2", "--out", "b"],
    ] {
        let o = rhonn(d.path(), args);
        assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
        assert!(
            stderr(&o).contains("campaign.beta_mpa") && stderr(&o).contains("area_1_cm2, area_2_cm2"),
            "{}",
            stderr(&o)
        );
        assert!(!d.path().join(args[args.len() - 1]).exists());
    }
}
