//! What a plant scenario's run produces: `summary.json` ([`PlantSummary`], display units)
//! and the columns of `trajectory.csv` and `validation.csv` ([`PlantColumn`], SI).

use super::ident_figures::RunFigures;
use super::scenario::signal;
use crate::error::Result;
use crate::plant::Quantity;
use crate::signal::SignalSpec;
use serde::Serialize;
use std::collections::BTreeMap;

/// What a run keeps: its columns and its summary, or its summary alone (a loop's columns
/// not assembled: a tenth of a short loop's time).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Keep {
    Columns,
    Summary,
}

/// One column of a run's table: SI values and how people read them.
#[derive(Debug, Clone, PartialEq)]
pub struct PlantColumn {
    /// Name (`h2`, `h2_hat`, `voltage_baseline`).
    pub name: String,
    /// What it shows (its quantity).
    pub quantity: Quantity,
    /// Values, SI.
    pub values: Vec<f64>,
    /// Whether it is a plant input (else time, a state, an estimate or a reference).
    pub input: bool,
}

/// Figures of one identified state (display units).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct IdentStateFigures {
    /// State.
    pub state: &'static str,
    /// Unit of the errors.
    pub unit: &'static str,
    /// RMS error of the online (series-parallel) estimate over the second half.
    pub training_rms_error: f64,
    /// Fit \[%\] of the same; left out of JSON when undefined (a state that does not
    /// move).
    #[serde(skip_serializing_if = "crate::metrics::undefined")]
    pub training_fit_percent: f64,
    /// RMS error of the frozen model's free run on the validation inputs (after its
    /// first tenth), when there is a validation (left out of JSON without one).
    #[serde(skip_serializing_if = "crate::metrics::absent_or_undefined")]
    pub validation_rms_error: Option<f64>,
    /// Fit \[%\] of the same (left out of JSON without a validation or when undefined).
    #[serde(skip_serializing_if = "crate::metrics::absent_or_undefined")]
    pub validation_fit_percent: Option<f64>,
    /// With `validate = true` and no `[validation]` (the frozen model run again on the
    /// training inputs): RMS error of its series-parallel estimate (its regressor on the
    /// measured states) after the run's first tenth; left out of JSON otherwise.
    #[serde(skip_serializing_if = "crate::metrics::absent_or_undefined")]
    pub series_parallel_rms_error: Option<f64>,
    /// Fit \[%\] of the same (left out of JSON otherwise, or when undefined).
    #[serde(skip_serializing_if = "crate::metrics::absent_or_undefined")]
    pub series_parallel_fit_percent: Option<f64>,
    /// |w| of the neuron at the end of training.
    pub final_weight_norm: f64,
    /// The thesis's figures over each whole run, on the solver's dense output.
    pub whole_run: WholeRunFigures,
}

/// One identified state's figures over the whole of each run (display units), integrated
/// on the solver's dense output: RMS error, fit, NRMSE, and the time after which the error
/// stays within 1 % of the state's range (the thesis's figures of the pump).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct WholeRunFigures {
    /// The training run's online (series-parallel) estimate, its last epoch.
    pub training: RunFigures,
    /// The frozen model's series-parallel estimate on the training inputs again (with
    /// `validate = true` and no `[validation]`); left out otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub series_parallel: Option<RunFigures>,
    /// The frozen model's free run (on the validation inputs, or on the training inputs
    /// again); left out without a validation.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub free_run: Option<RunFigures>,
}

