//! Chunks: read, checked, decompressed (bz2, lz4) and walked record by record.

use std::io::Read;

use crate::error::ReadError;
use crate::record::ScanRecord;
use crate::skip::SkipCounts;

use super::records::{Bad, Loc, RecordHeader, frame, op};
use super::{BagSource, SKIP_UNKNOWN_RECORD};

/// One decompressed chunk being read.
pub(super) struct Chunk {
    pub(super) data: Vec<u8>,
    /// Offset of the next record in `data`.
    pub(super) at: usize,
    /// Byte of the chunk record in the file.
    pub(super) record: u64,
    /// Byte of `data[0]` in the file, for uncompressed chunks.
    pub(super) data_in_file: Option<u64>,
    pub(super) compression: &'static str,
}

impl Chunk {
    pub(super) fn loc(&self, offset: usize) -> Loc {
        match self.data_in_file {
            Some(start) => Loc::File(start + offset as u64),
            None => Loc::Compressed {
                chunk: self.record,
                compression: self.compression,
                offset,
            },
        }
    }
}

impl BagSource {
    /// Reads a chunk record's data and decompresses it.
    pub(super) fn read_chunk(
        &mut self,
        start: u64,
        data_start: u64,
        data_len: u64,
        compression: Option<Vec<u8>>,
        size: Option<u32>,
    ) -> Result<Option<Result<ScanRecord, ReadError>>, ReadError> {
        let loc = Loc::File(start);
        let checked = chunk_kind(compression.as_deref(), size, data_len, self.max_chunk_bytes);
        let (compression, size) = match checked {
            Ok(c) => c,
            Err(bad) => {
                self.skip_data(start, data_len, "chunk data")?;
                return Ok(Some(Err(loc.error(&self.name, bad))));
            }
        };
        let mut raw = std::mem::take(&mut self.raw);
        if compression == "none" {
            // Cut short by the end of the input, the chunk's complete records are read before
            // the truncation ends the reader.
            let got = self
                .input
                .read_vec(data_len, &mut raw)
                .map_err(|e| self.io_error(e))?;
            if got < data_len {
                self.cut = Some(self.truncated(start, "chunk data", data_len, got));
            }
            self.chunk = Some(Chunk {
                data: raw,
                at: 0,
                record: start,
                data_in_file: Some(data_start),
                compression,
            });
            return Ok(None);
        }
        self.read_data(start, data_len, "chunk data", &mut raw)?;
        let data = self.decompress(&raw, compression, size);
        self.raw = raw;
        let data = match data {
            Ok(data) => data,
            Err(bad) => return Ok(Some(Err(loc.error(&self.name, bad)))),
        };
        self.chunk = Some(Chunk {
            data,
            at: 0,
            record: start,
            data_in_file: None,
            compression,
        });
        Ok(None)
    }

    /// The `size` bytes of a `bz2` or `lz4` chunk's data, decompressed into the spare buffer.
    fn decompress(&mut self, raw: &[u8], compression: &str, size: u32) -> Result<Vec<u8>, Bad> {
        let mut out = std::mem::take(&mut self.spare);
        out.clear();
        let result = if compression == "bz2" {
            bzip2::read::BzDecoder::new(raw)
                .take(u64::from(size) + 1)
                .read_to_end(&mut out)
        } else {
            lz4_flex::frame::FrameDecoder::new(raw)
                .take(u64::from(size) + 1)
                .read_to_end(&mut out)
        };
        match result {
            Ok(n) if n as u64 == u64::from(size) => Ok(out),
            Ok(n) => Err(Bad::new(
                format!("{size} bytes out of the {compression} chunk, as its `size` says"),
                if n as u64 > u64::from(size) {
                    "more".to_owned()
                } else {
                    format!("{n} bytes")
                },
            )),
            Err(e) => Err(Bad::new(
                format!("{compression}-compressed chunk data"),
                format!("data that does not decompress: {e}"),
            )),
        }
    }

    /// Reads the next record of the current chunk. `None` when the chunk is done.
    pub(super) fn chunk_record(
        &mut self,
        skipped: &mut SkipCounts,
    ) -> Option<Result<ScanRecord, ReadError>> {
        loop {
            let chunk = self.chunk.as_mut()?;
            let at = chunk.at;
            if at >= chunk.data.len() {
                let done = self.chunk.take();
                if let Some(done) = done {
                    self.spare = done.data;
                }
                return None;
            }
            let loc = chunk.loc(at);
            let data = &chunk.data;
            let framed = frame(data, at);
            let (header, body, next) = match framed {
                Ok(f) => f,
                Err(bad) => {
                    // The chunk's framing is lost: drop its rest, go on with the next record
                    // (in a chunk cut short, the record the end of the input cut says so).
                    chunk.at = data.len();
                    if self.cut.is_some() {
                        continue;
                    }
                    return Some(Err(loc.error(&self.name, bad)));
                }
            };
            chunk.at = next;
            let body_loc = chunk.loc(next - body.len());
            let parsed = RecordHeader::parse(header).and_then(|h| h.op().map(|op| (h, op)));
            let result = match parsed {
                Err(bad) => Some(Err(loc.error(&self.name, bad))),
                Ok((h, op::CONNECTION)) => h
                    .conn()
                    .and_then(|conn| self.state.connection(conn, h.topic, body))
                    .err()
                    .map(|bad| Err(loc.error(&self.name, bad))),
                Ok((h, op::MESSAGE_DATA)) => match h.conn() {
                    Err(bad) => Some(Err(loc.error(&self.name, bad))),
                    Ok(conn) => self
                        .state
                        .message(conn, h.time, body, body_loc, skipped)
                        .transpose(),
                },
                Ok(_) => {
                    skipped.add(SKIP_UNKNOWN_RECORD);
                    None
                }
            };
            if result.is_some() {
                return result;
            }
        }
    }
}

/// The compression and decompressed size of a chunk from its header's fields, checked
/// against `max` bytes (compressed or not).
fn chunk_kind(
    compression: Option<&[u8]>,
    size: Option<u32>,
    data_len: u64,
    max: u64,
) -> Result<(&'static str, u32), Bad> {
    let too_big = |what: &str, len: u64| {
        Bad::new(
            format!("a chunk of at most {max} bytes"),
            format!("{len} bytes {what}"),
        )
    };
    match (compression, size) {
        (None, _) => Err(Bad::new(
            "a `compression` field in the chunk header",
            "none",
        )),
        (_, None) => Err(Bad::new("a `size` field in the chunk header", "none")),
        (_, Some(size)) if u64::from(size) > max => Err(too_big("decompressed", u64::from(size))),
        _ if data_len > max => Err(too_big("compressed", data_len)),
        (Some(b"none"), Some(size)) => Ok(("none", size)),
        (Some(b"bz2"), Some(size)) => Ok(("bz2", size)),
        (Some(b"lz4"), Some(size)) => Ok(("lz4", size)),
        (Some(other), _) => Err(Bad::new(
            "chunk compression `none`, `bz2` or `lz4`",
            format!("`{}`", String::from_utf8_lossy(other).escape_debug()),
        )),
    }
}
