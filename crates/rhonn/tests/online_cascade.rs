//! The online identifier's cascade structure (`structure = "cascade"`): `rhonn fit`'s
//! chain of tanks with a hidden neuron, learned sample by sample by extended Kalman
//! filters from seeded starts; its frozen model, a user's loop, its checks.

use rhonn::data::Record;
use rhonn::ident::{
    identify_records, predict_records, CascadeOnlineSpec, OnlineIdentifier, OnlineModel, OnlineSpec,
    OnlineStructure, Scaling,
};

fn cascade(set: CascadeOnlineSpec, epochs: usize) -> OnlineSpec {
    OnlineSpec {
        structure: OnlineStructure::Cascade,
        cascade: Some(set),
        epochs,
        ..OnlineSpec::default()
    }
}

/// Two tanks in a chain (Torricelli outflows, the upper one hidden), 4 s samples, the
/// pump's voltage held for a random 10 to 40 samples at a random level in [2, 8] V,
/// the lower level measured with 0.02 noise (seeded): levels in V as the benchmark's.
fn tanks(seed: u64, n: usize) -> Record {
    let mut s = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    let mut rnd = move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut h1, mut h2) = (3.0f64, 3.0f64);
    let (mut u, mut hold) = (5.0, 0usize);
    let mut rec = Record {
        source: format!("tanks seed {seed}"),
        t: Vec::new(),
        inputs: vec![Vec::new()],
        outputs: vec![Vec::new()],
    };
    for k in 0..n {
        if hold == 0 {
            u = 2.0 + 6.0 * rnd();
            hold = 10 + (30.0 * rnd()) as usize;
        }
        hold -= 1;
        let noise = 0.02 * (rnd() + rnd() + rnd() - 1.5) * 2.0;
        rec.t.push(4.0 * k as f64);
        rec.inputs[0].push(u);
        rec.outputs[0].push(h2 + noise);
        for _ in 0..40 {
            let dt = 0.1;
            let d1 = 0.06 * u - 0.1 * h1.max(0.0).sqrt();
            let d2 = 0.1 * h1.max(0.0).sqrt() - 0.09 * h2.max(0.0).sqrt();
            h1 = (h1 + dt * d1).max(0.0);
            h2 = (h2 + dt * d2).max(0.0);
        }
    }
    rec
}

fn rms(a: &[f64], b: &[f64]) -> f64 {
    (a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>() / a.len() as f64).sqrt()
}

fn sd(a: &[f64]) -> f64 {
    let m = a.iter().sum::<f64>() / a.len() as f64;
    (a.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / a.len() as f64).sqrt()
}

/// Identified online on one record of a two-tank chain, the frozen model runs free on
/// another record (other inputs, other noise) within a tenth of its output's standard
/// deviation; the filters' starts alone (no pass) do not.
#[test]
fn a_chain_of_tanks_is_identified_online_and_runs_free_on_another_record() {
    let (train, test) = (tanks(1, 1000), tanks(2, 600));
    let y = ["y".to_string()];
    let spec = cascade(CascadeOnlineSpec::default(), 4);
    let run = identify_records(&spec, std::slice::from_ref(&train), &y).unwrap();
    let mut id = run.identifier.clone();
    let pred = predict_records(&mut id, std::slice::from_ref(&test), None).unwrap();
    let est: Vec<f64> = pred[0].iter().map(|v| v[0]).collect();
    let (err, scale) = (rms(&est[5..], &test.outputs[0][5..]), sd(&test.outputs[0]));
    eprintln!("free run on another record: RMS {err:.4} V, output sd {scale:.3} V");
    assert!(err < 0.1 * scale, "free run RMS {err} against sd {scale}");
    // The same spec with the filters' starts only: learning is what gets it there.
    let mut untrained = OnlineIdentifier::new(&spec, 1, 1, 4.0, id.scaling().clone()).unwrap();
    let pred = predict_records(&mut untrained, std::slice::from_ref(&test), None).unwrap();
    let est0: Vec<f64> = pred[0].iter().map(|v| v[0]).collect();
    let err0 = rms(&est0[5..], &test.outputs[0][5..]);
    eprintln!("before learning: RMS {err0:.4} V");
    assert!(err0 > 3.0 * err, "untrained {err0}, trained {err}");
    // Its free run reads the first `settle` measured outputs, and no other: what a
    // state-initialisation window must hold (`outputs_read_in_free_run`).
    let read = rhonn::ident::outputs_read_in_free_run(&spec);
    assert_eq!(read, CascadeOnlineSpec::default().settle);
    let free_run = |r: &Record| -> Vec<f64> {
        let mut id = run.identifier.clone();
        predict_records(&mut id, std::slice::from_ref(r), None).unwrap()[0]
            .iter()
            .map(|v| v[0])
            .collect()
    };
    let changed = |k: usize| {
        let mut r = test.clone();
        r.outputs[0][k] += 1.0;
        free_run(&r)
    };
    assert_eq!(changed(read)[read + 1..], est[read + 1..]);
    assert_ne!(changed(read - 1)[read + 1..], est[read + 1..]);
}

