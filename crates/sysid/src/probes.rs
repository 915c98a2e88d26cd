//! How a candidate runs free on inputs its folds do not hold: each fold's model runs free
//! once more on each held-out part with the part's inputs replaced by held steps at levels
//! of the part's own input distribution (its quantiles: every level is one the system was
//! recorded at, but held, as a user's next record of steps or pulses holds it), scored by
//! how far the free run leaves the training output range (the **excursion**: RMS distance
//! outside the range, in output standard deviations). Above 1 for the chosen model, a
//! caution (a true system may leave the range under held steps: a Wiener system's output
//! nonlinearity; on the unseen-systems corpus a rule that put out candidates above 1 and
//! twice the best ARX's chose worse models); above `select_candidates::EXCURSION_LIMIT`
//! (1.5), a rule: such a structure does not replace the ARX (`docs/results.md`).
//!
//! The same free runs give each structure's **disagreement** ([`disagreements`]): how far
//! its held-step runs are from those of the other structures that could replace the best
//! ARX, against how far those are from each other. That one is a rule (`select_rule`): a
//! structure that extrapolates in a way of its own, where the folds cannot judge it, does
//! not replace the ARX. Its distance to the best ARX's runs was measured first and does not
//! separate (a Wiener system's right model is far from the ARX there too).

use super::Model;
use crate::data::Record;
use crate::error::Result;

/// One part's prediction of every output and its first predicted sample (a held-out
/// part's free run, in `folds`, or its free run under held steps here).
pub(super) type PartRun = (Vec<Vec<f64>>, usize);

/// A fold model's probe figure, averaged over outputs and held-out parts.
#[derive(Debug, Clone, PartialEq, Default)]
pub(super) struct Probe {
    /// RMS distance outside the training range under held steps, in output standard
    /// deviations.
    pub excursion: f64,
    /// The free run under held steps, per held-out part (None: too short for the probe).
    pub held: Vec<Option<PartRun>>,
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
    measure(m, test).unwrap_or(Probe {
        excursion: f64::NAN,
        held: Vec::new(),
    })
}

fn measure(m: &Model, test: &[Record]) -> Result<Probe> {
    let needed = m.spec.max_lag() + 3;
    let (mut exc, mut n) = (0.0, 0.0);
    let mut held = Vec::with_capacity(test.len());
    for r in test {
        if r.len() < needed.max(16) {
            held.push(None);
            continue;
        }
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
        held.push(Some((steps, first)));
    }
    if n == 0.0 {
        return Ok(Probe { excursion: 0.0, held });
    }
    Ok(Probe {
        excursion: exc / n,
        held,
    })
}

/// How far `a`'s free runs under held steps are from `b`'s, fold by fold: the RMS
/// difference over the samples both predict, in output standard deviations `sd`, the mean
/// over parts and outputs; then the mean over folds. None when no fold has a part both
/// predict.
fn distance(a: &[&Probe], b: &[&Probe], sd: &[f64]) -> Option<f64> {
    let mut folds = Vec::new();
    for (pa, pb) in a.iter().zip(b) {
        let (mut sum, mut n) = (0.0, 0.0);
        for (x, y) in pa.held.iter().zip(&pb.held) {
            let (Some((ya, fa)), Some((yb, fb))) = (x, y) else {
                continue;
            };
            let first = (*fa).max(*fb);
            for (j, (ra, rb)) in ya.iter().zip(yb).enumerate() {
                let len = ra.len().min(rb.len());
                if len <= first {
                    continue;
                }
                let d = crate::metrics::rms_error(&ra[first..len], &rb[first..len]);
                sum += d / sd.get(j).copied().unwrap_or(1.0);
                n += 1.0;
            }
        }
        if n > 0.0 {
            folds.push(sum / n);
        }
    }
    (!folds.is_empty()).then(|| folds.iter().sum::<f64>() / folds.len() as f64)
}

/// Held-step runs within this many output standard deviations (RMS) of each other agree.
const AGREEMENT: f64 = 1e-3;

