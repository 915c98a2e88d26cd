//! Simulate the thesis's open-loop run and print its figures:
//! `cargo run --release -p rhonn --example simulate_pump [SCENARIO]`.

use rhonn::experiment::{preset, run, Trace};

fn main() -> Result<(), rhonn::Error> {
    let name = std::env::args().nth(1).unwrap_or_else(|| "thesis-ch3".into());
    let scenario = preset::load_any(&name)?.pump_run()?;
    let mut trace = Trace::default();
    let summary = run(&scenario, &mut trace)?;
    println!("{} samples", trace.len());
    println!("{:#?}", summary.figures);
    println!("{:#?}", summary.solver);
    Ok(())
}
