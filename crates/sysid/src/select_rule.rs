//! The selection's rule, for the outputs together and for each output alone: the best ARX
//! on the folds is the reference; a structure replaces it only when it is below it on
//! every fold (a lower mean alone is within the folds' spread: a linear system with noise,
//! a lagged RHONN 0.2 % below the ARX on the mean and above it on one fold, ran free 0.8 %
//! worse on new data); the eligible structure with the lowest mean wins, and a polynomial
//! (unbounded terms) only by a margin over the best structure with bounded terms. Three
//! kinds of structure are out whatever the folds say: one whose free run under held steps
//! disagrees with the other structures that beat the ARX (`probes`), one whose free run
//! there leaves the training output range far (`select_candidates::EXCURSION_LIMIT`), and a
//! lagged RHONN fitted one step ahead on an output far slower than its lags
//! (`select_candidates::one_step_on_slow`). The reference is one ARX, never an ensemble led
//! by one (such a mean holds other structures: on corpus seed 8 one ran free 1.62 x worse
//! than its ARX, having had nothing to beat).
//!
//! With several outputs, the rule applies per output too: the structure chosen for the
//! outputs together is judged on their mean, and it may serve most outputs well and lose to
//! the best ARX on one (the corpus's system of two outputs of different nature, seed 2:
//! 1.03 x the ARX on its first output). Where the best ARX is below the joint choice on an
//! output on every fold, that output is predicted by the ARX (`FittedModel::by_output`),
//! the others by the joint choice. A free choice per output among every candidate was
//! measured first and is worse: on the two-output systems of corpus seeds 3 to 6 (24
//! outputs) it put 3 outputs at 3.05, 3.27 and 6.41 x the ARX, where one structure for all
//! had at most 1.02 x and this rule has at most 1.02 x (the folds of one output tell its
//! candidates apart by less than their noise: an ARX of 8 lags 0.7 % below the ARX of 4 on
//! the folds ran 3 x worse on a test of steps).

use super::select_candidates::{CandidateScore, DISAGREEMENT_LIMIT, EXCURSION_LIMIT, POLYNOMIAL_MARGIN};
use serde::Serialize;

/// What the rule chose among the candidates by one measure of their error.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Choice {
    /// The chosen candidate and its mean score.
    pub chosen: usize,
    pub score: f64,
    /// The best ARX candidate and its mean score.
    pub best_arx: usize,
    pub arx_score: f64,
    /// Why a better mean was not chosen, in words.
    pub findings: Vec<String>,
}

/// The rule (see the module's docs) by `measure`: each candidate's fold scores and their
/// mean under one measure (None: no score). None when no ARX has a score.
pub(super) fn choose(candidates: &[CandidateScore], measure: &[Option<(&[f64], f64)>]) -> Option<Choice> {
    let scored = |arx_only: bool| {
        candidates
            .iter()
            .zip(measure)
            .enumerate()
            .filter(move |(_, (c, _))| !arx_only || c.is_single_arx())
            .filter_map(|(i, (_, m))| m.map(|(f, s)| (i, f, s)))
    };
    let (best_arx, arx_folds, arx_score) = scored(true).min_by(|a, b| a.2.total_cmp(&b.2))?;
    let below_on_every_fold =
        |f: &[f64]| f.len() == arx_folds.len() && f.iter().zip(arx_folds).all(|(c, a)| c < a);
    let beats_arx = |i: usize, f: &[f64]| {
        let c = &candidates[i];
        i == best_arx
            || (below_on_every_fold(f)
                && disagreement(c).is_none()
                && c.slow_one_step.is_none()
                && far(c).is_none())
    };
    let mut findings = Vec::new();
    if let Some((i, _, s)) = scored(false)
        .min_by(|a, b| a.2.total_cmp(&b.2))
        .filter(|&(_, f, _)| !below_on_every_fold(f))
        .filter(|&(i, _, _)| i != best_arx)
    {
        findings.push(format!(
            "{} scored {s:.4} on average, below the best ARX's {arx_score:.4}, but not on every fold: a structure must beat the best ARX on every fold to replace it",
            candidates[i].name
        ));
    }
    let polynomial = |c: &CandidateScore| c.model.polynomial_terms();
    let best_eligible = |bounded_only: bool| {
        scored(false)
            .filter(|&(i, f, _)| beats_arx(i, f) && !(bounded_only && polynomial(&candidates[i])))
            .map(|(i, _, s)| (i, s))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    };
    let (mut chosen, mut score) = best_eligible(false).unwrap_or((best_arx, arx_score));
    if polynomial(&candidates[chosen]) {
        // A polynomial's terms are unbounded: contiguous folds of one excitation cannot
        // show how it runs free on another, so it must win by a factor to be chosen.
        if let Some((i, s)) = best_eligible(true).filter(|&(_, s)| score > POLYNOMIAL_MARGIN * s) {
            findings.push(format!(
                "{} scored {score:.4}, not below {POLYNOMIAL_MARGIN} x the best structure with bounded terms ({s:.4}), which a polynomial must be to be chosen",
                candidates[chosen].name
            ));
            (chosen, score) = (i, s);
        }
    }
    let below: Vec<(usize, f64)> = scored(false)
        .filter(|&(i, f, _)| below_on_every_fold(f) && i != best_arx)
        .map(|(i, _, s)| (i, s))
        .collect();
    findings.extend(put_out(candidates, &below, arx_score));
    Some(Choice {
        chosen,
        score,
        best_arx,
        arx_score,
        findings,
    })
}