/// The upper median of `v` (None when empty).
fn median(mut v: Vec<f64>) -> Option<f64> {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied()
}

/// Each rival's disagreement under held steps (None for a candidate that is not one, and
/// for all when fewer than 3 are): the median of its distances to the other rivals' free
/// runs, over the median of those medians. About 1 for a structure that extrapolates as
/// most do; a structure far above runs in a way of its own where the folds cannot judge
/// it (on the corpus, seed 7: a lagged RHONN trained on its free run that scored 0.048 on
/// the folds against the best ARX's 0.32, its disagreement 3.7, ran free 6.8 x the ARX on
/// a test of steps). `rivals[i]`: candidate i's probe on every fold.
pub(super) fn disagreements(rivals: &[Option<Vec<&Probe>>], sd: &[f64]) -> Vec<Option<f64>> {
    let members: Vec<usize> = (0..rivals.len()).filter(|&i| rivals[i].is_some()).collect();
    let mut out = vec![None; rivals.len()];
    if members.len() < 3 {
        return out;
    }
    let probes = |i: usize| rivals[i].as_deref().unwrap_or(&[]);
    // The distance is symmetric: each pair once.
    let m = members.len();
    let mut pair = vec![None; m * m];
    for a in 0..m {
        for b in a + 1..m {
            let d = distance(probes(members[a]), probes(members[b]), sd);
            (pair[a * m + b], pair[b * m + a]) = (d, d);
        }
    }
    let own: Vec<Option<f64>> = (0..m)
        .map(|a| {
            median(
                (0..m)
                    .filter(|&b| b != a)
                    .filter_map(|b| pair[a * m + b])
                    .collect(),
            )
        })
        .collect();
    let Some(typical) = median(own.iter().flatten().copied().collect()) else {
        return out;
    };
    // Distances below AGREEMENT are agreement: rivals that all run within it of each other
    // (a noise-free linear record: 1e-13) have nothing to tell apart.
    let typical = typical.max(AGREEMENT);
    for (&i, m) in members.iter().zip(&own) {
        out[i] = m.map(|m| m / typical);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{disagreements, Probe};

    /// A probe of one fold, one part, one output: the held-step run `run`.
    fn probe(run: Vec<f64>) -> Probe {
        Probe {
            excursion: 0.0,
            held: vec![Some((vec![run], 0))],
        }
    }

    #[test]
    fn the_structure_that_runs_apart_from_the_others_under_held_steps_disagrees() {
        let runs = [
            probe(vec![0.0, 1.0, 2.0]),
            probe(vec![0.1, 1.1, 2.1]),
            probe(vec![0.0, 1.2, 1.9]),
            probe(vec![3.0, -2.0, 6.0]),
        ];
        let rivals: Vec<Option<Vec<&Probe>>> = runs.iter().map(|p| Some(vec![p])).collect();
        let d = disagreements(&rivals, &[1.0]);
        let far = d[3].unwrap();
        assert!(far > 5.0, "{d:?}");
        for x in &d[..3] {
            let x = x.unwrap();
            assert!((0.5..=1.5).contains(&x), "{d:?}");
        }
        // Rivals that agree to within rounding: no disagreement to speak of.
        let tiny: Vec<Probe> = [0.0, 1e-13, 2e-13, 9e-13]
            .iter()
            .map(|e| probe(vec![1.0 + e, 2.0 - e, 3.0]))
            .collect();
        let rivals: Vec<Option<Vec<&Probe>>> = tiny.iter().map(|p| Some(vec![p])).collect();
        assert!(disagreements(&rivals, &[1.0]).iter().all(|d| d.unwrap() < 1e-6));
        // A candidate that is not a rival has none, and fewer than 3 rivals give none.
        let some: Vec<Option<Vec<&Probe>>> = vec![Some(vec![&runs[0]]), None, Some(vec![&runs[3]])];
        assert_eq!(disagreements(&some, &[1.0]), vec![None, None, None]);
    }
}
