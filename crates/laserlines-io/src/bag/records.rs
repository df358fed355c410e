//! The records of a bag: their headers and fields, where they are (for errors), the framing
//! of a record inside a chunk, and a reader that counts the bytes it has read.

use std::io::{self, Read};

use crate::error::{ReadError, SourcePos};
use crate::reader::Input;

/// Record op codes.
pub(super) mod op {
    /// Version 1.2 only: a topic's message definition.
    pub(crate) const MESSAGE_DEFINITION: u8 = 0x01;
    pub(crate) const MESSAGE_DATA: u8 = 0x02;
    pub(crate) const BAG_HEADER: u8 = 0x03;
    pub(crate) const INDEX_DATA: u8 = 0x04;
    pub(crate) const CHUNK: u8 = 0x05;
    pub(crate) const CHUNK_INFO: u8 = 0x06;
    pub(crate) const CONNECTION: u8 = 0x07;
}

/// What was expected and what was found, for an error message.
pub(super) struct Bad {
    pub(super) expected: String,
    pub(super) found: String,
}

impl Bad {
    pub(super) fn new(expected: impl Into<String>, found: impl Into<String>) -> Self {
        Self {
            expected: expected.into(),
            found: found.into(),
        }
    }
}

/// Calls `f` with the name and value of every `field_len: u32, name=value` field of `raw`.
pub(super) fn for_each_field<'a>(
    raw: &'a [u8],
    mut f: impl FnMut(&'a [u8], &'a [u8]) -> Result<(), Bad>,
) -> Result<(), Bad> {
    let mut at = 0usize;
    while at < raw.len() {
        let rest = &raw[at..];
        let Some(len) = read_u32(rest, 0) else {
            return Err(Bad::new(
                format!("a field length (4 bytes) at header byte {at}"),
                format!("{} bytes", rest.len()),
            ));
        };
        let len = len as usize;
        let Some(field) = 4usize.checked_add(len).and_then(|end| rest.get(4..end)) else {
            return Err(Bad::new(
                format!("a field of {len} bytes at header byte {at}"),
                format!("{} bytes left in the header", rest.len() - 4),
            ));
        };
        let Some(eq) = field.iter().position(|b| *b == b'=') else {
            return Err(Bad::new(
                format!("a `name=value` field at header byte {at}"),
                "no `=`",
            ));
        };
        f(&field[..eq], &field[eq + 1..])?;
        at += 4 + len;
    }
    Ok(())
}

pub(super) fn read_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// The fields of a record header this reader uses.
#[derive(Default)]
pub(super) struct RecordHeader<'a> {
    pub(super) op: Option<u8>,
    pub(super) conn: Option<u32>,
    pub(super) time: Option<(u32, u32)>,
    pub(super) topic: Option<&'a [u8]>,
    /// Version 1.2: the message type and the record time, in the record header.
    pub(super) kind: Option<&'a [u8]>,
    pub(super) sec: Option<u32>,
    pub(super) nsec: Option<u32>,
    pub(super) compression: Option<&'a [u8]>,
    pub(super) size: Option<u32>,
    pub(super) ver: Option<u32>,
    pub(super) count: Option<u32>,
}

impl<'a> RecordHeader<'a> {
    pub(super) fn parse(raw: &'a [u8]) -> Result<Self, Bad> {
        let mut h = Self::default();
        for_each_field(raw, |name, value| {
            let u32_field = |v: &[u8]| -> Result<u32, Bad> {
                read_u32(v, 0).filter(|_| v.len() == 4).ok_or_else(|| {
                    Bad::new(
                        format!("a 4-byte `{}` field", String::from_utf8_lossy(name)),
                        format!("{} bytes", v.len()),
                    )
                })
            };
            match name {
                b"op" => match value {
                    [op] => h.op = Some(*op),
                    _ => {
                        return Err(Bad::new(
                            "a 1-byte `op` field",
                            format!("{} bytes", value.len()),
                        ));
                    }
                },
                b"conn" => h.conn = Some(u32_field(value)?),
                b"time" => {
                    if value.len() != 8 {
                        return Err(Bad::new(
                            "an 8-byte `time` field",
                            format!("{} bytes", value.len()),
                        ));
                    }
                    let secs = read_u32(value, 0).unwrap_or(0);
                    let nsecs = read_u32(value, 4).unwrap_or(0);
                    h.time = Some((secs, nsecs));
                }
                b"topic" => h.topic = Some(value),
                b"type" => h.kind = Some(value),
                b"sec" => h.sec = Some(u32_field(value)?),
                b"nsec" => h.nsec = Some(u32_field(value)?),
                b"compression" => h.compression = Some(value),
                b"size" => h.size = Some(u32_field(value)?),
                b"ver" => h.ver = Some(u32_field(value)?),
                b"count" => h.count = Some(u32_field(value)?),
                _ => {}
            }
            Ok(())
        })?;
        Ok(h)
    }

