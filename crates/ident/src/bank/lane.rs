//! One candidate of the bank run over a stream, one sample at a time, and its
//! prequential figures: each sample is predicted before it is learned (one step ahead);
//! at every half window of the scored part of the stream, a frozen copy of the candidate
//! as it stands then starts a free run on the inputs that follow and, once it has run a
//! whole window inside the same record, adds its errors to the free-run figure. A copy
//! whose record ends first is dropped. The same code serves `rhonn identify` over
//! recordings and a user's own loop (`OnlineBank`), so both give the same figures.

use super::{BankSettings, Candidate};
use crate::error::Result;
use crate::{OnlineIdentifier, OnlineSpec, WarmUp};
use std::collections::VecDeque;

/// Per output, the sum of squared errors and its count.
#[derive(Debug, Clone)]
pub(super) struct Sums {
    sq: Vec<f64>,
    pub(super) n: usize,
}

impl Sums {
    pub(super) fn new(ny: usize) -> Self {
        Sums {
            sq: vec![0.0; ny],
            n: 0,
        }
    }

    fn add(&mut self, y: &[f64], yh: &[f64]) {
        for ((s, a), b) in self.sq.iter_mut().zip(y).zip(yh) {
            *s += (a - b) * (a - b);
        }
        self.n += 1;
    }

    fn merge(&mut self, other: &Sums) {
        for (a, b) in self.sq.iter_mut().zip(&other.sq) {
            *a += b;
        }
        self.n += other.n;
    }

    /// RMS error / sd per output, averaged over outputs (None before any sample).
    pub(super) fn nrmse(&self, sd: &[f64]) -> Option<f64> {
        // Without `nrmse_each`'s vector: the loop's leader is judged on this every sample.
        if self.n == 0 {
            return None;
        }
        let n = self.n as f64;
        let v = self
            .sq
            .iter()
            .zip(sd)
            .map(|(s, d)| (s / n).sqrt() / d)
            .sum::<f64>()
            / sd.len() as f64;
        Some(v)
    }

    /// RMS error / sd of each output (None before any sample).
    pub(super) fn nrmse_each(&self, sd: &[f64]) -> Option<Vec<f64>> {
        if self.n == 0 {
            return None;
        }
        let n = self.n as f64;
        Some(self.sq.iter().zip(sd).map(|(s, d)| (s / n).sqrt() / d).collect())
    }
}

/// A sample of the stream, and whether a record started with it.
#[derive(Debug, Clone)]
pub(super) struct Sample {
    pub(super) t: f64,
    pub(super) u: Vec<f64>,
    pub(super) y: Vec<f64>,
    pub(super) starts_record: bool,
}

/// The stream's last `cap` samples: what each candidate, frozen as it ended, runs free
/// over before it may be chosen.
#[derive(Debug, Clone)]
pub(super) struct Tail {
    cap: usize,
    buf: VecDeque<Sample>,
}

impl Tail {
    pub(super) fn new(cap: usize) -> Self {
        Tail {
            cap,
            buf: VecDeque::with_capacity(cap.min(1 << 16)),
        }
    }

    pub(super) fn push(&mut self, t: f64, u: &[f64], y: &[f64], starts_record: bool) {
        if self.cap == 0 {
            return;
        }
        if self.buf.len() == self.cap {
            self.buf.pop_front();
        }
        self.buf.push_back(Sample {
            t,
            u: u.to_vec(),
            y: y.to_vec(),
            starts_record,
        });
    }

    /// Samples held.
    pub(super) fn len(&self) -> usize {
        self.buf.len()
    }
}

/// `id` frozen as it stands, run free over `tail` from the tail's start (restarted at
/// the tail's first sample and at every record's start), its errors counted from its
/// first genuine prediction after each restart. `Ok(None)`: its free run was not finite.
pub(super) fn final_free_run(id: &OnlineIdentifier, spec: &OnlineSpec, tail: &Tail) -> Result<Option<Sums>> {
    let Some(first) = tail.buf.front() else {
        return Ok(None);
    };
    let mut copy = id.clone();
    copy.freeze(true);
    copy.set_free_run(true);
    let lead = crate::first_prediction(spec);
    let mut sums = Sums::new(first.y.len());
    let mut since = 0;
    for (k, s) in tail.buf.iter().enumerate() {
        if k == 0 || s.starts_record {
            copy.reset();
            since = 0;
        }
        let yh = copy.update(s.t, &s.u, &s.y)?;
        if yh.iter().any(|v| !v.is_finite()) {
            return Ok(None);
        }
        if since >= lead {
            sums.add(&s.y, yh);
        }
        since += 1;
    }
    Ok(Some(sums))
}

/// A free-run copy under way: the copy, its errors so far, the samples it has run.
#[derive(Debug, Clone)]
struct FreeRun {
    id: OnlineIdentifier,
    sums: Sums,
    ran: usize,
}

