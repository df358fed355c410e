//! Scans in Python: the `Scan` class (a scan with its stamp, pose and odometry, ranges as a numpy
//! array) and `read(path, topic=None)`, which iterates the scans of any file the command line
//! reads.

use std::sync::Mutex;

use laserlines_io::{Format, ReadOptions, ScanReader, ScanRecord};
use numpy::{PyArray1, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::read_error;

/// One laser scan, shaped like `sensor_msgs/LaserScan`: beam `i` points at
/// `angle_min + i * angle_increment` (rad); ranges in metres (NaN or inf: no return).
#[pyclass(frozen, module = "laserlines")]
pub struct Scan {
    ranges: Py<PyArray1<f64>>,
    /// Angle of the first beam, rad.
    #[pyo3(get)]
    pub angle_min: f64,
    /// Angle between beams, rad (negative: clockwise).
    #[pyo3(get)]
    pub angle_increment: f64,
    /// Smallest valid range, m.
    #[pyo3(get)]
    pub range_min: f64,
    /// Largest valid range, m (`inf`: no limit; see [`Scan::range_max_py`]).
    pub range_max: f64,
    /// Time stamp, s, when the source has one.
    #[pyo3(get)]
    pub stamp: Option<f64>,
    /// The robot's pose `(x, y, theta)` (m, m, rad) when the source has one.
    #[pyo3(get)]
    pub pose: Option<(f64, f64, f64)>,
    /// The wheel odometry's pose `(x, y, theta)` (m, m, rad) at the scan, when the source
    /// has it.
    #[pyo3(get)]
    pub odometry: Option<(f64, f64, f64)>,
    intensities: Option<Py<PyArray1<f64>>>,
}

impl Scan {
    /// The ranges array.
    pub fn ranges<'py>(&self, py: Python<'py>) -> &Bound<'py, PyAny> {
        self.ranges.bind(py).as_any()
    }

    /// A record read from a file, its vectors moved into numpy arrays.
    fn of_record(py: Python<'_>, record: ScanRecord) -> Self {
        let s = record.scan;
        Self {
            ranges: PyArray1::from_vec(py, s.ranges).unbind(),
            angle_min: s.angle_min,
            angle_increment: s.angle_increment,
            range_min: s.range_min,
            range_max: s.range_max,
            stamp: s.stamp,
            pose: record.pose.map(|p| (p.x, p.y, p.theta)),
            odometry: record.odometry.map(|p| (p.x, p.y, p.theta)),
            intensities: s.intensities.map(|v| PyArray1::from_vec(py, v).unbind()),
        }
    }
}

#[pymethods]
impl Scan {
    #[new]
    #[pyo3(signature = (ranges, angle_min, angle_increment, range_min = 0.0, range_max = f64::INFINITY, stamp = None, pose = None, odometry = None))]
    #[pyo3(
        text_signature = "(ranges, angle_min, angle_increment, range_min=0.0, range_max=float('inf'), stamp=None, pose=None, odometry=None)"
    )]
    // The Python signature: a scan's fields as keyword arguments.
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        ranges: &Bound<'_, PyAny>,
        angle_min: f64,
        angle_increment: f64,
        range_min: f64,
        range_max: f64,
        stamp: Option<f64>,
        pose: Option<&Bound<'_, PyAny>>,
        odometry: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let pose = crate::args::optional_pose(pose, "pose")?;
        let odometry = crate::args::optional_pose(odometry, "odometry")?;
        let values = crate::arrays::ranges(ranges)?;
        crate::config::checked_view(
            values.as_slice(),
            angle_min,
            angle_increment,
            range_min,
            range_max,
        )
        .map_err(crate::errors::value_error)?;
        if let Some(t) = stamp.filter(|t| !t.is_finite()) {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "stamp must be a finite number of seconds or None, got {t}"
            )));
        }
        // A float64 array is kept as given; anything else as its float64 copy.
        let array = match ranges.cast::<PyArray1<f64>>() {
            Ok(a) => a.clone().unbind(),
            Err(_) => PyArray1::from_slice(py, values.as_slice()).unbind(),
        };
        Ok(Self {
            ranges: array,
            angle_min,
            angle_increment,
            range_min,
            range_max,
            stamp,
            pose,
            odometry,
            intensities: None,
        })
    }

    /// The ranges, m, as a float64 array.
    #[getter(ranges)]
    fn ranges_array<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.ranges.bind(py).clone()
    }

    /// The intensities, one per range, when the source has them.
    #[getter]
    fn intensities<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        self.intensities.as_ref().map(|a| a.bind(py).clone())
    }

    /// Largest valid range, m: `inf` for no limit (files without one, such as CSV, give the
    /// largest finite number, which is no limit either).
    #[getter(range_max)]
    fn range_max_py(&self) -> f64 {
        if self.range_max == f64::MAX {
            f64::INFINITY
        } else {
            self.range_max
        }
    }

    fn __len__(&self, py: Python<'_>) -> usize {
        PyUntypedArrayMethods::len(self.ranges.bind(py))
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let triple = |t: Option<(f64, f64, f64)>| {
            t.map_or_else(|| "None".to_owned(), |(x, y, a)| format!("({x}, {y}, {a})"))
        };
        format!(
            "Scan({} beams from {:.4} rad by {:.6} rad, ranges {}..{} m, stamp {}, pose {}, \
             odometry {})",
            PyUntypedArrayMethods::len(self.ranges.bind(py)),
            self.angle_min,
            self.angle_increment,
            self.range_min,
            self.range_max_py(),
            self.stamp
                .map_or_else(|| "None".to_owned(), |t| t.to_string()),
            triple(self.pose),
            triple(self.odometry),
        )
    }
}

