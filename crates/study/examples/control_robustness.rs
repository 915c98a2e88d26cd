//! The adaptive cascade against the cascade PI with the same sensors, in both of its
//! tunings (`tune_cascade_pi`): the robust one runs beside it in every `control-adaptive`
//! run; the nominal-optimal one runs alone on the same plant, set-points, demand and
//! noise. Plants: `rhonn_study::tuning::robustness_cases` (nominal, solenoid lags of
//! 1, 5 and 20 ms, a one-period delay, the 32 tolerance corners); every controller tuned
//! once, on the nominal plant. `cargo run --release -p rhonn-study --example control_robustness`

use rhonn::experiment::{preset, LoopFigures, NOMINAL_OPTIMAL};
use rhonn_study::tuning::{robustness_cases, with_cascade_pi};

fn overshoot(r: &LoopFigures) -> f64 {
    r.overshoot_percent.iter().fold(0.0f64, |a, &b| a.max(b))
}

fn main() -> Result<(), rhonn::Error> {
    println!("| plant | IAE adaptive | IAE cascade PI nominal-optimal | IAE cascade PI robust | within 1 % adaptive / nom.-opt. / robust | largest overshoot adaptive / nom.-opt. / robust | below P_min after 1 s adaptive / nom.-opt. / robust |");
    println!("|---|---|---|---|---|---|---|");
    let (mut beats_opt, mut beats_robust, mut n) = (0, 0, 0);
    for (name, spec) in robustness_cases(&preset::load_any("control-adaptive")?)? {
        let c = spec.run_summary()?.control.expect("a loop");
        let (ra, rr) = (&c[0], &c[1]);
        let opt = with_cascade_pi(&spec, NOMINAL_OPTIMAL)
            .run_summary()?
            .control
            .expect("a loop");
        let ro = &opt[0];
        beats_opt += (ra.iae < ro.iae) as usize;
        beats_robust += (ra.iae < rr.iae) as usize;
        n += 1;
        let below = |r: &LoopFigures| r.time_below_floor_after_settle_s.unwrap_or(f64::NAN);
        println!(
            "| {name} | {:.1} | {:.1} | {:.1} | {:.0} / {:.0} / {:.0} % | {:.0} / {:.0} / {:.0} % | {:.2} / {:.2} / {:.2} s |",
            ra.iae,
            ro.iae,
            rr.iae,
            ra.within_1pct_percent,
            ro.within_1pct_percent,
            rr.within_1pct_percent,
            overshoot(ra),
            overshoot(ro),
            overshoot(rr),
            below(ra),
            below(ro),
            below(rr),
        );
    }
    println!();
    println!("adaptive IAE lower than the nominal-optimal cascade PI on {beats_opt} of {n} plants, than the robust one on {beats_robust} of {n}");
    Ok(())
}
