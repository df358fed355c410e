//! Scans in, lines and scans out: the one place that chooses between the formats of
//! `laserlines-io`, MCAP and Parquet (`laserlines-parquet`), for input ([`open_scans`]) and
//! output ([`LinesOutput`], [`ScanOutput`]) alike. MCAP and Parquet are chosen by the format
//! given, else by the `.mcap` or `.parquet` extension; a directory is a ROS 2 bag (MCAP or
//! sqlite3 storage), as is a `.db3` file.

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use laserlines::Line;
use laserlines_io::{
    Format, LinesWriter, Output, ReadError, ReadOptions, ScanReader, ScanRecord, ScanWriter,
    WriteError,
};
use laserlines_parquet::{LinesParquetWriter, ScansParquetWriter};

use crate::McapReadOptions;
use crate::write::{McapSceneWriter, NOT_GZIPPED};

/// Opens the scans of `path` (`-` for standard input, with a format): an MCAP file, a ROS 2
/// bag directory or a `.db3` file with [`crate::read`], a Parquet table of scans with
/// [`laserlines_parquet::read`], any other format with [`laserlines_io::open_with`].
/// `options.topic` picks the topic (MCAP, ROS bag) or the laser (CARMEN).
///
/// # Errors
/// As the reader of the format: a [`ReadError`] naming the file.
pub fn open_scans(path: &Path, options: &ReadOptions) -> Result<ScanReader, ReadError> {
    let format = match options.format {
        Some(f) => Some(f),
        None if path.is_dir() => Some(Format::Mcap),
        None => Format::from_path(path),
    };
    if format == Some(Format::Db3) && path == Path::new("-") {
        return Err(ReadError::Open {
            file: "-".to_owned(),
            source: std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "a ROS 2 bag in sqlite3 storage is read from its file or directory (SQLite \
                 cannot read a database from standard input)",
            ),
        });
    }
    match format {
        Some(f @ (Format::Mcap | Format::Db3)) => {
            let mcap_options = McapReadOptions {
                db3: f == Format::Db3,
                ..McapReadOptions::topic(options.topic.as_deref())
            };
            crate::read::open(path, &mcap_options)
        }
        Some(Format::Parquet) => open_parquet(path, options),
        _ => laserlines_io::open_with(path, options),
    }
}

/// A Parquet table of scans: one stream (no topic); standard input is read whole.
fn open_parquet(path: &Path, options: &ReadOptions) -> Result<ScanReader, ReadError> {
    let name = path.display().to_string();
    if let Some(topic) = &options.topic {
        return Err(ReadError::Topic {
            file: name,
            topic: topic.clone(),
            expected: "no topic: a Parquet table holds one stream of scans".to_owned(),
        });
    }
    if path != Path::new("-") {
        return laserlines_parquet::read::open(path);
    }
    let mut bytes = Vec::new();
    std::io::Read::read_to_end(&mut std::io::stdin().lock(), &mut bytes).map_err(|source| {
        ReadError::Open {
            file: name.clone(),
            source,
        }
    })?;
    laserlines_parquet::read::from_bytes(&name, bytes)
}

/// `path` when it names an MCAP file to write: `.mcap`, not `.mcap.gz` (as
/// [`McapSceneWriter::create`] refuses it), or an existing device or pipe.
///
/// # Errors
/// [`WriteError::Name`] for any other name.
pub fn mcap_name(path: &Path) -> Result<&Path, WriteError> {
    let ext = |p: &Path| {
        p.extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase()
    };
    // A device or a pipe (`/dev/null`) takes what it is given, whatever its name.
    if ext(path) == "mcap" || is_stream(path) {
        return Ok(path);
    }
    let gzipped_mcap = ext(path) == "gz"
        && path
            .file_stem()
            .is_some_and(|s| ext(Path::new(s)) == "mcap");
    Err(WriteError::Name {
        file: path.display().to_string(),
        expected: if gzipped_mcap {
            NOT_GZIPPED
        } else {
            "an MCAP file named .mcap"
        },
    })
}

/// `path` when it names a Parquet file to write: `.parquet`, not `.parquet.gz` (Parquet
/// compresses its pages itself; a gzipped table is no Parquet file), and not `-` (standard
/// output).
fn parquet_name(path: &Path) -> Result<&Path, WriteError> {
    let gz = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gz"));
    if gz {
        return Err(WriteError::Name {
            file: path.display().to_string(),
            expected: "a Parquet file named .parquet (Parquet compresses its pages itself; \
                       .parquet.gz is not written)",
        });
    }
    if path == Path::new("-") {
        // Its footer, written last, says where every column is: a file, not a stream.
        return Err(WriteError::Io {
            file: "-".to_owned(),
            source: std::io::Error::other("Parquet output must be a file, not standard output"),
        });
    }
    Ok(path)
}

/// True when `path` exists and is neither a regular file nor a directory: a device, a named
/// pipe or a socket, which stream what they are given and have no extension to go by.
fn is_stream(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.is_file() && !m.is_dir())
}

/// Where `laserlines extract` writes its lines: an MCAP scene ([`McapSceneWriter`]: scan,
/// lines and pose) when the name ends in `.mcap`, a Parquet table of lines
/// ([`LinesParquetWriter`]: one row per line) when it ends in `.parquet`, else lines JSONL
/// ([`LinesWriter`]).
#[derive(Debug)]
pub enum LinesOutput {
    /// Lines JSONL (`-` = standard output, `.gz` = gzip).
    Jsonl(Box<LinesWriter<Output>>),
    /// An MCAP file that Foxglove plays.
    Mcap(Box<McapSceneWriter<BufWriter<File>>>),
    /// A Parquet table, one row per line.
    Parquet(Box<LinesParquetWriter<BufWriter<File>>>),
}

