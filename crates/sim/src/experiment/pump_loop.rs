//! The pump's run: its sensors (seeded noise streams), the control instant (measure,
//! control, the transport-delay line), the output clock, and what the run does at its
//! instants and after its steps ([`PumpHooks`]), driven by the one run loop
//! ([`super::sim::drive`]).

use super::ident_figures::IdentAcc;
use super::integrated::Integrated;
use super::loop_conditions::{Actuator, LoopConditions, SensorNoise, Sensors};
use super::pump_figures::{figures_of, AdaptiveReport, Figures};
use super::pump_settings::{Drive, Scenario, SolverSettings};
use super::quadrature::Scale;
use super::regulation::{Tracked, Tracker};
use super::sim::{describe, drive, start, Hooks, Instants};
use super::solver_spec::{Tolerances, DEFAULT_ATOL};
use super::trace::{Recorder, Sample};
use crate::control::{CascadeState, Controller};
use crate::error::{Error, Result};
use crate::plant::{Plant, PumpSystem, PLANT_DIM, P_LINE, STROKE};
use crate::signal::Signal;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use rhonn_ode::{Dopri5, Options, State, Stats, System};

/// Solver options of a scenario for a state of `dim` components (the pump's pressure and
/// stroke first; the rest get the relative tolerance and an absolute 1e-9), as every
/// plant's ([`Tolerances::options`]).
pub fn solver_options<S: rhonn_ode::State>(s: &SolverSettings, dim: usize) -> Options<S> {
    let mut atol = vec![DEFAULT_ATOL; 2];
    (atol[P_LINE], atol[STROKE]) = (s.atol_p_line_pa, s.atol_stroke_m);
    let t = Tolerances {
        profile: s.profile,
        rtol: s.rtol,
        atol,
        max_step_s: s.max_step_s,
    };
    t.options(dim)
}

/// The sampled controller of one simulation: none (open loop: the current is a
/// profile), or a [`Controller`] on the measured states.
pub(super) enum Ctl {
    Open,
    Closed(Box<dyn Controller>),
}

impl Ctl {
    /// The controller of `sc`'s drive, built by the controller registry on the plant
    /// starting at `x0` (SI).
    pub(super) fn of(sc: &Scenario, x0: &[f64]) -> Result<Ctl> {
        Ok(match sc.drive.closed() {
            None => Ctl::Open,
            Some(l) => Ctl::Closed(l.build(&sc.params, x0)?),
        })
    }
}

/// The loop conditions of a pump run (`loop_conditions`, as any plant's): pressure and
/// stroke noise, each from its own seeded stream; a PI's dither; the transport delay,
/// holding the initial current `i0` until the first command arrives.
fn conditions(sc: &Scenario, i0: f64) -> LoopConditions {
    let p = &sc.params;
    let seed = sc.spec.seed;
    LoopConditions {
        noise: vec![
            SensorNoise {
                state: P_LINE,
                std: sc.noise_std_pa,
                seed,
            },
            SensorNoise {
                state: STROKE,
                std: sc.stroke_noise_std_m,
                seed: seed ^ 0x5851_f42d_4c95_7f2d,
            },
        ],
        dither: match &sc.drive {
            Drive::Closed(l) => l.dither.clone(),
            _ => None,
        },
        delay_periods: p.delay_periods,
        held_input: Some(i0),
        input_range: (0.0, p.i_max),
    }
}

/// The noise of an open-loop run's recorded (not fed back) pressure: a third stream, so
/// that what is recorded never changes what a controller sees.
struct RecordedNoise {
    rng: rand_chacha::ChaCha8Rng,
    noise: Option<Normal<f64>>,
}

impl RecordedNoise {
    fn new(sc: &Scenario) -> Self {
        RecordedNoise {
            rng: rand_chacha::ChaCha8Rng::seed_from_u64(sc.spec.seed ^ 0x9e37_79b9_7f4a_7c15),
            noise: (sc.noise_std_pa > 0.0)
                .then(|| Normal::new(0.0, sc.noise_std_pa).expect("checked standard deviation")),
        }
    }

    /// A recorded pressure of an open-loop run.
    fn pressure(&mut self, p: f64) -> Option<f64> {
        self.noise.map(|n| p + n.sample(&mut self.rng))
    }
}

/// The output samples of a run, k * interval (and t_end), taken from each step's dense
/// output: k * interval_ms / 1000 rounds to the nearest double of the decimal time
/// (3.01, not 3.0100000000000002), which CSV readers and joins appreciate.
pub(super) struct OutputClock {
    t_end: f64,
    pub(super) n_out: u64,
    interval_ms: f64,
    k: u64,
    stride: u64,
    wants: bool,
}

impl OutputClock {
    fn new(sc: &Scenario, wants: bool, stride: u64) -> Self {
        let t_end = sc.spec.duration_s;
        OutputClock {
            t_end,
            n_out: (t_end / sc.output_interval_s).round().max(1.0) as u64,
            interval_ms: sc.spec.output_interval_ms,
            k: 0,
            stride: stride.max(1),
            wants,
        }
    }

