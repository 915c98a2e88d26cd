//! Tests of the `wiener-hammerstein` models.

use super::*;
use crate::{fit, Estimator, Kind};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A Wiener-Hammerstein system: a first-order low-pass, a saturation, a resonant
/// second-order filter; driven by seeded white noise held for 2 samples.
fn system(seed: u64, n: usize) -> Record {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut u = Vec::with_capacity(n);
    let mut level = 0.0;
    for k in 0..n {
        if k % 2 == 0 {
            level = rng.gen_range(-1.0..1.0);
        }
        u.push(level);
    }
    Record {
        source: format!("wh{seed}"),
        t: (0..n).map(|k| 0.01 * k as f64).collect(),
        outputs: vec![respond(&u)],
        inputs: vec![u],
    }
}

/// The system's output to `u` from rest.
fn respond(u: &[f64]) -> Vec<f64> {
    let (mut x, mut w1, mut w2) = (0.0f64, 0.0, 0.0);
    let mut y = Vec::with_capacity(u.len());
    for &uk in u {
        let v = (1.5 * x).tanh();
        let w = 1.6 * w1 - 0.8 * w2 + 0.2 * v;
        y.push(2.0 + w);
        (w2, w1) = (w1, w);
        x = 0.8 * x + 0.5 * uk;
    }
    y
}

fn names() -> (Vec<String>, Vec<String>) {
    (vec!["u".into()], vec!["y".into()])
}

fn spec(degree: usize) -> ModelSpec {
    ModelSpec {
        kind: Kind::WienerHammerstein,
        na: 3,
        nb: 4,
        nk: 0,
        degree,
        law: Estimator::SimulationError,
        epochs: 50,
        ..Default::default()
    }
}

/// RMS error of the prediction from `first`, over the output's standard deviation.
fn nrmse(r: &Record, pred: &[Vec<f64>], first: usize) -> f64 {
    let y = &r.outputs[0][first..];
    let mean = y.iter().sum::<f64>() / y.len() as f64;
    let sd = (y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / y.len() as f64).sqrt();
    crate::metrics::rms_error(y, &pred[0][first..]) / sd
}

#[test]
fn a_wiener_hammerstein_system_is_found_from_its_best_linear_approximation() {
    let (i, o) = names();
    let train = system(1, 4000);
    let test = system(2, 2000);
    let m = fit(&spec(7), std::slice::from_ref(&train), &i, &o).unwrap();
    m.validate().unwrap();
    let (pred, first) = m.predict(&test, None).unwrap();
    let wh = nrmse(&test, &pred, first);
    let arx = ModelSpec {
        kind: Kind::Arx,
        na: 3,
        nb: 4,
        nk: 0,
        ..Default::default()
    };
    let a = fit(&arx, std::slice::from_ref(&train), &i, &o).unwrap();
    let (pa, fa) = a.predict(&test, None).unwrap();
    let linear = nrmse(&test, &pa, fa);
    // The saturation costs a linear model a tenth of the output's deviation; the block
    // structure, run free on a record it never saw, a small share of that.
    assert!(linear > 0.05, "ARX {linear}");
    assert!(
        wh < 0.2 * linear && wh < 0.02,
        "Wiener-Hammerstein {wh}, ARX {linear}"
    );
    // One step ahead sees G2's measured past: no worse than the free run.
    let (p1, f1) = m.predict(&test, Some(1)).unwrap();
    assert!(
        nrmse(&test, &p1, f1) <= wh * 1.001,
        "{} vs {wh}",
        nrmse(&test, &p1, f1)
    );
    // Stored and read back, the same model.
    let back: Model = serde_json::from_str(&serde_json::to_string(&m).unwrap()).unwrap();
    back.validate().unwrap();
    assert_eq!(back.predict(&test, None).unwrap().0, pred);
}