impl LinesOutput {
    /// Creates the output named `path`, choosing the kind by its extension: `.mcap` for
    /// MCAP, `.parquet` for Parquet, `.jsonl` or `.ndjson` (optionally `.gz`) or `-` (standard
    /// output) for lines JSONL; lines JSONL too for an existing file that is neither a
    /// regular file nor a directory, whatever its name (`/dev/null`, a named pipe,
    /// `/dev/stdout`, a shell's `>(...)`).
    ///
    /// # Errors
    /// [`WriteError::Io`] when the file cannot be created, [`WriteError::Name`] for
    /// any other extension (a lines file named `.txt` or `.json` would be mistaken for
    /// something else) and for `.mcap.gz` (see [`McapSceneWriter::create`]).
    pub fn create(path: &Path) -> Result<Self, WriteError> {
        if path == Path::new("-") || is_stream(path) {
            return Ok(Self::Jsonl(Box::new(LinesWriter::create(path)?)));
        }
        Self::check_name(path)?;
        match Format::from_path(path) {
            Some(Format::Mcap) => Ok(Self::Mcap(Box::new(McapSceneWriter::create(path)?))),
            Some(Format::Parquet) => Ok(Self::Parquet(Box::new(LinesParquetWriter::create(
                parquet_name(path)?,
            )?))),
            _ => Ok(Self::Jsonl(Box::new(LinesWriter::create(path)?))),
        }
    }

    /// The [`WriteError::Name`] that [`LinesOutput::create`] gives `path`, without creating
    /// anything: for a command to refuse a name before it starts its work (opens a sensor).
    ///
    /// # Errors
    /// As [`LinesOutput::create`]'s name errors.
    pub fn check_name(path: &Path) -> Result<(), WriteError> {
        if path == Path::new("-") || is_stream(path) {
            return Ok(());
        }
        match Format::from_path(path) {
            Some(Format::Mcap) => mcap_name(path).map(|_| ()),
            Some(Format::Parquet) => parquet_name(path).map(|_| ()),
            Some(Format::Jsonl) => Ok(()),
            _ => Err(WriteError::Name {
                file: path.display().to_string(),
                expected: "lines JSONL (.jsonl, .jsonl.gz, or - for standard output), MCAP \
                           (.mcap) or Parquet (.parquet)",
            }),
        }
    }

    /// Writes the lines of scan number `scan` (0-based, in input order) with its record.
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn write_record(
        &mut self,
        scan: u64,
        record: &ScanRecord,
        lines: &[Line],
    ) -> Result<(), WriteError> {
        match self {
            Self::Jsonl(w) => w.write_record(scan, record, lines),
            Self::Mcap(w) => w.write_lines(record, lines),
            Self::Parquet(w) => w.write_record(scan, record, lines),
        }
    }

    /// Completes the output (MCAP summary, end of a gzip stream) and flushes it.
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn close(self) -> Result<(), WriteError> {
        match self {
            Self::Jsonl(w) => w.close(),
            Self::Mcap(w) => w.finish().map(|_| ()),
            Self::Parquet(w) => w.finish().map(|_| ()),
        }
    }
}

/// Where `laserlines convert` writes scans: an MCAP scene ([`McapSceneWriter`]: `/scan` and
/// `/tf`) for the format `mcap` or the `.mcap` extension, a Parquet table of scans
/// ([`ScansParquetWriter`]: one row per scan) for `parquet` or `.parquet`, else a scan file
/// of `laserlines-io` ([`ScanWriter`]: JSON, JSONL, CSV).
#[derive(Debug)]
pub enum ScanOutput {
    /// A scan file (`-` = standard output, `.gz` = gzip).
    Scans(Box<ScanWriter<Output>>),
    /// An MCAP file that Foxglove plays.
    Mcap(Box<McapSceneWriter<BufWriter<File>>>),
    /// A Parquet table, one row per scan.
    Parquet(Box<ScansParquetWriter<BufWriter<File>>>),
}

impl ScanOutput {
    /// Creates the output named `path` in `format` (by its extension when `None`).
    ///
    /// # Errors
    /// [`WriteError`] when the file cannot be created or the format cannot be written.
    pub fn create(path: &Path, format: Option<Format>) -> Result<Self, WriteError> {
        Ok(match format.or_else(|| Format::from_path(path)) {
            Some(Format::Mcap) => Self::Mcap(Box::new(McapSceneWriter::create(path)?)),
            Some(Format::Parquet) => {
                Self::Parquet(Box::new(ScansParquetWriter::create(parquet_name(path)?)?))
            }
            _ => Self::Scans(Box::new(ScanWriter::create(path, format)?)),
        })
    }

    /// Writes one scan.
    ///
    /// # Errors
    /// [`WriteError`] when writing fails.
    pub fn write(&mut self, record: &ScanRecord) -> Result<(), WriteError> {
        match self {
            Self::Mcap(w) => w.write_scan(record),
            Self::Scans(w) => w.write(record),
            Self::Parquet(w) => w.write(record),
        }
    }

    /// Completes the output (MCAP summary, end of a gzip stream) and flushes it.
    ///
    /// # Errors
    /// [`WriteError`] when writing fails.
    pub fn close(self) -> Result<(), WriteError> {
        match self {
            Self::Mcap(w) => w.finish().map(|_| ()),
            Self::Scans(w) => w.close(),
            Self::Parquet(w) => w.finish().map(|_| ()),
        }
    }
}
