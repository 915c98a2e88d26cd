//! The cascade candidate of the selection, its seeded starts in three runs.
//!
//! The cascade is the slowest candidate by far (on 900 samples 21 s of a 23 s selection),
//! and on most data a lagged structure beats it by a wide margin. So its folds are first
//! trained with a quarter of its starts (the probe); when the probe's fold error is above
//! [`PROBE_RATIO`] times the best bounded candidate's, it stops there: the other starts
//! would have to close more than that gap for it to be chosen. Otherwise the rest of the
//! cascade's first stage of starts runs, then its second stage, and each fold keeps the
//! run whose kept start trained to the lowest cost: exactly the start one fit of all of
//! them keeps (the same seeds, the same training, the lowest cost first and the earlier
//! start on a tie; the second stage only when the first had a valid start), so the score
//! is the one a single fit gives and only the time differs.
//!
//! The ratio is measured: the probe's fold error was up to 2.2 x the full run's (the
//! cascaded tanks: 0.245 after 4 starts, 0.215 after 8, 0.112 after 16; the coupled
//! electric drives 0.447 / 0.449 / 0.453; DaISy's ball-and-beam 1.57 / 1.60 / 1.58), so 4
//! leaves a margin of 1.8 over the worst seen.

use super::cascade::EARLY_STARTS;
use super::estimate::fit_cascade;
use super::folds::{held_out_runs, held_out_score, HeldOut};
use super::{Model, ModelSpec};
use crate::data::Record;
use crate::error::Result;
use rayon::prelude::*;

/// The probe stops the candidate when its fold error is above this many times the best
/// bounded candidate's.
pub(super) const PROBE_RATIO: f64 = 4.0;

/// A cascade's fold scores, and a note when it stopped after the probe.
pub(super) struct CascadeScore {
    /// Normalised error per fold.
    pub fold_scores: Vec<f64>,
    /// Their mean.
    pub score: f64,
    /// Said when the candidate stopped after the probe.
    pub note: Option<String>,
    /// The predictions on each fold's held-out parts.
    pub runs: Vec<HeldOut>,
}

/// `spec` fitted on every fold's training parts: the model and its training cost, or the
/// error.
fn fit_folds(
    spec: &ModelSpec,
    parts: &[(Vec<Record>, Vec<Record>)],
    inputs: &[String],
    outputs: &[String],
) -> Vec<Result<(Model, f64)>> {
    parts
        .par_iter()
        .map(|(train, _)| fit_cascade(spec, train, inputs, outputs))
        .collect()
}

/// Each fold's held-out error, the mean and the held-out predictions, or the first error.
fn errors(
    models: &[&Model],
    parts: &[(Vec<Record>, Vec<Record>)],
    steps: Option<usize>,
) -> Result<(Vec<f64>, f64, Vec<HeldOut>)> {
    let runs = models
        .iter()
        .zip(parts)
        .map(|(m, (_, test))| held_out_runs(m, test, steps))
        .collect::<Result<Vec<HeldOut>>>()?;
    let f = runs
        .iter()
        .zip(parts)
        .map(|(h, (_, test))| held_out_score(h, test))
        .collect::<Result<Vec<f64>>>()?;
    let mean = f.iter().sum::<f64>() / f.len() as f64;
    Ok((f, mean, runs))
}

/// The seeded starts of `spec` in the order they are tried: the probe (a quarter), the
/// rest of the cascade's first stage ([`EARLY_STARTS`]), the rest. Each range is within
/// one stage, so running them one after another runs what one fit runs.
fn phases(starts: usize) -> Vec<std::ops::Range<usize>> {
    let probe = (starts / 4).max(1);
    let stage = starts.min(EARLY_STARTS);
    [0..probe.min(stage), probe.min(stage)..stage, stage..starts]
        .into_iter()
        .filter(|r| !r.is_empty())
        .collect()
}

