//! The online model beside an offline ARX on each validation record (`rhonn identify`'s
//! baseline): the ARX with the lags that cross-validation on the training records chose
//! (`sysid::best_arx`), trained on them, run free on each validation record; both
//! scored from the same sample, per record and output (no pooled figure).

use crate::data::Record;
use crate::error::Result;
use crate::metrics;
use crate::sysid::FittedModel;
use serde::Serialize;

/// One validation record and output: the frozen online model's free run and the ARX's.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct RecordComparison {
    /// The validation record.
    pub record: String,
    /// The output.
    pub output: String,
    /// The first sample scored (the ARX's first prediction: it needs its lags).
    pub from_sample: usize,
    /// The online model's free-run RMS error (output units).
    pub online_rms_error: f64,
    /// Its fit \[%\] (left out for a constant output).
    #[serde(skip_serializing_if = "metrics::undefined")]
    pub online_fit_percent: f64,
    /// The offline ARX's free-run RMS error.
    pub arx_rms_error: f64,
    /// Its fit \[%\].
    #[serde(skip_serializing_if = "metrics::undefined")]
    pub arx_fit_percent: f64,
}

/// The ARX baseline of an identification (`summary.json`'s `baseline_arx`).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct ArxBaseline {
    /// Its lags, e.g. "na 4 nb 4 nk 1".
    pub structure: String,
    /// How it was chosen.
    pub chosen_as: String,
    /// Per validation record and output.
    pub records: Vec<RecordComparison>,
}

/// Compare the online model's free runs `online` (per record, sample, output), which read
/// the first `online_reads` measured outputs of each record, with the ARX `arx` run free
/// on the same `validation` records: both scored from the later of the ARX's first
/// prediction and `online_reads`, so that neither is scored where it still read
/// measurements.
pub fn compare_with_arx(
    validation: &[Record],
    (online, online_reads): (&[Vec<Vec<f64>>], usize),
    arx: &FittedModel,
    outputs: &[String],
) -> Result<ArxBaseline> {
    let mut records = Vec::new();
    for (r, pred) in validation.iter().zip(online) {
        let p = crate::sysid::predict(arx, r, None)?;
        // The ARX predicts on its own grid: the same as the online model's for a uniform
        // record (identify refuses any other).
        let from = p.first.max(online_reads).min(r.len());
        for (j, name) in outputs.iter().enumerate() {
            let y = &r.outputs[j][from..];
            let on: Vec<f64> = pred[from..].iter().map(|e| e[j]).collect();
            let ar = &p.outputs[j][from..];
            records.push(RecordComparison {
                record: r.source.clone(),
                output: name.clone(),
                from_sample: from,
                online_rms_error: metrics::rms_error(y, &on),
                online_fit_percent: metrics::fit_percent(y, &on),
                arx_rms_error: metrics::rms_error(y, ar),
                arx_fit_percent: metrics::fit_percent(y, ar),
            });
        }
    }
    Ok(ArxBaseline {
        structure: arx.model.spec.lags_name(),
        chosen_as: "the best ARX of 3-fold cross-validation (free run) on the training records, lags 1 to 8, trained on all of them".into(),
        records,
    })
}

impl ArxBaseline {
    /// In words: per record and output, the online model's error against the ARX's.
    pub fn findings(&self) -> Vec<String> {
        self.records
            .iter()
            .map(|c| {
                let ratio = c.online_rms_error / c.arx_rms_error;
                let verdict = if ratio < 1.0 {
                    format!("{:.0} % below", 100.0 * (1.0 - ratio))
                } else {
                    format!("{:.0} % above", 100.0 * (ratio - 1.0))
                };
                format!(
                    "{} on {}: the frozen online model runs free with RMS error {}, {verdict} the offline ARX ({}, {})",
                    c.output,
                    c.record,
                    metrics::sig(c.online_rms_error, 4),
                    self.structure,
                    metrics::sig(c.arx_rms_error, 4)
                )
            })
            .collect()
    }
}
