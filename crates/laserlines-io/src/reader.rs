//! Opening inputs (files, standard input, gzip) and the streaming [`ScanReader`].

use std::fs::File;
use std::io::{self, BufRead, BufReader, Cursor, Read};
use std::path::Path;

use crate::error::{ReadError, SourcePos};
use crate::format::{Format, describe_extension, has_gz_extension};
use crate::record::ScanRecord;
use crate::skip::SkipCounts;

/// A boxed, sendable buffered input: what every [`ScanSource`] reads from.
pub type Input = Box<dyn BufRead + Send>;

/// Longest line (or JSON element) a text reader accepts, bytes. Longer input ends the reader
/// with an error instead of exhausting memory.
pub const MAX_LINE_BYTES: usize = 64 * 1024 * 1024;

/// A format's parser behind a [`ScanReader`]: yields records one at a time.
///
/// Each format implements this on top of an [`Input`]. New formats (binary logs, other text
/// logs) slot in by implementing it and wrapping the source with [`ScanReader::from_source`].
pub trait ScanSource: Send {
    /// The next record, `None` at the end of the input.
    ///
    /// After `Some(Err(_))` the reader may be called again: it then goes on with the next
    /// record when the format allows it, or returns `None`. Records skipped by design (not
    /// returned as errors) are counted in `skipped`.
    fn next_record(&mut self, skipped: &mut SkipCounts) -> Option<Result<ScanRecord, ReadError>>;

    /// The next item like [`ScanSource::next_record`], possibly left unparsed so that the
    /// caller can parse it on another thread ([`Pending::parse`]). Formats whose parsing
    /// costs much more than reading (CARMEN text) override it; the default parses at once.
    /// [`Pending::parse`] must give exactly what `next_record` would have given.
    fn next_pending(&mut self, skipped: &mut SkipCounts) -> Option<Pending> {
        self.next_record(skipped).map(Pending::Ready)
    }
}

/// A parser of one record that may run on any thread.
pub type DeferredParse = Box<dyn FnOnce() -> Result<ScanRecord, ReadError> + Send>;

/// An item of [`ScanReader::next_pending`]: a record (or error), or what parses it.
pub enum Pending {
    /// Parsed already.
    Ready(Result<ScanRecord, ReadError>),
    /// Read but not parsed: [`Pending::parse`] parses it, on any thread.
    Deferred(DeferredParse),
}

impl Pending {
    /// The record or error, parsing it now when it was deferred.
    ///
    /// # Errors
    /// The error the format's parser gives for this record.
    pub fn parse(self) -> Result<ScanRecord, ReadError> {
        match self {
            Self::Ready(item) => item,
            Self::Deferred(parse) => parse(),
        }
    }
}

impl std::fmt::Debug for Pending {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Ready(item) => f.debug_tuple("Ready").field(item).finish(),
            Self::Deferred(_) => f.write_str("Deferred"),
        }
    }
}

/// A streaming reader of scans: an iterator of records (or errors) that reads its input
/// piece by piece, so memory stays flat on long inputs.
///
/// It counts what it skipped ([`ScanReader::skipped`]): every bad record it returned as an
/// error ([`ReadError::is_bad_record`]), under [`ReadError::reason`], and anything its format
/// skips by design. A failed read of the input ([`ReadError::Io`]) is returned, not counted:
/// it ends the reader, and is no skip.
pub struct ScanReader {
    name: String,
    format: Format,
    source: Box<dyn ScanSource>,
    skipped: SkipCounts,
    records: u64,
    finished: bool,
}

impl std::fmt::Debug for ScanReader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ScanReader")
            .field("name", &self.name)
            .field("format", &self.format)
            .field("records", &self.records)
            .field("skipped", &self.skipped)
            .field("finished", &self.finished)
            .finish_non_exhaustive()
    }
}

impl ScanReader {
    /// Wraps a format's parser. `name` is the input's name used in messages.
    #[must_use]
    pub fn from_source(name: &str, format: Format, source: Box<dyn ScanSource>) -> Self {
        Self {
            name: name.to_owned(),
            format,
            source,
            skipped: SkipCounts::new(),
            records: 0,
            finished: false,
        }
    }

    /// The input's name as given (a path, or `-`).
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The format being read.
    #[must_use]
    pub fn format(&self) -> Format {
        self.format
    }

    /// What was skipped so far, by reason.
    #[must_use]
    pub fn skipped(&self) -> &SkipCounts {
        &self.skipped
    }

    /// Number of records returned so far (not counting errors, nor items of
    /// [`ScanReader::next_pending`] that were left to parse).
    #[must_use]
    pub fn records(&self) -> u64 {
        self.records
    }