/// Over ten passes of a noisy record every parameter stays a valid chain (finite,
/// rates and bounds positive, exponents in [0.2, 1.5]) and the parameter norm settles:
/// the last pass's largest norm is within 5 % of the one before.
#[test]
fn cascade_parameters_stay_valid_and_settle_over_ten_passes() {
    let rec = tanks(3, 800);
    let spec = cascade(CascadeOnlineSpec::default(), 10);
    let run = identify_records(&spec, std::slice::from_ref(&rec), &["y".to_string()]).unwrap();
    let norms: Vec<f64> = run.max_norm_per_pass.iter().map(|p| p[0]).collect();
    eprintln!("largest parameter norm per pass: {norms:?}");
    assert_eq!(norms.len(), 10);
    assert!(norms.iter().all(|v| v.is_finite()));
    let (a, b) = (norms[8], norms[9]);
    assert!((b - a).abs() <= 0.05 * a, "pass 9 {a}, pass 10 {b}");
    let w = run.identifier.weights();
    // b, k1, k2, alpha1, alpha2, g1, o1, xmax1, xmax2, c
    assert_eq!(w[0].len(), 10);
    for (i, v) in w[0].iter().enumerate() {
        assert!(v.is_finite(), "{i}: {v}");
        if [0, 1, 2, 5, 7, 8].contains(&i) {
            assert!(*v > 0.0, "{i}: {v}");
        }
        if [3, 4].contains(&i) {
            assert!((0.2..=1.5).contains(v), "exponent {i}: {v}");
        }
    }
}

/// A user's loop: the first sample returns the measurement, later ones a prediction;
/// a snapshot restores the very same continuation; bad samples are refused.
#[test]
fn a_users_loop_snapshots_and_refuses_bad_samples() {
    let rec = tanks(4, 300);
    let scaling = Scaling::of(&[&rec.outputs[0]], &[&rec.inputs[0]]);
    let spec = cascade(CascadeOnlineSpec::default(), 1);
    let mut id = OnlineIdentifier::new(&spec, 1, 1, 4.0, scaling).unwrap();
    let first = id.update(0.0, &[rec.inputs[0][0]], &[rec.outputs[0][0]]).unwrap()[0];
    assert_eq!(first, rec.outputs[0][0]);
    for k in 1..200 {
        let e = id
            .update(rec.t[k], &[rec.inputs[0][k]], &[rec.outputs[0][k]])
            .unwrap()[0];
        assert!(e.is_finite());
    }
    let snap = id.snapshot();
    let run = |id: &mut OnlineIdentifier| -> Vec<f64> {
        (200..250)
            .map(|k| {
                id.update(rec.t[k], &[rec.inputs[0][k]], &[rec.outputs[0][k]])
                    .unwrap()[0]
            })
            .collect()
    };
    let a = run(&mut id);
    id.restore(&snap);
    assert_eq!(run(&mut id), a);
    let t = rec.t[250];
    let e = id.update(t, &[f64::NAN], &[1.0]).unwrap_err().to_string();
    assert!(e.contains("finite"), "{e}");
    let e = id.update(rec.t[100], &[1.0], &[1.0]).unwrap_err().to_string();
    assert!(e.contains("after the previous sample"), "{e}");
    let e = id.update(t, &[1.0, 2.0], &[1.0]).unwrap_err().to_string();
    assert!(e.contains("1 inputs and 1 output"), "{e}");
}

