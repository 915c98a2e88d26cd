//! `rhonn.Model`: a model of `rhonn fit` or a frozen online RHONN (`rhonn identify`,
//! `OnlineIdentifier.freeze()`), in the same `model.json` as the command line.

use crate::arrays::record;
use crate::errors::{json, rhonn_err, value_error};
use numpy::{PyArray2, PyReadonlyArray2};
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use rhonn::ident::OnlineModel;
use rhonn::sysid::FittedModel;
use std::path::PathBuf;

#[derive(Clone)]
enum Kind {
    Fitted(Box<FittedModel>),
    Online(Box<OnlineModel>),
}

/// A model: `predict`, `save`, its `summary`.
#[pyclass(module = "rhonn._rhonn", frozen)]
#[derive(Clone)]
pub struct Model {
    kind: Kind,
    summary: Option<String>,
    warnings: Vec<String>,
}

impl Model {
    pub fn fitted(m: FittedModel, summary: Option<String>, warnings: Vec<String>) -> Self {
        Model {
            kind: Kind::Fitted(Box::new(m)),
            summary,
            warnings,
        }
    }

    pub fn online(m: OnlineModel) -> Self {
        Model {
            kind: Kind::Online(Box::new(m)),
            summary: None,
            warnings: Vec::new(),
        }
    }

    /// The prediction's columns (one per output) and its figures as JSON.
    fn prediction(
        &self,
        py: Python<'_>,
        u: &PyReadonlyArray2<'_, f64>,
        y: &PyReadonlyArray2<'_, f64>,
        steps_ahead: Option<usize>,
        baseline: bool,
    ) -> PyResult<(Vec<Vec<f64>>, String)> {
        if baseline && !matches!(&self.kind, Kind::Fitted(f) if f.baseline.is_some()) {
            return Err(value_error(
                "baseline=True: this model has no ARX baseline (an online model, or one loaded without it)",
            ));
        }
        if steps_ahead == Some(0) {
            return Err(value_error(
                "steps_ahead = 0 is not allowed: give K >= 1, or None for a free run",
            ));
        }
        let (inputs, outputs, dt) = self.names();
        let rec = record("the data", dt, u, y, inputs, outputs)?;
        match &self.kind {
            Kind::Fitted(f) => {
                let needed = rhonn::sysid::samples_needed(f, steps_ahead);
                if rec.len() < needed {
                    return Err(value_error(format!(
                        "u and y have {} samples; this model needs at least {needed}",
                        rec.len()
                    )));
                }
                let p = py
                    .detach(|| rhonn::sysid::predict(f, &rec, steps_ahead))
                    .map_err(rhonn_err)?;
                match (baseline, p.baseline) {
                    // The ARX baseline's prediction and figures, as prediction.csv's
                    // `<y>_hat_arx` and summary.json's baseline.
                    (true, Some((cols, figures))) => Ok((cols, json(&figures)?)),
                    _ => Ok((p.outputs, json(&p.figures)?)),
                }
            }
            Kind::Online(m) => {
                let mut id = m.identifier().map_err(rhonn_err)?;
                let recs = std::slice::from_ref(&rec);
                let rows = py
                    .detach(|| rhonn::ident::predict_records(&mut id, recs, steps_ahead))
                    .map_err(rhonn_err)?
                    .remove(0);
                let figures = rhonn_report::identify::online_prediction_figures(
                    &rec,
                    &rows,
                    outputs,
                    steps_ahead.unwrap_or(0),
                );
                let cols = (0..outputs.len())
                    .map(|j| rows.iter().map(|r| r[j]).collect())
                    .collect();
                Ok((cols, json(&figures)?))
            }
        }
    }

    fn names(&self) -> (&[String], &[String], f64) {
        match &self.kind {
            Kind::Fitted(f) => (&f.model.inputs, &f.model.outputs, f.model.sample_time_s),
            Kind::Online(m) => (&m.inputs, &m.outputs, m.sample_time_s),
        }
    }
}

/// Read a model.json written by `rhonn fit`, `rhonn identify` or `Model.save`.
#[pyfunction]
pub fn load(path: PathBuf) -> PyResult<Model> {
    let text = std::fs::read_to_string(&path).map_err(|e| {
        PyOSError::new_err(format!(
            "cannot read {}: {}",
            path.display(),
            rhonn::error::path_problem(&path, &e)
        ))
    })?;
    from_json(&text, &path.display().to_string())
}

