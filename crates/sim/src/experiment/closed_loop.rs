//! A controller on one input of any [`Plant`] tracking a set-point, sampled at the
//! control period with zero-order hold, through the one run loop ([`super::sim`]): the
//! sensors and the actuator of the loop's conditions, the samples at the control instants
//! (or from the dense output), and the figures on the dense output
//! (`regulation.rs`).

use super::adaptive_report::AdaptiveReport;
use super::any_plant::{sampling_steps, solver, DenseSampler, DenseSamples, LOOP_RTOL};
use super::integrated::{Alone, Integrated};
use super::loop_conditions::{Actuator, LoopConditions, Sensors};
use super::quadrature::Scale;
use super::regulation::{Tracked, Tracker};
use super::sim::{describe, drive, Hooks, Instants};
use super::solver_spec::{SolverDefaults, Tolerances};
use crate::control::Controller;
use crate::error::{Error, Result};
use crate::plant::Plant;
use crate::signal::Signal;
use rhonn_ode::Dopri5;

/// What a closed-loop run keeps besides its figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LoopSamples {
    /// Every state, the measurements and a controller's inner set-point and weights at
    /// each control instant.
    AtInstants,
    /// As `AtInstants`, and the states every so many seconds (finer than the period)
    /// from the solver's dense output ([`LoopRun::samples`]).
    Every(f64),
    /// The figures, and what they are read from: the instants, the regulated state, the
    /// set-point and the input (a summary's run: no states, measurements or weights).
    FiguresOnly,
}

/// What one closed-loop run gives, sampled at the control instants.
#[derive(Debug, Clone, PartialEq)]
pub struct LoopRun {
    /// The controller's name.
    pub controller: &'static str,
    /// Control instants \[s\].
    pub t: Vec<f64>,
    /// The controlled state (the controller's first measurement), SI.
    pub y: Vec<f64>,
    /// The set-point, SI.
    pub setpoint: Vec<f64>,
    /// The input applied from each instant on, SI.
    pub u: Vec<f64>,
    /// Every plant state at each instant, SI (`states[i][k]`: state i at instant k).
    pub states: Vec<Vec<f64>>,
    /// A cascade's inner set-point at each instant, SI (empty for a single loop).
    pub inner_reference: Vec<f64>,
    /// An adaptive controller's weights at each instant (empty for others): |W|, |W_1|,
    /// |W_1 - centre| and the radius of W_1's ball, in the neuron's (scaled) units.
    pub weights: Vec<[f64; 4]>,
    /// An adaptive controller's model estimate of the regulated state at each control
    /// instant (SI; empty for other controllers).
    pub model_output: Vec<f64>,
    /// What the controller measured of the controlled state at each instant, SI (empty
    /// when no state is measured with noise).
    pub y_measured: Vec<f64>,
    /// Integral of |y - r| over the run (on the solver's dense output, 3-point
    /// Gauss-Legendre on each step), SI s.
    pub iae: f64,
    /// Integral of (y - r)^2, SI^2 s.
    pub ise: f64,
    /// The other figures of the same accumulation (SI).
    pub tracking: Tracking,
    /// What the solver did.
    pub stats: rhonn_ode::Stats,
    /// An adaptive controller's weights over the run (None for others).
    pub adaptive: Option<AdaptiveReport>,
    /// The plant's states at output instants finer than the control period, from the
    /// solver's dense output (None: the run is sampled at its control instants).
    pub samples: Option<DenseSamples>,
}

/// A closed-loop run's figures beside its integrals, on the dense output (SI).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Tracking {
    /// max |y - r| over the run.
    pub max_abs_deviation: f64,
    /// max |y - r| from the plant's settling time after each set-point change on.
    pub max_abs_deviation_settled: f64,
    /// The plant's settling time \[s\].
    pub settle_s: f64,
    /// max |y - r| from a tenth of the plant's settling time after each set-point change
    /// on.
    pub max_abs_deviation_early: f64,
    /// Time with |y - r| within 1 % of r \[s\].
    pub time_within_1pct_s: f64,
    /// Each set-point step's overshoot beyond its new value within the plant's settling
    /// time, in % of the step.
    pub overshoot_percent: Vec<f64>,
    /// Time the plant's floor state spent below its floor \[s\] (None: the plant has
    /// none).
    pub time_below_floor_s: Option<f64>,
    /// The same from the plant's settling time on \[s\].
    pub time_below_floor_after_settle_s: Option<f64>,
    /// Whether every plant state stayed within its bounds.
    pub states_bounded: bool,
}

impl LoopRun {
    /// `y - r` at the last control instant (NaN for an empty run), SI.
    pub fn final_error(&self) -> f64 {
        match (self.y.last(), self.setpoint.last()) {
            (Some(y), Some(r)) => y - r,
            _ => f64::NAN,
        }
    }
}

