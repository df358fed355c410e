//! Errors of the readers and writers, each naming the file, the place in it and what was wrong.

use std::fmt;

use laserlines::ScanError;

/// A place in an input: which line (and column), or which byte for binary formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum At {
    /// A 1-based line number.
    Line(usize),
    /// A 1-based line number and a 1-based column (in bytes).
    LineColumn {
        /// 1-based line number.
        line: usize,
        /// 1-based column, counted in bytes.
        column: usize,
    },
    /// A 0-based byte offset into the (decompressed) input.
    Byte(u64),
    /// A message of a database (a ROS 2 bag in sqlite3 storage), by its id.
    Message(i64),
    /// A 0-based row of a table (Parquet).
    Row(u64),
}

impl At {
    /// The line number, when this place is a line.
    #[must_use]
    pub fn line(self) -> Option<usize> {
        match self {
            Self::Line(line) | Self::LineColumn { line, .. } => Some(line),
            Self::Byte(_) | Self::Message(_) | Self::Row(_) => None,
        }
    }
}

/// A file name and a place in it, shown as `exp1.dat:17`, `scan.json:3:15`,
/// `log.bag: byte 1234`, `bag_0.db3: message 17` or `scans.parquet: row 12`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SourcePos {
    /// The input's name as the user gave it (a path, or `-` for standard input).
    pub file: String,
    /// The place in the input.
    pub at: At,
}

impl SourcePos {
    /// A position at a 1-based line.
    #[must_use]
    pub fn line(file: &str, line: usize) -> Self {
        Self {
            file: file.to_owned(),
            at: At::Line(line),
        }
    }

    /// A position at a 1-based line and column.
    #[must_use]
    pub fn line_column(file: &str, line: usize, column: usize) -> Self {
        Self {
            file: file.to_owned(),
            at: At::LineColumn { line, column },
        }
    }

    /// A position at a message of a database, by its id.
    #[must_use]
    pub fn message(file: &str, id: i64) -> Self {
        Self {
            file: file.to_owned(),
            at: At::Message(id),
        }
    }

    /// A position at a 0-based row of a table.
    #[must_use]
    pub fn row(file: &str, row: u64) -> Self {
        Self {
            file: file.to_owned(),
            at: At::Row(row),
        }
    }

    /// A position at a 0-based byte offset.
    #[must_use]
    pub fn byte(file: &str, offset: u64) -> Self {
        Self {
            file: file.to_owned(),
            at: At::Byte(offset),
        }
    }
}

impl fmt::Display for SourcePos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.at {
            At::Line(line) => write!(f, "{}:{line}", self.file),
            At::LineColumn { line, column } => write!(f, "{}:{line}:{column}", self.file),
            At::Byte(offset) => write!(f, "{}: byte {offset}", self.file),
            At::Message(id) => write!(f, "{}: message {id}", self.file),
            At::Row(row) => write!(f, "{}: row {row}", self.file),
        }
    }
}

