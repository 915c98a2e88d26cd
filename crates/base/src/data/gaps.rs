//! One rule for gaps in a record's times, the same in `rhonn fit`, `rhonn predict`,
//! `rhonn identify` and Python: a few missing samples are filled by interpolation, a long
//! gap splits the record (rhonn learns from several records), and a record with more
//! missing samples than a small share is refused with the count. Nothing is filled
//! silently: [`Split`] says what was done.

use super::Record;
use crate::error::Result;
use crate::metrics::sig;

/// The most missing samples one gap may hold and still be filled by interpolation; a
/// longer gap splits the record.
pub const MAX_FILLED_GAP: usize = 3;
/// The largest share of a record's samples that may be filled by interpolation.
pub const MAX_FILLED_SHARE: f64 = 0.01;

/// A gap: the sample after it and how many samples are missing before it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Gap {
    /// The index of the first sample after the gap.
    pub at: usize,
    /// Samples missing (the interval's length in sampling intervals, less one).
    pub missing: usize,
}

/// What the rule did to a record.
#[derive(Debug, Clone, PartialEq)]
pub struct Split {
    /// The record.
    pub source: String,
    /// The times \[s\] at which it was split (a gap of more than [`MAX_FILLED_GAP`]
    /// samples ends there).
    pub split_at_s: Vec<f64>,
    /// Samples missing in the gaps split at.
    pub missing_split: usize,
    /// Samples missing in the gaps left to be filled.
    pub missing_filled: usize,
}

impl std::fmt::Display for Split {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let at: Vec<String> = self
            .split_at_s
            .iter()
            .take(5)
            .map(|t| format!("{} s", sig(*t, 6)))
            .collect();
        let more = self.split_at_s.len().saturating_sub(5);
        write!(
            f,
            "{}: split into {} records at {} of more than {MAX_FILLED_GAP} missing samples ({} samples missing; at {}{}): no value was made up across them",
            self.source,
            self.split_at_s.len() + 1,
            crate::metrics::count(self.split_at_s.len(), "gap"),
            self.missing_split,
            at.join(", "),
            if more > 0 { format!(" and {more} more") } else { String::new() }
        )?;
        if self.missing_filled > 0 {
            write!(
                f,
                "; {} missing samples in shorter gaps filled by interpolation",
                self.missing_filled
            )?;
        }
        Ok(())
    }
}

impl Record {
    /// The gaps in its times, against its own sampling interval
    /// ([`Record::sample_interval`]): every interval longer than 1.5 of it.
    pub fn gaps(&self) -> Vec<Gap> {
        let dt = self.sample_interval();
        if !(dt.is_finite() && dt > 0.0) {
            return Vec::new();
        }
        self.t
            .windows(2)
            .enumerate()
            .filter(|(_, w)| w[1] - w[0] > 1.5 * dt)
            .map(|(k, w)| Gap {
                at: k + 1,
                missing: (((w[1] - w[0]) / dt).round() as usize).saturating_sub(1),
            })
            .collect()
    }

    /// The record split at its gaps of more than [`MAX_FILLED_GAP`] missing samples, and
    /// what that did (None: no split). The gaps left (to be filled when the parts are put
    /// on a grid) may hold at most [`MAX_FILLED_SHARE`] of its samples in all; more is
    /// an error with the count and what to do.
    pub fn split_at_gaps(&self) -> Result<(Vec<Record>, Option<Split>)> {
        let gaps = self.gaps();
        let (long, short): (Vec<Gap>, Vec<Gap>) = gaps.iter().partition(|g| g.missing > MAX_FILLED_GAP);
        let filled: usize = short.iter().map(|g| g.missing).sum();
        let share = filled as f64 / (self.len() + filled) as f64;
        if share > MAX_FILLED_SHARE {
            return Err(crate::Error::Argument(format!(
                "{}, column `t`: {filled} samples missing in {} short gaps ({} % of the samples): at most {} % may be missing in gaps of at most {MAX_FILLED_GAP} samples, which are filled by interpolation (a longer gap splits the record); give the missing rows, or cut the record into the parts that are whole",
                self.source,
                short.len(),
                sig(share * 100.0, 3),
                sig(MAX_FILLED_SHARE * 100.0, 3)
            )));
        }
        if long.is_empty() {
            return Ok((vec![self.clone()], None));
        }
        let mut parts = Vec::new();
        let mut a = 0;
        for g in &long {
            parts.push(self.slice(a, g.at));
            a = g.at;
        }
        parts.push(self.slice(a, self.len()));
        let split = Split {
            source: self.source.clone(),
            split_at_s: long.iter().map(|g| self.t[g.at]).collect(),
            missing_split: long.iter().map(|g| g.missing).sum(),
            missing_filled: filled,
        };
        Ok((parts, Some(split)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(t: Vec<f64>) -> Record {
        let n = t.len();
        Record {
            source: "r.csv".into(),
            t,
            inputs: vec![vec![1.0; n]],
            outputs: vec![(0..n).map(|k| k as f64).collect()],
        }
    }

    #[test]
    fn a_long_gap_splits_a_few_missing_samples_are_filled_and_many_are_refused() {
        // 1,024 samples with one jump of 3.9e7 s: two records, nothing filled.
        let mut t: Vec<f64> = (0..1024).map(|k| k as f64).collect();
        for v in &mut t[600..] {
            *v += 3.9e7;
        }
        let (parts, split) = record(t).split_at_gaps().unwrap();
        assert_eq!(parts.iter().map(Record::len).collect::<Vec<_>>(), [600, 424]);
        let s = split.unwrap();
        assert_eq!(s.split_at_s, [3.9e7 + 600.0]);
        assert!(s.to_string().contains("split into 2 records"), "{s}");
        // Five single missing samples in 1,000: filled (0.5 %), no split.
        let t: Vec<f64> = (0..1005).filter(|k| k % 200 != 7).map(|k| k as f64).collect();
        let (parts, split) = record(t).split_at_gaps().unwrap();
        assert_eq!((parts.len(), split), (1, None));
        // 100 single missing samples of 1,024: refused with the count.
        let t: Vec<f64> = (0..1124).filter(|k| k % 11 != 5).map(|k| k as f64).collect();
        let e = record(t).split_at_gaps().unwrap_err().to_string();
        assert!(
            e.contains("102 samples missing in 102 short gaps") && e.contains("at most 1 %"),
            "{e}"
        );
    }
}
