//! numpy in and out: the ranges of a scan read in place when they are a contiguous `float64`
//! array ([`Ranges`]), and the lines of a scan as a structured array ([`LineRecords`]).

use laserlines::Line;
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;

/// The ranges of a scan: borrowed from a contiguous `float64` array (no copy), or converted
/// (`float32`, or a strided view).
pub enum Ranges<'py> {
    /// Read in place; the borrow keeps the array alive and marks it read by Rust.
    Borrowed(PyReadonlyArray1<'py, f64>),
    /// Converted to `float64`.
    Owned(Vec<f64>),
}

impl Ranges<'_> {
    /// The ranges.
    pub fn as_slice(&self) -> &[f64] {
        match self {
            // A borrowed array is contiguous: checked when it was taken.
            Self::Borrowed(a) => a.as_slice().unwrap_or(&[]),
            Self::Owned(v) => v,
        }
    }
}

/// The ranges of `obj`, a 1-D numpy array of `float64` (read in place when contiguous) or of
/// another float type or byte order (converted), metres; NaN or inf for no return.
///
/// # Errors
/// `TypeError` for anything but a numpy array of those types (a masked array too: its mask
/// would be lost), `ValueError` for an array that is not 1-D.
pub fn ranges<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Ranges<'py>> {
    // A masked array is an ndarray whose mask the buffer does not show.
    if obj.hasattr("mask").unwrap_or(false) && obj.hasattr("filled").unwrap_or(false) {
        return Err(PyTypeError::new_err(
            "ranges is a masked array, whose mask would be ignored: \
             numpy.ma.filled(ranges, numpy.nan) makes the masked beams no return",
        ));
    }
    if let Ok(a) = obj.cast::<PyArray1<f64>>() {
        let ro = a
            .try_readonly()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        if ro.as_slice().is_ok() {
            return Ok(Ranges::Borrowed(ro));
        }
        return Ok(Ranges::Owned(ro.as_array().iter().copied().collect()));
    }
    if let Ok(a) = obj.cast::<PyArray1<f32>>() {
        let ro = a
            .try_readonly()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        return Ok(Ranges::Owned(
            ro.as_array().iter().map(|&r| f64::from(r)).collect(),
        ));
    }
    if let Ok(a) = obj.cast::<PyUntypedArray>() {
        if a.ndim() != 1 {
            return Err(PyValueError::new_err(format!(
                "ranges must be a 1-D array, got shape {:?}",
                a.shape()
            )));
        }
        // Other floats (float16, longdouble, the other byte order): their float64 copy.
        let kind = obj.getattr("dtype").and_then(|d| d.getattr("kind"));
        if kind.is_ok_and(|k| k.extract::<String>().is_ok_and(|k| k == "f"))
            && let Ok(native) = obj.call_method1("astype", ("float64",))
            && let Ok(native) = native.cast::<PyArray1<f64>>()
        {
            let ro = native
                .try_readonly()
                .map_err(|e| PyValueError::new_err(e.to_string()))?;
            return Ok(Ranges::Owned(ro.as_array().iter().copied().collect()));
        }
        let dtype = a
            .dtype()
            .str()
            .map_or_else(|_| "?".to_owned(), |s| s.to_string());
        return Err(PyTypeError::new_err(format!(
            "ranges must be float64 or float32 (metres), got dtype {dtype}"
        )));
    }
    let found = obj
        .get_type()
        .name()
        .map_or_else(|_| "?".to_owned(), |n| n.to_string());
    // A number (a Python float, a numpy scalar) is one range, not an array of them.
    let what = if obj.extract::<f64>().is_ok() {
        format!("a single number ({found})")
    } else {
        found
    };
    Err(PyTypeError::new_err(format!(
        "ranges must be a numpy array of float64 or float32, got {what} \
         (numpy.asarray(ranges, dtype=float) makes one)"
    )))
}

/// The record of one line in the structured array: `start` and `end` (2 float64 each),
/// `r`, `alpha`, `first`, `last`, `points`, `rms`, `covariance` (4 float64), little-endian.
const LINE_DTYPE: &std::ffi::CStr = c"__import__('numpy').dtype([('start', '<f8', (2,)), ('end', '<f8', (2,)), ('r', '<f8'), ('alpha', '<f8'), ('first', '<i8'), ('last', '<i8'), ('points', '<i8'), ('rms', '<f8'), ('covariance', '<f8', (2, 2))])";

/// Bytes of one record.
const RECORD_BYTES: usize = 14 * 8;

/// The structured dtype of a line, made once.
fn line_dtype(py: Python<'_>) -> PyResult<&Bound<'_, PyAny>> {
    static DTYPE: PyOnceLock<Py<PyAny>> = PyOnceLock::new();
    DTYPE
        .get_or_try_init(py, || py.eval(LINE_DTYPE, None, None).map(Bound::unbind))
        .map(|d| d.bind(py))
}

/// The lines of one scan as the records of a numpy structured array, built without the GIL.
#[derive(Debug, Default)]
pub struct LineRecords {
    bytes: Vec<u8>,
}

impl LineRecords {
    /// The records of `lines`.
    pub fn of(lines: &[Line]) -> Self {
        let mut bytes = Vec::with_capacity(lines.len() * RECORD_BYTES);
        for l in lines {
            let m = &l.covariance;
            let floats = [l.start.x, l.start.y, l.end.x, l.end.y, l.r, l.alpha];
            for v in floats {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
            for v in [l.first, l.last, l.points] {
                bytes.extend_from_slice(&(v as i64).to_le_bytes());
            }
            for v in [l.rms, m[(0, 0)], m[(0, 1)], m[(1, 0)], m[(1, 1)]] {
                bytes.extend_from_slice(&v.to_le_bytes());
            }
        }
        Self { bytes }
    }

    /// The structured array, one record per line: fields `start`, `end` (2,) m, `r` m,
    /// `alpha` rad, `first`, `last`, `points` (int64), `rms` m, `covariance` (2, 2);
    /// `lines["r"]` is the column of `r`, `lines["start"]` an (n, 2) array.
    pub fn into_array(self, py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
        PyArray1::from_slice(py, &self.bytes).call_method1("view", (line_dtype(py)?,))
    }
}
