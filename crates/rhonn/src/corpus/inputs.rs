//! The excitations of the corpus's records: what a user records a system with (a
//! multisine, filtered noise) and what they then run it on (steps, pulses).

use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use serde::Serialize;

/// The kind of an input signal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum InputKind {
    /// A random-phase multisine over a band.
    Multisine,
    /// Gaussian noise through a first-order low-pass filter.
    FilteredNoise,
    /// Random levels held for random durations.
    Steps,
    /// Rectangular pulses of random height and width from rest.
    Pulses,
}

impl InputKind {
    /// Its name in tables.
    pub fn name(self) -> &'static str {
        match self {
            InputKind::Multisine => "multisine",
            InputKind::FilteredNoise => "filtered noise",
            InputKind::Steps => "steps",
            InputKind::Pulses => "pulses",
        }
    }
}

/// `n` samples of a signal of `kind` with RMS about `rms`, its content up to `band`
/// (rad per sample, below pi): a multisine's highest line, the noise filter's corner, and
/// for steps and pulses the shortest hold of about 1 / `band` samples, many times it the
/// longest, so that a system of that bandwidth settles between changes.
pub fn signal(kind: InputKind, n: usize, band: f64, rms: f64, rng: &mut ChaCha8Rng) -> Vec<f64> {
    let band = band.clamp(1e-4, 3.0);
    let mut s = match kind {
        InputKind::Multisine => {
            let lines = 24;
            let lo = band / 40.0;
            let w: Vec<(f64, f64)> = (0..lines)
                .map(|k| {
                    let f = lo * (band / lo).powf(k as f64 / (lines - 1) as f64);
                    (f, rng.gen_range(0.0..std::f64::consts::TAU))
                })
                .collect();
            (0..n)
                .map(|i| w.iter().map(|(f, p)| (f * i as f64 + p).sin()).sum())
                .collect()
        }
        InputKind::FilteredNoise => {
            let a = (-band).exp();
            let mut y = 0.0;
            (0..n)
                .map(|_| {
                    let e: f64 = StandardNormal.sample(rng);
                    y = a * y + (1.0 - a) * e;
                    y
                })
                .collect()
        }
        InputKind::Steps | InputKind::Pulses => {
            let shortest = (1.0 / band).ceil().max(2.0) as usize;
            let mut v = Vec::with_capacity(n);
            let mut rest = true;
            while v.len() < n {
                let hold = rng.gen_range(shortest..=8 * shortest);
                let level = match kind {
                    InputKind::Steps => rng.gen_range(-1.0..1.0),
                    _ if rest => 0.0,
                    _ => rng.gen_range(0.3..1.0) * if rng.gen_bool(0.5) { 1.0 } else { -1.0 },
                };
                rest = !rest;
                v.extend(std::iter::repeat_n(level, hold.min(n - v.len())));
            }
            v
        }
    };
    let mean = s.iter().sum::<f64>() / n.max(1) as f64;
    if matches!(kind, InputKind::Multisine | InputKind::FilteredNoise) {
        s.iter_mut().for_each(|x| *x -= mean);
    }
    let r = (s.iter().map(|x| x * x).sum::<f64>() / n.max(1) as f64).sqrt();
    if r > 0.0 {
        s.iter_mut().for_each(|x| *x *= rms / r);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn each_kind_has_the_asked_rms_and_pulses_start_from_rest() {
        for kind in [
            InputKind::Multisine,
            InputKind::FilteredNoise,
            InputKind::Steps,
            InputKind::Pulses,
        ] {
            let mut rng = ChaCha8Rng::seed_from_u64(3);
            let s = signal(kind, 2000, 0.1, 2.0, &mut rng);
            let r = (s.iter().map(|x| x * x).sum::<f64>() / 2000.0).sqrt();
            assert!((r - 2.0).abs() < 1e-9, "{kind:?}: rms {r}");
            if kind == InputKind::Pulses {
                assert_eq!(s[0], 0.0, "pulses start at rest");
            }
        }
    }
}
