//! The `Extractor` class (an extractor by name, with its working memory kept across calls)
//! and the module-level `extract`.

use std::sync::{Mutex, MutexGuard, PoisonError};

use laserlines::registry::BoxedExtractor;
use laserlines::{Line, ScanView};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{LineRecords, ranges as read_ranges};
use crate::config::{self, make_extractor};
use crate::errors::value_error;
use crate::kwargs;
use crate::scans::Scan;
use crate::tables;

/// What an extraction works with: the extractor, its output buffer, and where the ranges it
/// last read were.
pub struct Working {
    pub extractor: BoxedExtractor,
    pub lines: Vec<Line>,
    /// Address of the first range the last extraction read.
    pub last_address: usize,
}

/// A line extractor chosen by name, with its parameters as keyword arguments laid over the
/// algorithm's defaults. It keeps its working memory between calls; the GIL is released while
/// it extracts, so threads with an extractor each run in parallel.
#[pyclass(frozen, module = "laserlines")]
pub struct Extractor {
    algorithm: String,
    params: toml::Table,
    working: Mutex<Working>,
}

impl Extractor {
    /// An extractor of `algorithm` with `params` over its defaults.
    pub fn build(algorithm: &str, params: toml::Table) -> PyResult<Self> {
        let built = make_extractor(algorithm, params).map_err(value_error)?;
        Ok(Self {
            algorithm: algorithm.to_owned(),
            params: built.params,
            working: Mutex::new(Working {
                extractor: built.extractor,
                lines: Vec::new(),
                last_address: 0,
            }),
        })
    }

    /// The working memory, for one extraction at a time. A panic in an extractor leaves it
    /// as it was (each extraction starts afresh).
    pub fn working(&self) -> MutexGuard<'_, Working> {
        self.working.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Extracts the lines of `view` without the GIL; the columns of the result.
    fn extract_view(&self, py: Python<'_>, view: ScanView<'_>) -> LineRecords {
        py.detach(|| {
            let mut w = self.working();
            let Working {
                extractor,
                lines,
                last_address,
            } = &mut *w;
            extractor.extract_view_into(view, lines);
            *last_address = view.ranges.as_ptr() as usize;
            LineRecords::of(lines)
        })
    }
}

#[pymethods]
impl Extractor {
    #[new]
    #[pyo3(signature = (algorithm = "hough-split", **params))]
    fn new(algorithm: &str, params: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        Self::build(algorithm, kwargs::to_table(params)?)
    }

    /// The algorithm's name.
    #[getter]
    fn algorithm(&self) -> &str {
        &self.algorithm
    }

