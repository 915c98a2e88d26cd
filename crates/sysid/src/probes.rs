//! How a candidate runs free on inputs its folds do not hold: each fold's model runs free
//! once more on each held-out part with the part's inputs replaced by held steps at levels
//! of the part's own input distribution (its quantiles: every level is one the system was
//! recorded at, but held, as a user's next record of steps or pulses holds it), scored by
//! how far the free run leaves the training output range (the **excursion**: RMS distance
//! outside the range, in output standard deviations). A caution, not a rule of the
//! selection: a true system may leave the range under held steps (a Wiener system's
//! output nonlinearity), and on the unseen-systems corpus a rule that put out candidates
//! beyond it chose worse models (`docs/results.md`).

use super::Model;
use crate::data::Record;
use crate::error::Result;

/// A fold model's probe figure, averaged over outputs and held-out parts.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct Probe {
    /// RMS distance outside the training range under held steps, in output standard
    /// deviations.
    pub excursion: f64,
}

/// The chosen model's excursion beyond which the selection says to check it on steps.
pub const EXCURSION_CAUTION: f64 = 1.0;

/// Quantiles the held steps take, in order.
const LEVELS: [f64; 8] = [0.5, 0.9, 0.1, 0.7, 0.3, 0.97, 0.03, 0.6];

/// `r` with its inputs replaced by held steps at quantiles of its own inputs.
fn held_steps(r: &Record, hold: usize) -> Record {
    let mut s = r.clone();
    for c in &mut s.inputs {
        let mut sorted = c.clone();
        sorted.sort_by(f64::total_cmp);
        let at = |q: f64| sorted[((sorted.len() - 1) as f64 * q).round() as usize];
        for (k, v) in c.iter_mut().enumerate() {
            *v = at(LEVELS[(k / hold) % LEVELS.len()]);
        }
    }
    s
}

/// `m`'s probe figure on the held-out parts `test` (parts shorter than its lags need are
/// left out; none left: zero). A free run that fails or is not finite gives NaN: no
/// figure (the candidate's score is the folds' matter, not the probe's).
pub(super) fn probe(m: &Model, test: &[Record]) -> Probe {
    measure(m, test).unwrap_or(Probe { excursion: f64::NAN })
}

fn measure(m: &Model, test: &[Record]) -> Result<Probe> {
    let needed = m.spec.max_lag() + 3;
    let (mut exc, mut n) = (0.0, 0.0);
    for r in test.iter().filter(|r| r.len() >= needed.max(16)) {
        let hold = (r.len() / LEVELS.len()).max(2 * needed);
        let (steps, first) = m.predict(&held_steps(r, hold), None)?;
        for j in 0..m.outputs.len() {
            let sd = m.output_norm[j].1;
            let (lo, hi) = m.output_range[j];
            let len = (steps[j].len() - first).max(1) as f64;
            let out: f64 = steps[j][first..]
                .iter()
                .map(|&v| ((v - hi).max(lo - v).max(0.0) / sd).powi(2))
                .sum();
            exc += (out / len).sqrt();
            n += 1.0;
        }
    }
    if n == 0.0 {
        return Ok(Probe::default());
    }
    Ok(Probe { excursion: exc / n })
}
