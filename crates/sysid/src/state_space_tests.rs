//! Tests of the `state-space` models.

use super::*;
use crate::{fit, Activation, Estimator, Kind};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A polynomial nonlinear state-space system of two states (a resonance with a cubic
/// stiffness in the first state and a quadratic term of the input), driven by seeded
/// white noise; its output measured with white noise of deviation `noise`.
fn system(seed: u64, n: usize, noise: f64) -> Record {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let u: Vec<f64> = (0..n).map(|_| rng.gen_range(-1.0..1.0)).collect();
    let (mut x1, mut x2) = (0.0f64, 0.0f64);
    let mut y = Vec::with_capacity(n);
    for &uk in &u {
        y.push(1.0 + x1 + noise * rng.gen_range(-3f64.sqrt()..3f64.sqrt()));
        let n1 = 1.2 * x1 - 0.5 * x2 + 0.3 * uk - 0.15 * x1 * x1 * x1;
        let n2 = x1 + 0.05 * uk * uk;
        (x1, x2) = (n1, n2);
    }
    Record {
        source: format!("pnlss{seed}"),
        t: (0..n).map(|k| 0.01 * k as f64).collect(),
        inputs: vec![u],
        outputs: vec![y],
    }
}

fn names() -> (Vec<String>, Vec<String>) {
    (vec!["u".into()], vec!["y".into()])
}

fn spec() -> ModelSpec {
    ModelSpec {
        kind: Kind::StateSpace,
        na: 2,
        nk: 1,
        degree: 3,
        activation: Activation::Identity,
        settle: 0,
        law: Estimator::SimulationError,
        epochs: 100,
        ..Default::default()
    }
}

/// RMS of the free run's error against the measured (noisy) output, from `first`.
fn free_run_rms(m: &Model, r: &Record) -> f64 {
    let (pred, first) = m.predict(r, None).unwrap();
    crate::metrics::rms_error(&r.outputs[0][first..], &pred[0][first..])
}

#[test]
fn a_simulated_pnlss_system_is_recovered_to_its_noise_floor() {
    let noise = 0.01;
    let (i, o) = names();
    let train = system(1, 3000, noise);
    let test = system(2, 2000, noise);
    let m = fit(&spec(), std::slice::from_ref(&train), &i, &o).unwrap();
    m.validate().unwrap();
    let ss = free_run_rms(&m, &test);
    // The free run on a record it was not trained on errs by the measurement noise alone,
    // within 1 %; the linear state-space model of the same order does not come close.
    assert!(
        ss <= 1.01 * noise,
        "state-space free run {ss} against noise {noise}"
    );
    let linear = fit(
        &ModelSpec { degree: 1, ..spec() },
        std::slice::from_ref(&train),
        &i,
        &o,
    )
    .unwrap();
    let lin = free_run_rms(&linear, &test);
    assert!(lin > 2.0 * noise, "linear {lin}");
}

#[test]
fn training_is_deterministic_and_the_stored_model_round_trips() {
    let (i, o) = names();
    let train = system(3, 1500, 0.02);
    let s = ModelSpec { epochs: 10, ..spec() };
    let a = fit(&s, std::slice::from_ref(&train), &i, &o).unwrap();
    let b = fit(&s, std::slice::from_ref(&train), &i, &o).unwrap();
    assert_eq!(a.weights, b.weights);
    let p = Params::from_stored(&a.spec, 1, 1, &a.weights[0]).unwrap();
    assert_eq!(p.to_stored(), a.weights[0]);
    assert_eq!((p.nx, p.has_d), (2, false));
}

#[test]
fn a_damaged_stored_model_is_refused_naming_the_field() {
    let (i, o) = names();
    let train = system(4, 800, 0.02);
    let mut m = fit(
        &ModelSpec { epochs: 3, ..spec() },
        std::slice::from_ref(&train),
        &i,
        &o,
    )
    .unwrap();
    m.weights[0].pop();
    let e = m.validate().unwrap_err().to_string();
    assert!(e.contains("model.weights[0]"), "{e}");
    m.weights[0][0] = 2.5;
    let e = m.validate().unwrap_err().to_string();
    assert!(e.contains("the number of states"), "{e}");
}

#[test]
fn the_initial_state_is_fitted_to_the_settle_window_and_a_k_step_prediction_runs() {
    let (i, o) = names();
    let train = system(5, 2000, 0.005);
    let s = ModelSpec { settle: 8, ..spec() };
    let m = fit(&s, std::slice::from_ref(&train), &i, &o).unwrap();
    // A record that starts mid-motion: the last 1,000 samples of another run.
    let mut mid = system(6, 2000, 0.005);
    mid.t.drain(..1000);
    mid.inputs[0].drain(..1000);
    mid.outputs[0].drain(..1000);
    let (free, first) = m.predict(&mid, None).unwrap();
    assert_eq!(first, 8);
    let early = crate::metrics::rms_error(&mid.outputs[0][8..40], &free[0][8..40]);
    assert!(early < 0.05, "the free run's start errs by {early}");
    let (ahead, first) = m.predict(&mid, Some(5)).unwrap();
    assert_eq!(first, 12);
    let e = crate::metrics::rms_error(&mid.outputs[0][first..], &ahead[0][first..]);
    assert!(e < 0.02, "5 steps ahead {e}");
}

#[test]
fn spec_rules_name_the_field() {
    for (s, field) in [
        (ModelSpec { nk: 2, ..spec() }, "model.nk"),
        (ModelSpec { degree: 9, ..spec() }, "model.degree"),
        (ModelSpec { na: 9, ..spec() }, "model.na"),
        (
            ModelSpec {
                law: Estimator::Rls,
                ..spec()
            },
            "model.law",
        ),
    ] {
        let e = s.check().unwrap_err().to_string();
        assert!(e.contains(field), "{field}: {e}");
    }
}

#[test]
fn the_sensitivities_give_the_gradient_and_the_cost_of_the_simulation_error() {
    let (i, o) = names();
    let train = system(7, 600, 0.01);
    let m = fit(
        &ModelSpec { epochs: 5, ..spec() },
        std::slice::from_ref(&train),
        &i,
        &o,
    )
    .unwrap();
    let mut p = Params::from_stored(&m.spec, 1, 1, &m.weights[0]).unwrap();
    // Off the trained point, every term in play, no state at a bound.
    let mut th = p.free();
    for (k, v) in th.iter_mut().enumerate() {
        *v += 0.002 * ((k % 7) as f64 - 3.0);
    }
    p.set_free(&th);
    p.x_lo = vec![f64::NEG_INFINITY; p.nx];
    p.x_hi = vec![f64::INFINITY; p.nx];
    let mono = Monomials::of(&m.spec, p.nx, 1);
    let windows = vec![normalised(&m, &train)];
    let (_, g, cost) = normal::normal(&p, &mono, 0, &windows).unwrap();
    let cost_at = |th: &[f64]| {
        let mut q = p.clone();
        q.set_free(th);
        let mut r = Vec::new();
        assert!(residuals(&q, &mono, m.spec.settle, &windows, &mut r));
        r.iter().map(|v| v * v).sum::<f64>()
    };
    assert!(
        (cost - cost_at(&th)).abs() <= 1e-9 * cost,
        "{cost} against {}",
        cost_at(&th)
    );
    // d cost / d theta = 2 J^T r, against central differences, for every parameter.
    crate::lm::assert_gradient(&th, g.as_slice(), cost, cost_at, "state-space");
}

#[test]
fn two_inputs_and_two_outputs_run_as_one_model_with_states_side_by_side() {
    // Two coupled first-order systems, each output with its own cubic, both inputs acting.
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let n = 2500;
    let u: Vec<Vec<f64>> = (0..2)
        .map(|_| (0..n).map(|_| rng.gen_range(-1.0..1.0)).collect())
        .collect();
    let (mut a, mut b) = (0.0f64, 0.0f64);
    let mut y = vec![Vec::new(), Vec::new()];
    for k in 0..n {
        y[0].push(a + 0.003 * rng.gen_range(-1.0..1.0));
        y[1].push(2.0 * b + 0.003 * rng.gen_range(-1.0..1.0));
        let na = 0.8 * a + 0.3 * u[0][k] + 0.1 * u[1][k] - 0.2 * a * a * a;
        let nb = 0.6 * b + 0.2 * a + 0.3 * u[1][k];
        (a, b) = (na, nb);
    }
    let r = Record {
        source: "mimo".into(),
        t: (0..n).map(|k| 0.01 * k as f64).collect(),
        inputs: u,
        outputs: y,
    };
    let (train, test) = (r.slice(0, 1800), r.slice(1800, n));
    let (i, o) = (
        vec!["u1".to_string(), "u2".to_string()],
        vec!["y1".to_string(), "y2".to_string()],
    );
    let s = ModelSpec {
        na: 1,
        nk: 1,
        settle: 4,
        epochs: 60,
        ..spec()
    };
    let m = fit(&s, std::slice::from_ref(&train), &i, &o).unwrap();
    m.validate().unwrap();
    let p = Params::from_stored(&m.spec, 2, 2, &m.weights[0]).unwrap();
    assert_eq!((p.nx, p.ni, p.no), (2, 2, 2));
    let (pred, first) = m.predict(&test, None).unwrap();
    for j in 0..2 {
        let e = crate::metrics::rms_error(&test.outputs[j][first..], &pred[j][first..]);
        let (_, sd) = crate::metrics::mean_std(&[&test.outputs[j][first..]]);
        assert!(
            e < 0.05 * sd,
            "output {j}: free-run error {e} against deviation {sd}"
        );
    }
}

#[test]
fn too_many_terms_are_refused_before_they_are_made() {
    let s = spec();
    assert_eq!(Monomials::count(&s, 2, 1), Monomials::of(&s, 2, 1).len());
    let states = ModelSpec {
        nonlinear_in: crate::NonlinearIn::States,
        degree: 4,
        ..s.clone()
    };
    assert_eq!(
        Monomials::count(&states, 3, 2),
        Monomials::of(&states, 3, 2).len()
    );
    // 60 inputs of degree 5: about 10 million terms, refused at once, naming the field.
    let wide = ModelSpec { degree: 5, ..s };
    let e = Monomials::check_count(&wide, 2, 60).unwrap_err().to_string();
    assert!(
        e.contains("model.degree") && e.contains("at most 2000 terms"),
        "{e}"
    );
}

#[test]
fn the_same_bits_on_one_thread_and_on_four() {
    // Subsections (`multi-step`) make many windows, summed by several tasks at once.
    let (i, o) = names();
    let train = system(10, 1200, 0.01);
    let s = ModelSpec {
        law: Estimator::MultiStep,
        horizon: 40,
        settle: 4,
        epochs: 8,
        ..spec()
    };
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| fit(&s, std::slice::from_ref(&train), &i, &o).unwrap().weights)
    };
    assert_eq!(on(1), on(4));
}

