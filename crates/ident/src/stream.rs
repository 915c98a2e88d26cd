//! Online identification of a live stream (`rhonn identify --stream`): samples arrive one
//! at a time, each is predicted before it is learned (an [`OnlineSession`]: a given model,
//! or the bank choosing online), and the running prequential error is kept. The sample
//! time is the first two samples' interval (`data::step_as_written`, as a file's); nothing but the session and a few sums is
//! held, so the memory stays bounded whatever the stream's length.

use super::bank::BankSelection;
use super::{OnlineModel, OnlineSession, OnlineSpec, SessionOptions};
use crate::error::{invalid, Result};
use serde::Serialize;

/// A stream being learned.
#[derive(Debug, Clone)]
pub struct Stream {
    inputs: Vec<String>,
    outputs: Vec<String>,
    model: Option<OnlineSpec>,
    samples: Option<usize>,
    /// The first sample, held until the second gives the sample time.
    first: Option<(f64, Vec<f64>, Vec<f64>)>,
    session: Option<OnlineSession>,
    /// Per output, the sum of squared prequential errors, and their count.
    squares: Vec<f64>,
    scored: usize,
    taken: usize,
}

/// One sample's result: the estimate of each output made before the sample was seen,
/// and each output's prequential RMS error so far.
#[derive(Debug, Clone, PartialEq)]
pub struct StreamStep {
    /// Per output.
    pub estimate: Vec<f64>,
    /// Per output, over every sample after the first.
    pub prequential_rms: Vec<f64>,
}

/// What a stream gave (`summary.json` of `rhonn identify --stream`).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct StreamSummary {
    /// Samples taken.
    pub samples: usize,
    /// The sample time \[s\]: the first two samples' interval.
    pub sample_time_s: f64,
    /// Per output, the prequential RMS error: each sample predicted before it was learned.
    pub prequential_rms_error: Vec<f64>,
    /// The output names, in the order of the figures.
    pub outputs: Vec<String>,
    /// Without a model: the online selection as it stood when the stream ended.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub selection: Option<BankSelection>,
    /// What the guard skipped or restarted over.
    pub notes: Vec<String>,
}

impl Stream {
    /// A stream of `inputs` -> `outputs`: `model` given, or None for the bank, judging
    /// as for a stream of `samples` samples when its length is known (as `rhonn identify
    /// --data` judges a file of that length) and as an open-ended one otherwise.
    pub fn new(
        inputs: Vec<String>,
        outputs: Vec<String>,
        model: Option<OnlineSpec>,
        samples: Option<usize>,
    ) -> Result<Self> {
        if outputs.is_empty() {
            return Err(invalid("outputs", "none", "at least one output"));
        }
        crate::data::check_names(&inputs, &outputs)?;
        let ny = outputs.len();
        Ok(Stream {
            inputs,
            outputs,
            model,
            samples,
            first: None,
            session: None,
            squares: vec![0.0; ny],
            scored: 0,
            taken: 0,
        })
    }

    /// Take the sample `(t, u, y)`; the first one is held until the second gives the
    /// sample time (None then).
    pub fn push(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<Option<StreamStep>> {
        if self.session.is_none() {
            let Some((t0, u0, y0)) = self.first.take() else {
                super::engine::check_sample_finite(t, u, y, true)?;
                self.first = Some((t, u.to_vec(), y.to_vec()));
                return Ok(None);
            };
            let opts = SessionOptions {
                samples: if self.model.is_none() { self.samples } else { None },
                ..SessionOptions::default()
            };
            let mut s = OnlineSession::new(
                self.inputs.clone(),
                self.outputs.clone(),
                crate::data::step_as_written(t - t0),
                self.model.clone(),
                opts,
            )?;
            s.update(t0, &u0, &y0)?;
            self.session = Some(s);
            self.taken = 1;
        }
        let session = self.session.as_mut().expect("set above");
        let estimate = session.update(t, u, y)?.to_vec();
        self.taken += 1;
        for (j, (e, m)) in estimate.iter().zip(y).enumerate() {
            self.squares[j] += (e - m) * (e - m);
        }
        self.scored += 1;
        let rms = self
            .squares
            .iter()
            .map(|s| (s / self.scored as f64).sqrt())
            .collect();
        Ok(Some(StreamStep {
            estimate,
            prequential_rms: rms,
        }))
    }

    /// Freeze the model learned so far and say what the stream gave; an error when fewer
    /// than two samples came.
    pub fn finish(&mut self) -> Result<(OnlineModel, StreamSummary)> {
        let Some(session) = self.session.as_mut() else {
            return Err(invalid(
                "the stream",
                crate::metrics::count(usize::from(self.first.is_some()), "sample"),
                "at least two samples (the first two give the sample time)",
            ));
        };
        let (taken, open_ended) = (self.taken, self.model.is_none() && self.samples.is_none());
        let selection = session.selection().map_err(|e| {
            if open_ended {
                crate::Error::Argument(format!(
                    "the stream ended after {}, open-ended (its length not given beforehand): the online \
                     selection judges such a stream as one of 2,000 samples, scored from sample 1,000, and could \
                     not judge its candidates on these ({e}); give the stream's length beforehand (the windows are \
                     then sized by it), or a model",
                    crate::metrics::count(taken, "sample")
                ))
            } else {
                e
            }
        })?;
        let model = session.freeze()?;
        let (_, _, dt) = session.signals();
        let summary = StreamSummary {
            samples: self.taken,
            sample_time_s: dt,
            prequential_rms_error: self
                .squares
                .iter()
                .map(|s| (s / self.scored.max(1) as f64).sqrt())
                .collect(),
            outputs: self.outputs.clone(),
            selection,
            notes: session.notes(),
        };
        Ok((model, summary))
    }
}
