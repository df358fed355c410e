//! The layout and values of a scan reply (`MD`, `MS`, `GD`, `GS`): a time stamp line, then
//! the values in data lines of 64 characters, a value possibly running on from one line to
//! the next.

use crate::codec::{self, Encoding};

use super::{Reply, ReplyError};

/// Characters of scan data per line (before the check character); the last line of a
/// scan may be shorter.
pub const DATA_LINE: usize = 64;

impl Reply<'_> {
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
