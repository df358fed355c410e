//! LaserScan messages one per row, as Ray Data's `read_mcap` gives them (`data`,
//! `schema_name`, `message_encoding`, `log_time` in ns), decoded into a table of scans.

use arrow_array::cast::AsArray;
use arrow_array::types::{Int64Type, UInt64Type};
use arrow_array::{Array, ArrayRef, RecordBatch};
use arrow_pyarrow::{IntoPyArrow, Table};
use arrow_schema::DataType;
use laserlines_foxglove::ScanEncoding;
use laserlines_foxglove::message::SCAN_ENCODINGS;
use laserlines_foxglove::message::decode_scan;
use laserlines_foxglove::proto::RangeLimits;
use laserlines_io::ScanRecord;
use laserlines_parquet::{ScansColumns, scans_schema};
use pyo3::prelude::*;

use crate::errors::value_error;

/// Bytes or text of a column at a row, whatever its Arrow type of bytes or strings.
fn bytes_at(column: &ArrayRef, row: usize) -> Option<&[u8]> {
    if column.is_null(row) {
        return None;
    }
    Some(match column.data_type() {
        DataType::Binary => column.as_binary::<i32>().value(row),
        DataType::LargeBinary => column.as_binary::<i64>().value(row),
        DataType::BinaryView => column.as_binary_view().value(row),
        DataType::Utf8 => column.as_string::<i32>().value(row).as_bytes(),
        DataType::LargeUtf8 => column.as_string::<i64>().value(row).as_bytes(),
        DataType::Utf8View => column.as_string_view().value(row).as_bytes(),
        _ => return None,
    })
}

/// Nanoseconds of an integer column at a row, as seconds.
fn seconds_at(column: Option<&ArrayRef>, row: usize) -> f64 {
    let Some(c) = column.filter(|c| c.is_valid(row)) else {
        return 0.0;
    };
    let ns = match c.data_type() {
        DataType::Int64 => c.as_primitive::<Int64Type>().value(row) as f64,
        DataType::UInt64 => c.as_primitive::<UInt64Type>().value(row) as f64,
        _ => 0.0,
    };
    ns * 1e-9
}

/// The scan of row `row` of a batch of messages.
pub fn scan_of_row(batch: &RecordBatch, row: usize) -> Result<ScanRecord, String> {
    let column = |name: &str| {
        batch.column_by_name(name).ok_or_else(|| {
            format!("messages: no column {name} (read_mcap(..., include_metadata=True) gives it)")
        })
    };
    let text = |name: &str| -> Result<String, String> {
        let bytes = bytes_at(column(name)?, row).ok_or_else(|| {
            format!("messages: row {row}: {name}: expected text, found null or another type")
        })?;
        Ok(String::from_utf8_lossy(bytes).into_owned())
    };
    let (schema, encoding) = (text("schema_name")?, text("message_encoding")?);
    let kind = ScanEncoding::of_channel(&schema, &encoding).ok_or_else(|| {
        format!(
            "messages: row {row}: {schema} in {encoding} is not a LaserScan ({SCAN_ENCODINGS}); \
             read_mcap(topics=...) picks the scans"
        )
    })?;
    let data = bytes_at(column("data")?, row).ok_or_else(|| {
        format!("messages: row {row}: data: expected bytes, found null or another type")
    })?;
    let log_seconds = seconds_at(batch.column_by_name("log_time"), row);
    let scan = decode_scan(kind, RangeLimits::default(), data, log_seconds)
        .map_err(|e| format!("messages: row {row}: {schema} message: {e}"))?;
    scan.validate()
        .map_err(|e| format!("messages: row {row}: invalid scan: {e}"))?;
    Ok(ScanRecord::new(scan))
}

/// The batches of a table of messages (anything with `__arrow_c_stream__`).
pub fn message_batches(table: &Bound<'_, PyAny>) -> PyResult<Vec<RecordBatch>> {
    let reader = crate::tables::arrow_stream(table, "a table of LaserScan messages")?;
    reader.collect::<Result<_, _>>().map_err(value_error)
}

/// A table of LaserScan messages (Ray Data's `read_mcap` with `include_metadata=True`:
/// `data`, `schema_name`, `message_encoding`, `log_time`) as a `pyarrow.Table` of the scans
/// schema, scans numbered by row. `foxglove.LaserScan` has no range limits of its own: they
/// become 0 and its largest range (its channel's metadata is not in the rows), which keeps
/// every range the writer kept.
#[pyfunction]
pub fn scans_from_messages<'py>(
    py: Python<'py>,
    table: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let batches = message_batches(table)?;
    let columns = py.detach(|| -> Result<ScansColumns, String> {
        let mut out = ScansColumns::new();
        let mut k = 0u64;
        for batch in &batches {
            for row in 0..batch.num_rows() {
                let record = scan_of_row(batch, row)?;
                out.push(k, &record).map_err(|e| e.to_string())?;
                k += 1;
            }
        }
        Ok(out)
    });
    let batch = columns
        .map_err(value_error)?
        .take_batch()
        .map_err(value_error)?;
    Table::try_new(vec![batch], scans_schema())
        .map_err(value_error)?
        .into_pyarrow(py)
}