/// Every setting of the structure is checked and the error names its key.
#[test]
fn cascade_settings_are_checked() {
    let s = Scaling::identity(1, 1);
    let err = |spec: &OnlineSpec, ny: usize| {
        let s = if ny == 1 {
            s.clone()
        } else {
            Scaling::identity(ny, 1)
        };
        OnlineIdentifier::new(spec, ny, 1, 1.0, s)
            .unwrap_err()
            .to_string()
    };
    let base = cascade(CascadeOnlineSpec::default(), 1);
    for (set, key) in [
        (
            CascadeOnlineSpec {
                neurons: 1,
                ..Default::default()
            },
            "model.cascade.neurons",
        ),
        (
            CascadeOnlineSpec {
                starts: 0,
                ..Default::default()
            },
            "model.cascade.starts",
        ),
        (
            CascadeOnlineSpec {
                measurement_var: 0.0,
                ..Default::default()
            },
            "model.cascade.measurement_var",
        ),
        (
            CascadeOnlineSpec {
                pass_var: f64::NAN,
                ..Default::default()
            },
            "model.cascade.pass_var",
        ),
        (
            CascadeOnlineSpec {
                substeps: 0,
                ..Default::default()
            },
            "model.cascade.substeps",
        ),
    ] {
        let e = err(&cascade(set, 1), 1);
        assert!(e.contains(key), "{key}: {e}");
    }
    let with_law = OnlineSpec {
        law: Some(rhonn::law::LawSpec::FilteredRegressorGradient { gamma: vec![] }),
        ..base.clone()
    };
    assert!(err(&with_law, 1).contains("model.law"));
    let with_filters = OnlineSpec {
        filters_s: vec![10.0],
        ..base.clone()
    };
    assert!(err(&with_filters, 1).contains("model.filters_s"));
    assert!(err(&base, 2).contains("one output"));
    let table_elsewhere = OnlineSpec {
        structure: OnlineStructure::Lagged,
        ..base.clone()
    };
    assert!(err(&table_elsewhere, 1).contains("model.cascade"));
}

/// The frozen model as `model.json` holds it runs again from the file; parameters that
/// are not a valid chain (a negative rate) are refused with their field.
#[test]
fn the_frozen_model_round_trips_and_bad_parameters_are_refused() {
    let rec = tanks(5, 500);
    let spec = cascade(CascadeOnlineSpec::default(), 2);
    let run = identify_records(&spec, std::slice::from_ref(&rec), &["y".to_string()]).unwrap();
    let model = OnlineModel {
        kind: OnlineModel::KIND.into(),
        inputs: vec!["u".into()],
        outputs: vec!["y".into()],
        sample_time_s: 4.0,
        model: spec.clone(),
        scaling: run.identifier.scaling().clone(),
        weights: run.identifier.weights(),
        own_y_bounds: Vec::new(),
    };
    let text = serde_json::to_string(&model).unwrap();
    let back: OnlineModel = serde_json::from_str(&text).unwrap();
    let mut a = run.identifier.clone();
    let mut b = back.identifier().unwrap();
    let pa = predict_records(&mut a, std::slice::from_ref(&rec), None).unwrap();
    let pb = predict_records(&mut b, std::slice::from_ref(&rec), None).unwrap();
    assert_eq!(pa, pb);
    let mut bad = model.clone();
    bad.weights[0][1] = -0.1;
    let e = bad.identifier().unwrap_err().to_string();
    assert!(e.contains("model.weights (cascade rate or bound)"), "{e}");
}
