use super::*;
use crate::estimate::batch_ls;
use crate::metrics;
use crate::models::nonlinear_regressors;

/// Issue: "the Cholesky `expect` in `sysid/mod.rs` fires with `ridge = 0` on collinear
/// data". A Gram matrix the factorisation refuses is now an error naming the ridge.
#[test]
fn a_gram_matrix_without_a_factorisation_is_an_error_naming_the_ridge() {
    let rows = vec![vec![1.0, f64::NAN], vec![2.0, 1.0], vec![3.0, 1.0]];
    let e = batch_ls(&rows, &[vec![1.0, 2.0, 3.0]], 0.0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("`model.ridge` = 0") && e.contains("collinear"), "{e}");
    // Exactly collinear regressors (a column repeated) still solve with the tiny
    // diagonal load, and the weights are finite.
    let rows: Vec<Vec<f64>> = (0..50).map(|k| vec![k as f64, k as f64, 1.0]).collect();
    let y: Vec<f64> = (0..50).map(|k| 2.0 * k as f64 + 1.0).collect();
    let w = batch_ls(&rows, &[y], 0.0).unwrap();
    assert!(w[0].iter().all(|v| v.is_finite()));
    assert!((w[0][0] + w[0][1] - 2.0).abs() < 1e-3, "{:?}", w[0]);
}

/// `n` samples of seeded uniform noise in [-amp, amp), each value held `hold` samples.
fn held_noise(seed: u64, n: usize, hold: usize, amp: f64) -> Vec<f64> {
    let mut s = seed;
    let mut next = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((s >> 33) as f64 / (1u64 << 31) as f64) - 0.5
    };
    let mut level = 0.0;
    (0..n)
        .map(|k| {
            if k % hold == 0 {
                level = 2.0 * amp * next();
            }
            level
        })
        .collect()
}

/// A record of y(k) = 0.5 y(k-1) + 0.3 u(k-1) + 0.2 y(k-1)^2-ish nonlinear system.
fn record(seed: u64, n: usize, nonlinear: bool) -> Record {
    let u = held_noise(seed, n, 7, 1.0);
    let mut y = vec![0.0; n];
    for k in 1..n {
        let lin = 0.5 * y[k - 1] + 0.3 * u[k - 1];
        y[k] = if nonlinear {
            lin + 0.4 * (y[k - 1]).tanh() * u[k - 1]
        } else {
            lin
        };
    }
    Record {
        source: format!("r{seed}"),
        t: (0..n).map(|k| k as f64 * 0.1).collect(),
        inputs: vec![u],
        outputs: vec![y],
    }
}

fn names() -> (Vec<String>, Vec<String>) {
    (vec!["u".into()], vec!["y".into()])
}

#[test]
fn spec_files_hold_one_structure_or_an_ensemble() {
    let one = parse_spec_file("na = 3\nnb = 1\n").unwrap();
    assert_eq!(one.len(), 1);
    assert_eq!((one[0].na, one[0].nb, one[0].kind), (3, 1, Kind::Rhonn));
    let two = parse_spec_file("[[members]]\nna = 2\n[[members]]\nkind = \"arx\"\nna = 4\n").unwrap();
    assert_eq!(two.len(), 2);
    assert_eq!((two[0].na, two[1].na, two[1].kind), (2, 4, Kind::Arx));
    for (text, says) in [
        ("members = []\n", "non-empty list"),
        ("na = 2\n[[members]]\nna = 3\n", "`na` beside `members`"),
        ("[[members]]\nna = 2\n[[members]]\nnaa = 3\n", "members[1]"),
        ("nope = 1\n", "nope"),
    ] {
        let e = parse_spec_file(text).unwrap_err();
        assert!(e.contains(says), "{text:?}: {e}");
    }
}

