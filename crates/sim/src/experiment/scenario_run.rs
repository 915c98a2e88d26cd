//! A scenario of the one format as one thing to run: [`ScenarioSpec::run`] gives a
//! [`ScenarioRun`] whose columns and summary are read the same way whatever the plant, so
//! the command line, Python and the report crate never ask which runner it was. (The
//! pump's scenarios run on the pump's own runner, lowered to its settings by
//! [`ScenarioSpec::pump_settings`], every other plant's on the generic one; this is
//! the one place that tells them apart.)

use super::bench::{bench, bench_plant, BenchFigures};
use super::plant_run::run_plant_scenario;
use super::plant_summary::PlantRunOutput;
use super::pump_run::{run_full, RunOutput};
use super::pump_settings::{PumpSettings, Scenario};
use super::scenario::ScenarioSpec;
use super::trace::Trace;
use crate::error::Result;
use std::time::Duration;

/// What a scenario's run produced, on either runner.
#[derive(Debug, Clone)]
pub enum ScenarioRun {
    /// A pump scenario: its samples and its output (summary, validation, model).
    Pump {
        /// The samples.
        trace: Box<Trace>,
        /// The summary, the validation runs and the trained model.
        output: Box<RunOutput>,
        /// The scenario's warnings (settings outside what was validated).
        warnings: Vec<String>,
    },
    /// A plant scenario's columns and summary.
    Plant(Box<PlantRunOutput>),
}

/// Columns as `(name, SI values)`.
pub type NamedColumns = Vec<(String, Vec<f64>)>;

impl ScenarioSpec {
    /// The pump runner's settings of a pump scenario (`[plant] kind = "pump"`), checked;
    /// `None` for any other plant, whose scenario runs as written.
    pub(crate) fn pump_settings(&self) -> Result<Option<PumpSettings>> {
        if self.plant.kind == "pump" {
            super::pump_scenario::lower_checked(self).map(Some)
        } else {
            Ok(None)
        }
    }

    /// A pump scenario checked into the run its runner takes ([`super::run_full`], for
    /// a run without recording every sample or with a recorder of one's own); an error
    /// naming `plant.kind` for any other plant.
    pub fn pump_run(&self) -> Result<Scenario> {
        match self.pump_settings()? {
            Some(spec) => spec.check(),
            None => Err(crate::error::invalid(
                "plant.kind",
                format!("{:?}", self.plant.kind),
                "\"pump\" (other plants run with `run` or `run_plant_scenario`)",
            )),
        }
    }

    /// Run it.
    pub fn run(&self) -> Result<ScenarioRun> {
        match self.pump_settings()? {
            Some(spec) => {
                let sc = spec.check()?;
                let mut trace = Trace::default();
                let output = run_full(&sc, &mut trace)?;
                Ok(ScenarioRun::Pump {
                    trace: Box::new(trace),
                    output: Box::new(output),
                    warnings: sc.warnings,
                })
            }
            None => Ok(ScenarioRun::Plant(Box::new(run_plant_scenario(self, None)?))),
        }
    }

    /// Time its runs for about `budget` (`rhonn bench`).
    pub fn bench(&self, budget: Duration) -> Result<BenchFigures> {
        match self.pump_settings()? {
            Some(spec) => bench(&spec.check()?, budget),
            None => bench_plant(self, budget),
        }
    }
}

impl ScenarioRun {
    /// The scenario's warnings (printed before the figures).
    pub fn warnings(&self) -> &[String] {
        match self {
            ScenarioRun::Pump { warnings, .. } => warnings,
            ScenarioRun::Plant(o) => &o.summary.warnings,
        }
    }

    /// The trajectory's columns, and the validation's when there is one (SI).
    pub fn into_columns(self) -> (NamedColumns, Option<NamedColumns>) {
        match self {
            ScenarioRun::Pump { trace, output, .. } => {
                let cols = |t: Trace| t.columns.into_iter().map(|c| (c.name, c.values)).collect();
                (cols(*trace), output.validation.map(cols))
            }
            ScenarioRun::Plant(o) => {
                let cols = |c: Vec<super::PlantColumn>| c.into_iter().map(|c| (c.name, c.values)).collect();
                (cols(o.trajectory), o.validation.map(cols))
            }
        }
    }
}
