//! Experiments: scenario files, running them, recording what they produce.

mod adaptive_report;
pub mod any_plant;
mod bench;
pub mod campaign;
mod campaign_plan;
pub mod closed_loop;
mod ident_figures;
mod integrated;
mod loop_conditions;
mod plant_control;
mod plant_ident;
mod plant_open;
mod plant_run;
mod plant_summary;
pub mod preset;
mod pump_controllers;
mod pump_figures;
mod pump_ident_figures;
mod pump_loop;
mod pump_run;
mod pump_scenario;
mod pump_settings;
mod quadrature;
mod regulation;
mod scenario;
mod scenario_run;
pub mod sim;
mod solver_spec;
mod trace;

pub use bench::{bench, bench_plant, median_run_seconds, BenchFigures};
pub use ident_figures::RunFigures;
pub use loop_conditions::{LoopConditions, SensorNoise};
pub use plant_run::{
    campaign_plan, drawn_scenario, nominal_plant_parameters, plant_measured_names, run_plant_scenario,
    run_plant_scenario_on,
};
pub use plant_summary::{
    FloorFigures, IdentStateFigures, LoopFigures, PlantColumn, PlantRunOutput, PlantSummary, SolverFigures,
    StateRange, WholeRunFigures, WEIGHT_QUANTITIES,
};
pub use pump_controllers::{CascadePiGainsMpa, NOMINAL_OPTIMAL, ROBUST};
pub use pump_run::{
    run, run_full, solver_options, AdaptiveReport, Alone, BaselineReport, ControlReport, Figures,
    IdentReport, Integrated, ModelFile, Regulation, RunOutput, SolverReport, StateFigures, Summary, SETTLE_S,
};
pub use pump_settings::{Scenario, SolverSettings};
pub use scenario::{
    is_plant_scenario, ControlSpec, LoopSpec, PlantSection, ProfileSpec, ScenarioSpec, SensorNoiseSpec,
    SolverSpec, ValidationSpec, MAX_DELAY_PERIODS,
};
pub use scenario_run::NamedColumns;
pub use solver_spec::{SolverDefaults, Tolerances, DEFAULT_ATOL};
pub use trace::{BaselineSample, Column, NoRecorder, Recorder, Sample, Trace};