#[test]
fn a_linear_polynomial_is_the_output_error_model() {
    // Degree 1: G2 G1 c_1 is linear; on a linear system it runs free as well as the
    // best linear approximation it starts from.
    let (i, o) = names();
    let mut train = system(3, 3000);
    let mut lin = train.clone();
    let (mut x, mut w1, mut w2) = (0.0, 0.0, 0.0);
    for (k, &uk) in train.inputs[0].iter().enumerate() {
        let w = 1.6 * w1 - 0.8 * w2 + 0.2 * 1.5 * x;
        lin.outputs[0][k] = w;
        (w2, w1) = (w1, w);
        x = 0.8 * x + 0.5 * uk;
    }
    train = lin;
    let m = fit(&spec(1), std::slice::from_ref(&train), &i, &o).unwrap();
    let (pred, first) = m.predict(&train, None).unwrap();
    assert!(
        nrmse(&train, &pred, first) < 1e-3,
        "{}",
        nrmse(&train, &pred, first)
    );
}

#[test]
fn the_hermite_basis_is_the_normalised_probabilists_polynomials() {
    for x in [-2.5, -0.3, 0.0, 1.0, 3.7] {
        let mut h = [0.0; 4];
        hermite(x, &mut h);
        let he = [x, x * x - 1.0, x.powi(3) - 3.0 * x, x.powi(4) - 6.0 * x * x + 3.0];
        let fact = [1.0f64, 2.0, 6.0, 24.0];
        for n in 0..4 {
            assert!((h[n] - he[n] / fact[n].sqrt()).abs() < 1e-12, "n {} x {x}", n + 1);
        }
    }
}

#[test]
fn the_basis_of_a_block_of_samples_is_each_samples_basis_bit_for_bit() {
    // Across a block boundary (64 samples) and at every degree: the same bits as `hermite`.
    let xs: Vec<f64> = (0..150)
        .map(|k| 4.0 * (k as f64 * 0.37).sin() + 0.01 * k as f64)
        .collect();
    for d in 0..=MAX_DEGREE {
        let mut rows = vec![f64::NAN; xs.len() * d];
        hermite_rows(&xs, d, &mut rows);
        let mut h = vec![0.0; d];
        for (k, &x) in xs.iter().enumerate() {
            hermite(x, &mut h);
            for j in 0..d {
                assert_eq!(
                    rows[k * d + j].to_bits(),
                    h[j].to_bits(),
                    "degree {d}, sample {k}, term {j}"
                );
            }
        }
    }
}

#[test]
fn a_filter_over_several_signals_at_once_gives_each_signals_run_bit_for_bit() {
    let f = Filter {
        b: vec![0.3, -0.2, 0.05],
        a: vec![-1.1, 0.3],
    };
    let (n, d) = (40, 5);
    let u: Vec<f64> = (0..n * d).map(|k| (k as f64 * 0.71).sin()).collect();
    for delay in [0, 2] {
        let mut all = Vec::new();
        f.run_columns(&u, d, delay, &mut all);
        assert_eq!(all.len(), n * d);
        for e in 0..d {
            let one: Vec<f64> = u.chunks(d).map(|r| r[e]).collect();
            let mut out = Vec::new();
            f.run(&one, delay, &mut out);
            for k in 0..n {
                assert_eq!(
                    all[k * d + e].to_bits(),
                    out[k].to_bits(),
                    "delay {delay}, signal {e}, sample {k}"
                );
            }
        }
    }
}

/// G2's free run as `Params::outer` computed it before its taps were walked as slices (a
/// test per tap whether it reaches the record, a call per sample asking whether it is
/// measured): the reference the faster form must give bit for bit.
fn outer_by_tests(
    p: &Params,
    v: &[f64],
    yn: &[f64],
    measured: &dyn Fn(usize) -> bool,
    b: (f64, f64),
) -> Vec<f64> {
    let mut w: Vec<f64> = Vec::with_capacity(v.len());
    for k in 0..v.len() {
        let val = if measured(k) {
            yn[k] - p.bias
        } else {
            let mut s = 0.0;
            for (i, bi) in p.g2.b.iter().enumerate() {
                if k >= i {
                    s += bi * v[k - i];
                }
            }
            for (i, ai) in p.g2.a.iter().enumerate() {
                if k > i {
                    s -= ai * w[k - 1 - i];
                }
            }
            s.max(b.0 - p.bias).min(b.1 - p.bias)
        };
        w.push(val);
    }
    w
}

