//! A plant scenario's `[identifier]` experiment: the online identification, then its
//! frozen model's free run on the `[validation]` inputs (or, without that section, its
//! series-parallel and free runs on the training inputs again, as the thesis validates),
//! their figures per state and the columns of `trajectory.csv` and `validation.csv`.

use super::any_plant::{identify, IdentRun, Weights};
use super::ident_figures::ModelFile;
use super::plant_summary::{
    time_and_inputs, IdentStateFigures, PlantColumn, PlantRunOutput, PlantSummary, WholeRunFigures,
};
use super::scenario::{drive, ScenarioSpec};
use super::solver_spec::Tolerances;
use crate::error::{invalid, Result};
use crate::plant::{Plant, Quantity};

pub(super) fn run_identification<P: Plant>(
    plant: P,
    x0: &[f64],
    spec: &ScenarioSpec,
    ident: &crate::ident::IdentifierSpec,
    mut summary: PlantSummary,
    tol: &Tolerances,
) -> Result<PlantRunOutput> {
    let is = ident.check_for(&plant)?;
    // Refused now, not after tens of seconds of stepping.
    ident.check_pole_speed(spec.duration_s, "duration_s")?;
    // (A validation's duration out of its own bounds is refused below, by its own name.)
    let valid = |d: f64| d.is_finite() && d > 0.0 && d / spec.output_interval_s <= 1e7;
    if let Some(v) = spec.validation.as_ref().filter(|v| valid(v.duration_s)) {
        ident.check_pole_speed(v.duration_s, "validation.duration_s")?;
    }
    let sampling = (spec.duration_s, spec.output_interval_s);
    // Each epoch runs the record again, its weights starting where the last ended; the
    // figures and columns are the last epoch's.
    let mut train = identify(plant.clone(), x0, &is, sampling, Weights::Initial, tol)?;
    summary.solver.add(train.stats);
    for _ in 1..is.epochs {
        train = identify(
            plant.clone(),
            x0,
            &is,
            sampling,
            Weights::From(&train.weights),
            tol,
        )?;
        summary.solver.add(train.stats);
    }
    summary.floor = train.floor.take();
    let validation = frozen_run(&plant, x0, spec, &is, &train.weights, tol)?;
    if let Some(v) = &validation {
        summary.solver.add(v.stats);
    }
    // Without `[validation]`, the frozen model runs again on the training inputs.
    let same_data = spec.validation.is_none() && validation.is_some();
    let quantities: Vec<Quantity> = is.states.iter().map(|s| *s.quantity(&plant)).collect();
    let half = spec.duration_s / 2.0;
    let (tr_rms, tr_fit) = (train.rms_after(half), train.fit_percent_after(half));
    let after = validation
        .as_ref()
        .map(|v| v.t.last().copied().unwrap_or(0.0) / 10.0)
        .unwrap_or(0.0);
    let sp = validation.as_ref().filter(|_| same_data).map(|v| {
        let sp = IdentRun {
            y_hat: v.y_hat_series_parallel.clone(),
            ..v.clone()
        };
        (sp.rms_after(after), sp.fit_percent_after(after))
    });
    let mut figs = Vec::new();
    for (k, q) in quantities.iter().enumerate() {
        let (v_rms, v_fit) = match &validation {
            Some(v) => (
                Some(q.to_display(v.rms_after(after)[k])),
                Some(v.fit_percent_after(after)[k]),
            ),
            None => (None, None),
        };
        let (sp_rms, sp_fit) = match &sp {
            Some((rms, fit)) => (Some(q.to_display(rms[k])), Some(fit[k])),
            None => (None, None),
        };
        figs.push(IdentStateFigures {
            state: q.name,
            unit: q.display_unit,
            training_rms_error: q.to_display(tr_rms[k]),
            training_fit_percent: tr_fit[k],
            validation_rms_error: v_rms,
            validation_fit_percent: v_fit,
            series_parallel_rms_error: sp_rms,
            series_parallel_fit_percent: sp_fit,
            final_weight_norm: train.weights[k].iter().map(|w| w * w).sum::<f64>().sqrt(),
            whole_run: WholeRunFigures {
                training: train.whole_run[0][k].clone(),
                series_parallel: validation
                    .as_ref()
                    .filter(|_| same_data)
                    .map(|v| v.whole_run[0][k].clone()),
                free_run: validation.as_ref().map(|v| v.whole_run[1][k].clone()),
            },
        });
        summary.findings.push(finding(q.name, tr_fit[k], v_fit, sp_fit));
    }
    summary.identification = Some(figs);
    let inputs: Vec<&Quantity> = plant.inputs().iter().collect();
    let trajectory = ident_columns(&spec.input, &train, (&quantities, &inputs), false)?;
    let validation = match (&validation, &spec.validation) {
        (Some(v), Some(vs)) => Some(ident_columns(&vs.input, v, (&quantities, &inputs), false)?),
        (Some(v), None) => Some(ident_columns(&spec.input, v, (&quantities, &inputs), true)?),
        _ => None,
    };
    let name = |s: &crate::plant::SignalRef| s.name_in(plant.states(), plant.inputs());
    Ok(PlantRunOutput {
        summary,
        trajectory,
        validation,
        model: Some(ModelFile::of(&is, name, train.weights)),
        duration_s: spec.duration_s,
        floor: None,
    })
}