    /// The next item like [`Iterator::next`], but possibly still to parse, so that a caller can
    /// parse records on several threads ([`Pending::parse`]) and keep them in input order.
    ///
    /// Errors of deferred items appear only when they are parsed: they are not in
    /// [`ScanReader::skipped`], and [`ScanReader::records`] does not count deferred records.
    /// The caller counts the bad records among them (e.g. `skipped.add(e.reason())`, then
    /// [`SkipCounts::merge`]).
    pub fn next_pending(&mut self) -> Option<Pending> {
        if self.finished {
            return None;
        }
        let pending = self.source.next_pending(&mut self.skipped);
        match &pending {
            None => self.finished = true,
            Some(Pending::Ready(Ok(_))) => self.records += 1,
            Some(Pending::Ready(Err(e))) if e.is_bad_record() => self.skipped.add(e.reason()),
            Some(Pending::Ready(Err(_))) => {}
            Some(Pending::Deferred(_)) => {}
        }
        pending
    }
}

impl Iterator for ScanReader {
    type Item = Result<ScanRecord, ReadError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.finished {
            return None;
        }
        match self.source.next_record(&mut self.skipped) {
            None => {
                self.finished = true;
                None
            }
            Some(Ok(record)) => {
                self.records += 1;
                Some(Ok(record))
            }
            Some(Err(e)) => {
                if e.is_bad_record() {
                    self.skipped.add(e.reason());
                }
                Some(Err(e))
            }
        }
    }
}

/// How to open an input: the format (told from the name when `None`) and, for formats that
/// hold several streams of scans, which one to read.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ReadOptions {
    /// The format; `None` tells it from the name ([`Format::from_path`]).
    pub format: Option<Format>,
    /// The stream to read, for formats that have several: a ROS bag topic (`/scan`), a
    /// CARMEN laser message (`FLASER`, `RLASER`, `ROBOTLASER1`, `RAWLASER1`, ...). `None`
    /// reads the format's default ([`crate::bag`], [`crate::carmen`]). Formats with a single
    /// stream refuse any topic.
    pub topic: Option<String>,
}

impl ReadOptions {
    /// Options with this format (or `None` to tell it from the name) and no topic.
    #[must_use]
    pub fn format(format: Option<Format>) -> Self {
        Self {
            format,
            topic: None,
        }
    }

    /// The same options reading `topic` (or the default stream when `None`).
    #[must_use]
    pub fn with_topic(mut self, topic: Option<&str>) -> Self {
        self.topic = topic.map(str::to_owned);
        self
    }
}

/// Opens a scan file, gzipped or not, as a streaming [`ScanReader`].
///
/// `format` overrides the choice by extension ([`Format::from_path`], ignoring `.gz`). The
/// path `-` reads standard input (then `format` is required). The input is decompressed when
/// its name ends in `.gz` or it starts with the gzip magic bytes.
///
/// # Errors
/// [`ReadError::UnknownFormat`] when no format is given and none can be told from the name;
/// [`ReadError::Open`] when the file cannot be opened or its first bytes cannot be read.
pub fn open(path: &Path, format: Option<Format>) -> Result<ScanReader, ReadError> {
    open_with(path, &ReadOptions::format(format))
}

/// Opens a scan file like [`open`], with a topic for formats that hold several streams.
///
/// # Errors
/// As [`open`], and [`ReadError::Topic`] when a topic is given for a format that has none or
/// that is not a name the format uses (a CARMEN laser message). A topic a ROS bag does not
/// hold is reported by the reader at the end of the file, once every connection was seen.
pub fn open_with(path: &Path, options: &ReadOptions) -> Result<ScanReader, ReadError> {
    let name = path.display().to_string();
    if path == Path::new("-") {
        let format = options.format.ok_or_else(|| ReadError::UnknownFormat {
            file: name.clone(),
            found: "standard input, which has no name".to_owned(),
        })?;
        return from_reader_with(
            &name,
            BufReader::new(io::stdin()),
            format,
            options.topic.as_deref(),
        );
    }
    let format = match options.format {
        Some(f) => f,
        None => Format::from_path(path).ok_or_else(|| ReadError::UnknownFormat {
            file: name.clone(),
            found: describe_extension(path),
        })?,
    };
    let file = File::open(path).map_err(|source| ReadError::Open {
        file: name.clone(),
        source,
    })?;
    let input = open_input(
        &name,
        Box::new(BufReader::with_capacity(1 << 16, file)),
        has_gz_extension(path),
    )?;
    reader_for(&name, input, format, (options.topic.as_deref(), Some(path)))
}

/// Reads scans of `format` from any buffered reader (e.g. standard input); `name` is used in
/// messages. Gzip input is recognised by its magic bytes and decompressed.
///
/// # Errors
/// [`ReadError::Open`] when the first bytes cannot be read.
pub fn from_reader(
    name: &str,
    reader: impl BufRead + Send + 'static,
    format: Format,
) -> Result<ScanReader, ReadError> {
    from_reader_with(name, reader, format, None)
}

