//! The block structure's online engine: its free run against `rhonn fit`'s, its stored
//! weights, its refits.

use super::*;

/// A spec of the structure and a fresh engine of it (one input, one output, unscaled).
fn engine(poles: usize, degree: usize, iterations: usize, window: usize) -> (OnlineSpec, BlockOnline) {
    let spec = OnlineSpec {
        structure: crate::online_spec::OnlineStructure::WienerHammerstein,
        block: Some(BlockOnlineSpec {
            poles,
            degree,
            iterations,
            window,
            ..Default::default()
        }),
        ..OnlineSpec::default()
    };
    let e = BlockOnline::new(&spec, 1, 1, Scaling::identity(1, 1)).unwrap();
    (spec, e)
}

/// A fitted structure run sample by sample, frozen and free, gives `rhonn fit`'s own
/// free run of the same parameters.
#[test]
fn frozen_free_run_is_the_offline_free_run() {
    let r = rhonn_sysid::benchmarks::wiener_hammerstein(3, 1500);
    let (_, mut e) = engine(4, 5, 10, 1000);
    for k in 0..1000 {
        e.update(r.t[k], &[r.inputs[0][k]], &[r.outputs[0][k]]).unwrap();
    }
    let f = e.fitted.clone().expect("fitted at the window's end");
    let [mu, su, my, sy] = f.norm;
    let un: Vec<f64> = r.inputs[0][1000..].iter().map(|v| (v - mu) / su).collect();
    let yn: Vec<f64> = r.outputs[0][1000..].iter().map(|v| (v - my) / sy).collect();
    let ms = ModelSpec {
        kind: Kind::WienerHammerstein,
        nk: 0,
        ..Default::default()
    };
    let offline = crate::models::wiener_hammerstein::free_run(&f.p, &ms, &un, &yn, f.bounds);
    e.freeze(true);
    e.set_free_run(true);
    e.reset();
    for k in 1000..1500 {
        let est = e.update(r.t[k], &[r.inputs[0][k]], &[r.outputs[0][k]]).unwrap()[0];
        let want = offline[k - 1000] * sy + my;
        assert!(
            (est - want).abs() <= 1e-9 * (1.0 + want.abs()),
            "sample {k}: {est} against {want}"
        );
    }
}

/// Stored weights are read back only when they are a fitted structure: an engine
/// that never reached its window, or orders beyond the spec's poles, are refused with
/// the reason; a fitted one round-trips exactly.
#[test]
fn stored_weights_round_trip_and_bad_ones_are_refused() {
    let r = rhonn_sysid::benchmarks::wiener_hammerstein(5, 800);
    let (spec, mut e) = engine(2, 3, 5, 500);
    assert!(e.unfinished().unwrap().contains("window of 500 samples"));
    let never = e.weights();
    let err = e.check_weights(&never).unwrap_err().to_string();
    assert!(err.contains("never fitted"), "{err}");
    for k in 0..800 {
        e.update(r.t[k], &[r.inputs[0][k]], &[r.outputs[0][k]]).unwrap();
    }
    assert!(e.unfinished().is_none() && e.window.is_empty());
    let w = e.weights();
    assert_eq!(w[0].len(), e.n_terms());
    assert_eq!(e.term_names(&[], &[]).len(), e.n_terms());
    let mut back = BlockOnline::new(&spec, 1, 1, Scaling::identity(1, 1)).unwrap();
    back.check_weights(&w).unwrap();
    back.set_weights(&w);
    assert_eq!(back.weights(), w);
    let mut big = w.clone();
    big[0][HEADER] = 3.0;
    let err = e.check_weights(&big).unwrap_err().to_string();
    assert!(err.contains("orders") && err.contains("[2, 3, 2, 3]"), "{err}");
}