/// An iterator of the scans of a file (see `laserlines.read`).
#[pyclass(frozen, module = "laserlines")]
pub struct ScanIterator {
    reader: Mutex<ScanReader>,
    skip_bad: bool,
    skipped: Mutex<u64>,
}

#[pymethods]
impl ScanIterator {
    fn __iter__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __next__(&self, py: Python<'_>) -> PyResult<Option<Scan>> {
        loop {
            let item = py.detach(|| {
                let mut reader = self
                    .reader
                    .lock()
                    .unwrap_or_else(std::sync::PoisonError::into_inner);
                reader.next()
            });
            match item {
                None => return Ok(None),
                Some(Ok(record)) => return Ok(Some(Scan::of_record(py, record))),
                // A failed read of the file itself is no bad record: it is raised.
                Some(Err(e)) if self.skip_bad && e.is_bad_record() => {
                    *self
                        .skipped
                        .lock()
                        .unwrap_or_else(std::sync::PoisonError::into_inner) += 1;
                    let _ = e;
                }
                Some(Err(e)) => return Err(read_error(&e)),
            }
        }
    }

    /// Records skipped so far (with `skip_bad=True`).
    #[getter]
    fn skipped(&self) -> u64 {
        *self
            .skipped
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// What the reader left out so far, by reason, as the command line's summary lists it:
    /// bad records skipped (`malformed record`), scans of other topics, readings sharing a
    /// beam, scans of a chunk or row group that could not be read, ...
    #[getter]
    fn skip_reasons<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let reader = self
            .reader
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let reasons = PyDict::new(py);
        for (reason, n) in reader.skipped().iter() {
            reasons.set_item(reason, n)?;
        }
        Ok(reasons)
    }
}

/// Opens `path` as the command line does: any format by its extension (MCAP and ROS 2 bag
/// directories, Parquet, BreezySLAM, CARMEN, ROS 1 bags, JSON, JSONL, CSV; `.gz` inflated),
/// or by `format`'s name (`laserlines extract --format`) whatever the name of the file.
///
/// # Errors
/// `ValueError` for an unknown format name; the reader's error (see `errors::read_error`).
pub fn open(
    path: &std::path::Path,
    format: Option<&str>,
    topic: Option<String>,
) -> PyResult<ScanReader> {
    let format = format
        .map(|name| {
            name.parse::<Format>().map_err(|_| {
                PyValueError::new_err(format!(
                    "unknown format {name:?}: expected one of {}",
                    Format::NAMES.join(", ")
                ))
            })
        })
        .transpose()?;
    let options = ReadOptions::format(format).with_topic(topic.as_deref());
    laserlines_foxglove::open_scans(path, &options).map_err(|e| read_error(&e))
}

/// Iterates the scans of the file `path`, with their stamps and poses.
#[pyfunction]
#[pyo3(signature = (path, topic = None, skip_bad = false, format = None))]
pub fn read(
    path: crate::args::FsPath,
    topic: Option<String>,
    skip_bad: bool,
    format: Option<&str>,
) -> PyResult<ScanIterator> {
    Ok(ScanIterator {
        reader: Mutex::new(open(&path.0, format, topic)?),
        skip_bad,
        skipped: Mutex::new(0),
    })
}

/// Readings at their own bearings (a spinning scanner's raw output: RPLIDAR, YDLIDAR) as a
/// `Scan` of evenly spaced beams, and the number of readings left out because their beam
/// kept a better one ([`laserlines::bearings::grid`]).
#[pyfunction]
#[pyo3(signature = (bearings, ranges, angle_increment = None, range_min = 0.0, range_max = f64::INFINITY))]
#[pyo3(
    text_signature = "(bearings, ranges, angle_increment=None, range_min=0.0, range_max=float('inf'))"
)]
pub fn scan_from_bearings(
    py: Python<'_>,
    bearings: Vec<f64>,
    ranges: Vec<f64>,
    angle_increment: Option<f64>,
    range_min: f64,
    range_max: f64,
) -> PyResult<(Scan, usize)> {
    // No upper limit, as a `Scan` of Python takes it: the largest finite range.
    let limit = if range_max == f64::INFINITY {
        f64::MAX
    } else {
        range_max
    };
    let gridded = py
        .detach(|| {
            laserlines::bearings::grid(&bearings, &ranges, angle_increment, range_min, limit)
        })
        .map_err(crate::errors::value_error)?;
    let s = gridded.scan;
    let scan = Scan {
        ranges: PyArray1::from_vec(py, s.ranges).unbind(),
        angle_min: s.angle_min,
        angle_increment: s.angle_increment,
        range_min,
        range_max,
        stamp: None,
        pose: None,
        odometry: None,
        intensities: None,
    };
    Ok((scan, gridded.shared))
}
