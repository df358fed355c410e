//! SCIP 2.0 replies: framing a byte stream into messages, and parsing one message into its
//! command echo, status and verified data lines.
//!
//! A reply is a command echo line, a status line (two status characters and their check
//! character, or one status character in the replies of the `SCIP2.0` switch and of a
//! sensor in SCIP 1.1), data lines (each ending with its check character), and an empty
//! line: every message ends with two line feeds.
//!
//! - this module: [`Reply`] (parsing a message, its status, its data and information
//!   lines) and [`Status`];
//! - `scan`: the layout and values of a scan reply;
//! - `framer`: [`Framer`], cutting the byte stream into messages;
//! - `error`: [`ReplyError`].

mod error;
mod framer;
mod scan;

use std::ops::Range;

use crate::codec::check_char;

pub use error::ReplyError;
pub use framer::{Framer, MAX_MESSAGE};
pub use scan::DATA_LINE;

/// The status of a reply.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Status {
    /// A SCIP 2.0 status: two characters (`00`, `99`, `0M`, ...), check character verified.
    Scip2([u8; 2]),
    /// A single status character: the reply of the `SCIP2.0` switch, or of a sensor still
    /// speaking SCIP 1.1.
    Single(u8),
}

impl Status {
    /// The status characters as text.
    #[must_use]
    pub fn as_string(&self) -> String {
        match self {
            Self::Scip2(s) => String::from_utf8_lossy(s).into_owned(),
            Self::Single(c) => char::from(*c).to_string(),
        }
    }

    /// True for `00`.
    #[must_use]
    pub fn is_ok(&self) -> bool {
        *self == Self::Scip2(*b"00")
    }
}

/// One parsed message: the echo, the status and the data lines without their check
/// characters (each verified), borrowed from the message's bytes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Reply<'a> {
    bytes: &'a [u8],
    /// The command echo (first line).
    pub echo: &'a [u8],
    /// The status.
    pub status: Status,
    /// Byte ranges of the data lines, check character included.
    lines: Vec<Range<usize>>,
}

/// Splits `message` (one whole message, ending with `\n\n`) into line ranges.
fn split_lines(message: &[u8]) -> Result<Vec<Range<usize>>, ReplyError> {
    if !message.ends_with(b"\n\n") {
        return Err(ReplyError::Unterminated);
    }
    let body = &message[..message.len() - 1];
    let mut out = Vec::with_capacity(body.len() / 64 + 4);
    let mut start = 0;
    for (i, &b) in body.iter().enumerate() {
        if b == b'\n' {
            out.push(start..i);
            start = i + 1;
        }
    }
    Ok(out)
}

impl<'a> Reply<'a> {
    /// Parses one message: verifies the status line's check character, that no line is
    /// empty, and every data line's check character.
    ///
    /// Information replies (`VV`, `PP`, `II`) end their data lines with `;` and a check
    /// character over the text before the `;`; use [`Reply::parse_unchecked`] and [`Reply::info`] for those, which
    /// verifies them itself (this function only splits them).
    ///
    /// # Errors
    /// The first [`ReplyError`] found.
    pub fn parse(message: &'a [u8]) -> Result<Self, ReplyError> {
        Self::parse_with(message, true)
    }

    /// Parses a message without verifying its data lines' check characters: for
    /// information replies (checked by [`Reply::info`]) and for scans, whose layout is
    /// checked first ([`Reply::check_scan_layout`]) and then their checks
    /// ([`Reply::verify_data`]), so that a cut line is told from a corrupted one.
    ///
    /// # Errors
    /// As [`Reply::parse`], less the data lines' checks.
    pub fn parse_unchecked(message: &'a [u8]) -> Result<Self, ReplyError> {
        Self::parse_with(message, false)
    }

    /// Verifies every data line's check character.
    ///
    /// # Errors
    /// [`ReplyError::Checksum`] naming the first bad line.
    pub fn verify_data(&self) -> Result<(), ReplyError> {
        for (k, r) in self.lines.iter().enumerate() {
            verify_line(self.bytes, r.clone(), k + 3)?;
        }
        Ok(())
    }

