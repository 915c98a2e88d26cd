//! The `summary.json` `rhonn corpus` writes (the command, in `rhonn-app`, fills it; its
//! schema documents it, `fields`).

use rhonn::corpus::{Judged, Summary};
use rhonn::ident::bank::BankSelection;
use rhonn::sysid::select::Selection;
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

/// `rhonn corpus`'s `<system>/summary.json`: one system's row and why each of its models was
/// chosen.
#[derive(Serialize, schemars::JsonSchema)]
pub struct SystemFile<'a> {
    /// The system's row, as in `summary.json`'s `systems`.
    pub system: &'a Judged,
    /// rhonn fit's default selection: every candidate's scores on the training folds.
    pub selection: Option<&'a Selection>,
    /// rhonn identify's default bank: every candidate's prequential figures.
    pub online_selection: Option<&'a BankSelection>,
}

/// The schema of `<system>/summary.json` (`fields`).
pub fn system_schema() -> serde_json::Value {
    schemars::schema_for!(SystemFile<'static>).to_value()
}
