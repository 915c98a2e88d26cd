//! The fixed-size online identifier of `rhonn-core` (what a microcontroller runs, no
//! allocation) gives the library's `OnlineIdentifier` (what `rhonn identify` runs)
//! estimates and weights bit for bit: the same update, one copy.

use rhonn::ident::{InputHold, OnlineIdentifier, OnlineSpec, Scaling};
use rhonn::law::{GainSpec, LawSpec};
use rhonn_core::ident::Robust;
use rhonn_core::online::UpdateError;
use rhonn_core::online_fixed::{FixedOnline, FixedSpec, SpecError};

const DT: f64 = 0.02;

/// y' = -y + u1 + 0.5 u1 tanh(y) - 0.3 u2^2, sampled every 20 ms, inputs switching
/// every 15 samples, the output with uniform noise of 0.02.
fn record(n: usize) -> Vec<(f64, [f64; 2], f64)> {
    let (mut y, mut s, mut u) = (0.3f64, 11u64, [0.0, 0.0]);
    let mut draw = move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    (0..n)
        .map(|k| {
            if k % 15 == 0 {
                u = [draw(), draw()];
            }
            let sample = (k as f64 * DT + 3.0, u, 2.0 + y + 0.02 * draw());
            for _ in 0..20 {
                y += DT / 20.0 * (-y + u[0] + 0.5 * u[0] * y.tanh() - 0.3 * u[1] * u[1]);
            }
            sample
        })
        .collect()
}

struct Case {
    name: &'static str,
    spec: OnlineSpec,
    robust: Option<Robust>,
    bounds: bool,
}

fn cases() -> Vec<Case> {
    let base = OnlineSpec::default();
    let sigma = |kind| Case {
        name: if kind == Robust::Switching {
            "sigma-switching"
        } else {
            "sigma-smooth"
        },
        spec: OnlineSpec {
            filters_s: vec![0.3],
            ..base.clone()
        },
        robust: Some(kind),
        bounds: false,
    };
    vec![
        Case {
            name: "defaults",
            spec: base.clone(),
            robust: None,
            bounds: false,
        },
        Case {
            name: "filters, linear inputs, dead zone, bounds",
            spec: OnlineSpec {
                filters_s: vec![0.2, 1.0],
                inputs: InputHold::Linear,
                dead_zone: 0.03,
                gain: 2.0,
                ..base.clone()
            },
            robust: None,
            bounds: true,
        },
        Case {
            name: "no output terms, degree 3",
            spec: OnlineSpec {
                filters_s: vec![0.5],
                output_terms: false,
                degree: 3,
                a_per_s: Some(4.0),
                ..base.clone()
            },
            robust: None,
            bounds: false,
        },
        sigma(Robust::Switching),
        sigma(Robust::Smooth),
    ]
}

#[test]
fn the_cores_fixed_size_identifier_is_the_librarys_bit_for_bit() {
    let rec = record(3000);
    let ys: Vec<f64> = rec.iter().map(|r| r.2).collect();
    let u1: Vec<f64> = rec.iter().map(|r| r.1[0]).collect();
    let u2: Vec<f64> = rec.iter().map(|r| r.1[1]).collect();
    let (radius, leak) = ([1.0], [20.0]);
    for case in cases() {
        let mut scaling = Scaling::of(&[&ys], &[&u1, &u2]);
        if case.bounds {
            scaling.y_bounds = Some(vec![[1.0, 3.5]]);
        }
        let mut spec = case.spec.clone();
        let mut fixed = FixedOnline::<f64, 12, 64>::new(&FixedSpec {
            filters_s: &spec.filters_s,
            degree: spec.degree,
            max_factors: spec.max_factors,
            output_terms: spec.output_terms,
            a_per_s: spec.a_per_s,
            gain: spec.gain,
            dead_zone: &[spec.dead_zone],
            hold: spec.inputs,
            period_s: DT,
            scaling: rhonn_core::online::Scaling {
                y_offset: &scaling.y_offset,
                y_scale: &scaling.y_scale,
                u_offset: &scaling.u_offset,
                u_scale: &scaling.u_scale,
                y_bounds: scaling.y_bounds.as_deref(),
            },
            robust: case.robust.map(|r| (r, &radius[..], &leak[..])),
        })
        .unwrap();
        let l = fixed.n_terms();
        if let Some(kind) = case.robust {
            let gamma = vec![GainSpec::Scalar(spec.gain / (DT * l as f64))];
            let (m, sigma) = (radius.to_vec(), leak.to_vec());
            spec.law = Some(match kind {
                Robust::Switching => LawSpec::SigmaSwitching { gamma, m, sigma },
                _ => LawSpec::SigmaSmooth { gamma, m, sigma },
            });
        }
        let mut lib = OnlineIdentifier::new(&spec, 1, 2, DT, scaling).unwrap();
        assert_eq!(lib.n_terms(), l, "{}", case.name);
        let mut moved = 0.0f64;
        for (k, (t, u, y)) in rec.iter().enumerate() {
            if k == 2500 {
                // The rest frozen and free: the model on its own.
                lib.freeze(true);
                lib.set_free_run(true);
                fixed.freeze(true);
                fixed.set_free_run(true);
            }
            let a = lib.update(*t, u, &[*y]).unwrap()[0];
            let b = fixed.update(*t, u, &[*y]).unwrap()[0];
            assert_eq!(a.to_bits(), b.to_bits(), "{}: sample {k}: {a} vs {b}", case.name);
            moved = moved.max((a - y).abs());
        }
        let (wl, wf) = (lib.weights(), fixed.weights(0));
        assert_eq!(wl[0], wf, "{}", case.name);
        assert!(wf.iter().any(|w| *w != 0.0), "{}: the weights learned", case.name);
        assert!(moved > 0.0 && moved.is_finite(), "{}", case.name);
    }
}

