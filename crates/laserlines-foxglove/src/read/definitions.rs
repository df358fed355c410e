//! The `Schema` and `Channel` records of an MCAP file's summary section, read before the data
//! section when the file can be read from its end (a file on disk, not gzipped; not standard
//! input). They stand in for definitions the data section lost: a message on a channel that
//! the data section has not defined (its `Channel` record was in a chunk that could not be
//! read) takes the summary's definition, so that the scans of the chunks after a damaged
//! first chunk are read. The summary is not trusted further: a channel the data section
//! defines keeps that definition, and a summary that does not parse is passed over.

use std::collections::HashMap;
use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use mcap::records::op;

use super::MAGIC;
use super::McapScanSource;
use super::records::Loc;
use super::tail::FOOTER_AND_MAGIC;

/// The largest `Schema` or `Channel` record taken from the summary, bytes (a ROS message
/// definition is a few kilobytes).
const MAX_DEFINITION_BYTES: u64 = 16 << 20;

/// The summary's `Schema` bodies by id, and its `Channel` bodies by id with their offsets.
#[derive(Debug, Default)]
pub(super) struct SummaryDefinitions {
    schemas: HashMap<u16, Vec<u8>>,
    channels: HashMap<u16, (u64, Vec<u8>)>,
}

impl SummaryDefinitions {
    /// The definitions of the file at `path`'s summary section; none when the file has no
    /// summary, no footer or closing magic, or cannot be read.
    pub(super) fn read(path: &Path) -> Self {
        Self::try_read(path).unwrap_or_default()
    }

    fn try_read(path: &Path) -> Option<Self> {
        let mut file = BufReader::new(File::open(path).ok()?);
        let len = file.get_ref().metadata().ok()?.len();
        let footer_at = len.checked_sub(FOOTER_AND_MAGIC as u64)?;
        let mut tail = [0u8; FOOTER_AND_MAGIC];
        file.seek(SeekFrom::Start(footer_at)).ok()?;
        file.read_exact(&mut tail).ok()?;
        if tail[0] != op::FOOTER
            || tail[1..9] != 20u64.to_le_bytes()
            || tail[FOOTER_AND_MAGIC - 8..] != MAGIC
        {
            return None;
        }
        let start = u64::from_le_bytes(tail[9..17].try_into().ok()?);
        // 0: no summary section. It starts after the magic and ends at the footer.
        if start < MAGIC.len() as u64 || start >= footer_at {
            return None;
        }
        file.seek(SeekFrom::Start(start)).ok()?;
        let mut out = Self::default();
        let mut at = start;
        // Record by record up to the footer: the definitions read, the rest passed over.
        while at + 9 <= footer_at {
            let mut head = [0u8; 9];
            file.read_exact(&mut head).ok()?;
            let len = u64::from_le_bytes(head[1..9].try_into().ok()?);
            let end = (at + 9).checked_add(len).filter(|&end| end <= footer_at)?;
            if matches!(head[0], op::SCHEMA | op::CHANNEL) && len <= MAX_DEFINITION_BYTES {
                let mut body = vec![0u8; usize::try_from(len).ok()?];
                file.read_exact(&mut body).ok()?;
                out.take(head[0], at, body);
            } else {
                file.seek_relative(i64::try_from(len).ok()?).ok()?;
            }
            at = end;
        }
        Some(out)
    }

    /// Keeps a `Schema` or `Channel` record (`opcode`) at byte `at`: the first one of its id.
    fn take(&mut self, opcode: u8, at: u64, body: Vec<u8>) {
        // Both records start with their id.
        let Some(id) = body.get(..2).map(|b| u16::from_le_bytes([b[0], b[1]])) else {
            return;
        };
        if opcode == op::SCHEMA {
            self.schemas.entry(id).or_insert(body);
        } else {
            self.channels.entry(id).or_insert((at, body));
        }
    }
}

impl McapScanSource {
    /// Defines channel `id`, which the data section has not defined, from the summary, and
    /// before it the summary's channels numbered below it that are not defined either, in
    /// order: writers number channels in the order they define them, so those were defined
    /// before it, in the chunk that was lost, and the topic is chosen as it would have been.
    /// A channel's schema comes from the summary too when the data section has not defined
    /// it. A definition that does not parse is passed over.
    pub(super) fn define_from_summary(&mut self, id: u16) {
        let mut earlier: Vec<u16> = (self.summary.channels.keys().copied())
            .filter(|&c| c <= id)
            .collect();
        earlier.sort_unstable();
        for c in earlier {
            let Some((at, body)) = self.summary.channels.remove(&c) else {
                continue;
            };
            if self.channels.contains_key(&c) {
                continue;
            }
            let schema_id = body.get(2..4).map(|b| u16::from_le_bytes([b[0], b[1]]));
            if let Some(schema_id) = schema_id
                && !self.schemas.contains_key(&schema_id)
                && let Some(schema) = self.summary.schemas.remove(&schema_id)
            {
                let _ = self.handle_schema(&schema);
            }
            let _ = self.handle_channel(&body, Loc::File(at));
        }
    }
}
