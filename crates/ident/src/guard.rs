//! What an online identifier lets in: a sensor glitch or a paused logger is ordinary in a
//! plant, and one sample must not poison what was learned. [`SampleGuard`] judges each
//! sample before any model sees it:
//! - a value far outside the range of the signal seen so far (more than
//!   [`OUTLIER_WIDTHS`] times that range beyond it, after [`SEEN_BEFORE_JUDGING`]
//!   samples) is an outlier: **skipped**, not learned, and the lag buffers restart after
//!   it (so it never enters a regressor); [`ACCEPTED_AFTER`] such samples in a row are a
//!   new operating range, not a glitch, and are learned;
//! - a time step longer than [`GAP_STEPS`] sample times is a **gap**: the lag buffers
//!   restart (a new record begins), instead of learning across it.
//!
//! The same guard screens `rhonn identify`'s records ([`screen`]: a record is split where
//! a sample is skipped or a gap falls) and Python's `OnlineIdentifier` (the session), so
//! that the command, the bank and Python learn the same samples.

use crate::data::Record;

/// How many ranges beyond the range seen so far a value is an outlier.
pub const OUTLIER_WIDTHS: f64 = 100.0;
/// How many samples are seen before outliers are judged.
pub const SEEN_BEFORE_JUDGING: usize = 20;
/// How many outliers in a row are a new range, learned from the last of them.
pub const ACCEPTED_AFTER: usize = 3;
/// A time step longer than this many sample times is a gap.
pub const GAP_STEPS: f64 = 3.0;

/// What to do with a sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// Learn it.
    Learn,
    /// A gap before it: restart the lag buffers, then learn it.
    AfterGap,
    /// An outlier: do not learn it; restart the lag buffers after it.
    Skip,
}

/// The range of one signal seen so far.
#[derive(Debug, Clone, Copy)]
struct Seen {
    lo: f64,
    hi: f64,
}

impl Seen {
    fn widen(&mut self, x: f64) {
        self.lo = self.lo.min(x);
        self.hi = self.hi.max(x);
    }

    /// How many ranges `x` lies beyond this one (0 inside it).
    fn beyond(&self, x: f64) -> f64 {
        // A constant signal's width: a millionth of its level (or of 1), so a change of a
        // constant input is not judged against a width of zero.
        let width = (self.hi - self.lo).max(1e-6 * self.hi.abs().max(self.lo.abs()).max(1.0));
        let out = (self.lo - x).max(x - self.hi).max(0.0);
        out / width
    }
}

/// The judge of a stream's samples (see the module's doc).
#[derive(Debug, Clone)]
pub struct SampleGuard {
    dt: f64,
    seen: Vec<Seen>,
    count: usize,
    run: usize,
    t_last: Option<f64>,
    /// Samples skipped, gaps restarted over.
    pub skipped: usize,
    /// Gaps.
    pub gaps: usize,
    notes: Vec<String>,
}

/// At most this many notes are kept word for word; the rest are counted.
const NOTES_KEPT: usize = 10;

impl SampleGuard {
    /// A guard for samples every `dt` s.
    pub fn new(dt: f64) -> Self {
        SampleGuard {
            dt,
            seen: Vec::new(),
            count: 0,
            run: 0,
            t_last: None,
            skipped: 0,
            gaps: 0,
            notes: Vec::new(),
        }
    }

    /// A new record starts with the next sample: no gap is judged before it.
    pub fn reset(&mut self) {
        self.t_last = None;
    }

    /// Judge the sample `(t, u, y)` (values already checked finite).
    pub fn judge(&mut self, t: f64, u: &[f64], y: &[f64]) -> Verdict {
        let values = || u.iter().chain(y);
        if self.seen.is_empty() {
            self.seen = values().map(|&x| Seen { lo: x, hi: x }).collect();
        }
        let gap = self.t_last.is_some_and(|tl| t - tl > GAP_STEPS * self.dt);
        self.t_last = Some(t);
        let worst = values()
            .zip(&self.seen)
            .enumerate()
            .map(|(i, (&x, s))| (i, x, s.beyond(x)))
            .max_by(|a, b| a.2.total_cmp(&b.2));
        if let Some((i, x, w)) = worst.filter(|w| self.count >= SEEN_BEFORE_JUDGING && w.2 > OUTLIER_WIDTHS) {
            self.run += 1;
            if self.run < ACCEPTED_AFTER {
                self.skipped += 1;
                let name = if i < u.len() {
                    format!("u[{i}]")
                } else {
                    format!("y[{}]", i - u.len())
                };
                self.note(format!(
                    "the sample at t = {} s was skipped, not learned: {name} = {} lies {} ranges beyond the {} samples seen before it (a glitch; {ACCEPTED_AFTER} such samples in a row are learned as a new range)",
                    crate::metrics::sig(t, 6),
                    crate::metrics::sig(x, 4),
                    crate::metrics::sig(w, 2),
                    self.count
                ));
                return Verdict::Skip;
            }
        } else {
            self.run = 0;
        }
        self.count += 1;
        for (s, &x) in self.seen.iter_mut().zip(values()) {
            s.widen(x);
        }
        if gap {
            self.gaps += 1;
            self.note(format!(
                "a gap in time before t = {} s (more than {GAP_STEPS} sample times): learning restarted after it, not across it",
                crate::metrics::sig(t, 6)
            ));
            return Verdict::AfterGap;
        }
        Verdict::Learn
    }

