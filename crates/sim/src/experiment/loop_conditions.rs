//! What stands between a controller and any plant in a closed loop: white Gaussian
//! noise on the states it measures (one seeded stream per state, so that noise on one
//! sensor never changes another's), an excitation (dither) added to its command, and a
//! transport delay of whole control periods before the command reaches the plant.
//! `closed_loop::closed_loop_with` applies them at each control instant; a scenario's
//! `[measurement]` and `[control]` sections set them.

use crate::control::Controller;
use crate::signal::Signal;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use std::collections::VecDeque;

/// The conditions of one closed loop (all SI); the default is a clean loop.
#[derive(Debug, Clone, Default)]
pub struct LoopConditions {
    /// The noisy sensors, one per plant state listed; states not listed are measured
    /// exactly.
    pub noise: Vec<SensorNoise>,
    /// An excitation added to the controller's command (SI, the input's unit); the sum
    /// is clipped to `input_range`.
    pub dither: Option<Signal>,
    /// The command reaches the plant this many control periods late; until the first
    /// one arrives, the plant holds `held_input`, or without one the controller's first
    /// command.
    pub delay_periods: u32,
    /// What the plant holds while the delay line fills (SI; the pump: its initial current).
    pub held_input: Option<f64>,
    /// The input's allowed range (SI), for the dithered command.
    pub input_range: (f64, f64),
}

/// White Gaussian noise on one plant state's measurement, from its own seeded stream.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorNoise {
    /// The plant state (index).
    pub state: usize,
    /// Standard deviation, SI.
    pub std: f64,
    /// Seed of this sensor's stream.
    pub seed: u64,
}

impl SensorNoise {
    /// Noise of standard deviation `std` on state `state`, its stream seeded by `seed`
    /// and the state's index (a scenario's `[measurement]`): a state's noise depends on
    /// nothing else. The first state's stream is `seed`'s own, the others' `seed` mixed
    /// with a multiple of a 64-bit odd constant (the pump's pressure and stroke draw what
    /// they always drew).
    pub fn per_state(state: usize, std: f64, seed: u64) -> Self {
        SensorNoise {
            state,
            std,
            seed: seed ^ (state as u64).wrapping_mul(0x5851_f42d_4c95_7f2d),
        }
    }
}

impl LoopConditions {
    /// Whether any state is measured with noise.
    pub fn noisy(&self) -> bool {
        !self.noise.is_empty()
    }
}

/// The sensors of one loop: a seeded stream per noisy state.
pub(crate) struct Sensors {
    streams: Vec<(usize, Normal<f64>, rand_chacha::ChaCha8Rng)>,
}

impl Sensors {
    /// A stream for each of `c`'s noisy states (a standard deviation of 0 is none).
    pub(crate) fn new(c: &LoopConditions) -> Self {
        let streams = c
            .noise
            .iter()
            .filter(|n| n.std > 0.0)
            .map(|n| {
                (
                    n.state,
                    Normal::new(0.0, n.std).expect("a checked standard deviation"),
                    rand_chacha::ChaCha8Rng::seed_from_u64(n.seed),
                )
            })
            .collect();
        Sensors { streams }
    }

    /// The measurement of plant state `i` whose true value is `x`.
    pub(crate) fn measure(&mut self, i: usize, x: f64) -> f64 {
        match self.streams.iter_mut().find(|(j, ..)| *j == i) {
            Some((_, n, rng)) => x + n.sample(rng),
            None => x,
        }
    }

    /// What `ctl` sees of the plant's states `x` at a control instant: each state it
    /// declares (`Controller::measurements`, the controlled one first), in its order,
    /// into `meas`.
    pub(crate) fn read_for(&mut self, ctl: &dyn Controller, x: &[f64], meas: &mut Vec<f64>) {
        meas.clear();
        for &i in ctl.measurements() {
            meas.push(self.measure(i, x[i]));
        }
    }
}

/// The actuator's side: dither, clip, delay line.
pub(crate) struct Actuator {
    dither: Option<Signal>,
    range: (f64, f64),
    delay: usize,
    held: Option<f64>,
    queue: VecDeque<f64>,
}

impl Actuator {
    pub(crate) fn new(c: &LoopConditions) -> Self {
        Actuator {
            dither: c.dither.clone(),
            range: c.input_range,
            delay: c.delay_periods as usize,
            held: c.held_input,
            queue: VecDeque::new(),
        }
    }

    /// What reaches the plant from this instant on, given the controller's command `u`
    /// at time `t`.
    pub(crate) fn apply(&mut self, t: f64, u: f64) -> f64 {
        let u = match &self.dither {
            Some(d) => (u + d.eval(t)).clamp(self.range.0, self.range.1),
            None => u,
        };
        if self.delay == 0 {
            return u;
        }
        if self.queue.is_empty() {
            let held = self.held.take().unwrap_or(u);
            self.queue.extend(std::iter::repeat_n(held, self.delay));
        }
        self.queue.push_back(u);
        self.queue
            .pop_front()
            .expect("the delay line holds at least this command")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_delay_line_holds_the_given_input_or_else_the_first_command() {
        let delayed = |held| LoopConditions {
            delay_periods: 2,
            held_input: held,
            input_range: (0.0, 10.0),
            ..LoopConditions::default()
        };
        let run = |c: &LoopConditions| {
            let mut a = Actuator::new(c);
            [1.0, 2.0, 3.0, 4.0]
                .iter()
                .enumerate()
                .map(|(k, &u)| a.apply(k as f64, u))
                .collect::<Vec<_>>()
        };
        assert_eq!(run(&delayed(Some(0.7))), [0.7, 0.7, 1.0, 2.0]);
        assert_eq!(run(&delayed(None)), [1.0, 1.0, 1.0, 2.0]);
        assert_eq!(run(&LoopConditions::default()), [1.0, 2.0, 3.0, 4.0]);
    }

    #[test]
    fn each_sensor_draws_from_its_own_stream() {
        let noisy = |noise| LoopConditions {
            noise,
            ..LoopConditions::default()
        };
        let a = SensorNoise::per_state(0, 1.0, 3);
        let b = SensorNoise::per_state(1, 1.0, 3);
        assert_ne!(a.seed, b.seed);
        let mut one = Sensors::new(&noisy(vec![a]));
        let mut both = Sensors::new(&noisy(vec![a, b]));
        for _ in 0..5 {
            // Measuring state 1 in between changes nothing of state 0's noise.
            let x = one.measure(0, 2.0);
            assert_ne!(both.measure(1, 2.0), 2.0);
            assert_eq!(both.measure(0, 2.0), x);
            assert_ne!(x, 2.0);
        }
        // No stream: exact.
        assert_eq!(one.measure(1, 2.0), 2.0);
    }
}
