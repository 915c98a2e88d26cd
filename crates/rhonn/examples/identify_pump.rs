//! Identify the pump as the thesis does and print the figures:
//! `cargo run --release -p rhonn --example identify_pump`.

use rhonn::experiment::{preset, run_full, Trace};

fn main() -> Result<(), rhonn::Error> {
    let scenario = preset::load_any("thesis-ch5")?.pump_run()?;
    let mut trace = Trace::default();
    let out = run_full(&scenario, &mut trace)?;
    let id = out
        .summary
        .identification
        .as_ref()
        .expect("an identified scenario");
    print!("{id}");
    println!(
        "{} rhs evaluations, {} samples",
        out.summary.solver.rhs_evaluations,
        trace.len()
    );
    Ok(())
}
