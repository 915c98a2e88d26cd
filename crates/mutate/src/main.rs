//! `rhonn-mutate`: the mutation harness from the command line (see the library's docs).

use anyhow::{bail, Result};
use clap::Parser;
use std::path::PathBuf;
use std::time::Duration;

/// Mutate every file the `rhonn` command reads and check what it does with each mutant.
#[derive(Parser)]
struct Args {
    /// The `rhonn` binary to test.
    #[arg(long, default_value = "target/release/rhonn")]
    bin: PathBuf,
    /// How many mutants.
    #[arg(long, default_value_t = 400)]
    cases: usize,
    /// Seed of the mutations.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Seconds after which a case counts as a hang.
    #[arg(long, default_value_t = 60)]
    timeout_s: u64,
    /// Cases run at once.
    #[arg(long, default_value_t = 2)]
    jobs: usize,
    /// Work folder (failed cases are kept there).
    #[arg(long, default_value = "target/mutate")]
    work: PathBuf,
    /// Also write the report as JSON to this file.
    #[arg(long)]
    json: Option<PathBuf>,
    /// Instead of --cases random mutants: every numeric value of every scenario, spec and
    /// model.json set to each extreme in turn (zero, -1, 1e-9, 1e9, +-1.7e308, 5e-324,
    /// and in TOML infinity and NaN).
    #[arg(long)]
    sweep: bool,
}

fn main() -> Result<()> {
    let a = Args::parse();
    if !a.bin.is_file() {
        bail!(
            "--bin {}: no such file (build it with `cargo build --release`)",
            a.bin.display()
        );
    }
    let _ = std::fs::remove_dir_all(&a.work);
    let cfg = rhonn_mutate::Config {
        bin: std::fs::canonicalize(&a.bin)?,
        work: std::path::absolute(&a.work)?,
        cases: a.cases,
        seed: a.seed,
        timeout: Duration::from_secs(a.timeout_s),
        jobs: a.jobs,
        sweep: a.sweep,
    };
    let report = rhonn_mutate::run(&cfg)?;
    print!("{}", report.table());
    if let Some(p) = a.json {
        std::fs::write(p, serde_json::to_string_pretty(&report)?)?;
    }
    if !report.failures.is_empty() || report.named_share() < 0.95 {
        std::process::exit(1);
    }
    Ok(())
}
