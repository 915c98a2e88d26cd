//! The `rhonn` command: glue between the command line and the `rhonn` and
//! `rhonn-report` libraries. No physics or numerics here: every command is a library
//! call that a test can make.

mod args;

use anyhow::{Context, Result};
use args::{Cli, Command};
use clap::Parser;
use rhonn::experiment::{preset, run_full, Trace};
use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = Cli::parse();
    match dispatch(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            for cause in e.chain().skip(1) {
                eprintln!("  caused by: {cause}");
            }
            ExitCode::from(2)
        }
    }
}

fn dispatch(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run { scenario, out } => cmd_run(&scenario, out),
        Command::Scenarios => {
            for (name, description) in preset::list() {
                println!("{name:<16} {description}");
            }
            Ok(())
        }
        Command::Reproduce { out } => {
            let root = out.unwrap_or_else(|| PathBuf::from("out"));
            for name in ["thesis-ch3", "thesis-ch5", "regulated-pi"] {
                cmd_run(name, Some(root.join(name)))?;
            }
            Ok(())
        }
        Command::Show { scenario } => {
            let spec = preset::load(&scenario)?;
            match preset::SHIPPED.iter().find(|(n, _)| *n == scenario) {
                Some((_, text)) => print!("{text}"),
                None => print!("{}", spec.to_toml()),
            }
            Ok(())
        }
    }
}

fn cmd_run(scenario: &str, out: Option<PathBuf>) -> Result<()> {
    let spec = preset::load(scenario)?;
    let sc = spec.check()?;
    for w in &sc.warnings {
        eprintln!("warning: {w}");
    }
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&spec.name));
    let mut trace = Trace::default();
    let output = run_full(&sc, &mut trace)?;
    let summary = &output.summary;
    let files = rhonn_report::write_run(&dir, &trace, &output).with_context(|| {
        format!(
            "scenario `{}` ran, but its outputs could not be written",
            spec.name
        )
    })?;
    let f = &summary.figures;
    println!(
        "{}: {} s simulated, {} samples",
        spec.name, f.duration_s, f.samples
    );
    println!(
        "  line pressure: final {:.3} MPa, min {:.3} MPa, max {:.3} MPa; below P_min for {:.3} s ({:.3} s after the first second)",
        f.final_p_line_mpa, f.p_line_min_mpa, f.p_line_max_mpa, f.time_below_p_min_s, f.time_below_p_min_after_1s_s
    );
    println!(
        "  stroke: final {:.4} mm, max {:.4} mm",
        f.final_stroke_mm, f.stroke_max_mm
    );
    if let Some(r) = &f.regulation {
        println!(
            "  regulation: max |p - p_ref| {:.3} MPa ({:.3} MPa from 1 s after each set-point change), ISE {:.3} MPa^2 s, current saturated {:.3} s",
            r.max_abs_deviation_mpa, r.max_abs_deviation_settled_mpa, r.ise_mpa2_s, r.time_current_saturated_s
        );
    }
    if let Some(id) = &summary.identification {
        println!(
            "  identification ({}, {} terms, {} epoch(s)):",
            id.law, id.n_terms, id.epochs
        );
        for (mode, figs) in [
            ("training", &id.training),
            ("series-parallel", &id.series_parallel),
            ("parallel", &id.parallel),
        ] {
            for f in figs {
                println!(
                    "    {mode:<16} {:<7} rms error {:.4} {}, fit {:.1} %, |w| {:.4e}",
                    f.state, f.rms_error, f.unit, f.fit_percent, f.final_weight_norm
                );
            }
        }
        for finding in &id.findings {
            println!("    finding: {finding}");
        }
    }
    let s = &summary.solver;
    println!(
        "  solver: {} rhs evaluations, {} accepted and {} rejected steps, {} events",
        s.rhs_evaluations, s.accepted_steps, s.rejected_steps, s.events
    );
    for file in files {
        println!("  wrote {}", file.display());
    }
    Ok(())
}
