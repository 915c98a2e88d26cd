//! Online model selection (`rhonn identify` without `--model`): a bank of candidate online
//! models, each run over the same stream of recordings in one pass, ranked by their
//! **prequential** error: every sample is predicted before it is learned (one step ahead),
//! and at regular starts a frozen copy of each candidate, as it stands then, runs free over
//! the next window of inputs and is compared with the outputs it has not yet learned from.
//! Nothing looks ahead: a candidate's weights at a window's start come from the samples
//! before it. The candidate with the lowest free-run error over the windows of the second
//! half of the stream wins (the first half is its warm-up); every candidate keeps its own
//! law's bound (least squares, whose covariance only shrinks, with its output bounds; the
//! continuous neurons' law; the cascade's bounded chain).

use super::online::{OnlineIdentifier, OnlineSpec, Scaling};
use super::online_spec::{LagSpec, OnlineStructure};
use crate::data::Record;
use crate::error::{invalid, Result};
use serde::Serialize;

/// A candidate of the bank: a name and its settings.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Candidate {
    /// A short name, e.g. "lagged RHONN na 4 nb 4 degree 2".
    pub name: String,
    /// The settings, as a `--model` spec would give them.
    pub spec: OnlineSpec,
}

/// One candidate's prequential figures.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CandidateScore {
    /// Its name.
    pub name: String,
    /// Its settings (`epochs`: the passes the winner is trained for once chosen; the bank
    /// itself judges every candidate on one pass).
    pub spec: OnlineSpec,
    /// One step ahead, predicted before learned, over the second half of the stream:
    /// RMS error / the output's standard deviation, averaged over outputs (None: failed).
    pub one_step_nrmse: Option<f64>,
    /// Free run of the frozen copy over each window of the second half, as the one-step
    /// figure (the ranking figure; None: failed).
    pub free_run_nrmse: Option<f64>,
    /// Why it has no figures (it diverged, or its settings do not fit the data).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failed: Option<String>,
}

/// What the bank found (`summary.json`'s `selection`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BankSelection {
    /// How the candidates were judged, in words.
    pub judged_by: String,
    /// Samples in each free-run window.
    pub window: usize,
    /// Every candidate, in the bank's order.
    pub candidates: Vec<CandidateScore>,
    /// Index of the winner.
    pub chosen: usize,
    /// Index of the best recursive ARX (the linear candidates).
    pub best_arx: Option<usize>,
}

impl BankSelection {
    /// The winner's settings.
    pub fn chosen_spec(&self) -> &OnlineSpec {
        &self.candidates[self.chosen].spec
    }

