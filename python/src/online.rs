//! `rhonn.OnlineIdentifier`: the online RHONN identifier one sample at a time, for a
//! user's own loop (the same code as `rhonn identify`).

use crate::arrays::vector_into;
use crate::errors::{report_err, rhonn_err, value_error};
use crate::model::Model;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use rhonn::ident::bank::{default_candidates, BankSettings, OnlineBank};
use rhonn::ident::{OnlineIdentifier as Inner, OnlineModel, OnlineSpec, Scaling};

/// Identify a sampled plant online: `update(t, u, y)` returns the estimate of `y(t)`
/// made before seeing `y`, then learns from it.
#[pyclass(module = "rhonn._rhonn", subclass)]
pub struct OnlineIdentifier {
    engine: Engine,
    inputs: Vec<String>,
    outputs: Vec<String>,
    dt: f64,
    u: Vec<f64>,
    y: Vec<f64>,
}

/// One model given by the caller, or the bank choosing one online until `freeze()`.
enum Engine {
    One {
        inner: Box<Inner>,
        spec: Box<OnlineSpec>,
    },
    Bank(Box<OnlineBank>),
}

/// The bank's settings for a stream of `samples` samples (None: not known).
fn bank_settings(samples: Option<usize>) -> PyResult<BankSettings> {
    match samples {
        Some(n) if n < 4 => Err(value_error(format!(
            "samples = {n} is not allowed: give the stream's length, at least 4 samples, or None"
        ))),
        Some(n) => Ok(BankSettings::for_stream(n)),
        None => Ok(BankSettings::open_ended()),
    }
}

/// A per-signal vector given by the caller, or `default` repeated.
fn per_signal(name: &str, v: Option<Vec<f64>>, n: usize, default: f64, positive: bool) -> PyResult<Vec<f64>> {
    let v = v.unwrap_or_else(|| vec![default; n]);
    if v.len() != n {
        return Err(value_error(format!(
            "{name} has {} values; {n} are needed (one per signal)",
            v.len()
        )));
    }
    if let Some((i, x)) = v
        .iter()
        .enumerate()
        .find(|(_, x)| !x.is_finite() || (positive && **x <= 0.0))
    {
        let allowed = if positive { "finite and > 0" } else { "finite" };
        return Err(value_error(format!(
            "{name}[{i}] = {x} is not allowed: {allowed}"
        )));
    }
    Ok(v)
}

/// Per output, a range `[low, high]` the estimate is held in.
fn check_bounds(b: Option<Vec<[f64; 2]>>, n: usize) -> PyResult<Option<Vec<[f64; 2]>>> {
    let Some(b) = b else { return Ok(None) };
    if b.len() != n {
        return Err(value_error(format!(
            "y_bounds has {} ranges; {n} are needed (one per output)",
            b.len()
        )));
    }
    if let Some((i, r)) = b
        .iter()
        .enumerate()
        .find(|(_, r)| !(r[0].is_finite() && r[1].is_finite() && r[0] < r[1]))
    {
        return Err(value_error(format!(
            "y_bounds[{i}] = [{}, {}] is not allowed: give finite [low, high] with low < high",
            r[0], r[1]
        )));
    }
    Ok(Some(b))
}

