//! Running a [`ScenarioSpec`] on any [`Plant`]: an online identification (then its
//! frozen model's free run on other inputs), a controller and its baseline on identical
//! plants, or the plant alone on its inputs. Produces columns (SI) and a summary (display
//! units) that the report crate writes as trajectory.csv, validation.csv, summary.json and
//! plots.

use super::any_plant::{IDENTIFY_RTOL, LOOP_RTOL};
use super::campaign_plan::{Plan, Uncertain};
use super::plant_control::run_control;
use super::plant_ident::run_identification;
use super::plant_open::run_open;
use super::plant_summary::{Keep, PlantColumn, PlantRunOutput, PlantSummary, SolverFigures};
use super::scenario::{clipped_inputs, configure, drive, ScenarioSpec};
use super::solver_spec::{SolverDefaults, Tolerances};
use crate::error::{Error, Result};
use crate::plant::{with_kind, Plant, WithPlant};

/// Run `spec` with its parameters replaced by `parameters` (display units, in the
/// plant's order) when given: a campaign's draw.
pub fn run_plant_scenario(spec: &ScenarioSpec, parameters: Option<&[f64]>) -> Result<PlantRunOutput> {
    run_keeping(spec, parameters, Keep::Columns)
}

/// The summary of [`run_plant_scenario`] without recording its samples: the scenario run
/// with its output interval set to its length (its `settings` still the scenario as
/// given). A loop's figures are integrated on the solver's dense output, so they are
/// [`run_plant_scenario`]'s to the bit; an open loop's state ranges are read at the
/// samples, here at the start and the end only.
pub fn run_plant_summary(spec: &ScenarioSpec, parameters: Option<&[f64]>) -> Result<PlantSummary> {
    let mut summary = run_keeping(&spec.without_samples(), parameters, Keep::Summary)?.summary;
    // The scenario as given: its copy as run differs in its output interval alone.
    summary.settings.output_interval_s = spec.output_interval_s;
    Ok(summary)
}

fn run_keeping(spec: &ScenarioSpec, parameters: Option<&[f64]>, keep: Keep) -> Result<PlantRunOutput> {
    spec.check_common()?;
    struct Run<'a>(&'a ScenarioSpec, Option<&'a [f64]>, Keep);
    impl WithPlant for Run<'_> {
        type Output = PlantRunOutput;
        fn with<P: Plant>(self, nominal: P) -> Result<PlantRunOutput> {
            run_on(&nominal, self.0, self.1, self.2)
        }
    }
    with_kind(&spec.plant.kind, Run(spec, parameters, keep))
}

/// Run `spec` on your own `plant` (any [`Plant`]; `spec.plant.kind` only names it): the
/// same experiment, figures and findings as a shipped plant's scenario, for
/// `rhonn_report::write_plant_run` to write as `rhonn run` does (`crates/cli/examples/custom_plant.rs`).
pub fn run_plant_scenario_on<P: Plant>(plant: &P, spec: &ScenarioSpec) -> Result<PlantRunOutput> {
    spec.check_common()?;
    run_on(plant, spec, None, Keep::Columns)
}

/// The plan of `spec`'s campaign on its plant (`[plant] kind`, not the pump's): the
/// `[campaign]` section over the plant's parameter table, each at the scenario's value.
pub fn campaign_plan(spec: &ScenarioSpec) -> Result<Plan> {
    struct Of<'a>(&'a ScenarioSpec);
    impl WithPlant for Of<'_> {
        type Output = Plan;
        fn with<P: Plant>(self, nominal: P) -> Result<Plan> {
            campaign_plan_of(&nominal, self.0)
        }
    }
    with_kind(&spec.plant.kind, Of(spec))
}

/// [`campaign_plan`] on `plant` (a shipped or a user's own).
fn campaign_plan_of<P: Plant>(plant: &P, spec: &ScenarioSpec) -> Result<Plan> {
    let uncertain: Vec<Uncertain> = plant
        .parameters()
        .iter()
        .map(|p| Uncertain {
            name: p.name,
            value: spec.plant.parameters.get(p.name).copied().unwrap_or(p.nominal),
            tolerance: p.tolerance,
        })
        .collect();
    Plan::new(spec.campaign.as_ref(), &uncertain)
}

/// The plant named by a scenario, nominal (for its parameter table).
pub fn nominal_plant_parameters(kind: &str) -> Result<&'static [crate::plant::Parameter]> {
    struct Parameters;
    impl WithPlant for Parameters {
        type Output = &'static [crate::plant::Parameter];
        fn with<P: Plant>(self, nominal: P) -> Result<Self::Output> {
            Ok(nominal.parameters())
        }
    }
    with_kind(kind, Parameters)
}

