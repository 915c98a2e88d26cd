//! `rhonn.Model`: a model of `rhonn fit` or a frozen online RHONN (`rhonn identify`,
//! `OnlineIdentifier.freeze()`), in the same `model.json` as the command line:
//! `rhonn::any_model::AnyModel` through `rhonn_report::any_model`, converted.

use crate::arrays::record;
use crate::errors::{report_err, value_error};
use numpy::{PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;
use rhonn::ident::OnlineModel;
use rhonn::sysid::FittedModel;
use rhonn_report::any_model::{self, AnyModel};
use std::path::PathBuf;

/// A model: `predict`, `save`, its `summary`.
#[pyclass(module = "rhonn._rhonn", frozen)]
#[derive(Clone)]
pub struct Model {
    model: AnyModel,
    summary: Option<String>,
    warnings: Vec<String>,
}

impl Model {
    pub fn fitted(m: FittedModel, summary: Option<String>, warnings: Vec<String>) -> Self {
        Model {
            model: AnyModel::Fitted(Box::new(m)),
            summary,
            warnings,
        }
    }

    pub fn online(m: OnlineModel) -> Self {
        Self::loaded(AnyModel::Online(Box::new(m)))
    }

    fn loaded(model: AnyModel) -> Self {
        Model {
            model,
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
        (steps_ahead, baseline, init_window): (Option<usize>, bool, Option<usize>),
    ) -> PyResult<(Vec<Vec<f64>>, String)> {
        let (inputs, outputs, dt) = self.model.signals();
        let rec = record("the data", dt, u, y, inputs, outputs)?;
        py.detach(|| any_model::predict(&self.model, &rec, (steps_ahead, init_window), baseline))
            .map_err(report_err)
    }
}

/// Read a model.json written by `rhonn fit`, `rhonn identify` or `Model.save`.
#[pyfunction]
pub fn load(path: PathBuf) -> PyResult<Model> {
    any_model::load(&path).map(Model::loaded).map_err(report_err)
}

#[pymethods]
impl Model {
    /// Predict the outputs from inputs `u` (n, m) and measured outputs `y` (n, p):
    /// free run (`steps_ahead` None: only the first samples of `y` are used) or K steps
    /// ahead (`init_window` N: a free run seeing only `y`'s first N rows). Returns (n, p);
    /// samples before the first prediction repeat `y`.
    #[pyo3(signature = (u, y, steps_ahead=None, baseline=false, init_window=None))]
    fn predict<'py>(
        &self,
        py: Python<'py>,
        u: PyReadonlyArray2<'py, f64>,
        y: PyReadonlyArray2<'py, f64>,
        steps_ahead: Option<usize>,
        baseline: bool,
        init_window: Option<usize>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let (cols, _) = self.prediction(py, &u, &y, (steps_ahead, baseline, init_window))?;
        let n = cols.first().map_or(0, Vec::len);
        let rows: Vec<Vec<f64>> = (0..n).map(|k| cols.iter().map(|c| c[k]).collect()).collect();
        PyArray2::from_vec2(py, &rows).map_err(|e| value_error(e.to_string()))
    }

    /// The figures `rhonn predict` prints and writes for the same data (JSON text: one
    /// object per output with `rms_error`, `fit_percent`, `nrmse`, `samples`).
    #[pyo3(signature = (u, y, steps_ahead=None, baseline=false, init_window=None))]
    fn score_json<'py>(
        &self,
        py: Python<'py>,
        u: PyReadonlyArray2<'py, f64>,
        y: PyReadonlyArray2<'py, f64>,
        steps_ahead: Option<usize>,
        baseline: bool,
        init_window: Option<usize>,
    ) -> PyResult<String> {
        Ok(self
            .prediction(py, &u, &y, (steps_ahead, baseline, init_window))?
            .1)
    }

    /// Write the model as `model.json` (the format `rhonn predict` and `rhonn.load` read).
    fn save(&self, path: PathBuf) -> PyResult<()> {
        any_model::save(&self.model, &path).map_err(report_err)
    }

    /// The model as model.json's text.
    fn to_json(&self) -> PyResult<String> {
        any_model::to_json(&self.model).map_err(report_err)
    }

    /// Read a model from model.json's text.
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Model> {
        any_model::from_json(text, "the model text")
            .map(Model::loaded)
            .map_err(report_err)
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
        self.model.kind()
    }

    /// Input names.
    #[getter]
    fn inputs(&self) -> Vec<String> {
        self.model.signals().0.to_vec()
    }

    /// Output names.
    #[getter]
    fn outputs(&self) -> Vec<String> {
        self.model.signals().1.to_vec()
    }

    /// Sample time \[s\].
    #[getter]
    fn sample_time_s(&self) -> f64 {
        self.model.signals().2
    }

    fn __repr__(&self) -> String {
        let (i, o, dt) = self.model.signals();
        format!(
            "Model(kind={:?}, inputs={i:?}, outputs={o:?}, sample_time_s={dt})",
            self.kind()
        )
    }
}
