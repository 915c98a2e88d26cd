//! The pump as one plant among others: a scenario with `[plant] kind = "pump"` runs on the
//! generic runner (`run_plant_scenario`) like any plant's: its parameters, its loop kinds,
//! its floor, its inputs' ranges and its rules on the one format's fields. (Its figures
//! are pinned to the thesis in `thesis_ch3.rs`, `thesis_ch5.rs`, `regulated.rs`,
//! `control.rs`.)

use rhonn::experiment::{preset, run_plant_scenario, ScenarioSpec};
use rhonn::plant::PumpParams;

/// Column `name` of a plant run's trajectory (SI).
fn column(out: &rhonn::experiment::PlantRunOutput, name: &str) -> Vec<f64> {
    out.trajectory
        .iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no column {name}"))
        .values
        .clone()
}

/// `regulated-pi` written as a plant scenario: the same PI (0.15 A/MPa, 0.08 s, the
/// balance current as its offset and as the solenoid's initial current), the same demand
/// trapezoids, 20 s.
fn pi_scenario(bias_a: f64) -> String {
    format!(
        r#"
name = "pump-pi"
duration_s = 20.0
[plant]
kind = "pump"
initial = [2.0, 0.0, {bias_a}]
[input]
demand = {{ kind = "trapezoids", slew_per_s = 2.0, pulses = [{{ start_s = 3.0, peak = 1.0, hold_s = 5.0 }}, {{ start_s = 12.0, peak = 1.8, hold_s = 6.0 }}] }}
[control]
input = "current"
input_range = [0.0, 0.8]
output = "p_line"
period_s = 0.005
setpoint = {{ kind = "constant", value = 10.0 }}
[control.controller]
kind = "pi"
state = "p_line"
kp = 0.15
ti_s = 0.08
bias = {bias_a}
[control.baseline]
kind = "pi"
state = "p_line"
kp = 0.05
ti_s = 0.08
bias = {bias_a}
"#
    )
}

#[test]
fn a_pi_loop_and_its_baseline_on_the_pump_settle_as_their_gains_say() {
    let p = PumpParams::default();
    let bias = p.k_a * p.q_0 / (p.k_l * p.omega * p.phi);
    let spec: ScenarioSpec = toml::from_str(&pi_scenario(bias)).unwrap();
    let out = run_plant_scenario(&spec, None).unwrap();
    let col = |name: &str| column(&out, name);
    assert_eq!(col("t").len(), 4000);

    let control = out.summary.control.as_ref().unwrap();
    // The summary holds both loops: the thesis's gain settles, a third of it lags.
    assert!(control[0].final_error.abs() < 0.1, "{:?}", control[0]);
    assert!(control[1].iae > 2.0 * control[0].iae, "{control:?}");
}

/// thesis-ch5 written as a plant scenario: the thesis's current ramp, the thesis's
/// identifier of both states with the sigma-switching law.
const THESIS_CH5_AS_PLANT: &str = r#"
name = "thesis-ch5-generic"
duration_s = 40.0
output_interval_s = 0.01
[plant]
kind = "pump"
initial = [2.0, 0.0, 0.0]
[input]
current = { kind = "piecewise-linear", points = [[0.0, 0.0], [15.0, 0.8], [25.0, 0.8], [40.0, 0.0]] }
[identifier]
states = ["p_line", "stroke"]
inputs = []
sigmoid = "logistic"
terms = [[[0, 1]], [[1, 1]]]
a = [120.0, 41.0]
initial_si = [0.0, 0.0]
law = { kind = "sigma-switching", gamma = [1e4, 30.0], m = [1e10, 10.0], sigma = [0.01, 0.01] }
[solver]
rtol = 1e-6
atol_si = { p_line = 1.0, stroke = 1e-9 }
max_step_ms = 100.0
"#;

