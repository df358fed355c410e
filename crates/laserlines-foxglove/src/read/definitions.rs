//! The `Schema` and `Channel` records of an MCAP file's summary section, read before the data
//! section when the file can be read from its end (a regular file on disk; not standard input
//! or a pipe; a gzipped file has no MCAP footer to find, so it gets none). They stand in for
//! definitions the data section lost in a record or chunk that could not be read:
//!
//! - a message on a channel that the data section has not defined takes the summary's
//!   definition, and before it the summary's channels numbered below it that the data section
//!   has not defined either (writers number channels in the order they define them, so those
//!   were defined before it, in what was lost);
//! - once a record or chunk could not be read, a channel the data section defines is preceded
//!   the same way by the summary's channels numbered below it,
//!
//! so that the scans of the chunks after a damaged first chunk are read, on the topic the whole
//! file would give. The summary is not trusted further: a channel the data section defines
//! keeps that definition, a summary that does not parse is passed over, and at most
//! [`MAX_DEFINITION_BYTES`] of definitions are kept.

use std::collections::{BTreeMap, HashMap};
use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use mcap::records::op;

use super::MAGIC;
use super::McapScanSource;
use super::records::{Loc, u16_at};
use super::tail::FOOTER_AND_MAGIC;

/// The most bytes of `Schema` and `Channel` records kept from a summary (a ROS message
/// definition is a few kilobytes).
pub(super) const MAX_DEFINITION_BYTES: u64 = 16 << 20;

/// The summary's `Schema` bodies by id, and its `Channel` bodies by id with their offsets.
#[derive(Debug, Default)]
pub(super) struct SummaryDefinitions {
    schemas: HashMap<u16, Vec<u8>>,
    channels: BTreeMap<u16, (u64, Vec<u8>)>,
}

impl SummaryDefinitions {
    /// The definitions of the summary section of the regular file at `path`; none when it
    /// is not a regular file, has no summary, footer or closing magic, or cannot be read.
    pub(super) fn read(path: &Path) -> Self {
        Self::try_read(path).unwrap_or_default()
    }

    fn try_read(path: &Path) -> Option<Self> {
        // A pipe would give its bytes to this read instead of the reader's.
        if !std::fs::metadata(path).ok()?.is_file() {
            return None;
        }
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
        let (mut at, mut kept) = (start, 0u64);
        // Record by record up to the footer: the definitions read, the rest passed over.
        while at + 9 <= footer_at {
            let mut head = [0u8; 9];
            file.read_exact(&mut head).ok()?;
            let len = u64::from_le_bytes(head[1..9].try_into().ok()?);
            let end = (at + 9).checked_add(len).filter(|&end| end <= footer_at)?;
            if matches!(head[0], op::SCHEMA | op::CHANNEL) {
                kept += len;
                if kept > MAX_DEFINITION_BYTES {
                    break;
                }
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
        let Some(id) = u16_at(&body, 0) else {
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
    /// Defines from the summary the channels numbered below `id` (and `id` itself when
    /// `with_id`) that the data section has not defined, in order, each with its schema when
    /// the data section has not defined that either. A definition that does not parse is
    /// passed over.
    pub(super) fn define_from_summary(&mut self, id: u16, with_id: bool) {
        let upto = if with_id {
            self.summary.channels.range(..=id)
        } else {
            self.summary.channels.range(..id)
        };
        let ids: Vec<u16> = upto.map(|(&c, _)| c).collect();
        for c in ids {
            let Some((at, body)) = self.summary.channels.remove(&c) else {
                continue;
            };
            if self.channels.contains_key(&c) || self.done {
                continue;
            }
            if let Some(schema_id) = u16_at(&body, 2)
                && !self.schemas.contains_key(&schema_id)
                && let Some(schema) = self.summary.schemas.remove(&schema_id)
            {
                let _ = self.handle_schema(&schema);
            }
            let _ = self.handle_channel(&body, Loc::File(at));
        }
    }
}