/// A structure's held-step disagreement above [`DISAGREEMENT_LIMIT`].
fn disagreement(c: &CandidateScore) -> Option<f64> {
    c.held_disagreement.filter(|&d| d > DISAGREEMENT_LIMIT)
}

/// A structure's held-step excursion above [`EXCURSION_LIMIT`].
fn far(c: &CandidateScore) -> Option<f64> {
    c.excursion.filter(|&e| e > EXCURSION_LIMIT)
}

/// Why a rule puts a structure out, in words (None: it does not).
type Reason<'a> = dyn Fn(&CandidateScore) -> Option<String> + 'a;

/// Each structure below the ARX on every fold (`below`: its index and mean score) put out
/// by one of the rules, said: by its disagreement, then by its slow one-step fit, then by
/// its excursion.
fn put_out(candidates: &[CandidateScore], below: &[(usize, f64)], arx_score: f64) -> Vec<String> {
    let whose = |c: &CandidateScore| {
        if c.members.is_empty() {
            "its"
        } else {
            "its worst member's"
        }
    };
    let disagrees = |c: &CandidateScore| {
        disagreement(c).map(|d| format!(
            "under held steps at the data's own input levels {} free run disagrees with the other structures that beat the ARX {} x as much as they do with each other (above {DISAGREEMENT_LIMIT}): it extrapolates in a way of its own, which the folds cannot judge",
            whose(c),
            crate::metrics::sig(d, 3)
        ))
    };
    let looks_back_too_little = |c: &CandidateScore| {
        c.slow_one_step.map(|n| format!(
            "it is fitted one step ahead and looks back {} samples, while the output falls to 1/e of its autocorrelation only after {n} samples (more than {} x): its lags see almost none of the dynamics, and its free run integrates their error away from the data, which the folds cannot judge",
            c.model.max_lag(),
            super::checks::SLOW_SPANS
        ))
    };
    let runs_away = |c: &CandidateScore| {
        far(c).map(|e| format!(
            "under held steps at the data's own input levels {} free run leaves the training output range by {} output standard deviations (above {EXCURSION_LIMIT}): it runs away from the training trajectory where the folds cannot judge it",
            whose(c),
            crate::metrics::sig(e, 3)
        ))
    };
    let rules: [&Reason; 3] = [&disagrees, &looks_back_too_little, &runs_away];
    let mut findings = Vec::new();
    for why in rules {
        for &(i, s) in below {
            if let Some(w) = why(&candidates[i]) {
                findings.push(format!(
                    "{} scored {s:.4}, below the best ARX's {arx_score:.4} on every fold, but {w}",
                    candidates[i].name
                ));
            }
        }
    }
    findings
}

/// One output's structure (`summary.json`'s `selection.by_output`).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct OutputChoice {
    /// The output's name.
    pub output: String,
    /// The candidate that predicts it (an index into `candidates`): the joint choice or the
    /// best ARX.
    pub chosen: usize,
    /// Its normalised RMS error on that output, the mean over the folds.
    pub score: f64,
    /// The best ARX (of the outputs together).
    pub best_arx: usize,
    /// The best ARX's score on that output.
    pub arx_score: f64,
}

/// Each output's structure (module docs): the joint choice, or, where the best ARX is below
/// it on that output on every fold, that ARX. One entry per output.
pub(super) fn per_output(
    candidates: &[CandidateScore],
    outputs: &[String],
    joint: &Choice,
) -> Vec<OutputChoice> {
    let (c, a) = (&candidates[joint.chosen], &candidates[joint.best_arx]);
    outputs
        .iter()
        .enumerate()
        .map(|(j, name)| {
            let beaten = match (c.output_fold_scores.get(j), a.output_fold_scores.get(j)) {
                (Some(cf), Some(af)) => {
                    !cf.is_empty() && cf.len() == af.len() && af.iter().zip(cf).all(|(x, y)| x < y)
                }
                _ => false,
            };
            let chosen = if beaten { joint.best_arx } else { joint.chosen };
            OutputChoice {
                output: name.clone(),
                chosen,
                score: candidates[chosen]
                    .output_scores
                    .get(j)
                    .copied()
                    .unwrap_or(f64::NAN),
                best_arx: joint.best_arx,
                arx_score: a.output_scores.get(j).copied().unwrap_or(f64::NAN),
            }
        })
        .collect()
}
