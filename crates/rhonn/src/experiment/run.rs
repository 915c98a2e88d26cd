//! Running a scenario: the plant in the event-locating solver, the sampled controller,
//! the measurement, the output samples taken from the dense output, and the figures.

use super::scenario::{Drive, ProfileSpec, Scenario, ScenarioSpec, SolverSettings};
use super::trace::{Recorder, Sample};
use crate::control::Pi;
use crate::error::{Error, Result};
use crate::plant::{Input, PumpSystem, P_LINE, STROKE};
use crate::units::*;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use rhonn_ode::{Dopri5, Options, Profile, Stats};
use serde::Serialize;

/// Deviations from the set-point are judged this long after each set-point change
/// (the start counts as one) for `max_abs_deviation_settled_mpa` [s].
pub const SETTLE_S: f64 = 1.0;

/// Solver settings and counters of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SolverReport {
    /// Settings.
    #[serde(flatten)]
    pub settings: SolverSettings,
    /// Right-hand-side evaluations (including event location).
    pub rhs_evaluations: u64,
    /// Accepted steps.
    pub accepted_steps: u64,
    /// Rejected steps.
    pub rejected_steps: u64,
    /// Events located (valve switching, bounds reached and left).
    pub events: u64,
    /// Steps landed on input breakpoints and control instants.
    pub breakpoints: u64,
}

/// Figures of a regulated run (display units).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Regulation {
    /// max |p_line - p_ref| over the run [MPa].
    pub max_abs_deviation_mpa: f64,
    /// max |p_line - p_ref| from 1 s after each set-point change on [MPa].
    pub max_abs_deviation_settled_mpa: f64,
    /// Integral of (p_line - p_ref)^2 over the run [MPa^2 s].
    pub ise_mpa2_s: f64,
    /// Time with the current at 0 or at its maximum [s].
    pub time_current_saturated_s: f64,
}

/// The figures of a run (display units, named with their unit).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Figures {
    /// Simulated time [s].
    pub duration_s: f64,
    /// Output samples.
    pub samples: usize,
    /// P_l at the end [MPa].
    pub final_p_line_mpa: f64,
    /// x at the end [mm].
    pub final_stroke_mm: f64,
    /// Lowest P_l [MPa].
    pub p_line_min_mpa: f64,
    /// Highest P_l [MPa].
    pub p_line_max_mpa: f64,
    /// Largest stroke [mm].
    pub stroke_max_mm: f64,
    /// Time with P_l below P_min, where the model is not valid [s].
    pub time_below_p_min_s: f64,
    /// Time with P_l below P_min after the first second [s].
    pub time_below_p_min_after_1s_s: f64,
    /// Regulated runs only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub regulation: Option<Regulation>,
}

/// What `summary.json` holds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    /// rhonn's version.
    pub rhonn_version: &'static str,
    /// The scenario as run.
    pub scenario: ScenarioSpec,
    /// Solver settings and counters.
    pub solver: SolverReport,
    /// The run's figures.
    pub figures: Figures,
    /// Warnings (also printed by the command).
    pub warnings: Vec<String>,
}

/// Running figures, fed one sample at a time (the time-weighted ones use the interval
/// to the next sample: left-point rule on the output grid).
struct Accumulator {
    p_min: f64,
    p_limit: f64,
    p_lo: f64,
    p_hi: f64,
    x_hi: f64,
    below: f64,
    below_after_1s: f64,
    ise: f64,
    max_dev: f64,
    max_dev_settled: f64,
    saturated: f64,
    i_max: f64,
    last: Option<Sample>,
    last_ref: Option<f64>,
    ref_changed_at: f64,
    n: usize,
}

