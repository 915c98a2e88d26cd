//! Tests of the `cascade` structure: the chain, its activation, settling, the stored
//! parameters.

use super::*;
use rhonn_ode::System;

#[test]
fn the_chain_holds_a_full_neuron_and_passes_its_share_of_the_overflow_on() {
    let p = Params {
        b: vec![1.0],
        k: vec![0.1, 0.1],
        alpha: vec![0.5, 0.5],
        g: vec![0.1],
        o: vec![0.4],
        xmax: vec![1.0, 100.0],
        c: 0.0,
    };
    let u = vec![vec![1.0; 20]];
    let mut out = Vec::new();
    simulate(&p, &u, &[0.5], 0.0, 20, &mut out).unwrap();
    // After the first neuron fills (within a sample: inflow 1 vs outflow <= 0.1),
    // the second gets g s_1 + 0.4 (1 - k_1 s_1) - k_2 s_2 = 0.1 + 0.36 - 0.1 s_2.
    let mut x2 = out[1];
    for k in 2..20 {
        let mut ref_x = x2;
        let h = 1e-3;
        for _ in 0..1000 {
            ref_x += h * (0.1 + 0.4 * 0.9 - 0.1 * ref_x.sqrt());
        }
        assert!((out[k] - ref_x).abs() < 1e-4, "sample {k}: {} vs {ref_x}", out[k]);
        x2 = out[k];
    }
    // Without the overflow share the second neuron rises more slowly.
    let q = Params { o: vec![0.0], ..p };
    let mut out0 = Vec::new();
    simulate(&q, &u, &[0.5], 0.0, 20, &mut out0).unwrap();
    assert!(out0[19] < out[19] - 1.0, "{} vs {}", out0[19], out[19]);
}

#[test]
fn the_solvers_right_hand_side_reuses_activations_bit_for_bit() {
    let p = Params {
        b: vec![1.0],
        k: vec![0.3, 0.2],
        alpha: vec![0.55, 1.3],
        g: vec![0.25],
        o: vec![0.4],
        xmax: vec![2.0, 3.0],
        c: 0.0,
    };
    let u = vec![vec![0.7; 4]];
    let mut sys = Chain::new(&p, &u);
    sys.update_modes(0.5, &[0.0, 0.0]);
    // Fresh levels, the same again, one level kept, both below the linear piece, at 0,
    // at a bound, and a NaN: each as `derivative` gives it.
    for x in [
        [0.8, 1.7],
        [0.8, 1.7],
        [0.8, 2.9],
        [5e-4, 2.9],
        [0.0, 0.0],
        [2.0, 3.0],
        [f64::NAN, 1.0],
        [0.8, 1.7],
    ] {
        let (mut a, mut b) = ([0.0; 2], [0.0; 2]);
        sys.rhs(0.5, &x, &mut a);
        derivative(&p, sys.inflow, &x, &mut b);
        assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits), "{x:?}");
    }
}

#[test]
fn stored_parameters_round_trip_through_the_coordinates() {
    let co = Coords {
        n: 3,
        ni: 2,
        free_exp: true,
    };
    let p = Params {
        b: vec![0.1, 0.2],
        k: vec![0.3, 0.4, 0.5],
        alpha: vec![0.3, 0.5, 1.2],
        g: vec![0.6, 0.7],
        o: vec![0.8, 0.05],
        xmax: vec![2.0, 3.0, 4.0],
        c: -1.5,
    };
    let back = co.params(&co.coords(&p));
    for (a, b) in back.stored().iter().zip(p.stored()) {
        assert!((a - b).abs() < 1e-12 * b.abs().max(1.0));
    }
    assert_eq!(Params::from_stored(3, 2, &p.stored()), p);
    assert_eq!(n_params(3, 2), p.stored().len());
}

#[test]
fn settling_finds_the_hidden_initial_level() {
    let p = Params {
        b: vec![0.05],
        k: vec![0.1, 0.08],
        alpha: vec![0.5, 0.5],
        g: vec![0.1],
        o: vec![0.5],
        xmax: vec![5.0, 5.0],
        c: -1.0,
    };
    let u = vec![vec![1.0; 30]];
    for h in [0.3, 1.7, 4.2] {
        let mut y = Vec::new();
        simulate(&p, &u, &[h], 0.5, 30, &mut y).unwrap();
        let got = settle_hidden(&p, &u, &y, 8);
        assert!((got[0] - h).abs() < 1e-3, "{} vs {h}", got[0]);
    }
}

#[test]
fn the_activation_is_the_power_to_a_few_units_in_the_last_place() {
    // Levels from the linear piece's edge to far above the output's range, every exponent
    // of the learned range.
    let mut worst: f64 = 0.0;
    for i in 0..=400 {
        let x = LINEAR_BELOW * 10f64.powf(i as f64 * 7.0 / 400.0);
        for j in 0..=26 {
            let a = EXPONENT_RANGE.0 + (EXPONENT_RANGE.1 - EXPONENT_RANGE.0) * j as f64 / 26.0;
            let rel = (activation(x, a) - x.powf(a)).abs() / x.powf(a);
            worst = worst.max(rel);
        }
    }
    assert!(worst < 16.0 * f64::EPSILON, "{worst:e}");
    assert!(worst > 0.0, "the power itself: this test would not see a change");
    // Continuous at the linear piece's edge, 0 at and below 0.
    let a = 0.5;
    assert!((activation(LINEAR_BELOW, a) - activation(LINEAR_BELOW * (1.0 - 1e-12), a)).abs() < 1e-12);
    assert_eq!(activation(0.0, a), 0.0);
    assert_eq!(activation(-1.0, a), 0.0);
}