    /// Pickling (`pickle`, `copy`, a Ray task's closure): an extractor of the same algorithm
    /// and parameters, `functools.partial(Extractor, algorithm, **params)()`, with fresh
    /// working memory.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, pyo3::types::PyTuple>)> {
        let py = slf.py();
        let this = slf.get();
        let params = kwargs::to_dict(py, &this.params)?;
        let partial = py
            .import("functools")?
            .getattr("partial")?
            .call((slf.get_type(), this.algorithm.as_str()), Some(&params))?;
        Ok((partial, pyo3::types::PyTuple::empty(py)))
    }

    /// Every parameter the extractor runs with (SI units, angles in radians), as a dict, as a
    /// params file writes them: one left unset (`range_limits`: the scan's own) is absent.
    #[getter]
    fn params<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        kwargs::to_dict(py, &self.params)
    }

    /// Address of the first range the last extraction read: the array's own buffer
    /// (`ranges.ctypes.data`) when it was read in place, a converted copy's otherwise.
    #[getter]
    fn last_ranges_address(&self, py: Python<'_>) -> usize {
        // The lock is waited for without the GIL, as every other use of it.
        py.detach(|| self.working().last_address)
    }

    /// The lines of one scan, a `Scan` or a 1-D float64/float32 array of ranges (m) with
    /// `angle_min` and `angle_increment` (rad) and, optionally, the valid range limits
    /// `range_min` (default 0) and `range_max` (default `inf`, no limit); a `Scan` brings its
    /// own geometry and limits. Returns a numpy structured array, one record per line
    /// (`start`, `end`, `r`, `alpha`, `first`, `last`, `points`, `rms`, `covariance`).
    #[pyo3(signature = (ranges, angle_min = None, angle_increment = None, range_min = None, range_max = None))]
    fn extract<'py>(
        &self,
        py: Python<'py>,
        ranges: &Bound<'py, PyAny>,
        angle_min: Option<&Bound<'py, PyAny>>,
        angle_increment: Option<&Bound<'py, PyAny>>,
        range_min: Option<&Bound<'py, PyAny>>,
        range_max: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let angle_min = number(angle_min, "angle_min")?;
        let angle_increment = number(angle_increment, "angle_increment")?;
        let range_min = number(range_min, "range_min")?;
        let range_max = number(range_max, "range_max")?;
        if let Ok(scan) = ranges.cast::<Scan>() {
            if angle_min.is_some() || angle_increment.is_some() {
                return Err(PyTypeError::new_err(
                    "extract(scan) takes its geometry from the scan: give no angle_min or angle_increment",
                ));
            }
            if range_min.is_some() || range_max.is_some() {
                return Err(PyTypeError::new_err(
                    "extract(scan) takes its range limits from the scan: give no range_min or \
                     range_max (Scan(ranges, angle_min, angle_increment, range_min, range_max) \
                     makes a scan with others)",
                ));
            }
            let scan = scan.get();
            let values = read_ranges(scan.ranges(py))?;
            let view = config::checked_view(
                values.as_slice(),
                scan.angle_min,
                scan.angle_increment,
                scan.range_min,
                scan.range_max,
            )
            .map_err(value_error)?;
            return self.extract_view(py, view).into_array(py);
        }
        let (Some(angle_min), Some(angle_increment)) = (angle_min, angle_increment) else {
            return Err(PyTypeError::new_err(
                "extract() needs angle_min and angle_increment (rad) with an array of ranges",
            ));
        };
        let values = read_ranges(ranges)?;
        let view = config::checked_view(
            values.as_slice(),
            angle_min,
            angle_increment,
            range_min.unwrap_or(0.0),
            range_max.unwrap_or(f64::INFINITY),
        )
        .map_err(value_error)?;
        self.extract_view(py, view).into_array(py)
    }

    /// Seconds per extraction of one scan, timed in Rust around the extraction alone
    /// (`repeat` times, the mean): what a call from Python costs beyond it is the binding's
    /// overhead.
    #[pyo3(signature = (ranges, angle_min, angle_increment, range_min = 0.0, range_max = f64::INFINITY, repeat = 1000))]
    #[pyo3(
        text_signature = "(self, ranges, angle_min, angle_increment, range_min=0.0, range_max=float('inf'), repeat=1000)"
    )]
    // The Python signature: a scan's fields as keyword arguments.
    #[allow(clippy::too_many_arguments)]
    fn time_extract(
        &self,
        py: Python<'_>,
        ranges: &Bound<'_, PyAny>,
        angle_min: f64,
        angle_increment: f64,
        range_min: f64,
        range_max: f64,
        repeat: i64,
    ) -> PyResult<f64> {
        let repeat = u32::try_from(repeat)
            .ok()
            .filter(|&r| r >= 1)
            .ok_or_else(|| {
                PyValueError::new_err(format!("repeat must be 1 to {}, got {repeat}", u32::MAX))
            })?;
        let values = read_ranges(ranges)?;
        let view = config::checked_view(
            values.as_slice(),
            angle_min,
            angle_increment,
            range_min,
            range_max,
        )
        .map_err(value_error)?;
        Ok(py.detach(|| {
            let mut w = self.working();
            let Working {
                extractor, lines, ..
            } = &mut *w;
            let start = std::time::Instant::now();
            for _ in 0..repeat {
                extractor.extract_view_into(view, lines);
            }
            start.elapsed().as_secs_f64() / f64::from(repeat)
        }))
    }

    /// The lines of every scan of a table of scans (the scans schema: `laserlines convert
    /// LOG scans.parquet`, a batch of Ray Data) as a `pyarrow.Table` of the lines schema.
    fn extract_table<'py>(
        &self,
        py: Python<'py>,
        table: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        tables::extract_table(self, py, table)
    }

    /// The lines of every LaserScan message of a table of messages (Ray Data's
    /// `read_mcap(..., include_metadata=True)` rows: `data`, `schema_name`,
    /// `message_encoding`, `log_time`) as a `pyarrow.Table` of the lines schema, scans
    /// numbered by row; decoded and extracted at full precision.
    fn extract_messages<'py>(
        &self,
        py: Python<'py>,
        table: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        tables::extract_messages(self, py, table)
    }

    /// The lines of every scan of the file `path` (any format the command line reads) as a
    /// `pyarrow.Table` of the lines schema.
    #[pyo3(signature = (path, topic = None, skip_bad = false, format = None))]
    fn extract_file<'py>(
        &self,
        py: Python<'py>,
        path: crate::args::FsPath,
        topic: Option<String>,
        skip_bad: bool,
        format: Option<&str>,
    ) -> PyResult<Bound<'py, PyAny>> {
        tables::extract_path(self, py, &path.0, format, topic, skip_bad)
    }

    fn __repr__(&self) -> String {
        format!("Extractor({:?})", self.algorithm)
    }
}

/// The number `name` given as `value` (`None` when not given or given as `None`); a
/// `TypeError` naming the argument for anything that is no number.
fn number(value: Option<&Bound<'_, PyAny>>, name: &str) -> PyResult<Option<f64>> {
    match value {
        Some(v) if !v.is_none() => v.extract::<f64>().map(Some).map_err(|_| {
            let found = v
                .get_type()
                .name()
                .map_or_else(|_| "?".to_owned(), |n| n.to_string());
            PyTypeError::new_err(format!("{name} must be a number, got {found}"))
        }),
        _ => Ok(None),
    }
}

/// The lines of one scan with a fresh extractor of `algorithm` and `params` laid over its
/// defaults: a `Scan`, or an array of ranges (m) with `angle_min` and `angle_increment`
/// (rad) and optional `range_min` and `range_max`; one record per line (`Extractor.extract`
/// tells the fields). An `Extractor` kept across scans saves rebuilding it.
#[pyfunction]
#[pyo3(signature = (ranges, angle_min = None, angle_increment = None, range_min = None, range_max = None, algorithm = "hough-split", **params))]
// The Python signature: a scan's fields as keyword arguments.
#[allow(clippy::too_many_arguments)]
pub fn extract<'py>(
    py: Python<'py>,
    ranges: &Bound<'py, PyAny>,
    angle_min: Option<&Bound<'py, PyAny>>,
    angle_increment: Option<&Bound<'py, PyAny>>,
    range_min: Option<&Bound<'py, PyAny>>,
    range_max: Option<&Bound<'py, PyAny>>,
    algorithm: &str,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let extractor = Extractor::build(algorithm, kwargs::to_table(params)?)?;
    extractor.extract(py, ranges, angle_min, angle_increment, range_min, range_max)
}