    fn note(&mut self, n: String) {
        if self.notes.len() < NOTES_KEPT {
            self.notes.push(n);
        }
    }

    /// What was skipped or restarted, for the user: the first notes word for word, then a
    /// count of the rest.
    pub fn notes(&self) -> Vec<String> {
        let mut out = self.notes.clone();
        let all = self.skipped + self.gaps;
        if all > out.len() {
            out.push(format!(
                "{} samples skipped and {} gaps in all ({} more not listed)",
                self.skipped,
                self.gaps,
                all - out.len()
            ));
        }
        out
    }
}

/// The records an online identifier learns from `records`: each split where the guard
/// skips a sample (dropped) or finds a gap (a new record starts there), with the guard's
/// notes; None when nothing is split (learn `records` as they are).
pub fn screen(records: &[Record], dt: f64) -> (Option<Vec<Record>>, Vec<String>) {
    let mut g = SampleGuard::new(dt);
    let mut out = Vec::new();
    let mut split = false;
    for r in records {
        g.reset();
        let (mut u, mut y) = (vec![0.0; r.inputs.len()], vec![0.0; r.outputs.len()]);
        // Contiguous parts [a, b) of the record.
        let mut parts: Vec<(usize, usize)> = vec![(0, 0)];
        for k in 0..r.len() {
            super::recordings::sample(r, k, &mut u, &mut y);
            match g.judge(r.t[k], &u, &y) {
                Verdict::Learn => parts.last_mut().expect("one part").1 = k + 1,
                Verdict::AfterGap => parts.push((k, k + 1)),
                Verdict::Skip => parts.push((k + 1, k + 1)),
            }
        }
        parts.retain(|(a, b)| b > a);
        split |= parts != [(0, r.len())];
        out.push(parts);
    }
    if !split {
        return (None, g.notes());
    }
    let learned = records
        .iter()
        .zip(&out)
        .flat_map(|(r, parts)| parts.iter().map(|&(a, b)| r.slice(a, b)))
        .collect();
    (Some(learned), g.notes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_glitch_is_skipped_a_new_range_learned_and_a_gap_restarts() {
        let mut g = SampleGuard::new(1.0);
        let mut t = 0.0;
        let mut verdicts = Vec::new();
        let mut feed = |g: &mut SampleGuard, dt: f64, y: f64| {
            t += dt;
            verdicts.push(g.judge(t, &[1.0], &[y]));
        };
        for k in 0..30 {
            feed(&mut g, 1.0, (k as f64 * 0.3).sin());
        }
        feed(&mut g, 1.0, 1e10);
        feed(&mut g, 1.0, 0.5);
        // A real change of range: skipped twice, learned from the third.
        for _ in 0..4 {
            feed(&mut g, 1.0, 500.0);
        }
        feed(&mut g, 1e6, 0.2);
        assert!(verdicts[..30].iter().all(|v| *v == Verdict::Learn));
        assert_eq!(verdicts[30], Verdict::Skip);
        assert_eq!(verdicts[31], Verdict::Learn);
        assert_eq!(
            verdicts[32..36],
            [Verdict::Skip, Verdict::Skip, Verdict::Learn, Verdict::Learn]
        );
        assert_eq!(verdicts[36], Verdict::AfterGap);
        assert_eq!((g.skipped, g.gaps), (3, 1));
        let notes = g.notes();
        assert!(
            notes[0].contains("t = 31 s") && notes[0].contains("y[0] = 1e10"),
            "{notes:?}"
        );
    }
}