/// `ctl` drives input `input` of `plant` from `x0` for `duration_s`, every `period_s`,
/// to follow `setpoint`; an error (with the time and the state) when the solver fails
/// or the controller's output is not finite. A clean loop: exact measurements, no
/// delay ([`closed_loop_with`] for noise, dither and delay).
pub fn closed_loop<P: Plant>(
    plant: P,
    x0: &[f64],
    ctl: &mut dyn Controller,
    input: usize,
    setpoint: &Signal,
    period_s: f64,
    duration_s: f64,
) -> Result<LoopRun> {
    let clean = LoopConditions::default();
    let tol = Tolerances::of_defaults(&SolverDefaults::plant(LOOP_RTOL), plant.states().len());
    closed_loop_with(
        plant,
        x0,
        ctl,
        input,
        (setpoint, period_s, duration_s),
        (&clean, LoopSamples::AtInstants),
        &tol,
    )
}

/// [`closed_loop`] under `conditions`: the controller sees its states through noisy
/// sensors, and its command, dithered, reaches the plant after the delay. `u` records
/// what reached the plant; `y_measured` what the controller saw of the regulated state.
/// `samples` says what it keeps besides its figures ([`LoopSamples`]). `tol`: the solver's settings
/// (see [`LOOP_RTOL`] for the scenarios' default).
pub fn closed_loop_with<P: Plant>(
    mut plant: P,
    x0: &[f64],
    ctl: &mut dyn Controller,
    input: usize,
    (setpoint, period_s, duration_s): (&Signal, f64, f64),
    (conditions, samples): (&LoopConditions, LoopSamples),
    tol: &Tolerances,
) -> Result<LoopRun> {
    let n_meas = ctl.measurements().len();
    let y_idx = *ctl.measurements().first().ok_or_else(|| {
        crate::error::invalid("controller.measurements", "[]", "at least the controlled state")
    })?;
    plant.hold_input(input, 0.0);
    let n_states = plant.states().len();
    let (floor, bounds, settle_s) = (plant.floor(), plant.state_bounds(), plant.settle_s());
    let mut s = solver(Alone(plant), x0, &[], tol)?;
    let steps = sampling_steps(duration_s, period_s)?;
    // One value per control instant: reserved once (a short run's vectors grew by
    // doubling, a tenth of its time in reallocations and page faults), at most 4Mi each
    // (a scenario has at most a million control periods; a caller's longer run grows).
    let n = usize::try_from(steps)
        .map_or(0, |k| k.saturating_add(1))
        .min(1 << 22);
    let per_instant = || Vec::with_capacity(n);
    let mut hooks = Regulate {
        run: LoopRun {
            controller: ctl.name(),
            t: per_instant(),
            y: per_instant(),
            setpoint: per_instant(),
            u: per_instant(),
            states: if samples == LoopSamples::FiguresOnly {
                vec![Vec::new(); n_states]
            } else {
                (0..n_states).map(|_| per_instant()).collect()
            },
            inner_reference: Vec::new(),
            weights: Vec::new(),
            model_output: Vec::new(),
            y_measured: Vec::new(),
            iae: 0.0,
            ise: 0.0,
            tracking: Tracking::default(),
            stats: rhonn_ode::Stats::default(),
            adaptive: None,
            samples: None,
        },
        tracker: Tracker::new(
            Tracked {
                regulated: Some((y_idx, setpoint)),
                display: Scale(1.0),
                floor,
                bounds,
                input: Some((input, conditions.input_range)),
                settle_s,
            },
            duration_s,
        ),
        dense: match samples {
            LoopSamples::Every(dt) => Some(DenseSampler::new(dt, duration_s, n_states)?),
            _ => None,
        },
        all: samples != LoopSamples::FiguresOnly,
        sensors: Sensors::new(conditions),
        actuator: Actuator::new(conditions),
        noisy: conditions.noisy(),
        meas: Vec::with_capacity(n_meas),
        y_idx,
        ctl,
        input,
        setpoint,
    };
    let instants = Instants::seconds(period_s);
    if let Some(d) = hooks.dense.as_mut() {
        d.take(&s);
    }
    drive(&mut s, instants.at(steps), Some(instants), &mut hooks)?;
    let mut run = hooks.run;
    run.samples = hooks.dense.map(|d| d.out);
    run.stats = s.stats();
    let tr = hooks.tracker;
    (run.iae, run.ise) = (tr.iae, tr.ise);
    run.tracking = Tracking {
        max_abs_deviation: tr.max_dev,
        max_abs_deviation_settled: tr.max_dev_settled,
        settle_s,
        max_abs_deviation_early: tr.max_dev_0_1,
        time_within_1pct_s: tr.within,
        overshoot_percent: tr.steps.iter().map(|s| s.3).collect(),
        time_below_floor_s: floor.map(|_| tr.below),
        time_below_floor_after_settle_s: floor.map(|_| tr.below_after_settle),
        states_bounded: tr.states_bounded(),
    };
    Ok(run)
}

