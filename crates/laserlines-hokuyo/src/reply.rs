//! SCIP 2.0 replies: framing a byte stream into messages, and parsing one message into its
//! command echo, status and verified data lines.
//!
//! A reply is a command echo line, a status line (two status characters and their check
//! character, or one status character in the replies of the `SCIP2.0` switch and of a
//! sensor in SCIP 1.1), data lines (each ending with its check character), and an empty
//! line: every message ends with two line feeds.

use std::ops::Range;

use crate::codec::{self, Encoding, check_char};

/// The largest message accepted, bytes. A scan of 1081 steps in 3-character encoding is
/// about 3.4 kB; a stream that goes this long without a message end is not SCIP.
pub const MAX_MESSAGE: usize = 64 * 1024;

/// Characters of scan data per line (before the check character); the last line of a
/// scan may be shorter.
pub const DATA_LINE: usize = 64;

/// What is wrong with a message. Line numbers count from 1 (the echo) and offsets are
/// bytes from the start of the message.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ReplyError {
    /// The message has no status line.
    #[error("line 2: the reply has no status line")]
    MissingStatus,
    /// The status line is neither `SS` + check character nor one SCIP 1.1 character.
    #[error(
        "line 2 (byte {offset}): status line {text:?} is not two status characters and a check character"
    )]
    BadStatusLine {
        /// Byte offset of the line.
        offset: usize,
        /// The line, lossily as text.
        text: String,
    },
    /// A line's check character does not match its bytes.
    #[error(
        "line {line} (byte {offset}): check character {found:?} where the line's bytes give {expected:?}"
    )]
    Checksum {
        /// Line number.
        line: usize,
        /// Byte offset of the line.
        offset: usize,
        /// The check character the bytes give.
        expected: char,
        /// The check character sent.
        found: char,
    },
    /// An empty line before the end of the message.
    #[error("line {line} (byte {offset}): empty line inside the message")]
    EmptyLine {
        /// Line number.
        line: usize,
        /// Byte offset.
        offset: usize,
    },
    /// The message does not end with two line feeds.
    #[error("the message does not end with two line feeds")]
    Unterminated,
    /// A scan reply without its time stamp line.
    #[error("line 3: a scan reply needs a time stamp line of 4 characters, got {found} characters")]
    BadTimestamp {
        /// Characters found.
        found: usize,
    },
    /// A character outside the number encoding.
    #[error("line {line} (byte {offset}): {source}")]
    BadCharacter {
        /// Line number.
        line: usize,
        /// Byte offset of the line.
        offset: usize,
        /// The decoding error (position within the line).
        source: codec::DecodeError,
    },
    /// The scan data have a number of characters that is not what the request asked for.
    #[error(
        "scan data: {found} characters, expected {expected} ({values} values of {chars} characters): truncated or garbled"
    )]
    Length {
        /// Characters expected.
        expected: usize,
        /// Characters found.
        found: usize,
        /// Values expected.
        values: usize,
        /// Characters per value.
        chars: usize,
    },
    /// A scan data line that is not 64 characters long, and is not the last.
    #[error(
        "line {line} (byte {offset}): scan data line of {found} characters where 64 were due: cut short"
    )]
    LineLength {
        /// Line number.
        line: usize,
        /// Byte offset.
        offset: usize,
        /// Characters found (without the check character).
        found: usize,
    },
    /// A data line of an information reply (`VV`, `PP`, `II`) is not `LABEL:VALUE;C`.
    #[error("line {line} (byte {offset}): {text:?} is not LABEL:VALUE;C")]
    BadInfoLine {
        /// Line number.
        line: usize,
        /// Byte offset.
        offset: usize,
        /// The line, lossily as text.
        text: String,
    },
}

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

    /// Checks that a scan reply is laid out as a whole scan of `values` values of
    /// `encoding`: a time stamp line of 4 characters, data lines of 64 characters (the
    /// last one at most 64) each with its check character, as many characters as asked.
    ///
    /// # Errors
    /// [`ReplyError::BadTimestamp`], [`ReplyError::LineLength`] or [`ReplyError::Length`].
    pub fn check_scan_layout(&self, encoding: Encoding, values: usize) -> Result<(), ReplyError> {
        let stamp = self.lines.first().map_or(0, |r| r.len().saturating_sub(1));
        if stamp != 4 {
            return Err(ReplyError::BadTimestamp { found: stamp });
        }
        let data = &self.lines[1..];
        for (k, r) in data.iter().enumerate() {
            let payload = r.len().saturating_sub(1);
            let last = k + 1 == data.len();
            if payload > DATA_LINE || (!last && payload != DATA_LINE) {
                return Err(ReplyError::LineLength {
                    line: k + 4,
                    offset: r.start,
                    found: payload,
                });
            }
        }
        let chars = encoding.chars();
        let found: usize = data.iter().map(|r| r.len().saturating_sub(1)).sum();
        let expected = values * chars;
        if found != expected {
            return Err(ReplyError::Length {
                expected,
                found,
                values,
                chars,
            });
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

    /// The time stamp and values of a scan reply (`MD`, `MS`, `GD`, `GS`): the first data
    /// line is the 4-character time stamp, the others carry the values, which may run on
    /// from one line to the next. `values` is how many the request asked for.
    ///
    /// # Errors
    /// [`ReplyError::BadTimestamp`], [`ReplyError::BadCharacter`] or
    /// [`ReplyError::Length`] (a truncated or garbled scan).
    pub fn scan_into(
        &self,
        encoding: Encoding,
        values: usize,
        out: &mut Vec<u32>,
    ) -> Result<u32, ReplyError> {
        out.clear();
        let stamp = self.data_line(0).unwrap_or_default();
        if stamp.len() != 4 {
            return Err(ReplyError::BadTimestamp { found: stamp.len() });
        }
        let timestamp = codec::decode(stamp).map_err(|source| ReplyError::BadCharacter {
            line: 3,
            offset: self.lines[0].start,
            source,
        })?;
        let chars = encoding.chars();
        let found: usize = (1..self.lines.len())
            .map(|k| self.lines[k].len().saturating_sub(1))
            .sum();
        let expected = values * chars;
        if found != expected {
            return Err(ReplyError::Length {
                expected,
                found,
                values,
                chars,
            });
        }
        out.reserve(values);
        // Values may straddle line ends: carry the partial one over.
        let mut acc = 0u32;
        let mut have = 0usize;
        for k in 1..self.lines.len() {
            let r = &self.lines[k];
            let line = &self.bytes[r.start..r.end - 1];
            for (i, &b) in line.iter().enumerate() {
                let digit = b.wrapping_sub(0x30);
                if digit > 0x3f {
                    return Err(ReplyError::BadCharacter {
                        line: k + 3,
                        offset: r.start,
                        source: codec::DecodeError {
                            position: i,
                            byte: b,
                        },
                    });
                }
                acc = (acc << 6) | u32::from(digit);
                have += 1;
                if have == chars {
                    out.push(acc);
                    acc = 0;
                    have = 0;
                }
            }
        }
        Ok(timestamp)
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

/// Cuts a byte stream into messages at every `\n\n`.
///
/// Push what the transport read with [`Framer::push`], then take whole messages with
/// [`Framer::next_message`]. A stream that runs past [`MAX_MESSAGE`] bytes without a
/// message end is dropped (and counted) rather than buffered without bound.
#[derive(Debug, Default, Clone)]
pub struct Framer {
    buf: Vec<u8>,
    /// Where the search for `\n\n` goes on from.
    scanned: usize,
    overflows: u64,
}

impl Framer {
    /// An empty framer.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends bytes read from the transport.
    pub fn push(&mut self, bytes: &[u8]) {
        self.buf.extend_from_slice(bytes);
    }

    /// The next whole message (ending with `\n\n`), if one is buffered. A leading line feed
    /// left over between messages is skipped.
    pub fn next_message(&mut self) -> Option<Vec<u8>> {
        // Stray line feeds before a message (e.g. after a host line ending of CR LF
        // echoed back) carry nothing.
        let lead = self.buf.iter().take_while(|&&b| b == b'\n').count();
        if lead > 0 {
            self.buf.drain(..lead);
            self.scanned = 0;
        }
        let from = self.scanned.saturating_sub(1);
        if let Some(pos) = self.buf[from..].windows(2).position(|w| w == b"\n\n") {
            let end = from + pos + 2;
            let message: Vec<u8> = self.buf.drain(..end).collect();
            self.scanned = 0;
            return Some(message);
        }
        self.scanned = self.buf.len();
        if self.buf.len() > MAX_MESSAGE {
            self.buf.clear();
            self.scanned = 0;
            self.overflows += 1;
        }
        None
    }

    /// Bytes buffered that do not yet make a whole message.
    #[must_use]
    pub fn pending(&self) -> usize {
        self.buf.len()
    }

    /// Drops everything buffered (after a reconnect).
    pub fn clear(&mut self) {
        self.buf.clear();
        self.scanned = 0;
    }

    /// Times more than [`MAX_MESSAGE`] bytes came without a message end.
    #[must_use]
    pub fn overflows(&self) -> u64 {
        self.overflows
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_qt_reply_parses() {
        let r = Reply::parse(b"QT\n00P\n\n").unwrap();
        assert_eq!(r.echo, b"QT");
        assert!(r.status.is_ok());
        assert_eq!(r.data_line_count(), 0);
    }

    // The PP reply lines the specification prints for the URG-04LX, with their checks.
    #[test]
    fn the_specifications_pp_reply_gives_its_parameters() {
        let msg =
            b"PP\n00P\nDMIN:20;4\nDMAX:5600;_\nAMIN:44;7\nAMAX:725;o\nAFRT:384;6\nSCAN:600;e\n\n";
        let r = Reply::parse_unchecked(msg).unwrap();
        let info = r.info().unwrap();
        assert_eq!(info[0], ("DMIN".to_owned(), "20".to_owned()));
        assert_eq!(info[5], ("SCAN".to_owned(), "600".to_owned()));
        // A wrong check character is reported with its line.
        let bad = b"PP\n00P\nDMIN:20;5\n\n";
        let e = Reply::parse_unchecked(bad).unwrap().info().unwrap_err();
        assert!(matches!(e, ReplyError::Checksum { line: 3, .. }), "{e}");
    }

    // A GD reply of three steps, 3-character encoding, built by hand from the
    // specification: echo, "00P", time stamp + check, data + check, empty line.
    #[test]
    fn a_hand_made_gd_reply_decodes() {
        // Time stamp 16,000,000 ms = "m2@0"; ranges 5432 ("1Dh"), 1234 ("01B"... 3 chars:
        // 1234 = 0b000000_010011_010010 = "0CB"), 7 ("007": an error code).
        let mut msg = b"GD0044004601\n00P\n".to_vec();
        msg.extend_from_slice(b"m2@0");
        msg.push(check_char(b"m2@0"));
        msg.push(b'\n');
        let data = b"1Dh0CB007";
        msg.extend_from_slice(data);
        msg.push(check_char(data));
        msg.extend_from_slice(b"\n\n");
        let r = Reply::parse(&msg).unwrap();
        let mut v = Vec::new();
        let t = r.scan_into(Encoding::Three, 3, &mut v).unwrap();
        assert_eq!(t, 16_000_000);
        assert_eq!(v, vec![5432, 1234, 7]);
        // Asking for four values: the data are short.
        assert!(matches!(
            r.scan_into(Encoding::Three, 4, &mut v),
            Err(ReplyError::Length {
                expected: 12,
                found: 9,
                ..
            })
        ));
    }

    #[test]
    fn values_straddling_line_ends_decode() {
        // 2 values of 3 chars split as "1D" | "h0CB".
        let mut msg = b"MD0044004501000\n99b\n".to_vec();
        for line in [&b"0000"[..], b"1D", b"h0CB"] {
            msg.extend_from_slice(line);
            msg.push(check_char(line));
            msg.push(b'\n');
        }
        msg.push(b'\n');
        let r = Reply::parse(&msg).unwrap();
        assert_eq!(r.status, Status::Scip2(*b"99"));
        let mut v = Vec::new();
        assert_eq!(r.scan_into(Encoding::Three, 2, &mut v), Ok(0));
        assert_eq!(v, vec![5432, 1234]);
    }

    #[test]
    fn damaged_messages_are_named() {
        assert_eq!(Reply::parse(b"QT\n00P\n"), Err(ReplyError::Unterminated));
        assert_eq!(Reply::parse(b"QT\n\n"), Err(ReplyError::MissingStatus));
        assert!(matches!(
            Reply::parse(b"QT\n00Q\n\n"),
            Err(ReplyError::Checksum { line: 2, .. })
        ));
        assert!(matches!(
            Reply::parse(b"QT\n00PP\n\n"),
            Err(ReplyError::BadStatusLine { .. })
        ));
        assert!(matches!(
            Reply::parse(b"GD\n00P\n0000!\n\n"),
            Err(ReplyError::Checksum { line: 3, .. })
        ));
        // A data line cut short before the last one is told from a corrupted one.
        let mut msg = b"MD0044004501000\n99b\n".to_vec();
        for line in [&b"0000"[..], b"1D", b"h0CB"] {
            msg.extend_from_slice(line);
            msg.push(check_char(line));
            msg.push(b'\n');
        }
        msg.push(b'\n');
        let r = Reply::parse_unchecked(&msg).unwrap();
        assert!(matches!(
            r.check_scan_layout(Encoding::Three, 2),
            Err(ReplyError::LineLength {
                line: 4,
                found: 2,
                ..
            })
        ));
        assert!(r.verify_data().is_ok());
        assert_eq!(
            Reply::parse(b"SCIP2.0\n0\n\n").unwrap().status,
            Status::Single(b'0')
        );
    }

    #[test]
    fn the_framer_cuts_at_double_line_feeds_across_pushes() {
        let mut f = Framer::new();
        f.push(b"QT\n00");
        assert_eq!(f.next_message(), None);
        f.push(b"P\n");
        assert_eq!(f.next_message(), None);
        f.push(b"\nBM\n00P\n\nVV");
        assert_eq!(f.next_message().unwrap(), b"QT\n00P\n\n");
        assert_eq!(f.next_message().unwrap(), b"BM\n00P\n\n");
        assert_eq!(f.next_message(), None);
        assert_eq!(f.pending(), 2);
        f.push(&vec![b'x'; MAX_MESSAGE + 1]);
        assert_eq!(f.next_message(), None);
        assert_eq!(f.overflows(), 1);
        assert_eq!(f.pending(), 0);
    }
}
