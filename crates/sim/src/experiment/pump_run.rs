//! Running a scenario: the plant in the event-locating solver, the sampled controller,
//! the measurement, the output samples taken from the dense output, and the figures.

use super::ident_figures::IdentAcc;
pub use super::integrated::{Alone, Integrated};
use super::pump_controllers::PumpLoop;
pub use super::pump_figures::*;
pub use super::pump_ident_figures::*;
pub use super::pump_loop::solver_options;
use super::pump_loop::{simulate, Ctl};
use super::pump_settings::{AdaptiveSettings, Drive, Scenario};
use super::quadrature::Scale;
use super::trace::{Column, NoRecorder, Recorder, Sample, Trace};
use crate::control::LoopSpec;
use crate::error::Result;
use crate::ident::{FrozenPair, IdentSettings, Identified, Mode};
use crate::plant::{Input, PumpSystem, SignalRef, CURRENT_EFF, PLANT_DIM, P_LINE, STROKE};
use rhonn_ode::{State, Stats, System};

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
        // Named by the scenario's controller (a baseline's run too, as it always was).
        findings: match (
            &figures.regulation,
            sc.spec.controller.as_ref().map(|c| &c.controller),
        ) {
            (Some(r), Some(LoopSpec::Pi(_))) => super::pump_figures::regulation_findings("the PI", r),
            (Some(r), Some(LoopSpec::PumpCascadePi(_))) => {
                super::pump_figures::regulation_findings("the cascade PI", r)
            }
            (Some(r), Some(_)) => super::pump_figures::regulation_findings("the adaptive controller", r),
            _ => Vec::new(),
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
    second: &'a [super::trace::BaselineSample],
    k: usize,
}

impl<R: Recorder> Recorder for WithBaseline<'_, R> {
    fn record(&mut self, s: &Sample) {
        let mut s = *s;
        s.baseline = self.base.get(self.k).copied();
        s.second_baseline = self.second.get(self.k).copied();
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
    let (wants, stride) = (rec.wants_samples(), rec.stride());
    let (st_b, fig_b, base) = run_baseline(sc, &a.baseline, wants, stride)?;
    let second = a
        .second_baseline
        .as_ref()
        .map(|(name, b)| run_baseline(sc, b, wants, stride).map(|r| (*name, b, r)))
        .transpose()?;
    let mut inj = WithBaseline {
        inner: rec,
        base: &base,
        second: second.as_ref().map_or(&[][..], |(_, _, (_, _, s))| s),
        k: 0,
    };
    let (st, fig, _, _, adaptive) = simulate(
        sc,
        pump_alone(sc),
        plant_initial(sc),
        &mut inj,
        &mut [],
        Ctl::of(sc, &plant_initial(sc))?,
        true,
    )?;
    let adaptive = adaptive.expect("an adaptive run reports its weights");
    let mut total = st;
    add_stats(&mut total, st_b);
    let mut findings = super::pump_figures::comparison(&fig, &fig_b, a.baseline.name());
    let second_baseline = second.map(|(name, b, (st2, fig2, _))| {
        add_stats(&mut total, st2);
        let label = format!("{}-{name}", b.name());
        findings.extend(super::pump_figures::comparison(&fig, &fig2, &label));
        BaselineReport {
            tuning: Some(name),
            ..BaselineReport::of(b, fig2)
        }
    });
    let control = ControlReport {
        adaptive,
        baseline: BaselineReport::of(&a.baseline, fig_b),
        second_baseline,
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

/// A baseline on an identical plant (same set-point, demand, noise): its solver
/// statistics, figures and samples.
fn run_baseline(
    sc: &Scenario,
    b: &PumpLoop,
    wants: bool,
    stride: u64,
) -> Result<(Stats, Figures, Vec<super::trace::BaselineSample>)> {
    let mut base_sc = sc.clone();
    base_sc.drive = Drive::Closed(Box::new(b.clone()));
    let mut base = BaselineCollector {
        wants,
        stride,
        samples: Vec::new(),
    };
    let (st_b, fig_b, _, _, _) = simulate(
        &base_sc,
        pump_alone(&base_sc),
        plant_initial(&base_sc),
        &mut base,
        &mut [],
        Ctl::of(&base_sc, &plant_initial(&base_sc))?,
        true,
    )?;
    Ok((st_b, fig_b, base.samples))
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

/// The pump alone in the solver.
fn pump_alone(sc: &Scenario) -> Alone<PumpSystem> {
    Alone(pump_system(sc))
}

/// Run a scenario, giving every output sample to `rec`; returns the summary. With an
/// `[identifier]` the samples are those of the last training epoch (see [`run_full`]
/// for the validation runs and the weights).
///
/// ```
/// use rhonn_sim::experiment::{preset, run, Trace};
/// let sc = preset::load_any("thesis-ch3").unwrap().pump_run().unwrap();
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
        let sys = pump_alone(sc);
        let (st, fig, _, _, _) = simulate(
            sc,
            sys,
            plant_initial(sc),
            rec,
            &mut [],
            Ctl::of(sc, &plant_initial(sc))?,
            true,
        )?;
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
            .map(|k| {
                let (state, unit, scale) = if names[k] == "p_line" {
                    ("p_line", "MPa", Scale::Over(crate::units::PA_PER_MPA))
                } else {
                    ("stroke", "mm", Scale::Over(crate::units::M_PER_MM))
                };
                StateFigures::of(state, unit, a.figures(k, scale), &weights[k])
            })
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
    let model = ModelFile::of(is, pump_name, weights);
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
    let mut acc = [
        IdentAcc::new(idx(is), sys.dim(), 0),
        IdentAcc::new(idx(is), sys.dim(), 1),
    ];
    let mut coll = Collector::new(is, wants);
    let (st, _, _, _, _) = simulate(
        sc,
        sys,
        x0,
        &mut coll,
        &mut acc,
        Ctl::of(sc, &plant_initial(sc))?,
        false,
    )?;
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
        let mut ia = [IdentAcc::new(idx(is), sys.dim(), 0)];
        let (st, fig, xf, sys, _) = if last {
            simulate(sc, sys, x0, rec, &mut ia, Ctl::of(sc, &plant_initial(sc))?, true)?
        } else {
            simulate(
                sc,
                sys,
                x0,
                &mut NoRecorder,
                &mut [],
                Ctl::of(sc, &plant_initial(sc))?,
                false,
            )?
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
    *total += st;
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
#[path = "pump_run_tests.rs"]
mod tests;

/// The pump states `is` identifies (indices; a state it cannot name reads the pressure).
fn idx(is: &IdentSettings) -> Vec<usize> {
    is.states
        .iter()
        .map(|s| s.state_index().unwrap_or(P_LINE))
        .collect()
}