/// A controller on a plant's input at each instant, and the run's samples.
struct Regulate<'a> {
    run: LoopRun,
    tracker: Tracker<'a>,
    dense: Option<DenseSampler>,
    /// Whether to keep the states, measurements, inner set-point and weights.
    all: bool,
    meas: Vec<f64>,
    y_idx: usize,
    ctl: &'a mut dyn Controller,
    input: usize,
    setpoint: &'a Signal,
    sensors: Sensors,
    actuator: Actuator,
    noisy: bool,
}

impl<P: Plant> Hooks<Alone<P>> for Regulate<'_> {
    fn instant(&mut self, s: &mut Dopri5<Alone<P>>) -> Result<()> {
        let t = s.t();
        self.sensors.read_for(&*self.ctl, s.state(), &mut self.meas);
        let r = self.setpoint.eval(t);
        let ctl = &mut *self.ctl;
        let u = ctl.control(t, &self.meas, r);
        if !u.is_finite() {
            return Err(Error::Controller {
                t_s: t,
                state: format!(
                    "{}, {} output {u}",
                    describe(s.system().plant(), s.state()),
                    ctl.name()
                ),
            });
        }
        let u = self.actuator.apply(t, u);
        s.system_mut().plant_mut().hold_input(self.input, u);
        let (run, y) = (&mut self.run, s.state()[self.y_idx]);
        run.t.push(t);
        run.y.push(y);
        run.setpoint.push(r);
        run.u.push(u);
        if self.all {
            if self.noisy {
                run.y_measured.push(self.meas[0]);
            }
            for (col, v) in run.states.iter_mut().zip(s.state()) {
                col.push(*v);
            }
            if let Some(r1) = ctl.inner_reference() {
                run.inner_reference.push(r1);
            }
        }
        if let Some(v) = ctl.adaptive(t) {
            if self.all {
                run.weights
                    .push([v.w_norm, v.w1_norm, v.w1_distance, v.ball_radius]);
                run.model_output.push(v.model_output);
            }
            run.adaptive.get_or_insert_with(AdaptiveReport::default).add(&v);
        }
        Ok(())
    }
    fn stepped(&mut self, s: &Dopri5<Alone<P>>, _done: bool) -> Result<()> {
        self.tracker.add_step(s);
        if let Some(d) = self.dense.as_mut() {
            d.take(s);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::{IndirectSettings, Pi, RhonnIndirect};
    use crate::plant::{Input, Tanks, TanksParams};
    use crate::signal::PiecewiseLinear;

    /// The upper tank's level by the pump voltage, set-point 100 -> 200 -> 150 mm.
    #[test]
    fn a_pi_and_the_rhonn_indirect_controller_regulate_the_upper_tank() {
        let sp = Signal::piecewise(
            PiecewiseLinear::new(vec![
                (0.0, 0.1),
                (300.0, 0.1),
                (305.0, 0.2),
                (600.0, 0.2),
                (605.0, 0.15),
            ]),
            f64::MIN,
            f64::MAX,
        );
        let tanks = Tanks::new(TanksParams::default(), Input::Held(0.0));
        // IMC on the level linearised at 0.15 m: gain 0.0655 m/V, time constant 67 s; 20 s.
        let mut pi = Pi::new(67.0 / (0.0655 * 20.0), 67.0, 1.0, 0.0, 0.0, 10.0);
        let mut adaptive = RhonnIndirect::new(
            IndirectSettings::for_pole(0.05, 0.1),
            0,
            (0.0, 10.0),
            1.0,
            0.01,
            0.05,
        );
        for ctl in [&mut pi as &mut dyn Controller, &mut adaptive] {
            let run = closed_loop(tanks.clone(), &[0.05, 0.05], ctl, 0, &sp, 1.0, 900.0).unwrap();
            let e = run.final_error();
            eprintln!(
                "{}: IAE {:.3} m s, final error {:.2} mm",
                run.controller,
                run.iae,
                e * 1e3
            );
            assert!(e.abs() < 2e-3, "{}: {e}", run.controller);
            assert!(run.u.iter().all(|u| (0.0..=10.0).contains(u)));
        }
        // A controller whose output is not finite is an error naming the time and the state.
        struct Broken;
        impl Controller for Broken {
            fn name(&self) -> &'static str {
                "broken"
            }
            fn measurements(&self) -> &[usize] {
                &[0]
            }
            fn control(&mut self, t: f64, _m: &[f64], _r: f64) -> f64 {
                if t < 10.0 {
                    1.0
                } else {
                    f64::NAN
                }
            }
        }
        let e = closed_loop(tanks, &[0.05, 0.05], &mut Broken, 0, &sp, 1.0, 100.0).unwrap_err();
        let e = e.to_string();
        assert!(
            e.contains("t = 10 s") && e.contains("h1 = ") && e.contains("broken output NaN"),
            "{e}"
        );
    }
}
