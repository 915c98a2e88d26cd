//! A plant scenario's `[control]` experiment: the controller and its baseline, each on an
//! identical plant under the same loop conditions, their figures (IAE, ISE, final error,
//! actuator activity) and findings, and `trajectory.csv`'s columns.

use super::closed_loop::{closed_loop_with, LoopRun, LoopSamples};
use super::plant_summary::{LoopFigures, PlantColumn, PlantRunOutput, PlantSummary, TIME, WEIGHT_QUANTITIES};
use super::scenario::{loop_conditions, signal, state_index, ScenarioSpec};
use super::solver_spec::Tolerances;
use crate::control::{LoopContext, LoopSpec};
use crate::error::{invalid, Result};
use crate::plant::{Plant, Quantity};

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
        b.label(),
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
    let (lo, hi) = plant.input_range(k);
    // A relative slack of 1e-12: the range given in display units, read back in SI.
    let slack = |v: f64| 1e-12 * v.abs();
    if range.0 < lo - slack(lo) || range.1 > hi + slack(hi) {
        let show = |v: f64| crate::metrics::sig(qu.to_display(v), 4);
        return Err(invalid(
            "control.input_range",
            format!("{:?}", c.input_range),
            format!(
                "within [{}, {}] {}: the range the {} takes its {} in",
                show(lo),
                show(hi),
                qu.display_unit,
                plant.name(),
                qu.name
            ),
        ));
    }
    Ok((k, range))
}

/// The set-point of `c` (on state `y`) within the state's working range at all times:
/// its bounds ([`Plant::state_bounds`]), from its floor up where it has one
/// ([`Plant::floor`]; the pump's pressure in [P_min, P_max]).
fn setpoint_within<P: Plant>(
    plant: &P,
    y: usize,
    c: &super::scenario::ControlSpec,
    duration_s: f64,
) -> Result<()> {
    let (mut lo, hi) = plant.state_bounds()[y];
    if let Some((i, floor)) = plant.floor() {
        if i == y {
            lo = lo.max(floor);
        }
    }
    if !(lo.is_finite() || hi.is_finite()) {
        return Ok(());
    }
    let q = &plant.states()[y];
    let bounded = signal(
        &c.setpoint,
        "control.setpoint",
        q,
        (q.to_display(lo), q.to_display(hi)),
    )?;
    if bounded.clips_on(duration_s) {
        let show = |v: f64| crate::metrics::sig(q.to_display(v), 4);
        return Err(invalid(
            "control.setpoint",
            "a set-point",
            format!(
                "within [{}, {}] {} at all times (the {}'s working range of {})",
                show(lo),
                show(hi),
                q.display_unit,
                plant.name(),
                q.name
            ),
        ));
    }
    Ok(())
}

/// The input `k` that `c` drives, at rest (SI): what its baseline's (else its controller's)
/// settings add at rest, or the plant's operating input. Both loops start from it, and
/// the plant holds it while a delay line fills.
pub(super) fn rest_input<P: Plant>(plant: &P, c: &super::scenario::ControlSpec, k: usize) -> f64 {
    c.baseline
        .as_ref()
        .unwrap_or(&c.controller)
        .bias()
        .map_or(plant.operating_input(k), |b| b / plant.inputs()[k].display_per_si)
}

/// The loop's period, its set-point (on state `y`) within the state's working range, and
/// no `[input]` profile for the input it drives.
fn check_loop<P: Plant>(
    plant: &P,
    spec: &ScenarioSpec,
    c: &super::scenario::ControlSpec,
    y: usize,
) -> Result<()> {
    if !(c.period_s.is_finite() && c.period_s > 0.0 && c.period_s <= spec.duration_s) {
        return Err(invalid(
            "control.period_s",
            c.period_s,
            "finite, > 0 and at most duration_s",
        ));
    }
    check_control_periods(spec.duration_s, c.period_s)?;
    setpoint_within(plant, y, c, spec.duration_s)?;
    if spec.input.contains_key(&c.input) {
        return Err(invalid(
            format!("input.{}", c.input),
            "a profile",
            format!(
                "none with a [control] section (its controller drives the {})",
                c.input
            ),
        ));
    }
    Ok(())
}