impl Accumulator {
    fn new(p_limit: f64, i_max: f64) -> Self {
        Accumulator {
            p_min: p_limit,
            p_limit,
            p_lo: f64::INFINITY,
            p_hi: f64::NEG_INFINITY,
            x_hi: f64::NEG_INFINITY,
            below: 0.0,
            below_after_1s: 0.0,
            ise: 0.0,
            max_dev: 0.0,
            max_dev_settled: 0.0,
            saturated: 0.0,
            i_max,
            last: None,
            last_ref: None,
            ref_changed_at: 0.0,
            n: 0,
        }
    }

    fn add(&mut self, s: &Sample) {
        if let Some(prev) = self.last {
            let dt = s.t - prev.t;
            if prev.p_line < self.p_limit {
                self.below += dt;
                if prev.t >= 1.0 {
                    self.below_after_1s += dt;
                }
            }
            if let Some(r) = prev.p_ref {
                self.ise += (mpa(prev.p_line - r)).powi(2) * dt;
            }
            if prev.current <= 0.0 || prev.current >= self.i_max {
                self.saturated += dt;
            }
        }
        self.p_lo = self.p_lo.min(s.p_line);
        self.p_hi = self.p_hi.max(s.p_line);
        self.x_hi = self.x_hi.max(s.stroke);
        if let Some(r) = s.p_ref {
            if self.last_ref.is_some_and(|lr| lr != r) {
                self.ref_changed_at = s.t;
            }
            self.last_ref = Some(r);
            let dev = mpa((s.p_line - r).abs());
            self.max_dev = self.max_dev.max(dev);
            if s.t >= self.ref_changed_at + SETTLE_S {
                self.max_dev_settled = self.max_dev_settled.max(dev);
            }
        }
        self.last = Some(*s);
        self.n += 1;
    }

    fn figures(&self, duration_s: f64, regulated: bool) -> Figures {
        let last = self.last.expect("a run has at least one sample");
        let _ = self.p_min;
        Figures {
            duration_s,
            samples: self.n,
            final_p_line_mpa: mpa(last.p_line),
            final_stroke_mm: mm(last.stroke),
            p_line_min_mpa: mpa(self.p_lo),
            p_line_max_mpa: mpa(self.p_hi),
            stroke_max_mm: mm(self.x_hi),
            time_below_p_min_s: self.below,
            time_below_p_min_after_1s_s: self.below_after_1s,
            regulation: regulated.then(|| Regulation {
                max_abs_deviation_mpa: self.max_dev,
                max_abs_deviation_settled_mpa: self.max_dev_settled,
                ise_mpa2_s: self.ise,
                time_current_saturated_s: self.saturated,
            }),
        }
    }
}

fn solver_error(e: rhonn_ode::Error, t: f64, x: &[f64]) -> Error {
    Error::Solver {
        t_s: t,
        state: format!(
            "p_line = {:.6} MPa, stroke = {:.6} mm",
            mpa(x[P_LINE]),
            mm(x[STROKE])
        ),
        source: e,
    }
}

/// Solver options of a scenario.
pub fn solver_options(s: &SolverSettings) -> Options<[f64; 2]> {
    let mut o = Options::<[f64; 2]>::default();
    o.rtol = [s.rtol; 2];
    o.atol = [s.atol_p_line_pa, s.atol_stroke_m];
    o.h_max_s = s.max_step_s;
    o.profile = match s.profile {
        ProfileSpec::Hairer => Profile::Hairer,
        ProfileSpec::Ode45 | ProfileSpec::SimulinkOde45 => Profile::Ode45,
    };
    o
}

