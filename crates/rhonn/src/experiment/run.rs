//! Running a scenario: the plant in the event-locating solver, the sampled controller,
//! the measurement, the output samples taken from the dense output, and the figures.

use super::figures::Accumulator;
pub use super::figures::*;
use super::ident_figures::IdentAcc;
pub use super::ident_figures::*;
pub use super::integrated::Integrated;
use super::pump_controllers::Baseline;
use super::pump_loop::{act, OutputClock, Sensors};
use super::scenario::{AdaptiveSettings, Drive, ProfileSpec, Scenario, SolverSettings};
use super::trace::{Column, NoRecorder, Recorder, Sample, Trace};
use crate::control::{Controller, Pi, RhonnCascade};
use crate::error::{Error, Result};
use crate::ident::{FrozenPair, IdentSettings, Identified, Mode};
use crate::plant::{Input, PumpSystem, SignalRef, CURRENT_EFF, PLANT_DIM, P_LINE, STROKE};
use crate::units::*;
use rhonn_ode::{Dopri5, Options, Profile, State, Stats, System};

fn solver_error(e: rhonn_ode::Error, t: f64, x: &[f64]) -> Error {
    Error::Solver {
        t_s: t,
        state: format!(
            "p_line = {:.6} MPa, stroke = {:.6} mm",
            mpa(x[P_LINE]),
            mm(x[STROKE])
        ),
        source: Box::new(e),
    }
}

/// Solver options of a scenario for a state of `dim` components (the pump's two
/// first; identifier states get the relative tolerance and an absolute 1e-9).
pub fn solver_options<S: rhonn_ode::State>(s: &SolverSettings, dim: usize) -> Options<S> {
    let mut rtol = S::splat(dim, s.rtol);
    let mut atol = S::splat(dim, 1e-9);
    atol.as_mut_slice()[P_LINE] = s.atol_p_line_pa;
    atol.as_mut_slice()[STROKE] = s.atol_stroke_m;
    rtol.as_mut_slice()[0] = s.rtol;
    let mut o = Options::uniform(dim, s.rtol, 1e-9);
    o.rtol = rtol;
    o.atol = atol;
    o.h_max_s = s.max_step_s;
    o.profile = match s.profile {
        ProfileSpec::Hairer => Profile::Hairer,
        ProfileSpec::Ode45 | ProfileSpec::SimulinkOde45 => Profile::Ode45,
    };
    o
}

/// The sampled controller of one simulation: none (open loop: the current is a
/// profile), or a [`Controller`] on the measured states.
pub(super) enum Ctl {
    Open,
    Closed(Box<dyn Controller>),
}

impl Ctl {
    fn of(sc: &Scenario) -> Ctl {
        let p = &sc.params;
        match &sc.drive {
            Drive::OpenLoop(_) => Ctl::Open,
            Drive::Pi(s) => {
                let mut pi = Pi::new(s.kp, s.ti_s, p.t_control, s.bias, 0.0, p.i_max);
                pi.measured = [P_LINE];
                pi.dither = s.dither.clone();
                Ctl::Closed(Box::new(pi))
            }
            Drive::Adaptive(a) => Ctl::Closed(Box::new(cascade_for(sc, &a.cascade))),
            Drive::CascadePi(s) => Ctl::Closed(Box::new(s.controller(p.t_control))),
        }
    }
}

/// The adaptive cascade of a scenario, its gain weights starting from the nominal
/// table's `beta k_l omega / V_l` at the initial set-point (MPa/(s mm)).
fn cascade_for(sc: &Scenario, settings: &crate::control::CascadeSettings) -> RhonnCascade {
    // The controller knows the nominal table only, never the plant's overrides.
    let nominal = crate::plant::PumpParams::default();
    let p_ref0 = sc.drive.setpoint().map_or(nominal.p_min, |s| s.eval(0.0));
    let gain =
        nominal.beta * nominal.k_l * nominal.omega / (nominal.v_l0 * (1.0 + nominal.alpha_v * p_ref0)) * 1e-9; // Pa/(s m) -> MPa/(s mm)
    RhonnCascade::new(
        settings.clone(),
        nominal.k_a,
        nominal.phi,
        sc.params.i_max,
        sc.params.x_max,
        sc.params.p_max,
        sc.params.t_control,
        gain,
        sc.initial[P_LINE],
    )
}

