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
mod quadrature;
mod regulation;
mod scenario;
mod scenario_run;
pub mod sim;
mod solver_spec;
mod trace;

pub use crate::control::{CascadePiGainsMpa, NOMINAL_OPTIMAL, ROBUST};
pub use adaptive_report::AdaptiveReport;
pub use bench::{bench_plant, median_run_seconds, BenchFigures};
pub use ident_figures::{ModelFile, RunFigures};
pub use integrated::{Alone, Integrated};
pub use loop_conditions::{LoopConditions, SensorNoise};
pub use plant_run::{
    campaign_plan, drawn_scenario, nominal_plant_parameters, plant_measured_names, run_plant_scenario,
    run_plant_scenario_on, run_plant_summary,
};
pub use plant_summary::{
    FloorFigures, IdentStateFigures, LoopFigures, PlantColumn, PlantRunOutput, PlantSummary, SolverFigures,
    StateRange, WholeRunFigures, WEIGHT_QUANTITIES,
};
pub use scenario::{
    is_plant_scenario, ControlSpec, LoopSpec, PlantSection, ProfileSpec, ScenarioSpec, SensorNoiseSpec,
    SolverSpec, ValidationSpec, MAX_DELAY_PERIODS,
};
pub use scenario_run::NamedColumns;
pub use solver_spec::{SolverDefaults, Tolerances, DEFAULT_ATOL};
pub use trace::{Column, Trace};
