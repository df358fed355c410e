//! The end of an MCAP file after its `DataEnd` record: the summary section, the `Footer`
//! record and the closing magic. They are skimmed, not trusted: when they are cut short, the
//! messages were all read, and the cut is counted as a skip ([`SKIP_CUT_SUMMARY`]) instead of
//! passing unnoticed. Of the summary only the `Statistics` record is read, and the `Schema`
//! and `Channel` records of channels the data section never defined: the message count per
//! channel tells how many scans of the topic read were in records or chunks that could not be
//! read ([`SKIP_LOST_SCAN`]), so that a skipped chunk reports the scans it held, even when it
//! held the channel's own definition (a file of one chunk).

use std::io::Read;

use laserlines_io::SkipCounts;
use mcap::records::op;

use super::channels::Role;
use super::records::{Body, Loc, u16_at};
use super::{MAGIC, McapScanSource};

/// The skip reason of a file whose summary section, footer or closing magic is cut short.
pub const SKIP_CUT_SUMMARY: &str =
    "cut summary section (footer or closing magic missing; every message was read)";

/// The skip reason of scans of the topic read that the file's `Statistics` record counts but
/// that were in a record or chunk that could not be read.
pub const SKIP_LOST_SCAN: &str =
    "scan in a record or chunk that could not be read (counted by the file's statistics)";

/// A `Footer` record (opcode, length 20, three numbers) and the closing magic.
pub(super) const FOOTER_AND_MAGIC: usize = 9 + 20 + 8;

/// The most summary bytes kept (its first ones) to look for the `Statistics` record.
const MAX_SUMMARY_BYTES: usize = 64 << 20;

impl McapScanSource {
    /// Reads the rest of the input after `DataEnd` and checks that it ends with a `Footer`
    /// record and the magic; counts [`SKIP_CUT_SUMMARY`] when it does not, and
    /// [`SKIP_LOST_SCAN`] for the scans the statistics count but the reader never met. Then
    /// ends the input.
    pub(super) fn skim_summary(&mut self, skipped: &mut SkipCounts) {
        let mut buf = [0u8; 8192];
        let mut summary = Vec::new();
        // The last bytes seen.
        let mut tail = [0u8; FOOTER_AND_MAGIC];
        let mut total = 0u64;
        loop {
            let n = match self.input.read(&mut buf) {
                Ok(0) => break,
                Ok(n) => n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => return self.io_error(self.pos + total, e),
            };
            total += n as u64;
            // The summary's first bytes only, without gaps (the statistics come early).
            let room = MAX_SUMMARY_BYTES - summary.len();
            summary.extend_from_slice(&buf[..n.min(room)]);
            let keep = n.min(FOOTER_AND_MAGIC);
            tail.copy_within(keep.., 0);
            tail[FOOTER_AND_MAGIC - keep..].copy_from_slice(&buf[n - keep..n]);
        }
        let whole = total >= FOOTER_AND_MAGIC as u64
            && tail[0] == op::FOOTER
            && tail[1..9] == 20u64.to_le_bytes()
            && tail[FOOTER_AND_MAGIC - 8..] == MAGIC;
        if !whole {
            skipped.add(SKIP_CUT_SUMMARY);
        }
        self.learn_channels(&summary, self.pos);
        skipped.add_n(SKIP_LOST_SCAN, self.scans_never_met(&summary));
        self.pos += total;
        self.finish_input(self.pos);
    }

    /// Takes the `Schema` and `Channel` records of the summary (which starts at byte `start`)
    /// for the schemas and channels the data section did not define: their definitions were in
    /// a record or chunk that could not be read. A summary record that does not parse is passed
    /// over; the summary is not trusted.
    fn learn_channels(&mut self, summary: &[u8], start: u64) {
        let mut at = 0usize;
        while let Some((opcode, body)) = record_at(summary, at) {
            match (opcode, u16_at(body, 0)) {
                (op::SCHEMA, Some(id)) if !self.schemas.contains_key(&id) => {
                    let _ = self.handle_schema(body);
                }
                (op::CHANNEL, Some(id)) if !self.channels.contains_key(&id) => {
                    let _ = self.handle_channel(body, Loc::File(start + at as u64));
                }
                (op::FOOTER, _) => return,
                _ => {}
            }
            at += 9 + body.len();
        }
    }

    /// The scans of the topic read that the summary's `Statistics` record counts beyond those
    /// met; 0 without statistics (they are optional) or when they do not parse.
    fn scans_never_met(&self, summary: &[u8]) -> u64 {
        let Some(counts) = statistics(summary) else {
            return 0;
        };
        counts
            .into_iter()
            .filter(|(id, _)| {
                self.channels.get(id).is_some_and(|c| {
                    matches!(c.role, Role::Scan(..))
                        && self.topic.as_deref() == Some(c.topic.as_str())
                })
            })
            .map(|(id, n)| n.saturating_sub(self.seen.get(&id).copied().unwrap_or(0)))
            .sum()
    }
}

/// The record at byte `at` of `summary`: its opcode and body, when it is there whole.
fn record_at(summary: &[u8], at: usize) -> Option<(u8, &[u8])> {
    let head = summary.get(at..at.checked_add(9)?)?;
    let len = usize::try_from(u64::from_le_bytes(head[1..9].try_into().ok()?)).ok()?;
    let body = summary.get(at + 9..(at + 9).checked_add(len)?)?;
    Some((head[0], body))
}

/// The channel message counts of the first `Statistics` record among the summary's records.
fn statistics(summary: &[u8]) -> Option<Vec<(u16, u64)>> {
    let mut at = 0usize;
    while let Some((opcode, body)) = record_at(summary, at) {
        if opcode == op::STATISTICS {
            return channel_counts(body).ok();
        }
        if opcode == op::FOOTER {
            return None;
        }
        at += 9 + body.len();
    }
    None
}

/// Parses a `Statistics` body down to its `channel_message_counts` map.
fn channel_counts(body: &[u8]) -> Result<Vec<(u16, u64)>, String> {
    let mut b = Body::new(body);
    b.u64("message count")?;
    b.u16("schema count")?;
    b.u32("channel count")?;
    b.u32("attachment count")?;
    b.u32("metadata count")?;
    b.u32("chunk count")?;
    b.u64("message start time")?;
    b.u64("message end time")?;
    let len = b.u32("channel message counts length")?;
    let mut map = Body::new(b.bytes(u64::from(len), "channel message counts")?);
    let mut out = Vec::new();
    for _ in 0..len / 10 {
        out.push((map.u16("channel id")?, map.u64("message count")?));
    }
    Ok(out)
}