/// What one simulation returns: solver counters, figures, final state, the system, and
/// (adaptive runs) the weights' report.
type Simulated<S> = (Stats, Figures, <S as System>::State, S, Option<AdaptiveReport>);

/// One simulation of `sys` through the scenario's time, controller and measurement.
fn simulate<S: Integrated>(
    sc: &Scenario,
    sys: S,
    x0: S::State,
    rec: &mut impl Recorder,
    ident_acc: &mut [IdentAcc],
    mut ctl: Ctl,
    plant_figures: bool,
) -> Result<Simulated<S>> {
    let p = &sc.params;
    let dim = sys.dim();
    let setpoint = sc.drive.setpoint();
    let opts = solver_options::<S::State>(&sc.solver, dim);
    let mut solver =
        Dopri5::new(sys, 0.0, x0.clone(), opts).map_err(|e| solver_error(e, 0.0, x0.as_slice()))?;
    let mut sensors = Sensors::new(sc);
    // Transport delay: what the controller outputs reaches the solenoid this many
    // periods later; until then the initial current holds.
    let mut queue = std::collections::VecDeque::from(vec![
        solver.system().pump().current_at(0.0);
        p.delay_periods as usize
    ]);
    let mut adaptive = match &ctl {
        Ctl::Closed(c) => c.adaptive(0.0).map(|_| AdaptiveReport::default()),
        Ctl::Open => None,
    };
    let mut ctl_state: Option<crate::control::CascadeState> = None;

    let t_end = sc.spec.duration_s;
    let mut clock = OutputClock::new(sc, rec.wants_samples(), rec.stride());
    let regulated = !matches!(ctl, Ctl::Open);
    let mut acc = Accumulator::new(p.p_min, p.i_max, setpoint, t_end);
    acc.p_max = p.p_max;
    acc.x_max = p.x_max;
    // Control instants k * T, computed from T in ms like the output times, so that a
    // control instant and an output sample at the same decimal time coincide exactly.
    let t_ctl_ms = sc.spec.plant.t_control_ms;
    let mut k_ctl: u64 = 0;
    let mut last_meas: Option<f64> = None;

    // The controller acts at t = 0 on the first measurement.
    if let (true, Some(sp)) = (regulated, setpoint) {
        let (y, cs) = act(&mut solver, &mut ctl, &mut sensors, sp, &mut adaptive, &mut queue)?;
        last_meas = Some(y);
        ctl_state = cs;
        k_ctl = 1;
    }
    let bounds = [(0.0, p.p_max), (0.0, p.x_max)];
    let mut full = S::State::zeros(dim);
    loop {
        let t_stop = if regulated {
            (k_ctl as f64 * t_ctl_ms / 1000.0).min(t_end)
        } else {
            t_end
        };
        let r = solver
            .step(t_stop)
            .map_err(|e| solver_error(e, solver.t(), solver.state()))?;
        // (Runs whose plant figures nobody reads, the earlier training epochs and the
        // frozen-weight validations, skip them: a fifth of thesis-ch5's time.)
        if plant_figures {
            acc.add_step(&solver);
        }
        for ia in ident_acc.iter_mut() {
            ia.add_step(&solver);
        }
        let done = solver.t() >= t_end;
        // Output samples in [t_prev, t) from this step's dense output (and t_end at the end).
        while let Some(t) = clock.next(solver.t(), done) {
            solver.interpolate(t, full.as_mut_slice());
            let xs = full.as_slice();
            let sys = solver.system();
            let pump = sys.pump();
            let p_line = xs[P_LINE].clamp(bounds[0].0, bounds[0].1);
            rec.record(&Sample {
                t,
                p_line,
                stroke: xs[STROKE].clamp(bounds[1].0, bounds[1].1),
                current: pump.current_at(t),
                demand: pump.demand_at(t),
                p_ref: setpoint.map(|sp| sp.eval(t)),
                p_meas: if regulated {
                    last_meas
                } else if sensors.noisy() {
                    Some(sensors.recorded_pressure(p_line))
                } else {
                    None
                },
                hat: sys.hats(xs, 0),
                hat_parallel: sys.hats(xs, 1),
                control: ctl_state,
                baseline: None,
            });
        }
        if done {
            break;
        }
        if let (rhonn_ode::StepResult::Reached { .. }, true, Some(sp)) = (r, regulated, setpoint) {
            let (y, cs) = act(&mut solver, &mut ctl, &mut sensors, sp, &mut adaptive, &mut queue)?;
            last_meas = Some(y);
            ctl_state = cs;
            k_ctl += 1;
        }
    }
    let last = [solver.state()[P_LINE], solver.state()[STROKE]];
    let mut figures = acc.figures(t_end, clock.n_out as usize + 1, last, regulated);
    if let (Some(r), Some(a)) = (figures.regulation.as_mut(), adaptive.as_ref()) {
        r.signals_bounded &=
            a.w1_distance_max <= a.w1_ball_radius * (1.0 + 1e-9) && a.w_norm_max <= a.w_bound;
    }
    let mut xf = S::State::zeros(dim);
    xf.as_mut_slice().copy_from_slice(solver.state());
    let stats = solver.stats();
    Ok((stats, figures, xf, solver.into_system(), adaptive))
}