    /// What was found, in words.
    pub fn findings(&self) -> Vec<String> {
        let c = &self.candidates[self.chosen];
        let mut v = vec![format!(
            "online selection: {} of {} candidates won ({}: free-run error {:.3} of the output's standard deviation)",
            c.name,
            self.candidates.len(),
            self.judged_by,
            c.free_run_nrmse.unwrap_or(f64::NAN)
        )];
        if let Some(a) = self.best_arx.map(|k| &self.candidates[k]) {
            if let (Some(w), Some(b)) = (c.free_run_nrmse, a.free_run_nrmse) {
                if a.name != c.name {
                    v.push(format!(
                        "online selection: {:.0} % lower prequential free-run error than the best recursive ARX ({}, {:.3})",
                        100.0 * (1.0 - w / b),
                        a.name,
                        b
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

/// Whether a candidate is a recursive ARX (the lagged structure of degree 1).
fn is_linear(spec: &OnlineSpec) -> bool {
    spec.structure == OnlineStructure::Lagged && spec.degree == 1
}

/// The most samples of a stream the cascade candidate (extended Kalman filters from
/// several starts, the slowest) runs on.
pub const MAX_CASCADE_SAMPLES: usize = 5_000;

/// The default bank for `ny` outputs and a stream of `samples` samples: recursive ARX at
/// three orders, the lagged RHONN by recursive least squares at three orders of degree 2
/// and two of degree 3 (the high-order terms on the first lags only at the longer orders), the thesis's continuous-time neurons, and, for one output and a
/// stream of at most [`MAX_CASCADE_SAMPLES`], the cascade with a hidden neuron.
pub fn default_candidates(ny: usize, samples: usize) -> Vec<Candidate> {
    let mut c = vec![
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

/// Per output, the sum of squared errors and its count.
#[derive(Clone)]
struct Sums {
    sq: Vec<f64>,
    n: usize,
}

impl Sums {
    fn new(ny: usize) -> Self {
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

    /// RMS error / sd per output, averaged.
    fn nrmse(&self, sd: &[f64]) -> f64 {
        let n = self.n.max(1) as f64;
        self.sq
            .iter()
            .zip(sd)
            .map(|(s, d)| (s / n).sqrt() / d)
            .sum::<f64>()
            / sd.len() as f64
    }
}

/// Run one candidate over the stream: (one-step, free-run) normalised errors.
fn score(c: &Candidate, records: &[Record], dt: f64, window: usize, sd: &[f64]) -> Result<(f64, f64)> {
    let (ny, nu) = (records[0].outputs.len(), records[0].inputs.len());
    let scaling: Scaling = super::record_scaling(&c.spec, records);
    // One pass, whatever the candidate's final passes: predicted before learned.
    let one_pass = OnlineSpec {
        epochs: 1,
        ..c.spec.clone()
    };
    let mut id = OnlineIdentifier::new(&one_pass, ny, nu, dt, scaling)?;
    let total: usize = records.iter().map(Record::len).sum();
    let (mut one, mut free) = (Sums::new(ny), Sums::new(ny));
    let (mut u, mut y) = (vec![0.0; nu], vec![0.0; ny]);
    let mut g = 0;
    id.new_pass();
    for r in records {
        id.reset();
        id.freeze(false);
        for k in 0..r.len() {
            let scored = g >= total / 2;
            // A window starts every half window in the scored half, wherever a whole one
            // fits in the record (after the candidate's first sample there).
            if scored && k > 0 && k % (window / 2).max(1) == 0 && k + window <= r.len() {
                let mut f = id.clone();
                f.freeze(true);
                f.set_free_run(true);
                for j in k..k + window {
                    super::recordings::sample(r, j, &mut u, &mut y);
                    let yh = f.update(r.t[j], &u, &y)?;
                    free.add(&y, yh);
                }
            }
            super::recordings::sample(r, k, &mut u, &mut y);
            let yh = id.update(r.t[k], &u, &y)?;
            if scored {
                one.add(&y, yh);
            }
            g += 1;
        }
    }
    if free.n == 0 {
        return Err(invalid(
            "data",
            format!("{total} samples"),
            format!("records long enough for a free-run window of {window} samples in the second half"),
        ));
    }
    Ok((one.nrmse(sd), free.nrmse(sd)))
}

/// Run the bank `candidates` on `records` (outputs named `outputs`) and pick the winner
/// by its prequential free-run error. Candidates run in parallel; one that fails
/// (diverges, or does not fit the data) is listed with its reason.
pub fn select(candidates: Vec<Candidate>, records: &[Record], outputs: &[String]) -> Result<BankSelection> {
    use rayon::prelude::*;
    let dt = super::sample_time(records)?;
    super::check_outputs_vary(records, outputs)?;
    let total: usize = records.iter().map(Record::len).sum();
    let window = window_for(total);
    let ny = records[0].outputs.len();
    let sd: Vec<f64> = (0..ny)
        .map(|j| {
            let col: Vec<&[f64]> = records.iter().map(|r| r.outputs[j].as_slice()).collect();
            crate::metrics::mean_std(&col).1
        })
        .collect();
    let scored: Vec<CandidateScore> = candidates
        .into_par_iter()
        .map(|c| {
            let (one, free, failed) = match score(&c, records, dt, window, &sd) {
                Ok((a, b)) if a.is_finite() && b.is_finite() => (Some(a), Some(b), None),
                Ok(_) => (
                    None,
                    None,
                    Some("its prequential error is not finite".to_string()),
                ),
                Err(e) => (None, None, Some(e.to_string())),
            };
            CandidateScore {
                name: c.name,
                spec: c.spec,
                one_step_nrmse: one,
                free_run_nrmse: free,
                failed,
            }
        })
        .collect();
    let best = |arx: bool| {
        scored
            .iter()
            .enumerate()
            .filter(|(_, c)| !arx || is_linear(&c.spec))
            .filter_map(|(k, c)| c.free_run_nrmse.map(|s| (k, s)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(k, _)| k)
    };
    let Some(chosen) = best(false) else {
        let why: Vec<String> = scored
            .iter()
            .map(|c| format!("{}: {}", c.name, c.failed.clone().unwrap_or_default()))
            .collect();
        return Err(invalid(
            "online selection",
            "every candidate failed",
            why.join("; "),
        ));
    };
    Ok(BankSelection {
        judged_by: format!(
            "prequential free run over windows of {window} samples in the second half of the stream"
        ),
        window,
        best_arx: best(true),
        candidates: scored,
        chosen,
    })
}