#[test]
fn the_stability_of_a_is_the_largest_eigenvalue_inside_the_unit_circle() {
    // A rotation scaled to radius r: a complex pair of modulus r; then a real pole alone.
    let rotation = |r: f64| {
        let mut p = Params::zeros(2, 1, 1, false, 0);
        let (c, s) = (0.6, 0.8);
        p.a = vec![r * c, -r * s, r * s, r * c];
        p
    };
    assert!(rotation(0.99).is_stable());
    assert!(!rotation(1.0 + 1e-9).is_stable());
    assert!(!rotation(1.3).is_stable());
    let mut p = rotation(0.5);
    p.a[3] = f64::NAN;
    assert!(!p.is_stable(), "not finite");
    let mut one = Params::zeros(1, 1, 1, false, 0);
    one.a = vec![-1.01];
    assert!(!one.is_stable());
    one.a = vec![-0.999];
    assert!(one.is_stable());
}

#[test]
fn an_integrator_is_trained_to_a_stable_model() {
    // y(k+1) = y(k) + 0.05 u(k): the least-squares ARX puts its pole at 1 or just beyond,
    // and the simulation error pulls A toward the circle; the trained A stays inside it,
    // and the free run on a record of another seed stays finite and near the output.
    let integrator = |seed: u64| {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let u: Vec<f64> = (0..2000)
            .map(|k| (k as f64 * 0.01).sin() + 0.3 * rng.gen_range(-1.0..1.0))
            .collect();
        let mut y = vec![0.0];
        for k in 0..u.len() - 1 {
            y.push(y[k] + 0.05 * u[k]);
        }
        Record {
            source: format!("integrator{seed}"),
            t: (0..u.len()).map(|k| 0.01 * k as f64).collect(),
            inputs: vec![u],
            outputs: vec![y],
        }
    };
    let (i, o) = names();
    let s = ModelSpec {
        na: 1,
        degree: 2,
        epochs: 50,
        ..spec()
    };
    let train = integrator(1);
    let m = fit(&s, std::slice::from_ref(&train), &i, &o).unwrap();
    let p = Params::from_stored(&m.spec, 1, 1, &m.weights[0]).unwrap();
    assert!(p.is_stable(), "A = {:?}", p.a);
    let rms = free_run_rms(&m, &integrator(2));
    assert!(rms.is_finite(), "{rms}");
}
