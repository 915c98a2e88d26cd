//! The corpus's systems: continuous-time plants sampled with the input held over each
//! sample (fourth-order Runge-Kutta in sub-steps), each family's structure with its
//! parameters drawn from the system's generator.
//!
//! Written here rather than with the crate's ODE solver: these are small fixed-step
//! simulations whose only requirement is to be the same on every machine, and the
//! backlash's play is a state update between steps, which an adaptive solver would not
//! hold.

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

/// A system family of the corpus.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Family {
    /// A mass with viscous and Coulomb friction whose position a PD loop holds on a
    /// reference; the record is the force and the position (a double integrator seen from
    /// its input, recorded in closed loop).
    ClosedLoopIntegrator,
    /// A second-order linear system sampled a hundred times faster than its dynamics.
    FastSampling,
    /// A second-order linear system behind an input saturation.
    Saturation,
    /// A second-order linear system behind an input dead zone.
    DeadZone,
    /// A first-order motor whose position drives a load through gear play.
    Backlash,
    /// An oscillator with a Bouc-Wen hysteretic restoring force.
    Hysteresis,
    /// A second-order linear system followed by a static output nonlinearity.
    Wiener,
    /// A static input nonlinearity followed by a second-order linear system.
    Hammerstein,
    /// A first-order system whose pole moves with the input.
    Bilinear,
    /// A first-order linear system with a dead time of several samples.
    InputDelay,
    /// Two inputs, two outputs: a fast linear speed and a slow temperature heated by the
    /// square of the first input.
    TwoOutputs,
    /// A Hammerstein system recorded for 150 to 300 samples only.
    ShortRecord,
    /// A second-order linear system whose output drifts slowly (an unmeasured
    /// disturbance, different in every record).
    SlowDrift,
}

impl Family {
    /// Every family, in the order systems cycle through them.
    pub const ALL: [Family; 13] = [
        Family::ClosedLoopIntegrator,
        Family::FastSampling,
        Family::Saturation,
        Family::DeadZone,
        Family::Backlash,
        Family::Hysteresis,
        Family::Wiener,
        Family::Hammerstein,
        Family::Bilinear,
        Family::InputDelay,
        Family::TwoOutputs,
        Family::ShortRecord,
        Family::SlowDrift,
    ];

    /// Its name in tables.
    pub fn name(self) -> &'static str {
        match self {
            Family::ClosedLoopIntegrator => "closed-loop integrator",
            Family::FastSampling => "fast sampling",
            Family::Saturation => "saturation",
            Family::DeadZone => "dead zone",
            Family::Backlash => "backlash",
            Family::Hysteresis => "hysteresis",
            Family::Wiener => "wiener",
            Family::Hammerstein => "hammerstein",
            Family::Bilinear => "bilinear",
            Family::InputDelay => "input delay",
            Family::TwoOutputs => "two outputs",
            Family::ShortRecord => "short record",
            Family::SlowDrift => "slow drift",
        }
    }
}

/// Right-hand side: states, held inputs, derivatives.
pub(super) type Rhs = Box<dyn Fn(&[f64], &[f64], &mut [f64])>;
/// Output map: states, outputs.
pub(super) type OutputMap = Box<dyn Fn(&[f64], &mut [f64])>;
/// A state update after each sub-step.
pub(super) type AfterStep = Box<dyn Fn(&mut [f64])>;

/// A sampled plant: x' = f(x, u) with u held over each sample, y = h(x); `after` updates
/// states after every sub-step (the backlash's play).
pub(super) struct Plant {
    pub states: usize,
    pub outputs: usize,
    pub f: Rhs,
    pub h: OutputMap,
    pub after: Option<AfterStep>,
    /// Sub-steps per sample.
    pub sub: usize,
    /// Sample time \[s\].
    pub dt: f64,
}

