//! Rust errors as Python exceptions: bad values are `ValueError`, files that cannot be opened
//! `OSError` (`FileNotFoundError` when missing), with the message naming what was wrong.

use laserlines_io::ReadError;
use pyo3::PyErr;
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyPermissionError, PyValueError};

/// A read error as an exception: opening failures are `OSError`s, everything else (a bad
/// record, an unknown format or topic) a `ValueError`, each with the reader's message
/// (file, line or byte offset or row, what was expected).
pub fn read_error(e: &ReadError) -> PyErr {
    let message = e.to_string();
    match e {
        ReadError::Open { source, .. } | ReadError::Io { source, .. } => match source.kind() {
            std::io::ErrorKind::NotFound => PyFileNotFoundError::new_err(message),
            std::io::ErrorKind::PermissionDenied => PyPermissionError::new_err(message),
            _ => PyOSError::new_err(message),
        },
        _ => PyValueError::new_err(message),
    }
}

/// Any error whose message says it all, as a `ValueError`.
pub fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}
