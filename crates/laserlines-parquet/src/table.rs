//! Writing record batches to a Parquet file: the one place that sets the file's properties
//! (zstd pages, row group size) and turns the `parquet` crate's errors into [`WriteError`]s
//! naming the file.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use arrow_array::RecordBatch;
use arrow_schema::SchemaRef;
use laserlines_io::WriteError;
use parquet::arrow::ArrowWriter;
use parquet::basic::{Compression, ZstdLevel};
use parquet::file::properties::WriterProperties;

/// A Parquet file being written, batch by batch.
pub struct TableWriter<W: Write + Send> {
    name: String,
    writer: ArrowWriter<W>,
}

impl<W: Write + Send> std::fmt::Debug for TableWriter<W> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TableWriter")
            .field("name", &self.name)
            .finish_non_exhaustive()
    }
}

impl TableWriter<BufWriter<File>> {
    /// Creates the file `path` for tables of `schema`, at most `row_group` rows per row group.
    ///
    /// # Errors
    /// [`WriteError::Io`] when the file cannot be created.
    pub fn create(path: &Path, schema: SchemaRef, row_group: usize) -> Result<Self, WriteError> {
        let name = path.display().to_string();
        let file = File::create(path).map_err(|source| WriteError::Io {
            file: name.clone(),
            source,
        })?;
        Self::new(BufWriter::new(file), &name, schema, row_group)
    }
}

impl<W: Write + Send> TableWriter<W> {
    /// Writes tables of `schema` to `out`, named `name` in errors, at most `row_group` rows
    /// per row group (which bounds the memory a writer holds).
    ///
    /// # Errors
    /// [`WriteError::Io`] when the header cannot be written.
    pub fn new(
        out: W,
        name: &str,
        schema: SchemaRef,
        row_group: usize,
    ) -> Result<Self, WriteError> {
        let props = WriterProperties::builder()
            .set_compression(Compression::ZSTD(ZstdLevel::default()))
            .set_max_row_group_row_count(Some(row_group.max(1)))
            .set_created_by(format!("laserlines {}", env!("CARGO_PKG_VERSION")))
            .build();
        let writer =
            ArrowWriter::try_new(out, schema, Some(props)).map_err(|e| io_error(name, e))?;
        Ok(Self {
            name: name.to_owned(),
            writer,
        })
    }

    /// The file's name, as errors give it.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Writes one batch (of the writer's schema).
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn write(&mut self, batch: &RecordBatch) -> Result<(), WriteError> {
        if batch.num_rows() == 0 {
            return Ok(());
        }
        self.writer
            .write(batch)
            .map_err(|e| io_error(&self.name, e))
    }

    /// Writes the footer and returns the output, flushed.
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn finish(self) -> Result<W, WriteError> {
        let name = self.name;
        let mut out = self.writer.into_inner().map_err(|e| io_error(&name, e))?;
        out.flush().map_err(|source| WriteError::Io {
            file: name.clone(),
            source,
        })?;
        Ok(out)
    }
}

/// A `parquet` or `arrow` error as a [`WriteError`] naming the file.
pub(crate) fn io_error(
    name: &str,
    e: impl std::error::Error + Send + Sync + 'static,
) -> WriteError {
    WriteError::Io {
        file: name.to_owned(),
        source: std::io::Error::other(e),
    }
}
