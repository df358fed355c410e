//! The end of an MCAP file after its `DataEnd` record: the summary section (indexes and
//! statistics the reader does not use), the `Footer` record and the closing magic. They are
//! skimmed, not parsed: when they are cut short, the messages were all read, and the cut is
//! counted as a skip ([`SKIP_CUT_SUMMARY`]) instead of passing unnoticed.

use std::io::Read;

use laserlines_io::SkipCounts;
use mcap::records::op;

use super::{MAGIC, McapScanSource};

/// The skip reason of a file whose summary section, footer or closing magic is cut short.
pub const SKIP_CUT_SUMMARY: &str =
    "cut summary section (footer or closing magic missing; every message was read)";

/// A `Footer` record (opcode, length 20, three numbers) and the closing magic.
const FOOTER_AND_MAGIC: usize = 9 + 20 + 8;

impl McapScanSource {
    /// Reads the rest of the input after `DataEnd` and checks that it ends with a `Footer`
    /// record and the magic; counts [`SKIP_CUT_SUMMARY`] when it does not. Then ends the
    /// input.
    pub(super) fn skim_summary(&mut self, skipped: &mut SkipCounts) {
        let mut buf = [0u8; 8192];
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
        self.pos += total;
        self.finish_input(self.pos);
    }
}
