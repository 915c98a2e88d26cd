//! Sensor noise, a transport delay and a dither on a plant other than the pump: the
//! tanks' control scenario with `[measurement]` noise and `control.delay_periods`.

use rhonn::experiment::{run_plant_scenario, PlantRunOutput, ScenarioSpec};

fn tanks_control() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenarios/tanks-control.toml"
    ))
    .unwrap()
}

/// The shipped tanks scenario, shortened to 900 s, with `extra` appended to `[control]`
/// and `tail` at the end.
fn run(extra: &str, tail: &str) -> PlantRunOutput {
    let text = tanks_control()
        .replace("duration_s = 2400.0", "duration_s = 900.0")
        .replace("period_s = 1.0\n", &format!("period_s = 1.0\n{extra}\n"))
        + tail;
    let spec = ScenarioSpec::from_toml(&text, "tanks-noisy.toml").unwrap();
    run_plant_scenario(&spec, None).unwrap()
}

fn column<'a>(out: &'a PlantRunOutput, name: &str) -> &'a [f64] {
    &out.trajectory
        .iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no column {name}"))
        .values
}

fn std_dev(v: &[f64]) -> f64 {
    let m = v.iter().sum::<f64>() / v.len() as f64;
    (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
}

#[test]
fn the_tanks_run_with_sensor_noise_and_a_delay() {
    let clean = run("", "");
    let noise = "\n[measurement]\nnoise_std = { h2 = 2.0, h1 = 1.0 }\nseed = 7\n";
    let noisy = run("delay_periods = 3", noise);
    // The controllers saw the lower level through a sensor with 2 mm of noise.
    let (h2, seen) = (column(&noisy, "h2"), column(&noisy, "h2_measured"));
    let e: Vec<f64> = h2.iter().zip(seen).map(|(a, b)| b - a).collect();
    let s = std_dev(&e) * 1e3;
    assert!((1.8..2.2).contains(&s), "measured noise std {s} mm, 2 mm asked");
    assert!(column(&noisy, "h2_measured_baseline").len() == h2.len());
    assert!(clean.trajectory.iter().all(|c| !c.name.contains("measured")));
    // Noise and delay cost IAE, for both loops; every figure stays finite.
    let [a0, b0]: [_; 2] = clean.summary.control.clone().unwrap().try_into().unwrap();
    let [a1, b1]: [_; 2] = noisy.summary.control.clone().unwrap().try_into().unwrap();
    for (f0, f1) in [(&a0, &a1), (&b0, &b1)] {
        assert!(f1.iae > f0.iae, "{}: {} -> {}", f1.controller, f0.iae, f1.iae);
        assert!(f1.input_total_variation > f0.input_total_variation);
        assert!(f1.iae.is_finite() && f1.final_error.is_finite());
    }
    // Seeded: the same seed gives the same run, another seed another.
    assert_eq!(run("delay_periods = 3", noise), noisy);
    let other = run("delay_periods = 3", &noise.replace("seed = 7", "seed = 8"));
    assert_ne!(column(&other, "h2_measured"), seen);
    // The delay alone: the first voltage the controller commands reaches the plant 3
    // periods late, unchanged (until then both plants saw the same inputs).
    let delayed = run("delay_periods = 3", "");
    let (u0, u3) = (column(&clean, "voltage"), column(&delayed, "voltage"));
    let k = u0.iter().position(|u| *u != u0[0]).unwrap();
    assert!(u3[..k + 3].iter().all(|u| *u == u0[0]), "{:?}", &u3[..k + 4]);
    assert_eq!(u3[k + 3], u0[k]);
}

#[test]
fn a_dither_moves_both_loops_inputs_within_the_range() {
    let clean = run("", "");
    let dithered = run(
        "dither = { kind = \"prbs\", start_s = 0.0, end_s = 900.0, bit_s = 5.0, low = -0.5, high = 0.5, seed = 1 }",
        "",
    );
    for name in ["voltage", "voltage_baseline"] {
        let (u0, u1) = (column(&clean, name), column(&dithered, name));
        assert_ne!(u0, u1, "{name}");
        assert!(u1.iter().all(|u| (0.0..=10.0).contains(u)), "{name}");
    }
}

#[test]
fn bad_conditions_are_errors_naming_the_field_and_what_is_allowed() {
    let base = tanks_control();
    let cases = [
        (
            "\n[measurement]\nnoise_std = { h3 = 1.0 }\n",
            "measurement.noise_std.h3",
            "a state of the",
        ),
        (
            "\n[measurement]\nnoise_std = { h2 = -1.0 }\n",
            "measurement.noise_std.h2",
            ">= 0 in mm",
        ),
        (
            "\n[measurement]\nnoise_std = { h2 = nan }\n",
            "measurement.noise_std.h2",
            ">= 0 in mm",
        ),
    ];
    for (tail, field, allowed) in cases {
        let spec = ScenarioSpec::from_toml(&(base.clone() + tail), "t.toml").unwrap();
        let e = run_plant_scenario(&spec, None).unwrap_err().to_string();
        assert!(e.contains(field) && e.contains(allowed), "{e}");
    }
    let text = base.replace("period_s = 1.0\n", "period_s = 1.0\ndelay_periods = 100001\n");
    let spec = ScenarioSpec::from_toml(&text, "t.toml").unwrap();
    let e = run_plant_scenario(&spec, None).unwrap_err().to_string();
    assert!(e.contains("control.delay_periods") && e.contains("100000"), "{e}");
    // Noise on an identification: refused, saying why.
    let ident = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenarios/tanks-identify.toml"
    ))
    .unwrap()
        + "\n[measurement]\nnoise_std = { h1 = 1.0 }\n";
    let spec = ScenarioSpec::from_toml(&ident, "t.toml").unwrap();
    let e = run_plant_scenario(&spec, None).unwrap_err().to_string();
    assert!(
        e.contains("measurement") && e.contains("only with a [control] section"),
        "{e}"
    );
}

