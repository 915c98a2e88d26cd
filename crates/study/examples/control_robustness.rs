//! The adaptive cascade against the cascade PI with the same sensors, in both of its
//! tunings (`tune_cascade_pi`): the robust one runs beside it in every `control-adaptive`
//! run; the nominal-optimal one runs alone on the same plant, set-points, demand and
//! noise. Plants: `rhonn_study::tuning::robustness_cases` (nominal, solenoid lags of
//! 1, 5 and 20 ms, a one-period delay, the 32 tolerance corners); every controller tuned
//! once, on the nominal plant. `cargo run --release -p rhonn-study --example control_robustness`

use rhonn::experiment::{preset, run_full, NoRecorder, Regulation, NOMINAL_OPTIMAL};
use rhonn_study::tuning::{robustness_cases, with_cascade_pi};

fn overshoot(r: &Regulation) -> f64 {
    r.overshoot_percent.iter().fold(0.0f64, |a, &b| a.max(b))
}

fn main() -> Result<(), rhonn::Error> {
    println!("| plant | IAE adaptive | IAE cascade PI nominal-optimal | IAE cascade PI robust | within 1 % adaptive / nom.-opt. / robust | largest overshoot adaptive / nom.-opt. / robust | below P_min after 1 s adaptive / nom.-opt. / robust |");
    println!("|---|---|---|---|---|---|---|");
    let (mut beats_opt, mut beats_robust, mut n) = (0, 0, 0);
    for (name, spec) in robustness_cases(&preset::load_any("control-adaptive")?)? {
        let out = run_full(&spec.pump_run()?, &mut NoRecorder)?;
        let fa = &out.summary.figures;
        let c = out.summary.control.as_ref().expect("an adaptive run");
        let fr = &c.baseline.figures;
        let opt = with_cascade_pi(&spec, NOMINAL_OPTIMAL).pump_run()?;
        let fo = run_full(&opt, &mut NoRecorder)?.summary.figures;
        let [ra, ro, rr] = [fa, &fo, fr].map(|f| f.regulation.clone().expect("a regulated run"));
        beats_opt += (ra.iae_mpa_s < ro.iae_mpa_s) as usize;
        beats_robust += (ra.iae_mpa_s < rr.iae_mpa_s) as usize;
        n += 1;
        println!(
            "| {name} | {:.1} | {:.1} | {:.1} | {:.0} / {:.0} / {:.0} % | {:.0} / {:.0} / {:.0} % | {:.2} / {:.2} / {:.2} s |",
            ra.iae_mpa_s,
            ro.iae_mpa_s,
            rr.iae_mpa_s,
            ra.within_1pct_percent,
            ro.within_1pct_percent,
            rr.within_1pct_percent,
            overshoot(&ra),
            overshoot(&ro),
            overshoot(&rr),
            fa.time_below_p_min_after_1s_s,
            fo.time_below_p_min_after_1s_s,
            fr.time_below_p_min_after_1s_s,
        );
    }
    println!();
    println!("adaptive IAE lower than the nominal-optimal cascade PI on {beats_opt} of {n} plants, than the robust one on {beats_robust} of {n}");
    Ok(())
}