/// Why reading scans failed. Every variant names the input; all but [`ReadError::Open`],
/// [`ReadError::UnknownFormat`] and [`ReadError::Topic`] also name the line (or byte offset)
/// and what was expected.
///
/// After an error, a [`crate::ScanReader`] goes on with the next record where the format
/// allows it (a JSONL line, a `.dat` line, an element of a JSON array); after an error that
/// leaves it lost (a read failure, broken JSON framing, any CSV error) it ends. So a caller can
/// stop at the first error, or skip a bad record and keep iterating. A failed read of the
/// input itself ([`ReadError::Io`]) is no bad record ([`ReadError::is_bad_record`]): nothing
/// after it can be read, so a caller that skips bad records still stops there.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// A topic was asked for that the format does not have (a single-stream format such as
    /// JSON, or a name that is not one of the format's topics).
    #[error("{file}: cannot read topic `{topic}`: expected {expected}")]
    Topic {
        /// The input's name.
        file: String,
        /// The topic asked for.
        topic: String,
        /// What the format accepts as a topic.
        expected: String,
    },
    /// The input could not be opened.
    #[error("{file}: cannot open: {source}")]
    Open {
        /// The input's name.
        file: String,
        /// The underlying error.
        source: std::io::Error,
    },
    /// No format was given and none could be told from the name.
    #[error(
        "{file}: cannot tell the scan format from the name (found {found}); expected a name \
         ending in .json, .jsonl, .ndjson, .csv, .dat, .mcap, .clf, .log, .bag or .db3 \
         (optionally followed by .gz) or .parquet, or an explicit format (one of: json, jsonl, \
         csv, dat, mcap, carmen, bag, db3, parquet)"
    )]
    UnknownFormat {
        /// The input's name.
        file: String,
        /// What the name ends with, e.g. `extension .txt` or `no extension`.
        found: String,
    },
    /// Reading failed part way (I/O error, corrupt or truncated gzip stream, invalid UTF-8
    /// where text is required, a line too long). Ends the reader; not a bad record
    /// ([`ReadError::is_bad_record`]) and not counted as a skip.
    #[error("{pos}: read failed: {source}")]
    Io {
        /// Where reading failed (the line being read).
        pos: SourcePos,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The text does not have the shape the format requires.
    #[error("{pos}: expected {expected}, found {found}")]
    Syntax {
        /// Where.
        pos: SourcePos,
        /// What the format requires there.
        expected: String,
        /// What the input holds there.
        found: String,
    },
    /// A JSON text is malformed (the message is `serde_json`'s, without its position).
    #[error("{pos}: malformed JSON: {message}")]
    Json {
        /// Where the JSON parser stopped.
        pos: SourcePos,
        /// The parser's description of the problem.
        message: String,
    },
    /// A field holds a value of the wrong kind or out of range.
    #[error("{pos}: {field}: expected {expected}, found {found}")]
    Field {
        /// Where the field is.
        pos: SourcePos,
        /// The field's name (e.g. `ranges`, `ranges[3]`, `token 0 (timestamp)`).
        field: String,
        /// What the field must hold.
        expected: String,
        /// What it holds.
        found: String,
    },
    /// The record parsed but is not a valid scan ([`laserlines::Scan::validate`]).
    #[error("{pos}: invalid scan: {source}")]
    InvalidScan {
        /// Where the record is.
        pos: SourcePos,
        /// The validation error.
        source: ScanError,
    },
}

impl ReadError {
    /// The input's name.
    #[must_use]
    pub fn file(&self) -> &str {
        match self {
            Self::Open { file, .. }
            | Self::UnknownFormat { file, .. }
            | Self::Topic { file, .. } => file,
            Self::Io { pos, .. }
            | Self::Syntax { pos, .. }
            | Self::Json { pos, .. }
            | Self::Field { pos, .. }
            | Self::InvalidScan { pos, .. } => &pos.file,
        }
    }

    /// The place in the input, when the error has one.
    #[must_use]
    pub fn pos(&self) -> Option<&SourcePos> {
        match self {
            Self::Open { .. } | Self::UnknownFormat { .. } | Self::Topic { .. } => None,
            Self::Io { pos, .. }
            | Self::Syntax { pos, .. }
            | Self::Json { pos, .. }
            | Self::Field { pos, .. }
            | Self::InvalidScan { pos, .. } => Some(pos),
        }
    }

    /// The 1-based line of the error, when it has one.
    #[must_use]
    pub fn line(&self) -> Option<usize> {
        self.pos().and_then(|p| p.at.line())
    }

    /// A record at `pos` whose length field is corrupt (`expected` what the format allows,
    /// `found` what it holds): the records after it cannot be found, so the rest of the input
    /// is not read. A failed read ([`ReadError::Io`]), not a bad record: a skip would end the
    /// reading there with the rest of the input unread and uncounted.
    #[must_use]
    pub fn corrupt_length(pos: SourcePos, expected: &str, found: &str) -> Self {
        Self::Io {
            pos,
            source: std::io::Error::other(format!(
                "expected {expected}, found {found}; the records after it cannot be found, so \
                 the rest of the input is not read"
            )),
        }
    }

