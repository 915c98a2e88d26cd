//! The parts of a pump run's loop: its sensors (seeded noise streams), the control
//! instant (measure, control, the transport-delay line) and the output clock.

use super::figures::AdaptiveReport;
use super::integrated::Integrated;
use super::run::Ctl;
use super::scenario::Scenario;
use crate::error::{Error, Result};
use crate::plant::{P_LINE, STROKE};
use crate::signal::Signal;
use crate::units::*;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use rhonn_ode::Dopri5;

/// The sensors of a pump run: pressure and stroke noise, each with its own seeded
/// stream, and a third stream for recorded (not fed back) pressures, so that what is
/// recorded never changes what the controller sees.
pub(super) struct Sensors {
    rng: rand_chacha::ChaCha8Rng,
    rng_x: rand_chacha::ChaCha8Rng,
    rng_out: rand_chacha::ChaCha8Rng,
    noise: Option<Normal<f64>>,
    x_noise: Option<Normal<f64>>,
}

impl Sensors {
    pub(super) fn new(sc: &Scenario) -> Self {
        let normal =
            |std: f64| (std > 0.0).then(|| Normal::new(0.0, std).expect("checked standard deviation"));
        Sensors {
            rng: rand_chacha::ChaCha8Rng::seed_from_u64(sc.spec.seed),
            rng_x: rand_chacha::ChaCha8Rng::seed_from_u64(sc.spec.seed ^ 0x5851_f42d_4c95_7f2d),
            rng_out: rand_chacha::ChaCha8Rng::seed_from_u64(sc.spec.seed ^ 0x9e37_79b9_7f4a_7c15),
            noise: normal(sc.noise_std_pa),
            x_noise: normal(sc.stroke_noise_std_m),
        }
    }

    pub(super) fn noisy(&self) -> bool {
        self.noise.is_some()
    }

    /// The pressure the controller measures.
    pub(super) fn pressure(&mut self, p: f64) -> f64 {
        self.noise.map_or(p, |n| p + n.sample(&mut self.rng))
    }

    /// The stroke the controller measures.
    pub(super) fn stroke(&mut self, x: f64) -> f64 {
        self.x_noise.map_or(x, |n| x + n.sample(&mut self.rng_x))
    }

    /// A recorded pressure of an open-loop run.
    pub(super) fn recorded_pressure(&mut self, p: f64) -> f64 {
        self.noise.map_or(p, |n| p + n.sample(&mut self.rng_out))
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
    pub(super) fn new(sc: &Scenario, wants: bool, stride: u64) -> Self {
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
            if (self.k - 1) % self.stride == 0 {
                return Some(ts);
            }
        }
        None
    }
}

/// One control instant: measure, compute, send through the delay line; returns the
/// measured pressure and an adaptive controller's state.
pub(super) fn act<S: Integrated>(
    solver: &mut Dopri5<S>,
    ctl: &mut Ctl,
    sensors: &mut Sensors,
    sp: &Signal,
    adaptive: &mut Option<AdaptiveReport>,
    queue: &mut std::collections::VecDeque<f64>,
) -> Result<(f64, Option<crate::control::CascadeState>)> {
    let t = solver.t();
    let y = sensors.pressure(solver.state()[P_LINE]);
    let xm = sensors.stroke(solver.state()[STROKE]);
    let Ctl::Closed(c) = ctl else {
        return Ok((y, None));
    };
    // What the sensors give, by plant state; the controller reads what it declares.
    let sensors = [y, xm];
    let mut meas = [0.0; 2];
    for (m, &i) in meas.iter_mut().zip(c.measurements()) {
        *m = sensors[i];
    }
    let u = c.control(t, &meas[..c.measurements().len()], sp.eval(t));
    let mut cs = None;
    if let (Some(v), Some(rep)) = (c.adaptive(t), adaptive.as_mut()) {
        cs = Some(adaptive_state(t, u, &v, solver.state(), rep)?);
    }
    queue.push_back(u);
    let applied = queue
        .pop_front()
        .expect("the delay line holds at least this output");
    solver.system_mut().pump_mut().set_current(applied);
    Ok((y, cs))
}

/// An adaptive controller's state at a control instant, checked finite, and its
/// running report.
fn adaptive_state(
    t: f64,
    u: f64,
    v: &crate::control::AdaptiveView,
    state: &[f64],
    rep: &mut AdaptiveReport,
) -> Result<crate::control::CascadeState> {
    let st = crate::control::CascadeState {
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
        && v.inner_reference.map_or(true, f64::is_finite))
    {
        return Err(Error::Controller {
            t_s: t,
            state: format!(
                "p_line = {:.6} MPa, stroke = {:.6} mm, current = {u} A, |W| = {}, |W_1| = {}",
                mpa(state[P_LINE]),
                mm(state[STROKE]),
                st.w_norm,
                st.w1_norm
            ),
        });
    }
    rep.w_norm_max = rep.w_norm_max.max(st.w_norm);
    rep.w_norm_final = st.w_norm;
    if !v.identifying {
        rep.w1_distance_max = rep.w1_distance_max.max(v.w1_distance);
    }
    rep.w1_ball_radius = v.ball_radius;
    rep.w_bound = v.w_bound;
    rep.w1_final = v.w1.to_vec();
    rep.projections = v.projections;
    Ok(st)
}