#[test]
fn an_ensemble_predicts_the_mean_of_its_members() {
    let (i, o) = names();
    let specs = [
        ModelSpec {
            na: 1,
            nb: 1,
            ..Default::default()
        },
        ModelSpec {
            na: 3,
            nb: 2,
            degree: 1,
            max_factors: 1,
            ..Default::default()
        },
    ];
    let rec = record(1, 400, true);
    let ens = fit_ensemble(&specs, std::slice::from_ref(&rec), &i, &o, None).unwrap();
    assert_eq!(ens.members.len(), 1);
    ens.validate().unwrap();
    assert_eq!(ens.max_lag(), 3);
    let val = record(2, 300, true);
    for steps in [None, Some(1), Some(4)] {
        let (p, first) = ens.predict(&val, steps).unwrap();
        let (pa, fa) = ens.model.predict(&val, steps).unwrap();
        let (pb, fb) = ens.members[0].predict(&val, steps).unwrap();
        assert_eq!(first, fa.max(fb));
        for k in 0..val.len() {
            let want = if k < first {
                val.outputs[0][k]
            } else {
                (pa[0][k] + pb[0][k]) / 2.0
            };
            assert!((p[0][k] - want).abs() < 1e-12, "{steps:?} sample {k}");
        }
    }
    // A single structure is the one-member case, with no `members` in model.json.
    let single = fit_with_baseline(&specs[0], std::slice::from_ref(&rec), &i, &o).unwrap();
    assert!(single.members.is_empty());
    assert!(!serde_json::to_string(&single).unwrap().contains("members"));
    assert_eq!(
        single.predict(&val, None).unwrap(),
        single.model.predict(&val, None).unwrap()
    );
}

#[test]
fn nonlinear_lags_limit_the_high_order_terms_to_the_newest_lags() {
    let (i, o) = names();
    let spec = ModelSpec {
        na: 3,
        nb: 4,
        degree: 2,
        max_factors: 2,
        nonlinear_lags: Some(2),
        input_filters_s: vec![1.0],
        ..Default::default()
    };
    // phi = [y lags 1..3 (0, 1, 2), u lags 1..4 (3..7), filtered u (7)]
    assert_eq!(nonlinear_regressors(&spec, 1, 1), vec![0, 1, 3, 4, 7]);
    let m = fit(&spec, &[record(1, 400, true)], &i, &o).unwrap();
    // 5 factors, degree 2: 5 linear + 5 squares + 10 products.
    assert_eq!(m.terms.len(), 20);
    let used: std::collections::BTreeSet<usize> = m.terms.iter().flatten().map(|f| f[0]).collect();
    assert_eq!(used.into_iter().collect::<Vec<_>>(), vec![0, 1, 3, 4, 7]);
    let all = ModelSpec {
        nonlinear_lags: None,
        ..spec.clone()
    };
    assert_eq!(nonlinear_regressors(&all, 1, 1), (0..8).collect::<Vec<_>>());
    let bad = ModelSpec {
        nonlinear_lags: Some(0),
        ..spec
    };
    let e = bad.check().unwrap_err().to_string();
    assert!(e.contains("model.nonlinear_lags") && e.contains("[1, 50]"), "{e}");
}

#[test]
fn arx_recovers_a_linear_system_exactly_and_predicts_unseen_data() {
    let (i, o) = names();
    let spec = ModelSpec {
        kind: Kind::Arx,
        na: 1,
        nb: 1,
        nk: 1,
        ..Default::default()
    };
    let m = fit(&spec, &[record(1, 500, false)], &i, &o).unwrap();
    let val = record(2, 300, false);
    let (p, first) = m.predict(&val, None).unwrap();
    let f = m.figures(&val, &p, first);
    assert!(f[0].fit_percent > 99.9, "{f:?}");
    assert_eq!(first, 1);
}

