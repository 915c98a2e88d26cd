//! Tests of the `cascade` models.

use super::*;
use rand::Rng;

fn names() -> (Vec<String>, Vec<String>) {
    (vec!["u".into()], vec!["y".into()])
}

/// Two tanks in physical units (levels in V, time in s): the upper one overflows
/// at 10 V, sending 40 % of what it cannot hold on to the lower one.
fn tanks(u: &[f64], x0: [f64; 2], dt: f64) -> (Vec<f64>, usize) {
    let (k1, k4, k2, k3, o) = (0.06, 0.08, 0.05, 0.05, 0.4);
    let (mut x1, mut x2) = (x0[0], x0[1]);
    let h = dt / 400.0;
    let mut y = Vec::new();
    let mut overflowing = 0;
    for &uk in u {
        y.push(x2);
        overflowing += usize::from(x1 >= 10.0);
        for _ in 0..400 {
            let mut d1 = k4 * uk - k1 * x1.max(0.0).sqrt();
            let mut over = 0.0;
            if x1 >= 10.0 && d1 > 0.0 {
                over = d1;
                d1 = 0.0;
            }
            let d2 = k2 * x1.max(0.0).sqrt() - k3 * x2.max(0.0).sqrt() + o * over;
            x1 = (x1 + h * d1).clamp(0.0, 10.0);
            x2 = (x2 + h * d2).max(0.0);
        }
    }
    (y, overflowing)
}

fn steps(seed: u64, n: usize) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut u = Vec::new();
    let mut level = 0.0;
    for k in 0..n {
        if k % 40 == 0 {
            level = rng.gen_range(0.5..5.5);
        }
        u.push(level);
    }
    u
}

/// A record and the samples at which its upper tank overflows.
fn record(seed: u64, n: usize, x0: [f64; 2]) -> (Record, usize) {
    let u = steps(seed, n);
    let (y, overflowing) = tanks(&u, x0, 4.0);
    let r = Record {
        source: format!("tanks{seed}"),
        t: (0..n).map(|k| 4.0 * k as f64).collect(),
        inputs: vec![u],
        outputs: vec![y],
    };
    (r, overflowing)
}

/// A record of the two tanks and a cascade model shell trained on it for one
/// iteration from one start (names and normalisation set; tests put weights in).
fn shell(seed: u64, n: usize) -> (Record, Model) {
    let (i, o) = names();
    let (r, _) = record(seed, n, [3.0, 2.0]);
    let spec = ModelSpec {
        kind: super::super::Kind::Cascade,
        starts: 1,
        epochs: 1,
        ..ModelSpec::default()
    };
    let m = super::super::fit(&spec, std::slice::from_ref(&r), &i, &o).unwrap();
    (r, m)
}

#[test]
fn a_cascade_learns_two_tanks_with_overflow_and_runs_free_on_an_unseen_record() {
    let (i, o) = names();
    let (r1, o1) = record(1, 400, [3.0, 2.0]);
    let (r2, o2) = record(2, 400, [9.0, 6.0]);
    // The upper tank overflows in both records (else the share would go untested).
    assert!(o1 > 20 && o2 > 20, "{o1} {o2}");
    let train = [r1, r2];
    let spec = ModelSpec {
        kind: super::super::Kind::Cascade,
        starts: 6,
        epochs: 60,
        ..ModelSpec::default()
    };
    let m = super::super::fit(&spec, &train, &i, &o).unwrap();
    let (val, _) = record(3, 400, [6.0, 4.0]);
    let (p, first) = m.predict(&val, None).unwrap();
    assert_eq!(first, spec.settle);
    let f = m.figures(&val, &p, first);
    // The plant is in the model class: the free run is close to exact (levels span
    // about 2 to 10 V), and the learned exponents are Torricelli's.
    assert!(f[0].rms_error < 0.01, "rms {}", f[0].rms_error);
    let p = Params::from_stored(2, 1, &m.weights[0]);
    for a in &p.alpha {
        assert!((a - 0.5).abs() < 0.01, "exponents {:?}", p.alpha);
    }
    // An ARX with the same record runs visibly worse.
    let arx = ModelSpec {
        kind: super::super::Kind::Arx,
        ..ModelSpec::default()
    };
    let a = super::super::fit(&arx, &train, &i, &o).unwrap();
    let (pa, fa) = a.predict(&val, None).unwrap();
    let fa = a.figures(&val, &pa, fa);
    assert!(
        f[0].rms_error < 0.5 * fa[0].rms_error,
        "{} vs ARX {}",
        f[0].rms_error,
        fa[0].rms_error
    );
    // One step ahead from the measurements: at least as good as the free run.
    let (p1, f1) = m.predict(&val, Some(1)).unwrap();
    assert_eq!(f1, spec.settle);
    assert!(m.figures(&val, &p1, f1)[0].rms_error < 0.01);
}

#[test]
fn a_simulation_the_solver_cannot_finish_is_an_error_with_time_and_levels() {
    let (r, mut m) = shell(1, 60);
    // A first neuron that drains a million times faster than it fills, at the
    // smallest exponent: it settles on the activation's linear piece just above
    // empty, where its outflow's slope is about 2.5e8 per sample; the explicit solver
    // runs out of its 200 steps per sample.
    let mut p = Params::from_stored(2, 1, &m.weights[0]);
    p.k[0] = 1e6;
    p.alpha[0] = EXPONENT_RANGE.0;
    p.check().unwrap();
    m.weights = vec![p.stored()];
    m.validate().unwrap();
    let e = m.predict(&r, None).unwrap_err().to_string();
    assert!(e.starts_with("simulation failed at t = "), "{e}");
    assert!(e.contains("tanks1: cascade levels ["), "{e}");
    assert!(e.contains("`y` = ") && e.contains("in samples"), "{e}");
}

