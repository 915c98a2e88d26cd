//! A model.json of either kind (`rhonn fit`'s model, or a frozen online RHONN of `rhonn
//! identify` and `OnlineIdentifier.freeze()`) as one value: read, written, and asked for
//! a prediction with the figures `rhonn predict` gives. Python's `rhonn.Model` is this,
//! converted.

use crate::{Error, Result};
use rhonn::data::Record;
use rhonn::ident::OnlineModel;
use rhonn::sysid::FittedModel;
use std::path::Path;

/// A model of either kind.
#[derive(Debug, Clone)]
pub enum AnyModel {
    /// `rhonn fit`'s.
    Fitted(Box<FittedModel>),
    /// A frozen online RHONN.
    Online(Box<OnlineModel>),
}

/// A prediction's columns (one per output) and its figures as JSON text.
pub type Prediction = (Vec<Vec<f64>>, String);

fn json(v: &impl serde::Serialize) -> Result<String> {
    serde_json::to_string(v).map_err(|e| Error::Input(format!("cannot write the figures as JSON: {e}")))
}

impl AnyModel {
    /// Read model.json at `path`.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            Error::Rhonn(rhonn::Error::Io {
                path: path.display().to_string(),
                message: rhonn::error::path_problem(path, &e),
            })
        })?;
        Self::from_json(&text, &path.display().to_string())
    }

    /// A model from model.json's text; `source` names it in errors.
    pub fn from_json(text: &str, source: &str) -> Result<Self> {
        let kind = serde_json::from_str::<serde_json::Value>(text)
            .map_err(|e| Error::Input(format!("{source} is not JSON: {e}")))?
            .get("kind")
            .and_then(|k| k.as_str().map(str::to_string));
        if kind.as_deref() == Some(OnlineModel::KIND) {
            let m: OnlineModel = serde_json::from_str(text)
                .map_err(|e| Error::Input(format!("{source} is not a valid online model: {e}")))?;
            m.identifier()
                .map_err(|e| Error::Input(format!("{source} is not a valid model: {e}")))?;
            return Ok(AnyModel::Online(Box::new(m)));
        }
        let f: FittedModel = serde_json::from_str(text)
            .map_err(|e| Error::Input(format!("{source} is not a model written by `rhonn fit`: {e}")))?;
        f.validate()
            .map_err(|e| Error::Input(format!("{source} is not a valid model: {e}")))?;
        Ok(AnyModel::Fitted(Box::new(f)))
    }

    /// model.json's text.
    pub fn to_json(&self) -> Result<String> {
        match self {
            AnyModel::Fitted(f) => serde_json::to_string_pretty(f),
            AnyModel::Online(m) => serde_json::to_string_pretty(m),
        }
        .map_err(|e| Error::Input(format!("cannot write the model: {e}")))
    }

    /// Write model.json at `path`, whole or not at all.
    pub fn save(&self, path: &Path) -> Result<()> {
        let text = self.to_json()?;
        let tmp = path.with_extension("json.partial");
        let io = |e: std::io::Error| Error::File {
            path: path.to_path_buf(),
            message: e.to_string(),
        };
        std::fs::write(&tmp, text + "\n").map_err(io)?;
        std::fs::rename(&tmp, path).map_err(io)
    }

    /// `"fit"` or `"online-rhonn"`.
    pub fn kind(&self) -> &'static str {
        match self {
            AnyModel::Fitted(_) => "fit",
            AnyModel::Online(_) => OnlineModel::KIND,
        }
    }

    /// Its input names, output names and sample time \[s\].
    pub fn signals(&self) -> (&[String], &[String], f64) {
        match self {
            AnyModel::Fitted(f) => (&f.model.inputs, &f.model.outputs, f.model.sample_time_s),
            AnyModel::Online(m) => (&m.inputs, &m.outputs, m.sample_time_s),
        }
    }

    /// Predict `rec`'s outputs: free run (`steps_ahead` None) or K steps ahead; with
    /// `baseline`, the ARX baseline's prediction and figures instead (prediction.csv's
    /// `<y>_hat_arx` and summary.json's baseline).
    pub fn predict(&self, rec: &Record, steps_ahead: Option<usize>, baseline: bool) -> Result<Prediction> {
        if baseline && !matches!(self, AnyModel::Fitted(f) if f.baseline.is_some()) {
            return Err(Error::Input(
                "baseline=True: this model has no ARX baseline (an online model, or one loaded without it)"
                    .into(),
            ));
        }
        if steps_ahead == Some(0) {
            return Err(Error::Input(
                "steps_ahead = 0 is not allowed: give K >= 1, or None for a free run".into(),
            ));
        }
        match self {
            AnyModel::Fitted(f) => {
                let needed = rhonn::sysid::samples_needed(f, steps_ahead);
                if rec.len() < needed {
                    return Err(Error::Input(format!(
                        "u and y have {} samples; this model needs at least {needed}",
                        rec.len()
                    )));
                }
                let p = rhonn::sysid::predict(f, rec, steps_ahead)?;
                match (baseline, p.baseline) {
                    (true, Some((cols, figures))) => Ok((cols, json(&figures)?)),
                    _ => Ok((p.outputs, json(&p.figures)?)),
                }
            }
            AnyModel::Online(m) => {
                let mut id = m.identifier()?;
                let rows =
                    rhonn::ident::predict_records(&mut id, std::slice::from_ref(rec), steps_ahead)?.remove(0);
                let outputs = &m.outputs;
                let figures =
                    crate::identify::online_prediction_figures(rec, &rows, outputs, steps_ahead.unwrap_or(0));
                let cols = (0..outputs.len())
                    .map(|j| rows.iter().map(|r| r[j]).collect())
                    .collect();
                Ok((cols, json(&figures)?))
            }
        }
    }
}
