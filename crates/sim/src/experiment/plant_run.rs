//! Running a [`ScenarioSpec`] on any [`Plant`]: an online identification (then its
//! frozen model's free run on other inputs), or a controller and its baseline on
//! identical plants. Produces columns (SI) and a summary (display units) that the
//! report crate writes as trajectory.csv, validation.csv, summary.json and plots.

use super::any_plant::{closed_loop_with, identify, IdentRun, LoopRun, IDENTIFY_RTOL, LOOP_RTOL};
use super::scenario::{configure, drive, loop_conditions, signal, state_index, ScenarioSpec};
use super::solver_spec::{SolverDefaults, Tolerances};
use crate::control::LoopContext;
use crate::error::{invalid, Error, Result};
use crate::plant::{with_kind, Plant, Quantity, WithPlant};
use serde::Serialize;

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
#[derive(Debug, Clone, PartialEq, Serialize)]
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
    /// |w| of the neuron at the end of training.
    pub final_weight_norm: f64,
}

/// Figures of one controller (display units of the regulated state).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LoopFigures {
    /// Controller.
    pub controller: &'static str,
    /// Integral of |y - r| \[unit s\].
    pub iae: f64,
    /// Integral of (y - r)^2 \[unit^2 s\].
    pub ise: f64,
    /// y - r at the end \[unit\].
    pub final_error: f64,
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

/// `summary.json` of a plant scenario.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlantSummary {
    /// rhonn's version.
    pub rhonn_version: &'static str,
    /// Scenario name.
    pub scenario: String,
    /// The plant.
    pub plant: &'static str,
    /// Its parameters as run (display units, the unit in the name).
    pub parameters: Vec<(String, f64)>,
    /// Identification figures per identified state.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub identification: Option<Vec<IdentStateFigures>>,
    /// The regulated state and its unit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub regulated: Option<(&'static str, &'static str)>,
    /// The controller's and the baseline's figures.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub control: Option<[LoopFigures; 2]>,
    /// What the figures say, in words.
    pub findings: Vec<String>,
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
            if let Some(f) = s.validation_fit_percent {
                v.push((format!("{}_validation_fit_percent", s.state), f));
            }
        }
        for (role, f) in ["controller", "baseline"]
            .iter()
            .zip(self.control.iter().flatten())
        {
            v.push((format!("{role}_iae"), f.iae));
            v.push((format!("{role}_ise"), f.ise));
            v.push((format!("{role}_final_error"), f.final_error));
            v.push((format!("{role}_input_total_variation"), f.input_total_variation));
            v.push((format!("{role}_time_input_switching_s"), f.time_input_switching_s));
        }
        v
    }
}

/// The controller's actuator activity beside the baseline's, in words.
fn activity_finding(a: &LoopFigures, b: &LoopFigures, unit: &str) -> String {
    let unit = shown_unit(unit);
    format!(
        "{}: the input moved {}{unit} in all (total variation; RMS change per control period {}{unit}) against {}{unit} (RMS change {}{unit}) for the baseline {}; at a bound {} s against {} s, switching between the bounds {} s against {} s",
        a.controller,
        crate::metrics::sig(a.input_total_variation, 3),
        crate::metrics::sig(a.input_rms_change_per_sample, 3),
        crate::metrics::sig(b.input_total_variation, 3),
        crate::metrics::sig(b.input_rms_change_per_sample, 3),
        b.controller,
        crate::metrics::sig(a.time_input_saturated_s, 4),
        crate::metrics::sig(b.time_input_saturated_s, 4),
        crate::metrics::sig(a.time_input_switching_s, 4),
        crate::metrics::sig(b.time_input_switching_s, 4),
    )
}

/// The loop's conditions in words, when it is not clean: what both controllers faced.
fn conditions_finding<P: Plant>(
    plant: &P,
    c: &super::scenario::ControlSpec,
    spec: &ScenarioSpec,
    qu: &Quantity,
) -> Option<String> {
    let mut parts = Vec::new();
    if let Some(m) = &spec.measurement {
        let noise: Vec<String> = plant
            .states()
            .iter()
            .filter_map(|q| {
                let std = m.noise_std.get(q.name)?;
                Some(format!(
                    "{} {}{}",
                    q.name,
                    crate::metrics::sig(*std, 3),
                    shown_unit(q.display_unit)
                ))
            })
            .collect();
        parts.push(format!(
            "sensor noise (standard deviation) {} (seed {})",
            noise.join(", "),
            m.seed
        ));
    }
    if c.delay_periods > 0 {
        parts.push(format!(
            "the command delayed {} control periods ({} s)",
            c.delay_periods,
            crate::metrics::sig(f64::from(c.delay_periods) * c.period_s, 4)
        ));
    }
    if c.dither.is_some() {
        parts.push(format!("a dither added to the {}", qu.name));
    }
    (!parts.is_empty()).then(|| format!("both controllers ran with {}", parts.join("; ")))
}

