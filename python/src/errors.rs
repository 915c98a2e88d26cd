//! Errors as Python exceptions, by the library's kind of each: what a caller gave wrong is
//! a `ValueError` (`OSError` for a file that cannot be read or written), what failed while
//! running a `RuntimeError`; the message is the command line's.

use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::PyErr;
use rhonn::ErrorKind;

pub fn value_error(msg: impl Into<String>) -> PyErr {
    PyValueError::new_err(msg.into())
}

fn exception(kind: ErrorKind, msg: String) -> PyErr {
    match kind {
        ErrorKind::Input => PyValueError::new_err(msg),
        ErrorKind::Io => PyOSError::new_err(msg),
        ErrorKind::Failed => PyRuntimeError::new_err(msg),
    }
}

pub fn rhonn_err(e: rhonn::Error) -> PyErr {
    exception(e.kind(), e.to_string())
}

pub fn report_err(e: rhonn_report::Error) -> PyErr {
    exception(e.kind(), e.message())
}
