//! Unmodeled dynamics (pump-model.md section 3): a first-order lag on the solenoid current.

use rhonn::experiment::{preset, PlantRunOutput};
use rhonn::signal::SignalSpec;

/// A current step from 0.2 A to 0.6 A at t = 0.5 s, with a solenoid lag of `lag_ms`.
fn step_response(lag_ms: f64) -> PlantRunOutput {
    let mut spec = preset::load_any("thesis-ch3").unwrap();
    spec.duration_s = 1.0;
    spec.plant.initial = vec![25.0, 4.3];
    spec.input.insert(
        "current".into(),
        SignalSpec::Steps {
            initial: 0.2,
            steps: vec![[0.5, 0.6]],
        },
    );
    spec.plant.parameters.insert("solenoid_lag_ms".into(), lag_ms);
    spec.run().unwrap()
}

#[test]
fn a_solenoid_lag_delays_the_stroke_by_about_its_time_constant() {
    let stroke_at = |tr: &PlantRunOutput, t: f64| {
        let k = tr.column("t").unwrap().iter().position(|&v| v >= t).unwrap();
        tr.column("stroke").unwrap()[k]
    };
    let base = step_response(0.0);
    let mut last_gap = 0.0;
    for lag in [1.0, 5.0, 20.0] {
        let lagged = step_response(lag);
        // Early in the response the lagged stroke is behind, by more for a longer lag ...
        let gap = stroke_at(&base, 0.53) - stroke_at(&lagged, 0.53);
        assert!(gap > last_gap, "lag {lag} ms: gap {gap}");
        last_gap = gap;
        // ... and both settle to the same steady stroke, phi I / K_a.
        let x_ss = 28.0 * 0.6 / 1300.0;
        assert!(
            (stroke_at(&lagged, 1.0) - x_ss).abs() < 0.02 * x_ss,
            "lag {lag} ms"
        );
    }
}

#[test]
fn the_thesis_identifier_stays_bounded_under_solenoid_lags() {
    for lag in [1.0, 5.0, 20.0] {
        let mut spec = preset::load_any("thesis-ch5").unwrap();
        spec.plant.parameters.insert("solenoid_lag_ms".into(), lag);
        // An exciting current: a PRBS between 0.2 and 0.7 A, so that the lag matters.
        spec.input.insert(
            "current".into(),
            SignalSpec::Prbs {
                start_s: 0.0,
                end_s: 40.0,
                bit_s: 0.3,
                low: 0.2,
                high: 0.7,
                seed: 3,
            },
        );
        spec.identifier.as_mut().unwrap().validate = false;
        let tr = spec.run().unwrap();
        let id = tr.summary.identification.clone().unwrap();
        for (k, f) in id.iter().enumerate() {
            assert!(
                f.whole_run.training.rms_error.is_finite() && f.final_weight_norm.is_finite(),
                "lag {lag} ms"
            );
            assert!(
                f.final_weight_norm < [1e10, 10.0][k],
                "lag {lag} ms: |w| {}",
                f.final_weight_norm
            );
        }
        let ph = tr.column("p_line_hat").unwrap();
        assert!(ph.iter().all(|v| v.is_finite() && v.abs() < 1e9), "lag {lag} ms");
    }
}
