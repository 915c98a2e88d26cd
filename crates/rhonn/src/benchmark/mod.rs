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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Published {
    /// Per output, in the data's units.
    pub rmse: Vec<f64>,
    /// The model.
    pub model: String,
    /// The paper or result file.
    pub source: String,
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