/// The frozen model's run: on the inputs of `[validation]` when there is one, else, with
/// `validate = true`, on the training inputs again (as the thesis validates the pump's):
/// its free run and, from the same integration, its series-parallel estimate.
fn frozen_run<P: Plant>(
    plant: &P,
    x0: &[f64],
    spec: &ScenarioSpec,
    is: &crate::ident::IdentSettings,
    weights: &[Vec<f64>],
    tol: &Tolerances,
) -> Result<Option<IdentRun>> {
    let Some(v) = &spec.validation else {
        if !is.validate {
            return Ok(None);
        }
        let sampling = (spec.duration_s, spec.output_interval_s);
        return identify(plant.clone(), x0, is, sampling, Weights::Frozen(weights), tol).map(Some);
    };
    if !is.validate {
        return Err(invalid(
            "validation",
            "a section",
            "absent with identifier.validate = false (no frozen-weight run), or validate = true",
        ));
    }
    // As many output samples as the run may hold (check_times' bound).
    if !(v.duration_s.is_finite() && v.duration_s > 0.0 && v.duration_s / spec.output_interval_s <= 1e7) {
        return Err(invalid(
            "validation.duration_s",
            v.duration_s,
            "finite, > 0 and at most 10,000,000 output intervals (output_interval_s)",
        ));
    }
    let p = drive(plant.clone(), &v.input, "validation.input", v.duration_s)?;
    let sampling = (v.duration_s, spec.output_interval_s);
    identify(p, x0, is, sampling, Weights::Frozen(weights), tol).map(Some)
}

/// A state's finding: its fit while learning, and the frozen model's (free run on the
/// validation inputs, or series-parallel and free run on the training inputs again), with
/// what the free run says of the model.
fn finding(state: &str, training: f64, free_run: Option<f64>, series_parallel: Option<f64>) -> String {
    let verdict = |f: f64| {
        if f >= 80.0 {
            "the frozen model runs on its own"
        } else if f >= 0.0 {
            "the frozen model runs on its own only roughly"
        } else {
            "the model tracks while it adapts but does not run on its own: its frozen weights describe little more than the last operating point"
        }
    };
    match (free_run, series_parallel) {
        (Some(f), Some(sp)) => format!(
            "{state}: fit {training:.1} % while learning online (second half); with frozen weights on the same inputs {sp:.1} % series-parallel, {f:.1} % running free: {}",
            verdict(f)
        ),
        (Some(f), None) => format!(
            "{state}: fit {training:.1} % while learning online (second half), {f:.1} % running free with frozen weights on the validation inputs: {}",
            verdict(f)
        ),
        _ => format!("{state}: fit {training:.1} % while learning online (second half)"),
    }
}

/// Columns of an identification run: time, each input as the scenario gives it, each
/// identified state and its estimate (`<state>_hat`); for the frozen model run again on the
/// training inputs (`both`), its series-parallel and its free-run estimates instead (the
/// names of the pump's validation.csv).
fn ident_columns(
    inputs_spec: &std::collections::BTreeMap<String, crate::signal::SignalSpec>,
    run: &IdentRun,
    (quantities, inputs): (&[Quantity], &[&Quantity]),
    both: bool,
) -> Result<Vec<PlantColumn>> {
    let mut cols = time_and_inputs(inputs_spec, &run.t, inputs)?;
    for (k, q) in quantities.iter().enumerate() {
        let mut named = vec![(q.name.to_string(), &run.y[k])];
        if both {
            named.push((
                format!("{}_hat_series_parallel", q.name),
                &run.y_hat_series_parallel[k],
            ));
            named.push((format!("{}_hat_parallel", q.name), &run.y_hat[k]));
        } else {
            named.push((format!("{}_hat", q.name), &run.y_hat[k]));
        }
        for (name, values) in named {
            cols.push(PlantColumn {
                name,
                quantity: *q,
                values: values.clone(),
                input: false,
            });
        }
    }
    Ok(cols)
}
