//! What is wrong with a message.

use crate::codec;

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
