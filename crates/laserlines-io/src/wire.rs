//! A bounds-checked cursor over a serialized message, shared by the ROS 1 and CDR decoders.

use std::fmt;

/// Why a serialized message could not be decoded: where in the message, which field, and what
/// was wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DecodeError {
    /// Byte offset into the message's serialized data where the field starts.
    pub offset: usize,
    /// The field being read (e.g. `ranges`, `header.frame_id`).
    pub field: &'static str,
    /// What the field must hold.
    pub expected: String,
    /// What the message holds there.
    pub found: String,
}

impl fmt::Display for DecodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} at byte {} of the message: expected {}, found {}",
            self.field, self.offset, self.expected, self.found
        )
    }
}

impl std::error::Error for DecodeError {}

/// Byte order of the numbers in a message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Endian {
    Little,
    Big,
}

/// Reads fixed-size numbers, strings and sequences from a byte slice, never past its end.
///
/// `origin` is where alignment is counted from (CDR aligns relative to the end of the
/// encapsulation header); `align` is a no-op for formats without alignment (ROS 1).
pub(crate) struct Wire<'a> {
    data: &'a [u8],
    pos: usize,
    origin: usize,
    endian: Endian,
    aligned: bool,
}

impl<'a> Wire<'a> {
    /// A cursor at `start`, aligning relative to `start` when `aligned` is set.
    pub(crate) fn new(data: &'a [u8], start: usize, endian: Endian, aligned: bool) -> Self {
        Self {
            data,
            pos: start,
            origin: start,
            endian,
            aligned,
        }
    }

    /// The byte the next read starts at.
    pub(crate) fn position(&self) -> usize {
        self.pos
    }

    fn remaining(&self) -> usize {
        self.data.len().saturating_sub(self.pos)
    }

    fn short(&self, field: &'static str, need: usize) -> DecodeError {
        DecodeError {
            offset: self.pos,
            field,
            expected: format!("{need} more bytes"),
            found: format!("the message ends after {}", self.remaining()),
        }
    }

    /// Skips padding so that the next read starts at a multiple of `n` from the origin.
    pub(crate) fn align(&mut self, n: usize, field: &'static str) -> Result<(), DecodeError> {
        if !self.aligned || n <= 1 {
            return Ok(());
        }
        let rel = self.pos - self.origin;
        let pad = (n - rel % n) % n;
        if pad > self.remaining() {
            return Err(self.short(field, pad));
        }
        self.pos += pad;
        Ok(())
    }

    fn take<const N: usize>(&mut self, field: &'static str) -> Result<[u8; N], DecodeError> {
        self.align(N, field)?;
        let bytes = self
            .data
            .get(self.pos..self.pos + N)
            .and_then(|s| <[u8; N]>::try_from(s).ok())
            .ok_or_else(|| self.short(field, N))?;
        self.pos += N;
        Ok(bytes)
    }

    pub(crate) fn u32(&mut self, field: &'static str) -> Result<u32, DecodeError> {
        let b = self.take::<4>(field)?;
        Ok(match self.endian {
            Endian::Little => u32::from_le_bytes(b),
            Endian::Big => u32::from_be_bytes(b),
        })
    }

    pub(crate) fn i32(&mut self, field: &'static str) -> Result<i32, DecodeError> {
        let b = self.take::<4>(field)?;
        Ok(match self.endian {
            Endian::Little => i32::from_le_bytes(b),
            Endian::Big => i32::from_be_bytes(b),
        })
    }

    pub(crate) fn f32(&mut self, field: &'static str) -> Result<f32, DecodeError> {
        self.u32(field).map(f32::from_bits)
    }

    /// A string: a `u32` byte count, then the bytes. With `nul` (CDR) the count includes a
    /// terminating NUL, which is dropped. Invalid UTF-8 is replaced, not rejected: frame names
    /// are informative only.
    pub(crate) fn string(&mut self, field: &'static str, nul: bool) -> Result<String, DecodeError> {
        let at = self.pos;
        let len = self.u32(field)? as usize;
        if len > self.remaining() {
            return Err(DecodeError {
                offset: at,
                field,
                expected: format!("a string of {len} bytes"),
                found: format!("the message ends after {}", self.remaining()),
            });
        }
        let mut bytes = &self.data[self.pos..self.pos + len];
        self.pos += len;
        if nul {
            bytes = bytes.strip_suffix(&[0]).unwrap_or(bytes);
        }
        Ok(String::from_utf8_lossy(bytes).into_owned())
    }

