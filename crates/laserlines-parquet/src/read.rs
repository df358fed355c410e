//! Reading scans back from a Parquet table of [`crate::schema::scans_schema`] (or any table
//! with its required columns) as a [`ScanReader`], like every other format: `laserlines
//! extract scans.parquet` and `laserlines.read("scans.parquet")` read it.
//!
//! The file is read one row group after the other, one batch of rows at a time, so memory
//! stays bounded by a row group. A row that is not a valid scan (a null where a number is
//! required, limits out of order) is an error naming the file, the row and the column;
//! reading goes on with the next row. A file that is not Parquet, lacks a column or holds one
//! of another type, or whose metadata places a column chunk outside the file, or one of whose
//! dictionary pages claims more values than its bytes hold ([`crate::dictionary`]), is an
//! error at opening; a page that cannot be decoded is an error naming the first row of its
//! batch, the rest of its row group is counted as lost ([`SKIP_LOST_ROWS`]), and reading goes
//! on with the next row group.

use std::fs::File;
use std::panic::AssertUnwindSafe;
use std::path::Path;
use std::sync::Arc;

use bytes::Bytes;
use laserlines_io::{Format, ReadError, ScanReader, ScanRecord, ScanSource, SkipCounts, SourcePos};
use parquet::arrow::arrow_reader::{
    ArrowReaderMetadata, ArrowReaderOptions, ParquetRecordBatchReader,
    ParquetRecordBatchReaderBuilder,
};
use parquet::file::metadata::ParquetMetaData;
use parquet::file::reader::{ChunkReader, Length};

use crate::columns::{ScanColumns, check_schema};
use crate::dictionary::check_dictionaries;

/// Rows decoded at a time.
const BATCH_ROWS: usize = 1024;

/// Opens the Parquet file `path` as a reader of scans.
///
/// # Errors
/// [`ReadError::Open`] when the file cannot be opened; [`ReadError::Syntax`] when it is not
/// a Parquet file; [`ReadError::Field`] for a missing column or one of another type.
pub fn open(path: &Path) -> Result<ScanReader, ReadError> {
    let name = path.display().to_string();
    let open = |source| ReadError::Open {
        file: name.clone(),
        source,
    };
    let file = File::open(path).map_err(open)?;
    // A second handle, for the check of the dictionary pages before the rows are read.
    let again = file.try_clone().map_err(open)?;
    from_chunks(&name, file, &Arc::new(again))
}

/// Reads scans from a whole Parquet file in memory (standard input, a fuzzer's bytes).
///
/// # Errors
/// As [`open`], but for opening.
pub fn from_bytes(name: &str, bytes: impl Into<Bytes>) -> Result<ScanReader, ReadError> {
    let bytes = bytes.into();
    from_chunks(name, bytes.clone(), &Arc::new(bytes))
}

/// Opens `input` as a reader of scans; `again` is the same input, for
/// [`check_dictionaries`].
fn from_chunks<T: ChunkReader + 'static>(
    name: &str,
    input: T,
    again: &Arc<T>,
) -> Result<ScanReader, ReadError> {
    let not_parquet = |e: parquet::errors::ParquetError| ReadError::Syntax {
        pos: SourcePos::byte(name, 0),
        expected: "a Parquet file".to_owned(),
        found: e.to_string(),
    };
    let file_len = input.len();
    // A gzipped Parquet file (`.parquet.gz`) would only say "corrupt footer".
    if file_len >= 2
        && input
            .get_bytes(0, 2)
            .is_ok_and(|head| head[..] == [0x1f, 0x8b])
    {
        return Err(ReadError::Syntax {
            pos: SourcePos::byte(name, 0),
            expected: "a Parquet file".to_owned(),
            found: "gzip-compressed data (Parquet compresses its own pages and is read as \
                    .parquet: gunzip the file first)"
                .to_owned(),
        });
    }
    let input = Shared(Arc::new(input));
    let meta =
        ArrowReaderMetadata::load(&input, ArrowReaderOptions::default()).map_err(not_parquet)?;
    check_chunks(meta.metadata(), file_len).map_err(|(offset, found)| ReadError::Syntax {
        pos: SourcePos::byte(name, offset),
        expected: "column chunks within the file (metadata)".to_owned(),
        found,
    })?;
    check_dictionaries(meta.metadata(), again).map_err(|(offset, found)| ReadError::Syntax {
        pos: SourcePos::byte(name, offset),
        expected: "dictionary pages whose values fit in their bytes".to_owned(),
        found,
    })?;
    check_schema(meta.schema()).map_err(|e| ReadError::Field {
        pos: SourcePos::row(name, 0),
        field: e.column.to_owned(),
        expected: e.expected.to_owned(),
        found: e.found,
    })?;
    // The first row of each row group, and the end of the last.
    let mut group_rows = vec![0u64];
    for group in meta.metadata().row_groups() {
        let end = group_rows[group_rows.len() - 1];
        group_rows.push(end.saturating_add(u64::try_from(group.num_rows()).unwrap_or(0)));
    }
    let source = ParquetScanSource {
        name: name.to_owned(),
        input,
        meta,
        group_rows,
        group: 0,
        batches: None,
        current: None,
        row_in_batch: 0,
        batch_rows: 0,
        row: 0,
    };
    Ok(ScanReader::from_source(
        name,
        Format::Parquet,
        Box::new(source),
    ))
}

