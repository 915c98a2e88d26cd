//! Identify the pump as the thesis does and print the figures:
//! `cargo run --release -p rhonn --example identify_pump`.

use rhonn::experiment::preset;

fn main() -> Result<(), rhonn::Error> {
    let out = preset::load_any("thesis-ch5")?.run()?;
    let id = out
        .summary
        .identification
        .as_ref()
        .expect("an identified scenario");
    for s in id {
        let w = &s.whole_run;
        println!(
            "{}: fit {:.4} % training, RMS error {:.4} {}",
            s.state, w.training.fit_percent, w.training.rms_error, s.unit
        );
        for (mode, f) in [("series-parallel", &w.series_parallel), ("free run", &w.free_run)] {
            if let Some(f) = f {
                println!(
                    "  frozen, {mode}: fit {:.4} %, RMS error {:.4} {}",
                    f.fit_percent, f.rms_error, s.unit
                );
            }
        }
    }
    for f in &out.summary.findings {
        println!("{f}");
    }
    let samples = out.column("t").map_or(0, <[f64]>::len);
    println!(
        "{} rhs evaluations, {samples} samples",
        out.summary.solver.rhs_evaluations
    );
    Ok(())
}
