//! Identify the pump as the thesis does and print the figures:
//! `cargo run --release -p rhonn --example identify_pump`.

use rhonn::experiment::{preset, run_full, Trace};

fn main() -> Result<(), rhonn::Error> {
    let scenario = preset::load("thesis-ch5")?.check()?;
    let mut trace = Trace::default();
    let out = run_full(&scenario, &mut trace)?;
    let id = out
        .summary
        .identification
        .as_ref()
        .expect("an identified scenario");
    for (mode, figs) in [
        ("training", &id.training),
        ("series-parallel", &id.series_parallel),
        ("parallel", &id.parallel),
    ] {
        for f in figs {
            println!(
                "{mode:>16} {:>7}: rms {:.4e} {}, fit {:7.2} %, converged at {:?} s, |w| {:.4e}",
                f.state, f.rms_error, f.unit, f.fit_percent, f.convergence_time_s, f.final_weight_norm
            );
        }
    }
    println!("{}", out.summary.solver.rhs_evaluations);
    Ok(())
}