    fn parse_with(message: &'a [u8], check_data: bool) -> Result<Self, ReplyError> {
        let lines = split_lines(message)?;
        let mut it = lines.into_iter();
        let echo = it.next().map_or(&message[..0], |r| &message[r]);
        let status_range = it.next().ok_or(ReplyError::MissingStatus)?;
        let status = parse_status(message, status_range)?;
        let data: Vec<Range<usize>> = it.collect();
        for (k, r) in data.iter().enumerate() {
            let line = k + 3;
            if r.is_empty() {
                return Err(ReplyError::EmptyLine {
                    line,
                    offset: r.start,
                });
            }
            if check_data {
                verify_line(message, r.clone(), line)?;
            }
        }
        Ok(Self {
            bytes: message,
            echo,
            status,
            lines: data,
        })
    }

    /// Number of data lines.
    #[must_use]
    pub fn data_line_count(&self) -> usize {
        self.lines.len()
    }

    /// Data line `k` (0-based, after the status line) without its check character.
    #[must_use]
    pub fn data_line(&self, k: usize) -> Option<&'a [u8]> {
        self.lines
            .get(k)
            .map(|r| &self.bytes[r.start..r.end.saturating_sub(1).max(r.start)])
    }

    /// The `LABEL:VALUE` pairs of an information reply (`VV`, `PP`, `II`), in order. Each
    /// line is `LABEL:VALUE;C` with the check character `C` over `LABEL:VALUE` (as the
    /// specification's examples); a check over the text with its `;` is also accepted.
    ///
    /// # Errors
    /// [`ReplyError::BadInfoLine`] or [`ReplyError::Checksum`] naming the line.
    pub fn info(&self) -> Result<Vec<(String, String)>, ReplyError> {
        let mut out = Vec::with_capacity(self.lines.len());
        for (k, r) in self.lines.iter().enumerate() {
            let line_no = k + 3;
            let line = &self.bytes[r.clone()];
            let bad = || ReplyError::BadInfoLine {
                line: line_no,
                offset: r.start,
                text: String::from_utf8_lossy(line).into_owned(),
            };
            if line.len() < 3 || line[line.len() - 2] != b';' {
                return Err(bad());
            }
            let found = line[line.len() - 1];
            let text = &line[..line.len() - 2];
            if check_char(text) != found && check_char(&line[..line.len() - 1]) != found {
                return Err(ReplyError::Checksum {
                    line: line_no,
                    offset: r.start,
                    expected: char::from(check_char(text)),
                    found: char::from(found),
                });
            }
            let text = String::from_utf8_lossy(text);
            let (label, value) = text.split_once(':').ok_or_else(bad)?;
            out.push((label.trim().to_owned(), value.trim().to_owned()));
        }
        Ok(out)
    }
}

fn parse_status(message: &[u8], r: Range<usize>) -> Result<Status, ReplyError> {
    let line = &message[r.clone()];
    match line.len() {
        1 => Ok(Status::Single(line[0])),
        3 => {
            let expected = check_char(&line[..2]);
            if expected != line[2] {
                return Err(ReplyError::Checksum {
                    line: 2,
                    offset: r.start,
                    expected: char::from(expected),
                    found: char::from(line[2]),
                });
            }
            Ok(Status::Scip2([line[0], line[1]]))
        }
        _ => Err(ReplyError::BadStatusLine {
            offset: r.start,
            text: String::from_utf8_lossy(line).into_owned(),
        }),
    }
}

fn verify_line(message: &[u8], r: Range<usize>, line: usize) -> Result<(), ReplyError> {
    let bytes = &message[r.clone()];
    let (payload, found) = bytes.split_at(bytes.len() - 1);
    let expected = check_char(payload);
    if expected != found[0] {
        return Err(ReplyError::Checksum {
            line,
            offset: r.start,
            expected: char::from(expected),
            found: char::from(found[0]),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests;
