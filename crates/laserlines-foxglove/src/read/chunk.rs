//! Chunks: inflated one at a time (zstd, lz4, none), their CRC checked, and their records
//! walked.

use std::io::{self, Read};

use laserlines_io::SkipCounts;

use super::McapScanSource;
use super::records::{Body, Loc, opcode_name};

impl McapScanSource {
    pub(super) fn handle_chunk(&mut self, at: u64, body: &[u8], skipped: &mut SkipCounts) {
        if let Err(found) = self.chunk_records(at, body, skipped) {
            let e = self.syntax(at, "a well-formed Chunk record", found);
            self.pending.push_back(Err(e));
        }
    }

    /// Decompresses a chunk and handles its records; `Err` describes what was wrong with the
    /// chunk (records handled before the problem stay handled).
    pub(super) fn chunk_records(
        &mut self,
        at: u64,
        body: &[u8],
        skipped: &mut SkipCounts,
    ) -> Result<(), String> {
        let mut b = Body::new(body);
        let _start = b.u64("message start time")?;
        let _end = b.u64("message end time")?;
        let size = b.u64("uncompressed size")?;
        let crc = b.u32("uncompressed CRC")?;
        let compression = b.string("compression")?;
        let records_len = b.u64("records length")?;
        let records_offset = b.pos as u64;
        let records = b.bytes(records_len, "records")?;
        if size > self.options.max_record_bytes {
            return Err(format!(
                "an uncompressed size of {size} bytes, over the limit of {}",
                self.options.max_record_bytes
            ));
        }
        let mut out = std::mem::take(&mut self.chunk);
        out.clear();
        let decompressed = match compression.as_str() {
            "" => Ok(false),
            "zstd" => inflate(
                zstd::stream::read::Decoder::with_buffer(records),
                size,
                &mut out,
            ),
            "lz4" => inflate(lz4::Decoder::new(records), size, &mut out),
            other => Err(format!(
                "records compressed with {other:?}, which is not zstd, lz4 or none"
            )),
        };
        let result = decompressed.and_then(|compressed| {
            let data: &[u8] = if compressed { &out } else { records };
            if data.len() as u64 != size {
                return Err(format!(
                    "{} bytes of records, where the chunk declares {size}",
                    data.len()
                ));
            }
            if crc != 0 {
                let got = crc32fast::hash(data);
                if got != crc {
                    return Err(format!(
                        "records whose CRC is {got:08x}, where the chunk declares {crc:08x}"
                    ));
                }
            }
            let base = at + 9 + records_offset;
            self.walk_chunk(
                data,
                |offset| {
                    if compressed {
                        Loc::Chunk { chunk: at, offset }
                    } else {
                        Loc::File(base + offset)
                    }
                },
                skipped,
            )
        });
        self.chunk = out;
        result
    }

    pub(super) fn walk_chunk(
        &mut self,
        data: &[u8],
        loc: impl Fn(u64) -> Loc,
        skipped: &mut SkipCounts,
    ) -> Result<(), String> {
        let mut off = 0usize;
        while off < data.len() && !self.done {
            let left = data.len() - off;
            if left < 9 {
                return Err(format!(
                    "a record header at byte {off} of its records, but only {left} bytes left"
                ));
            }
            let opcode = data[off];
            let mut len_bytes = [0u8; 8];
            len_bytes.copy_from_slice(&data[off + 1..off + 9]);
            let len = u64::from_le_bytes(len_bytes);
            if len > (left - 9) as u64 {
                return Err(format!(
                    "a {} record of {len} bytes at byte {off} of its records, running past \
                     the chunk's end ({} bytes left)",
                    opcode_name(opcode),
                    left - 9
                ));
            }
            let end = off + 9 + len as usize;
            self.handle_record(opcode, &data[off + 9..end], loc(off as u64), skipped);
            off = end;
        }
        Ok(())
    }
}

/// Decompresses into `out`, reading at most one byte more than `size` so that a chunk that
/// inflates beyond its declared size is caught without inflating it all. `Ok(true)`: `out`
/// holds the records.
fn inflate<R: Read>(decoder: io::Result<R>, size: u64, out: &mut Vec<u8>) -> Result<bool, String> {
    let decoder = decoder.map_err(|e| format!("compressed data that cannot be decoded ({e})"))?;
    out.reserve(size.min(1 << 24) as usize);
    decoder
        .take(size.saturating_add(1))
        .read_to_end(out)
        .map_err(|e| format!("compressed data that cannot be decoded ({e})"))?;
    Ok(true)
}