#[test]
fn rhonn_beats_arx_with_the_same_lags_on_a_nonlinear_system() {
    let (i, o) = names();
    let spec = ModelSpec {
        na: 1,
        nb: 1,
        nk: 1,
        ..Default::default()
    };
    let fm = fit_with_baseline(&spec, &[record(3, 800, true)], &i, &o).unwrap();
    let val = record(4, 400, true);
    let free = |m: &Model| {
        let (p, first) = m.predict(&val, None).unwrap();
        m.figures(&val, &p, first)[0].fit_percent
    };
    let (rh, arx) = (free(&fm.model), free(fm.baseline.as_ref().unwrap()));
    assert!(rh > 95.0 && rh > arx + 20.0, "rhonn {rh} %, arx {arx} %");
}

#[test]
fn k_steps_ahead_sits_between_one_step_and_free_run() {
    let (i, o) = names();
    let m = fit(
        &ModelSpec {
            kind: Kind::Arx,
            na: 2,
            nb: 2,
            nk: 1,
            ..Default::default()
        },
        &[record(5, 500, true)],
        &i,
        &o,
    )
    .unwrap();
    let val = record(6, 300, true);
    let fit_of = |k: Option<usize>| {
        let (p, first) = m.predict(&val, k).unwrap();
        m.figures(&val, &p, first)[0].fit_percent
    };
    let (one, ten, free) = (fit_of(Some(1)), fit_of(Some(10)), fit_of(None));
    assert!(one >= ten - 1e-9 && ten >= free - 1.0, "{one} {ten} {free}");
}

#[test]
fn simulation_and_multi_step_training_lower_their_own_criterion_below_least_squares() {
    let (i, o) = names();
    // Noisy measurements: one-step least squares is biased for free runs.
    let mut data = record(9, 600, true);
    let mut s = 7u64;
    for v in data.outputs[0].iter_mut() {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        *v += 0.05 * (((s >> 33) as f64 / (1u64 << 31) as f64) - 0.5);
    }
    let base = ModelSpec {
        na: 2,
        nb: 2,
        nk: 1,
        epochs: 20,
        ..Default::default()
    };
    let err = |m: &Model, h: Option<usize>| {
        let (p, first) = m.predict(&data, h).unwrap();
        m.figures(&data, &p, first)[0].rms_error
    };
    let ls = fit(&base, std::slice::from_ref(&data), &i, &o).unwrap();
    let se = fit(
        &ModelSpec {
            law: Estimator::SimulationError,
            ..base.clone()
        },
        std::slice::from_ref(&data),
        &i,
        &o,
    )
    .unwrap();
    let ms = fit(
        &ModelSpec {
            law: Estimator::MultiStep,
            horizon: 5,
            ..base.clone()
        },
        std::slice::from_ref(&data),
        &i,
        &o,
    )
    .unwrap();
    assert!(
        err(&se, None) < err(&ls, None),
        "free run: {} vs {}",
        err(&se, None),
        err(&ls, None)
    );
    assert!(
        err(&ms, Some(5)) < err(&ls, Some(5)),
        "5 steps: {} vs {}",
        err(&ms, Some(5)),
        err(&ls, Some(5))
    );
}

#[test]
fn input_filters_stand_for_an_unmeasured_lagged_state() {
    // y(k) = 2 x(k-1), x a first-order lag (tau = 1 s, T = 0.1 s) of u: a static map
    // of the filtered input, which two input lags cannot express.
    let (i, o) = names();
    let mut r = record(11, 600, false);
    let a = (-0.1f64 / 1.0).exp();
    let mut x = r.inputs[0][0];
    let u = r.inputs[0].clone();
    for k in 0..r.len() {
        r.outputs[0][k] = 2.0 * x;
        x = a * x + (1.0 - a) * u[k];
    }
    let free_fit = |spec: &ModelSpec| {
        let m = fit(spec, std::slice::from_ref(&r), &i, &o).unwrap();
        let (p, first) = m.predict(&r, None).unwrap();
        m.figures(&r, &p, first)[0].fit_percent
    };
    let plain = ModelSpec {
        kind: Kind::Arx,
        na: 1,
        nb: 1,
        nk: 1,
        ..Default::default()
    };
    let filtered = ModelSpec {
        input_filters_s: vec![1.0],
        ..plain.clone()
    };
    let (f0, f1) = (free_fit(&plain), free_fit(&filtered));
    assert!(f1 > 99.9, "with the filter: {f1} %");
    assert!(f0 < f1, "{f0} vs {f1}");
    let bad = ModelSpec {
        input_filters_s: vec![-1.0],
        ..plain
    };
    assert!(bad
        .check()
        .unwrap_err()
        .to_string()
        .contains("`model.input_filters_s[0]` = -1"));
}