/// The names of the states a sensor measures on the plant `kind`, in its order.
pub fn plant_measured_names(kind: &str) -> Result<Vec<&'static str>> {
    struct Measured;
    impl WithPlant for Measured {
        type Output = Vec<&'static str>;
        fn with<P: Plant>(self, nominal: P) -> Result<Self::Output> {
            Ok(nominal
                .measured()
                .iter()
                .map(|&i| nominal.states()[i].name)
                .collect())
        }
    }
    with_kind(kind, Measured)
}

fn run_on<P: Plant>(
    nominal: &P,
    spec: &ScenarioSpec,
    parameters: Option<&[f64]>,
    keep: Keep,
) -> Result<PlantRunOutput> {
    // `[campaign]` is `rhonn campaign`'s, checked by every run (as the pump's).
    if spec.campaign.is_some() {
        campaign_plan_of(nominal, spec)?;
    }
    let (mut plant, given) = configure(nominal, &spec.plant)?;
    if let Some(v) = parameters {
        plant = plant.with_parameters(v)?;
    }
    let used: Vec<f64> = match parameters {
        Some(v) => v.to_vec(),
        None => plant
            .parameters()
            .iter()
            .map(|p| spec.plant.parameters.get(p.name).copied().unwrap_or(p.nominal))
            .collect(),
    };
    let mut summary = PlantSummary {
        rhonn_version: env!("CARGO_PKG_VERSION"),
        scenario: spec.name.clone(),
        settings: spec.clone(),
        plant: plant.name(),
        parameters: plant
            .parameters()
            .iter()
            .map(|p| p.name.to_string())
            .zip(used)
            .collect(),
        solver: SolverFigures::default(),
        identification: None,
        regulated: None,
        control: None,
        open_loop: None,
        floor: None,
        warnings: Vec::new(),
        findings: Vec::new(),
    };
    summary.warnings = clipped_inputs(&plant, &spec.input, "input", spec.duration_s)?;
    if let Some(v) = &spec.validation {
        let d = v.duration_s;
        if d.is_finite() && d > 0.0 {
            summary
                .warnings
                .extend(clipped_inputs(&plant, &v.input, "validation.input", d)?);
        }
    }
    let input = slew_scaled(&plant, spec, parameters);
    let plant = drive(plant, &input, "input", spec.duration_s)?;
    let x0 = plant.initial_state(&given, &inputs_at_start(&plant, spec));
    summary.warnings.extend(below_floor_at_start(&plant, &x0));
    let closed = spec.identifier.is_none() && spec.control.is_some();
    let tol = tolerances(&plant, spec, if closed { LOOP_RTOL } else { IDENTIFY_RTOL })?;
    summary.solver = SolverFigures::of(&tol, plant.states());
    let floor = plant
        .floor()
        .map(|(i, v)| (plant.states()[i].name, plant.states()[i], v));
    let mut out = match &spec.identifier {
        Some(ident) => run_identification(plant, &x0, spec, ident, summary, &tol)?,
        None if closed => run_control(plant, &x0, spec, summary, &tol, keep)?,
        None => run_open(plant, &x0, spec, summary, &tol)?,
    };
    out.floor = floor;
    all_finite(&out.trajectory, "trajectory.csv")?;
    if let Some(v) = &out.validation {
        all_finite(v, "validation.csv")?;
    }
    Ok(out)
}

/// The scenario of a campaign's draw `values` (display units, the plant's parameter
/// order) as it runs: each value written into `[plant]`, and a slew parameter's input
/// scaled ([`Plant::slew_parameter`]), so that the file reruns to the draw's figures.
pub fn drawn_scenario(spec: &ScenarioSpec, values: &[f64]) -> Result<ScenarioSpec> {
    struct Drawn<'a>(&'a ScenarioSpec, &'a [f64]);
    impl WithPlant for Drawn<'_> {
        type Output = ScenarioSpec;
        fn with<P: Plant>(self, nominal: P) -> Result<ScenarioSpec> {
            let (spec, values) = (self.0, self.1);
            let mut run = spec.clone();
            run.input = slew_scaled(&nominal, spec, Some(values)).into_owned();
            for (p, v) in nominal.parameters().iter().zip(values) {
                run.plant.parameters.insert(p.name.to_string(), *v);
            }
            Ok(run)
        }
    }
    with_kind(&spec.plant.kind, Drawn(spec, values))
}