fn report(sc: &Scenario, st: Stats, figures: Figures, identification: Option<IdentReport>) -> Summary {
    Summary {
        rhonn_version: env!("CARGO_PKG_VERSION"),
        scenario: sc.spec.clone(),
        solver: SolverReport {
            settings: sc.solver.clone(),
            rhs_evaluations: st.rhs_evaluations,
            accepted_steps: st.accepted_steps,
            rejected_steps: st.rejected_steps,
            events: st.events,
            breakpoints: st.breakpoints,
        },
        figures,
        identification,
        control: None,
        warnings: sc.warnings.clone(),
    }
}

/// Forwards the adaptive run's samples with the baseline's plant at the same instant.
struct WithBaseline<'a, R: Recorder> {
    inner: &'a mut R,
    base: &'a [super::trace::BaselineSample],
    k: usize,
}

impl<R: Recorder> Recorder for WithBaseline<'_, R> {
    fn record(&mut self, s: &Sample) {
        let mut s = *s;
        s.baseline = self.base.get(self.k).copied();
        self.k += 1;
        self.inner.record(&s);
    }
    fn wants_samples(&self) -> bool {
        self.inner.wants_samples()
    }
    fn stride(&self) -> u64 {
        self.inner.stride()
    }
}

/// Keeps the baseline run's plant, sample by sample.
struct BaselineCollector {
    wants: bool,
    stride: u64,
    samples: Vec<super::trace::BaselineSample>,
}

impl Recorder for BaselineCollector {
    fn record(&mut self, s: &Sample) {
        self.samples.push(super::trace::BaselineSample {
            p_line: s.p_line,
            stroke: s.stroke,
            current: s.current,
        });
    }
    fn wants_samples(&self) -> bool {
        self.wants
    }
    fn stride(&self) -> u64 {
        self.stride
    }
}

/// An adaptive run: the PI baseline on an identical plant (same set-point, demand,
/// noise), then the adaptive cascade, its samples carrying the baseline's.
fn run_adaptive(sc: &Scenario, a: &AdaptiveSettings, rec: &mut impl Recorder) -> Result<RunOutput> {
    let mut base_sc = sc.clone();
    base_sc.drive = match &a.baseline {
        Baseline::Pi(s) => Drive::Pi(s.clone()),
        Baseline::CascadePi(s) => Drive::CascadePi(s.clone()),
    };
    let mut base = BaselineCollector {
        wants: rec.wants_samples(),
        stride: rec.stride(),
        samples: Vec::new(),
    };
    let (st_b, fig_b, _, _, _) = simulate(
        &base_sc,
        pump_system(&base_sc),
        plant_initial(&base_sc),
        &mut base,
        &mut [],
        Ctl::of(&base_sc),
        true,
    )?;
    let mut inj = WithBaseline {
        inner: rec,
        base: &base.samples,
        k: 0,
    };
    let (st, fig, _, _, adaptive) = simulate(
        sc,
        pump_system(sc),
        plant_initial(sc),
        &mut inj,
        &mut [],
        Ctl::of(sc),
        true,
    )?;
    let adaptive = adaptive.expect("an adaptive run reports its weights");
    let mut total = st;
    add_stats(&mut total, st_b);
    let findings = super::figures::comparison(&fig, &fig_b, a.baseline.name());
    let control = ControlReport {
        adaptive,
        baseline: BaselineReport::of(&a.baseline, fig_b),
        findings,
    };
    let mut summary = report(sc, total, fig, None);
    summary.control = Some(control);
    Ok(RunOutput {
        summary,
        validation: None,
        model: None,
    })
}

