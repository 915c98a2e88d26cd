//! Simulate the thesis's open-loop run and print its figures:
//! `cargo run --release -p rhonn --example simulate_pump [SCENARIO]`.

use rhonn::experiment::preset;

fn main() -> Result<(), rhonn::Error> {
    let name = std::env::args().nth(1).unwrap_or_else(|| "thesis-ch3".into());
    let out = preset::load_any(&name)?.run()?;
    println!("{} samples", out.column("t").map_or(0, <[f64]>::len));
    for f in &out.summary.findings {
        println!("{f}");
    }
    println!("{:#?}", out.summary.solver);
    Ok(())
}