impl Plant {
    /// Advance `x` over one sample with `u` held.
    pub fn advance(&self, x: &mut [f64], u: &[f64]) {
        let h = self.dt / self.sub as f64;
        let n = self.states;
        let (mut k1, mut k2, mut k3, mut k4, mut tmp) = (
            vec![0.0; n],
            vec![0.0; n],
            vec![0.0; n],
            vec![0.0; n],
            vec![0.0; n],
        );
        for _ in 0..self.sub {
            (self.f)(x, u, &mut k1);
            tmp.iter_mut()
                .zip(x.iter())
                .zip(&k1)
                .for_each(|((t, x), k)| *t = x + 0.5 * h * k);
            (self.f)(&tmp, u, &mut k2);
            tmp.iter_mut()
                .zip(x.iter())
                .zip(&k2)
                .for_each(|((t, x), k)| *t = x + 0.5 * h * k);
            (self.f)(&tmp, u, &mut k3);
            tmp.iter_mut()
                .zip(x.iter())
                .zip(&k3)
                .for_each(|((t, x), k)| *t = x + h * k);
            (self.f)(&tmp, u, &mut k4);
            for i in 0..n {
                x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
            if let Some(a) = &self.after {
                a(x);
            }
        }
    }

    /// The outputs of an open-loop run from rest under `u` (one column per input): y(k)
    /// is the output at the start of sample k, before u(k) acts.
    pub fn run(&self, u: &[Vec<f64>]) -> Vec<Vec<f64>> {
        let n = u.first().map_or(0, Vec::len);
        let mut x = vec![0.0; self.states];
        let mut y = vec![vec![0.0; n]; self.outputs];
        let mut yk = vec![0.0; self.outputs];
        let mut uk = vec![0.0; u.len()];
        for k in 0..n {
            (self.h)(&x, &mut yk);
            for (col, v) in y.iter_mut().zip(&yk) {
                col[k] = *v;
            }
            for (v, col) in uk.iter_mut().zip(u) {
                *v = col[k];
            }
            self.advance(&mut x, &uk);
        }
        y
    }
}

/// A linear second-order system x'' + 2 zeta w x' + w^2 x = w^2 g(u), with natural
/// frequency `w` \[rad/s\] and damping `zeta`, behind the static map `g`.
fn second_order(w: f64, zeta: f64, dt: f64, g: impl Fn(f64) -> f64 + 'static) -> Plant {
    Plant {
        states: 2,
        outputs: 1,
        f: Box::new(move |x, u, d| {
            d[0] = x[1];
            d[1] = w * w * (g(u[0]) - x[0]) - 2.0 * zeta * w * x[1];
        }),
        h: Box::new(|x, y| y[0] = x[0]),
        after: None,
        sub: 4,
        dt,
    }
}

/// What a family's draw gives: the plant, its inputs and outputs, the band to excite
/// (rad per sample) and its parameters in words.
pub(super) struct Drawn {
    pub plant: Plant,
    pub inputs: usize,
    pub band: f64,
    pub about: String,
    /// Samples of dead time on the input.
    pub delay: usize,
}

/// Draw an open-loop system of `family` (every family but the closed-loop one, which
/// `closed_loop` simulates with its controller).
pub(super) fn draw(family: Family, rng: &mut ChaCha8Rng) -> Drawn {
    let dt = 0.01;
    // Natural frequency: 3 to 20 samples per radian, the fast family 80 to 300.
    let w = if family == Family::FastSampling {
        rng.gen_range(1.0f64 / 300.0..1.0 / 80.0) / dt
    } else {
        rng.gen_range(0.05f64..0.3) / dt
    };
    let zeta = rng.gen_range(0.2..0.9);
    let band: f64 = (1.5 * w * dt).min(1.0);
    let lin = |p: Plant, about: String| Drawn {
        plant: p,
        inputs: 1,
        band,
        about,
        delay: 0,
    };
    let base = format!("w {:.3} rad/sample, zeta {zeta:.2}", w * dt);
    match family {
        Family::FastSampling | Family::SlowDrift => lin(second_order(w, zeta, dt, |u| u), base),
        Family::Saturation => {
            let s = rng.gen_range(0.5..1.2);
            lin(
                second_order(w, zeta, dt, move |u| u.clamp(-s, s)),
                format!("{base}, saturation at {s:.2}"),
            )
        }
        Family::DeadZone => {
            let d = rng.gen_range(0.2..0.6);
            let g = move |u: f64| if u.abs() <= d { 0.0 } else { u - d * u.signum() };
            lin(second_order(w, zeta, dt, g), format!("{base}, dead zone {d:.2}"))
        }
        Family::Hammerstein | Family::ShortRecord => {
            let a = rng.gen_range(0.8..2.0);
            lin(
                second_order(w, zeta, dt, move |u| (a * u).tanh() / a + 0.2 * u * u),
                format!("{base}, input tanh({a:.2} u)/{a:.2} + 0.2 u^2"),
            )
        }
        Family::Wiener => {
            let a = rng.gen_range(0.5..1.5);
            let mut p = second_order(w, zeta, dt, |u| u);
            p.h = Box::new(move |x, y| y[0] = x[0] + a * x[0] * x[0] * x[0] / 3.0 - 0.3 * (x[0] * a).tanh());
            lin(p, format!("{base}, output x + {a:.2} x^3/3 - 0.3 tanh({a:.2} x)"))
        }
        Family::Hysteresis => lin(hysteresis(w, zeta, dt, rng), base),
        Family::Backlash => {
            let play = rng.gen_range(0.1..0.4);
            lin(
                backlash(w, play, dt),
                format!("w {:.3} rad/sample, play {play:.2}", w * dt),
            )
        }
        Family::Bilinear => {
            let n = rng.gen_range(0.1..0.25);
            let p = ode(1, 1, dt, move |x, u, d| {
                d[0] = w * (-x[0] + u[0] + n * x[0] * u[0])
            });
            lin(
                p,
                format!("w {:.3} rad/sample, x' = w (-x + u + {n:.2} x u)", w * dt),
            )
        }
        Family::InputDelay => {
            let delay = rng.gen_range(3..=15);
            let p = ode(1, 1, dt, move |x, u, d| d[0] = w * (u[0] - x[0]));
            let about = format!(
                "w {:.3} rad/sample, first order, {delay} samples of dead time",
                w * dt
            );
            Drawn {
                delay,
                ..lin(p, about)
            }
        }
        Family::TwoOutputs => {
            let slow = rng.gen_range(10.0..30.0);
            let p = ode(2, 2, dt, move |x, u, d| {
                d[0] = w * (u[0] - 0.5 * u[1] - x[0]);
                d[1] = w / slow * (u[0] * u[0] - x[1]);
            });
            let about = format!(
                "speed w {:.3} rad/sample; temperature {slow:.0} x slower, heated by u1^2",
                w * dt
            );
            Drawn {
                inputs: 2,
                ..lin(p, about)
            }
        }
        Family::ClosedLoopIntegrator => unreachable!("simulated by closed_loop"),
    }
}

/// A plant of `states` states whose first `outputs` states are its outputs, 4 sub-steps
/// per sample.
fn ode(states: usize, outputs: usize, dt: f64, f: impl Fn(&[f64], &[f64], &mut [f64]) + 'static) -> Plant {
    Plant {
        states,
        outputs,
        f: Box::new(f),
        h: Box::new(move |x, y| y.copy_from_slice(&x[..outputs])),
        after: None,
        sub: 4,
        dt,
    }
}

/// A first-order motor (velocity, position) driving a load position through gear play
/// of `play`: the load moves only when the motor pushes it at either end of the play.
fn backlash(w: f64, play: f64, dt: f64) -> Plant {
    let mut p = ode(3, 1, dt, move |x, u, d| {
        d[0] = w * (u[0] - x[0]);
        d[1] = x[0];
        d[2] = 0.0;
    });
    p.h = Box::new(|x, y| y[0] = x[2]);
    p.after = Some(Box::new(move |x| {
        if x[1] - x[2] > play / 2.0 {
            x[2] = x[1] - play / 2.0;
        } else if x[2] - x[1] > play / 2.0 {
            x[2] = x[1] + play / 2.0;
        }
    }));
    p
}

/// An oscillator with a Bouc-Wen hysteretic restoring force: x'' + 2 zeta w x' +
/// w^2 (a x + (1 - a) z) = w^2 u, z' = x' - beta |x'| z - gamma x' |z|.
fn hysteresis(w: f64, zeta: f64, dt: f64, rng: &mut ChaCha8Rng) -> Plant {
    let a = rng.gen_range(0.2..0.6);
    let beta = rng.gen_range(0.5..1.5);
    let gamma = rng.gen_range(0.0..0.5);
    Plant {
        states: 3,
        outputs: 1,
        f: Box::new(move |x, u, d| {
            d[0] = x[1];
            d[1] = w * w * (u[0] - a * x[0] - (1.0 - a) * x[2]) - 2.0 * zeta * w * x[1];
            d[2] = x[1] - beta * x[1].abs() * x[2] - gamma * x[1] * x[2].abs();
        }),
        h: Box::new(|x, y| y[0] = x[0]),
        after: None,
        sub: 4,
        dt,
    }
}

/// The closed-loop integrator: a mass `m` with viscous friction `c` and Coulomb friction
/// `fc` (smoothed over 1 mm/s), its position held on reference `r` by a PD loop (natural
/// frequency `wc`) from a position measured with noise `noise`, plus a small dither on
/// the force. Returns the force and the measured position, sampled at `dt`.
pub(super) struct ClosedLoop {
    pub m: f64,
    pub c: f64,
    pub fc: f64,
    pub wc: f64,
    pub dt: f64,
}

impl ClosedLoop {
    /// Draw one.
    pub fn draw(rng: &mut ChaCha8Rng) -> ClosedLoop {
        ClosedLoop {
            m: rng.gen_range(0.5..2.0),
            c: rng.gen_range(0.2..2.0),
            fc: rng.gen_range(0.2..1.0),
            wc: std::f64::consts::TAU * rng.gen_range(1.0..3.0),
            dt: 0.005,
        }
    }

