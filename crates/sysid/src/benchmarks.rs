//! Synthetic systems to try a fit on, which no part of rhonn was designed around: the
//! records of `rhonn fit`'s "never worse than ARX" test and of the README's table of
//! unseen systems (`cargo run --release -p rhonn-report --example unseen_systems`).
//!
//! Both are sampled every 0.1 s under random multilevel inputs, with uniform output noise
//! of 1 % of full scale, from a seeded generator (the same seed gives the same record on
//! every machine).

use crate::data::Record;

/// A linear congruential generator of uniform numbers in [-1, 1).
struct Uniform(u64);

impl Uniform {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 33) as f64 / (1u64 << 31) as f64) * 2.0 - 1.0
    }
}

/// `n` samples of a Wiener-Hammerstein chain: a saturating actuator `tanh(2 u)`, a
/// second-order lag, a cubic sensor `x + 0.3 x^3`; one input `u` (a new level every 15
/// samples), one output `y`.
pub fn wiener_hammerstein(seed: u64, n: usize) -> Record {
    generate(seed, n, 1)
}

/// `n` samples of a bilinear system `x+ = 0.85 x + 0.2 u1 + 0.25 u1 u2 - 0.1 x u2`,
/// `y = x`; inputs `u1` (a new level every 15 samples) and `u2` (every 23).
pub fn bilinear(seed: u64, n: usize) -> Record {
    generate(seed, n, 2)
}

fn generate(seed: u64, n: usize, inputs: usize) -> Record {
    let mut rnd = Uniform(seed);
    let (mut x1, mut x2) = (0.0f64, 0.0f64);
    let (mut u1, mut u2) = (0.0, 0.0);
    let mut r = Record {
        source: format!(
            "{} (seed {seed})",
            if inputs == 1 {
                "wiener-hammerstein"
            } else {
                "bilinear"
            }
        ),
        t: Vec::with_capacity(n),
        inputs: vec![Vec::with_capacity(n); inputs],
        outputs: vec![Vec::with_capacity(n)],
    };
    for k in 0..n {
        if k % 15 == 0 {
            u1 = rnd.next();
        }
        if k % 23 == 0 {
            u2 = rnd.next();
        }
        let y = if inputs == 1 { x1 + 0.3 * x1.powi(3) } else { x1 } + 0.01 * rnd.next();
        r.t.push(k as f64 * 0.1);
        r.inputs[0].push(u1);
        r.outputs[0].push(y);
        if inputs == 1 {
            let v = (2.0 * u1).tanh();
            let x1n = 1.5 * x1 - 0.7 * x2 + 0.2 * v;
            x2 = x1;
            x1 = x1n;
        } else {
            r.inputs[1].push(u2);
            x1 = 0.85 * x1 + 0.2 * u1 + 0.25 * u1 * u2 - 0.1 * x1 * u2;
        }
    }
    r
}

/// The record as CSV text: `t`, the inputs (`u`, or `u1,u2`), `y`; every number written
/// so that it reads back to the same value.
pub fn to_csv(r: &Record) -> String {
    let mut text = String::from(if r.inputs.len() == 1 {
        "t,u,y\n"
    } else {
        "t,u1,u2,y\n"
    });
    for k in 0..r.t.len() {
        text.push_str(&format!("{}", r.t[k]));
        for u in &r.inputs {
            text.push_str(&format!(",{}", u[k]));
        }
        text.push_str(&format!(",{}\n", r.outputs[0][k]));
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_seed_gives_the_same_record_and_another_seed_another() {
        let a = wiener_hammerstein(3, 200);
        assert_eq!(a, wiener_hammerstein(3, 200));
        assert_ne!(a.outputs, wiener_hammerstein(4, 200).outputs);
        let b = bilinear(3, 200);
        assert_eq!(b.inputs.len(), 2);
        // The systems move: not a constant record.
        let (lo, hi) = b.outputs[0]
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, h), &v| (l.min(v), h.max(v)));
        assert!(hi - lo > 0.5, "{lo} {hi}");
        assert!(to_csv(&b).starts_with("t,u1,u2,y\n0,"));
    }
}
