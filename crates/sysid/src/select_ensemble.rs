//! The selection's ensembles: the mean of the best few candidates' predictions, judged on
//! the same folds from the predictions the candidates already made there (no fit more).
//!
//! On a short, noisy record the structures that run free best each err in their own way,
//! and their mean errs less than any of them: on the coupled electric drives' training
//! records the mean of the best two (a lagged RHONN trained on its free run and the
//! cascade) scores 0.418 on the folds against the best one's 0.472 alone (the best three:
//! 0.445). An ensemble is a candidate like
//! the others: chosen only when it beats the best ARX on every fold and every candidate on
//! the mean. Its members are the best candidates by score that ran in full and have bounded
//! terms (a polynomial must win by a margin on its own, as the selection asks of it), among
//! the best ARX and the structures below it on the mean (`select::may_join`); a free run
//! of the ensemble is the mean of its members' free runs, as `FittedModel::predict` makes
//! it once trained on every record.

use super::folds::{fold_output_scores, held_out_score, HeldOut, PartRun};
use super::ModelSpec;
use crate::data::Record;
use crate::error::Result;

/// What an ensemble needs of one candidate of the selection.
pub(super) struct Entry<'a> {
    pub name: &'a str,
    pub model: &'a ModelSpec,
    /// Its fold score (None: failed or skipped).
    pub score: Option<f64>,
    /// Judged in full (not a cascade stopped after its probe, not itself an ensemble).
    pub full: bool,
    /// Its predictions on each fold's held-out parts.
    pub runs: &'a [HeldOut],
}

/// One ensemble: its members (indices into the entries, the best first), its name and
/// what the folds said.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Ensemble {
    pub name: String,
    pub members: Vec<usize>,
    pub fold_scores: Vec<f64>,
    pub score: Option<f64>,
    /// Per output, its normalised RMS error fold by fold (empty when it failed).
    pub output_fold_scores: Vec<Vec<f64>>,
    pub failed: Option<String>,
}

/// Ensemble sizes tried: the best 2 and the best 3.
pub(super) const SIZES: [usize; 2] = [2, 3];

/// The mean of `members`' predictions on one fold: per part, from the latest member's
/// first prediction on (None where a member has none).
fn mean_of(members: &[&HeldOut]) -> HeldOut {
    let first = members[0];
    let parts = (0..first.parts.len())
        .map(|p| {
            let runs: Option<Vec<&PartRun>> = members.iter().map(|m| m.parts[p].as_ref()).collect();
            let runs = runs?;
            let start = runs.iter().map(|r| r.1).max().unwrap_or(0);
            // Summed member after member, then divided: `FittedModel::predict`'s order.
            let mut sum = runs[0].0.clone();
            for r in &runs[1..] {
                for (s, pj) in sum.iter_mut().zip(&r.0) {
                    for (a, b) in s.iter_mut().zip(pj) {
                        *a += b;
                    }
                }
            }
            let k = runs.len() as f64;
            for s in &mut sum {
                for v in s.iter_mut() {
                    *v /= k;
                }
            }
            Some((sum, start))
        })
        .collect();
    // The ensemble's excursion is its worst member's, taken from their scores
    // (`select::append_ensembles`); this mean is judged on its predictions only.
    HeldOut {
        parts,
        output_sd: first.output_sd.clone(),
        probe: Default::default(),
    }
}

/// May candidate `c` be an ensemble's member: judged in full, with bounded terms.
fn may_join(c: &Entry) -> bool {
    c.score.is_some() && c.full && !c.model.polynomial_terms()
}

