//! Writers: extracted lines as JSONL, and scans as JSON, JSONL or CSV.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use laserlines::Line;

use crate::error::WriteError;
use crate::format::{Format, has_gz_extension};
use crate::lines::{LineRecord, ScanLines};
use crate::record::{Pose2, ScanRecord};

/// An output opened by name: a file (gzipped when the name ends in `.gz`) or standard
/// output (`-`). Call [`Output::finish`] (or the writers' `close`) to complete it and see
/// any error.
pub struct Output {
    inner: OutputInner,
}

enum OutputInner {
    Plain(BufWriter<File>),
    Gzip(Box<flate2::write::GzEncoder<BufWriter<File>>>),
    Stdout(BufWriter<io::Stdout>),
}

impl std::fmt::Debug for Output {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kind = match self.inner {
            OutputInner::Plain(_) => "file",
            OutputInner::Gzip(_) => "gzip file",
            OutputInner::Stdout(_) => "standard output",
        };
        f.debug_struct("Output").field("kind", &kind).finish()
    }
}

impl Output {
    /// Creates `path` (`-` = standard output); names ending in `.gz` are gzip-compressed.
    ///
    /// # Errors
    /// The error of creating the file.
    pub fn create(path: &Path) -> io::Result<Self> {
        let inner = if path == Path::new("-") {
            OutputInner::Stdout(BufWriter::new(io::stdout()))
        } else {
            let file = BufWriter::with_capacity(1 << 16, File::create(path)?);
            if has_gz_extension(path) {
                OutputInner::Gzip(Box::new(flate2::write::GzEncoder::new(
                    file,
                    flate2::Compression::default(),
                )))
            } else {
                OutputInner::Plain(file)
            }
        };
        Ok(Self { inner })
    }

    /// Flushes everything (and ends the gzip stream).
    ///
    /// # Errors
    /// Any write error.
    pub fn finish(self) -> io::Result<()> {
        match self.inner {
            OutputInner::Plain(mut w) => w.flush(),
            OutputInner::Gzip(w) => w.finish()?.flush(),
            OutputInner::Stdout(mut w) => w.flush(),
        }
    }
}

impl Write for Output {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match &mut self.inner {
            OutputInner::Plain(w) => w.write(buf),
            OutputInner::Gzip(w) => w.write(buf),
            OutputInner::Stdout(w) => w.write(buf),
        }
    }

    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        match &mut self.inner {
            OutputInner::Plain(w) => w.write_all(buf),
            OutputInner::Gzip(w) => w.write_all(buf),
            OutputInner::Stdout(w) => w.write_all(buf),
        }
    }

    fn flush(&mut self) -> io::Result<()> {
        match &mut self.inner {
            OutputInner::Plain(w) => w.flush(),
            OutputInner::Gzip(w) => w.flush(),
            OutputInner::Stdout(w) => w.flush(),
        }
    }
}

/// Writes the lines JSONL schema ([`crate::lines`]): one object per scan,
/// `{"scan": k, "stamp": s, "pose": {..}, "odometry": {..}, "lines": [..]}`, with `stamp`,
/// `pose` and `odometry` only when known.
pub struct LinesWriter<W: Write> {
    out: W,
    name: String,
    records: Vec<LineRecord>,
    buf: Vec<u8>,
}

impl<W: Write> std::fmt::Debug for LinesWriter<W> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LinesWriter")
            .field("name", &self.name)
            .finish_non_exhaustive()
    }
}

impl<W: Write> LinesWriter<W> {
    /// A writer into `out`, named `output` in messages.
    pub fn new(out: W) -> Self {
        Self::with_name(out, "output")
    }

    /// A writer into `out`, named `name` in messages.
    pub fn with_name(out: W, name: &str) -> Self {
        Self {
            out,
            name: name.to_owned(),
            records: Vec::new(),
            buf: Vec::new(),
        }
    }

    fn io(&self, source: io::Error) -> WriteError {
        WriteError::Io {
            file: self.name.clone(),
            source,
        }
    }

    /// Writes the lines of scan number `scan` (0-based, in input order), with its stamp (s)
    /// and the robot's pose when known.
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn write_scan(
        &mut self,
        scan: u64,
        stamp: Option<f64>,
        pose: Option<Pose2>,
        lines: &[Line],
    ) -> Result<(), WriteError> {
        self.write_encoded(scan, stamp, (pose, None), lines)
    }