/// Run a scenario, giving every output sample to `rec`; returns the summary.
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
    let p = &sc.params;
    let (current, mut pi, setpoint) = match &sc.drive {
        Drive::OpenLoop(sig) => (Input::Signal(sig.clone()), None, None),
        Drive::Pi(s) => (
            Input::Held(s.bias),
            Some(Pi::new(s.kp, s.ti_s, p.t_control, s.bias, 0.0, p.i_max)),
            Some(&s.setpoint),
        ),
    };
    let sys = PumpSystem::new(p.clone(), current, Input::Signal(sc.demand.clone()));
    let opts = solver_options(&sc.solver);
    let mut solver =
        Dopri5::new(sys, 0.0, sc.initial, opts).map_err(|e| solver_error(e, 0.0, &sc.initial))?;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(sc.spec.seed);
    let noise = Normal::new(0.0, sc.noise_std_pa.max(0.0)).expect("checked standard deviation");
    let noisy = sc.noise_std_pa > 0.0;
    let measure = |p: f64, rng: &mut rand_chacha::ChaCha8Rng| {
        if noisy {
            p + noise.sample(rng)
        } else {
            p
        }
    };

    let t_end = sc.spec.duration_s;
    let dt = sc.output_interval_s;
    let n_out = (t_end / dt).round().max(1.0) as u64;
    let out_time = |k: u64| if k >= n_out { t_end } else { k as f64 * dt };
    let mut k_out: u64 = 0;
    let mut acc = Accumulator::new(p.p_min, p.i_max);
    let regulated = pi.is_some();
    let t_ctl = p.t_control;
    let mut k_ctl: u64 = 0;
    let mut last_meas: Option<f64> = None;
    let mut x = [0.0; 2];

    // The controller acts at t = 0 on the first measurement.
    if let (Some(pi), Some(sp)) = (pi.as_mut(), setpoint) {
        let y = measure(sc.initial[P_LINE], &mut rng);
        last_meas = Some(y);
        let u = pi.update(sp.eval(0.0), y);
        solver.system_mut().set_current(u);
        k_ctl = 1;
    }

    let emit = |solver: &Dopri5<PumpSystem>,
                upto: f64,
                inclusive: bool,
                k_out: &mut u64,
                last_meas: Option<f64>,
                rng: &mut rand_chacha::ChaCha8Rng,
                acc: &mut Accumulator,
                rec: &mut dyn FnMut(&Sample)| {
        while *k_out <= n_out {
            let t = out_time(*k_out);
            if t > upto || (!inclusive && t >= upto) {
                break;
            }
            let mut xs = [0.0; 2];
            solver.interpolate(t, &mut xs);
            let sys = solver.system();
            let bounds = [(0.0, sys.params.p_max), (0.0, sys.params.x_max)];
            for (v, (lo, hi)) in xs.iter_mut().zip(bounds) {
                *v = v.clamp(lo, hi);
            }
            let s = Sample {
                t,
                p_line: xs[P_LINE],
                stroke: xs[STROKE],
                current: sys.current_at(t),
                demand: sys.demand_at(t),
                p_ref: setpoint.map(|sp| sp.eval(t)),
                p_meas: if regulated {
                    last_meas
                } else if noisy {
                    Some(measure(xs[P_LINE], rng))
                } else {
                    None
                },
            };
            acc.add(&s);
            rec(&s);
            *k_out += 1;
        }
    };
    let mut record = |s: &Sample| rec.record(s);

    loop {
        let t_stop = if regulated {
            (k_ctl as f64 * t_ctl).min(t_end)
        } else {
            t_end
        };
        let r = solver
            .step(t_stop)
            .map_err(|e| solver_error(e, solver.t(), solver.state()))?;
        let done = solver.t() >= t_end;
        emit(
            &solver,
            solver.t(),
            done,
            &mut k_out,
            last_meas,
            &mut rng,
            &mut acc,
            &mut record,
        );
        if done {
            break;
        }
        if let (rhonn_ode::StepResult::Reached { .. }, Some(pi), Some(sp)) = (r, pi.as_mut(), setpoint) {
            x.copy_from_slice(solver.state());
            let t = solver.t();
            let y = measure(x[P_LINE], &mut rng);
            last_meas = Some(y);
            let u = pi.update(sp.eval(t), y);
            solver.system_mut().set_current(u);
            k_ctl += 1;
        }
    }
    let st: Stats = solver.stats();
    Ok(Summary {
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
        figures: acc.figures(t_end, regulated),
        warnings: sc.warnings.clone(),
    })
}
