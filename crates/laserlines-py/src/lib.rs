//! # laserlines-py
//!
//! The Python package `laserlines` (PyO3, built by maturin as one stable-ABI wheel for every
//! CPython >= 3.9; see `pyproject.toml` and `laserlines.pyi`):
//!
//! - `extract(ranges, angle_min, angle_increment, range_min=None, range_max=None,
//!   algorithm="hough-split", **params)` and the `Extractor` class, which keeps its working
//!   memory: lines of one scan as a numpy structured array (one record per line). A contiguous `float64` array is read
//!   in place ([`laserlines::ScanView`]), never copied; the GIL is released while extracting.
//! - `read(path, topic=None, skip_bad=False, format=None)`: the scans of any file the
//!   command line reads, with stamp and pose.
//! - `extract_file(path, ...)` and `Extractor.extract_table(table)`: lines as a
//!   `pyarrow.Table` of the Parquet lines schema ([`laserlines_parquet::schema`]), built in
//!   Rust and handed over through the Arrow C data interface.
//!
//! The bindings are behind the feature `python` (maturin turns it on), so that building and
//! testing the workspace needs no Python. [`config`] holds what they decide without Python.

pub mod config;

#[cfg(feature = "python")]
mod args;
#[cfg(feature = "python")]
mod arrays;
#[cfg(feature = "python")]
mod errors;
#[cfg(feature = "python")]
mod extractor;
#[cfg(feature = "python")]
mod kwargs;
#[cfg(feature = "python")]
mod messages;
#[cfg(feature = "python")]
mod scans;
#[cfg(feature = "python")]
mod tables;

#[cfg(feature = "python")]
use pyo3::prelude::*;

/// The module `laserlines`.
#[cfg(feature = "python")]
#[pymodule]
#[pyo3(name = "laserlines")]
fn laserlines_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__doc__", module_doc())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add(
        "ALGORITHMS",
        pyo3::types::PyTuple::new(py, laserlines::registry::ALGORITHMS)?,
    )?;
    m.add_class::<extractor::Extractor>()?;
    m.add_class::<scans::Scan>()?;
    m.add_class::<scans::ScanIterator>()?;
    m.add_function(wrap_pyfunction!(extractor::extract, m)?)?;
    m.add_function(wrap_pyfunction!(scans::read, m)?)?;
    m.add_function(wrap_pyfunction!(scans::scan_from_bearings, m)?)?;
    m.add_function(wrap_pyfunction!(tables::extract_file, m)?)?;
    m.add_function(wrap_pyfunction!(tables::lines_schema_py, m)?)?;
    m.add_function(wrap_pyfunction!(tables::scans_schema_py, m)?)?;
    m.add_function(wrap_pyfunction!(messages::scans_from_messages, m)?)?;
    Ok(())
}

/// The module's docstring at run time: the one of `laserlines.pyi` (units, frames, the fields
/// of a line), so that `help(laserlines)` says what the stub says.
#[cfg(feature = "python")]
fn module_doc() -> &'static str {
    const STUB: &str = include_str!("../laserlines.pyi");
    STUB.strip_prefix("\"\"\"")
        .and_then(|rest| rest.split_once("\"\"\"").map(|(doc, _)| doc))
        .unwrap_or("Line segments from 2D laser range scans.")
}
