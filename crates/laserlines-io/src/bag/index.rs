//! The connection records of a bag's index section (after the chunks, at the bag header's
//! `index_pos`), read before the chunks when the bag is a file on disk (version 2.0, not
//! gzipped; not standard input). They stand in for connection records the chunks lost: a
//! message on a connection that no record read so far declared (its connection record was in
//! a chunk that could not be read) takes the index section's record, so that the scans of the
//! chunks after a damaged first chunk are read. Nothing else of the index is used, and a
//! connection the chunks declare keeps their record: `index_pos` is wrong in some real bags,
//! so an index section that does not parse is passed over.

use std::collections::HashMap;
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

/// The connection records of the index section of the bag at `path`, by connection number;
/// none when the bag has no index section or it cannot be read.
pub(super) fn indexed_connections(path: &Path) -> HashMap<u32, IndexedConnection> {
    read(path).unwrap_or_default()
}

fn read(path: &Path) -> Option<HashMap<u32, IndexedConnection>> {
    let mut file = BufReader::new(File::open(path).ok()?);
    let len = file.get_ref().metadata().ok()?.len();
    let mut magic = [0u8; MAGIC.len()];
    file.read_exact(&mut magic).ok()?;
    if &magic != MAGIC {
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
    file.seek(SeekFrom::Start(index_pos)).ok()?;
    let mut out = HashMap::new();
    // Connection and chunk info records, up to the end or the first other record.
    while let Some(header) = block(&mut file) {
        let h = RecordHeader::parse(&header).ok()?;
        match (h.op, h.conn) {
            (Some(op::CONNECTION), Some(conn)) => {
                let data = block(&mut file)?;
                let topic = h.topic.map(<[u8]>::to_vec);
                out.entry(conn).or_insert(IndexedConnection { topic, data });
            }
            (Some(op::CHUNK_INFO), _) => {
                let mut data_len = [0u8; 4];
                file.read_exact(&mut data_len).ok()?;
                file.seek_relative(i64::from(u32::from_le_bytes(data_len)))
                    .ok()?;
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

/// A `len: u32` and `len` bytes, at most [`MAX_HEADER_BYTES`] of them.
fn block(file: &mut BufReader<File>) -> Option<Vec<u8>> {
    let mut len = [0u8; 4];
    file.read_exact(&mut len).ok()?;
    let len = u32::from_le_bytes(len);
    if u64::from(len) > MAX_HEADER_BYTES {
        return None;
    }
    let mut out = vec![0u8; len as usize];
    file.read_exact(&mut out).ok()?;
    Some(out)
}
