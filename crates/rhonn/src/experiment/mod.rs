//! Experiments: scenario files, running them, recording what they produce.

pub mod any_plant;
mod any_scenario;
mod bench;
pub mod campaign;
mod campaign_plan;
mod figures;
pub mod front;
mod ident_figures;
mod integrated;
mod loop_conditions;
mod plant_run;
mod plant_scenario;
pub mod preset;
mod pump_controllers;
mod pump_loop;
pub mod pump_scenario;
mod run;
mod scenario;
pub mod sim;
mod trace;
pub mod tuning;

pub use any_scenario::{NamedColumns, ScenarioRun};
pub use bench::{bench, bench_plant, median_run_seconds, BenchFigures};
pub use loop_conditions::{LoopConditions, SensorNoise};
pub use plant_run::{
    nominal_plant_parameters, run_plant_scenario, run_plant_scenario_on, IdentStateFigures, LoopFigures,
    PlantColumn, PlantRunOutput, PlantSummary, WEIGHT_QUANTITIES,
};
pub use plant_scenario::{
    is_plant_scenario, ControlSpec, LoopSpec, PlantScenarioSpec, PlantSection, SensorNoiseSpec,
    ValidationSpec, MAX_DELAY_PERIODS,
};
pub use pump_controllers::{
    baseline_kind, Baseline, CascadePiGainsMpa, CascadePiSettings, PiSettings, NOMINAL_OPTIMAL, ROBUST,
};
pub use run::{
    run, run_full, solver_options, AdaptiveReport, Alone, BaselineReport, ControlReport, Figures,
    IdentReport, Integrated, ModelFile, Regulation, RunOutput, SolverReport, StateFigures, Summary, SETTLE_S,
};
pub use scenario::{
    AdaptiveSettings, ControllerSpec, Drive, InitialSpec, MeasurementSpec, ProfileSpec, Scenario,
    ScenarioSpec, SolverSettings, SolverSpec, Q_L_MAX_DM3_S,
};
pub use trace::{BaselineSample, Column, NoRecorder, Recorder, Sample, Trace};
