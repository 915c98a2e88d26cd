//! A plant scenario with neither `[identifier]` nor `[control]`: the plant driven by its
//! `[input]` profiles alone (open loop), sampled every `output_interval_s`. Its columns
//! (time, inputs, states) are data for `rhonn fit` or `rhonn identify`; its summary says
//! where each state started and ended, and its range.

use super::any_plant::simulate;
use super::plant_summary::{time_and_inputs, PlantColumn, PlantRunOutput, PlantSummary, StateRange};
use super::scenario::ScenarioSpec;
use super::solver_spec::Tolerances;
use crate::error::Result;
use crate::metrics::sig;
use crate::plant::Plant;

/// Run `spec`'s plant, driven by its inputs, from `x0`.
pub(super) fn run_open<P: Plant>(
    plant: P,
    x0: &[f64],
    spec: &ScenarioSpec,
    mut summary: PlantSummary,
    tol: &Tolerances,
) -> Result<PlantRunOutput> {
    let (states, input_qs) = (plant.states().to_vec(), plant.inputs().to_vec());
    let plant_internal = plant.internal_states();
    let run = simulate(plant, x0, (spec.duration_s, spec.output_interval_s), tol)?;
    summary.solver.add(run.stats);
    summary.floor = run.floor;
    let inputs: Vec<_> = input_qs.iter().collect();
    let mut trajectory = time_and_inputs(&spec.input, &run.t, &inputs)?;
    let mut ranges = Vec::new();
    let internal = plant_internal;
    for (q, v) in states
        .iter()
        .zip(&run.states)
        .enumerate()
        .filter(|(i, _)| !internal.contains(i))
        .map(|(_, qv)| qv)
    {
        let shown: Vec<f64> = v.iter().map(|x| q.to_display(*x)).collect();
        let (min, max) = shown
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(*x), hi.max(*x))
            });
        let r = StateRange {
            state: q.name,
            unit: q.display_unit,
            initial: shown.first().copied().unwrap_or(f64::NAN),
            final_value: shown.last().copied().unwrap_or(f64::NAN),
            min_value: min,
            max_value: max,
        };
        summary.findings.push(format!(
            "{}: from {} to {} {u} (range {} to {} {u})",
            q.name,
            sig(r.initial, 4),
            sig(r.final_value, 4),
            sig(r.min_value, 4),
            sig(r.max_value, 4),
            u = q.display_unit
        ));
        ranges.push(r);
        trajectory.push(PlantColumn {
            name: q.name.into(),
            quantity: *q,
            values: v.clone(),
            input: false,
        });
    }
    summary.open_loop = Some(ranges);
    Ok(PlantRunOutput {
        summary,
        trajectory,
        validation: None,
        model: None,
        duration_s: spec.duration_s,
        floor: None,
    })
}