#[test]
fn the_fixed_identifier_refuses_what_does_not_fit_and_bad_samples() {
    let s = rhonn_core::online::Scaling {
        y_offset: &[0.0],
        y_scale: &[1.0],
        u_offset: &[0.0, 0.0],
        u_scale: &[1.0, 1.0],
        y_bounds: None,
    };
    let spec = FixedSpec {
        filters_s: &[0.1, 0.5],
        degree: 2,
        max_factors: 2,
        output_terms: true,
        a_per_s: None,
        gain: 0.5,
        dead_zone: &[0.0],
        hold: InputHold::Hold,
        period_s: 0.005,
        scaling: s,
        robust: None,
    };
    // 1 output, 2 inputs, 2 filters: 8 signals with the constant, 36 terms, 57 factors.
    assert_eq!(
        FixedOnline::<f32, 7, 64>::new(&spec).unwrap_err(),
        SpecError::Capacity(8)
    );
    assert!(matches!(FixedOnline::<f32, 8, 32>::new(&spec), Err(SpecError::Capacity(n)) if n > 32));
    let mut id = FixedOnline::<f32, 8, 64>::new(&spec).unwrap();
    assert_eq!(id.n_terms(), 36);
    assert_eq!(
        FixedOnline::<f32, 8, 64>::new(&FixedSpec { degree: 5, ..spec }).unwrap_err(),
        SpecError::Invalid("degree")
    );
    assert_eq!(
        FixedOnline::<f32, 8, 64>::new(&FixedSpec {
            period_s: 0.0,
            ..spec
        })
        .unwrap_err(),
        SpecError::Invalid("period_s")
    );
    assert_eq!(id.update(0.0, &[0.1], &[0.0]).unwrap_err(), UpdateError::Sizes);
    assert_eq!(
        id.update(0.0, &[f32::NAN, 0.0], &[0.0]).unwrap_err(),
        UpdateError::NotFinite
    );
    id.update(0.0, &[0.1, 0.2], &[0.3]).unwrap();
    assert_eq!(
        id.update(0.0, &[0.1, 0.2], &[0.3]).unwrap_err(),
        UpdateError::NotAfter { t_last: 0.0 }
    );
    assert!(id.update(0.005, &[0.1, 0.2], &[0.3]).is_ok());
    assert_eq!(id.weights(0).len(), 36);
    assert!(id.weights(1).is_empty(), "one output, one neuron");
    // Not configured, or left empty by a refused configuration: every update refused.
    let mut empty = FixedOnline::<f32, 8, 64>::empty();
    assert_eq!(empty.update(0.0, &[], &[]).unwrap_err(), UpdateError::Sizes);
    assert_eq!(
        empty.configure(&FixedSpec { degree: 0, ..spec }),
        Err(SpecError::Invalid("degree"))
    );
    assert_eq!(
        empty.update(0.0, &[0.1, 0.2], &[0.3]).unwrap_err(),
        UpdateError::Sizes
    );
    empty.configure(&spec).unwrap();
    assert!(empty.update(0.0, &[0.1, 0.2], &[0.3]).is_ok());
}