/// A unit as printed after a number: none for a dimensionless "1".
fn shown_unit(unit: &str) -> String {
    if unit == "1" {
        String::new()
    } else {
        format!(" {unit}")
    }
}

/// A warning when `r`'s input sits at a bound of `range` over the run's last tenth (at
/// least its last 10 control periods) and the output ends more than 1 % of the
/// set-point's size (of the output's unit if the set-point is 0) away from it: the
/// actuator cannot reach the set-point.
fn limit_warning(
    r: &LoopRun,
    range: (f64, f64),
    (qy, qu): (&Quantity, &Quantity),
    duration_s: f64,
) -> Option<String> {
    let n = r.u.len();
    let tail = (n / 10).max(10).min(n);
    if tail == 0 {
        return None;
    }
    let tol = 1e-9 * (range.1 - range.0);
    let last = &r.u[n - tail..];
    let bound = if last.iter().all(|u| *u >= range.1 - tol) {
        ("upper", range.1)
    } else if last.iter().all(|u| *u <= range.0 + tol) {
        ("lower", range.0)
    } else {
        return None;
    };
    let e = r.final_error();
    let size = r.setpoint.last().map_or(0.0, |v| v.abs());
    let allowed = if size > 0.0 {
        0.01 * size
    } else {
        1.0 / qy.display_per_si
    };
    if !(e.abs() > allowed) {
        return None;
    }
    let at = r.u[..n - tail]
        .iter()
        .rposition(|u| (u - bound.1).abs() > tol)
        .map_or(r.t[0], |k| r.t[k + 1]);
    Some(format!(
        "warning: {} sits at its {} limit ({}{}) from {} s to the end ({} s) and ends {}{} from the set-point: the actuator cannot reach it (widen control.input_range, or give a set-point within reach)",
        r.controller,
        bound.0,
        crate::metrics::sig(qu.to_display(bound.1), 4),
        shown_unit(qu.display_unit),
        crate::metrics::sig(at, 4),
        crate::metrics::sig(duration_s, 4),
        crate::metrics::sig(qy.to_display(e), 3),
        shown_unit(qy.display_unit)
    ))
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
    /// Simulated time \[s\] (the scenario's `duration_s`).
    pub duration_s: f64,
}

const TIME: Quantity = Quantity::si("t", "s", "time");
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

/// Run `spec` with its parameters replaced by `parameters` (display units, in the
/// plant's order) when given: a campaign's draw.
pub fn run_plant_scenario(spec: &ScenarioSpec, parameters: Option<&[f64]>) -> Result<PlantRunOutput> {
    spec.check_common()?;
    struct Run<'a>(&'a ScenarioSpec, Option<&'a [f64]>);
    impl WithPlant for Run<'_> {
        type Output = PlantRunOutput;
        fn with<P: Plant>(self, nominal: P) -> Result<PlantRunOutput> {
            run_on(&nominal, self.0, self.1)
        }
    }
    with_kind(&spec.plant.kind, Run(spec, parameters))
}

