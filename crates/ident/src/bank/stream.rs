//! The bank in a user's own loop (`rhonn.OnlineIdentifier()` without a model): samples
//! arrive one at a time. The first `warmup` samples are kept; when the window is full its
//! means, standard deviations and range normalise every candidate, which then learn the
//! kept samples in order and every sample after as it comes. Each candidate is the same
//! [`Lane`] that [`super::select_with`] runs over recordings, so a stream fed here gives
//! the figures `rhonn identify` gives for the same records.

use super::lane::{Lane, Sample, Spread, Tail};
use super::{judge, BankSelection, BankSettings, Candidate};
use crate::error::{invalid, Result};
use crate::{OnlineIdentifier, WarmUp};

/// The bank fed one sample at a time.
#[derive(Debug, Clone)]
pub struct OnlineBank {
    candidates: Vec<Candidate>,
    settings: BankSettings,
    ny: usize,
    nu: usize,
    dt: f64,
    kept: Vec<Sample>,
    lanes: Vec<Lane>,
    tail: Tail,
    spread: Spread,
    estimate: Vec<f64>,
    /// The last measurement (the estimate during the warm-up).
    held: Vec<f64>,
    t_last: Option<f64>,
    record_starts: bool,
    /// With several outputs: each output's own bank (`super::per_output`), fed that
    /// output alone.
    own: Vec<OnlineBank>,
}

impl OnlineBank {
    /// The bank `candidates` for `ny` outputs and `nu` inputs sampled every `dt` s,
    /// judged by `settings`.
    pub fn new(
        candidates: Vec<Candidate>,
        ny: usize,
        nu: usize,
        dt: f64,
        settings: BankSettings,
    ) -> Result<Self> {
        if candidates.is_empty() {
            return Err(invalid("candidates", "none", "at least one candidate"));
        }
        if ny == 0 || nu == 0 {
            return Err(invalid(
                "outputs and inputs",
                format!("{ny} and {nu}"),
                "at least one of each",
            ));
        }
        if !(dt.is_finite() && (1e-9..=1e9).contains(&dt)) {
            return Err(invalid("sample time", dt, "a number of seconds in [1e-9, 1e9]"));
        }
        if settings.warmup < 2 || settings.window < 2 {
            return Err(invalid(
                "warm-up and window",
                format!("{} and {} samples", settings.warmup, settings.window),
                "at least 2 samples each",
            ));
        }
        Ok(OnlineBank {
            candidates,
            settings,
            ny,
            nu,
            dt,
            kept: Vec::new(),
            lanes: Vec::new(),
            tail: Tail::new(settings.check),
            spread: Spread::new(ny),
            estimate: vec![0.0; ny],
            held: vec![0.0; ny],
            t_last: None,
            record_starts: true,
            own: Vec::new(),
        })
    }

    /// With several outputs, also run each output's own bank of `candidates` (one
    /// output each; those that may stand alone, as `rhonn identify` does over recordings:
    /// [`super::select_per_output`]); nothing for one output.
    pub fn with_own_banks(mut self, candidates: Vec<Candidate>) -> Result<Self> {
        if self.ny > 1 {
            let candidates = super::per_output::own_candidates(candidates);
            self.own = (0..self.ny)
                .map(|_| OnlineBank::new(candidates.clone(), 1, self.nu, self.dt, self.settings))
                .collect::<Result<_>>()?;
        }
        Ok(self)
    }

    /// How it judges.
    pub fn settings(&self) -> BankSettings {
        self.settings
    }

    /// Take the sample `(t, u, y)` and return the estimate of `y(t)` made before seeing
    /// it: the leading candidate's; during the warm-up (no candidate has learned yet) the
    /// last measurement held (`y` itself at a record's first sample).
    pub fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<&[f64]> {
        self.check(t, u, y)?;
        self.spread.add(y);
        let starts = std::mem::replace(&mut self.record_starts, false);
        self.t_last = Some(t);
        self.tail.push(t, u, y, starts);
        if self.lanes.is_empty() {
            let held = if starts { y } else { &self.held };
            self.estimate.copy_from_slice(held);
            self.held.copy_from_slice(y);
            self.kept.push(Sample {
                t,
                u: u.to_vec(),
                y: y.to_vec(),
                starts_record: starts,
            });
            if self.kept.len() >= self.settings.warmup {
                self.start_lanes();
            }
            self.update_own(t, u, y, None)?;
            return Ok(&self.estimate);
        }
        if starts {
            self.lanes.iter_mut().for_each(Lane::reset);
        }
        for l in &mut self.lanes {
            l.update(t, u, y);
        }
        let leader = self.leader();
        if let Some(k) = leader {
            self.estimate.copy_from_slice(&self.lanes[k].estimate);
        }
        self.update_own(t, u, y, leader)?;
        Ok(&self.estimate)
    }

