//! A user's own plant (`examples/custom_plant.rs`, an oven with a heating element and a
//! chamber) is a first-class run: its identification and its cascade are written as a
//! shipped plant's (trajectory.csv, summary.json, plots, report.html), and a controller that
//! sits at its limit without reaching the set-point is warned about.

#[path = "../examples/custom_plant.rs"]
#[allow(dead_code)]
mod example;

use example::{Oven, CASCADE};
use rhonn::experiment::{run_plant_scenario_on, ScenarioSpec};
use rhonn::plant::Input;

#[test]
fn a_users_plant_is_run_and_written_as_a_shipped_one() {
    let d = tempfile::tempdir().unwrap();
    let files = example::run(d.path()).unwrap();
    for (run, extra) in [
        ("custom-plant-identify", &["validation.csv", "validation.svg"][..]),
        ("custom-plant-cascade", &[][..]),
    ] {
        for f in [
            "trajectory.csv",
            "summary.json",
            "states.svg",
            "inputs.svg",
            "report.html",
        ]
        .iter()
        .chain(extra)
        {
            let p = d.path().join(run).join(f);
            assert!(p.exists() && files.contains(&p), "{}", p.display());
        }
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.path().join(run).join("summary.json")).unwrap())
                .unwrap();
        assert_eq!(s["plant"], "oven", "{s}");
        assert!(!s["findings"].as_array().unwrap().is_empty(), "{s}");
    }
    let html = std::fs::read_to_string(d.path().join("custom-plant-cascade/report.html")).unwrap();
    assert!(
        html.contains("pi-over-rhonn-cascade") && html.contains("<svg"),
        "the report shows the run"
    );
}

#[test]
fn a_controller_at_its_limit_short_of_the_set_point_is_warned_about() {
    let oven = Oven(Input::Held(0.0));
    let run = |text: &str| {
        let spec = ScenarioSpec::from_toml(text, "test").unwrap();
        run_plant_scenario_on(&oven, &spec).unwrap().summary.findings
    };
    // The shipped cascade reaches its set-points: no warning.
    let reachable = run(CASCADE);
    assert!(
        reachable.iter().all(|f| !f.starts_with("warning")),
        "{reachable:?}"
    );
    // 700 K above ambient is beyond the heater (the chamber tops out near 645 K at full
    // power), with room for the element's set-point: both controllers sit at full heat.
    let text = CASCADE
        .replace(
            "initial = 150.0, steps = [[600.0, 300.0], [1200.0, 400.0], [1800.0, 250.0]]",
            "initial = 150.0, steps = [[600.0, 700.0]]",
        )
        .replace("inner_range = [0.0, 900.0]", "inner_range = [0.0, 2000.0]");
    assert_ne!(text, CASCADE);
    let out_of_reach = run(&text);
    let warned: Vec<&String> = out_of_reach
        .iter()
        .filter(|f| f.starts_with("warning") && f.contains("sits at its upper limit (1)"))
        .collect();
    assert_eq!(warned.len(), 2, "{out_of_reach:?}");
    println!("{}\n{}", warned[0], warned[1]);
    assert!(warned[0].contains("pi-over-rhonn-cascade") && warned[1].contains("pi-cascade"));
    assert!(
        warned[0].contains("the actuator cannot reach it"),
        "{}",
        warned[0]
    );
}

#[test]
fn a_users_plant_takes_sensor_noise_a_delay_and_a_dither() {
    let oven = Oven(Input::Held(0.0));
    let figures = |text: &str| {
        let spec = ScenarioSpec::from_toml(text, "test").unwrap();
        run_plant_scenario_on(&oven, &spec).unwrap()
    };
    let clean = figures(CASCADE);
    let text = CASCADE.replace("period_s = 1.0\n", "period_s = 1.0\ndelay_periods = 2\n")
        + "\n[control.dither]\nkind = \"prbs\"\nstart_s = 0.0\nend_s = 100.0\nbit_s = 2.0\nlow = -0.05\nhigh = 0.05\nseed = 4\n\n[measurement]\nnoise_std = { chamber = 1.0 }\nseed = 3\n";
    let noisy = figures(&text);
    assert!(noisy.trajectory.iter().any(|c| c.name == "chamber_measured"));
    let [a0, _]: [_; 2] = clean.summary.control.unwrap().try_into().unwrap();
    let [a1, _]: [_; 2] = noisy.summary.control.unwrap().try_into().unwrap();
    assert!(a1.iae.is_finite() && a1.iae != a0.iae, "{} -> {}", a0.iae, a1.iae);
    assert!(a1.input_total_variation > a0.input_total_variation);
}