    pub(super) fn op(&self) -> Result<u8, Bad> {
        self.op
            .ok_or_else(|| Bad::new("an `op` field in the record header", "none"))
    }

    pub(super) fn conn(&self) -> Result<u32, Bad> {
        self.conn
            .ok_or_else(|| Bad::new("a `conn` field in the record header", "none"))
    }
}

/// Where a record sits, for errors.
#[derive(Debug, Clone, Copy)]
pub(super) enum Loc {
    /// At this byte of the file.
    File(u64),
    /// Inside a compressed chunk: the chunk record's byte in the file, the compression and
    /// the offset in the decompressed data.
    Compressed {
        chunk: u64,
        compression: &'static str,
        offset: usize,
    },
}

impl Loc {
    pub(super) fn pos(self, file: &str) -> SourcePos {
        match self {
            Self::File(at) | Self::Compressed { chunk: at, .. } => SourcePos::byte(file, at),
        }
    }

    /// `""`, or ` (at offset N of the decompressed bz2 chunk)`.
    pub(super) fn context(self) -> String {
        match self {
            Self::File(_) => String::new(),
            Self::Compressed {
                compression,
                offset,
                ..
            } => format!(" (at offset {offset} of the decompressed {compression} chunk)"),
        }
    }

    pub(super) fn error(self, file: &str, bad: Bad) -> ReadError {
        ReadError::Syntax {
            pos: self.pos(file),
            expected: format!("{}{}", bad.expected, self.context()),
            found: bad.found,
        }
    }
}

/// The input with a count of the bytes consumed.
pub(super) struct Counted {
    pub(super) input: Input,
    pub(super) pos: u64,
}

impl Counted {
    /// Fills `buf` unless the input ends; returns how many bytes were read.
    pub(super) fn read_full(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let mut got = 0;
        while got < buf.len() {
            match self.input.read(&mut buf[got..]) {
                Ok(0) => break,
                Ok(n) => got += n,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => {
                    self.pos += got as u64;
                    return Err(e);
                }
            }
        }
        self.pos += got as u64;
        Ok(got)
    }

    /// Reads up to `len` bytes into `out` (cleared first), growing it as bytes arrive.
    pub(super) fn read_vec(&mut self, len: u64, out: &mut Vec<u8>) -> io::Result<u64> {
        out.clear();
        let got = (&mut self.input).take(len).read_to_end(out)? as u64;
        self.pos += got;
        Ok(got)
    }

    /// Skips up to `len` bytes; returns how many were skipped.
    pub(super) fn skip(&mut self, len: u64) -> io::Result<u64> {
        let got = io::copy(&mut (&mut self.input).take(len), &mut io::sink())?;
        self.pos += got;
        Ok(got)
    }
}

/// Splits the record at `at` of a chunk: its header, its data and the offset after it.
pub(super) fn frame(data: &[u8], at: usize) -> Result<(&[u8], &[u8], usize), Bad> {
    let left = data.len() - at;
    let header_len = read_u32(data, at).ok_or_else(|| {
        Bad::new(
            "a record header length (4 bytes)",
            format!("{left} bytes left in the chunk"),
        )
    })? as usize;
    let header_start = at + 4;
    let header = header_start
        .checked_add(header_len)
        .and_then(|end| data.get(header_start..end))
        .ok_or_else(|| {
            Bad::new(
                format!("a record header of {header_len} bytes"),
                format!("{} bytes left in the chunk", left.saturating_sub(4)),
            )
        })?;
    let data_len_at = header_start + header_len;
    let data_len = read_u32(data, data_len_at).ok_or_else(|| {
        Bad::new(
            "a record data length (4 bytes)",
            format!("{} bytes left in the chunk", data.len() - data_len_at),
        )
    })? as usize;
    let body_start = data_len_at + 4;
    let body = body_start
        .checked_add(data_len)
        .and_then(|end| data.get(body_start..end))
        .ok_or_else(|| {
            Bad::new(
                format!("record data of {data_len} bytes"),
                format!("{} bytes left in the chunk", data.len() - body_start),
            )
        })?;
    Ok((header, body, body_start + data_len))
}