/// `rhonn fit`'s block structure fitted on `r`'s samples `from..to` as the engine fits
/// its window (`BlockOnline::fit`'s spec).
fn offline_fit(e: &BlockOnline, r: &Record, from: usize, to: usize) -> Params {
    let spec = e.window_spec();
    let part = Record {
        source: "part".into(),
        t: r.t[from..to].to_vec(),
        inputs: vec![r.inputs[0][from..to].to_vec()],
        outputs: vec![r.outputs[0][from..to].to_vec()],
    };
    let names = |s: &str| vec![s.to_string()];
    let m = rhonn_sysid::fit(&spec, &[part], &names("u"), &names("y")).unwrap();
    Params::from_stored(e.set.degree, &m.weights[0]).unwrap()
}

/// With `refits = 1` the structure is fitted on its first window, then from scratch on
/// the next: its filters are then `rhonn fit`'s on the second window's samples alone,
/// bit for bit, and it collects nothing more (its memory is one window at most). Without
/// refits the filters stay the first window's.
#[test]
fn a_refit_is_the_fit_of_the_next_window_and_then_collecting_stops() {
    let r = rhonn_sysid::benchmarks::wiener_hammerstein(7, 1500);
    let run = |refits: usize, upto: usize| {
        let (_, mut e) = engine(2, 3, 5, 500);
        e.set.refits = refits;
        for k in 0..upto {
            e.update(r.t[k], &[r.inputs[0][k]], &[r.outputs[0][k]]).unwrap();
        }
        e
    };
    let filters = |p: &Params| (p.g1.clone(), p.g2.clone());
    let first = offline_fit(&run(0, 0), &r, 0, 500);
    let second = offline_fit(&run(0, 0), &r, 500, 1000);
    assert_ne!(filters(&first), filters(&second));
    let kept = run(0, 1000);
    assert_eq!(filters(&kept.fitted.unwrap().p), filters(&first));
    assert!(kept.window.is_empty());
    let refitted = run(1, 1000);
    let p = &refitted.fitted.as_ref().unwrap().p;
    assert_eq!(filters(p), filters(&second));
    assert_eq!(
        p.c, second.c,
        "the polynomial as fitted: no sample learned after the refit yet"
    );
    assert_eq!((refitted.refitted, refitted.kept), (1, 0));
    let later = run(1, 1500);
    assert_eq!(filters(&later.fitted.unwrap().p), filters(&second));
    assert!(
        later.window.is_empty() && later.kept == 0,
        "nothing collected after the last refit"
    );
}

/// A refit whose window holds no record long enough for the structure (here records of 3
/// samples, against the 8 its lags need) keeps the last fit and the stream goes on.
#[test]
fn a_refit_that_cannot_be_made_keeps_the_last_fit() {
    let r = rhonn_sysid::benchmarks::wiener_hammerstein(9, 1100);
    let (_, mut e) = engine(2, 3, 5, 500);
    e.set.refits = 1;
    for k in 0..500 {
        e.update(r.t[k], &[r.inputs[0][k]], &[r.outputs[0][k]]).unwrap();
    }
    let before = e.fitted.clone().unwrap().p;
    for k in 500..1100 {
        if k % 3 == 2 {
            e.reset();
        }
        e.update(r.t[k], &[r.inputs[0][k]], &[r.outputs[0][k]]).unwrap();
    }
    let after = e.fitted.clone().unwrap().p;
    assert_eq!((after.g1, after.g2), (before.g1, before.g2));
    assert_eq!(e.refitted, 1);
    assert!(e.window.is_empty());
}

/// A frozen free run reads `rhonn fit`'s settling samples, and says so: a start-up
/// window (`data::within_window`) gives the block structure as many measured outputs as
/// the offline model of the same parameters.
#[test]
fn a_free_run_reads_the_fits_settling_samples() {
    let (spec, _) = engine(2, 3, 5, 500);
    assert_eq!(
        crate::outputs_read_in_free_run(&spec),
        ModelSpec::default().settle
    );
    assert_eq!(settle(), 5);
}
