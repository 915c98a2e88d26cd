//! What stands between a controller and any plant in a closed loop: white Gaussian
//! noise on the states it measures (one seeded stream per state, so that noise on one
//! sensor never changes another's), an excitation (dither) added to its command, and a
//! transport delay of whole control periods before the command reaches the plant.
//! `any_plant::closed_loop_with` applies them at each control instant; a plant
//! scenario's `[measurement]` and `[control]` sections set them.

use crate::signal::Signal;
use rand::SeedableRng;
use rand_distr::{Distribution, Normal};
use std::collections::VecDeque;

/// The conditions of one closed loop (all SI); the default is a clean loop.
#[derive(Debug, Clone, Default)]
pub struct LoopConditions {
    /// Per plant state (by index): the standard deviation of the noise on its
    /// measurement, SI. States not listed are measured exactly.
    pub noise_std: Vec<(usize, f64)>,
    /// Seed of the noise streams.
    pub seed: u64,
    /// An excitation added to the controller's command (SI, the input's unit); the sum
    /// is clipped to `input_range`.
    pub dither: Option<Signal>,
    /// The command reaches the plant this many control periods late; until the first
    /// one arrives, the plant holds the controller's first command.
    pub delay_periods: u32,
    /// The input's allowed range (SI), for the dithered command.
    pub input_range: (f64, f64),
}

impl LoopConditions {
    /// Whether any state is measured with noise.
    pub fn noisy(&self) -> bool {
        !self.noise_std.is_empty()
    }
}

/// The sensors of one loop: a seeded stream per noisy state.
pub(crate) struct Sensors {
    streams: Vec<(usize, Normal<f64>, rand_chacha::ChaCha8Rng)>,
}

impl Sensors {
    /// Streams for `c`'s noisy states, each seeded by the seed and the state's index: a
    /// state's noise depends on nothing else.
    pub(crate) fn new(c: &LoopConditions) -> Self {
        let streams = c
            .noise_std
            .iter()
            .filter(|(_, std)| *std > 0.0)
            .map(|&(i, std)| {
                let rng = rand_chacha::ChaCha8Rng::seed_from_u64(
                    c.seed ^ (i as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15),
                );
                (
                    i,
                    Normal::new(0.0, std).expect("a checked standard deviation"),
                    rng,
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
}

/// The actuator's side: dither, clip, delay line.
pub(crate) struct Actuator {
    dither: Option<Signal>,
    range: (f64, f64),
    delay: usize,
    queue: VecDeque<f64>,
}

impl Actuator {
    pub(crate) fn new(c: &LoopConditions) -> Self {
        Actuator {
            dither: c.dither.clone(),
            range: c.input_range,
            delay: c.delay_periods as usize,
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
            self.queue.extend(std::iter::repeat(u).take(self.delay));
        }
        self.queue.push_back(u);
        self.queue
            .pop_front()
            .expect("the delay line holds at least this command")
    }
}
