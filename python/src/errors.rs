//! Errors as Python exceptions: what a caller gave wrong is a `ValueError` (or `OSError`
//! for a file that cannot be read), what failed while running a `RuntimeError`; the
//! message is the command line's.

use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::PyErr;

pub fn value_error(msg: impl Into<String>) -> PyErr {
    PyValueError::new_err(msg.into())
}

pub fn rhonn_err(e: rhonn::Error) -> PyErr {
    use rhonn::Error as E;
    match &e {
        E::Invalid { .. } | E::Parse { .. } | E::UnknownScenario { .. } | E::Argument(_) => {
            PyValueError::new_err(e.to_string())
        }
        E::Io { .. } => PyOSError::new_err(e.to_string()),
        _ => PyRuntimeError::new_err(e.to_string()),
    }
}

pub fn report_err(e: rhonn_report::Error) -> PyErr {
    use rhonn_report::Error as E;
    match e {
        E::Rhonn(e) => rhonn_err(e),
        E::Input(m) => PyValueError::new_err(m),
        E::Data(d) => PyValueError::new_err(d.to_string()),
        E::Context { context, source } => {
            let inner = report_err(*source);
            let text = pyo3::Python::attach(|py| inner.value(py).to_string());
            let msg = format!("{context}: {text}");
            pyo3::Python::attach(|py| {
                if inner.is_instance_of::<PyValueError>(py) {
                    PyValueError::new_err(msg)
                } else if inner.is_instance_of::<PyOSError>(py) {
                    PyOSError::new_err(msg)
                } else {
                    PyRuntimeError::new_err(msg)
                }
            })
        }
        E::Folder { .. } | E::File { .. } => PyOSError::new_err(e.to_string()),
        other => PyRuntimeError::new_err(other.to_string()),
    }
}

/// JSON text of a summary (Python parses it into a dict).
pub fn json(v: &impl serde::Serialize) -> pyo3::PyResult<String> {
    serde_json::to_string(v)
        .map_err(|e| PyRuntimeError::new_err(format!("cannot write the summary as JSON: {e}")))
}