#[test]
fn g2s_free_run_is_the_tap_by_tap_one_bit_for_bit() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let n = 60;
    let v: Vec<f64> = (0..n).map(|_| rng.gen_range(-2.0..2.0)).collect();
    let yn: Vec<f64> = (0..n).map(|_| rng.gen_range(-1.0..1.0)).collect();
    for (nb, na) in [(1, 0), (3, 2), (1, 4), (6, 6), (0, 1)] {
        let p = Params {
            g1: Filter {
                b: vec![1.0],
                a: vec![],
            },
            c: vec![1.0],
            g2: Filter {
                b: (0..nb).map(|_| rng.gen_range(-0.5..0.5)).collect(),
                a: (0..na).map(|_| rng.gen_range(-0.3..0.3)).collect(),
            },
            bias: 0.1,
            x_range: (f64::NEG_INFINITY, f64::INFINITY),
        };
        // Bounds that clip some samples, and none.
        for b in [(-0.4, 0.5), (-1e9, 1e9)] {
            for measured in [0, 1, 5, n] {
                let fast = p.outer(&v, &yn, measured, b);
                let slow = outer_by_tests(&p, &v, &yn, &|k| k < measured, b);
                let bits = |w: &[f64]| w.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(
                    bits(&fast),
                    bits(&slow),
                    "nb {nb}, na {na}, measured {measured}, {b:?}"
                );
            }
        }
    }
}

#[test]
fn roots_and_polynomials_round_trip_with_complex_pairs_kept_together() {
    // (z - 0.5)(z^2 - 1.2 z + 0.61): a real root and the pair 0.6 +- 0.5 i.
    let c = [2.0, -3.4, 2.42, -0.61];
    let r = roots(&c);
    let g = groups(&r);
    assert_eq!(g.len(), 2);
    assert_eq!(g.iter().map(Vec::len).sum::<usize>(), 3);
    let back = poly(&r);
    for (a, b) in back.iter().zip(c.iter().map(|v| v / c[0])) {
        assert!((a - b).abs() < 1e-9, "{back:?} vs {c:?}");
    }
}

#[test]
fn the_stability_test_agrees_with_the_poles_found_as_roots() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let (mut stable, mut unstable) = (0, 0);
    for _ in 0..2000 {
        let n = rng.gen_range(1..=6);
        let a: Vec<f64> = (0..n).map(|_| rng.gen_range(-1.5..1.5)).collect();
        let mut den = vec![1.0];
        den.extend(&a);
        let radius = roots(&den).iter().fold(0.0f64, |m, r| m.max(r.norm()));
        // Poles within 1e-6 of the circle are left out: the eigenvalues' own rounding.
        if (radius - 1.0).abs() < 1e-6 {
            continue;
        }
        let f = Filter { b: vec![1.0], a };
        assert_eq!(f.is_stable(), radius < 1.0, "{:?}: largest pole {radius}", f.a);
        if radius < 1.0 {
            stable += 1;
        } else {
            unstable += 1;
        }
    }
    // Both sides drawn often enough for the comparison to mean something.
    assert!(
        stable > 200 && unstable > 200,
        "{stable} stable, {unstable} unstable"
    );
}

#[test]
fn an_unstable_start_is_reflected_inside_the_unit_circle() {
    // Poles 1.25 and 0.5: 1.25 moves to 0.8, 0.5 stays.
    let a = [-1.75, 0.625];
    let s = stabilised(&a);
    let mut den = vec![1.0];
    den.extend(&s);
    let mut r: Vec<f64> = roots(&den).iter().map(|r| r.re).collect();
    r.sort_by(f64::total_cmp);
    assert!((r[0] - 0.5).abs() < 1e-9 && (r[1] - 0.8).abs() < 1e-9, "{r:?}");
    // A pole on the circle goes to 0.99; a stable filter is kept bit for bit.
    let s = stabilised(&[-1.0]);
    assert!((s[0] + 0.99).abs() < 1e-12, "{s:?}");
    assert_eq!(stabilised(&[-1.2, 0.35]), vec![-1.2, 0.35]);
}