fn from_json(text: &str, source: &str) -> PyResult<Model> {
    let kind = serde_json::from_str::<serde_json::Value>(text)
        .map_err(|e| value_error(format!("{source} is not JSON: {e}")))?
        .get("kind")
        .and_then(|k| k.as_str().map(str::to_string));
    if kind.as_deref() == Some(OnlineModel::KIND) {
        let m: OnlineModel = serde_json::from_str(text)
            .map_err(|e| value_error(format!("{source} is not a valid online model: {e}")))?;
        m.identifier()
            .map_err(|e| value_error(format!("{source} is not a valid model: {e}")))?;
        return Ok(Model::online(m));
    }
    let f: FittedModel = serde_json::from_str(text)
        .map_err(|e| value_error(format!("{source} is not a model written by `rhonn fit`: {e}")))?;
    f.validate()
        .map_err(|e| value_error(format!("{source} is not a valid model: {e}")))?;
    Ok(Model::fitted(f, None, Vec::new()))
}

#[pymethods]
impl Model {
    /// Predict the outputs from inputs `u` (n, m) and measured outputs `y` (n, p):
    /// free run (`steps_ahead` None: only the first samples of `y` are used) or K steps
    /// ahead. Returns (n, p); samples before the first prediction repeat `y`.
    #[pyo3(signature = (u, y, steps_ahead=None, baseline=false))]
    fn predict<'py>(
        &self,
        py: Python<'py>,
        u: PyReadonlyArray2<'py, f64>,
        y: PyReadonlyArray2<'py, f64>,
        steps_ahead: Option<usize>,
        baseline: bool,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (cols, _) = self.prediction(py, &u, &y, steps_ahead, baseline)?;
        let n = cols.first().map_or(0, Vec::len);
        let rows: Vec<Vec<f64>> = (0..n).map(|k| cols.iter().map(|c| c[k]).collect()).collect();
        PyArray2::from_vec2(py, &rows).map_err(|e| value_error(e.to_string()))
    }

    /// The figures `rhonn predict` prints and writes for the same data (JSON text: one
    /// object per output with `rms_error`, `fit_percent`, `nrmse`, `samples`).
    #[pyo3(signature = (u, y, steps_ahead=None, baseline=false))]
    fn score_json<'py>(
        &self,
        py: Python<'py>,
        u: PyReadonlyArray2<'py, f64>,
        y: PyReadonlyArray2<'py, f64>,
        steps_ahead: Option<usize>,
        baseline: bool,
    ) -> PyResult<String> {
        Ok(self.prediction(py, &u, &y, steps_ahead, baseline)?.1)
    }

    /// Write the model as `model.json` (the format `rhonn predict` and `rhonn.load` read).
    fn save(&self, path: PathBuf) -> PyResult<()> {
        let text = self.to_json()?;
        let tmp = path.with_extension("json.partial");
        let io = |e: std::io::Error| PyOSError::new_err(format!("cannot write {}: {e}", path.display()));
        std::fs::write(&tmp, text + "\n").map_err(io)?;
        std::fs::rename(&tmp, &path).map_err(io)
    }

    /// The model as model.json's text.
    fn to_json(&self) -> PyResult<String> {
        let r = match &self.kind {
            Kind::Fitted(f) => serde_json::to_string_pretty(f),
            Kind::Online(m) => serde_json::to_string_pretty(m),
        };
        r.map_err(|e| value_error(format!("cannot write the model: {e}")))
    }

    /// Read a model from model.json's text.
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Model> {
        from_json(text, "the model text")
    }

    /// The fit's summary (summary.json's text of `rhonn fit`), None for a loaded model.
    #[getter]
    fn summary_json(&self) -> Option<String> {
        self.summary.clone()
    }

    /// What the data checks found (as `rhonn fit` prints them).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// `"fit"` or `"online-rhonn"`.
    #[getter]
    fn kind(&self) -> &'static str {
        match self.kind {
            Kind::Fitted(_) => "fit",
            Kind::Online(_) => OnlineModel::KIND,
        }
    }

    /// Input names.
    #[getter]
    fn inputs(&self) -> Vec<String> {
        self.names().0.to_vec()
    }

    /// Output names.
    #[getter]
    fn outputs(&self) -> Vec<String> {
        self.names().1.to_vec()
    }

    /// Sample time \[s\].
    #[getter]
    fn sample_time_s(&self) -> f64 {
        self.names().2
    }

    fn __repr__(&self) -> String {
        let (i, o, dt) = self.names();
        format!(
            "Model(kind={:?}, inputs={i:?}, outputs={o:?}, sample_time_s={dt})",
            self.kind()
        )
    }
}