#[test]
fn a_direct_two_step_predictor_is_exact_on_a_linear_system() {
    // y(k) = 0.5 y(k-1) + 0.3 u(k-1) = 0.25 y(k-2) + 0.15 u(k-2) + 0.3 u(k-1).
    let (i, o) = names();
    let spec = ModelSpec {
        kind: Kind::Arx,
        na: 1,
        nb: 2,
        nk: 1,
        output_lag_start: 2,
        ..Default::default()
    };
    assert_eq!(spec.max_lag(), 2);
    let m = fit(&spec, &[record(12, 400, false)], &i, &o).unwrap();
    let val = record(13, 200, false);
    let (p, first) = m.predict(&val, Some(2)).unwrap();
    assert!(m.figures(&val, &p, first)[0].fit_percent > 99.99);
}

#[test]
fn pruning_keeps_the_terms_that_matter() {
    // The nonlinear record needs the product tanh(y(k-1)) u(k-1): with two terms kept
    // out of the nine of degree 2 the model must keep that one and stay accurate.
    let (i, o) = names();
    let data = [record(14, 800, true)];
    let spec = ModelSpec {
        na: 1,
        nb: 1,
        nk: 1,
        max_terms: Some(2),
        ..Default::default()
    };
    let m = fit(&spec, &data, &i, &o).unwrap();
    assert_eq!(m.terms.len(), 2);
    assert!(m.terms.contains(&vec![[0, 1], [1, 1]]), "{:?}", m.terms);
    let val = record(15, 300, true);
    let (p, first) = m.predict(&val, None).unwrap();
    assert!(m.figures(&val, &p, first)[0].fit_percent > 90.0);
    let full = fit(
        &ModelSpec {
            max_terms: None,
            ..spec
        },
        &data,
        &i,
        &o,
    )
    .unwrap();
    assert!(full.terms.len() > 2);
}

#[test]
fn error_reduction_keeps_the_term_that_explains_the_output() {
    // The same record: forward regression by error reduction ratio, one term kept out of
    // nine, keeps the product tanh(y(k-1)) u(k-1) and runs free on another record.
    let (i, o) = names();
    let spec = ModelSpec {
        na: 1,
        nb: 1,
        nk: 1,
        max_terms: Some(1),
        term_selection: TermSelection::ErrorReduction,
        ..Default::default()
    };
    let m = fit(&spec, &[record(14, 800, true)], &i, &o).unwrap();
    assert_eq!(m.terms, vec![vec![[0, 1], [1, 1]]]);
    let val = record(15, 300, true);
    let (p, first) = m.predict(&val, None).unwrap();
    assert!(m.figures(&val, &p, first)[0].fit_percent > 90.0);
    // model.json names it; the default is not written (files as before).
    assert!(serde_json::to_string(&m.spec)
        .unwrap()
        .contains("\"term_selection\":\"error-reduction\""));
    assert!(!serde_json::to_string(&ModelSpec::default())
        .unwrap()
        .contains("term_selection"));
    // Without max_terms there is nothing to choose: refused, naming the key.
    let e = ModelSpec {
        max_terms: None,
        ..spec
    }
    .check()
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("model.term_selection") && e.contains("max_terms"),
        "{e}"
    );
}