/// `spec`'s inputs, with a campaign's draw of the plant's slew parameter
/// ([`Plant::slew_parameter`]) applied: that input's trapezoids' slew scaled by the drawn
/// value's ratio to the scenario's (as the pump's campaigns have drawn the demand's slew).
fn slew_scaled<'a, P: Plant>(
    plant: &P,
    spec: &'a ScenarioSpec,
    parameters: Option<&[f64]>,
) -> std::borrow::Cow<'a, std::collections::BTreeMap<String, crate::signal::SignalSpec>> {
    use crate::signal::SignalSpec;
    let scaled = (|| {
        let (i, k) = plant.slew_parameter()?;
        let p = plant.parameters().get(i)?;
        let drawn = *parameters?.get(i)?;
        let given = spec.plant.parameters.get(p.name).copied().unwrap_or(p.nominal);
        let name = plant.inputs().get(k)?.name;
        let mut input = spec.input.clone();
        if let Some(SignalSpec::Trapezoids { slew_per_s, .. }) = input.get_mut(name) {
            *slew_per_s *= drawn / given;
        }
        Some(input)
    })();
    match scaled {
        Some(input) => std::borrow::Cow::Owned(input),
        None => std::borrow::Cow::Borrowed(&spec.input),
    }
}

/// A warning when the run starts with the plant's floor state below its floor (the
/// pump's pressure below P_min), where its model is not valid.
fn below_floor_at_start<P: Plant>(plant: &P, x0: &[f64]) -> Option<String> {
    let (i, floor) = plant.floor()?;
    let (q, v) = (plant.states().get(i)?, *x0.get(i)?);
    (v < floor).then(|| {
        format!(
            "plant.initial: {} starts at {} {u}, below the {}'s floor of {} {u}: its model is not valid there",
            q.name,
            crate::metrics::sig(q.to_display(v), 4),
            plant.name(),
            crate::metrics::sig(q.to_display(floor), 4),
            u = q.display_unit
        )
    })
}

/// The plant's inputs at t = 0 (SI): the profiles', and a `[control]` loop's input at rest
/// ([`super::plant_control::rest_input`]).
fn inputs_at_start<P: Plant>(plant: &P, spec: &ScenarioSpec) -> Vec<f64> {
    (0..plant.inputs().len())
        .map(|k| match &spec.control {
            Some(c) if c.input == plant.inputs()[k].name => super::plant_control::rest_input(plant, c, k),
            _ => plant.input_at(0.0, k),
        })
        .collect()
}

/// The solver's settings of `spec` on `plant`: `[solver]`, over the plant's own defaults
/// ([`Plant::solver_defaults`]: the pump's) or the runner's (`rtol`, atol 1e-9, no step
/// limit).
fn tolerances<P: Plant>(plant: &P, spec: &ScenarioSpec, rtol: f64) -> Result<Tolerances> {
    let defaults = plant
        .solver_defaults()
        .unwrap_or_else(|| SolverDefaults::plant(rtol));
    match &spec.solver {
        Some(s) => s.check(plant.name(), plant.states(), &defaults, spec.duration_s),
        None => Ok(Tolerances::of_defaults(&defaults, plant.states().len())),
    }
}

/// Refuse columns with a value that is not finite, naming the first (column, time): a run
/// never writes NaN or infinity with success, whatever a setting let through.
fn all_finite(columns: &[PlantColumn], file: &str) -> Result<()> {
    for c in columns {
        if let Some(k) = c.values.iter().position(|v| !v.is_finite()) {
            let t = columns
                .first()
                .and_then(|t| t.values.get(k))
                .copied()
                .unwrap_or(f64::NAN);
            return Err(Error::NotFinite {
                what: format!("{file}'s column `{}` at t = {} s ({})", c.name, crate::metrics::sig(t, 6), c.values[k]),
                cause: "a setting far outside its working range (a gain, a scale, an initial guess): check the scenario's controller and identifier settings".into(),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::plant_summary::TIME;
    use super::*;

    #[test]
    fn a_column_with_a_non_finite_value_is_an_error_naming_it_and_the_time() {
        let col = |name: &str, values: Vec<f64>| PlantColumn {
            name: name.into(),
            quantity: TIME,
            values,
            input: false,
        };
        let ok = [col("t", vec![0.0, 1.0]), col("w1_norm", vec![0.5, 0.7])];
        assert!(all_finite(&ok, "trajectory.csv").is_ok());
        let bad = [col("t", vec![0.0, 1.0]), col("w1_norm", vec![0.5, f64::INFINITY])];
        let e = all_finite(&bad, "trajectory.csv").unwrap_err().to_string();
        assert!(e.contains("column `w1_norm` at t = 1 s"), "{e}");
    }
}