/// `output_interval_s` finer than the control period: the trajectory is taken from the
/// solver's dense output between the control instants (ten samples a period here), the
/// loop itself unchanged: the same figures to the bit, the same states at the control
/// instants (within the interpolation's rounding), the input held between them.
#[test]
fn a_control_run_sampled_finer_than_its_period_is_the_same_run() {
    let coarse = run("", "");
    let text = tanks_control().replace(
        "duration_s = 2400.0",
        "duration_s = 900.0\noutput_interval_s = 0.1",
    );
    let spec = ScenarioSpec::from_toml(&text, "tanks-fine.toml").unwrap();
    let fine = run_plant_scenario(&spec, None).unwrap();
    assert_eq!(fine.summary.control, coarse.summary.control);
    assert_eq!(fine.summary.findings, coarse.summary.findings);
    let (t, tc) = (column(&fine, "t"), column(&coarse, "t"));
    assert_eq!((t.len(), tc.len()), (9000, 900));
    for name in [
        "h1",
        "h2",
        "h1_baseline",
        "voltage",
        "voltage_baseline",
        "h2_ref",
        "w_norm",
    ] {
        let (f, c) = (column(&fine, name), column(&coarse, name));
        for k in 0..tc.len() {
            assert!(
                (t[10 * k] - tc[k]).abs() < 1e-9,
                "{name}: t {} against {}",
                t[10 * k],
                tc[k]
            );
            let scale = c[k].abs().max(1e-3);
            assert!(
                (f[10 * k] - c[k]).abs() <= 1e-9 * scale,
                "{name} at {} s: {} against {}",
                tc[k],
                f[10 * k],
                c[k]
            );
        }
    }
    // Between the instants the states move and the input holds.
    let (h2, u) = (column(&fine, "h2"), column(&fine, "voltage"));
    assert!((1..9).all(|j| u[100 + j] == u[100]));
    assert!((1..9).any(|j| h2[100 + j] != h2[100]));
}