/// Reads scans of `format` from any buffered reader like [`from_reader`], choosing a topic
/// for formats that hold several streams ([`ReadOptions::topic`]).
///
/// # Errors
/// [`ReadError::Open`] when the first bytes cannot be read; [`ReadError::Topic`] as in
/// [`open_with`].
pub fn from_reader_with(
    name: &str,
    reader: impl BufRead + Send + 'static,
    format: Format,
    topic: Option<&str>,
) -> Result<ScanReader, ReadError> {
    let input = open_input(name, Box::new(reader), false)?;
    reader_for(name, input, format, (topic, None))
}

/// The reader of `input` in `format`, on `topic`; `path` is the file on disk, when the input
/// is one (a bag's index section is read from it: [`crate::bag`]).
fn reader_for(
    name: &str,
    input: Input,
    format: Format,
    (topic, path): (Option<&str>, Option<&Path>),
) -> Result<ScanReader, ReadError> {
    if let Some(topic) = topic
        && !format.has_topics()
    {
        return Err(ReadError::Topic {
            file: name.to_owned(),
            topic: topic.to_owned(),
            expected: format!(
                "no topic: the {} format holds one stream of scans",
                format.name()
            ),
        });
    }
    let source: Box<dyn ScanSource> = match format {
        Format::Json => Box::new(crate::json::JsonSource::new(name, input)),
        Format::Jsonl => Box::new(crate::json::JsonlSource::new(name, input)),
        Format::Csv => Box::new(crate::csv::CsvSource::new(name, input)),
        Format::BreezyDat => Box::new(crate::breezy::DatSource::new(name, input)),
        Format::Carmen => Box::new(crate::carmen::CarmenSource::new(name, input, topic)?),
        Format::Bag => {
            let source = crate::bag::BagSource::new(name, input, topic);
            Box::new(match path {
                Some(path) => source.with_index(path),
                None => source,
            })
        }
        Format::Mcap | Format::Db3 => Box::new(ReadElsewhere::new(name, "laserlines-foxglove")),
        Format::Parquet => Box::new(ReadElsewhere::new(name, "laserlines-parquet")),
    };
    Ok(ScanReader::from_source(name, format, source))
}

/// A format another crate reads (MCAP: `laserlines-foxglove`, Parquet: `laserlines-parquet`):
/// one error saying so, then the end.
struct ReadElsewhere {
    name: String,
    reader: &'static str,
    done: bool,
}

impl ReadElsewhere {
    fn new(name: &str, reader: &'static str) -> Self {
        Self {
            name: name.to_owned(),
            reader,
            done: false,
        }
    }
}

impl ScanSource for ReadElsewhere {
    fn next_record(&mut self, _: &mut SkipCounts) -> Option<Result<ScanRecord, ReadError>> {
        if std::mem::replace(&mut self.done, true) {
            return None;
        }
        Some(Err(ReadError::Syntax {
            pos: SourcePos::byte(&self.name, 0),
            expected: "a format laserlines-io reads".to_owned(),
            found: format!("a format the {} crate reads", self.reader),
        }))
    }
}

/// Wraps `input` in a gzip decoder when `gz` is set or it starts with the gzip magic.
///
/// # Errors
/// [`ReadError::Open`] when the first bytes cannot be read.
pub fn open_input(name: &str, mut input: Input, gz: bool) -> Result<Input, ReadError> {
    let mut head = [0u8; 2];
    let mut got = 0;
    while got < head.len() {
        match input.read(&mut head[got..]) {
            Ok(0) => break,
            Ok(n) => got += n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(source) => {
                return Err(ReadError::Open {
                    file: name.to_owned(),
                    source,
                });
            }
        }
    }
    let is_gzip = got == head.len() && head == crate::gzip::MAGIC;
    let restored: Input = Box::new(Cursor::new(head[..got].to_vec()).chain(input));
    if is_gzip || (gz && got > 0) {
        let decoder = crate::gzip::Members::new(restored);
        Ok(Box::new(BufReader::with_capacity(1 << 16, decoder)))
    } else {
        Ok(restored)
    }
}

/// One line of text read by [`Lines`].
pub(crate) enum LineItem<'a> {
    /// A line (without its `\n` or `\r\n`) and its 1-based number.
    Text(usize, &'a str),
    /// A line that is not UTF-8: a recoverable error.
    NotUtf8(ReadError),
}

/// Reads an input line by line, with line numbers, a length limit, and clear errors.
pub(crate) struct Lines {
    name: String,
    input: Input,
    buf: Vec<u8>,
    line: usize,
    done: bool,
    /// The last line read ended without `\n` (the input's end came first).
    unterminated: bool,
    /// The error of garbage after gzip data that followed the last line: the next item.
    failed: Option<ReadError>,
}

