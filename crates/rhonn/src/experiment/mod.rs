//! Experiments: scenario files, running them, recording what they produce.

pub mod any_plant;
mod bench;
pub mod campaign;
mod figures;
mod ident_figures;
mod integrated;
mod plant_run;
mod plant_scenario;
pub mod preset;
mod pump_controllers;
mod pump_loop;
mod run;
mod scenario;
mod trace;
pub mod tuning;

pub use bench::{bench, bench_plant, BenchFigures};
pub use plant_run::{
    nominal_plant_parameters, run_plant_scenario, IdentStateFigures, LoopFigures, PlantColumn,
    PlantRunOutput, PlantSummary, WEIGHT_QUANTITIES,
};
pub use plant_scenario::{
    is_plant_scenario, ControlSpec, LoopSpec, PlantScenarioSpec, PlantSection, ValidationSpec,
};
pub use pump_controllers::{Baseline, CascadePiGainsMpa, CascadePiSettings, NOMINAL_OPTIMAL, ROBUST};
pub use run::{
    run, run_full, solver_options, AdaptiveReport, BaselineReport, ControlReport, Figures, IdentReport,
    Integrated, ModelFile, Regulation, RunOutput, SolverReport, StateFigures, Summary, SETTLE_S,
};
pub use scenario::{
    AdaptiveSettings, ControllerSpec, Drive, InitialSpec, MeasurementSpec, PiSettings, ProfileSpec, Scenario,
    ScenarioSpec, SolverSettings, SolverSpec, Q_L_MAX_DM3_S,
};
pub use trace::{BaselineSample, Column, NoRecorder, Recorder, Sample, Trace};
