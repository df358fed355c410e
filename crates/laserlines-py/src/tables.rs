//! Arrow tables: the lines of a table of scans or of a file as a `pyarrow.Table` of the lines
//! schema, and the two schemas. Tables cross between pyarrow and Rust through the Arrow C
//! data interface (PyCapsules), without copying their buffers; the lines table is built by
//! `laserlines-parquet`, the same code that writes `extract -o lines.parquet`.

use std::path::Path;
use std::sync::MutexGuard;

use arrow_array::ffi_stream::RecordBatchStreamReader;
use arrow_array::{RecordBatch, RecordBatchReader};
use arrow_pyarrow::{FromPyArrow, IntoPyArrow, Table, ToPyArrow};
use laserlines_io::{ScanRecord, SourcePos};
use laserlines_parquet::columns::{ScanColumns, check_schema};
use laserlines_parquet::{LinesColumns, lines_schema, scans_schema};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{read_error, value_error};
use crate::extractor::{Extractor, Working};
use crate::kwargs;

/// Scans between two checks for a pending signal (Ctrl-C) while a file is extracted.
const SIGNAL_SCANS: u64 = 256;

/// Runs Python's signal handlers (Ctrl-C raises `KeyboardInterrupt`) from inside an
/// extraction that runs without the GIL, every [`SIGNAL_SCANS`] scans (`done`). The
/// extractor's lock is released while the GIL is taken: a thread that holds the GIL and waits
/// for this extractor (or a signal handler that uses it) would otherwise wait for ever.
fn check_signals<'a>(
    extractor: &'a Extractor,
    guard: MutexGuard<'a, Working>,
    done: u64,
) -> (MutexGuard<'a, Working>, PyResult<()>) {
    if done == 0 || !done.is_multiple_of(SIGNAL_SCANS) {
        return (guard, Ok(()));
    }
    drop(guard);
    let checked = Python::attach(|py| py.check_signals());
    (extractor.working(), checked)
}

/// The record batches of `table`, or a `TypeError` that says what is taken (`what`: the
/// table's role).
pub fn arrow_stream(table: &Bound<'_, PyAny>, what: &str) -> PyResult<RecordBatchStreamReader> {
    RecordBatchStreamReader::from_pyarrow_bound(table).map_err(|e| {
        let kind = table
            .get_type()
            .name()
            .map_or_else(|_| "?".to_owned(), |n| n.to_string());
        pyo3::exceptions::PyTypeError::new_err(format!(
            "expected {what}: a pyarrow Table, RecordBatch or RecordBatchReader, or anything \
             with __arrow_c_stream__ (a pandas DataFrame), got {kind} ({e})"
        ))
    })
}

/// Lines per record batch of a table built here.
const BATCH_LINES: usize = 64 * 1024;

/// Lines of records, in record batches of the lines schema.
struct LinesTable {
    batches: Vec<RecordBatch>,
    columns: LinesColumns,
}

impl LinesTable {
    fn new() -> Self {
        Self {
            batches: Vec::new(),
            columns: LinesColumns::new(),
        }
    }

    /// Extracts the lines of `record` (scan number `scan`) and adds them.
    fn push(&mut self, w: &mut Working, scan: u64, record: &ScanRecord) -> Result<(), String> {
        let Working {
            extractor, lines, ..
        } = w;
        extractor.extract_into(&record.scan, lines);
        self.columns.push_record(scan, record, lines);
        if self.columns.len() >= BATCH_LINES {
            self.batches
                .push(self.columns.take_batch().map_err(|e| e.to_string())?);
        }
        Ok(())
    }

    fn into_pyarrow(mut self, py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
        if !self.columns.is_empty() || self.batches.is_empty() {
            self.batches
                .push(self.columns.take_batch().map_err(value_error)?);
        }
        Table::try_new(self.batches, lines_schema())
            .map_err(value_error)?
            .into_pyarrow(py)
    }
}