/// The input, shared by the readers of its row groups.
struct Shared<T>(Arc<T>);

impl<T> Clone for Shared<T> {
    fn clone(&self) -> Self {
        Self(Arc::clone(&self.0))
    }
}

impl<T: ChunkReader> Length for Shared<T> {
    fn len(&self) -> u64 {
        self.0.len()
    }
}

impl<T: ChunkReader> ChunkReader for Shared<T> {
    type T = T::T;

    fn get_read(&self, start: u64) -> parquet::errors::Result<Self::T> {
        self.0.get_read(start)
    }

    fn get_bytes(&self, start: u64, length: usize) -> parquet::errors::Result<Bytes> {
        self.0.get_bytes(start, length)
    }
}

/// The message of a caught panic.
fn panic_text(panic: &(dyn std::any::Any + Send)) -> String {
    panic
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic".to_owned())
}

/// Checks that every column chunk the metadata names lies within the file (`file_len`
/// bytes): the decoder takes those offsets and sizes on trust, and panics on a negative
/// one. The error gives the chunk's claimed offset (0 when negative) and what is wrong.
fn check_chunks(metadata: &ParquetMetaData, file_len: u64) -> Result<(), (u64, String)> {
    for (g, group) in metadata.row_groups().iter().enumerate() {
        for (c, chunk) in group.columns().iter().enumerate() {
            let start = chunk
                .dictionary_page_offset()
                .unwrap_or_else(|| chunk.data_page_offset());
            let size = chunk.compressed_size();
            let end = u64::try_from(start)
                .ok()
                .zip(u64::try_from(size).ok())
                .and_then(|(a, b)| a.checked_add(b));
            if end.is_none_or(|end| end > file_len) {
                return Err((
                    u64::try_from(start).unwrap_or(0),
                    format!(
                        "row group {g}, column {} ({}): {size} bytes at offset {start} in a file \
                         of {file_len} bytes",
                        c,
                        chunk.column_path()
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// What a batch that cannot be decoded was expected to be.
const READABLE: &str = "a readable row group";

/// The skip reason of the rows of a row group after a batch that could not be decoded (the
/// error names the batch's first row, and counts as that row's bad record; the reader goes on
/// with the next row group), or that its metadata counts but the decoder did not give.
pub const SKIP_LOST_ROWS: &str =
    "scan in a row group that could not be decoded (after the row its error names)";

/// The [`ScanSource`] of a Parquet table, read one row group after the other.
struct ParquetScanSource<T: ChunkReader + 'static> {
    name: String,
    input: Shared<T>,
    meta: ArrowReaderMetadata,
    /// The first row of each row group, and the end of the last.
    group_rows: Vec<u64>,
    /// The next row group to read.
    group: usize,
    /// The batches of the row group being read; `None` between row groups and at the end.
    batches: Option<ParquetRecordBatchReader>,
    current: Option<ScanColumns>,
    row_in_batch: usize,
    batch_rows: usize,
    /// The 0-based row of the table about to be read.
    row: u64,
}

impl<T: ChunkReader + 'static> ParquetScanSource<T> {
    /// The error of a batch that was not what was `expected`, at its first row. The rest of
    /// its row group is counted as lost and reading goes on with the next one.
    fn lost_group(&mut self, expected: &str, found: String, skipped: &mut SkipCounts) -> ReadError {
        self.batches = None;
        self.current = None;
        let end = self.group_rows[self.group];
        // The row the error names is counted with the error (a bad record).
        skipped.add_n(SKIP_LOST_ROWS, end.saturating_sub(self.row + 1));
        let e = ReadError::Syntax {
            pos: SourcePos::row(&self.name, self.row),
            expected: expected.to_owned(),
            found,
        };
        self.row = end;
        e
    }

    /// The batches of the next row group; `None` after the last.
    fn open_group(
        &mut self,
    ) -> Option<Result<ParquetRecordBatchReader, parquet::errors::ParquetError>> {
        if self.group + 1 >= self.group_rows.len() {
            return None;
        }
        // Rows past the end the metadata gives (a decoder that read more) keep their numbers.
        self.row = self.row.max(self.group_rows[self.group]);
        self.group += 1;
        let builder = ParquetRecordBatchReaderBuilder::new_with_metadata(
            self.input.clone(),
            self.meta.clone(),
        );
        Some(
            builder
                .with_row_groups(vec![self.group - 1])
                .with_batch_size(BATCH_ROWS)
                .build(),
        )
    }

    /// Decodes the next batch; `None` at the end, an error when it cannot be decoded.
    fn next_batch(&mut self, skipped: &mut SkipCounts) -> Option<Result<(), ReadError>> {
        loop {
            if self.batches.is_none() {
                match self.open_group()? {
                    Ok(batches) => self.batches = Some(batches),
                    Err(e) => return Some(Err(self.lost_group(READABLE, e.to_string(), skipped))),
                }
            }
            let batches = self.batches.as_mut()?;
            // The `parquet` crate's decoder panics on some malformed pages (a data page that
            // refers to a dictionary the chunk lacks, levels past the page's end) where it
            // should return an error: its panic is caught here and reported as one, and the
            // row group's reader (whose state the panic left undefined) is dropped.
            let next = std::panic::catch_unwind(AssertUnwindSafe(|| batches.next()));
            let batch = match next {
                Ok(None) => {
                    // Rows the metadata gives that the decoder did not: counted as lost.
                    let end = self.group_rows[self.group];
                    skipped.add_n(SKIP_LOST_ROWS, end.saturating_sub(self.row));
                    self.batches = None;
                    continue;
                }
                Ok(Some(Ok(batch))) => batch,
                Ok(Some(Err(e))) => {
                    return Some(Err(self.lost_group(READABLE, e.to_string(), skipped)));
                }
                Err(panic) => {
                    let found = format!("the Parquet decoder failed: {}", panic_text(&*panic));
                    return Some(Err(self.lost_group(READABLE, found, skipped)));
                }
            };
            self.row_in_batch = 0;
            self.batch_rows = batch.num_rows();
            self.current = ScanColumns::of(&batch);
            if self.current.is_none() {
                // The schema was checked at opening: a batch of another schema is a defect
                // of the file or of the decoder, not of one row.
                let found = "a batch of another schema".to_owned();
                return Some(Err(self.lost_group(
                    "rows of the file's schema",
                    found,
                    skipped,
                )));
            }
            return Some(Ok(()));
        }
    }
}

impl<T: ChunkReader + 'static> ScanSource for ParquetScanSource<T> {
    fn next_record(&mut self, skipped: &mut SkipCounts) -> Option<Result<ScanRecord, ReadError>> {
        while self.current.is_none() || self.row_in_batch >= self.batch_rows {
            if let Err(e) = self.next_batch(skipped)? {
                return Some(Err(e));
            }
        }
        let columns = self.current.as_ref()?;
        let item = columns.record(self.row_in_batch, &SourcePos::row(&self.name, self.row));
        self.row_in_batch += 1;
        self.row += 1;
        Some(item)
    }
}
