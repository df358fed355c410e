//! numpy in and out: the ranges of a scan read in place when they are a contiguous `float64`
//! array ([`Ranges`]), and the lines of a scan as a dict of arrays ([`LineColumns`]).

use laserlines::Line;
use numpy::ndarray::{Array2, Array3};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

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

/// The ranges of `obj`, a 1-D numpy array of `float64` or `float32` (metres; NaN or inf for
/// no return).
///
/// # Errors
/// `TypeError` for anything but a numpy array of those types, `ValueError` for an array that
/// is not 1-D.
pub fn ranges<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Ranges<'py>> {
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
    Err(PyTypeError::new_err(format!(
        "ranges must be a numpy array of float64 or float32, got {found} \
         (numpy.asarray(ranges, dtype=float) makes one)"
    )))
}

/// The lines of one scan as columns: what the dict of arrays holds.
#[derive(Debug, Default)]
pub struct LineColumns {
    start: Vec<f64>,
    end: Vec<f64>,
    r: Vec<f64>,
    alpha: Vec<f64>,
    first: Vec<i64>,
    last: Vec<i64>,
    points: Vec<i64>,
    rms: Vec<f64>,
    covariance: Vec<f64>,
}

impl LineColumns {
    /// The columns of `lines`.
    pub fn of(lines: &[Line]) -> Self {
        let n = lines.len();
        let mut c = Self {
            start: Vec::with_capacity(2 * n),
            end: Vec::with_capacity(2 * n),
            r: Vec::with_capacity(n),
            alpha: Vec::with_capacity(n),
            first: Vec::with_capacity(n),
            last: Vec::with_capacity(n),
            points: Vec::with_capacity(n),
            rms: Vec::with_capacity(n),
            covariance: Vec::with_capacity(4 * n),
        };
        for l in lines {
            c.start.extend([l.start.x, l.start.y]);
            c.end.extend([l.end.x, l.end.y]);
            c.r.push(l.r);
            c.alpha.push(l.alpha);
            c.first.push(l.first as i64);
            c.last.push(l.last as i64);
            c.points.push(l.points as i64);
            c.rms.push(l.rms);
            let m = &l.covariance;
            c.covariance
                .extend([m[(0, 0)], m[(0, 1)], m[(1, 0)], m[(1, 1)]]);
        }
        c
    }

    /// The dict of arrays: `start`, `end` (n, 2), `r`, `alpha`, `rms` (n,) float64, `first`,
    /// `last`, `points` (n,) int64, `covariance` (n, 2, 2). The vectors move into the
    /// arrays, without a copy.
    pub fn into_dict(self, py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
        let n = self.r.len();
        let shape = |e: numpy::ndarray::ShapeError| PyValueError::new_err(e.to_string());
        let d = PyDict::new(py);
        let pairs = |v: Vec<f64>| Array2::from_shape_vec((n, 2), v).map_err(shape);
        d.set_item(
            "start",
            numpy::PyArray2::from_owned_array(py, pairs(self.start)?),
        )?;
        d.set_item(
            "end",
            numpy::PyArray2::from_owned_array(py, pairs(self.end)?),
        )?;
        d.set_item("r", PyArray1::from_vec(py, self.r))?;
        d.set_item("alpha", PyArray1::from_vec(py, self.alpha))?;
        d.set_item("first", PyArray1::from_vec(py, self.first))?;
        d.set_item("last", PyArray1::from_vec(py, self.last))?;
        d.set_item("points", PyArray1::from_vec(py, self.points))?;
        d.set_item("rms", PyArray1::from_vec(py, self.rms))?;
        let cov = Array3::from_shape_vec((n, 2, 2), self.covariance).map_err(shape)?;
        d.set_item("covariance", numpy::PyArray3::from_owned_array(py, cov))?;
        Ok(d)
    }
}
