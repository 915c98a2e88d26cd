//! A scenario of the one format as one thing to run: [`ScenarioSpec::run`] runs it on the
//! generic runner, whatever the plant, and gives its columns and summary
//! ([`PlantRunOutput`]), so the command line, Python and the report crate read every run
//! the same way.

use super::bench::{bench_plant, BenchFigures};
use super::plant_run::{run_plant_scenario, run_plant_summary};
use super::plant_summary::PlantRunOutput;
use super::scenario::ScenarioSpec;
use crate::error::Result;
use std::time::Duration;

/// Columns as `(name, SI values)`.
pub type NamedColumns = Vec<(String, Vec<f64>)>;

impl ScenarioSpec {
    /// The scenario with its output interval set to its length: a run that records no
    /// sample but its start and end ([`ScenarioSpec::run_summary`]).
    pub(super) fn without_samples(&self) -> ScenarioSpec {
        let mut quiet = self.clone();
        quiet.output_interval_s = self.duration_s;
        quiet
    }

    /// Run it on the generic runner.
    pub fn run(&self) -> Result<PlantRunOutput> {
        run_plant_scenario(self, None)
    }

    /// The run's summary without recording its samples ([`run_plant_summary`]): a loop's
    /// figures are [`ScenarioSpec::run`]'s to the bit, at a fraction of the cost. What
    /// `rhonn bench` times and the tuning studies run by the thousand.
    pub fn run_summary(&self) -> Result<super::PlantSummary> {
        run_plant_summary(self, None)
    }

    /// Time its runs for about `budget` (`rhonn bench`).
    pub fn bench(&self, budget: Duration) -> Result<BenchFigures> {
        bench_plant(self, budget)
    }
}

impl PlantRunOutput {
    /// The trajectory's column `name` (SI), if it has one.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.trajectory
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.values.as_slice())
    }

    /// The trajectory's columns, and the validation's when there is one (SI).
    pub fn into_columns(self) -> (NamedColumns, Option<NamedColumns>) {
        let cols = |c: Vec<super::PlantColumn>| c.into_iter().map(|c| (c.name, c.values)).collect();
        (cols(self.trajectory), self.validation.map(cols))
    }
}
