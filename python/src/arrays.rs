//! numpy arrays in and out: every array from Python is checked (shape, size, finite
//! values) before it reaches the library, and the error names the argument.

use crate::errors::value_error;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rhonn::data::Record;

/// The columns of a 2-D array (n, k) (its shape checked by the library); `name` names
/// the argument.
pub fn columns(name: &str, a: &PyReadonlyArray2<'_, f64>, k: usize) -> PyResult<Vec<Vec<f64>>> {
    let v = a.as_array();
    rhonn::data::check_shape(name, v.dim(), k).map_err(crate::errors::rhonn_err)?;
    Ok((0..k).map(|j| v.column(j).to_vec()).collect())
}

/// A 1-D float64 array or a sequence of numbers, of `out.len()` values, into
/// `out` (a float64 array is read without a copy).
pub fn vector_into(name: &str, a: &Bound<'_, PyAny>, out: &mut [f64]) -> PyResult<()> {
    // A complex array would lose its imaginary part in a conversion to float: refused.
    let kind = a
        .getattr("dtype")
        .and_then(|d| d.getattr("kind"))
        .and_then(|k| k.extract::<String>());
    if kind.is_ok_and(|k| k == "c") {
        return Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "{name} must hold real numbers, not complex ones"
        )));
    }
    // One signal: a plain number is its value.
    if out.len() == 1 && a.get_type().name().is_ok_and(|n| n != "str") {
        if let Ok(v) = a.extract::<f64>() {
            out[0] = v;
            return Ok(());
        }
    }
    let owned: Vec<f64>;
    let arr;
    let contiguous = a
        .cast::<PyArray1<f64>>()
        .ok()
        .map(|x| x.readonly())
        .filter(|r| r.is_c_contiguous());
    let values: &[f64] = if let Some(r) = contiguous {
        arr = r;
        arr.as_slice()
            .map_err(|_| value_error(format!("{name} must be a contiguous array")))?
    } else {
        owned = a.extract::<Vec<f64>>().map_err(|_| {
            pyo3::exceptions::PyTypeError::new_err(format!(
                "{name} must be a 1-D array or a sequence of {} numbers, not {}",
                out.len(),
                a.get_type().name().map(|n| n.to_string()).unwrap_or_default()
            ))
        })?;
        &owned
    };
    if values.len() != out.len() {
        return Err(value_error(format!(
            "{name} has {} values; {} are needed",
            values.len(),
            out.len()
        )));
    }
    // Finite values are the library's check (the identifier names the sample).
    out.copy_from_slice(values);
    Ok(())
}

/// A record sampled every `dt` s from inputs `u` (n, m) and outputs `y` (n, p).
pub fn record(
    source: &str,
    dt: f64,
    u: &PyReadonlyArray2<'_, f64>,
    y: &PyReadonlyArray2<'_, f64>,
    inputs: &[String],
    outputs: &[String],
) -> PyResult<Record> {
    let (u, y) = (columns("u", u, inputs.len())?, columns("y", y, outputs.len())?);
    Record::sampled(source, dt, u, y).map_err(crate::errors::rhonn_err)
}

/// A dict of column name -> 1-D float64 array; each array takes over its column's
/// memory (no copy).
pub fn columns_dict(py: Python<'_>, cols: impl Iterator<Item = (String, Vec<f64>)>) -> PyResult<Py<PyAny>> {
    let d = PyDict::new(py);
    for (name, values) in cols {
        d.set_item(name, PyArray1::from_vec(py, values))?;
    }
    Ok(d.into_any().unbind())
}
