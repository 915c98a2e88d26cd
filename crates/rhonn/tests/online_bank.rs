//! The online selection's bank (`rhonn::ident::bank`): it ranks candidates by their
//! prequential error, picks a nonlinear model where the data are nonlinear and a linear
//! one where they are linear, and every candidate stays bounded over ten noisy passes.

use rand::{Rng, SeedableRng};
use rhonn::data::Record;
use rhonn::ident::bank::{default_candidates, select};
use rhonn::ident::{identify_records, predict_records, OnlineSpec};

/// `y[k+1] = a y + b u + c u tanh(2 y)` under seeded random steps, with measurement noise.
fn record(n: usize, seed: u64, c: f64, noise: f64) -> Record {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let (mut y, mut u) = (0.0_f64, 0.0);
    let (mut t, mut us, mut ys) = (vec![], vec![], vec![]);
    for k in 0..n {
        if k % 9 == 0 {
            u = rng.gen_range(-2.0..2.0);
        }
        t.push(k as f64 * 0.1);
        us.push(u);
        ys.push(y + noise * rng.gen_range(-1.0..1.0));
        y = 0.8 * y + 0.3 * u + c * u * (2.0 * y).tanh();
    }
    Record {
        source: format!("sim{seed}.csv"),
        t,
        inputs: vec![us],
        outputs: vec![ys],
    }
}

fn free_run_rms(spec: &OnlineSpec, train: &Record, test: &Record) -> f64 {
    let out = vec!["y".to_string()];
    let run = identify_records(spec, std::slice::from_ref(train), &out).unwrap();
    let mut id = run.identifier.clone();
    let p = predict_records(&mut id, std::slice::from_ref(test), None).unwrap();
    let e: Vec<f64> = (0..test.len()).map(|k| test.outputs[0][k] - p[0][k][0]).collect();
    (e.iter().map(|x| x * x).sum::<f64>() / e.len() as f64).sqrt()
}

#[test]
fn a_nonlinear_system_gets_a_nonlinear_winner_that_runs_free_better_than_the_recursive_arx() {
    let (train, test) = (record(3000, 1, 0.4, 0.01), record(1500, 2, 0.4, 0.0));
    let out = vec!["y".to_string()];
    let sel = select(
        default_candidates(1, train.len()),
        std::slice::from_ref(&train),
        &out,
    )
    .unwrap();
    let chosen = &sel.candidates[sel.chosen];
    assert!(!chosen.name.starts_with("recursive ARX"), "{}", chosen.name);
    // Every candidate has its prequential figures (or says why not), and its final check
    // (frozen as it ended, run free over the stream's second half): one worse than the
    // mean is ruled out, and the winner is not.
    for c in &sel.candidates {
        assert!(c.free_run_nrmse.is_some() || c.failed.is_some(), "{}", c.name);
        if c.failed.is_none() {
            let f = c.final_free_run_nrmse.unwrap_or(f64::INFINITY);
            assert_eq!(c.ruled_out.is_some(), f >= 1.0, "{c:?}");
        }
    }
    assert_eq!(sel.checked, 1500);
    assert!(chosen.ruled_out.is_none() && sel.warnings.is_empty(), "{sel:?}");
    let arx = &sel.candidates[sel.best_arx.unwrap()];
    assert!(chosen.free_run_nrmse.unwrap() < arx.free_run_nrmse.unwrap());
    // Frozen and run free on a record it never saw, the winner beats the best recursive
    // ARX trained the same way.
    let (w, a) = (
        free_run_rms(&chosen.spec, &train, &test),
        free_run_rms(&arx.spec, &train, &test),
    );
    assert!(w < 0.7 * a, "winner {w}, recursive ARX {a}");
    assert!(sel
        .findings()
        .iter()
        .any(|f| f.contains("lower prequential free-run error than the best recursive ARX")));
}

#[test]
fn a_linear_system_gets_a_linear_winner_or_one_as_good() {
    let train = record(3000, 3, 0.0, 0.01);
    let out = vec!["y".to_string()];
    let sel = select(
        default_candidates(1, train.len()),
        std::slice::from_ref(&train),
        &out,
    )
    .unwrap();
    let w = sel.candidates[sel.chosen].free_run_nrmse.unwrap();
    let a = sel.candidates[sel.best_arx.unwrap()].free_run_nrmse.unwrap();
    assert!(w <= a);
    assert!(a < 0.05, "the recursive ARX fits a linear system: {a}");
}

#[test]
fn every_candidate_stays_bounded_over_ten_noisy_passes() {
    let train = record(1200, 5, 0.4, 0.05);
    let out = vec!["y".to_string()];
    for c in default_candidates(1, train.len()) {
        let spec = OnlineSpec {
            epochs: 10,
            ..c.spec.clone()
        };
        let run = identify_records(&spec, std::slice::from_ref(&train), &out).unwrap();
        let peaks: Vec<f64> = run.max_norm_per_pass.iter().map(|p| p[0]).collect();
        assert!(peaks.iter().all(|p| p.is_finite()), "{}: {peaks:?}", c.name);
        // The peak norm settles: least squares over repeated records tends to the
        // least-squares solution of the stacked data (regularised by P(0) = p0 I), so its
        // increase per pass shrinks; the other laws hold a bound of their own. The last
        // increase is under half the largest of the first passes', and each of the last
        // three is no larger than the one before.
        let inc: Vec<f64> = peaks.windows(2).map(|w| (w[1] - w[0]).max(0.0)).collect();
        let early = inc[..4].iter().copied().fold(0.0, f64::max);
        assert!(inc[8] <= 0.5 * early + 1e-9 * peaks[9], "{}: {peaks:?}", c.name);
        assert!(
            inc[6] >= inc[7] - 1e-9 && inc[7] >= inc[8] - 1e-9,
            "{}: {peaks:?}",
            c.name
        );
    }
}