/// The plant's initial state: pressure, stroke, and the solenoid carrying the current
/// commanded at t = 0.
fn plant_initial(sc: &Scenario) -> [f64; PLANT_DIM] {
    let mut x = [0.0; PLANT_DIM];
    x[P_LINE] = sc.initial[P_LINE];
    x[STROKE] = sc.initial[STROKE];
    x[CURRENT_EFF] = match &sc.drive {
        Drive::OpenLoop(sig) => sig.eval(0.0).clamp(0.0, sc.params.i_max),
        d => d.bias().unwrap_or(0.0),
    };
    x
}

fn pump_system(sc: &Scenario) -> PumpSystem {
    let current = match &sc.drive {
        Drive::OpenLoop(sig) => Input::Signal(sig.clone()),
        d => Input::Held(d.bias().unwrap_or(0.0)),
    };
    PumpSystem::new(sc.params.clone(), current, Input::Signal(sc.demand.clone()))
}

/// Run a scenario, giving every output sample to `rec`; returns the summary. With an
/// `[identifier]` the samples are those of the last training epoch (see [`run_full`]
/// for the validation runs and the weights).
///
/// ```
/// use rhonn::experiment::{preset, run, Trace};
/// let sc = preset::load("thesis-ch3").unwrap().check().unwrap();
/// let mut trace = Trace::default();
/// let summary = run(&sc, &mut trace).unwrap();
/// assert!((summary.figures.final_stroke_mm - 1.01).abs() < 0.05);
/// assert_eq!(trace.len(), 40_001);
/// ```
pub fn run(sc: &Scenario, rec: &mut impl Recorder) -> Result<Summary> {
    run_full(sc, rec).map(|o| o.summary)
}

/// Everything a run produces beside its samples.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOutput {
    /// The summary.
    pub summary: Summary,
    /// Identified runs: the validation runs with frozen weights on the same data
    /// (columns `t`, then per state `<s>`, `<s>_hat_series_parallel`, `<s>_hat_parallel`).
    pub validation: Option<Trace>,
    /// Identified runs: the trained model.
    pub model: Option<ModelFile>,
}

