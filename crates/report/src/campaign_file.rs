//! The `summary.json` of a finished campaign (`rhonn campaign`, `rhonn merge`): the
//! type the campaign fills and the reference of fields describes.

use crate::worst_runs::WorstRun;
use rhonn::experiment::campaign::{FigureStats, Plan};
use serde::Serialize;

/// A plant campaign's `summary.json`.
#[derive(Serialize, schemars::JsonSchema)]
pub struct CampaignSummary<'a> {
    /// The scenario's name.
    pub scenario: &'a str,
    /// The plant (`[plant] kind`).
    pub plant: &'a str,
    /// Runs in the campaign.
    pub runs: usize,
    /// Runs that failed (their figures NaN in runs.csv).
    pub failed: usize,
    /// The parameters' distributions as drawn (the plant's parameter order).
    pub plan: &'a Plan,
    /// Each figure's statistics over the runs that finished.
    pub figures: Vec<FigureStats>,
    /// The failed runs and those with the worst key figure, each with its scenario file.
    pub worst_runs: Vec<WorstRun>,
    /// The worst runs in words.
    pub findings: Vec<String>,
    /// Runs whose traces make the envelope, per series (`envelope.csv`'s series).
    pub envelope_runs: Vec<(String, usize)>,
}

/// The schema of `summary.json` (`fields`).
pub(crate) fn schema() -> serde_json::Value {
    schemars::schema_for!(CampaignSummary<'static>).to_value()
}