    /// Encodes scan number `scan` with its stamp, pose and odometry into the reused buffers
    /// and writes it.
    fn write_encoded(
        &mut self,
        scan: u64,
        stamp: Option<f64>,
        poses: (Option<Pose2>, Option<Pose2>),
        lines: &[Line],
    ) -> Result<(), WriteError> {
        let mut records = std::mem::take(&mut self.records);
        let mut buf = std::mem::take(&mut self.buf);
        buf.clear();
        let encoded = encode_scan_lines(scan, stamp, poses, lines, &mut records, &mut buf);
        let written = encoded.and_then(|()| self.out.write_all(&buf));
        self.records = records;
        self.buf = buf;
        written.map_err(|e| self.io(e))
    }

    /// Writes scan number `scan` from what [`encode_unnumbered`] made of it (e.g. on another
    /// thread, before the scan's number was known): the same bytes as
    /// [`LinesWriter::write_record`].
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails, or when `unnumbered` does not start with `{`.
    pub fn write_numbered(&mut self, scan: u64, unnumbered: &[u8]) -> Result<(), WriteError> {
        let Some(rest) = unnumbered.strip_prefix(b"{") else {
            return Err(self.io(io::Error::new(
                io::ErrorKind::InvalidInput,
                "not an object made by encode_unnumbered",
            )));
        };
        write!(self.out, "{{\"scan\":{scan},")
            .and_then(|()| self.out.write_all(rest))
            .map_err(|e| self.io(e))
    }

    /// Writes the lines of scan number `scan`, taking the stamp, pose and odometry from its
    /// record.
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn write_record(
        &mut self,
        scan: u64,
        record: &ScanRecord,
        lines: &[Line],
    ) -> Result<(), WriteError> {
        let poses = (record.pose, record.odometry);
        self.write_encoded(scan, record.scan.stamp, poses, lines)
    }

    /// Flushes and returns the inner writer.
    ///
    /// # Errors
    /// [`WriteError::Io`] when flushing fails.
    pub fn finish(mut self) -> Result<W, WriteError> {
        self.out.flush().map_err(|e| self.io(e))?;
        Ok(self.out)
    }
}

/// Appends to `buf` the JSONL line of a scan without its number, `{"stamp":..,"pose":..,
/// "lines":[..]}` and a newline, for [`LinesWriter::write_numbered`]: so that callers encode
/// scans on several threads before knowing which number each gets (bad records skipped
/// before it do not count), and write them in order.
///
/// # Errors
/// An error of the JSON encoder (none is expected for these types).
pub fn encode_unnumbered(record: &ScanRecord, lines: &[Line], buf: &mut Vec<u8>) -> io::Result<()> {
    /// [`ScanLines`] without `scan`.
    #[derive(serde::Serialize)]
    struct Unnumbered<'a> {
        #[serde(skip_serializing_if = "Option::is_none")]
        stamp: Option<f64>,
        #[serde(skip_serializing_if = "Option::is_none")]
        pose: Option<Pose2>,
        #[serde(skip_serializing_if = "Option::is_none")]
        odometry: Option<Pose2>,
        lines: &'a [LineRecord],
    }
    let records: Vec<LineRecord> = lines.iter().map(LineRecord::from).collect();
    let object = Unnumbered {
        stamp: record.scan.stamp,
        pose: record.pose,
        odometry: record.odometry,
        lines: &records,
    };
    serde_json::to_writer(&mut *buf, &object).map_err(io::Error::other)?;
    buf.push(b'\n');
    Ok(())
}

fn encode_scan_lines(
    scan: u64,
    stamp: Option<f64>,
    (pose, odometry): (Option<Pose2>, Option<Pose2>),
    lines: &[Line],
    records: &mut Vec<LineRecord>,
    buf: &mut Vec<u8>,
) -> io::Result<()> {
    records.clear();
    records.extend(lines.iter().map(LineRecord::from));
    let object = ScanLines {
        scan,
        stamp,
        pose,
        odometry,
        lines: std::mem::take(records),
    };
    let serialized = serde_json::to_writer(&mut *buf, &object);
    *records = object.lines;
    serialized.map_err(io::Error::other)?;
    buf.push(b'\n');
    Ok(())
}

impl LinesWriter<Output> {
    /// Creates a lines JSONL file (`-` = standard output, `.gz` = gzip).
    ///
    /// # Errors
    /// [`WriteError::Io`] when the file cannot be created.
    pub fn create(path: &Path) -> Result<Self, WriteError> {
        let name = path.display().to_string();
        let out = Output::create(path).map_err(|source| WriteError::Io {
            file: name.clone(),
            source,
        })?;
        Ok(Self::with_name(out, &name))
    }

