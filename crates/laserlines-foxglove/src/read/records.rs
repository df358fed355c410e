//! The top-level records of an MCAP file: where they are (for errors), a bounds-checked
//! cursor over a record's body, and opcode names.

use std::io::{self, Read};

use mcap::records::op;

/// Where a record sits: at a file offset, or inside a compressed chunk.
#[derive(Debug, Clone, Copy)]
pub(super) enum Loc {
    /// At this byte of the file (also records of uncompressed chunks).
    File(u64),
    /// In the compressed chunk at `chunk`, at byte `offset` of its decompressed records.
    Chunk { chunk: u64, offset: u64 },
}

impl Loc {
    pub(super) fn byte(self) -> u64 {
        match self {
            Self::File(b) => b,
            Self::Chunk { chunk, .. } => chunk,
        }
    }

    /// Words to add to a message about a record in a compressed chunk.
    pub(super) fn context(self) -> String {
        match self {
            Self::File(_) => String::new(),
            Self::Chunk { offset, .. } => {
                format!(" (in the compressed chunk, at byte {offset} of its records)")
            }
        }
    }
}

/// Reads the fields of one record body, never past its end.
pub(super) struct Body<'a> {
    data: &'a [u8],
    pub(super) pos: usize,
}

impl<'a> Body<'a> {
    pub(super) fn new(data: &'a [u8]) -> Self {
        Self { data, pos: 0 }
    }

    pub(super) fn bytes(&mut self, n: u64, what: &str) -> Result<&'a [u8], String> {
        let left = self.data.len() - self.pos;
        if n > left as u64 {
            return Err(format!(
                "{what} of {n} bytes, but the record has {left} bytes left"
            ));
        }
        let n = n as usize;
        let out = &self.data[self.pos..self.pos + n];
        self.pos += n;
        Ok(out)
    }

    pub(super) fn array<const N: usize>(&mut self, what: &str) -> Result<[u8; N], String> {
        let b = self.bytes(N as u64, what)?;
        <[u8; N]>::try_from(b).map_err(|_| format!("{what}: short read"))
    }

    pub(super) fn u16(&mut self, what: &str) -> Result<u16, String> {
        self.array::<2>(what).map(u16::from_le_bytes)
    }

    pub(super) fn u32(&mut self, what: &str) -> Result<u32, String> {
        self.array::<4>(what).map(u32::from_le_bytes)
    }

    pub(super) fn u64(&mut self, what: &str) -> Result<u64, String> {
        self.array::<8>(what).map(u64::from_le_bytes)
    }

    pub(super) fn string(&mut self, what: &str) -> Result<String, String> {
        let n = self.u32(what)?;
        let b = self.bytes(u64::from(n), what)?;
        String::from_utf8(b.to_vec()).map_err(|_| format!("{what} that is not UTF-8"))
    }

    pub(super) fn map(&mut self, what: &str) -> Result<Vec<(String, String)>, String> {
        let n = self.u32(what)?;
        let mut inner = Body::new(self.bytes(u64::from(n), what)?);
        let mut out = Vec::new();
        while inner.pos < inner.data.len() {
            let k = inner.string(what)?;
            let v = inner.string(what)?;
            out.push((k, v));
        }
        Ok(out)
    }

    pub(super) fn rest(&mut self) -> &'a [u8] {
        let out = &self.data[self.pos..];
        self.pos = self.data.len();
        out
    }
}

/// The little-endian `u16` at byte `at` of `bytes`: `Schema` and `Channel` records start
/// with their id, and a `Channel` record's schema id follows it.
pub(super) fn u16_at(bytes: &[u8], at: usize) -> Option<u16> {
    let b = bytes.get(at..at.checked_add(2)?)?;
    Some(u16::from_le_bytes([b[0], b[1]]))
}

pub(super) fn opcode_name(opcode: u8) -> &'static str {
    match opcode {
        op::HEADER => "Header",
        op::FOOTER => "Footer",
        op::SCHEMA => "Schema",
        op::CHANNEL => "Channel",
        op::MESSAGE => "Message",
        op::CHUNK => "Chunk",
        op::MESSAGE_INDEX => "MessageIndex",
        op::CHUNK_INDEX => "ChunkIndex",
        op::ATTACHMENT => "Attachment",
        op::ATTACHMENT_INDEX => "AttachmentIndex",
        op::STATISTICS => "Statistics",
        op::METADATA => "Metadata",
        op::METADATA_INDEX => "MetadataIndex",
        op::SUMMARY_OFFSET => "SummaryOffset",
        op::DATA_END => "DataEnd",
        _ => "unknown",
    }
}

pub(super) fn hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Reads as many bytes as are there, up to `buf.len()`; fewer only at the end of the input.
pub(super) fn read_full(input: &mut dyn Read, buf: &mut [u8]) -> io::Result<usize> {
    let mut got = 0;
    while got < buf.len() {
        match input.read(&mut buf[got..]) {
            Ok(0) => break,
            Ok(n) => got += n,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(got)
}