/// Figures of one controller (display units of the regulated state).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct LoopFigures {
    /// Controller.
    pub controller: &'static str,
    /// The stored tuning it runs with (a second baseline), if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tuning: Option<&'static str>,
    /// Integral of |y - r| \[unit s\], on the solver's dense output (3-point
    /// Gauss-Legendre on each step).
    pub iae: f64,
    /// Integral of (y - r)^2 \[unit^2 s\], likewise.
    pub ise: f64,
    /// y - r at the end \[unit\].
    pub final_error: f64,
    /// max |y - r| over the run \[unit\].
    pub max_abs_deviation: f64,
    /// max |y - r| from the plant's settling time after each set-point change on (the
    /// pump: 1 s, the tanks: 150 s) \[unit\].
    pub max_abs_deviation_settled: f64,
    /// The plant's settling time, the window of the settled figures \[s\] (the pump: 1 s,
    /// the tanks: 150 s).
    pub settle_s: f64,
    /// max |y - r| from a tenth of the plant's settling time after each set-point change
    /// on (the pump: 0.1 s) \[unit\].
    pub max_abs_deviation_early: f64,
    /// Time with |y - r| within 1 % of r \[s\].
    pub time_within_1pct_s: f64,
    /// The same in % of the run.
    pub within_1pct_percent: f64,
    /// Each set-point step's overshoot beyond its new value within the plant's settling
    /// time, in % of the step (0 when the output does not pass it).
    pub overshoot_percent: Vec<f64>,
    /// Time the plant's floor state spent below its floor \[s\] (the pump: the pressure
    /// below P_min); left out for a plant without one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_below_floor_s: Option<f64>,
    /// The same from the plant's settling time on \[s\]; left out likewise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_below_floor_after_settle_s: Option<f64>,
    /// Whether every plant state stayed within its bounds (the pump's pressure and
    /// stroke within their limits).
    pub states_bounded: bool,
    /// An adaptive controller's weights over the run; left out for others.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub adaptive: Option<super::AdaptiveReport>,
    /// Time the input spent at a bound of its range \[s\].
    pub time_input_saturated_s: f64,
    /// Sum of the input's changes |u(k) - u(k-1)| over the control instants (the
    /// input's display unit).
    pub input_total_variation: f64,
    /// RMS of the input's change per control period (the input's display unit).
    pub input_rms_change_per_sample: f64,
    /// Time the input spent at a bound reached from the other bound within
    /// `activity::SWITCH_WINDOW` control periods (bang-bang) \[s\].
    pub time_input_switching_s: f64,
}

impl LoopFigures {
    /// How findings name it: the kind, and its stored tuning if any
    /// (`cascade-pi-nominal-optimal`).
    pub fn label(&self) -> String {
        match self.tuning {
            Some(t) => format!("{}-{t}", self.controller),
            None => self.controller.to_string(),
        }
    }
}

/// One state of an open-loop run (display units): where it started and ended, and its
/// range over the samples.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct StateRange {
    /// State.
    pub state: &'static str,
    /// Unit of the values.
    pub unit: &'static str,
    /// At t = 0.
    pub initial: f64,
    /// At the end.
    pub final_value: f64,
    /// The smallest sample.
    pub min_value: f64,
    /// The largest sample.
    pub max_value: f64,
}

/// The solver's settings and what it did over every integration of the run (each loop,
/// training and validation).
#[derive(Debug, Clone, PartialEq, Default, Serialize, schemars::JsonSchema)]
pub struct SolverFigures {
    /// Step-size control profile (`hairer`, `ode45`, `simulink-ode45`).
    #[schemars(with = "String")]
    pub profile: super::solver_spec::ProfileSpec,
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance per plant state, SI (as `[solver] atol_si` writes it).
    pub atol_si: BTreeMap<String, f64>,
    /// Largest step \[s\]; left out without a limit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_step_s: Option<f64>,
    /// Right-hand-side evaluations (including event location).
    pub rhs_evaluations: u64,
    /// Accepted steps.
    pub accepted_steps: u64,
    /// Rejected steps.
    pub rejected_steps: u64,
    /// Events located (a plant's switching, bounds reached and left).
    pub events: u64,
    /// Steps landed on input breakpoints and sampling instants.
    pub breakpoints: u64,
}

impl SolverFigures {
    /// The settings `tol` on the states `states`, and no work yet.
    pub(super) fn of(tol: &super::solver_spec::Tolerances, states: &[Quantity]) -> Self {
        SolverFigures {
            profile: tol.profile,
            rtol: tol.rtol,
            atol_si: states
                .iter()
                .map(|q| q.name.to_string())
                .zip(tol.atol.iter().copied())
                .collect(),
            max_step_s: tol.max_step_s.is_finite().then_some(tol.max_step_s),
            ..SolverFigures::default()
        }
    }

    /// Count the work of one integration.
    pub(super) fn add(&mut self, st: rhonn_ode::Stats) {
        self.rhs_evaluations += st.rhs_evaluations;
        self.accepted_steps += st.accepted_steps;
        self.rejected_steps += st.rejected_steps;
        self.events += st.events;
        self.breakpoints += st.breakpoints;
    }
}

