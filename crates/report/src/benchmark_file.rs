//! The files `rhonn benchmark` writes: `benchmark.csv`'s rows and `summary.json` (the
//! command, in `rhonn-app`, fills them; their schema documents them, `fields`).

use serde::Serialize;

/// One row of the table: one output of one test set.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Row {
    /// The benchmark.
    pub benchmark: String,
    /// The test set.
    pub test: String,
    /// The output.
    pub output: String,
    /// Its unit (empty when the data's owners give none).
    pub unit: String,
    /// The first sample scored, and how many.
    pub scored_from: usize,
    /// Samples scored.
    pub samples: usize,
    /// How the fit column's model was made when it is not the default selection's choice
    /// (`rhonn fit (--model)`); absent otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fit_method: Option<String>,
    /// Free-run RMS error of rhonn fit's default model, its structure and training time.
    pub fit_rmse: f64,
    /// See `fit_rmse`.
    pub fit_structure: String,
    /// See `fit_rmse` \[s\].
    pub fit_time_s: f64,
    /// The same for rhonn identify's default online model.
    pub online_rmse: f64,
    /// See `online_rmse`.
    pub online_structure: String,
    /// See `online_rmse` \[s\].
    pub online_time_s: f64,
    /// The same for the ARX of lags by cross-validation on train.
    pub arx_rmse: f64,
    /// See `arx_rmse`.
    pub arx_structure: String,
    /// See `arx_rmse` \[s\].
    pub arx_time_s: f64,
    /// The best published figure on this test set and output under the protocol's own
    /// split, its model and source (with the year).
    pub published_rmse: Option<f64>,
    /// See `published_rmse`.
    pub published_model: String,
    /// See `published_rmse`.
    pub published_source: String,
    /// The best published neural network on it (the baseline a user would train), cited
    /// as `model, source, year`.
    pub baseline_rmse: Option<f64>,
    /// See `baseline_rmse`.
    pub baseline_cited: String,
    /// A published figure on another split, when below `published_rmse`: cited, with the
    /// split it used.
    pub other_split_rmse: Option<f64>,
    /// See `other_split_rmse`.
    pub other_split_cited: String,
}

/// `summary.json` of the whole run.
#[derive(Debug, Serialize, schemars::JsonSchema)]
pub struct Summary<'a> {
    /// rhonn's version.
    pub rhonn_version: &'static str,
    /// How every model was trained and judged, in words.
    pub protocol: &'static str,
    /// One row per benchmark, test set, output and method (benchmark.csv's rows).
    pub rows: &'a [Row],
}

/// The schema of `summary.json` (`fields`).
pub fn schema() -> serde_json::Value {
    schemars::schema_for!(Summary<'static>).to_value()
}