/// Run a scenario: with an `[identifier]`, train it for its epochs (the final weights of
/// one epoch start the next), then validate with frozen weights in series-parallel and
/// in parallel (free-run) mode on the same data.
pub fn run_full(sc: &Scenario, rec: &mut impl Recorder) -> Result<RunOutput> {
    let Some(is) = &sc.identifier else {
        if let Drive::Adaptive(a) = &sc.drive {
            return run_adaptive(sc, a, rec);
        }
        let sys = pump_system(sc);
        let (st, fig, _, _, _) = simulate(sc, sys, plant_initial(sc), rec, &mut [], Ctl::of(sc), true)?;
        return Ok(RunOutput {
            summary: report(sc, st, fig, None),
            validation: None,
            model: None,
        });
    };
    let wants = rec.wants_validation();
    // Small identifiers (the thesis's: 9 states) run on stack arrays, so that the
    // solver's loops have a constant length and unroll: 14 % faster on thesis-ch5
    // (1.41 -> 1.22 ms); larger ones on a Vec.
    let dim = PLANT_DIM + is.ident.dim();
    let IdentRuns {
        total,
        weights,
        fig,
        train_acc,
        val,
        val_acc,
    } = match dim {
        5 => ident_runs::<[f64; 5]>(sc, is, rec)?,
        7 => ident_runs::<[f64; 7]>(sc, is, rec)?,
        9 => ident_runs::<[f64; 9]>(sc, is, rec)?,
        11 => ident_runs::<[f64; 11]>(sc, is, rec)?,
        _ => ident_runs::<Vec<f64>>(sc, is, rec)?,
    };
    let pump_name = |s: &SignalRef| s.name_in(&crate::plant::pump::STATES, &crate::plant::pump::INPUTS);
    let names: Vec<&str> = is.states.iter().map(pump_name).collect();
    let figures_of = |a: &IdentAcc| -> Vec<StateFigures> {
        (0..names.len())
            .map(|k| a.figures(k, names[k], &weights[k]))
            .collect()
    };
    let training = figures_of(&train_acc);
    let parallel = val_acc.get(1).map(figures_of).unwrap_or_default();
    let mut findings = Vec::new();
    for (tr, par) in training.iter().zip(&parallel) {
        let verdict = if par.fit_percent >= 80.0 {
            "the frozen model runs on its own"
        } else if par.fit_percent >= 0.0 {
            "the frozen model runs on its own only roughly"
        } else {
            "the model tracks while it adapts but does not run on its own: its frozen weights describe \
             little more than the last operating point"
        };
        findings.push(format!(
            "{}: fit {:.1} % while training, {:.1} % free-run (parallel) with frozen weights; {verdict}",
            tr.state, tr.fit_percent, par.fit_percent
        ));
    }
    let report_id = IdentReport {
        law: is.ident.law.name,
        epochs: is.epochs,
        n_terms: is.ident.net.n_terms(),
        training,
        series_parallel: val_acc.first().map(figures_of).unwrap_or_default(),
        parallel,
        final_weights: weights.clone(),
        findings,
    };
    let validation = val.filter(|_| wants).map(|val| {
        let mut vt = Trace::default();
        vt.columns.push(Column {
            name: "t".into(),
            unit: "s",
            values: val.t.clone(),
        });
        for (k, n) in names.iter().enumerate() {
            let unit = if *n == "p_line" { "Pa" } else { "m" };
            vt.columns.push(Column {
                name: (*n).into(),
                unit,
                values: val.y[k].clone(),
            });
            vt.columns.push(Column {
                name: format!("{n}_hat_series_parallel"),
                unit,
                values: val.yhat[k].clone(),
            });
            vt.columns.push(Column {
                name: format!("{n}_hat_parallel"),
                unit,
                values: val.yhat_parallel[k].clone(),
            });
        }
        vt
    });
    let model = ModelFile {
        states: names.iter().map(|s| s.to_string()).collect(),
        inputs: is.inputs.iter().map(|s| pump_name(s).to_string()).collect(),
        sigmoid: is.ident.net.sigmoid,
        state_scale: is.ident.net.state_scale.clone(),
        input_scale: is.ident.net.input_scale.clone(),
        terms: (0..is.ident.net.n_terms())
            .map(|k| is.ident.net.terms.factors(k))
            .collect(),
        a: is.ident.net.a.clone(),
        law: is.ident.law.name,
        weights,
    };
    Ok(RunOutput {
        summary: report(sc, total, fig, Some(report_id)),
        validation,
        model: Some(model),
    })
}

/// The training epochs and the frozen-weight validations of an identification run.
struct IdentRuns {
    total: Stats,
    weights: Vec<Vec<f64>>,
    fig: Figures,
    train_acc: IdentAcc,
    /// The validations' samples (series-parallel and parallel together).
    val: Option<Collector>,
    /// Series-parallel, parallel.
    val_acc: Vec<IdentAcc>,
}

/// The frozen-weight validations, series-parallel and parallel, in one integration:
/// their solver counters, samples and figures.
fn validate<St: State>(
    sc: &Scenario,
    is: &IdentSettings,
    weights: &[Vec<f64>],
    wants: bool,
) -> Result<(Stats, Collector, [IdentAcc; 2])> {
    let sys = FrozenPair::<_, St>::new(
        pump_system(sc),
        &is.ident,
        weights,
        is.states.clone(),
        is.inputs.clone(),
    )?;
    let s0 = FrozenPair::<PumpSystem, St>::initial_state(&is.ident, &is.xhat0);
    let mut x0 = St::zeros(PLANT_DIM + s0.len());
    x0.as_mut_slice()[..PLANT_DIM].copy_from_slice(&plant_initial(sc));
    x0.as_mut_slice()[PLANT_DIM..].copy_from_slice(&s0);
    let mut acc = [IdentAcc::new(is, sys.dim(), 0), IdentAcc::new(is, sys.dim(), 1)];
    let mut coll = Collector::new(is, wants);
    let (st, _, _, _, _) = simulate(sc, sys, x0, &mut coll, &mut acc, Ctl::of(sc), false)?;
    Ok((st, coll, acc))
}

