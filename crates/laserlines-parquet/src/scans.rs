//! The scans table: one row per scan ([`crate::schema::scans_schema`]), filled record by
//! record ([`ScansColumns`]) and written to Parquet ([`ScansParquetWriter`]). Every number
//! keeps all 64 bits, ranges and intensities too: a scan read back is the scan written, so a
//! log and its Parquet conversion give the same lines.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;
use std::sync::Arc;

use arrow_array::{ArrayRef, Float64Array, Int64Array, ListArray, RecordBatch};
use arrow_buffer::{BooleanBuffer, NullBuffer, OffsetBuffer, ScalarBuffer};
use arrow_schema::{ArrowError, DataType, Field};
use laserlines_io::{ScanRecord, WriteError};

use crate::schema::scans_schema;
use crate::table::{TableWriter, io_error};

/// Scans per batch handed to the Parquet writer.
const BATCH_ROWS: usize = 1024;
/// Scans per row group (4096 scans of 1081 beams: about 35 MB before compression).
const ROW_GROUP: usize = 4096;

/// A `list<float64>` column being filled.
#[derive(Debug, Clone)]
struct F64Lists {
    offsets: Vec<i32>,
    values: Vec<f64>,
    valid: Vec<bool>,
}

impl Default for F64Lists {
    fn default() -> Self {
        Self {
            offsets: vec![0],
            values: Vec::new(),
            valid: Vec::new(),
        }
    }
}

impl F64Lists {
    /// Appends one list (`None`: a null list). More than `i32::MAX` values in all are an
    /// error, and change nothing.
    fn push(&mut self, list: Option<&[f64]>) -> Result<(), ArrowError> {
        let n = list.map_or(0, <[f64]>::len);
        let end = i32::try_from(self.values.len() + n).map_err(|_| {
            ArrowError::ComputeError("more than 2^31 values in one batch".to_owned())
        })?;
        if let Some(list) = list {
            self.values.extend_from_slice(list);
        }
        self.offsets.push(end);
        self.valid.push(list.is_some());
        Ok(())
    }

    fn into_array(self) -> ArrayRef {
        let nulls = if self.valid.iter().all(|&v| v) {
            None
        } else {
            Some(NullBuffer::new(BooleanBuffer::from(self.valid)))
        };
        let item = Arc::new(Field::new("item", DataType::Float64, true));
        let offsets = OffsetBuffer::new(ScalarBuffer::from(self.offsets));
        let values = Arc::new(Float64Array::from(self.values));
        Arc::new(ListArray::new(item, offsets, values, nulls))
    }
}

/// The columns of the scans table, filled record by record, taken as a [`RecordBatch`].
#[derive(Debug, Default, Clone)]
pub struct ScansColumns {
    scan: Vec<i64>,
    stamp: Vec<Option<f64>>,
    pose: [Vec<Option<f64>>; 3],
    odometry: [Vec<Option<f64>>; 3],
    /// angle_min, angle_increment, range_min, range_max.
    geometry: [Vec<f64>; 4],
    ranges: F64Lists,
    intensities: F64Lists,
}

impl ScansColumns {
    /// No rows.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of rows (scans) so far.
    #[must_use]
    pub fn len(&self) -> usize {
        self.scan.len()
    }

    /// True when there is no row.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.scan.is_empty()
    }

    /// Adds the record as scan number `scan` (0-based).
    ///
    /// # Errors
    /// An [`ArrowError`] when the batch would hold more than 2^31 ranges.
    pub fn push(&mut self, scan: u64, record: &ScanRecord) -> Result<(), ArrowError> {
        let s = &record.scan;
        self.ranges.push(Some(&s.ranges))?;
        self.intensities.push(s.intensities.as_deref())?;
        self.scan.push(i64::try_from(scan).unwrap_or(i64::MAX));
        self.stamp.push(s.stamp);
        for (columns, pose) in [
            (&mut self.pose, record.pose),
            (&mut self.odometry, record.odometry),
        ] {
            let pose = pose.map(|p| [p.x, p.y, p.theta]);
            for (k, column) in columns.iter_mut().enumerate() {
                column.push(pose.map(|p| p[k]));
            }
        }
        let geometry = [s.angle_min, s.angle_increment, s.range_min, s.range_max];
        for (column, v) in self.geometry.iter_mut().zip(geometry) {
            column.push(v);
        }
        Ok(())
    }

    /// The rows so far as a batch of [`crate::schema::scans_schema`]; the columns are left
    /// empty.
    ///
    /// # Errors
    /// An [`ArrowError`] only if the columns disagreed with the schema (a defect).
    pub fn take_batch(&mut self) -> Result<RecordBatch, ArrowError> {
        let taken = std::mem::take(self);
        let opt = |v: Vec<Option<f64>>| Arc::new(Float64Array::from(v)) as ArrayRef;
        let mut columns: Vec<ArrayRef> =
            vec![Arc::new(Int64Array::from(taken.scan)), opt(taken.stamp)];
        columns.extend(taken.pose.map(opt));
        columns.extend(taken.odometry.map(opt));
        columns.extend(
            taken
                .geometry
                .map(|v| Arc::new(Float64Array::from(v)) as ArrayRef),
        );
        columns.push(taken.ranges.into_array());
        columns.push(taken.intensities.into_array());
        RecordBatch::try_new(scans_schema(), columns)
    }
}

/// Writes scans to a Parquet file of [`crate::schema::scans_schema`], in batches, so that
/// memory stays bounded on any log.
#[derive(Debug)]
pub struct ScansParquetWriter<W: Write + Send> {
    table: TableWriter<W>,
    columns: ScansColumns,
    count: u64,
}

impl ScansParquetWriter<BufWriter<File>> {
    /// Creates the file `path`.
    ///
    /// # Errors
    /// [`WriteError::Io`] when the file cannot be created.
    pub fn create(path: &Path) -> Result<Self, WriteError> {
        Ok(Self {
            table: TableWriter::create(path, scans_schema(), ROW_GROUP)?,
            columns: ScansColumns::new(),
            count: 0,
        })
    }
}

impl<W: Write + Send> ScansParquetWriter<W> {
    /// Writes to `out`, named `name` in errors.
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn new(out: W, name: &str) -> Result<Self, WriteError> {
        Ok(Self {
            table: TableWriter::new(out, name, scans_schema(), ROW_GROUP)?,
            columns: ScansColumns::new(),
            count: 0,
        })
    }

    /// Writes one scan; scans are numbered from 0 in the order written.
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn write(&mut self, record: &ScanRecord) -> Result<(), WriteError> {
        self.columns
            .push(self.count, record)
            .map_err(|e| io_error(self.table.name(), e))?;
        self.count += 1;
        if self.columns.len() >= BATCH_ROWS {
            self.flush_batch()?;
        }
        Ok(())
    }

    fn flush_batch(&mut self) -> Result<(), WriteError> {
        let batch = self
            .columns
            .take_batch()
            .map_err(|e| io_error(self.table.name(), e))?;
        self.table.write(&batch)
    }

    /// Writes what is left and the footer; returns the output, flushed.
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn finish(mut self) -> Result<W, WriteError> {
        self.flush_batch()?;
        self.table.finish()
    }
}
