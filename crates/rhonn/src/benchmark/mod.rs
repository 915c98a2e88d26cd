//! The field's standard benchmarks under their published protocol (`rhonn benchmark`):
//! train on the training records only, run free on every test set from its start-up
//! window, and score the RMS error in the data's units, for rhonn's default model
//! (`rhonn fit` with no spec: the structure selected by cross-validation on train),
//! rhonn's default online identifier (`rhonn identify` with no spec: the bank), and an ARX
//! whose lags cross-validation on train chose, beside the published figures. Every setting
//! is chosen on train; the test sets only report. The records are read by the caller
//! (`rhonn-report` reads `data/benchmarks/NAME/benchmark.toml` and its files).

mod methods;

use crate::data::Record;
use crate::error::{invalid, Result};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

pub use methods::{run, run_with, BenchmarkOutcome, MethodResult, TestScore};

/// A benchmark's protocol, as `benchmark.toml` writes it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BenchmarkSpec {
    /// What the system is.
    pub title: String,
    /// The benchmark's reference paper.
    pub reference: String,
    /// Input columns.
    pub inputs: Vec<String>,
    /// Output columns.
    pub outputs: Vec<String>,
    /// Units of the columns (none where the data's owners give none).
    #[serde(default)]
    pub units: BTreeMap<String, String>,
    /// The start-up window: the model may see the first `skip` outputs of a test set;
    /// the error is scored after them (and after every model's first prediction).
    pub skip: usize,
    /// The sample time \[s\] when the files have no time column (their time is then the
    /// sample index times this).
    #[serde(default)]
    pub sample_time_s: Option<f64>,
    /// The training file (relative to `benchmark.toml`).
    pub train: String,
    /// The test sets.
    pub test: Vec<TestSpec>,
}

/// One test set.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TestSpec {
    /// Its name in the tables, e.g. "arrow (full)".
    pub label: String,
    /// Its file (relative to `benchmark.toml`).
    pub file: String,
    /// Only the first `rows` rows of the file (e.g. Silverbox's arrow without
    /// extrapolation).
    #[serde(default)]
    pub rows: Option<usize>,
    /// Only the rows of this `record` (files holding several records).
    #[serde(default)]
    pub record: Option<i64>,
    /// The published figures on it.
    #[serde(default)]
    pub published: Vec<Published>,
}

/// A published free-run RMS error.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Published {
    /// Per output, in the data's units.
    pub rmse: Vec<f64>,
    /// The model.
    pub model: String,
    /// The paper or result file (authors, venue).
    pub source: String,
    /// The year it was published.
    #[serde(default)]
    pub year: Option<u16>,
    /// A neural network of the baseline paper (or the field's), the realistic alternative
    /// a user would train: shown beside the best.
    #[serde(default)]
    pub neural_baseline: bool,
    /// Trained or scored on another split than the protocol's (what it was): shown
    /// separately, never as the best on the protocol.
    #[serde(default)]
    pub other_split: Option<String>,
}

impl Published {
    /// The citation: `model, source, year`.
    pub fn cited(&self) -> String {
        match self.year {
            Some(y) => format!("{}, {}, {y}", self.model, self.source),
            None => format!("{}, {}", self.model, self.source),
        }
    }
}

/// The published figures of a test set for one output, as a table shows them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PublishedBest<'a> {
    /// The lowest on the protocol's own split.
    pub best: Option<&'a Published>,
    /// The lowest neural baseline on it.
    pub neural_baseline: Option<&'a Published>,
    /// The lowest on another split, when it is below `best` (or there is no `best`).
    pub other_split: Option<&'a Published>,
}

/// The lowest of `published` for output `j` in each role.
pub fn published_best(published: &[Published], j: usize) -> PublishedBest<'_> {
    let lowest = |keep: &dyn Fn(&Published) -> bool| {
        published
            .iter()
            .filter(|p| keep(p))
            .min_by(|a, c| a.rmse[j].total_cmp(&c.rmse[j]))
    };
    let best = lowest(&|p| p.other_split.is_none());
    let other = lowest(&|p| p.other_split.is_some()).filter(|o| best.is_none_or(|b| o.rmse[j] < b.rmse[j]));
    PublishedBest {
        best,
        neural_baseline: lowest(&|p| p.neural_baseline && p.other_split.is_none()),
        other_split: other,
    }
}