/// Many short records (as a robot's 66 runs of 605 samples): the free-run windows are
/// sized by the records, not by the whole stream, whose tenth would fit in none of them
/// (every candidate then failed), so the bank scores its candidates and chooses one.
#[test]
fn many_short_records_get_windows_that_fit_in_them() {
    let recs: Vec<Record> = (0..30).map(|s| record(200, 100 + s, 0.4, 0.01)).collect();
    let out = vec!["y".to_string()];
    let total: usize = recs.iter().map(Record::len).sum();
    assert!(rhonn::ident::bank::window_for(total) > 200);
    let sel = select(default_candidates(1, total), &recs, &out).unwrap();
    assert_eq!(sel.window, 100, "{sel:?}");
    let chosen = &sel.candidates[sel.chosen];
    assert!(
        chosen.failed.is_none() && chosen.free_run_nrmse.is_some(),
        "{chosen:?}"
    );
    let scored = sel
        .candidates
        .iter()
        .filter(|c| c.free_run_nrmse.is_some())
        .count();
    assert!(
        scored * 2 > sel.candidates.len(),
        "{scored} of {} scored",
        sel.candidates.len()
    );
    // One long record keeps the tenth of the stream.
    assert_eq!(
        rhonn::ident::bank::BankSettings::for_records(&[total]).window,
        rhonn::ident::bank::window_for(total)
    );
}

#[test]
fn a_record_too_short_for_a_window_or_a_constant_output_is_a_clear_error() {
    let mut r = record(100, 6, 0.4, 0.0);
    let out = vec!["y".to_string()];
    r.outputs[0].iter_mut().for_each(|v| *v = 1.0);
    let e = select(default_candidates(1, r.len()), std::slice::from_ref(&r), &out)
        .unwrap_err()
        .to_string();
    assert!(e.contains("output `y`") && e.contains("constant"), "{e}");
}

/// The bank fed one sample at a time (`OnlineBank`, Python's `OnlineIdentifier()`)
/// gives the figures and the winner the bank over recordings gives (`rhonn identify`),
/// on two records; and `rhonn identify`'s retraining of the winner for one pass, with
/// the bank's warm-up, is the very model the bank ran.
#[test]
fn the_bank_in_a_loop_gives_the_figures_of_the_bank_over_recordings() {
    use rhonn::ident::bank::{select_with, BankSettings, OnlineBank};
    let recs = vec![record(900, 5, 0.4, 0.01), record(700, 6, 0.4, 0.01)];
    let out = vec!["y".to_string()];
    let settings = BankSettings::for_stream(1600);
    let cands = default_candidates(1, 1600);
    let (batch, winner) = select_with(cands.clone(), &recs, &out, settings).unwrap();
    // The sample time as the command measures it from `t` (the continuous-time
    // candidates integrate over it).
    let dt = rhonn::ident::sample_time(&recs).unwrap();
    let mut bank = OnlineBank::new(cands, 1, 1, dt, settings).unwrap();
    let mut last = Vec::new();
    for r in &recs {
        bank.reset();
        for k in 0..r.len() {
            last = bank
                .update(r.t[k], &[r.inputs[0][k]], &[r.outputs[0][k]])
                .unwrap()
                .to_vec();
        }
    }
    let (streamed, id) = bank.selection().unwrap();
    assert_eq!(streamed, batch);
    assert_eq!(id.weights(), winner.weights());
    // The loop's estimates are the leader's: finite, and the last one close to the
    // measurement it predicted.
    let y_last = *recs[1].outputs[0].last().unwrap();
    assert!((last[0] - y_last).abs() < 0.5, "{last:?} {y_last}");
    // One pass of the winner, retrained with the bank's warm-up: the same weights.
    let spec = OnlineSpec {
        epochs: 1,
        ..batch.chosen_spec().clone()
    };
    let run = rhonn::ident::identify_records_scaled(&spec, &recs, &out, Some(settings.warmup)).unwrap();
    assert_eq!(run.identifier.weights(), winner.weights());
    assert_eq!(run.identifier.scaling(), winner.scaling());
}

/// An online identifier's scaling comes from the warm-up window alone: changing every
/// sample after it changes neither the offsets nor the scales, and its bounds cover the
/// range of the samples it learned from (widened by the margin), not more.
#[test]
fn warm_up_scaling_uses_nothing_after_the_window() {
    use rhonn::ident::WarmUp;
    let a = record(1000, 7, 0.4, 0.01);
    let mut b = a.clone();
    for v in &mut b.outputs[0][500..] {
        *v = 3.0 * *v + 10.0;
    }
    let (wa, wb) = (
        WarmUp::of_records(std::slice::from_ref(&a), 500),
        WarmUp::of_records(std::slice::from_ref(&b), 500),
    );
    assert_eq!(wa, wb);
    let spec = OnlineSpec::default();
    let out = vec!["y".to_string()];
    let run =
        rhonn::ident::identify_records_scaled(&spec, std::slice::from_ref(&b), &out, Some(500)).unwrap();
    let (lo, hi) = b.outputs[0]
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(*v), h.max(*v))
        });
    let m = spec.output_margin * (hi - lo);
    let got = run.identifier.scaling().y_bounds.clone().unwrap()[0];
    assert!(
        (got[0] - (lo - m)).abs() < 1e-9 && (got[1] - (hi + m)).abs() < 1e-9,
        "{got:?}"
    );
    assert_eq!(run.identifier.scaling().y_offset, wa.scaling.y_offset);
}
