//! The connection records of a bag's index section (after the chunks, at the bag header's
//! `index_pos`), read before the chunks when the bag is a regular file on disk (version 2.0;
//! not standard input or a pipe; a gzipped bag has no bag header to find, so it gets none).
//! They stand in for connection records lost in a record or chunk that could not be read:
//!
//! - a message on a connection that no record read so far declared takes the index section's
//!   record, and before it the indexed connections numbered below it that are not declared
//!   either (bags number their connections in the order they declare them, so those were
//!   declared before it, in what was lost);
//! - once a record or chunk could not be read, a connection the records declare is preceded
//!   the same way by the indexed connections numbered below it,
//!
//! so that the scans of the chunks after a damaged first chunk are read, on the topic the whole
//! bag would give. Nothing else of the index section is used (the reader never walks by it:
//! the index data records of the CCNY `demo.bag` declare wrong lengths), a connection the
//! records declare keeps their record, an index section that does not parse is passed over,
//! and at most [`MAX_HEADER_BYTES`] of connection data are kept.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use super::records::{RecordHeader, for_each_field, op};
use super::{MAGIC, MAX_HEADER_BYTES};

/// An index section's connection record: its `topic` header field and its data.
#[derive(Debug, Clone)]
pub(super) struct IndexedConnection {
    pub(super) topic: Option<Vec<u8>>,
    pub(super) data: Vec<u8>,
}

/// The connection records of the index section of the bag at `path` (a regular file), by
/// connection number; none when the bag has no index section or it cannot be read.
pub(super) fn indexed_connections(path: &Path) -> BTreeMap<u32, IndexedConnection> {
    read(path).unwrap_or_default()
}

fn read(path: &Path) -> Option<BTreeMap<u32, IndexedConnection>> {
    // A pipe would give its bytes to this read instead of the reader's.
    let len = std::fs::metadata(path).ok().filter(|m| m.is_file())?.len();
    if len <= MAGIC.len() as u64 {
        return None;
    }
    let mut file = Bounded {
        file: BufReader::new(File::open(path).ok()?),
        left: len,
    };
    let mut magic = [0u8; MAGIC.len()];
    file.read(&mut magic)?;
    if &magic != MAGIC {
        return None;
    }
    let header = file.block()?;
    let h = RecordHeader::parse(&header).ok()?;
    if h.op != Some(op::BAG_HEADER) {
        return None;
    }
    let index_pos = index_pos(&header)?;
    // The index section follows the bag header and the chunks.
    if index_pos <= MAGIC.len() as u64 || index_pos >= len {
        return None;
    }
    file.file.seek(SeekFrom::Start(index_pos)).ok()?;
    file.left = len - index_pos;
    let mut out = BTreeMap::new();
    let mut kept = 0u64;
    // Connection and chunk info records, up to the end or the first other record.
    while let Some(header) = file.block() {
        let h = RecordHeader::parse(&header).ok()?;
        match (h.op, h.conn) {
            (Some(op::CONNECTION), Some(conn)) => {
                let data = file.block()?;
                kept += data.len() as u64;
                if kept > MAX_HEADER_BYTES {
                    break;
                }
                let topic = h.topic.map(<[u8]>::to_vec);
                out.entry(conn).or_insert(IndexedConnection { topic, data });
            }
            (Some(op::CHUNK_INFO), _) => {
                let mut data_len = [0u8; 4];
                file.read(&mut data_len)?;
                file.skip(u64::from(u32::from_le_bytes(data_len)))?;
            }
            _ => break,
        }
    }
    Some(out)
}

/// The `index_pos` field of a bag header record's header.
fn index_pos(header: &[u8]) -> Option<u64> {
    let mut pos = None;
    for_each_field(header, |name, value| {
        if name == b"index_pos" {
            pos = value.try_into().ok().map(u64::from_le_bytes);
        }
        Ok(())
    })
    .ok()?;
    pos
}

/// A file and the bytes left in it: no length read from it allocates beyond its end.
struct Bounded {
    file: BufReader<File>,
    left: u64,
}

impl Bounded {
    fn read(&mut self, buf: &mut [u8]) -> Option<()> {
        self.file.read_exact(buf).ok()?;
        self.left = self.left.saturating_sub(buf.len() as u64);
        Some(())
    }

    fn skip(&mut self, n: u64) -> Option<()> {
        if n > self.left {
            return None;
        }
        self.file.seek_relative(i64::try_from(n).ok()?).ok()?;
        self.left -= n;
        Some(())
    }

    /// A `len: u32` and `len` bytes, at most [`MAX_HEADER_BYTES`] of them and no more than
    /// the file holds.
    fn block(&mut self) -> Option<Vec<u8>> {
        let mut len = [0u8; 4];
        self.read(&mut len)?;
        let len = u64::from(u32::from_le_bytes(len));
        if len > MAX_HEADER_BYTES || len > self.left {
            return None;
        }
        let mut out = vec![0u8; usize::try_from(len).ok()?];
        self.read(&mut out)?;
        Some(out)
    }
}
