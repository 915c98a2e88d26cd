//! A `model.json` of either kind, `rhonn fit`'s model or a frozen online model of
//! `rhonn identify` (and `OnlineIdentifier.freeze()`), as one value: read from its text
//! (checked), written, and asked for a prediction with its figures. `rhonn predict` and
//! Python's `rhonn.Model` both call these, so the two read and predict a model alike.

use crate::data::{within_window, Record};
use crate::ident::{predict_records, OnlineModel};
use crate::identification::{online_prediction_figures, OnlinePredictionFigures};
use crate::sysid::{FittedModel, Prediction};
use serde::de::DeserializeOwned;

/// A model of either kind.
#[derive(Debug, Clone)]
pub enum AnyModel {
    /// `rhonn fit`'s.
    Fitted(Box<FittedModel>),
    /// A frozen online model.
    Online(Box<OnlineModel>),
}

/// Why a `model.json` text was refused; `source_name` names the file (or the text).
#[derive(Debug, thiserror::Error)]
pub enum ModelFileError {
    /// Not JSON at all (with the line and column where it breaks).
    #[error("{source_name} is not JSON: {message}")]
    NotJson {
        /// The file.
        source_name: String,
        /// What the JSON reader said.
        message: String,
    },
    /// JSON, but not a model of its kind: the field's path in it and what is wrong.
    #[error("{source_name} is not {what}: field `{field}`: {message}")]
    Malformed {
        /// The file.
        source_name: String,
        /// What it should be, e.g. "a model written by `rhonn fit`".
        what: &'static str,
        /// The field's path, e.g. `model.weights[0][4]`.
        field: String,
        /// What the reader said.
        message: String,
    },
    /// A model whose values the checks refuse.
    #[error("{source_name} is not a valid model")]
    Invalid {
        /// The file.
        source_name: String,
        /// The check that refused it.
        #[source]
        source: crate::Error,
    },
}

/// A prediction of either kind of model.
#[derive(Debug, Clone)]
pub enum AnyPrediction {
    /// `rhonn fit`'s model: outputs, figures, its ARX baseline's.
    Fitted(Box<Prediction>),
    /// A frozen online model: one row per sample (each output's estimate) and the
    /// figures per output.
    Online {
        /// The estimates, one row per sample.
        rows: Vec<Vec<f64>>,
        /// Figures per output.
        figures: Vec<OnlinePredictionFigures>,
    },
}

/// What to do with a model spec given where a fitted model is asked for (a newcomer's
/// first `rhonn predict --model spec.toml`): an empty text when `text` is not a TOML
/// table with a field.
fn spec_hint(text: &str) -> &'static str {
    match toml::from_str::<toml::Table>(text) {
        Ok(t) if !t.is_empty() => {
            " (it reads as TOML: a model spec? `rhonn fit --model SPEC.toml` or `rhonn identify --model SPEC.toml` trains it and writes the model.json that runs here)"
        }
        _ => "",
    }
}

/// `text` as a `T`; an error names the field's path in it.
fn parse<T: DeserializeOwned>(
    text: &str,
    source_name: &str,
    what: &'static str,
) -> Result<T, ModelFileError> {
    let de = &mut serde_json::Deserializer::from_str(text);
    serde_path_to_error::deserialize(de).map_err(|e| {
        let field = e.path().to_string();
        ModelFileError::Malformed {
            source_name: source_name.to_string(),
            what,
            field,
            message: e.into_inner().to_string(),
        }
    })
}

/// The largest model file read: every model rhonn writes is far smaller.
pub const MAX_MODEL_BYTES: usize = 16 << 20;

/// A model file's `rhonn_version`: a version this rhonn can read (`MAJOR.MINOR.PATCH`, not
/// newer in its major version, or for 0.x in its minor: semantic versioning's breaking
/// changes).
fn check_version(v: &serde_json::Value) -> crate::Result<()> {
    let ours: Vec<u64> = env!("CARGO_PKG_VERSION")
        .split('.')
        .filter_map(|p| p.parse().ok())
        .collect();
    let text = v.as_str().unwrap_or_default();
    let parts: Vec<u64> = text
        .split(['.', '-', '+'])
        .take(3)
        .map_while(|p| p.parse().ok())
        .collect();
    let bad = |why: String| crate::error::invalid("rhonn_version", v.to_string(), why);
    if parts.len() != 3 {
        return Err(bad("a version rhonn writes, MAJOR.MINOR.PATCH".into()));
    }
    let breaking = |p: &[u64]| if p[0] == 0 { (0, p[1]) } else { (p[0], 0) };
    if breaking(&parts) > breaking(&ours) {
        return Err(bad(format!(
            "a version this rhonn ({}) reads: the file was written by a newer rhonn; update rhonn to read it",
            env!("CARGO_PKG_VERSION")
        )));
    }
    Ok(())
}