/// The `[control]` experiment: the controller and the baseline, each on an identical
/// plant from `x0`.
pub(super) fn run_control<P: Plant>(
    plant: P,
    x0: &[f64],
    spec: &ScenarioSpec,
    mut summary: PlantSummary,
    tol: &Tolerances,
    keep: super::plant_summary::Keep,
) -> Result<PlantRunOutput> {
    let c = spec
        .control
        .as_ref()
        .ok_or_else(|| invalid("control", "none", "a [control] section"))?;
    let (k, range) = control_input(&plant, c)?;
    let qu = &plant.inputs()[k];
    let y = state_index(&plant, "control.output", &c.output)?;
    let qy = plant.states()[y];
    check_loop(&plant, spec, c, y)?;
    // Bounded so that the error's integrals (IAE, ISE) stay finite.
    let sp = signal(&c.setpoint, "control.setpoint", &qy, (-1e150, 1e150))?;
    let mut conditions = loop_conditions(&plant, spec, c, qu, range)?;
    conditions.held_input = Some(rest_input(&plant, c, k));
    // A trajectory finer than the control period comes from the solver's dense output.
    let samples = match keep {
        super::plant_summary::Keep::Summary => LoopSamples::FiguresOnly,
        _ if spec.output_interval_s < c.period_s => LoopSamples::Every(spec.output_interval_s),
        _ => LoopSamples::AtInstants,
    };
    let loops = loops_of(c)?;
    let mut runs = Vec::new();
    for (field, l, _) in &loops {
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
            operating_input: plant.operating_input(k),
        };
        let mut ctl = l.build(&cx)?;
        runs.push(closed_loop_with(
            plant.clone(),
            x0,
            ctl.as_mut(),
            k,
            (&sp, c.period_s, spec.duration_s),
            (&conditions, samples),
            tol,
        )?);
    }
    let figures: Vec<LoopFigures> = runs
        .iter()
        .zip(&loops)
        .map(|(r, (_, _, tuning))| LoopFigures {
            tuning: *tuning,
            ..loop_figures(r, range, (c.period_s, spec.duration_s), (&qy, qu))
        })
        .collect();
    summary.findings.extend(conditions_finding(&plant, c, spec, qu));
    summary.findings.extend(comparison_findings(&figures, &qy, qu));
    for r in &runs {
        summary
            .findings
            .extend(limit_warning(r, range, (&qy, qu), spec.duration_s));
    }
    summary.regulated = Some((qy.name, qy.display_unit));
    summary.control = Some(figures);
    for r in &runs {
        summary.solver.add(r.stats);
    }
    let inner: Vec<Option<Quantity>> = loops
        .iter()
        .map(|(_, l, _)| {
            let s = l.inner_state()?;
            plant.states().iter().find(|q| q.name == s).copied()
        })
        .collect();
    let trajectory = match keep {
        super::plant_summary::Keep::Columns => loop_columns(&plant, runs, &qy, qu, &inner),
        super::plant_summary::Keep::Summary => Vec::new(),
    };
    Ok(PlantRunOutput {
        summary,
        trajectory,
        validation: None,
        model: None,
        duration_s: spec.duration_s,
        floor: None,
    })
}

/// The loops of `c`, each on an identical plant: the controller, its baseline if given,
/// and a second baseline (a stored tuning of the baseline's kind), with their fields.
fn loops_of(c: &super::scenario::ControlSpec) -> Result<Vec<(&'static str, LoopSpec, Option<&'static str>)>> {
    let mut loops = vec![("control.controller", c.controller.clone(), None)];
    // A controller's own default comparison when `[control]` names no baseline.
    let baseline = c
        .baseline
        .clone()
        .or_else(|| c.controller.settings().default_baseline());
    if let Some(b) = &baseline {
        loops.push(("control.baseline", b.clone(), None));
    }
    if let Some(name) = &c.second_baseline {
        let Some(b) = &baseline else {
            return Err(invalid(
                "control.second_baseline",
                format!("\"{name}\""),
                "beside a [control.baseline] (a stored tuning of the baseline's kind)",
            ));
        };
        let tunings = b.settings().tunings();
        let Some((l, t)) = tunings
            .iter()
            .find(|t| **t == name.as_str())
            .and_then(|t| Some((b.settings().tuning(t)?, *t)))
        else {
            return Err(invalid(
                "control.second_baseline",
                format!("\"{name}\""),
                if tunings.is_empty() {
                    format!("none: the baseline's kind `{}` has no stored tuning", b.name())
                } else {
                    format!(
                        "a stored tuning of the baseline's kind `{}`: {}",
                        b.name(),
                        tunings.join(", ")
                    )
                },
            ));
        };
        loops.push(("control.second_baseline", l, Some(t)));
    }
    Ok(loops)
}

