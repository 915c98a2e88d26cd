//! Running a scenario: the plant in the event-locating solver, the sampled controller,
//! the measurement, the output samples taken from the dense output, and the figures.

use super::scenario::{Drive, ProfileSpec, Scenario, ScenarioSpec, SolverSettings};
use super::trace::{Recorder, Sample};
use crate::control::Pi;
use crate::error::{Error, Result};
use crate::plant::{Input, PumpSystem, P_LINE, STROKE};
use crate::signal::Signal;
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

/// The run's figures, accumulated step by step on the solver's dense output, so that
/// they do not depend on the output interval: time-weighted figures are integrated
/// with 3-point Gauss-Legendre quadrature on each step (split where the set-point has a
/// breakpoint, at 1 s, and where a settling window ends), the time below P_min from
/// the located crossings, extremes from the step ends and the Gauss points.
struct Accumulator<'a> {
    p_limit: f64,
    i_max: f64,
    setpoint: Option<&'a Signal>,
    /// Times where an interval must be split, sorted; `cursor` is the next one.
    splits: Vec<f64>,
    cursor: usize,
    /// Set-point breakpoints (sorted) for the settling windows.
    changes: Vec<f64>,
    p_lo: f64,
    p_hi: f64,
    x_hi: f64,
    below: f64,
    below_after_1s: f64,
    ise: f64,
    max_dev: f64,
    max_dev_settled: f64,
    saturated: f64,
}

/// Gauss-Legendre nodes on [0, 1] and weights (summing to 1).
const GAUSS: [(f64, f64); 3] = [
    (0.112_701_665_379_258_31, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.887_298_334_620_741_7, 5.0 / 18.0),
];

impl<'a> Accumulator<'a> {
    fn new(p_limit: f64, i_max: f64, setpoint: Option<&'a Signal>, t_end: f64) -> Self {
        let mut changes = vec![0.0];
        let mut splits = vec![1.0];
        if let Some(sp) = setpoint {
            let mut t = 0.0;
            loop {
                let b = sp.next_breakpoint(t);
                if !(b < t_end) {
                    break;
                }
                changes.push(b);
                t = b;
            }
            for &c in &changes {
                splits.push(c);
                splits.push(c + SETTLE_S);
            }
        }
        splits.retain(|&v| v > 0.0 && v < t_end);
        splits.sort_by(f64::total_cmp);
        splits.dedup();
        Accumulator {
            p_limit,
            i_max,
            setpoint,
            splits,
            cursor: 0,
            changes,
            p_lo: f64::INFINITY,
            p_hi: f64::NEG_INFINITY,
            x_hi: f64::NEG_INFINITY,
            below: 0.0,
            below_after_1s: 0.0,
            ise: 0.0,
            max_dev: 0.0,
            max_dev_settled: 0.0,
            saturated: 0.0,
        }
    }

    /// Account for the last step `[t_prev, t]` of `solver`.
    fn add_step(&mut self, solver: &Dopri5<PumpSystem>) {
        let (t0, t1) = (solver.t_prev(), solver.t());
        if !(t1 > t0) {
            return;
        }
        while self.cursor < self.splits.len() && self.splits[self.cursor] <= t0 {
            self.cursor += 1;
        }
        let mut a = t0;
        let mut k = self.cursor;
        while k < self.splits.len() && self.splits[k] < t1 {
            self.add_interval(solver, a, self.splits[k]);
            a = self.splits[k];
            k += 1;
        }
        self.add_interval(solver, a, t1);
    }

    /// `[a, b]` lies in one step, one set-point segment and one settling window.
    fn add_interval(&mut self, solver: &Dopri5<PumpSystem>, a: f64, b: f64) {
        let h = b - a;
        if !(h > 0.0) {
            return;
        }
        let prm = &solver.system().params;
        // The interpolant of a step that ends on a bound may pass it by a hair.
        let state = |t: f64| {
            let mut x = [0.0; 2];
            solver.interpolate(t, &mut x);
            [x[P_LINE].clamp(0.0, prm.p_max), x[STROKE].clamp(0.0, prm.x_max)]
        };
        let mid = 0.5 * (a + b);
        let seg = self.setpoint.map(|sp| (sp, sp.segment(mid)));
        let settled = {
            let last_change = self
                .changes
                .iter()
                .rev()
                .find(|&&c| c <= mid)
                .copied()
                .unwrap_or(0.0);
            mid >= last_change + SETTLE_S
        };
        let mut pts = [(a, 0.0); 5];
        pts[0] = (a, state(a)[P_LINE]);
        for (j, (node, _)) in GAUSS.iter().enumerate() {
            let t = a + node * h;
            let x = state(t);
            pts[j + 1] = (t, x[P_LINE]);
            self.x_hi = self.x_hi.max(x[STROKE]);
        }
        let xb = state(b);
        pts[4] = (b, xb[P_LINE]);
        self.x_hi = self.x_hi.max(xb[STROKE]).max(state(a)[STROKE]);
        for &(t, p) in &pts {
            self.p_lo = self.p_lo.min(p);
            self.p_hi = self.p_hi.max(p);
            if let Some((sp, sg)) = seg {
                let dev = mpa((p - sp.eval_in(sg, t)).abs());
                self.max_dev = self.max_dev.max(dev);
                if settled {
                    self.max_dev_settled = self.max_dev_settled.max(dev);
                }
            }
        }
        if let Some((sp, sg)) = seg {
            self.ise += h * GAUSS
                .iter()
                .zip(&pts[1..4])
                .map(|((_, w), &(t, p))| w * mpa(p - sp.eval_in(sg, t)).powi(2))
                .sum::<f64>();
            let i = solver.system().current_at(mid);
            if i <= 0.0 || i >= self.i_max {
                self.saturated += h;
            }
        }
        // Time below P_min: the sub-intervals between the five points, with the
        // crossings located by bisection on the dense output.
        let mut below = 0.0;
        for w in pts.windows(2) {
            let ((ta, pa), (tb, pb)) = (w[0], w[1]);
            let (ba, bb) = (pa < self.p_limit, pb < self.p_limit);
            if ba && bb {
                below += tb - ta;
            } else if ba != bb {
                let (mut lo, mut hi) = (ta, tb);
                while hi - lo > 1e-10 * (1.0 + hi.abs()) {
                    let m = 0.5 * (lo + hi);
                    if (state(m)[P_LINE] < self.p_limit) == ba {
                        lo = m;
                    } else {
                        hi = m;
                    }
                }
                let tc = 0.5 * (lo + hi);
                below += if ba { tc - ta } else { tb - tc };
            }
        }
        self.below += below;
        if a >= 1.0 {
            self.below_after_1s += below;
        }
    }

