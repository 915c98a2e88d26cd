//! The PI baseline (`regulated-pi`): figures checked against the trace, the valid
//! range, current limits, seeded noise.

use rhonn::experiment::{preset, LoopFigures, PlantRunOutput};

fn simulate(edit: impl FnOnce(&mut rhonn::experiment::ScenarioSpec)) -> (PlantRunOutput, LoopFigures) {
    let mut spec = preset::load_any("regulated-pi").unwrap();
    edit(&mut spec);
    let out = spec.run().unwrap();
    let figures = out.summary.control.as_ref().unwrap()[0].clone();
    (out, figures)
}

#[test]
fn figures_agree_with_the_trace_sampled_every_millisecond() {
    let (tr, s) = simulate(|_| {});
    let t = tr.column("t").unwrap();
    let p = tr.column("p_line").unwrap();
    let r = tr.column("p_line_ref").unwrap();
    // Trapezoidal ISE on the 1 ms samples [MPa^2 s].
    let e2: Vec<f64> = p.iter().zip(r).map(|(p, r)| ((p - r) / 1e6).powi(2)).collect();
    let ise: f64 = (1..t.len())
        .map(|k| 0.5 * (e2[k] + e2[k - 1]) * (t[k] - t[k - 1]))
        .sum();
    assert!((s.ise - ise).abs() < 0.02 * ise, "{} vs {ise}", s.ise);
    // Largest deviation after the first second (the set-point is constant).
    let dev = (0..t.len())
        .filter(|&k| t[k] >= 1.0)
        .map(|k| (p[k] - r[k]).abs() / 1e6)
        .fold(0.0, f64::max);
    assert!(
        (s.max_abs_deviation_settled - dev).abs() < 0.05 * dev,
        "{} vs {dev}",
        s.max_abs_deviation_settled
    );
    // A summary-only run gives the same figures.
    let quiet = preset::load_any("regulated-pi").unwrap().run_summary().unwrap();
    assert_eq!(quiet.control.unwrap()[0], s);
}

#[test]
fn pressure_stays_in_the_valid_range_after_start_up_and_current_in_its_limits() {
    let (tr, s) = simulate(|_| {});
    let t = tr.column("t").unwrap();
    let p = tr.column("p_line").unwrap();
    let i = tr.column("current").unwrap();
    for k in 0..t.len() {
        if t[k] >= 1.0 {
            assert!(
                p[k] >= 1e6 && p[k] <= 25e6,
                "p = {} MPa at t = {}",
                p[k] / 1e6,
                t[k]
            );
        }
        assert!((0.0..=0.8).contains(&i[k]));
    }
    assert_eq!(s.time_below_floor_after_settle_s, Some(0.0));
    // The start from 2 MPa with no stroke drains the line in milliseconds: unavoidable.
    let below = s.time_below_floor_s.unwrap();
    assert!(below > 0.0 && below < 0.05, "{below}");
    // ZOH: the current changes only at multiples of T = 5 ms.
    for k in 1..t.len() {
        if i[k] != i[k - 1] {
            let m = (t[k] * 1000.0).round() as i64;
            assert_eq!(m % 5, 0, "current changed at t = {}", t[k]);
        }
    }
}

#[test]
fn measurement_noise_is_seeded() {
    let noisy = |seed: u64| {
        simulate(|s| {
            s.measurement = Some(rhonn::experiment::SensorNoiseSpec {
                noise_std: [("p_line".to_string(), 0.05)].into(),
                seed,
            });
        })
    };
    let (a, sa) = noisy(7);
    let (b, _) = noisy(7);
    let (c, _) = noisy(8);
    assert_eq!(a, b);
    assert_ne!(a.column("p_line_measured"), c.column("p_line_measured"));
    // The measurement differs from the pressure by about the noise level.
    let p = a.column("p_line").unwrap();
    let m = a.column("p_line_measured").unwrap();
    let sd = (p.iter().zip(m).map(|(p, m)| (p - m).powi(2)).sum::<f64>() / p.len() as f64).sqrt() / 1e6;
    assert!(sd > 0.03 && sd < 0.5, "{sd}");
    assert!(sa.iae > 0.0);
}

#[test]
fn what_a_parallel_campaign_shares_is_send_sync_and_clone() {
    fn check<T: Send + Sync + Clone>() {}
    check::<rhonn::experiment::ScenarioSpec>();
    check::<rhonn::experiment::PlantRunOutput>();
    check::<rhonn::sysid::Model>();
    check::<rhonn::ident::Identifier>();
    fn send<T: Send>() {}
    send::<rhonn::ident::Identified<rhonn::plant::PumpSystem>>();
    send::<rhonn::ident::Identified<rhonn::plant::Tanks>>();
    send::<rhonn::ident::DiscreteIdentifier>();
    send::<rhonn::Error>();
}
