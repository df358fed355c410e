//! The lines table: one row per line ([`crate::schema::lines_schema`]), filled scan by scan
//! ([`LinesColumns`]) and written to Parquet ([`LinesParquetWriter`]).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;
use std::sync::Arc;

use arrow_array::{ArrayRef, Float64Array, Int64Array, RecordBatch};
use arrow_schema::ArrowError;
use laserlines::Line;
use laserlines_io::{Pose2, ScanRecord, WriteError};

use crate::schema::lines_schema;
use crate::table::{TableWriter, io_error};

/// Lines per batch handed to the Parquet writer.
const BATCH_ROWS: usize = 8192;
/// Lines per row group.
const ROW_GROUP: usize = 64 * 1024;

/// The columns of the lines table, filled scan by scan, taken as a [`RecordBatch`].
#[derive(Debug, Default, Clone)]
pub struct LinesColumns {
    scan: Vec<i64>,
    stamp: Vec<Option<f64>>,
    pose: [Vec<Option<f64>>; 3],
    /// start x, start y, end x, end y, r, alpha.
    geometry: [Vec<f64>; 6],
    /// first, last, points.
    beams: [Vec<i64>; 3],
    /// rms and the covariance's rr, ralpha, alphaalpha.
    fit: [Vec<f64>; 4],
}

impl LinesColumns {
    /// No rows.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of rows (lines) so far.
    #[must_use]
    pub fn len(&self) -> usize {
        self.scan.len()
    }

    /// True when there is no row.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.scan.is_empty()
    }

    /// Adds one row per line of scan number `scan` (0-based), with the scan's stamp and the
    /// robot's pose.
    pub fn push(&mut self, scan: u64, stamp: Option<f64>, pose: Option<Pose2>, lines: &[Line]) {
        let index = i64::try_from(scan).unwrap_or(i64::MAX);
        let pose = pose.map(|p| [p.x, p.y, p.theta]);
        for line in lines {
            self.scan.push(index);
            self.stamp.push(stamp);
            for (k, column) in self.pose.iter_mut().enumerate() {
                column.push(pose.map(|p| p[k]));
            }
            let geometry = [
                line.start.x,
                line.start.y,
                line.end.x,
                line.end.y,
                line.r,
                line.alpha,
            ];
            for (column, v) in self.geometry.iter_mut().zip(geometry) {
                column.push(v);
            }
            let beams = [line.first, line.last, line.points].map(|b| b as i64);
            for (column, v) in self.beams.iter_mut().zip(beams) {
                column.push(v);
            }
            let c = &line.covariance;
            let fit = [line.rms, c[(0, 0)], c[(0, 1)], c[(1, 1)]];
            for (column, v) in self.fit.iter_mut().zip(fit) {
                column.push(v);
            }
        }
    }

    /// Adds the lines of a record read from a log ([`LinesColumns::push`]).
    pub fn push_record(&mut self, scan: u64, record: &ScanRecord, lines: &[Line]) {
        self.push(scan, record.scan.stamp, record.pose, lines);
    }

    /// The rows so far as a batch of [`crate::schema::lines_schema`]; the columns are left
    /// empty.
    ///
    /// # Errors
    /// An [`ArrowError`] only if the columns disagreed with the schema (a defect).
    pub fn take_batch(&mut self) -> Result<RecordBatch, ArrowError> {
        let taken = std::mem::take(self);
        let f64s = |v: Vec<f64>| Arc::new(Float64Array::from(v)) as ArrayRef;
        let opt = |v: Vec<Option<f64>>| Arc::new(Float64Array::from(v)) as ArrayRef;
        let i64s = |v: Vec<i64>| Arc::new(Int64Array::from(v)) as ArrayRef;
        let mut columns = vec![i64s(taken.scan), opt(taken.stamp)];
        columns.extend(taken.pose.map(opt));
        columns.extend(taken.geometry.map(f64s));
        columns.extend(taken.beams.map(i64s));
        columns.extend(taken.fit.map(f64s));
        RecordBatch::try_new(lines_schema(), columns)
    }
}

/// Writes lines to a Parquet file of [`crate::schema::lines_schema`], in batches, so that
/// memory stays bounded on any log.
#[derive(Debug)]
pub struct LinesParquetWriter<W: Write + Send> {
    table: TableWriter<W>,
    columns: LinesColumns,
}

impl LinesParquetWriter<BufWriter<File>> {
    /// Creates the file `path`.
    ///
    /// # Errors
    /// [`WriteError::Io`] when the file cannot be created.
    pub fn create(path: &Path) -> Result<Self, WriteError> {
        Ok(Self {
            table: TableWriter::create(path, lines_schema(), ROW_GROUP)?,
            columns: LinesColumns::new(),
        })
    }
}

impl<W: Write + Send> LinesParquetWriter<W> {
    /// Writes to `out`, named `name` in errors.
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn new(out: W, name: &str) -> Result<Self, WriteError> {
        Ok(Self {
            table: TableWriter::new(out, name, lines_schema(), ROW_GROUP)?,
            columns: LinesColumns::new(),
        })
    }

    /// Writes the lines of scan number `scan` (0-based, in input order) with its record's
    /// stamp and pose. A scan without lines adds no row.
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn write_record(
        &mut self,
        scan: u64,
        record: &ScanRecord,
        lines: &[Line],
    ) -> Result<(), WriteError> {
        self.columns.push_record(scan, record, lines);
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