/// The controller's figures beside each baseline's, in words.
fn comparison_findings(f: &[LoopFigures], qy: &Quantity, qu: &Quantity) -> Vec<String> {
    let sig = crate::metrics::sig;
    let Some((a, baselines)) = f.split_first() else {
        return Vec::new();
    };
    let u = qy.display_unit;
    if baselines.is_empty() {
        let iu = shown_unit(qu.display_unit);
        return vec![
            format!(
                "{}: IAE {} {u} s; final error {} {u}; within 1 % of the set-point {} % of the run; largest deviation from {} s after each set-point change {} {u}",
                a.label(),
                sig(a.iae, 4),
                sig(a.final_error, 3),
                sig(a.within_1pct_percent, 3),
                sig(a.settle_s, 3),
                sig(a.max_abs_deviation_settled, 3)
            ),
            format!(
                "{}: the input moved {}{iu} in all (total variation; RMS change per control period {}{iu}), at a bound {} s, switching between the bounds {} s",
                a.label(),
                sig(a.input_total_variation, 4),
                sig(a.input_rms_change_per_sample, 3),
                sig(a.time_input_saturated_s, 3),
                sig(a.time_input_switching_s, 3)
            ),
        ];
    }
    let mut v = Vec::new();
    for b in baselines {
        v.push(format!(
            "{}: IAE {} {u} s against {} for the baseline {} ({:+.1} %); final error {} against {} {u}",
            a.label(),
            sig(a.iae, 4),
            sig(b.iae, 4),
            b.label(),
            100.0 * (a.iae / b.iae - 1.0),
            sig(a.final_error, 3),
            sig(b.final_error, 3),
        ));
        v.extend(figure_lines(a, b, u));
        v.push(activity_finding(a, b, qu.display_unit));
    }
    v
}

/// One line per tracking figure of the controller `a` against the baseline `b`: both
/// numbers and which is better.
fn figure_lines(a: &LoopFigures, b: &LoopFigures, u: &str) -> Vec<String> {
    let sig = crate::metrics::sig;
    let line = |what: String, va: f64, vb: f64, unit: &str, lower_better: bool| {
        // Equal as printed is equal (to 4 significant digits).
        let verdict = if sig(va, 4) == sig(vb, 4) {
            "equal".to_string()
        } else if (va < vb) == lower_better {
            format!("{} better", a.label())
        } else {
            format!("{} better", b.label())
        };
        format!(
            "{what}: {} {} {unit}, {} {} {unit} ({verdict})",
            a.label(),
            sig(va, 4),
            b.label(),
            sig(vb, 4)
        )
    };
    let over = |f: &LoopFigures| f.overshoot_percent.iter().fold(0.0f64, |m, &o| m.max(o));
    let mut v = vec![
        line("ISE".into(), a.ise, b.ise, &format!("{u}^2 s"), true),
        line(
            format!(
                "largest deviation from {} s after each set-point change",
                sig(a.settle_s / 10.0, 3)
            ),
            a.max_abs_deviation_early,
            b.max_abs_deviation_early,
            u,
            true,
        ),
        line(
            format!(
                "largest deviation from {} s after each set-point change",
                sig(a.settle_s, 3)
            ),
            a.max_abs_deviation_settled,
            b.max_abs_deviation_settled,
            u,
            true,
        ),
        line(
            "largest overshoot of a set-point step".into(),
            over(a),
            over(b),
            "%",
            true,
        ),
        line(
            "share of the run within 1 % of the set-point".into(),
            a.within_1pct_percent,
            b.within_1pct_percent,
            "%",
            false,
        ),
    ];
    if let (Some(fa), Some(fb)) = (
        a.time_below_floor_after_settle_s,
        b.time_below_floor_after_settle_s,
    ) {
        v.push(line(
            format!("time below the plant's floor from {} s on", sig(a.settle_s, 3)),
            fa,
            fb,
            "s",
            true,
        ));
    }
    v
}

/// A loop's figures in display units: the regulated state's errors and the input's
/// activity over `range` at the control period `period_s`, over a run of `duration_s`.
fn loop_figures(
    r: &LoopRun,
    range: (f64, f64),
    (period_s, duration_s): (f64, f64),
    (qy, qu): (&Quantity, &Quantity),
) -> LoopFigures {
    let act = crate::activity::activity(&r.u, range, period_s);
    LoopFigures {
        controller: r.controller,
        tuning: None,
        iae: qy.to_display(r.iae),
        ise: qy.to_display(qy.to_display(r.ise)),
        final_error: qy.to_display(r.final_error()),
        max_abs_deviation: qy.to_display(r.tracking.max_abs_deviation),
        max_abs_deviation_settled: qy.to_display(r.tracking.max_abs_deviation_settled),
        settle_s: r.tracking.settle_s,
        max_abs_deviation_early: qy.to_display(r.tracking.max_abs_deviation_early),
        time_within_1pct_s: r.tracking.time_within_1pct_s,
        within_1pct_percent: 100.0 * r.tracking.time_within_1pct_s / duration_s,
        overshoot_percent: r.tracking.overshoot_percent.clone(),
        time_below_floor_s: r.tracking.time_below_floor_s,
        time_below_floor_after_settle_s: r.tracking.time_below_floor_after_settle_s,
        states_bounded: r.tracking.states_bounded,
        adaptive: r.adaptive.clone(),
        time_input_saturated_s: act.time_saturated_s,
        input_total_variation: qu.to_display(act.total_variation),
        input_rms_change_per_sample: qu.to_display(act.rms_change_per_sample),
        time_input_switching_s: act.time_switching_s,
    }
}