    /// Flushes and completes the output (ends a gzip stream).
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn close(self) -> Result<(), WriteError> {
        let name = self.name.clone();
        self.finish()?
            .finish()
            .map_err(|source| WriteError::Io { file: name, source })
    }
}

/// Writes scans as JSON, JSONL or CSV (see [`crate::json`] and [`crate::csv`] for the
/// layouts), so that formats can be converted.
///
/// - JSONL: one object per line.
/// - JSON: a single object when one scan was written, else a top-level array with one
///   object per line (`[]` for none). The layout is decided at [`ScanWriter::finish`], so
///   call it (or [`ScanWriter::close`]); dropping the writer finishes it too but cannot report
///   errors.
/// - CSV: one scan per file; the range limits, stamp, pose and odometry go into `# key: value`
///   comments, intensities into a fourth column. A second scan is an error.
///
/// Ranges read back as they were: a NaN one ("no return") as `null` (JSON) or `nan` (CSV),
/// an infinite one (REP 117's "nothing within range", "too near") as `Infinity` and
/// `-Infinity` (JSON, as Python's `json.dump` writes them) or `inf` and `-inf` (CSV).
pub struct ScanWriter<W: Write> {
    out: Option<W>,
    name: String,
    format: Format,
    count: usize,
    /// JSON: the first object, held until we know whether an array is needed.
    pending: Option<Vec<u8>>,
    buf: Vec<u8>,
}

impl<W: Write> std::fmt::Debug for ScanWriter<W> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ScanWriter")
            .field("name", &self.name)
            .field("format", &self.format)
            .field("count", &self.count)
            .finish_non_exhaustive()
    }
}

impl<W: Write> ScanWriter<W> {
    /// A writer of `format` into `out`, named `output` in messages.
    ///
    /// # Errors
    /// [`WriteError::Unsupported`] for formats that cannot be written
    /// ([`Format::is_writable`]).
    pub fn new(out: W, format: Format) -> Result<Self, WriteError> {
        Self::with_name(out, "output", format)
    }

    /// A writer of `format` into `out`, named `name` in messages.
    ///
    /// # Errors
    /// [`WriteError::Unsupported`] for formats that cannot be written.
    pub fn with_name(out: W, name: &str, format: Format) -> Result<Self, WriteError> {
        if !format.is_writable() {
            return Err(WriteError::Unsupported {
                file: name.to_owned(),
                format: format.name(),
            });
        }
        Ok(Self {
            out: Some(out),
            name: name.to_owned(),
            format,
            count: 0,
            pending: None,
            buf: Vec::new(),
        })
    }

    /// Number of scans written.
    #[must_use]
    pub fn count(&self) -> usize {
        self.count
    }

    fn io(&self, source: io::Error) -> WriteError {
        WriteError::Io {
            file: self.name.clone(),
            source,
        }
    }

    fn emit(&mut self, bytes: &[u8]) -> Result<(), WriteError> {
        match self.out.as_mut() {
            Some(out) => out.write_all(bytes).map_err(|e| WriteError::Io {
                file: self.name.clone(),
                source: e,
            }),
            None => Err(self.io(io::Error::other("writer already finished"))),
        }
    }

    /// Writes one scan (with its stamp and pose).
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails; [`WriteError::OneScanPerFile`] for a second
    /// CSV scan.
    pub fn write(&mut self, record: &ScanRecord) -> Result<(), WriteError> {
        self.count += 1;
        let mut buf = std::mem::take(&mut self.buf);
        buf.clear();
        let result = self.write_inner(record, &mut buf);
        self.buf = buf;
        result
    }

    fn write_inner(&mut self, record: &ScanRecord, buf: &mut Vec<u8>) -> Result<(), WriteError> {
        match self.format {
            Format::Jsonl => {
                crate::json::write_scan(buf, record).map_err(|e| self.io(e))?;
                buf.push(b'\n');
                self.emit(buf)
            }
            Format::Json => {
                crate::json::write_scan(buf, record).map_err(|e| self.io(e))?;
                if self.count == 1 {
                    self.pending = Some(buf.clone());
                    Ok(())
                } else {
                    if let Some(first) = self.pending.take() {
                        self.emit(b"[\n")?;
                        self.emit(&first)?;
                    }
                    self.emit(b",\n")?;
                    self.emit(buf)
                }
            }
            Format::Csv => {
                if self.count > 1 {
                    return Err(WriteError::OneScanPerFile {
                        file: self.name.clone(),
                        format: "csv",
                        count: self.count,
                    });
                }
                write_csv(buf, record).map_err(|e| self.io(e))?;
                self.emit(buf)
            }
            Format::BreezyDat
            | Format::Mcap
            | Format::Carmen
            | Format::Bag
            | Format::Db3
            | Format::Parquet => Err(WriteError::Unsupported {
                file: self.name.clone(),
                format: self.format.name(),
            }),
        }
    }