/// thesis-ch3 (the pump driven open loop by the thesis's current ramp) as a plant scenario
/// with the thesis's `[solver]`: the time below P_min on the dense output, and a start
/// below it warned of.
#[test]
fn thesis_ch3_as_a_plant_scenario_counts_its_time_below_the_floor() {
    let text = THESIS_CH5_AS_PLANT.replace("output_interval_s = 0.01", "output_interval_s = 0.001");
    let text = format!(
        "{}{}",
        &text[..text.find("[identifier]").unwrap()],
        &text[text.find("[solver]").unwrap()..]
    );
    let spec: ScenarioSpec = toml::from_str(&text).unwrap();
    let out = run_plant_scenario(&spec, None).unwrap();
    assert_eq!(column(&out, "t").len(), 40_001);
    let floor = out.summary.floor.as_ref().expect("the pump has a floor");
    eprintln!(
        "below P_min: {} s ({} s after 1 s)",
        floor.time_below_s, floor.time_below_after_settle_s
    );
    assert_eq!((floor.state, floor.unit), ("p_line", "MPa"));
    // The ramp starts at 2 MPa with no current: the pressure falls below P_min (1 MPa)
    // before the pump's flow lifts it (thesis-ch3.rs pins the run itself).
    assert!(floor.time_below_s > 1.0 && floor.time_below_after_settle_s > 0.1);
    assert!(floor.time_below_after_settle_s < floor.time_below_s);
    assert!(out.summary.warnings.is_empty());
    // Started below P_min, it says so.
    let low = toml::from_str::<ScenarioSpec>(&text.replace("initial = [2.0,", "initial = [0.5,")).unwrap();
    let warnings = run_plant_scenario(&low, None).unwrap().summary.warnings;
    eprintln!("{warnings:?}");
    assert!(
        warnings.len() == 1
            && warnings[0].contains("p_line starts at 0.5 MPa, below the pump's floor of 1 MPa"),
        "{warnings:?}"
    );
}

#[test]
fn the_pumps_parameters_are_its_plant_parameters() {
    let mut spec: ScenarioSpec = toml::from_str(THESIS_CH5_AS_PLANT).unwrap();
    spec.duration_s = 2.0;
    spec.plant.parameters.insert("beta_mpa".into(), 1000.0);
    let out = run_plant_scenario(&spec, None).unwrap();
    assert!(out.summary.parameters.contains(&("beta_mpa".to_string(), 1000.0)));
    // Every key of the pump's `[plant]` table is a parameter (22, the thesis's table 3.3):
    // P_min moves the floor the figures use.
    let names: Vec<&str> = rhonn::plant::pump::PARAMETERS.iter().map(|p| p.name).collect();
    assert_eq!(out.summary.parameters.len(), 22);
    assert!(names.contains(&"qdot_max_dm3_s2") && names.contains(&"solenoid_lag_ms"));
    let mut high = spec.clone();
    high.plant.parameters.insert("p_min_mpa".into(), 3.0);
    let floor = run_plant_scenario(&high, None).unwrap().summary.floor.unwrap();
    assert_eq!(floor.floor, 3.0);
    assert!(floor.time_below_s > out.summary.floor.as_ref().unwrap().time_below_s);
    // A parameter the pump does not have, and the two `[control]` gives, are errors that
    // list the pump's.
    for (key, value) in [
        ("alpha", 1.0),
        ("t_control_ms", 5.0),
        ("transport_delay_periods", 1.0),
    ] {
        let mut bad = spec.clone();
        bad.plant.parameters.insert(key.into(), value);
        let e = run_plant_scenario(&bad, None).unwrap_err().to_string();
        assert!(
            e.contains(&format!("plant.{key}")) && e.contains("q_0_dm3_s"),
            "{e}"
        );
    }
    // The table's own rules: P_min below P_max.
    let mut bad = spec.clone();
    bad.plant.parameters.insert("p_min_mpa".into(), 30.0);
    let e = run_plant_scenario(&bad, None).unwrap_err().to_string();
    assert!(e.contains("plant.p_min_mpa") && e.contains("p_max_mpa"), "{e}");
    let mut bad = spec.clone();
    bad.plant.parameters.insert("mu_1".into(), -1.0);
    let e = run_plant_scenario(&bad, None).unwrap_err().to_string();
    assert!(e.contains("plant.mu_1") && e.contains("> 0"), "{e}");
}

/// `control-adaptive` written as a plant scenario: the pump's adaptive cascade and its
/// robust cascade PI as loop kinds (`pump-rhonn-adaptive`, `pump-cascade-pi`) of the one
/// format, on the same demand and set-points (no noise, 20 s).
fn adaptive_scenario(bias_a: f64) -> String {
    format!(
        r#"
name = "pump-adaptive"
duration_s = 20.0
[plant]
kind = "pump"
initial = [2.0, 0.0, {bias_a}]
[input]
demand = {{ kind = "trapezoids", slew_per_s = 2.0, pulses = [{{ start_s = 3.0, peak = 1.0, hold_s = 3.0 }}, {{ start_s = 8.0, peak = 1.8, hold_s = 3.0 }}, {{ start_s = 17.0, peak = 1.2, hold_s = 3.0 }}] }}
[control]
input = "current"
input_range = [0.0, 0.8]
output = "p_line"
period_s = 0.005
setpoint = {{ kind = "steps", initial = 10.0, steps = [[15.0, 5.0]] }}
controller = {{ kind = "pump-rhonn-adaptive", state = "p_line" }}
baseline = {{ kind = "pump-cascade-pi", state = "p_line", kp_mm_per_mpa = 0.15, ti_s = 0.07, setpoint_weight = 0.8, stroke_gain = 8.0 }}
"#
    )
}

