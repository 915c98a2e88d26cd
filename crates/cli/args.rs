//! Command-line arguments. Each command's help says what it writes and in which units.

use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// rhonn: simulate, identify and control a solenoid-controlled variable-displacement
/// pump with Recurrent High-Order Neural Networks.
#[derive(Debug, Parser)]
#[command(name = "rhonn", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a scenario and write its trajectory, summary and plots.
    ///
    /// Writes into DIR (default out/<scenario name>):
    ///   trajectory.csv  header, then one row per output sample (default every 1 ms):
    ///                   t [s], p_line [Pa], stroke [m], current [A], demand [m^3/s],
    ///                   and for regulated runs p_ref [Pa] and p_meas [Pa] (the
    ///                   measurement the controller last saw); SI units throughout
    ///   summary.json    the scenario as run, solver settings and counters, and the
    ///                   figures in display units (MPa, mm, s): final values, pressure
    ///                   extremes, time below P_min, and for regulated runs the largest
    ///                   deviation from the set-point and the ISE
    ///   pressure.svg    line pressure [MPa] against time (thesis figure 3.7)
    ///   stroke.svg      pump stroke [mm] against time (thesis figure 3.6)
    ///   inputs.svg      solenoid current [A] and demanded flow [dm^3/s]
    /// With an [identifier] (e.g. thesis-ch5) also:
    ///   trajectory.csv  + p_line_hat [Pa], stroke_hat [m] (last training epoch)
    ///   weights.json    the trained model: states, inputs, sigmoid, scales, terms,
    ///                   poles, law, weights (SI)
    ///   validation.csv  frozen weights on the same data: t [s], <state>,
    ///                   <state>_hat_series_parallel, <state>_hat_parallel (SI)
    ///   summary.json    + per state and mode: RMS error and convergence band [MPa or
    ///                   mm], fit [%], NRMSE, convergence time [s], final |w|
    ///   ident_errors.svg, ident_states.svg, ident_zoom.svg, validation.svg
    /// Files appear only when all of them are complete. Exit code 2 on any error.
    #[command(verbatim_doc_comment)]
    Run {
        /// A shipped scenario's name (see `rhonn scenarios`) or a path to a TOML file.
        scenario: String,
        /// Output folder.
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
    },
    /// Reproduce the thesis: run thesis-ch3 (the pump, chapter 3), thesis-ch5 (the RHONN
    /// identification, chapter 5) and regulated-pi (the PI baseline) into DIR/<name>
    /// (default out/), each writing what `rhonn run` writes.
    Reproduce {
        /// Output root.
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
    },
    /// List the shipped scenarios with a one-line description each.
    Scenarios,
    /// Print a scenario's TOML (a shipped one as it ships: copy it to start your own).
    Show {
        /// A shipped scenario's name or a path to a TOML file.
        scenario: String,
    },
}