impl Lines {
    pub(crate) fn new(name: &str, input: Input) -> Self {
        Self {
            name: name.to_owned(),
            input,
            buf: Vec::new(),
            line: 0,
            done: false,
            unterminated: false,
            failed: None,
        }
    }

    /// True when the last line read had no `\n`: the input ended inside it (a file cut
    /// there, or one whose writer left out the last line end).
    pub(crate) fn last_unterminated(&self) -> bool {
        self.unterminated
    }

    /// The number of the last line read (0 before the first).
    pub(crate) fn line_number(&self) -> usize {
        self.line
    }

    /// The next line; `Err` is fatal (the reader is then done). Garbage after the end of gzip
    /// data, inside a line without its line end, gives that line first, then the error.
    pub(crate) fn next_line(&mut self) -> Option<Result<LineItem<'_>, ReadError>> {
        if let Some(e) = self.failed.take() {
            self.done = true;
            return Some(Err(e));
        }
        if self.done {
            return None;
        }
        self.buf.clear();
        let limit = MAX_LINE_BYTES as u64 + 1;
        let read = loop {
            match (&mut self.input)
                .take(limit)
                .read_until(b'\n', &mut self.buf)
            {
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                other => break other,
            }
        };
        self.line += 1;
        let read = match read {
            // Garbage after whole gzip data: the part of a line read before it is whole.
            Err(source) if !self.buf.is_empty() && crate::gzip::TrailingGarbage::is(&source) => {
                self.failed = Some(ReadError::Io {
                    pos: SourcePos::line(&self.name, self.line),
                    source,
                });
                Ok(self.buf.len())
            }
            other => other,
        };
        match read {
            Err(source) => {
                self.done = true;
                Some(Err(ReadError::Io {
                    pos: SourcePos::line(&self.name, self.line),
                    source,
                }))
            }
            Ok(0) => {
                self.done = true;
                self.line -= 1;
                None
            }
            Ok(_) => {
                self.unterminated = self.buf.last() != Some(&b'\n');
                if self.buf.len() > MAX_LINE_BYTES && self.unterminated {
                    self.done = true;
                    return Some(Err(ReadError::Io {
                        pos: SourcePos::line(&self.name, self.line),
                        source: io::Error::new(
                            io::ErrorKind::InvalidData,
                            format!("line longer than {MAX_LINE_BYTES} bytes"),
                        ),
                    }));
                }
                let mut end = self.buf.len();
                if end > 0 && self.buf[end - 1] == b'\n' {
                    end -= 1;
                    if end > 0 && self.buf[end - 1] == b'\r' {
                        end -= 1;
                    }
                }
                let bytes = &self.buf[..end];
                let bytes = if self.line == 1 {
                    bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes)
                } else {
                    bytes
                };
                match std::str::from_utf8(bytes) {
                    Ok(text) => Some(Ok(LineItem::Text(self.line, text))),
                    Err(e) => Some(Ok(LineItem::NotUtf8(ReadError::Syntax {
                        pos: SourcePos::line_column(&self.name, self.line, e.valid_up_to() + 1),
                        expected: "UTF-8 text".to_owned(),
                        found: format!("the byte 0x{:02x}", bytes[e.valid_up_to()]),
                    }))),
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines_of(data: &'static [u8]) -> Vec<String> {
        let mut lines = Lines::new("t", Box::new(data));
        let mut out = Vec::new();
        while let Some(item) = lines.next_line() {
            match item {
                Ok(LineItem::Text(n, t)) => out.push(format!("{n}:{t}")),
                Ok(LineItem::NotUtf8(e)) => out.push(e.to_string()),
                Err(e) => out.push(format!("fatal {e}")),
            }
        }
        out
    }

    #[test]
    fn lines_strip_newlines_bom_and_report_bad_utf8() {
        assert_eq!(
            lines_of(b"\xEF\xBB\xBFa\r\nb\n\nc"),
            vec!["1:a", "2:b", "3:", "4:c"]
        );
        assert_eq!(
            lines_of(b"ok\nx\xffy\nz\n"),
            vec![
                "1:ok",
                "t:2:2: expected UTF-8 text, found the byte 0xff",
                "3:z"
            ]
        );
    }

    #[test]
    fn gzip_is_detected_by_magic() {
        use std::io::Write;
        let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        enc.write_all(b"hello\n").unwrap();
        let gz = enc.finish().unwrap();
        let mut input = open_input("t", Box::new(Cursor::new(gz)), false).unwrap();
        let mut s = String::new();
        input.read_to_string(&mut s).unwrap();
        assert_eq!(s, "hello\n");
        let mut plain = open_input("t", Box::new(&b"x"[..]), false).unwrap();
        s.clear();
        plain.read_to_string(&mut s).unwrap();
        assert_eq!(s, "x");
    }
}