#[test]
fn recursive_laws_approach_batch_least_squares() {
    let (i, o) = names();
    let data = [record(7, 600, false)];
    let base = ModelSpec {
        kind: Kind::Arx,
        na: 1,
        nb: 1,
        nk: 1,
        ..Default::default()
    };
    let w_ls = fit(&base, &data, &i, &o).unwrap().weights;
    let w_rls = fit(
        &ModelSpec {
            law: Estimator::Rls,
            epochs: 3,
            ..base.clone()
        },
        &data,
        &i,
        &o,
    )
    .unwrap()
    .weights;
    let w_g = fit(
        &ModelSpec {
            law: Estimator::Gradient,
            epochs: 200,
            ..base.clone()
        },
        &data,
        &i,
        &o,
    )
    .unwrap()
    .weights;
    for k in 0..w_ls[0].len() {
        assert!((w_ls[0][k] - w_rls[0][k]).abs() < 1e-3, "{w_ls:?} {w_rls:?}");
        assert!((w_ls[0][k] - w_g[0][k]).abs() < 2e-2, "{w_ls:?} {w_g:?}");
    }
}

/// A discretised Duffing oscillator (a hardening cubic spring, Silverbox's law) driven by
/// seeded noise held 3 samples, of amplitude `amp`.
fn duffing(seed: u64, n: usize, amp: f64) -> Record {
    let u = held_noise(seed, n, 3, amp);
    let mut y = vec![0.0; n];
    for k in 2..n {
        y[k] = 1.6 * y[k - 1] - 0.8 * y[k - 2] + 0.1 * u[k - 1] - 0.5 * y[k - 1].powi(3);
    }
    Record {
        source: format!("duffing{seed}"),
        t: (0..n).map(|k| k as f64 * 0.01).collect(),
        inputs: vec![u],
        outputs: vec![y],
    }
}

#[test]
fn a_polynomial_rhonn_extrapolates_a_cubic_spring_where_the_sigmoid_saturates() {
    let (i, o) = names();
    let train = duffing(1, 3000, 1.0);
    // A larger input than in training: the spring goes further into its cubic range.
    let test = duffing(2, 2000, 1.6);
    let spec = |activation| ModelSpec {
        na: 2,
        nb: 1,
        degree: 3,
        max_factors: 3,
        activation,
        law: Estimator::SimulationError,
        epochs: 30,
        ..Default::default()
    };
    let err = |m: &Model| {
        let (p, first) = m.predict(&test, None).unwrap();
        metrics::rms_error(&test.outputs[0][first..], &p[0][first..])
    };
    let sd = {
        let y = &test.outputs[0];
        let mean = y.iter().sum::<f64>() / y.len() as f64;
        (y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / y.len() as f64).sqrt()
    };
    let poly = fit(&spec(Activation::Identity), std::slice::from_ref(&train), &i, &o).unwrap();
    let sig = fit(&spec(Activation::Tanh), std::slice::from_ref(&train), &i, &o).unwrap();
    let (ep, es) = (err(&poly), err(&sig));
    // The polynomial holds the law itself (y^3 is one of its terms).
    assert!(ep < 0.01 * sd, "polynomial {ep}, output deviation {sd}");
    assert!(ep < 0.2 * es, "polynomial {ep}, tanh {es}");
    // The file says `activation` only when it is not the default.
    let text = serde_json::to_string(&poly).unwrap();
    assert!(text.contains("\"activation\":\"identity\""), "{text}");
    assert!(!serde_json::to_string(&sig).unwrap().contains("activation"));
}

#[test]
fn a_law_a_kind_does_not_train_with_is_named_as_the_spec_writes_it() {
    for (kind, law, allowed) in [
        (Kind::Pump, Estimator::BatchLs, "multi-step"),
        (Kind::WienerHammerstein, Estimator::MultiStep, "simulation-error"),
        (Kind::Cascade, Estimator::Rls, "simulation-error"),
    ] {
        let e = ModelSpec {
            kind,
            law,
            ..Default::default()
        }
        .check()
        .unwrap_err()
        .to_string();
        assert!(
            e.contains(&format!("`model.law` = {}", law.name())) && e.contains(allowed),
            "{e}"
        );
    }
}