    /// The next sample to record in [t_prev, t) of a step ending at `t` (t_end too when
    /// the run is `done`), skipping those the stride leaves out.
    pub(super) fn next(&mut self, t: f64, done: bool) -> Option<f64> {
        while self.wants && self.k <= self.n_out {
            let ts = if self.k >= self.n_out {
                self.t_end
            } else {
                self.k as f64 * self.interval_ms / 1000.0
            };
            if ts > t || (!done && ts >= t) {
                return None;
            }
            self.k += 1;
            if (self.k - 1).is_multiple_of(self.stride) {
                return Some(ts);
            }
        }
        None
    }
}

/// One control instant: measure, compute, send through the dither and the delay line;
/// returns the measured pressure, an adaptive controller's state and what reached the
/// solenoid.
#[inline]
fn act<S: Integrated<Plant = PumpSystem>>(
    solver: &mut Dopri5<S>,
    ctl: &mut Ctl,
    (sensors, actuator, meas): (&mut Sensors, &mut Actuator, &mut Vec<f64>),
    sp: &Signal,
    adaptive: &mut Option<AdaptiveReport>,
) -> Result<(f64, Option<CascadeState>, Option<f64>)> {
    let t = solver.t();
    let Ctl::Closed(c) = ctl else {
        return Ok((sensors.measure(P_LINE, solver.state()[P_LINE]), None, None));
    };
    // Every pump controller measures the pressure first (what `p_meas` records).
    sensors.read_for(c.as_ref(), solver.state(), meas);
    let y = meas[0];
    let u = c.control(t, meas, sp.eval(t));
    let mut cs = None;
    if let (Some(v), Some(rep)) = (c.adaptive(t), adaptive.as_mut()) {
        cs = Some(adaptive_state(
            solver.system().plant(),
            t,
            u,
            &v,
            solver.state(),
            rep,
        )?);
    }
    let applied = actuator.apply(t, u);
    solver.system_mut().plant_mut().set_current(applied);
    Ok((y, cs, Some(applied)))
}

/// An adaptive controller's state at a control instant, checked finite, and its
/// running report.
fn adaptive_state(
    plant: &PumpSystem,
    t: f64,
    u: f64,
    v: &crate::control::AdaptiveView,
    state: &[f64],
    rep: &mut AdaptiveReport,
) -> Result<CascadeState> {
    let st = CascadeState {
        stroke_ref: v.inner_reference.unwrap_or(f64::NAN),
        p_hat: v.model_output,
        w_norm: v.w_norm,
        w1_norm: v.w1_norm,
        w1_distance: v.w1_distance,
        ball_radius: v.ball_radius,
    };
    if !(u.is_finite()
        && st.w_norm.is_finite()
        && st.w1_norm.is_finite()
        && v.inner_reference.is_none_or(f64::is_finite))
    {
        return Err(Error::Controller {
            t_s: t,
            state: format!(
                "{}, current = {u} A, |W| = {}, |W_1| = {}",
                describe(plant, state),
                st.w_norm,
                st.w1_norm
            ),
        });
    }
    rep.add(v);
    Ok(st)
}

/// What a pump run does at its control instants (measure, control, the delay line)
/// and after its steps (figures on the dense output, output samples).
struct PumpHooks<'a, R: Recorder> {
    rec: &'a mut R,
    ident_acc: &'a mut [IdentAcc],
    acc: Tracker<'a>,
    plant_figures: bool,
    ctl: Ctl,
    /// The applied current's activity at the control instants.
    activity: crate::activity::ActivityCounter,
    sensors: Sensors,
    /// Dither and transport delay between the controller and the solenoid.
    actuator: Actuator,
    /// What the controller measured at the last instant.
    meas: Vec<f64>,
    recorded_noise: RecordedNoise,
    adaptive: Option<AdaptiveReport>,
    ctl_state: Option<CascadeState>,
    last_meas: Option<f64>,
    clock: OutputClock,
    setpoint: Option<&'a Signal>,
    regulated: bool,
    bounds: [(f64, f64); 2],
    full: Vec<f64>,
}