/// Score the cascade `spec` on the folds `parts` (see the module's docs); `best_bounded`
/// is the best score of the bounded candidates already judged.
pub(super) fn score(
    spec: &ModelSpec,
    parts: &[(Vec<Record>, Vec<Record>)],
    inputs: &[String],
    outputs: &[String],
    steps: Option<usize>,
    best_bounded: Option<f64>,
) -> Result<CascadeScore> {
    // Beyond two stages one fit would try its later stages only when its first had a
    // valid start, which the runs below reproduce for two stages only: one run then.
    let ranges = if spec.starts > 2 * EARLY_STARTS {
        std::iter::once(0..spec.starts).collect()
    } else {
        phases(spec.starts)
    };
    // Per fold: the kept model so far and its cost, or the first error.
    let mut kept: Vec<Result<(Model, f64)>> = Vec::new();
    for (k, range) in ranges.iter().enumerate() {
        let part_spec = ModelSpec {
            starts: range.len(),
            seed: spec.seed.wrapping_add(range.start as u64),
            ..spec.clone()
        };
        let fits = fit_folds(&part_spec, parts, inputs, outputs);
        kept = if k == 0 {
            fits
        } else {
            kept.into_iter()
                .zip(fits)
                .map(|(old, new)| match (old, new) {
                    // The lower cost wins, the earlier starts on a tie.
                    (Ok(o), Ok(n)) => Ok(if n.1 < o.1 { n } else { o }),
                    (Ok(o), Err(_)) => Ok(o),
                    // One fit stops after its first stage when none of it was valid.
                    (Err(e), _) if range.start >= EARLY_STARTS => Err(e),
                    (Err(_), n) => n,
                })
                .collect()
        };
        if k == 0 && ranges.len() > 1 {
            let Some(best) = best_bounded else { continue };
            let Ok(models) = kept
                .iter()
                .map(|r| r.as_ref().map(|(m, _)| m))
                .collect::<std::result::Result<Vec<_>, _>>()
            else {
                continue;
            };
            let Ok((fold_scores, score, runs)) = errors(&models, parts, steps) else {
                continue;
            };
            if score > PROBE_RATIO * best {
                return Ok(CascadeScore {
                    fold_scores,
                    score,
                    runs,
                    note: Some(format!(
                        "stopped after the first {} of {} starts: their fold error, {score:.4}, is more than \
                         {PROBE_RATIO} x the best bounded candidate's, {best:.4}",
                        range.len(),
                        spec.starts
                    )),
                });
            }
        }
    }
    let models = kept
        .into_iter()
        .map(|r| r.map(|(m, _)| m))
        .collect::<Result<Vec<Model>>>()?;
    let (fold_scores, score, runs) = errors(&models.iter().collect::<Vec<_>>(), parts, steps)?;
    Ok(CascadeScore {
        fold_scores,
        score,
        note: None,
        runs,
    })
}

#[cfg(test)]
mod tests {
    use super::super::folds::{folds, held_out_error};
    use super::super::{fit, Estimator, Kind};
    use super::*;

    #[test]
    fn the_runs_are_a_quarter_then_the_first_stage_then_the_rest() {
        assert_eq!(phases(16), vec![0..4, 4..8, 8..16]);
        assert_eq!(phases(8), vec![0..2, 2..8]);
        assert_eq!(phases(3), vec![0..1, 1..3]);
        assert_eq!(phases(1), vec![0..1]);
    }

    /// Two tanks (levels in V, 4 s samples) under steps of the pump's voltage.
    fn tanks(n: usize) -> Record {
        let (mut x1, mut x2, mut u) = (3.0f64, 2.0f64, 0.0);
        let (mut ys, mut us) = (Vec::new(), Vec::new());
        let mut s = 7u64;
        for k in 0..n {
            if k % 25 == 0 {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                u = 0.5 + 5.0 * ((s >> 33) as f64 / (1u64 << 31) as f64);
            }
            us.push(u);
            ys.push(x2);
            for _ in 0..40 {
                let d1 = 0.08 * u - 0.06 * x1.max(0.0).sqrt();
                let d2 = 0.05 * x1.max(0.0).sqrt() - 0.05 * x2.max(0.0).sqrt();
                x1 = (x1 + 0.1 * d1).max(0.0);
                x2 = (x2 + 0.1 * d2).max(0.0);
            }
        }
        Record {
            source: "tanks".into(),
            t: (0..n).map(|k| 4.0 * k as f64).collect(),
            inputs: vec![us],
            outputs: vec![ys],
        }
    }

    /// The claim of the module: the three runs score exactly what one fit of all 16
    /// starts scores, fold by fold; a best bounded score far below the probe's stops it
    /// after the first 4 starts, and says so.
    #[test]
    fn the_runs_score_what_one_fit_of_every_start_scores_and_a_far_better_rival_stops_the_probe() {
        let (i, o) = (vec!["u".to_string()], vec!["y".to_string()]);
        let spec = ModelSpec {
            kind: Kind::Cascade,
            law: Estimator::SimulationError,
            starts: 16,
            epochs: 4,
            ..ModelSpec::default()
        };
        let parts = folds(&[tanks(240)], 3);
        let one_fit: Vec<f64> = parts
            .iter()
            .map(|(train, test)| held_out_error(&fit(&spec, train, &i, &o).unwrap(), test, None).unwrap())
            .collect();
        let runs = score(&spec, &parts, &i, &o, None, None).unwrap();
        assert_eq!(runs.fold_scores, one_fit);
        assert!(runs.note.is_none());
        let rival = runs.score / 100.0;
        let stopped = score(&spec, &parts, &i, &o, None, Some(rival)).unwrap();
        let note = stopped.note.unwrap();
        assert!(
            note.starts_with("stopped after the first 4 of 16 starts"),
            "{note}"
        );
        assert_eq!(stopped.fold_scores.len(), 3);
        assert!(stopped.score > PROBE_RATIO * rival);
        // A rival the probe is within PROBE_RATIO of: every start runs.
        let close = score(&spec, &parts, &i, &o, None, Some(stopped.score)).unwrap();
        assert_eq!(close.fold_scores, one_fit);
    }
}
