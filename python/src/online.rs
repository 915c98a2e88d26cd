//! `rhonn.OnlineIdentifier`: the online RHONN identifier one sample at a time, for a
//! user's own loop: `rhonn::ident::OnlineSession` (the same code as `rhonn identify`),
//! its arguments converted.

use crate::arrays::vector_into;
use crate::errors::{report_err, rhonn_err, value_error};
use crate::model::Model;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use rhonn::ident::{OnlineSession, SessionOptions};
use rhonn_app::any_model::AnyModel;

/// Identify a sampled plant online: `update(t, u, y)` returns the estimate of `y(t)`
/// made before seeing `y`, then learns from it.
#[pyclass(module = "rhonn._rhonn", subclass)]
pub struct OnlineIdentifier {
    session: OnlineSession,
    u: Vec<f64>,
    y: Vec<f64>,
}

#[pymethods]
impl OnlineIdentifier {
    /// `inputs`, `outputs`: the signals' names; `dt`: the sample time \[s\]; `model`: the
    /// settings as TOML text (`models/tanks-online.toml`'s keys), None for the defaults;
    /// offsets and scales: the identifier sees `(signal - offset) / scale`; `y_bounds`: per
    /// output the range `[low, high]` its estimate is held in.
    #[new]
    #[pyo3(signature = (inputs, outputs, dt, model=None, y_offset=None, y_scale=None, u_offset=None, u_scale=None, y_bounds=None, samples=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        inputs: Vec<String>,
        outputs: Vec<String>,
        dt: f64,
        model: Option<&str>,
        y_offset: Option<Vec<f64>>,
        y_scale: Option<Vec<f64>>,
        u_offset: Option<Vec<f64>>,
        u_scale: Option<Vec<f64>>,
        y_bounds: Option<Vec<[f64; 2]>>,
        samples: Option<usize>,
    ) -> PyResult<Self> {
        let spec = model
            .map(|text| rhonn_app::online_spec(text, "model"))
            .transpose()
            .map_err(report_err)?;
        let opts = SessionOptions {
            y_offset,
            y_scale,
            u_offset,
            u_scale,
            y_bounds,
            samples,
        };
        let (nu, ny) = (inputs.len(), outputs.len());
        let session = OnlineSession::new(inputs, outputs, dt, spec, opts).map_err(rhonn_err)?;
        Ok(OnlineIdentifier {
            session,
            u: vec![0.0; nu],
            y: vec![0.0; ny],
        })
    }

    /// Take the sample `(t, u, y)`; returns the estimate of `y(t)` made before seeing `y`.
    fn update<'py>(
        &mut self,
        py: Python<'py>,
        t: f64,
        u: &Bound<'py, PyAny>,
        y: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        vector_into("u", u, &mut self.u)?;
        vector_into("y", y, &mut self.y)?;
        let est = self.session.update(t, &self.u, &self.y).map_err(rhonn_err)?;
        Ok(PyArray1::from_slice(py, est))
    }

    /// Stop adapting and return the frozen model, frozen until `resume()`. Choosing
    /// online: the winner so far becomes the identifier (the others are dropped).
    fn freeze(&mut self) -> PyResult<Model> {
        let m = self.session.freeze().map_err(rhonn_err)?;
        Ok(Model(AnyModel::Online(Box::new(m)), None, Vec::new()))
    }

    /// Adapt the weights again after `freeze()`.
    fn resume(&mut self) {
        self.session.resume();
    }

    /// Forget the last sample (a new record starts); the weights stay.
    fn reset(&mut self) {
        self.session.reset();
    }

    /// The weights, one row per output's neuron (normalised units), shape (p, terms);
    /// choosing online: the leading candidate's.
    #[getter]
    fn weights<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let w = self.session.weight_rows().map_err(rhonn_err)?;
        PyArray2::from_vec2(py, &w).map_err(|e| value_error(e.to_string()))
    }

    /// What the guard skipped (glitches) or restarted over (gaps in time).
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.session.notes()
    }

    /// Each term's name, in weight order (choosing online: the leading candidate's).
    #[getter]
    fn term_names(&self) -> PyResult<Vec<String>> {
        self.session.term_names().map_err(rhonn_err)
    }

    /// Choosing online: the selection so far as JSON (summary.json's); None with a model.
    #[getter]
    fn _selection_json(&self) -> PyResult<Option<String>> {
        self.session.selection_json().map_err(rhonn_err)
    }

    /// For `python/bench.py`: `update` on the rows of `t`, `u` (n, m) and `y` (n, p), from
    /// Rust on a copy of this identifier; returns the seconds per update.
    fn _rust_seconds_per_update(
        &self,
        t: numpy::PyReadonlyArray1<'_, f64>,
        u: numpy::PyReadonlyArray2<'_, f64>,
        y: numpy::PyReadonlyArray2<'_, f64>,
    ) -> PyResult<f64> {
        let t: Vec<f64> = t.as_array().iter().copied().collect();
        let u = crate::arrays::columns("u", &u, self.u.len())?;
        let y = crate::arrays::columns("y", &y, self.y.len())?;
        self.session.seconds_per_update(&t, &u, &y).map_err(rhonn_err)
    }

    fn __repr__(&self) -> String {
        let (inputs, outputs, dt) = self.session.signals();
        let terms = self
            .session
            .given()
            .map_or("choosing online".into(), |g| g.n_terms().to_string());
        format!("OnlineIdentifier(inputs={inputs:?}, outputs={outputs:?}, dt={dt}, terms={terms})")
    }
}
