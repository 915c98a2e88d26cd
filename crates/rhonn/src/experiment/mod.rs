//! Experiments: scenario files, running them, recording what they produce.

pub mod any_plant;
mod bench;
pub mod campaign;
pub mod preset;
mod run;
mod scenario;
mod trace;

pub use bench::{bench, BenchFigures};
pub use run::{
    run, run_full, solver_options, AdaptiveReport, BaselineReport, ControlReport, Figures, IdentReport,
    ModelFile, Plant, Regulation, RunOutput, SolverReport, StateFigures, Summary, SETTLE_S,
};
pub use scenario::{
    AdaptiveSettings, ControllerSpec, Drive, InitialSpec, MeasurementSpec, PiSettings, ProfileSpec, Scenario,
    ScenarioSpec, SolverSettings, SolverSpec, Q_L_MAX_DM3_S,
};
pub use trace::{BaselineSample, Column, NoRecorder, Recorder, Sample, Trace};