#[test]
fn a_filter_with_a_pole_outside_the_unit_circle_has_no_residuals() {
    // The free run holds its output in range, so an unstable G2 would otherwise score.
    let spec = spec(1);
    let data = vec![(vec![0.1; 50], vec![0.0; 50])];
    let mut p = Params {
        g1: Filter {
            b: vec![1.0],
            a: vec![-0.5],
        },
        c: vec![1.0],
        g2: Filter {
            b: vec![1.0],
            a: vec![-0.9],
        },
        bias: 0.0,
        x_range: (f64::NEG_INFINITY, f64::INFINITY),
    };
    let inner: Vec<Vec<f64>> = data.iter().map(|(u, _)| p.inner(u, 0)).collect();
    let mut out = Vec::new();
    assert!(residuals(&p, &spec, &data, &inner, (-1.0, 1.0), &mut out));
    p.g2.a = vec![-1.2];
    assert!(!residuals(&p, &spec, &data, &inner, (-1.0, 1.0), &mut out));
    p.g2.a = vec![-0.9];
    p.g1.a = vec![-1.0];
    assert!(!residuals(&p, &spec, &data, &inner, (-1.0, 1.0), &mut out));
}

#[test]
fn stored_parameters_that_do_not_fit_the_layout_are_refused_by_name() {
    let bad_order = [1.5, 1.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.0, -1.0, 1.0];
    let e = Params::from_stored(1, &bad_order).unwrap_err().to_string();
    assert!(
        e.contains("model.weights[0..4]") && e.contains("whole numbers"),
        "{e}"
    );
    let short = [0.0, 1.0, 0.0, 1.0, 1.0];
    let e = Params::from_stored(1, &short).unwrap_err().to_string();
    assert!(e.contains("model.weights") && e.contains("finite numbers"), "{e}");
    let reversed = [0.0, 1.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 2.0, -2.0];
    let e = Params::from_stored(1, &reversed).unwrap_err().to_string();
    assert!(e.contains("low <= high"), "{e}");
    let ok = [0.0, 1.0, 0.0, 1.0, 1.0, 1.0, 1.0, 0.0, -2.0, 2.0];
    assert!(Params::from_stored(1, &ok).is_ok());
}

#[test]
fn two_inputs_are_refused_with_the_reason() {
    let mut r = system(4, 500);
    r.inputs.push(r.inputs[0].iter().map(|v| v * v).collect());
    let e = fit(&spec(3), &[r], &["u".into(), "u2".into()], &["y".into()])
        .unwrap_err()
        .to_string();
    assert!(e.contains("one input and one output"), "{e}");
}

#[test]
fn a_record_longer_than_the_ranking_samples_is_fitted_where_it_goes_beyond_them() {
    // The splits are ranked and first refined on the first 20,000 samples; here the input
    // is 2.5 times as large after them. The polynomial is solved again over every sample
    // before the last refinement, so the samples beyond the first ones' amplitude are fitted
    // too: fitted on the first ones alone, its free run there was 0.89 of the output's
    // deviation (this test's figure is 1e-4).
    let (i, o) = names();
    let mut r = system(3, 24_000);
    let mut quiet = system(4, 20_000);
    for v in &mut quiet.inputs[0] {
        *v *= 0.4;
    }
    let u: Vec<f64> = quiet.inputs[0]
        .iter()
        .chain(&r.inputs[0][20_000..])
        .copied()
        .collect();
    r.outputs[0] = respond(&u);
    r.inputs[0] = u;
    let s = ModelSpec {
        epochs: 10,
        ..spec(15)
    };
    let m = fit(&s, std::slice::from_ref(&r), &i, &o).unwrap();
    let (pred, first) = m.predict(&r, None).unwrap();
    let late = Record {
        source: "late".into(),
        t: r.t[20_000..].to_vec(),
        inputs: vec![r.inputs[0][20_000..].to_vec()],
        outputs: vec![r.outputs[0][20_000..].to_vec()],
    };
    let late_pred = vec![pred[0][20_000..].to_vec()];
    assert!(first < 20_000);
    let e = nrmse(&late, &late_pred, 0);
    assert!(e < 0.01, "free run beyond the first samples' amplitude: {e}");
}