impl<S: Integrated<Plant = PumpSystem>, R: Recorder> Hooks<S> for PumpHooks<'_, R> {
    #[inline]
    fn instant(&mut self, solver: &mut Dopri5<S>) -> Result<()> {
        if let Some(sp) = self.setpoint {
            let (y, cs, applied) = act(
                solver,
                &mut self.ctl,
                (&mut self.sensors, &mut self.actuator, &mut self.meas),
                sp,
                &mut self.adaptive,
            )?;
            if let Some(u) = applied {
                self.activity.add(u);
            }
            self.last_meas = Some(y);
            self.ctl_state = cs;
        }
        Ok(())
    }

    #[inline]
    fn stepped(&mut self, solver: &Dopri5<S>, done: bool) -> Result<()> {
        // (Runs whose plant figures nobody reads, the earlier training epochs and the
        // frozen-weight validations, skip them: a fifth of thesis-ch5's time.)
        if self.plant_figures {
            self.acc.add_step(solver);
        }
        for ia in self.ident_acc.iter_mut() {
            ia.add_step(solver);
        }
        // Output samples in [t_prev, t) from this step's dense output (and t_end at the end).
        while let Some(t) = self.clock.next(solver.t(), done) {
            let (mut hat, mut hat_parallel) = ([None; PLANT_DIM], [None; PLANT_DIM]);
            solver.interpolate(t, &mut self.full);
            let xs = &self.full[..];
            let sys = solver.system();
            let pump = sys.plant();
            let p_line = xs[P_LINE].clamp(self.bounds[0].0, self.bounds[0].1);
            sys.hats(xs, 0, &mut hat);
            sys.hats(xs, 1, &mut hat_parallel);
            self.rec.record(&Sample {
                t,
                p_line,
                stroke: xs[STROKE].clamp(self.bounds[1].0, self.bounds[1].1),
                current: pump.current_at(t),
                demand: pump.demand_at(t),
                p_ref: self.setpoint.map(|sp| sp.eval(t)),
                p_meas: if self.regulated {
                    self.last_meas
                } else {
                    self.recorded_noise.pressure(p_line)
                },
                hat: [hat[P_LINE], hat[STROKE]],
                hat_parallel: [hat_parallel[P_LINE], hat_parallel[STROKE]],
                control: self.ctl_state,
                baseline: None,
                second_baseline: None,
            });
        }
        Ok(())
    }
}

/// What one simulation returns: solver counters, figures, final state, the system, and
/// (adaptive runs) the weights' report.
pub(super) type Simulated<S> = (Stats, Figures, <S as System>::State, S, Option<AdaptiveReport>);

/// One simulation of `sys` through the scenario's time, controller and measurement.
pub(super) fn simulate<S: Integrated<Plant = PumpSystem>>(
    sc: &Scenario,
    sys: S,
    x0: S::State,
    rec: &mut impl Recorder,
    ident_acc: &mut [IdentAcc],
    ctl: Ctl,
    plant_figures: bool,
) -> Result<Simulated<S>> {
    let p = &sc.params;
    let dim = sys.dim();
    let setpoint = sc.drive.setpoint();
    let opts = solver_options::<S::State>(&sc.solver, dim);
    let conds = conditions(sc, sys.plant().current_at(0.0));
    let mut solver = start(sys, x0, opts)?;
    let adaptive = match &ctl {
        Ctl::Closed(c) => c.adaptive(0.0).map(|_| AdaptiveReport::default()),
        Ctl::Open => None,
    };
    let t_end = sc.spec.duration_s;
    let regulated = !matches!(ctl, Ctl::Open);
    let acc = Tracker::new(
        Tracked {
            regulated: setpoint.map(|sp| (P_LINE, sp)),
            display: Scale::Over(crate::units::PA_PER_MPA),
            floor: solver.system().plant().floor(),
            bounds: solver.system().plant().state_bounds(),
            input: Some((0, (0.0, p.i_max))),
            settle_s: solver.system().plant().settle_s(),
        },
        t_end,
    );
    let mut hooks = PumpHooks {
        clock: OutputClock::new(sc, rec.wants_samples(), rec.stride()),
        rec,
        ident_acc,
        acc,
        plant_figures,
        sensors: Sensors::new(&conds),
        actuator: Actuator::new(&conds),
        meas: Vec::with_capacity(PLANT_DIM),
        recorded_noise: RecordedNoise::new(sc),
        adaptive,
        ctl_state: None,
        last_meas: None,
        setpoint,
        regulated,
        bounds: [(0.0, p.p_max), (0.0, p.x_max)],
        full: vec![0.0; dim],
        ctl,
        activity: crate::activity::ActivityCounter::new((0.0, p.i_max), sc.spec.plant.t_control_ms * 1e-3),
    };
    // Control instants k * T, computed from T in ms like the output times, so that a
    // control instant and an output sample at the same decimal time coincide exactly;
    // the controller acts at t = 0 on the first measurement.
    let instants =
        (regulated && setpoint.is_some()).then(|| Instants::milliseconds(sc.spec.plant.t_control_ms));
    drive(&mut solver, t_end, instants, &mut hooks)?;
    let last = [solver.state()[P_LINE], solver.state()[STROKE]];
    let mut figures = figures_of(&hooks.acc, t_end, hooks.clock.n_out as usize + 1, last, regulated);
    if let Some(r) = figures.regulation.as_mut() {
        let a = hooks.activity.finish();
        r.current_total_variation_a = a.total_variation;
        r.current_rms_change_per_sample_a = a.rms_change_per_sample;
        r.time_current_switching_s = a.time_switching_s;
    }
    if let (Some(r), Some(a)) = (figures.regulation.as_mut(), hooks.adaptive.as_ref()) {
        r.signals_bounded &= a.within_balls();
    }
    let mut xf = S::State::zeros(dim);
    xf.as_mut_slice().copy_from_slice(solver.state());
    let stats = solver.stats();
    Ok((stats, figures, xf, solver.into_system(), hooks.adaptive))
}
