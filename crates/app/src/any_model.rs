//! [`rhonn::any_model::AnyModel`] (a model.json of either kind) read from and written to
//! files, and its prediction as columns and JSON figures: what Python's `rhonn.Model`
//! converts. `rhonn predict` reads and predicts through the same library calls.

pub use rhonn::any_model::{AnyModel, AnyPrediction, ModelFileError};
use rhonn::data::Record;
use rhonn_report::{Error, Result};
use std::path::Path;

/// A prediction's columns (one per output) and its figures as JSON text.
pub type Prediction = (Vec<Vec<f64>>, String, Vec<String>);

fn json(v: &impl serde::Serialize) -> Result<String> {
    serde_json::to_string(v).map_err(|e| Error::Input(format!("cannot write the figures as JSON: {e}")))
}

/// A refused model.json as one message (Python's wording: a refused check follows the
/// file's name after a colon).
pub fn file_error(e: ModelFileError) -> Error {
    match e {
        ModelFileError::Invalid { source_name, source } => {
            Error::Input(format!("{source_name} is not a valid model: {source}"))
        }
        other => Error::Input(other.to_string()),
    }
}

/// Read model.json at `path`.
pub fn load(path: &Path) -> Result<AnyModel> {
    let text = rhonn::error::read_text(path).map_err(|e| {
        Error::Rhonn(rhonn::Error::Io {
            path: path.display().to_string(),
            message: rhonn::error::path_problem(path, &e),
        })
    })?;
    from_json(&text, &path.display().to_string())
}

/// A model from model.json's text; `source` names it in errors.
pub fn from_json(text: &str, source: &str) -> Result<AnyModel> {
    AnyModel::parse(text, source).map_err(file_error)
}

/// model.json's text.
pub fn to_json(model: &AnyModel) -> Result<String> {
    model
        .to_json()
        .map_err(|e| Error::Input(format!("cannot write the model: {e}")))
}

/// Write model.json at `path`, whole or not at all; a different file already there is
/// replaced only with `force`.
pub fn save(model: &AnyModel, path: &Path, force: bool) -> Result<()> {
    let text = to_json(model)?;
    if !force && path.exists() && std::fs::read_to_string(path).ok().as_deref() != Some(&format!("{text}\n"))
    {
        return Err(Error::File {
            path: path.to_path_buf(),
            message: "exists and holds something else: nothing written; give force=True to replace it".into(),
        });
    }
    let tmp = path.with_extension("json.partial");
    let io = |e: std::io::Error| Error::File {
        path: path.to_path_buf(),
        message: e.to_string(),
    };
    std::fs::write(&tmp, text + "\n").map_err(io)?;
    std::fs::rename(&tmp, path).map_err(io)
}

/// Predict `rec`'s outputs: free run (`steps_ahead` None; seeing only the first
/// `init_window` outputs when given) or K steps ahead; with `baseline`, the ARX
/// baseline's prediction and figures instead (prediction.csv's `<y>_hat_arx` and
/// summary.json's baseline); and the warnings `rhonn predict` prints (inputs beyond the
/// training range). The options as Python gives them, any int: checked by the library's
/// rules (`rhonn::sysid::prediction_options`).
pub fn predict(
    model: &AnyModel,
    rec: &Record,
    (steps_ahead, init_window): (Option<i128>, Option<i128>),
    baseline: bool,
) -> Result<Prediction> {
    let (steps_ahead, init_window) = rhonn::sysid::prediction_options(steps_ahead, init_window)?;
    if baseline && !matches!(model, AnyModel::Fitted(f) if f.baseline.is_some()) {
        return Err(Error::Input(
            "baseline=True: this model has no ARX baseline (an online model, or one loaded without it)"
                .into(),
        ));
    }
    let needed = model.samples_needed(steps_ahead);
    if matches!(model, AnyModel::Fitted(_)) && rec.len() < needed {
        return Err(Error::Input(format!(
            "u and y have {} samples; this model needs at least {needed}",
            rec.len()
        )));
    }
    match model.predict_with(rec, steps_ahead, init_window)? {
        AnyPrediction::Fitted(p) => {
            let said = p.range_warnings();
            match (baseline, p.baseline) {
                (true, Some((cols, figures))) => Ok((cols, json(&figures)?, said)),
                _ => Ok((p.outputs, json(&p.figures)?, said)),
            }
        }
        AnyPrediction::Online { rows, figures } => {
            let cols = (0..figures.len())
                .map(|j| rows.iter().map(|r| r[j]).collect())
                .collect();
            Ok((cols, json(&figures)?, Vec::new()))
        }
    }
}
