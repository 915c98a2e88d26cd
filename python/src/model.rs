//! `rhonn.Model`: a model of `rhonn fit` or a frozen online RHONN (`rhonn identify`,
//! `OnlineIdentifier.freeze()`), in the same `model.json` as the command line:
//! `rhonn::any_model::AnyModel` through `rhonn_app::any_model`, converted.

use crate::arrays::record;
use crate::errors::report_err;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2, PyReadonlyArray2};
use pyo3::prelude::*;
use rhonn_app::any_model::{self, AnyModel};
use std::path::PathBuf;

/// A model: `predict`, `save`, its `summary`. Its parts: the model, what `rhonn fit`
/// wrote of it (its summary.json's text) and the warnings it printed.
#[pyclass(module = "rhonn._rhonn", frozen)]
#[derive(Clone)]
pub struct Model(pub AnyModel, pub Option<String>, pub Vec<String>);

/// `Model._info`: kind, inputs, outputs, sample time \[s\], summary.json's text, warnings.
type Info = (&'static str, Names, Names, f64, Option<String>, Names);
type Names = Vec<String>;

/// Read a model.json written by `rhonn fit`, `rhonn identify` or `Model.save`.
#[pyfunction]
pub fn load(path: PathBuf) -> PyResult<Model> {
    any_model::load(&path)
        .map(|m| Model(m, None, Vec::new()))
        .map_err(report_err)
}

#[pymethods]
impl Model {
    /// `rhonn predict` on inputs `u` (n, m) and measured outputs `y` (n, p): the prediction
    /// (n, p), its figures as JSON and its warnings (`Model.predict` and `Model.score`).
    #[pyo3(signature = (u, y, steps_ahead=None, baseline=false, init_window=None))]
    fn _predict<'py>(
        &self,
        py: Python<'py>,
        u: PyReadonlyArray2<'py, f64>,
        y: PyReadonlyArray2<'py, f64>,
        steps_ahead: Option<i128>,
        baseline: bool,
        init_window: Option<i128>,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, String, Vec<String>)> {
        let (inputs, outputs, dt) = self.0.signals();
        let rec = record("the data", dt, &u, &y, inputs, outputs)?;
        let (cols, json, warnings) = py
            .detach(|| any_model::predict(&self.0, &rec, (steps_ahead, init_window), baseline))
            .map_err(report_err)?;
        let n = cols.first().map_or(0, Vec::len);
        let arr = Array2::from_shape_fn((n, cols.len()), |(k, j)| cols[j][k]);
        Ok((arr.into_pyarray(py), json, warnings))
    }

    /// Write the model as `model.json` (the format `rhonn predict` and `rhonn.load` read).
    #[pyo3(signature = (path, force=false))]
    fn save(&self, path: PathBuf, force: bool) -> PyResult<()> {
        any_model::save(&self.0, &path, force).map_err(report_err)
    }

    /// The model as model.json's text.
    fn to_json(&self) -> PyResult<String> {
        any_model::to_json(&self.0).map_err(report_err)
    }

    /// Read a model from model.json's text.
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Model> {
        any_model::from_json(text, "the model text")
            .map(|m| Model(m, None, Vec::new()))
            .map_err(report_err)
    }

    /// `(kind, inputs, outputs, sample time s, summary.json's text or None, warnings)`:
    /// `"fit"` or `"online-rhonn"`, the signals' names, what `rhonn fit` printed.
    #[getter]
    fn _info(&self) -> Info {
        let (i, o, dt) = self.0.signals();
        let (s, w) = (self.1.clone(), self.2.clone());
        (self.0.kind(), i.to_vec(), o.to_vec(), dt, s, w)
    }
}