#[test]
fn the_pumps_adaptive_controller_and_cascade_pi_run_as_loop_kinds_of_the_one_format() {
    let p = PumpParams::default();
    let bias = p.k_a * p.q_0 / (p.k_l * p.omega * p.phi);
    let spec: ScenarioSpec = toml::from_str(&adaptive_scenario(bias)).unwrap();
    let out = run_plant_scenario(&spec, None).unwrap();
    let col = |name: &str| column(&out, name);
    let (p_adaptive, p_pi) = (col("p_line"), col("p_line_baseline"));
    let [a, b]: [_; 2] = out.summary.control.clone().unwrap().try_into().unwrap();
    assert_eq!((a.controller, b.controller), ("rhonn-adaptive", "cascade-pi"));
    eprintln!("IAE: adaptive {} MPa s, cascade PI {} MPa s", a.iae, b.iae);
    // Both settle on each set-point between the demand's pulses: within 1 % of it at 14.5 s
    // (10 MPa, the pulses of 3 and 8 s over) and at the end (5 MPa, 3 s after the last).
    let t = col("t");
    for (at, r) in [(14.5, 10e6), (19.99, 5e6)] {
        let k = t.iter().position(|tk| *tk >= at - 1e-9).unwrap();
        eprintln!(
            "at {at} s: adaptive {} Pa, cascade PI {} Pa",
            p_adaptive[k], p_pi[k]
        );
        assert!(
            (p_adaptive[k] - r).abs() < 0.01 * r,
            "adaptive at {at} s: {}",
            p_adaptive[k]
        );
        assert!(
            (p_pi[k] - r).abs() < 0.01 * r,
            "cascade PI at {at} s: {}",
            p_pi[k]
        );
    }
    assert!(a.states_bounded && b.states_bounded && a.iae.is_finite() && b.iae.is_finite());
    // The kinds refuse a plant that is not the pump, naming the field.
    let tanks = adaptive_scenario(bias)
        .replace("kind = \"pump\"\ninitial = [2.0, 0.0, {bias_a}]", "")
        .replace(
            &format!("kind = \"pump\"\ninitial = [2.0, 0.0, {bias}]"),
            "kind = \"tanks\"",
        )
        .replace("output = \"p_line\"", "output = \"h2\"")
        .replace("input = \"current\"", "input = \"voltage\"")
        .replace("state = \"p_line\"", "state = \"h2\"")
        .replace("demand = ", "# demand = ");
    let spec: ScenarioSpec = toml::from_str(&tanks).unwrap();
    let e = run_plant_scenario(&spec, None).unwrap_err().to_string();
    assert!(
        e.contains("control.controller.state") && e.contains("stroke"),
        "{e}"
    );
}

#[test]
fn the_shipped_adaptive_scenario_runs_its_three_loops() {
    // control-adaptive as shipped: the adaptive cascade, the robust cascade PI and the
    // nominal-optimal one (`second_baseline`, a stored tuning of the baseline's kind), with
    // the pressure sensor's noise.
    let out = preset::load_any("control-adaptive").unwrap().run().unwrap();
    let c = out.summary.control.as_ref().unwrap();
    let names: Vec<String> = c.iter().map(|f| f.label()).collect();
    assert_eq!(
        names,
        ["rhonn-adaptive", "cascade-pi", "cascade-pi-nominal-optimal"]
    );
    for f in c {
        assert!(
            f.states_bounded && f.time_below_floor_after_settle_s.is_some(),
            "{f:?}"
        );
        // Four set-point steps: an overshoot each.
        assert_eq!(f.overshoot_percent.len(), 4, "{f:?}");
    }
    // The adaptive controller's weights stay in their balls; only it has weights.
    let a = c[0].adaptive.as_ref().unwrap();
    assert!(a.within_balls() && c[1].adaptive.is_none() && c[2].adaptive.is_none());
    assert!(out
        .summary
        .findings
        .iter()
        .any(|f| f.contains("for the baseline cascade-pi-nominal-optimal")));
}

