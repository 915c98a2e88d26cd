//! The cascade PI baseline's two tunings, found by one reproducible search
//! (`rhonn::experiment::tuning`: criteria and why simulation):
//! `cargo run --release -p rhonn --example tune_cascade_pi` (about 3 minutes on 2 cores).
//!
//! * **nominal-optimal**: the lowest nominal IAE with every step's overshoot at most 10 %;
//! * **robust**: the lowest nominal IAE with that overshoot limit that still regulates
//!   with doubled gains (6 dB), a 5 ms solenoid lag and a one-period delay.

use rhonn::experiment::preset;
use rhonn::experiment::tuning::{full_grid, search, TuningScore};

fn show(what: &str, s: &TuningScore) {
    let (g, n) = (s.gains, s.nominal);
    println!(
        "{what}: kp_mm_per_mpa = {}, ti_s = {}, setpoint_weight = {}, stroke_gain = {}",
        g.kp_mm_per_mpa, g.ti_s, g.setpoint_weight, g.stroke_gain
    );
    println!(
        "  nominal: IAE {:.2} MPa s, largest overshoot {:.1} %, within 1 % for {:.1} % of the run",
        n.iae_mpa_s, n.overshoot_percent, n.within_1pct_percent
    );
    for (name, r) in [
        ("gains doubled", s.doubled),
        ("solenoid lag 5 ms", s.lag_5ms),
        ("delay 1 period", s.delay_1),
    ] {
        println!(
            "  {name}: IAE {:.2} MPa s, within 1 % {:.1} % ({})",
            r.iae_mpa_s,
            r.within_1pct_percent,
            if r.holds(&n) { "holds" } else { "does not hold" }
        );
    }
}

fn main() -> Result<(), rhonn::Error> {
    let spec = preset::load("control-adaptive")?;
    let grid = full_grid();
    let (_, optimal, robust) = search(&spec, &grid);
    println!(
        "{} gain sets on the nominal control-adaptive run (60 s)",
        grid.len()
    );
    match optimal {
        Some(s) => show("nominal-optimal", &s),
        None => println!("nominal-optimal: no gain set keeps every overshoot within 10 %"),
    }
    match robust {
        Some(s) => show("robust", &s),
        None => println!("robust: no gain set holds with doubled gains, a 5 ms lag and a one-period delay"),
    }
    Ok(())
}