/// One candidate on the stream.
#[derive(Debug, Clone)]
pub(super) struct Lane {
    pub(super) candidate: Candidate,
    /// The candidate as it learns (None once it failed).
    pub(super) id: Option<OnlineIdentifier>,
    /// Why it failed (it diverged, or its settings do not fit the data).
    pub(super) failed: Option<String>,
    pub(super) one: Sums,
    pub(super) free: Sums,
    runs: Vec<FreeRun>,
    /// Its last one-step estimate.
    pub(super) estimate: Vec<f64>,
    settings: BankSettings,
    /// Samples seen in the stream, and in the current record.
    seen: usize,
    in_record: usize,
}

impl Lane {
    /// The candidate normalised by the warm-up window, judged on one pass whatever its
    /// final passes.
    /// A block structure's window is at most the warm-up (it is fitted before the scored
    /// part starts).
    pub(super) fn new(mut candidate: Candidate, warm: &WarmUp, dt: f64, settings: BankSettings) -> Self {
        let ny = warm.lo.len();
        if let Some(b) = &mut candidate.spec.block {
            b.window = b.window.min(settings.warmup).max(20);
        }
        let one_pass = OnlineSpec {
            epochs: 1,
            ..candidate.spec.clone()
        };
        let (id, failed) = match warm.identifier(&one_pass, dt) {
            Ok(mut id) => {
                id.new_pass();
                (Some(id), None)
            }
            Err(e) => (None, Some(e.to_string())),
        };
        Lane {
            candidate,
            id,
            failed,
            one: Sums::new(ny),
            free: Sums::new(ny),
            runs: Vec::new(),
            estimate: vec![0.0; ny],
            settings,
            seen: 0,
            in_record: 0,
        }
    }

    /// A new record starts: the model restarts at its next measurement; free runs under
    /// way are dropped (they would cross into another record).
    pub(super) fn reset(&mut self) {
        if let Some(id) = &mut self.id {
            id.reset();
        }
        self.runs.clear();
        self.in_record = 0;
    }

    /// Take the sample `(t, u, y)`; a failure ends the lane (kept in `failed`).
    pub(super) fn update(&mut self, t: f64, u: &[f64], y: &[f64]) {
        if self.id.is_none() {
            return;
        }
        if let Err(e) = self.step(t, u, y) {
            self.failed = Some(e.to_string());
            self.id = None;
            self.runs.clear();
        }
    }

    fn step(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<()> {
        let Some(id) = &mut self.id else { return Ok(()) };
        let s = self.settings;
        let scored = self.seen >= s.scored_from;
        if scored && self.in_record > 0 && self.in_record.is_multiple_of((s.window / 2).max(1)) {
            let mut copy = id.clone();
            copy.freeze(true);
            copy.set_free_run(true);
            self.runs.push(FreeRun {
                id: copy,
                sums: Sums::new(y.len()),
                ran: 0,
            });
        }
        for r in &mut self.runs {
            let yh = r.id.update(t, u, y)?;
            r.sums.add(y, yh);
            r.ran += 1;
        }
        let free = &mut self.free;
        self.runs.retain(|r| {
            let done = r.ran >= s.window;
            if done {
                free.merge(&r.sums);
            }
            !done
        });
        let yh = id.update(t, u, y)?;
        if yh.iter().any(|v| !v.is_finite()) {
            return Err(crate::Error::NotFinite {
                what: format!("the estimate at t = {t} s"),
                cause: "its prequential error is not finite".into(),
            });
        }
        self.estimate.copy_from_slice(yh);
        if scored {
            self.one.add(y, yh);
        }
        self.seen += 1;
        self.in_record += 1;
        Ok(())
    }
}

/// Per output, the running mean and variance of the samples seen (Welford's update), to
/// normalise the candidates' errors.
#[derive(Debug, Clone)]
pub(super) struct Spread {
    n: usize,
    mean: Vec<f64>,
    m2: Vec<f64>,
}

impl Spread {
    pub(super) fn new(ny: usize) -> Self {
        Spread {
            n: 0,
            mean: vec![0.0; ny],
            m2: vec![0.0; ny],
        }
    }

    pub(super) fn add(&mut self, y: &[f64]) {
        self.n += 1;
        let n = self.n as f64;
        for ((m, s), v) in self.mean.iter_mut().zip(&mut self.m2).zip(y) {
            let d = v - *m;
            *m += d / n;
            *s += d * (v - *m);
        }
    }

    /// Per output, the standard deviation (1 for an output that has not moved).
    pub(super) fn sd(&self) -> Vec<f64> {
        self.m2
            .iter()
            .map(|s| {
                let sd = (s / self.n.max(1) as f64).sqrt();
                if sd > 0.0 && sd.is_finite() {
                    sd
                } else {
                    1.0
                }
            })
            .collect()
    }
}