    /// Feed each output's own bank its output; where its leader runs free better than the
    /// joint leader on that output so far, the estimate of that output is its leader's.
    fn update_own(&mut self, t: f64, u: &[f64], y: &[f64], leader: Option<usize>) -> Result<()> {
        if self.own.is_empty() {
            return Ok(());
        }
        let sd = self.spread.sd();
        let joint = leader.and_then(|k| self.lanes[k].free.nrmse_each(&sd));
        for (j, b) in self.own.iter_mut().enumerate() {
            let e = b.update(t, u, &y[j..=j])?[0];
            let mine = b.leader().and_then(|k| b.lanes[k].free.nrmse(&b.spread.sd()));
            if let (Some(m), Some(theirs)) = (mine, joint.as_ref().map(|v| v[j])) {
                if m < theirs {
                    self.estimate[j] = e;
                }
            }
        }
        Ok(())
    }

    /// A new record starts with the next sample (the weights stay).
    pub fn reset(&mut self) {
        self.record_starts = true;
        self.t_last = None;
        self.own.iter_mut().for_each(OnlineBank::reset);
    }

    /// The warm-up window is full (or the stream ends): normalise every candidate by it
    /// and let each learn the kept samples in order.
    fn start_lanes(&mut self) {
        let ys: Vec<Vec<f64>> = (0..self.ny)
            .map(|j| self.kept.iter().map(|k| k.y[j]).collect())
            .collect();
        let us: Vec<Vec<f64>> = (0..self.nu)
            .map(|j| self.kept.iter().map(|k| k.u[j]).collect())
            .collect();
        let warm = WarmUp::of(&ys, &us);
        let (dt, settings) = (self.dt, self.settings);
        self.lanes = self
            .candidates
            .iter()
            .map(|c| Lane::new(c.clone(), &warm, dt, settings))
            .collect();
        for s in std::mem::take(&mut self.kept) {
            for l in &mut self.lanes {
                if s.starts_record {
                    l.reset();
                }
                l.update(s.t, &s.u, &s.y);
            }
        }
    }

    /// The candidate with the lowest free-run error so far (before any window has
    /// ended: the lowest one-step error; None before any).
    fn leader(&self) -> Option<usize> {
        let sd = self.spread.sd();
        let by = |f: &dyn Fn(&Lane) -> Option<f64>| {
            self.lanes
                .iter()
                .enumerate()
                .filter(|(_, l)| l.failed.is_none())
                .filter_map(|(k, l)| f(l).map(|v| (k, v)))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(k, _)| k)
        };
        by(&|l: &Lane| l.free.nrmse(&sd)).or_else(|| by(&|l: &Lane| l.one.nrmse(&sd)))
    }

    /// Every candidate's figures so far and the winner, with the winner as it stands
    /// (still learning; freeze it to keep it). A stream shorter than the warm-up is
    /// judged on what it has; one too short for a whole free-run window in its scored
    /// part is an error that says so.
    pub fn selection(&self) -> Result<(BankSelection, OnlineIdentifier)> {
        let mut me = self.clone();
        if me.lanes.is_empty() {
            if me.kept.len() < 2 {
                return Err(invalid(
                    "online selection",
                    format!("{} samples", me.kept.len()),
                    "at least 2 samples before a model can be chosen",
                ));
            }
            me.start_lanes();
        }
        let (mut sel, id) = judge(me.lanes, &me.spread.sd(), me.settings, &me.tail)?;
        if me.own.is_empty() {
            return Ok((sel, id));
        }
        let mut own_ids = Vec::new();
        for (j, b) in me.own.iter().enumerate() {
            // An output whose own bank cannot choose keeps the joint winner.
            let Ok((own_sel, own_id)) = b.selection() else {
                continue;
            };
            let v = super::per_output::verdict(&sel, j, &format!("y{j}"), own_sel);
            if v.own {
                own_ids.push((j, own_id));
            }
            sel.by_output.push(v);
        }
        if own_ids.is_empty() {
            return Ok((sel, id));
        }
        let combined = OnlineIdentifier::per_output(id, own_ids, &sel.chosen_spec())?;
        Ok((sel, combined))
    }

    fn check(&self, t: f64, u: &[f64], y: &[f64]) -> Result<()> {
        if u.len() != self.nu || y.len() != self.ny {
            return Err(invalid(
                "update",
                format!("{} inputs and {} outputs", u.len(), y.len()),
                format!("{} inputs and {} outputs", self.nu, self.ny),
            ));
        }
        crate::engine::check_sample_finite(t, u, y, true)?;
        if let Some(tl) = self.t_last.filter(|tl| t <= *tl) {
            return Err(invalid(
                "t",
                t,
                format!("a time after the previous sample's, {tl} s"),
            ));
        }
        Ok(())
    }
}