fn ident_runs<St: State>(sc: &Scenario, is: &IdentSettings, rec: &mut impl Recorder) -> Result<IdentRuns> {
    let make = |mode: Mode, w: Option<&[Vec<f64>]>| {
        let mut ident = is.ident.clone();
        ident.mode = mode;
        let s0 = ident.initial_state(&is.xhat0, w);
        let mut x0 = St::zeros(PLANT_DIM + s0.len());
        x0.as_mut_slice()[..PLANT_DIM].copy_from_slice(&plant_initial(sc));
        x0.as_mut_slice()[PLANT_DIM..].copy_from_slice(&s0);
        let sys = Identified::<_, St>::new(pump_system(sc), ident, is.states.clone(), is.inputs.clone())?;
        Ok((sys, x0))
    };
    let wants = rec.wants_validation();
    let mut weights: Option<Vec<Vec<f64>>> = None;
    let mut total = Stats::default();
    let mut train = None;
    for epoch in 1..=is.epochs {
        let (sys, x0) = make(Mode::Train, weights.as_deref())?;
        let last = epoch == is.epochs;
        let mut ia = [IdentAcc::new(is, sys.dim(), 0)];
        let (st, fig, xf, sys, _) = if last {
            simulate(sc, sys, x0, rec, &mut ia, Ctl::of(sc), true)?
        } else {
            simulate(sc, sys, x0, &mut NoRecorder, &mut [], Ctl::of(sc), false)?
        };
        add_stats(&mut total, st);
        weights = Some(sys.ident.weights(&xf.as_slice()[PLANT_DIM..]));
        if last {
            let [ia] = ia;
            train = Some((fig, ia));
        }
    }
    let weights = weights.expect("at least one epoch");
    let (fig, train_acc) = train.expect("a last epoch");
    let (val, val_acc) = if is.validate {
        // Both frozen-weight validations ride on one integration of the plant.
        let dim = PLANT_DIM + 2 * is.ident.net.n;
        let (st, coll, acc) = match dim {
            5 => validate::<[f64; 5]>(sc, is, &weights, wants)?,
            7 => validate::<[f64; 7]>(sc, is, &weights, wants)?,
            _ => validate::<Vec<f64>>(sc, is, &weights, wants)?,
        };
        add_stats(&mut total, st);
        (Some(coll), Vec::from(acc))
    } else {
        (None, Vec::new())
    };
    Ok(IdentRuns {
        total,
        weights,
        fig,
        train_acc,
        val,
        val_acc,
    })
}

fn add_stats(total: &mut Stats, st: Stats) {
    total.rhs_evaluations += st.rhs_evaluations;
    total.accepted_steps += st.accepted_steps;
    total.rejected_steps += st.rejected_steps;
    total.events += st.events;
    total.breakpoints += st.breakpoints;
}

/// Collects `(t, state, estimate)` of the identified states.
struct Collector {
    wants: bool,
    states: Vec<usize>,
    t: Vec<f64>,
    y: Vec<Vec<f64>>,
    yhat: Vec<Vec<f64>>,
    yhat_parallel: Vec<Vec<f64>>,
}

impl Collector {
    fn new(is: &IdentSettings, wants: bool) -> Self {
        let states: Vec<usize> = is
            .states
            .iter()
            .map(|s| s.state_index().unwrap_or(P_LINE))
            .collect();
        let n = states.len();
        Collector {
            wants,
            states,
            t: vec![],
            y: vec![vec![]; n],
            yhat: vec![vec![]; n],
            yhat_parallel: vec![vec![]; n],
        }
    }
}

impl Recorder for Collector {
    fn wants_samples(&self) -> bool {
        self.wants
    }
    fn record(&mut self, s: &Sample) {
        self.t.push(s.t);
        for (k, &i) in self.states.iter().enumerate() {
            self.y[k].push(if i == P_LINE { s.p_line } else { s.stroke });
            self.yhat[k].push(s.hat[i].unwrap_or(f64::NAN));
            self.yhat_parallel[k].push(s.hat_parallel[i].unwrap_or(f64::NAN));
        }
    }
}

#[cfg(test)]
#[path = "run_tests.rs"]
mod tests;
