//! `rhonn._rhonn`: the Rust side of the Python package `rhonn` (the pure-Python
//! `rhonn/__init__.py` checks arguments and shapes the results). Glue only: every call is
//! a `rhonn` or `rhonn_report` library call, made with the GIL released when it can take
//! long. No panic reaches Python: sizes and values from the caller are checked here or
//! by the library, which returns errors.

mod arrays;
mod errors;
mod model;
mod online;

use arrays::{columns_dict, record};
use errors::{report_err, rhonn_err};
use numpy::PyReadonlyArray2;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use rhonn::cancel::{Waited, Worker};
use rhonn::experiment::ScenarioSpec;
use std::path::PathBuf;

/// A scenario given as a shipped name, a path, or TOML text.
fn scenario(name_or_path: &str, toml_text: Option<&str>) -> PyResult<ScenarioSpec> {
    rhonn::experiment::preset::load_or_parse(name_or_path, toml_text).map_err(rhonn_err)
}

/// TOML text of a JSON object (a scenario or model spec given as a Python dict).
#[pyfunction]
fn json_to_toml(json: &str) -> PyResult<String> {
    rhonn_app::toml_of_json(json).map_err(report_err)
}

/// A run's trajectory (name -> SI array), validation columns, and summary.json's text.
type RunResult = (Py<PyAny>, Option<Py<PyAny>>, String);

/// `f` on a worker thread (`rhonn::cancel::Worker`); Ctrl-C is checked every 50 ms, and
/// raises KeyboardInterrupt at once while the library stops at its next check.
fn interruptible<T: Send + 'static>(py: Python<'_>, f: impl FnOnce() -> T + Send + 'static) -> PyResult<T> {
    let w = Worker::start(f);
    loop {
        match py.detach(|| w.wait(std::time::Duration::from_millis(50))) {
            Waited::Done(v) => return Ok(v),
            Waited::Running => py.check_signals().inspect_err(|_| rhonn::cancel::request())?,
            Waited::Lost => return Err(PyRuntimeError::new_err("the call's worker thread panicked")),
        }
    }
}

/// Run a scenario; write its folder too when `out` is given.
#[pyfunction]
#[pyo3(signature = (name, toml_text=None, out=None))]
fn run(py: Python<'_>, name: &str, toml_text: Option<&str>, out: Option<PathBuf>) -> PyResult<RunResult> {
    let sc = scenario(name, toml_text)?;
    let (run, _) =
        interruptible(py, move || rhonn_app::run_scenario(&sc, out.as_deref()))?.map_err(report_err)?;
    let summary = rhonn_report::scenario_run::summary_json(&run).map_err(report_err)?;
    let (traj, val) = run.into_columns();
    let traj = columns_dict(py, traj.into_iter())?;
    let val = val.map(|v| columns_dict(py, v.into_iter())).transpose()?;
    Ok((traj, val, summary))
}

/// Fit a model to recordings (`us[k]`: (n, m), `ys[k]`: (n, p), sampled every `dt` s);
/// `spec`: TOML text and what names it; `select`: `fit_args::FitArgs::given`'s arguments.
#[pyfunction]
#[pyo3(signature = (us, ys, dt, inputs, outputs, spec=None, select=(None, None, None)))]
#[allow(clippy::too_many_arguments)]
fn fit(
    py: Python<'_>,
    us: Vec<PyReadonlyArray2<'_, f64>>,
    ys: Vec<PyReadonlyArray2<'_, f64>>,
    dt: f64,
    inputs: Vec<String>,
    outputs: Vec<String>,
    spec: Option<(String, String)>,
    select: (Option<String>, Option<i128>, Option<f64>),
) -> PyResult<model::Model> {
    let recs = us
        .iter()
        .zip(&ys)
        .enumerate()
        .map(|(k, (u, y))| record(&format!("recording {k}"), dt, u, y, &inputs, &outputs))
        .collect::<PyResult<Vec<_>>>()?;
    let (fitted, summary, notes) = interruptible(py, move || {
        let spec = spec.as_ref().map(|(t, s)| (t.as_str(), s.as_str()));
        let args = rhonn_app::fit_args::FitArgs::given(select.0.as_deref(), select.1, select.2);
        rhonn_app::fit_in_memory(&recs, &inputs, &outputs, spec, args)
    })?
    .map_err(report_err)?;
    Ok(model::Model(fitted, Some(summary), notes))
}

/// A Monte Carlo campaign into `out` (resuming one); `threads` None: every core.
#[pyfunction]
#[pyo3(signature = (name, runs, seed, out, toml_text=None, threads=None, corners=false, envelope_runs=1000))]
#[allow(clippy::too_many_arguments)]
fn campaign(
    py: Python<'_>,
    name: &str,
    runs: u64,
    seed: u64,
    out: PathBuf,
    toml_text: Option<&str>,
    threads: Option<usize>,
    corners: bool,
    envelope_runs: u64,
) -> PyResult<String> {
    use rhonn_app::campaign::CampaignOptions;
    let sc = scenario(name, toml_text)?;
    let opts = CampaignOptions::whole(runs, seed, corners, envelope_runs);
    let zero = "threads = 0 is not allowed: give 1 or more, or None for every core";
    let shown = out.display().to_string();
    interruptible(py, move || {
        rhonn_app::campaign(&sc, &opts, &out, (threads, zero), &|_| {})
    })?
    .map_err(report_err)?;
    Ok(shown)
}

/// For `python/bench.py`: the median seconds of `repeats` runs of a scenario from Rust.
#[pyfunction]
fn _rust_run_seconds(py: Python<'_>, name: &str, repeats: usize) -> PyResult<f64> {
    let sc = scenario(name, None)?;
    py.detach(|| rhonn::experiment::median_run_seconds(&sc, repeats))
        .map_err(rhonn_err)
}

/// The shipped scenarios: (name, description).
#[pyfunction]
fn scenarios() -> Vec<(&'static str, String)> {
    rhonn::experiment::preset::list()
}

/// A scenario's TOML text (a shipped one as shipped).
#[pyfunction]
fn show(name: &str) -> PyResult<String> {
    rhonn_app::show(name).map_err(report_err)
}

/// The Rust side of `rhonn`.
#[pymodule]
fn _rhonn(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(fit, m)?)?;
    m.add_function(wrap_pyfunction!(campaign, m)?)?;
    m.add_function(wrap_pyfunction!(scenarios, m)?)?;
    m.add_function(wrap_pyfunction!(show, m)?)?;
    m.add_function(wrap_pyfunction!(json_to_toml, m)?)?;
    m.add_function(wrap_pyfunction!(_rust_run_seconds, m)?)?;
    m.add_function(wrap_pyfunction!(model::load, m)?)?;
    m.add_class::<model::Model>()?;
    m.add_class::<online::OnlineIdentifier>()?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
