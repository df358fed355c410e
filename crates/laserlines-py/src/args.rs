//! Arguments taken as Python takes them elsewhere: a path as `str`, `bytes` or
//! `os.PathLike` (as `open()` takes one), and a pose as any sequence of three numbers (a
//! tuple, a list, a numpy array).

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyString};
use std::path::PathBuf;

/// A file path given as `str`, `bytes` or `os.PathLike` of either.
#[derive(Debug, Clone)]
pub struct FsPath(pub PathBuf);

impl FromPyObject<'_, '_> for FsPath {
    type Error = PyErr;

    fn extract(ob: Borrowed<'_, '_, PyAny>) -> PyResult<Self> {
        let os = ob.py().import("os")?;
        let refused = || {
            PyTypeError::new_err(format!(
                "path must be a str, bytes or os.PathLike, got {}",
                type_name(&ob)
            ))
        };
        let given = os.call_method1("fspath", (ob,)).map_err(|_| refused())?;
        // Bytes are the file system's own encoding: `os.fsdecode` gives the str that encodes
        // back to them, byte for byte (undecodable bytes as surrogate escapes).
        let text = if given.cast::<PyBytes>().is_ok() {
            os.call_method1("fsdecode", (given,))?
        } else if given.cast::<PyString>().is_ok() {
            given
        } else {
            return Err(refused());
        };
        Ok(Self(text.extract::<PathBuf>()?))
    }
}

/// A pose `(x, y, theta)` (m, m, rad) given as any sequence of three finite numbers.
#[derive(Debug, Clone, Copy)]
pub struct Pose3(pub (f64, f64, f64));

impl Pose3 {
    /// The pose argument `name` from `ob`.
    ///
    /// # Errors
    /// `TypeError` for anything that is no sequence of numbers, `ValueError` for a sequence
    /// of another length or with a value that is not finite; each names the argument.
    pub fn from_arg(ob: &Bound<'_, PyAny>, name: &str) -> PyResult<Self> {
        let expected = "three finite numbers (x, y, theta) or None";
        if ob.cast::<PyString>().is_ok() || ob.cast::<PyBytes>().is_ok() {
            return Err(PyTypeError::new_err(format!(
                "{name} must be {expected}, got {}",
                type_name(&ob.as_borrowed())
            )));
        }
        let values: Vec<f64> = ob.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "{name} must be {expected}, got {}",
                type_name(&ob.as_borrowed())
            ))
        })?;
        match values[..] {
            [x, y, t] if x.is_finite() && y.is_finite() && t.is_finite() => Ok(Self((x, y, t))),
            [x, y, t] => Err(PyValueError::new_err(format!(
                "{name} must be {expected}, got ({x}, {y}, {t})"
            ))),
            _ => Err(PyValueError::new_err(format!(
                "{name} must be {expected}, got {} numbers",
                values.len()
            ))),
        }
    }
}

/// The pose argument `name`, `None` when not given or given as `None`.
///
/// # Errors
/// As [`Pose3::from_arg`].
pub fn optional_pose(
    ob: Option<&Bound<'_, PyAny>>,
    name: &str,
) -> PyResult<Option<(f64, f64, f64)>> {
    match ob {
        Some(v) if !v.is_none() => Pose3::from_arg(v, name).map(|p| Some(p.0)),
        _ => Ok(None),
    }
}

fn type_name(ob: &Borrowed<'_, '_, PyAny>) -> String {
    ob.get_type()
        .name()
        .map_or_else(|_| "an object".to_owned(), |n| n.to_string())
}