/// `summary.json` of a plant scenario.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct PlantSummary {
    /// rhonn's version.
    pub rhonn_version: &'static str,
    /// Scenario name.
    pub scenario: String,
    /// The scenario as run, in the one scenario format (`rhonn run` of this, saved as
    /// TOML, runs it again).
    #[schemars(with = "serde_json::Value")]
    #[serde(serialize_with = "settings_as_given")]
    pub settings: super::ScenarioSpec,
    /// The plant.
    pub plant: &'static str,
    /// Its parameters as run (display units, the unit in the name).
    pub parameters: Vec<(String, f64)>,
    /// The solver's settings and work.
    pub solver: SolverFigures,
    /// Identification figures per identified state.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub identification: Option<Vec<IdentStateFigures>>,
    /// The regulated state and its unit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub regulated: Option<(&'static str, &'static str)>,
    /// The controller's figures, then its baseline's and second baseline's when run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub control: Option<Vec<LoopFigures>>,
    /// An open-loop run's states: where each started and ended, and its range.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub open_loop: Option<Vec<StateRange>>,
    /// An open-loop or identification run's time below the plant's floor (the pump's
    /// P_min); left out for a plant without one, and for a closed loop (whose `control[]`
    /// gives it per loop).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub floor: Option<FloorFigures>,
    /// What the settings let through but the plant's model does not cover (also printed
    /// by the command); left out when there is none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// What the figures say, in words.
    pub findings: Vec<String>,
}

/// The scenario as JSON without the settings left to their defaults: a key whose value is
/// absent or not a number (a controller's gain computed at run time) is left out, so
/// summary.json holds no null.
fn settings_as_given<S: serde::Serializer>(
    spec: &super::ScenarioSpec,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    fn strip(v: &mut serde_json::Value) {
        match v {
            serde_json::Value::Object(m) => {
                m.retain(|_, x| !x.is_null());
                m.values_mut().for_each(strip);
            }
            serde_json::Value::Array(a) => a.iter_mut().for_each(strip),
            _ => {}
        }
    }
    let mut v = serde_json::to_value(spec).map_err(serde::ser::Error::custom)?;
    strip(&mut v);
    v.serialize(s)
}

/// The time a run's floor state spent below the plant's floor (display units): where the
/// plant's model is not valid (the pump's pressure below P_min).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct FloorFigures {
    /// The state.
    pub state: &'static str,
    /// Unit of the floor.
    pub unit: &'static str,
    /// The floor.
    pub floor: f64,
    /// Time below it over the run \[s\], the crossings located on the solver's dense
    /// output.
    pub time_below_s: f64,
    /// The plant's settling time \[s\] (the pump: 1 s).
    pub settle_s: f64,
    /// The same from the plant's settling time on (the start's transient excluded) \[s\].
    pub time_below_after_settle_s: f64,
}

impl PlantSummary {
    /// Every figure as `(name, value)`: what a campaign records per run.
    pub fn figures(&self) -> Vec<(String, f64)> {
        let mut v = Vec::new();
        for s in self.identification.iter().flatten() {
            v.push((
                format!("{}_training_fit_percent", s.state),
                s.training_fit_percent,
            ));
            if let Some(f) = s.series_parallel_fit_percent {
                v.push((format!("{}_series_parallel_fit_percent", s.state), f));
            }
            if let Some(f) = s.validation_fit_percent {
                v.push((format!("{}_validation_fit_percent", s.state), f));
            }
        }
        for s in self.open_loop.iter().flatten() {
            v.push((format!("{}_final", s.state), s.final_value));
            v.push((format!("{}_min", s.state), s.min_value));
            v.push((format!("{}_max", s.state), s.max_value));
        }
        // Names carry the regulated state's display unit (`controller_iae_mpa_s`).
        let u = self.regulated.map_or(String::new(), |(_, u)| u.to_lowercase());
        for (role, f) in ["controller", "baseline", "second_baseline"]
            .iter()
            .zip(self.control.iter().flatten())
        {
            v.push((format!("{role}_iae_{u}_s"), f.iae));
            v.push((format!("{role}_ise_{u}2_s"), f.ise));
            v.push((format!("{role}_final_error_{u}"), f.final_error));
            v.push((
                format!("{role}_max_abs_deviation_settled_{u}"),
                f.max_abs_deviation_settled,
            ));
            v.push((format!("{role}_within_1pct_percent"), f.within_1pct_percent));
            if let Some(t) = f.time_below_floor_after_settle_s {
                v.push((format!("{role}_time_below_floor_after_settle_s"), t));
            }
            v.push((format!("{role}_input_total_variation"), f.input_total_variation));
            v.push((format!("{role}_time_input_switching_s"), f.time_input_switching_s));
        }
        v
    }
}