/// Run `spec` on your own `plant` (any [`Plant`]; `spec.plant.kind` only names it): the
/// same experiment, figures and findings as a shipped plant's scenario, for
/// `rhonn_report::write_plant_run` to write as `rhonn run` does (`examples/custom_plant.rs`).
pub fn run_plant_scenario_on<P: Plant>(plant: &P, spec: &ScenarioSpec) -> Result<PlantRunOutput> {
    spec.check_common()?;
    run_on(plant, spec, None)
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

fn run_on<P: Plant>(nominal: &P, spec: &ScenarioSpec, parameters: Option<&[f64]>) -> Result<PlantRunOutput> {
    let (mut plant, x0) = configure(nominal, &spec.plant)?;
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
    let summary = PlantSummary {
        rhonn_version: env!("CARGO_PKG_VERSION"),
        scenario: spec.name.clone(),
        plant: plant.name(),
        parameters: plant
            .parameters()
            .iter()
            .map(|p| p.name.to_string())
            .zip(used)
            .collect(),
        identification: None,
        regulated: None,
        control: None,
        findings: Vec::new(),
    };
    let plant = drive(plant, &spec.input, "input")?;
    let out = match &spec.identifier {
        Some(ident) => run_identification(plant, &x0, spec, ident, summary)?,
        None => run_control(plant, &x0, spec, summary)?,
    };
    all_finite(&out.trajectory, "trajectory.csv")?;
    if let Some(v) = &out.validation {
        all_finite(v, "validation.csv")?;
    }
    Ok(out)
}

/// The solver's settings of `spec` on `plant` (`[solver]`, else the runner's: `rtol`,
/// atol 1e-9, no step limit).
fn tolerances<P: Plant>(plant: &P, spec: &ScenarioSpec, rtol: f64) -> Result<Tolerances> {
    let defaults = SolverDefaults::plant(rtol);
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

/// The input `c` drives (its index) and its range in SI, checked.
fn control_input<P: Plant>(plant: &P, c: &super::scenario::ControlSpec) -> Result<(usize, (f64, f64))> {
    let k = plant
        .inputs()
        .iter()
        .position(|q| q.name == c.input)
        .ok_or_else(|| {
            invalid(
                "control.input",
                format!("\"{}\"", c.input),
                "an input of the plant",
            )
        })?;
    let qu = &plant.inputs()[k];
    let range = (
        c.input_range[0] / qu.display_per_si,
        c.input_range[1] / qu.display_per_si,
    );
    if !(range.0.is_finite() && range.1.is_finite() && range.0 < range.1) {
        return Err(invalid(
            "control.input_range",
            format!("{:?}", c.input_range),
            "[min, max] with min < max",
        ));
    }
    Ok((k, range))
}

/// The `[control]` experiment: the controller and the baseline, each on an identical
/// plant from `x0`.
fn run_control<P: Plant>(
    plant: P,
    x0: &[f64],
    spec: &ScenarioSpec,
    mut summary: PlantSummary,
) -> Result<PlantRunOutput> {
    let c = spec
        .control
        .as_ref()
        .ok_or_else(|| invalid("control", "none", "a [control] section"))?;
    let (k, range) = control_input(&plant, c)?;
    let qu = &plant.inputs()[k];
    let y = state_index(&plant, "control.output", &c.output)?;
    let qy = plant.states()[y];
    if !(c.period_s.is_finite() && c.period_s > 0.0 && c.period_s <= spec.duration_s) {
        return Err(invalid(
            "control.period_s",
            c.period_s,
            "finite, > 0 and at most duration_s",
        ));
    }
    check_control_periods(spec.duration_s, c.period_s)?;
    // Bounded so that the error's integrals (IAE, ISE) stay finite.
    let sp = signal(&c.setpoint, "control.setpoint", &qy, (-1e150, 1e150))?;
    let conditions = loop_conditions(&plant, spec, c, qu, range)?;
    let tol = tolerances(&plant, spec, LOOP_RTOL)?;
    let baseline = c.baseline.as_ref().ok_or_else(|| {
        invalid(
            "control.baseline",
            "missing",
            "the controller the one under test is compared with, run on an identical plant",
        )
    })?;
    let mut runs = Vec::new();
    for (field, l) in [
        ("control.controller", &c.controller),
        ("control.baseline", baseline),
    ] {
        if l.state() != c.output {
            return Err(invalid(
                format!("{field}.state"),
                format!("\"{}\"", l.state()),
                format!("the regulated state \"{}\"", c.output),
            ));
        }
        let cx = LoopContext {
            plant: plant.name(),
            states: plant.states(),
            field: field.to_string(),
            output: qu,
            range,
            period_s: c.period_s,
            setpoint0: sp.eval(0.0),
            x0,
        };
        let mut ctl = l.build(&cx)?;
        runs.push(closed_loop_with(
            plant.clone(),
            x0,
            ctl.as_mut(),
            k,
            (&sp, c.period_s, spec.duration_s),
            &conditions,
            &tol,
        )?);
    }
    let figs = |r: &LoopRun| {
        let act = crate::activity::activity(&r.u, range, c.period_s);
        LoopFigures {
            controller: r.controller,
            iae: qy.to_display(r.iae),
            ise: qy.to_display(qy.to_display(r.ise)),
            final_error: qy.to_display(r.final_error()),
            time_input_saturated_s: act.time_saturated_s,
            input_total_variation: qu.to_display(act.total_variation),
            input_rms_change_per_sample: qu.to_display(act.rms_change_per_sample),
            time_input_switching_s: act.time_switching_s,
        }
    };
    let [a, b] = [figs(&runs[0]), figs(&runs[1])];
    summary.findings.extend(conditions_finding(&plant, c, spec, qu));
    summary.findings.push(format!(
        "{}: IAE {:.1} {u} s against {:.1} for the baseline {} ({:+.1} %); final error {:.3} against {:.3} {u}",
        a.controller,
        a.iae,
        b.iae,
        b.controller,
        100.0 * (a.iae / b.iae - 1.0),
        a.final_error,
        b.final_error,
        u = qy.display_unit
    ));
    summary.findings.push(activity_finding(&a, &b, qu.display_unit));
    for r in &runs {
        summary
            .findings
            .extend(limit_warning(r, range, (&qy, qu), spec.duration_s));
    }
    summary.regulated = Some((qy.name, qy.display_unit));
    summary.control = Some([a, b]);
    let inner = [&c.controller, baseline].map(|l| {
        let s = l.inner_state()?;
        plant.states().iter().find(|q| q.name == s).copied()
    });
    let trajectory = loop_columns(&plant, &runs, &qy, qu, inner);
    Ok(PlantRunOutput {
        summary,
        trajectory,
        validation: None,
        duration_s: spec.duration_s,
    })
}

fn loop_columns<P: Plant>(
    plant: &P,
    runs: &[LoopRun],
    qy: &Quantity,
    qu: &Quantity,
    inner: [Option<Quantity>; 2],
) -> Vec<PlantColumn> {
    let col = |name: String, quantity: Quantity, values: Vec<f64>| PlantColumn {
        name,
        quantity,
        values,
        input: false,
    };
    let mut cols = vec![
        col("t".into(), TIME, runs[0].t.clone()),
        col(format!("{}_ref", qy.name), *qy, runs[0].setpoint.clone()),
    ];
    for ((run, suffix), inner) in runs.iter().zip(["", "_baseline"]).zip(inner) {
        for (q, v) in plant.states().iter().zip(&run.states) {
            cols.push(col(format!("{}{suffix}", q.name), *q, v.clone()));
        }
        cols.push(PlantColumn {
            input: true,
            ..col(format!("{}{suffix}", qu.name), *qu, run.u.clone())
        });
        if !run.y_measured.is_empty() {
            cols.push(col(
                format!("{}_measured{suffix}", qy.name),
                *qy,
                run.y_measured.clone(),
            ));
        }
        if let (false, Some(q)) = (run.inner_reference.is_empty(), inner) {
            cols.push(col(
                format!("{}_ref{suffix}", q.name),
                q,
                run.inner_reference.clone(),
            ));
        }
        if !run.weights.is_empty() {
            let w = |k: usize| run.weights.iter().map(|v| v[k]).collect::<Vec<f64>>();
            let [wq, w1q, ballq] = WEIGHT_QUANTITIES;
            cols.push(col(format!("w_norm{suffix}"), wq, w(0)));
            cols.push(col(format!("w1_norm{suffix}"), w1q, w(1)));
            cols.push(col(format!("w1_distance{suffix}"), ballq, w(2)));
            cols.push(col(format!("w1_ball_radius{suffix}"), ballq, w(3)));
        }
    }
    cols
}

fn run_identification<P: Plant>(
    plant: P,
    x0: &[f64],
    spec: &ScenarioSpec,
    ident: &crate::ident::IdentifierSpec,
    mut summary: PlantSummary,
) -> Result<PlantRunOutput> {
    let is = ident.check_for(&plant)?;
    let tol = tolerances(&plant, spec, IDENTIFY_RTOL)?;
    let sampling = (spec.duration_s, spec.output_interval_s);
    let train = identify(plant.clone(), x0, &is, sampling, None, &tol)?;
    let validation = match &spec.validation {
        Some(v) => {
            // As many output samples as the run may hold (check_times' bound).
            if !(v.duration_s.is_finite()
                && v.duration_s > 0.0
                && v.duration_s / spec.output_interval_s <= 1e7)
            {
                return Err(invalid(
                    "validation.duration_s",
                    v.duration_s,
                    "finite, > 0 and at most 10,000,000 output intervals (output_interval_s)",
                ));
            }
            let p = drive(plant.clone(), &v.input, "validation.input")?;
            let sampling = (v.duration_s, spec.output_interval_s);
            Some(identify(p, x0, &is, sampling, Some(&train.weights), &tol)?)
        }
        None => None,
    };
    let quantities: Vec<Quantity> = is.states.iter().map(|s| *s.quantity(&plant)).collect();
    let half = spec.duration_s / 2.0;
    let (tr_rms, tr_fit) = (train.rms_after(half), train.fit_percent_after(half));
    let after = validation
        .as_ref()
        .map(|v| v.t.last().copied().unwrap_or(0.0) / 10.0)
        .unwrap_or(0.0);
    let mut figs = Vec::new();
    for (k, q) in quantities.iter().enumerate() {
        let (v_rms, v_fit) = match &validation {
            Some(v) => (
                Some(q.to_display(v.rms_after(after)[k])),
                Some(v.fit_percent_after(after)[k]),
            ),
            None => (None, None),
        };
        figs.push(IdentStateFigures {
            state: q.name,
            unit: q.display_unit,
            training_rms_error: q.to_display(tr_rms[k]),
            training_fit_percent: tr_fit[k],
            validation_rms_error: v_rms,
            validation_fit_percent: v_fit,
            final_weight_norm: train.weights[k].iter().map(|w| w * w).sum::<f64>().sqrt(),
        });
        summary.findings.push(match v_fit {
            Some(f) => format!(
                "{}: fit {:.1} % while learning online (second half), {f:.1} % running free with frozen weights on the validation inputs",
                q.name, tr_fit[k]
            ),
            None => format!("{}: fit {:.1} % while learning online (second half)", q.name, tr_fit[k]),
        });
    }
    summary.identification = Some(figs);
    let inputs: Vec<&Quantity> = plant.inputs().iter().collect();
    let trajectory = ident_columns(&spec.input, &train, &quantities, &inputs)?;
    let validation = match (&validation, &spec.validation) {
        (Some(v), Some(vs)) => Some(ident_columns(&vs.input, v, &quantities, &inputs)?),
        _ => None,
    };
    Ok(PlantRunOutput {
        summary,
        trajectory,
        validation,
        duration_s: spec.duration_s,
    })
}

/// Columns of an identification run: time, each input as the scenario gives it, each
/// identified state and its estimate.
fn ident_columns(
    inputs_spec: &std::collections::BTreeMap<String, crate::signal::SignalSpec>,
    run: &IdentRun,
    quantities: &[Quantity],
    inputs: &[&Quantity],
) -> Result<Vec<PlantColumn>> {
    let mut cols = vec![PlantColumn {
        name: "t".into(),
        quantity: TIME,
        values: run.t.clone(),
        input: false,
    }];
    for q in inputs {
        let values = match inputs_spec.get(q.name) {
            Some(sp) => {
                let s = signal(sp, q.name, q, (f64::NEG_INFINITY, f64::INFINITY))?;
                run.t.iter().map(|&t| s.eval(t)).collect()
            }
            None => vec![0.0; run.t.len()],
        };
        cols.push(PlantColumn {
            name: q.name.into(),
            quantity: **q,
            values,
            input: true,
        });
    }
    for (k, q) in quantities.iter().enumerate() {
        cols.push(PlantColumn {
            name: q.name.into(),
            quantity: *q,
            values: run.y[k].clone(),
            input: false,
        });
        cols.push(PlantColumn {
            name: format!("{}_hat", q.name),
            quantity: *q,
            values: run.y_hat[k].clone(),
            input: false,
        });
    }
    Ok(cols)
}

/// At most [`MAX_CONTROL_PERIODS`] control periods in a run: a period of nanoseconds
/// would otherwise run until the solver's step budget failed it, naming no setting.
pub(crate) fn check_control_periods(duration_s: f64, period_s: f64) -> Result<()> {
    if duration_s / period_s > MAX_CONTROL_PERIODS {
        return Err(invalid(
            "control.period_s",
            crate::metrics::sig(period_s, 6),
            format!(
                "at most 1,000,000 control periods in the run's duration_s = {} s: a period of at least {} s",
                crate::metrics::sig(duration_s, 6),
                crate::metrics::sig(duration_s / MAX_CONTROL_PERIODS, 3)
            ),
        ));
    }
    Ok(())
}

/// The most control periods a run may hold.
pub(crate) const MAX_CONTROL_PERIODS: f64 = 1e6;

#[cfg(test)]
mod tests {
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
            final_weight_norm: 0.5,
        };
        let json = serde_json::to_string(&f).unwrap();
        assert!(!json.contains("null") && !json.contains("validation"), "{json}");
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
