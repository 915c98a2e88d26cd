//! The cascade PI baseline's two tunings, found by one reproducible search
//! (`rhonn_study::tuning`: criteria and why simulation):
//! `cargo run --release -p rhonn-study --example tune_cascade_pi` (about 3 minutes on 2 cores).
//!
//! * **nominal-optimal**: the lowest nominal IAE with every step's overshoot at most 10 %;
//! * **robust**: the lowest nominal IAE with that overshoot limit that still regulates
//!   with doubled gains, a 5 ms solenoid lag and a one-period delay, and keeps a 6 dB gain
//!   margin and a 45 degree phase margin, measured on the simulated pump, at 5, 10 and
//!   15 MPa with no demand and with 1.8 dm^3/s (`tuning::worst_margins`).
//!
//! `--margins`: instead of the search, the gain and phase margins of both shipped tunings
//! at each operating point (`tuning::margins`: sine injection at the current).
//! `--sensitivity`: their peak sensitivity M_s at each point with 2.5, 5 and 10 mA of
//! injection (`tuning::sensitivity_peak`), and the margins the worst M_s guarantees.
//! `--probe KP,TI,B,G`: both for any gain set (mm/MPa, s, -, -).

use rhonn::experiment::{preset, CascadePiGainsMpa, NOMINAL_OPTIMAL, ROBUST};
use rhonn_study::tuning::{full_grid, margins, margins_of_peak, search, sensitivity_peak, TuningScore};

/// The worst gain and phase margins over the operating points (5, 10, 15 MPa; no demand
/// and 1.8 dm^3/s), measured on the simulated pump (`tuning::margins`).
fn show_margins(what: &str, g: CascadePiGainsMpa) -> Result<(), rhonn::Error> {
    let (mut gm, mut pm) = (f64::INFINITY, f64::INFINITY);
    for p in [5.0, 10.0, 15.0] {
        for q in [0.0, 1.8] {
            let (a, b) = margins(g, p, q)?;
            println!(
                "  {what} at {p} MPa, {q} dm^3/s: gain margin {:.1} dB, phase margin {b:.0} deg",
                20.0 * a.log10()
            );
            gm = gm.min(a);
            pm = pm.min(b);
        }
    }
    println!(
        "  {what}: worst gain margin {:.1} dB, worst phase margin {pm:.0} deg",
        20.0 * gm.log10()
    );
    Ok(())
}

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
    if let Some(m) = s.margins {
        println!(
            "  margins (worst of 5, 10, 15 MPa x 0, 1.8 dm^3/s): gain {:.1} dB, phase {:.1} deg{}",
            20.0 * m.gain.log10(),
            m.phase_deg,
            if m.measurable {
                ""
            } else {
                " (not measurable at every point)"
            }
        );
    }
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

/// The peak sensitivity M_s at each operating point for three injection amplitudes
/// (`tuning::sensitivity_peak`), and the margins the worst one guarantees.
fn show_sensitivity(what: &str, g: CascadePiGainsMpa) -> Result<(), rhonn::Error> {
    let mut worst: f64 = 0.0;
    for p in [5.0, 10.0, 15.0] {
        for q in [0.0, 1.8] {
            let mut line = format!("  {what} at {p} MPa, {q} dm^3/s: M_s");
            for a in [0.0025, 0.005, 0.01] {
                let (ms, w) = sensitivity_peak(g, p, q, 32, a)?;
                line += &format!("  {ms:.3} at {w:.0} rad/s ({:.1} mA)", a * 1e3);
                worst = worst.max(ms);
            }
            println!("{line}");
        }
    }
    let (gm, pm) = margins_of_peak(worst);
    println!(
        "  {what}: worst M_s {worst:.3}: gain margin >= {:.1} dB, phase margin >= {pm:.1} deg",
        20.0 * gm.log10()
    );
    Ok(())
}

fn main() -> Result<(), rhonn::Error> {
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "--probe") {
        let v: Vec<f64> = args
            .get(i + 1)
            .map(|s| s.split(',').filter_map(|x| x.trim().parse().ok()).collect())
            .unwrap_or_default();
        let [kp_mm_per_mpa, ti_s, setpoint_weight, stroke_gain] = v[..] else {
            eprintln!("--probe takes KP,TI,B,G: four numbers (mm/MPa, s, -, -)");
            std::process::exit(2);
        };
        let g = CascadePiGainsMpa {
            kp_mm_per_mpa,
            ti_s,
            setpoint_weight,
            stroke_gain,
        };
        show_margins("probe", g)?;
        return show_sensitivity("probe", g);
    }
    if std::env::args().any(|a| a == "--sensitivity") {
        show_sensitivity("nominal-optimal", NOMINAL_OPTIMAL)?;
        return show_sensitivity("robust", ROBUST);
    }
    if std::env::args().any(|a| a == "--margins") {
        show_margins("nominal-optimal", NOMINAL_OPTIMAL)?;
        return show_margins("robust", ROBUST);
    }
    let spec = preset::load_any("control-adaptive")?;
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