impl OnlineIdentifier {
    /// The model's identifier: the one given, or, choosing online, the leader so far.
    fn current(&self) -> PyResult<std::borrow::Cow<'_, Inner>> {
        match &self.engine {
            Engine::One { inner, .. } => Ok(std::borrow::Cow::Borrowed(inner.as_ref())),
            Engine::Bank(b) => Ok(std::borrow::Cow::Owned(b.selection().map_err(rhonn_err)?.1)),
        }
    }
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
        if outputs.is_empty() {
            return Err(value_error("outputs is empty: name at least one output"));
        }
        if !(dt.is_finite() && dt > 0.0) {
            return Err(value_error(format!(
                "dt = {dt} is not allowed: give the sample time in seconds, finite and > 0"
            )));
        }
        let (ny, nu) = (outputs.len(), inputs.len());
        let Some(text) = model else {
            let given = [
                ("y_offset", y_offset.is_some()),
                ("y_scale", y_scale.is_some()),
                ("u_offset", u_offset.is_some()),
                ("u_scale", u_scale.is_some()),
                ("y_bounds", y_bounds.is_some()),
            ];
            if let Some((name, _)) = given.iter().find(|(_, g)| *g) {
                return Err(value_error(format!(
                    "{name} needs a model: without one the identifier picks its model online and normalises by its warm-up window (give model={{}} for the continuous-time neurons with your scaling)"
                )));
            }
            let settings = bank_settings(samples)?;
            let cands = default_candidates(ny, samples.unwrap_or(usize::MAX));
            let bank = OnlineBank::new(cands, ny, nu, dt, settings).map_err(rhonn_err)?;
            return Ok(OnlineIdentifier {
                engine: Engine::Bank(Box::new(bank)),
                inputs,
                outputs,
                dt,
                u: vec![0.0; nu],
                y: vec![0.0; ny],
            });
        };
        if samples.is_some() {
            return Err(value_error(
                "samples is for the online selection (no model): a given model does not use it",
            ));
        }
        let spec = rhonn_report::commands::online_spec(text, "model").map_err(report_err)?;
        let scaling = Scaling {
            y_offset: per_signal("y_offset", y_offset, ny, 0.0, false)?,
            y_scale: per_signal("y_scale", y_scale, ny, 1.0, true)?,
            u_offset: per_signal("u_offset", u_offset, nu, 0.0, false)?,
            u_scale: per_signal("u_scale", u_scale, nu, 1.0, true)?,
            y_bounds: check_bounds(y_bounds, ny)?,
        };
        let inner = Box::new(Inner::new(&spec, ny, nu, dt, scaling).map_err(rhonn_err)?);
        Ok(OnlineIdentifier {
            engine: Engine::One {
                inner,
                spec: Box::new(spec),
            },
            inputs,
            outputs,
            dt,
            u: vec![0.0; nu],
            y: vec![0.0; ny],
        })
    }

    /// Take the sample `(t, u, y)` (t in s, strictly after the last one); returns the
    /// estimate of `y(t)` made before seeing `y` (the first sample returns `y`).
    fn update<'py>(
        &mut self,
        py: Python<'py>,
        t: f64,
        u: &Bound<'py, PyAny>,
        y: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        vector_into("u", u, &mut self.u)?;
        vector_into("y", y, &mut self.y)?;
        let est = match &mut self.engine {
            Engine::One { inner, .. } => inner.update(t, &self.u, &self.y),
            Engine::Bank(b) => b.update(t, &self.u, &self.y),
        }
        .map_err(rhonn_err)?;
        Ok(PyArray1::from_slice(py, est))
    }

    /// Stop adapting and return the frozen model (`Model.predict`, `Model.save`); the
    /// identifier stays frozen until `resume()`. Choosing online: the winner so far
    /// becomes the identifier (the other candidates are dropped).
    fn freeze(&mut self) -> PyResult<Model> {
        if let Engine::Bank(b) = &self.engine {
            let (sel, id) = b.selection().map_err(rhonn_err)?;
            self.engine = Engine::One {
                inner: Box::new(id),
                spec: Box::new(sel.chosen_spec().clone()),
            };
        }
        let Engine::One { inner, spec } = &mut self.engine else {
            return Err(value_error("no model to freeze"));
        };
        inner.freeze(true);
        Ok(Model::online(OnlineModel::of(
            inner,
            spec.as_ref().clone(),
            &self.inputs,
            &self.outputs,
            self.dt,
        )))
    }

    /// Adapt the weights again after `freeze()`.
    fn resume(&mut self) {
        if let Engine::One { inner, .. } = &mut self.engine {
            inner.freeze(false);
        }
    }

    /// Forget the last sample (a new record starts); the weights stay.
    fn reset(&mut self) {
        match &mut self.engine {
            Engine::One { inner, .. } => inner.reset(),
            Engine::Bank(b) => b.reset(),
        }
    }

    /// The weights, one row per output's neuron (normalised units), shape (p, terms);
    /// choosing online: the leading candidate's.
    #[getter]
    fn weights<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        PyArray2::from_vec2(py, &self.current()?.weights()).map_err(|e| value_error(e.to_string()))
    }

    /// Each term's name, in weight order (choosing online: the leading candidate's).
    #[getter]
    fn term_names(&self) -> PyResult<Vec<String>> {
        Ok(self.current()?.term_names(&self.outputs, &self.inputs))
    }

    /// Choosing online: every candidate's prequential figures and the winner so far, as
    /// JSON (`rhonn identify`'s `selection` in summary.json); None with a given model.
    #[getter]
    fn _selection_json(&self) -> PyResult<Option<String>> {
        match &self.engine {
            Engine::One { .. } => Ok(None),
            Engine::Bank(b) => {
                let (sel, _) = b.selection().map_err(rhonn_err)?;
                crate::errors::json(&sel).map(Some)
            }
        }
    }

    /// For the bench (`python/bench.py`): the same updates as `update` on the rows of `t`,
    /// `u` (n, m) and `y` (n, p), made from Rust on a copy of this identifier (which stays
    /// as it was); returns the seconds per update.
    fn _rust_seconds_per_update(
        &self,
        t: numpy::PyReadonlyArray1<'_, f64>,
        u: numpy::PyReadonlyArray2<'_, f64>,
        y: numpy::PyReadonlyArray2<'_, f64>,
    ) -> PyResult<f64> {
        let t = t.as_array();
        let u = crate::arrays::columns("u", &u, self.u.len())?;
        let y = crate::arrays::columns("y", &y, self.y.len())?;
        if u.iter().chain(&y).any(|c| c.len() != t.len()) {
            return Err(value_error("t, u and y need one row per sample"));
        }
        let Engine::One { inner, .. } = &self.engine else {
            return Err(value_error("the bench times a given model (give model=...)"));
        };
        let mut id = inner.as_ref().clone();
        let (mut uk, mut yk) = (self.u.clone(), self.y.clone());
        let start = std::time::Instant::now();
        for (k, tk) in t.iter().enumerate() {
            uk.iter_mut().zip(&u).for_each(|(v, c)| *v = c[k]);
            yk.iter_mut().zip(&y).for_each(|(v, c)| *v = c[k]);
            std::hint::black_box(id.update(*tk, &uk, &yk).map_err(rhonn_err)?);
        }
        Ok(start.elapsed().as_secs_f64() / t.len().max(1) as f64)
    }

    fn __repr__(&self) -> String {
        format!(
            "OnlineIdentifier(inputs={:?}, outputs={:?}, dt={}, terms={})",
            self.inputs,
            self.outputs,
            self.dt,
            match &self.engine {
                Engine::One { inner, .. } => inner.n_terms().to_string(),
                Engine::Bank(_) => "choosing online".into(),
            }
        )
    }
}