/// The ensembles of the best of the candidates `scored`, judged on the folds' held-out
/// parts `tests`.
pub(super) fn ensembles(scored: &[Entry], tests: &[&[Record]]) -> Vec<Ensemble> {
    let mut order: Vec<usize> = (0..scored.len())
        .filter(|&i| may_join(&scored[i]) && scored[i].runs.len() == tests.len())
        .collect();
    order.sort_by(|&a, &b| {
        scored[a]
            .score
            .unwrap_or(f64::INFINITY)
            .total_cmp(&scored[b].score.unwrap_or(f64::INFINITY))
    });
    SIZES
        .iter()
        .filter(|&&k| order.len() >= k)
        .map(|&k| {
            let members = &order[..k];
            let judged: Result<Vec<(f64, Vec<f64>)>> = tests
                .iter()
                .enumerate()
                .map(|(f, test)| {
                    let fold: Vec<&HeldOut> = members.iter().map(|&i| &scored[i].runs[f]).collect();
                    let mean = mean_of(&fold);
                    Ok((held_out_score(&mean, test)?, fold_output_scores(&mean, test)))
                })
                .collect();
            let names: Vec<&str> = members.iter().map(|&i| scored[i].name).collect();
            let (fold_scores, score, output_fold_scores, failed) = match judged {
                Ok(f) => {
                    let (folds, per_output): (Vec<f64>, Vec<Vec<f64>>) = f.into_iter().unzip();
                    let s = folds.iter().sum::<f64>() / folds.len() as f64;
                    let no = per_output.first().map_or(0, Vec::len);
                    let by_output = (0..no)
                        .map(|j| per_output.iter().map(|p| p[j]).collect())
                        .collect();
                    (folds, Some(s), by_output, None)
                }
                Err(e) => (Vec::new(), None, Vec::new(), Some(e.to_string())),
            };
            Ensemble {
                name: format!("mean of the best {k}: {}", names.join("; ")),
                members: members.to_vec(),
                fold_scores,
                score,
                output_fold_scores,
                failed,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::folds::{folds, held_out_runs};
    use super::super::{fit, FittedModel};
    use super::*;
    use crate::models::{Activation, Kind};

    /// `n` samples of a saturating first-order system under a staircase input.
    fn record(n: usize) -> Record {
        let u: Vec<f64> = (0..n).map(|k| ((k / 7) as f64 * 1.7).sin()).collect();
        let mut y = vec![0.0; n];
        for k in 1..n {
            y[k] = 0.7 * y[k - 1] + 0.5 * (1.5 * u[k - 1]).tanh() + 0.01 * ((k * 13) as f64).sin();
        }
        Record {
            source: "r".into(),
            t: (0..n).map(|k| k as f64).collect(),
            inputs: vec![u],
            outputs: vec![y],
        }
    }

    fn names() -> (Vec<String>, Vec<String>) {
        (vec!["u".into()], vec!["y".into()])
    }

    #[test]
    fn an_ensembles_fold_score_is_what_the_fitted_ensemble_scores_there_bit_for_bit() {
        let (i, o) = names();
        let parts = folds(&[record(300)], 3);
        let specs = [
            ModelSpec {
                kind: Kind::Arx,
                na: 2,
                nb: 2,
                ..Default::default()
            },
            ModelSpec {
                na: 1,
                nb: 1,
                ..Default::default()
            },
        ];
        for (train, test) in &parts {
            let models: Vec<_> = specs.iter().map(|s| fit(s, train, &i, &o).unwrap()).collect();
            let runs: Vec<HeldOut> = models
                .iter()
                .map(|m| held_out_runs(m, test, None).unwrap())
                .collect();
            let score = held_out_score(&mean_of(&[&runs[0], &runs[1]]), test).unwrap();
            let fitted = FittedModel {
                rhonn_version: String::new(),
                model: models[0].clone(),
                members: vec![models[1].clone()],
                baseline: None,
                units: Default::default(),
                no_better_than_mean: Vec::new(),
                by_output: Vec::new(),
            };
            let mut direct = 0.0;
            for r in test {
                let (p, first) = fitted.predict(r, None).unwrap();
                direct += crate::metrics::rms_error(&r.outputs[0][first..], &p[0][first..])
                    / models[0].output_norm[0].1;
            }
            direct /= test.len() as f64;
            assert_eq!(score, direct);
            // And it is not one member's score.
            for r in &runs {
                assert_ne!(held_out_score(r, test).unwrap(), score);
            }
        }
    }

    /// A candidate of `kind` and `activation` (its name, model, score, whether judged in
    /// full) and its held-out predictions on the one part of each of 2 folds: the output
    /// plus `offset`.
    fn candidate(
        kind: Kind,
        activation: Activation,
        offset: f64,
        test: &Record,
    ) -> (ModelSpec, Vec<HeldOut>) {
        let pred: Vec<f64> = test.outputs[0].iter().map(|y| y + offset).collect();
        let h = HeldOut {
            parts: vec![Some((vec![pred], 1))],
            output_sd: vec![2.0],
            probe: Default::default(),
        };
        (
            ModelSpec {
                kind,
                activation,
                ..Default::default()
            },
            vec![h.clone(), h],
        )
    }

    #[test]
    fn the_members_are_the_best_full_bounded_candidates_and_their_mean_is_judged() {
        let test = record(40);
        let (t, b) = (Kind::Rhonn, Activation::Tanh);
        // name, kind, activation, score, judged in full, offset of its predictions
        let list = [
            ("arx", Kind::Arx, b, Some(0.5), true, 0.3),
            ("over", t, b, Some(0.2), true, 1.0),
            ("polynomial", t, Activation::Identity, Some(0.05), true, 0.0),
            ("stopped", Kind::Cascade, b, Some(0.1), false, 0.0),
            ("under", t, b, Some(0.3), true, -1.0),
            ("failed", t, b, None, true, 0.0),
        ];
        let made: Vec<_> = list.iter().map(|c| candidate(c.1, c.2, c.5, &test)).collect();
        let entries: Vec<Entry> = list
            .iter()
            .zip(&made)
            .map(|(c, (model, runs))| Entry {
                name: c.0,
                model,
                score: c.3,
                full: c.4,
                runs,
            })
            .collect();
        let tests: Vec<&[Record]> = vec![std::slice::from_ref(&test); 2];
        let e = ensembles(&entries, &tests);
        assert_eq!(e.len(), 2);
        assert_eq!(e[0].name, "mean of the best 2: over; under");
        assert_eq!(e[0].members, vec![1, 4]);
        // +1 and -1 cancel: the mean is the output.
        assert!(
            e[0].fold_scores.iter().all(|s| s.abs() < 1e-15),
            "{:?}",
            e[0].fold_scores
        );
        assert_eq!(e[1].name, "mean of the best 3: over; under; arx");
        assert_eq!(e[1].members, vec![1, 4, 0]);
        let s = e[1].score.unwrap();
        assert!((s - 0.1 / 2.0).abs() < 1e-12, "{s}");
        // Fewer than 2 members: none.
        assert!(ensembles(&entries[1..4], &tests).is_empty());
    }
}