    /// Its parameters in words.
    pub fn about(&self) -> String {
        format!(
            "m {:.2} kg, viscous {:.2} N s/m, Coulomb {:.2} N, PD loop at {:.1} Hz, 5 ms samples",
            self.m,
            self.c,
            self.fc,
            self.wc / std::f64::consts::TAU
        )
    }

    /// Run on reference `r` with dither `dither` and measurement noise `noise` (one value
    /// per sample each): (force, measured position).
    pub fn run(&self, r: &[f64], dither: &[f64], noise: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let (m, c, fc) = (self.m, self.c, self.fc);
        let plant = Plant {
            states: 2,
            outputs: 1,
            f: Box::new(move |x, u, d| {
                d[0] = x[1];
                d[1] = (u[0] - c * x[1] - fc * (x[1] / 1e-3).tanh()) / m;
            }),
            h: Box::new(|x, y| y[0] = x[0]),
            after: None,
            sub: 8,
            dt: self.dt,
        };
        let (kp, kd) = (m * self.wc * self.wc, 2.0 * 0.7 * m * self.wc);
        let mut x = [0.0; 2];
        let (mut force, mut pos) = (Vec::with_capacity(r.len()), Vec::with_capacity(r.len()));
        let mut last = 0.0;
        let mut speed = 0.0;
        for k in 0..r.len() {
            let y = x[0] + noise[k];
            // The speed from differences of the measured position, low-passed at 5 wc.
            let a = (-5.0 * self.wc * self.dt).exp();
            speed = a * speed + (1.0 - a) * (y - last) / self.dt;
            last = y;
            let u = kp * (r[k] - y) - kd * speed + dither[k];
            force.push(u);
            pos.push(y);
            plant.advance(&mut x, &[u]);
        }
        (force, pos)
    }
}
