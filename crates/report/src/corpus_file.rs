//! The `summary.json` `rhonn corpus` writes (the command, in `rhonn-app`, fills it; its
//! schema documents it, `fields`).

use rhonn::corpus::{Judged, Summary};
use serde::Serialize;

/// `rhonn corpus`'s `summary.json`.
#[derive(Serialize, schemars::JsonSchema)]
pub struct SummaryFile<'a> {
    /// rhonn's version.
    pub rhonn_version: &'static str,
    /// The seed the systems were drawn from.
    pub seed: u64,
    /// How each system was judged, in words.
    pub protocol: &'static str,
    /// The figures over every output.
    pub summary: &'a Summary,
    /// Each system, its models and their figures per output.
    pub systems: &'a [Judged],
}

/// The schema of `summary.json` (`fields`).
pub fn schema() -> serde_json::Value {
    schemars::schema_for!(SummaryFile<'static>).to_value()
}