/// A benchmark with its records loaded.
#[derive(Debug, Clone)]
pub struct Benchmark {
    /// Its folder's name, e.g. `silverbox`.
    pub name: String,
    /// Its protocol.
    pub spec: BenchmarkSpec,
    /// The training records.
    pub train: Vec<Record>,
    /// Per test set of `spec.test`, its record.
    pub tests: Vec<Record>,
}

impl Benchmark {
    /// Check that the records fit the protocol: one test record per test set, the
    /// columns' counts, every published figure one value per output.
    pub fn check(&self) -> Result<()> {
        let (ni, no) = (self.spec.inputs.len(), self.spec.outputs.len());
        if ni == 0 || no == 0 {
            return Err(invalid(
                format!("benchmark {}: inputs and outputs", self.name),
                format!("{ni} and {no} columns"),
                "at least one of each",
            ));
        }
        if self.train.is_empty() || self.tests.len() != self.spec.test.len() {
            return Err(invalid(
                format!("benchmark {}", self.name),
                format!(
                    "{} training and {} test records",
                    self.train.len(),
                    self.tests.len()
                ),
                format!(
                    "at least one training record and one test record per test set ({})",
                    self.spec.test.len()
                ),
            ));
        }
        for r in self.train.iter().chain(&self.tests) {
            if r.inputs.len() != ni || r.outputs.len() != no || r.len() <= self.spec.skip + 2 {
                return Err(invalid(
                    format!("benchmark {}: {}", self.name, r.source),
                    format!(
                        "{} inputs, {} outputs, {} samples",
                        r.inputs.len(),
                        r.outputs.len(),
                        r.len()
                    ),
                    format!(
                        "{ni} inputs, {no} outputs and more than {} samples",
                        self.spec.skip + 2
                    ),
                ));
            }
        }
        for (t, p) in self
            .spec
            .test
            .iter()
            .flat_map(|t| t.published.iter().map(move |p| (t, p)))
        {
            if p.year.is_some_and(|y| !(1950..=2100).contains(&y)) {
                return Err(invalid(
                    format!(
                        "benchmark {}, test `{}`, published `{}`: year",
                        self.name, t.label, p.model
                    ),
                    format!("{:?}", p.year),
                    "a year from 1950 to 2100",
                ));
            }
            if p.rmse.len() != no || p.rmse.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
                return Err(invalid(
                    format!(
                        "benchmark {}, test `{}`, published `{}`: rmse",
                        self.name, t.label, p.model
                    ),
                    format!("{:?}", p.rmse),
                    format!("{no} finite values >= 0, one per output"),
                ));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(rmse: f64, model: &str, neural: bool, other: bool) -> Published {
        Published {
            rmse: vec![rmse],
            model: model.into(),
            source: "S".into(),
            year: Some(2020),
            neural_baseline: neural,
            other_split: other.then(|| "another".into()),
        }
    }

    #[test]
    fn the_best_is_on_the_protocols_split_and_another_split_shows_only_when_lower() {
        let all = [
            p(0.3, "A", false, false),
            p(0.5, "N", true, false),
            p(0.1, "O", false, true),
            p(0.2, "N2", true, true),
        ];
        let b = published_best(&all, 0);
        assert_eq!(b.best.unwrap().model, "A");
        assert_eq!(b.neural_baseline.unwrap().model, "N");
        assert_eq!(b.other_split.unwrap().model, "O");
        let b = published_best(&all[..2], 0);
        assert!(b.other_split.is_none());
        let higher = [p(0.3, "A", false, false), p(0.4, "O", false, true)];
        assert!(published_best(&higher, 0).other_split.is_none());
        assert_eq!(all[0].cited(), "A, S, 2020");
    }
}