impl AnyModel {
    /// A model from `model.json`'s text, of the kind its `kind` field says, checked;
    /// `source_name` names it in errors.
    pub fn parse(text: &str, source_name: &str) -> Result<Self, ModelFileError> {
        // Checked before the text is parsed: a JSON tree takes many times its text's memory.
        if text.len() > MAX_MODEL_BYTES {
            return Err(ModelFileError::Invalid {
                source_name: source_name.to_string(),
                source: crate::error::invalid(
                    "the file",
                    format!("{} MB", crate::metrics::sig(text.len() as f64 / 1e6, 3)),
                    "at most 16 MB: no model rhonn writes comes near (at most 256 terms per output)",
                ),
            });
        }
        let value = serde_json::from_str::<serde_json::Value>(text).map_err(|e| ModelFileError::NotJson {
            source_name: source_name.to_string(),
            message: format!("{e}{}", spec_hint(text)),
        })?;
        let invalid = |source: crate::Error| ModelFileError::Invalid {
            source_name: source_name.to_string(),
            source,
        };
        if let Some(v) = value.get("rhonn_version") {
            check_version(v).map_err(invalid)?;
        }
        if value.get("kind").and_then(|k| k.as_str()) == Some(OnlineModel::KIND) {
            let m: OnlineModel = parse(text, source_name, "a valid online model")?;
            m.identifier().map_err(invalid)?;
            return Ok(AnyModel::Online(Box::new(m)));
        }
        let f: FittedModel = parse(text, source_name, "a model written by `rhonn fit`")?;
        f.validate().map_err(invalid)?;
        Ok(AnyModel::Fitted(Box::new(f)))
    }

    /// `model.json`'s text.
    pub fn to_json(&self) -> serde_json::Result<String> {
        match self {
            AnyModel::Fitted(f) => serde_json::to_string_pretty(f),
            AnyModel::Online(m) => serde_json::to_string_pretty(m),
        }
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

    /// The fewest samples a record needs for a prediction `steps_ahead` (None: free run).
    pub fn samples_needed(&self, steps_ahead: Option<usize>) -> usize {
        match self {
            AnyModel::Fitted(f) => crate::sysid::samples_needed(f, steps_ahead),
            AnyModel::Online(_) => 2,
        }
    }

    /// Predict `rec`'s outputs: free run (`steps_ahead` None) or K steps ahead, with the
    /// figures `rhonn predict` prints (a fitted model's on its own grid, its ARX
    /// baseline's beside).
    pub fn predict(&self, rec: &Record, steps_ahead: Option<usize>) -> crate::Result<AnyPrediction> {
        self.predict_with(rec, steps_ahead, None)
    }

    /// [`AnyModel::predict`], and with `init_window` = N a free run that sees only the
    /// record's first N outputs, scored from sample N on (`rhonn predict --init-window`:
    /// [`crate::sysid::predict_with`], [`crate::data::within_window`]).
    pub fn predict_with(
        &self,
        rec: &Record,
        steps_ahead: Option<usize>,
        init_window: Option<usize>,
    ) -> crate::Result<AnyPrediction> {
        match self {
            AnyModel::Fitted(f) => Ok(AnyPrediction::Fitted(Box::new(crate::sysid::predict_with(
                f,
                rec,
                steps_ahead,
                init_window,
            )?))),
            AnyModel::Online(m) => {
                crate::sysid::check_window(init_window, steps_ahead, rec)?;
                let mut id = m.identifier()?;
                let mut run = |r: &Record| predict_records(&mut id, std::slice::from_ref(r), steps_ahead);
                let (rows, from) = match init_window {
                    None => (run(rec)?.remove(0), steps_ahead.unwrap_or(0)),
                    Some(w) => {
                        let lag = crate::ident::outputs_read_in_free_run(&m.model);
                        let (cols, _) =
                            within_window(rec, w, |r| Ok((rows_to_columns(run(r)?.remove(0)), lag)))?;
                        let rows = (0..rec.len())
                            .map(|k| cols.iter().map(|c| c[k]).collect())
                            .collect();
                        (rows, w)
                    }
                };
                let figures = online_prediction_figures(rec, &rows, &m.outputs, from);
                crate::sysid::ensure_finite_errors(
                    figures.iter().map(|f| (f.output.as_str(), f.rms_error)),
                    &rec.source,
                )?;
                Ok(AnyPrediction::Online { rows, figures })
            }
        }
    }
}

/// Per-sample rows (one value per output) as one column per output.
fn rows_to_columns(rows: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
    let n = rows.first().map_or(0, Vec::len);
    (0..n).map(|j| rows.iter().map(|r| r[j]).collect()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_refused_text_says_what_it_is_not_and_where() {
        let e = AnyModel::parse("not json", "m.json").unwrap_err();
        assert!(matches!(e, ModelFileError::NotJson { .. }), "{e}");
        assert!(e.to_string().starts_with("m.json is not JSON: "), "{e}");
        assert!(!e.to_string().contains("TOML"), "{e}");
        // A model spec where a trained model is asked for: what to do with it.
        let e = AnyModel::parse("kind = \"arx\"\nna = 2\n", "spec.toml").unwrap_err();
        assert!(
            e.to_string().starts_with("spec.toml is not JSON: ")
                && e.to_string()
                    .contains("it reads as TOML: a model spec? `rhonn fit --model SPEC.toml`"),
            "{e}"
        );
        // The `kind` field picks the reader: an online model's fields are asked for.
        let e = AnyModel::parse(r#"{"kind": "online-rhonn", "weights": []}"#, "m.json").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("m.json is not a valid online model: field `.`: missing field `inputs`"),
            "{e}"
        );
        // Anything else is read as `rhonn fit`'s model, and the field's path is named.
        let e = AnyModel::parse(r#"{"model": {"weights": "x"}}"#, "m.json").unwrap_err();
        assert!(
            e.to_string()
                .starts_with("m.json is not a model written by `rhonn fit`: field `model"),
            "{e}"
        );
    }
}