    /// True for a bad record, which a caller may skip (counted in [`crate::SkipCounts`]
    /// under [`ReadError::reason`]) and read on; false for a failed read of the input itself
    /// ([`ReadError::Io`]: an I/O error, a corrupt or truncated gzip stream, a line or JSON
    /// element too long), after which nothing more can be read, and for the errors of
    /// opening. Skipping the latter would lose the rest of the input: they end the reading.
    #[must_use]
    pub fn is_bad_record(&self) -> bool {
        match self {
            Self::Open { .. }
            | Self::UnknownFormat { .. }
            | Self::Topic { .. }
            | Self::Io { .. } => false,
            Self::Syntax { .. }
            | Self::Json { .. }
            | Self::Field { .. }
            | Self::InvalidScan { .. } => true,
        }
    }

    /// A short reason, used as the key of [`crate::SkipCounts`] (e.g. `malformed JSON`).
    #[must_use]
    pub fn reason(&self) -> &'static str {
        match self {
            Self::Open { .. } => "cannot open",
            Self::UnknownFormat { .. } => "unknown format",
            Self::Topic { .. } => "unknown topic",
            Self::Io { .. } => "read failed",
            Self::Syntax { .. } => "malformed record",
            Self::Json { .. } => "malformed JSON",
            Self::Field { .. } => "bad field",
            Self::InvalidScan { .. } => "invalid scan",
        }
    }
}

/// Why writing scans or lines failed.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// The output could not be created or written.
    #[error("{file}: {source}")]
    Io {
        /// The output's name.
        file: String,
        /// The underlying error.
        source: std::io::Error,
    },
    /// The format cannot be written (e.g. BreezySLAM `.dat`, whose extra fields are unknown).
    #[error("{file}: writing the {format} format is not supported")]
    Unsupported {
        /// The output's name.
        file: String,
        /// The format's name.
        format: &'static str,
    },
    /// The format holds one scan per file and a second one was written.
    #[error("{file}: the {format} format holds one scan per file; the input has {count} or more")]
    OneScanPerFile {
        /// The output's name.
        file: String,
        /// The format's name.
        format: &'static str,
        /// 1-based number of the scan that did not fit.
        count: usize,
    },
    /// No format was given and none could be told from the name.
    #[error(
        "{file}: cannot tell the output format from the name; expected a name ending in \
         .json, .jsonl, .ndjson or .csv (optionally followed by .gz), or an explicit format"
    )]
    UnknownFormat {
        /// The output's name.
        file: String,
    },
    /// The name does not say what to write in a way the writer accepts.
    #[error("{file}: cannot write this name; expected {expected}")]
    Name {
        /// The output's name.
        file: String,
        /// The names accepted.
        expected: &'static str,
    },
}

/// Human description of a JSON value's kind, for "found ..." messages.
pub fn json_kind(v: &serde_json::Value) -> String {
    use serde_json::Value;
    match v {
        Value::Null => "null".to_owned(),
        Value::Bool(b) => format!("a boolean ({b})"),
        Value::Number(n) => format!("a number ({n})"),
        Value::String(s) => {
            let shown: String = s.chars().take(20).collect();
            if shown.len() < s.len() {
                format!("a string (\"{shown}...\")")
            } else {
                format!("a string (\"{shown}\")")
            }
        }
        Value::Array(a) if a.len() == 1 => "an array of 1 value".to_owned(),
        Value::Array(a) => format!("an array of {} values", a.len()),
        Value::Object(_) => "an object".to_owned(),
    }
}

/// Shows a piece of input text in a message: quoted and cut to a sensible length.
pub(crate) fn shown(text: &str) -> String {
    const MAX: usize = 40;
    let mut out: String = text.chars().take(MAX).collect();
    if out.len() < text.len() {
        out.push_str("...");
    }
    format!("`{}`", out.escape_debug())
}

/// `e` and its causes joined by `: `, leaving out a cause whose text the message already ends
/// with (many errors end their own message with their cause's): the one line the command-line
/// tools print for an error.
#[must_use]
pub fn error_chain(e: &(dyn std::error::Error + 'static)) -> String {
    let mut message = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        let text = c.to_string();
        if !(message == text || message.ends_with(&format!(": {text}"))) {
            message.push_str(": ");
            message.push_str(&text);
        }
        cause = c.source();
    }
    message
}