#[test]
fn k_steps_ahead_restarts_an_inexact_model_from_the_measurements() {
    // The true plant as a cascade, and a model of it with the lower tank's outflow
    // 30 % too small: its free run drifts; predictions re-anchored on the
    // measurements K samples back drift less the smaller K.
    let (r, mut m) = shell(4, 300);
    let settle = m.spec.settle;
    let (ym, ysd) = m.output_norm[0];
    let usd = m.input_norm[0].1;
    // Physical rates per second -> normalised per sample (levels / ysd, input / usd).
    let (dt, a) = (4.0, 0.5);
    let scale = |k: f64| k * dt * ysd.powf(a - 1.0);
    let exact = Params {
        b: vec![0.08 * usd * dt / ysd],
        k: vec![scale(0.06), scale(0.05)],
        alpha: vec![0.5, 0.5],
        g: vec![scale(0.05)],
        o: vec![0.4],
        xmax: vec![10.0 / ysd, 20.0 / ysd],
        c: -ym / ysd,
    };
    exact.check().unwrap();
    let mut p = exact.clone();
    p.k[1] *= 0.7;
    let rms = |m: &Model, k: Option<usize>| {
        let (pr, first) = m.predict(&r, k).unwrap();
        // Judge every K on the same samples.
        let from = first.max(settle - 1 + 20);
        let (y, yh) = (&r.outputs[0][from..], &pr[0][from..]);
        (y.iter().zip(yh).map(|(a, b)| (a - b) * (a - b)).sum::<f64>() / y.len() as f64).sqrt()
    };
    // The exact parameters run free on the plant (the units are right).
    m.weights = vec![exact.stored()];
    let e = rms(&m, None);
    assert!(e < 0.01, "exact model: {e}");
    m.weights = vec![p.stored()];
    let (e1, e5, e20, free) = (
        rms(&m, Some(1)),
        rms(&m, Some(5)),
        rms(&m, Some(20)),
        rms(&m, None),
    );
    assert!(e1 < e5 && e5 < e20 && e20 < free, "{e1} {e5} {e20} {free}");
    assert!(free > 1.0 && e1 < 0.1 * free, "{e1} {free}");
}

/// When none of the first starts trains to a valid cascade the fit stops there, long
/// before its 64 starts; when one does, every start runs (the result is then the one all
/// starts give, whatever the thread count).
#[test]
fn the_starts_stop_early_when_none_of_the_first_is_valid() {
    let ran = std::sync::Mutex::new(Vec::new());
    let run = |r: std::ops::Range<usize>| {
        ran.lock().unwrap().push(r.clone());
        r.collect::<Vec<usize>>()
    };
    let ends = staged_starts(64, run, |_| false);
    assert_eq!(ends, (0..EARLY_STARTS).collect::<Vec<_>>());
    assert_eq!(*ran.lock().unwrap(), vec![0..EARLY_STARTS]);
    ran.lock().unwrap().clear();
    let ends = staged_starts(64, run, |&s| s == 3);
    assert_eq!(ends, (0..64).collect::<Vec<_>>());
    assert_eq!(*ran.lock().unwrap(), vec![0..EARLY_STARTS, EARLY_STARTS..64]);
    // Fewer starts than the first stage: just those.
    assert_eq!(staged_starts(3, run, |_| true), vec![0, 1, 2]);
}

#[test]
fn a_hidden_state_column_from_its_own_record_is_the_full_evaluation_bit_for_bit() {
    // Three records of three neurons (two hidden states each): every Jacobian column,
    // a model coordinate's or a hidden state's, equals the full evaluation at the moved
    // point, so training does not depend on which one ran.
    let (_, m) = shell(3, 60);
    let co = Coords {
        n: 3,
        ni: 1,
        free_exp: true,
    };
    let data: Vec<_> = [4u64, 5, 6]
        .iter()
        .map(|&s| normalised(&m, &record(s, 40 + s as usize, [2.0, 1.0]).0))
        .collect();
    let fr = FreeRuns::new(co, &data);
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let th = random_start(co, -1.5, 1.5, data.len(), &mut rng);
    assert_eq!(th.len(), co.n_model() + 3 * 2);
    let mut r0 = Vec::new();
    assert!(fr.all(&th, &mut r0));
    assert_eq!(r0.len(), 43 + 44 + 45);
    let (mut full, mut col) = (Vec::new(), Vec::new());
    for c in 0..th.len() {
        let mut moved = th.clone();
        moved[c] += 0.3;
        assert!(fr.all(&moved, &mut full));
        assert!(fr.column(&moved, c, &r0, &mut col));
        assert_eq!(full, col, "column {c}");
        if c >= co.n_model() {
            // Only the moved state's record changed.
            let q = (c - co.n_model()) / 2;
            let at = [0, 43, 87, 132];
            assert!((0..r0.len()).all(|i| (at[q]..at[q + 1]).contains(&i) || full[i] == r0[i]));
            assert!(
                (at[q]..at[q + 1]).any(|i| full[i] != r0[i]),
                "column {c} moved nothing"
            );
        }
    }
}