    fn figures(&self, duration_s: f64, samples: usize, last: [f64; 2], regulated: bool) -> Figures {
        Figures {
            duration_s,
            samples,
            final_p_line_mpa: mpa(last[P_LINE]),
            final_stroke_mm: mm(last[STROKE]),
            p_line_min_mpa: mpa(self.p_lo),
            p_line_max_mpa: mpa(self.p_hi),
            stroke_max_mm: mm(self.x_hi),
            time_below_p_min_s: self.below,
            time_below_p_min_after_1s_s: self.below_after_1s,
            regulation: regulated.then_some(Regulation {
                max_abs_deviation_mpa: self.max_dev,
                max_abs_deviation_settled_mpa: self.max_dev_settled,
                ise_mpa2_s: self.ise,
                time_current_saturated_s: self.saturated,
            }),
        }
    }
}

fn sc_last(solver: &Dopri5<PumpSystem>) -> [f64; 2] {
    [solver.state()[P_LINE], solver.state()[STROKE]]
}

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

/// Solver options of a scenario.
pub fn solver_options(s: &SolverSettings) -> Options<[f64; 2]> {
    Options {
        rtol: [s.rtol; 2],
        atol: [s.atol_p_line_pa, s.atol_stroke_m],
        h_max_s: s.max_step_s,
        profile: match s.profile {
            ProfileSpec::Hairer => Profile::Hairer,
            ProfileSpec::Ode45 | ProfileSpec::SimulinkOde45 => Profile::Ode45,
        },
        ..Options::default()
    }
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
    // k * interval_ms / 1000 rounds to the nearest double of the decimal time
    // (3.01, not 3.0100000000000002), which CSV readers and joins appreciate.
    let interval_ms = sc.spec.output_interval_ms;
    let out_time = |k: u64| {
        if k >= n_out {
            t_end
        } else {
            k as f64 * interval_ms / 1000.0
        }
    };
    let mut k_out: u64 = 0;
    let regulated = pi.is_some();
    let mut acc = Accumulator::new(p.p_min, p.i_max, setpoint, t_end);
    // Noise on recorded (not fed back) measurements has its own stream, so what is
    // recorded never changes what the controller sees.
    let mut rng_out = rand_chacha::ChaCha8Rng::seed_from_u64(sc.spec.seed ^ 0x9e37_79b9_7f4a_7c15);
    // Control instants k * T, computed from T in ms like the output times, so that a
    // control instant and an output sample at the same decimal time coincide exactly.
    let t_ctl_ms = sc.spec.plant.t_control_ms;
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

    let wants = rec.wants_samples();
    let bounds = [(0.0, p.p_max), (0.0, p.x_max)];
    loop {
        let t_stop = if regulated {
            (k_ctl as f64 * t_ctl_ms / 1000.0).min(t_end)
        } else {
            t_end
        };
        let r = solver
            .step(t_stop)
            .map_err(|e| solver_error(e, solver.t(), solver.state()))?;
        acc.add_step(&solver);
        let done = solver.t() >= t_end;
        // Output samples in [t_prev, t) from this step's dense output (and t_end at the end).
        while wants && k_out <= n_out {
            let t = out_time(k_out);
            if t > solver.t() || (!done && t >= solver.t()) {
                break;
            }
            let mut xs = [0.0; 2];
            solver.interpolate(t, &mut xs);
            for (v, (lo, hi)) in xs.iter_mut().zip(bounds) {
                *v = v.clamp(lo, hi);
            }
            let sys = solver.system();
            rec.record(&Sample {
                t,
                p_line: xs[P_LINE],
                stroke: xs[STROKE],
                current: sys.current_at(t),
                demand: sys.demand_at(t),
                p_ref: setpoint.map(|sp| sp.eval(t)),
                p_meas: if regulated {
                    last_meas
                } else if noisy {
                    Some(measure(xs[P_LINE], &mut rng_out))
                } else {
                    None
                },
            });
            k_out += 1;
        }
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
        figures: acc.figures(t_end, n_out as usize + 1, sc_last(&solver), regulated),
        warnings: sc.warnings.clone(),
    })
}