#[test]
fn the_shipped_pi_scenario_runs_alone_from_the_pumps_initial_state() {
    // regulated-pi as shipped: `initial = [2.0, 0.0]` (the solenoid's current starts at the
    // PI's bias, the balance current when none is given), no baseline.
    let out = preset::load_any("regulated-pi").unwrap().run().unwrap();
    let c = out.summary.control.as_ref().unwrap();
    assert_eq!(c.len(), 1);
    assert!(!out.trajectory.iter().any(|c| c.name.ends_with("_baseline")));
    let (p, x) = (column(&out, "p_line"), column(&out, "stroke"));
    assert_eq!((p[0], x[0]), (2e6, 0.0));
}

#[test]
fn a_second_baseline_is_a_stored_tuning_of_the_baselines_kind_and_a_pump_starts_from_two_states() {
    let tanks = preset::load_any("tanks-control").unwrap();
    let mut spec = tanks.clone();
    spec.control.as_mut().unwrap().second_baseline = Some("robust".into());
    let e = run_plant_scenario(&spec, None).unwrap_err().to_string();
    assert!(
        e.contains("control.second_baseline") && e.contains("has no stored tuning"),
        "{e}"
    );
    let mut spec = preset::load_any("control-adaptive").unwrap();
    spec.control.as_mut().unwrap().second_baseline = Some("fast".into());
    let e = run_plant_scenario(&spec, None).unwrap_err().to_string();
    assert!(e.contains("nominal-optimal, robust"), "{e}");
    let mut spec = preset::load_any("regulated-pi").unwrap();
    spec.plant.initial = vec![2.0];
    let e = run_plant_scenario(&spec, None).unwrap_err().to_string();
    assert!(
        e.contains("plant.initial") && e.contains("or the first 2 (p_line, stroke"),
        "{e}"
    );
}

/// A pump loop on the generic runner shows what the pump's runner showed: the demand, the
/// cascades' stroke reference and the adaptive controller's pressure model, not the
/// solenoid's internal current; without `[control.baseline]` the adaptive controller is
/// compared with its default, the robust cascade PI, as the pump's format has always done.
#[test]
fn a_pump_loop_shows_its_demand_references_and_model_and_has_a_default_baseline() {
    let mut spec = preset::load_any("control-adaptive").unwrap();
    spec.duration_s = 10.0;
    let written = run_plant_scenario(&spec, None).unwrap();
    spec.control.as_mut().unwrap().baseline = None;
    let out = run_plant_scenario(&spec, None).unwrap();
    let names: Vec<&str> = out.trajectory.iter().map(|c| c.name.as_str()).collect();
    for n in [
        "demand",
        "stroke_ref",
        "p_line_model",
        "stroke_ref_baseline",
        "p_line_measured",
    ] {
        assert!(names.contains(&n), "{n} not in {names:?}");
    }
    assert!(!names.iter().any(|n| n.starts_with("current_eff")), "{names:?}");
    // The demand as its profile gives it (trapezoids from 3 s on), at every sample.
    let lim = rhonn::signal::spec_limits(0.0, f64::INFINITY, None, None);
    let profile = spec.input["demand"].build("demand", 1e-3, lim).unwrap();
    let (t, demand) = (column(&out, "t"), column(&out, "demand"));
    assert_eq!(names.iter().filter(|n| **n == "demand").count(), 1);
    assert!(
        demand.iter().any(|d| *d > 1e-4),
        "the trapezoids are in the column"
    );
    let worst = t
        .iter()
        .zip(&demand)
        .map(|(tk, d)| (profile.eval(*tk) - d).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-15, "{worst} m^3/s");
    let labels: Vec<String> = out
        .summary
        .control
        .as_ref()
        .unwrap()
        .iter()
        .map(|f| f.label())
        .collect();
    assert_eq!(
        labels,
        ["rhonn-adaptive", "cascade-pi", "cascade-pi-nominal-optimal"]
    );
    let (a, b) = (
        written.summary.control.as_ref().unwrap(),
        out.summary.control.as_ref().unwrap(),
    );
    assert_eq!(a[1].iae, b[1].iae, "the default baseline is the shipped one");
}