    /// A sequence of `f32`: a `u32` count, then the values. The count is checked against the
    /// bytes left before anything is allocated.
    pub(crate) fn f32_seq(&mut self, field: &'static str) -> Result<Vec<f32>, DecodeError> {
        let at = self.pos;
        let n = self.u32(field)? as usize;
        self.align(4, field)?;
        let bytes = n.checked_mul(4).filter(|b| *b <= self.remaining());
        let Some(bytes) = bytes else {
            return Err(DecodeError {
                offset: at,
                field,
                expected: format!("{n} float32 values ({} bytes)", n as u64 * 4),
                found: format!("the message ends after {} bytes", self.remaining()),
            });
        };
        let raw = &self.data[self.pos..self.pos + bytes];
        self.pos += bytes;
        let endian = self.endian;
        Ok(raw
            .chunks_exact(4)
            .map(|c| {
                let b = [c[0], c[1], c[2], c[3]];
                f32::from_bits(match endian {
                    Endian::Little => u32::from_le_bytes(b),
                    Endian::Big => u32::from_be_bytes(b),
                })
            })
            .collect())
    }

    /// A sequence of `sensor_msgs/LaserEcho` (each a sequence of `f32`): the first value of
    /// each, NaN for one with none, and how many values past the first were left out. The
    /// count is checked against the bytes left (4 at least per echo list) before anything is
    /// allocated.
    pub(crate) fn first_echoes(
        &mut self,
        field: &'static str,
    ) -> Result<(Vec<f32>, usize), DecodeError> {
        let at = self.pos;
        let n = self.u32(field)? as usize;
        if n.checked_mul(4).is_none_or(|b| b > self.remaining()) {
            return Err(DecodeError {
                offset: at,
                field,
                expected: format!("{n} echo lists (at least {} bytes)", n as u64 * 4),
                found: format!("the message ends after {} bytes", self.remaining()),
            });
        }
        let mut firsts = Vec::with_capacity(n);
        let mut more = 0;
        for _ in 0..n {
            let list_at = self.pos;
            let m = self.u32(field)? as usize;
            let bytes = m.checked_mul(4).filter(|b| *b <= self.remaining());
            let Some(bytes) = bytes else {
                return Err(DecodeError {
                    offset: list_at,
                    field,
                    expected: format!(
                        "echo list {} of {n}: {m} float32 values ({} bytes)",
                        firsts.len(),
                        m as u64 * 4
                    ),
                    found: format!("the message ends after {} bytes", self.remaining()),
                });
            };
            let first = if m == 0 {
                f32::NAN
            } else {
                let c = &self.data[self.pos..self.pos + 4];
                let b = [c[0], c[1], c[2], c[3]];
                f32::from_bits(match self.endian {
                    Endian::Little => u32::from_le_bytes(b),
                    Endian::Big => u32::from_be_bytes(b),
                })
            };
            self.pos += bytes;
            firsts.push(first);
            more += m.saturating_sub(1);
        }
        Ok((firsts, more))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn alignment_counts_from_the_origin() {
        // origin 4; a u8-sized string leaves pos at 4 + 4 + 2 = 10; a u32 then aligns to 12.
        let mut data = vec![0, 1, 0, 0];
        data.extend_from_slice(&2u32.to_le_bytes());
        data.extend_from_slice(b"a\0");
        data.extend_from_slice(&[0xff, 0xff]);
        data.extend_from_slice(&7u32.to_le_bytes());
        let mut w = Wire::new(&data, 4, Endian::Little, true);
        assert_eq!(w.string("s", true).unwrap(), "a");
        assert_eq!(w.u32("n").unwrap(), 7);
        assert!(w.u32("x").is_err());
    }

    #[test]
    fn huge_sequence_counts_are_errors_not_allocations() {
        let data = u32::MAX.to_le_bytes();
        let mut w = Wire::new(&data, 0, Endian::Little, false);
        let e = w.f32_seq("ranges").unwrap_err();
        assert_eq!(e.field, "ranges");
        assert_eq!(e.offset, 0);
        assert!(e.expected.contains("4294967295 float32"), "{e}");
    }
}