    fn end(&mut self) -> Result<(), WriteError> {
        if self.format == Format::Json {
            if let Some(first) = self.pending.take() {
                self.emit(&first)?;
                self.emit(b"\n")?;
            } else if self.count == 0 {
                self.emit(b"[]\n")?;
            } else {
                self.emit(b"\n]\n")?;
            }
        }
        match self.out.as_mut() {
            Some(out) => out.flush().map_err(|e| WriteError::Io {
                file: self.name.clone(),
                source: e,
            }),
            None => Ok(()),
        }
    }

    /// Completes the layout, flushes and returns the inner writer.
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn finish(mut self) -> Result<W, WriteError> {
        if let Err(e) = self.end() {
            self.out = None;
            return Err(e);
        }
        self.out
            .take()
            .ok_or_else(|| self.io(io::Error::other("writer already finished")))
    }
}

impl<W: Write> Drop for ScanWriter<W> {
    fn drop(&mut self) {
        if self.out.is_some() {
            // Best effort: `finish` is the way to see errors.
            let _ = self.end();
        }
    }
}

impl ScanWriter<Output> {
    /// Creates a scan file (`-` = standard output, `.gz` = gzip) in `format`, or in the
    /// format told by the name when `format` is `None`.
    ///
    /// # Errors
    /// [`WriteError::UnknownFormat`], [`WriteError::Unsupported`], or [`WriteError::Io`]
    /// when the file cannot be created.
    pub fn create(path: &Path, format: Option<Format>) -> Result<Self, WriteError> {
        let name = path.display().to_string();
        let format = match format.or_else(|| Format::from_path(path)) {
            Some(f) => f,
            None => return Err(WriteError::UnknownFormat { file: name }),
        };
        if !format.is_writable() {
            return Err(WriteError::Unsupported {
                file: name,
                format: format.name(),
            });
        }
        let out = Output::create(path).map_err(|source| WriteError::Io {
            file: name.clone(),
            source,
        })?;
        Self::with_name(out, &name, format)
    }

    /// Completes the layout and the output (ends a gzip stream).
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn close(self) -> Result<(), WriteError> {
        let name = self.name.clone();
        self.finish()?
            .finish()
            .map_err(|source| WriteError::Io { file: name, source })
    }
}

/// Writes a number so that it reads back exactly (shortest round-trip form).
fn number(out: &mut Vec<u8>, x: f64) -> io::Result<()> {
    if x.is_nan() {
        out.extend_from_slice(b"nan");
        Ok(())
    } else {
        write!(out, "{x:?}")
    }
}

fn write_csv(out: &mut Vec<u8>, record: &ScanRecord) -> io::Result<()> {
    let s = &record.scan;
    out.extend_from_slice(b"# angle_min: ");
    number(out, s.angle_min)?;
    out.extend_from_slice(b"\n# angle_increment: ");
    number(out, s.angle_increment)?;
    out.extend_from_slice(b"\n# range_min: ");
    number(out, s.range_min)?;
    out.extend_from_slice(b"\n# range_max: ");
    number(out, s.range_max)?;
    out.push(b'\n');
    if let Some(stamp) = s.stamp {
        out.extend_from_slice(b"# stamp: ");
        number(out, stamp)?;
        out.push(b'\n');
    }
    for (pose, keys) in [
        (record.pose, ["pose_x", "pose_y", "pose_theta"]),
        (
            record.odometry,
            ["odometry_x", "odometry_y", "odometry_theta"],
        ),
    ] {
        if let Some(p) = pose {
            for (key, v) in keys.into_iter().zip([p.x, p.y, p.theta]) {
                write!(out, "# {key}: ")?;
                number(out, v)?;
                out.push(b'\n');
            }
        }
    }
    let intensities = s.intensities.as_deref();
    out.extend_from_slice(if intensities.is_some() {
        crate::csv::HEADER_WITH_INTENSITY.as_bytes()
    } else {
        crate::csv::HEADER.as_bytes()
    });
    out.push(b'\n');
    for (i, &r) in s.ranges.iter().enumerate() {
        write!(out, "{i},")?;
        number(out, s.angle(i))?;
        out.push(b',');
        number(out, r)?;
        if let Some(int) = intensities {
            out.push(b',');
            number(out, int.get(i).copied().unwrap_or(f64::NAN))?;
        }
        out.push(b'\n');
    }
    Ok(())
}