/// An input profile beyond the range the plant clips it to is said, once.
#[test]
fn a_current_beyond_the_pumps_range_is_warned_of() {
    let text = r#"
name = "over"
duration_s = 1.0
output_interval_s = 0.01
[plant]
kind = "pump"
[input]
current = { kind = "constant", value = 1.0 }
"#;
    let spec: ScenarioSpec = toml::from_str(text).unwrap();
    let w = run_plant_scenario(&spec, None).unwrap().summary.warnings;
    assert_eq!(w, ["input.current leaves [0, 0.8] A and is clipped"]);
    let ok: ScenarioSpec = toml::from_str(&text.replace("1.0 }", "0.5 }")).unwrap();
    assert!(run_plant_scenario(&ok, None).unwrap().summary.warnings.is_empty());
}

/// The pump's rules on the one format's fields are the generic runner's, read from its
/// plant's hooks (its states' bounds and floor, its inputs' ranges and pulse limits): each
/// an error naming the field and what is allowed, or a warning where the plant clips.
#[test]
fn the_pumps_ranges_are_errors_naming_the_field() {
    let shipped = |name: &str| preset::load_any(name).unwrap();
    let error = |spec: &ScenarioSpec| spec.run_summary().unwrap_err().to_string();
    let mut s = shipped("thesis-ch3");
    s.duration_s = 1.0;
    s.plant.initial = vec![30.0, 0.0];
    let e = error(&s);
    assert!(
        e.contains("plant.initial[0] (p_line, MPa)") && e.contains("[0, 25] MPa"),
        "{e}"
    );
    s.plant.initial = vec![2.0, 50.0];
    let e = error(&s);
    assert!(
        e.contains("plant.initial[1] (stroke, mm)") && e.contains("[0, 24] mm"),
        "{e}"
    );
    // A negative demand is clipped to none, and said.
    let mut s = shipped("thesis-ch3");
    s.duration_s = 1.0;
    s.input.insert(
        "demand".into(),
        toml::from_str("kind = \"constant\"\nvalue = -1.0").unwrap(),
    );
    let clipped = s.run().unwrap();
    let w = &clipped.summary.warnings;
    assert!(
        w.iter()
            .any(|w| w.contains("input.demand leaves [0, inf] dm^3/s and is clipped")),
        "{w:?}"
    );
    s.input.remove("demand");
    let none = s.run().unwrap();
    assert_eq!(clipped.column("p_line"), none.column("p_line"));
    // The demand's pulses: slew at most Qdot_max, peaks below Q_l,max.
    let mut c = shipped("control-adaptive");
    c.duration_s = 1.0;
    let text = c.to_toml();
    for (from, to, field, allowed) in [
        (
            "slew_per_s = 2.0",
            "slew_per_s = 5.0",
            "input.demand.slew_per_s",
            "at most 2 (Qdot_max",
        ),
        (
            "peak = 1.8",
            "peak = 3.0",
            "input.demand.pulses[1].peak",
            "below 2.1 (the max pump flow",
        ),
    ] {
        assert!(text.contains(from), "{from}");
        let bad: ScenarioSpec = toml::from_str(&text.replacen(from, to, 1)).unwrap();
        let e = error(&bad);
        assert!(e.contains(field) && e.contains(allowed), "{e}");
    }
    // The loop: its set-point within [P_min, P_max], its input range within the
    // solenoid's, its input driven by the controller alone.
    let mut bad = c.clone();
    let ctl = bad.control.as_mut().unwrap();
    ctl.setpoint = toml::from_str("kind = \"constant\"\nvalue = 30.0").unwrap();
    let e = error(&bad);
    assert!(
        e.contains("control.setpoint") && e.contains("within [1, 25] MPa at all times"),
        "{e}"
    );
    let mut bad = c.clone();
    bad.control.as_mut().unwrap().input_range = [0.0, 2.0];
    let e = error(&bad);
    assert!(
        e.contains("control.input_range") && e.contains("within [0, 0.8] A"),
        "{e}"
    );
    let mut bad = c.clone();
    bad.input.insert(
        "current".into(),
        toml::from_str("kind = \"constant\"\nvalue = 0.3").unwrap(),
    );
    let e = error(&bad);
    assert!(
        e.contains("input.current") && e.contains("none with a [control] section"),
        "{e}"
    );
    // The pump's own controllers drive its solenoid only.
    let mut bad = c.clone();
    bad.input.clear();
    bad.control.as_mut().unwrap().input = "demand".into();
    bad.control.as_mut().unwrap().input_range = [0.0, 1.0];
    let e = error(&bad);
    assert!(e.contains("control.input") && e.contains("\"current\""), "{e}");
}