/// The suffix of each loop's columns: the controller's, the baseline's, the second
/// baseline's.
const LOOP_SUFFIXES: [&str; 3] = ["", "_baseline", "_second_baseline"];

/// `trajectory.csv`'s columns: at the control instants, or at the output instants of the
/// dense output (the states there; the set-point, input, measurement, inner set-point and
/// weights as held since the last control instant).
fn loop_columns<P: Plant>(
    plant: &P,
    mut runs: Vec<LoopRun>,
    qy: &Quantity,
    qu: &Quantity,
    inner: &[Option<Quantity>],
) -> Vec<PlantColumn> {
    let col = |name: String, quantity: Quantity, values: Vec<f64>| PlantColumn {
        name,
        quantity,
        values,
        input: false,
    };
    // Per run: its instant-held values on the output grid (moved out of the run when the
    // grid is its instants), and its states there.
    let at = |samples: &Option<super::any_plant::DenseSamples>, t: &[f64], v: &mut Vec<f64>| match samples {
        Some(d) => d.held(t, v),
        None => std::mem::take(v),
    };
    let t = match &runs[0].samples {
        Some(d) => d.t.clone(),
        None => runs[0].t.clone(),
    };
    let first = &mut runs[0];
    let mut cols = vec![col(
        format!("{}_ref", qy.name),
        *qy,
        at(&first.samples, &first.t, &mut first.setpoint),
    )];
    // The inputs the loops do not drive (the same profiles on every plant), as the plant
    // reads them: `input_at` holds within the modes `update_modes` sets at each time.
    let mut reader = plant.clone();
    let rest = vec![0.0; reader.dim()];
    for (k, q) in plant
        .inputs()
        .iter()
        .enumerate()
        .filter(|(_, q)| q.name != qu.name)
    {
        let v = t
            .iter()
            .map(|&tk| {
                reader.update_modes(tk, &rest);
                reader.input_at(tk, k)
            })
            .collect();
        cols.push(PlantColumn {
            input: true,
            ..col(q.name.to_string(), *q, v)
        });
    }
    cols.insert(0, col("t".into(), TIME, t));
    let shown = |i: &usize| !plant.internal_states().contains(i);
    for ((mut run, suffix), inner) in runs.into_iter().zip(LOOP_SUFFIXES).zip(inner) {
        let states = match run.samples.as_mut() {
            Some(d) => std::mem::take(&mut d.states),
            None => std::mem::take(&mut run.states),
        };
        for (i, (q, v)) in plant.states().iter().zip(states).enumerate() {
            if shown(&i) {
                cols.push(col(format!("{}{suffix}", q.name), *q, v));
            }
        }
        let (samples, ti) = (&run.samples, &run.t);
        cols.push(PlantColumn {
            input: true,
            ..col(format!("{}{suffix}", qu.name), *qu, at(samples, ti, &mut run.u))
        });
        if !run.y_measured.is_empty() {
            cols.push(col(
                format!("{}_measured{suffix}", qy.name),
                *qy,
                at(samples, ti, &mut run.y_measured),
            ));
        }
        if let (false, Some(q)) = (run.inner_reference.is_empty(), inner) {
            cols.push(col(
                format!("{}_ref{suffix}", q.name),
                *q,
                at(samples, ti, &mut run.inner_reference),
            ));
        }
        if !run.model_output.is_empty() {
            cols.push(col(
                format!("{}_model{suffix}", qy.name),
                *qy,
                at(samples, ti, &mut run.model_output),
            ));
        }
        if !run.weights.is_empty() {
            let w = |k: usize| {
                at(
                    samples,
                    ti,
                    &mut run.weights.iter().map(|v| v[k]).collect::<Vec<f64>>(),
                )
            };
            let [wq, w1q, ballq] = WEIGHT_QUANTITIES;
            cols.push(col(format!("w_norm{suffix}"), wq, w(0)));
            cols.push(col(format!("w1_norm{suffix}"), w1q, w(1)));
            cols.push(col(format!("w1_distance{suffix}"), ballq, w(2)));
            cols.push(col(format!("w1_ball_radius{suffix}"), ballq, w(3)));
        }
    }
    cols
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