/// What a plant scenario's run produced.
#[derive(Debug, Clone, PartialEq)]
pub struct PlantRunOutput {
    /// The summary.
    pub summary: PlantSummary,
    /// trajectory.csv's columns (the first is time).
    pub trajectory: Vec<PlantColumn>,
    /// validation.csv's columns, when there is a validation.
    pub validation: Option<Vec<PlantColumn>>,
    /// An identification's trained model (weights.json).
    pub model: Option<super::ModelFile>,
    /// Simulated time \[s\] (the scenario's `duration_s`).
    pub duration_s: f64,
    /// The plant's floor, for plots: the state, its quantity and the floor (SI); None
    /// for a plant without one ([`crate::plant::Plant::floor`]).
    pub floor: Option<(&'static str, Quantity, f64)>,
}

pub(super) const TIME: Quantity = Quantity::si("t", "s", "time");
/// The first columns of a run's table: time (`t`, the samples `t`), then each of the
/// plant's `inputs` as the scenario's profiles `inputs_spec` give it (0 where none does).
pub(super) fn time_and_inputs(
    inputs_spec: &BTreeMap<String, SignalSpec>,
    t: &[f64],
    inputs: &[&Quantity],
) -> Result<Vec<PlantColumn>> {
    let mut cols = vec![PlantColumn {
        name: "t".into(),
        quantity: TIME,
        values: t.to_vec(),
        input: false,
    }];
    for q in inputs {
        let values = match inputs_spec.get(q.name) {
            Some(sp) => {
                let s = signal(sp, q.name, q, (f64::NEG_INFINITY, f64::INFINITY))?;
                t.iter().map(|&t| s.eval(t)).collect()
            }
            None => vec![0.0; t.len()],
        };
        cols.push(PlantColumn {
            name: q.name.into(),
            quantity: **q,
            values,
            input: true,
        });
    }
    Ok(cols)
}

/// An adaptive controller's weights (the neuron's scaled units): |W|, |W_1|, and W_1's
/// distance from its ball's centre beside the ball's radius (the projection's bound).
pub const WEIGHT_QUANTITIES: [Quantity; 3] = [
    Quantity::si("w_norm", "1/s", "adaptive drift weights |W| (scaled units)"),
    Quantity::si("w1_norm", "1/s", "adaptive gain weights |W_1| (scaled units)"),
    Quantity::si(
        "w1_ball",
        "1/s",
        "gain weights' distance from their ball's centre, and the ball's radius (bound)",
    ),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// Found by `rhonn-mutate` (seed 50): an identification scenario without `[validation]`
    /// wrote `"validation_fit_percent": null`, which a reader takes for a failed number.
    #[test]
    fn an_identification_without_validation_leaves_its_figures_out_not_null() {
        let f = IdentStateFigures {
            state: "h1",
            unit: "mm",
            training_rms_error: 1.0,
            training_fit_percent: 90.0,
            validation_rms_error: None,
            validation_fit_percent: None,
            series_parallel_rms_error: None,
            series_parallel_fit_percent: None,
            final_weight_norm: 0.5,
            whole_run: WholeRunFigures {
                training: RunFigures {
                    rms_error: 1.0,
                    fit_percent: 90.0,
                    nrmse: 0.01,
                    convergence_band: 0.1,
                    convergence_time_s: Some(10.0),
                },
                series_parallel: None,
                free_run: None,
            },
        };
        let json = serde_json::to_string(&f).unwrap();
        assert!(
            !json.contains("null") && !json.contains("validation") && !json.contains("series"),
            "{json}"
        );
        let with = IdentStateFigures {
            validation_rms_error: Some(2.0),
            validation_fit_percent: Some(80.0),
            ..f
        };
        assert!(serde_json::to_string(&with)
            .unwrap()
            .contains("\"validation_fit_percent\":80.0"));
    }
}