/// The lines of every scan of `table` (anything with `__arrow_c_stream__`: a
/// `pyarrow.Table`, a `RecordBatchReader`) in the scans schema. Scans are numbered by the
/// table's `scan` column, else by their row.
pub fn extract_table<'py>(
    extractor: &Extractor,
    py: Python<'py>,
    table: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let reader = arrow_stream(table, "a table of scans")?;
    check_schema(&reader.schema()).map_err(|e| {
        value_error(format!(
            "table of scans: column {}: expected {}, found {}",
            e.column, e.expected, e.found
        ))
    })?;
    let batches: Vec<RecordBatch> = reader.collect::<Result<_, _>>().map_err(value_error)?;
    let built = py.detach(|| -> PyResult<LinesTable> {
        let mut w = extractor.working();
        let mut out = LinesTable::new();
        let mut row = 0u64;
        for batch in &batches {
            let columns = ScanColumns::of(batch)
                .ok_or_else(|| value_error("table of scans: a batch of another schema"))?;
            for i in 0..batch.num_rows() {
                let record = columns
                    .record(i, &SourcePos::row("table of scans", row))
                    .map_err(value_error)?;
                let scan = match columns.scan_index(i) {
                    None => row,
                    Some(k) => u64::try_from(k).map_err(|_| {
                        value_error(format!(
                            "table of scans, row {row}: column scan: expected an index of 0 or more, found {k}"
                        ))
                    })?,
                };
                out.push(&mut w, scan, &record).map_err(value_error)?;
                row += 1;
                let checked;
                (w, checked) = check_signals(extractor, w, row);
                checked?;
            }
        }
        Ok(out)
    });
    built?.into_pyarrow(py)
}

/// The lines of every LaserScan message of `table` (rows as `scans_from_messages` takes
/// them), decoded and extracted in Rust at full precision; scans numbered by row.
pub fn extract_messages<'py>(
    extractor: &Extractor,
    py: Python<'py>,
    table: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let batches = crate::messages::message_batches(table)?;
    let built = py.detach(|| -> PyResult<LinesTable> {
        let mut w = extractor.working();
        let mut out = LinesTable::new();
        let mut row = 0u64;
        for batch in &batches {
            for i in 0..batch.num_rows() {
                let record = crate::messages::scan_of_row(batch, i).map_err(value_error)?;
                out.push(&mut w, row, &record).map_err(value_error)?;
                row += 1;
                let checked;
                (w, checked) = check_signals(extractor, w, row);
                checked?;
            }
        }
        Ok(out)
    });
    built?.into_pyarrow(py)
}

/// The lines of every scan of the file `path`, scans numbered from 0 in file order.
pub fn extract_path<'py>(
    extractor: &Extractor,
    py: Python<'py>,
    path: &Path,
    format: Option<&str>,
    topic: Option<String>,
    skip_bad: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let mut reader = crate::scans::open(path, format, topic)?;
    let built = py.detach(|| -> Result<(LinesTable, u64), PyErr> {
        let mut w = extractor.working();
        let mut out = LinesTable::new();
        let (mut scan, mut skipped) = (0u64, 0u64);
        for item in reader.by_ref() {
            let record = match item {
                Ok(record) => record,
                // A failed read of the file itself is no bad record: it is raised.
                Err(e) if skip_bad && e.is_bad_record() => {
                    skipped += 1;
                    continue;
                }
                Err(e) => return Err(read_error(&e)),
            };
            out.push(&mut w, scan, &record).map_err(value_error)?;
            scan += 1;
            // Ctrl-C (or any signal handler's exception) ends a long file between scans.
            let checked;
            (w, checked) = check_signals(extractor, w, scan);
            checked?;
        }
        Ok((out, skipped))
    });
    let (table, skipped) = built?;
    if skipped > 0 {
        // Skipped records are reported, as the command line reports them.
        let message = format!(
            "{}: skipped {skipped} bad record{} ({})",
            reader.name(),
            if skipped == 1 { "" } else { "s" },
            reader.skipped()
        );
        let message = std::ffi::CString::new(message).map_err(value_error)?;
        let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
        PyErr::warn(py, &category, &message, 1)?;
    }
    table.into_pyarrow(py)
}

/// The lines of every scan of the file `path` as a `pyarrow.Table` (one row per line, with
/// the scan's index, stamp and pose), with a fresh extractor of `algorithm`.
#[pyfunction]
#[pyo3(signature = (path, topic = None, algorithm = "hough-split", skip_bad = false, format = None, **params))]
pub fn extract_file<'py>(
    py: Python<'py>,
    path: crate::args::FsPath,
    topic: Option<String>,
    algorithm: &str,
    skip_bad: bool,
    format: Option<&str>,
    params: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyAny>> {
    let extractor = Extractor::build(algorithm, kwargs::to_table(params)?)?;
    extract_path(&extractor, py, &path.0, format, topic, skip_bad)
}

/// The schema of the lines table (`extract -o lines.parquet`, `extract_file`).
#[pyfunction]
#[pyo3(name = "lines_schema")]
pub fn lines_schema_py(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    lines_schema().as_ref().to_pyarrow(py)
}

/// The schema of the scans table (`convert LOG scans.parquet`).
#[pyfunction]
#[pyo3(name = "scans_schema")]
pub fn scans_schema_py(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    scans_schema().as_ref().to_pyarrow(py)
}
