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
use std::io::{BufReader, Seek, SeekFrom};
use std::path::Path;

use super::records::{Counted, RecordHeader, for_each_field, op};
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
    let mut file = counted_at(path, 0)?;
    let mut magic = [0u8; MAGIC.len()];
    if file.read_full(&mut magic).ok()? < magic.len() || &magic != MAGIC {
        return None;
    }
    let header = block(&mut file)?;
    let h = RecordHeader::parse(&header).ok()?;
    if h.op != Some(op::BAG_HEADER) {
        return None;
    }
    let index_pos = index_pos(&header)?;
    // The index section follows the bag header and the chunks.
    if index_pos <= MAGIC.len() as u64 || index_pos >= len {
        return None;
    }
    let mut file = counted_at(path, index_pos)?;
    let mut out = BTreeMap::new();
    let mut kept = 0u64;
    // Connection and chunk info records, up to the end or the first other record.
    while let Some(header) = block(&mut file) {
        let h = RecordHeader::parse(&header).ok()?;
        match (h.op, h.conn) {
            (Some(op::CONNECTION), Some(conn)) => {
                let data = block(&mut file)?;
                kept += data.len() as u64;
                if kept > MAX_HEADER_BYTES {
                    break;
                }
                let topic = h.topic.map(<[u8]>::to_vec);
                out.entry(conn).or_insert(IndexedConnection { topic, data });
            }
            (Some(op::CHUNK_INFO), _) => {
                let mut data_len = [0u8; 4];
                if file.read_full(&mut data_len).ok()? < 4 {
                    break;
                }
                let data_len = u64::from(u32::from_le_bytes(data_len));
                if file.skip(data_len).ok()? < data_len {
                    break;
                }
            }
            _ => break,
        }
    }
    Some(out)
}

/// The file at `path` read from byte `at` on.
fn counted_at(path: &Path, at: u64) -> Option<Counted> {
    let mut file = File::open(path).ok()?;
    file.seek(SeekFrom::Start(at)).ok()?;
    Some(Counted {
        input: Box::new(BufReader::new(file)),
        pos: at,
    })
}

/// A `len: u32` and `len` bytes, at most [`MAX_HEADER_BYTES`] of them; `None` when the input
/// ends first (the bytes are kept as they arrive, so a length the file does not hold
/// allocates no more than the file).
fn block(file: &mut Counted) -> Option<Vec<u8>> {
    let mut len = [0u8; 4];
    if file.read_full(&mut len).ok()? < len.len() {
        return None;
    }
    let len = u64::from(u32::from_le_bytes(len));
    if len > MAX_HEADER_BYTES {
        return None;
    }
    let mut out = Vec::new();
    (file.read_vec(len, &mut out).ok()? == len).then_some(out)
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
