//! What reading a scan gives: a whole scan, or a drop and its reason.

use std::time::Instant;

use laserlines::Scan;

use crate::info::NoReturn;

/// Why a scan was dropped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DropReason {
    /// A line's check character did not match (or a character outside the encoding).
    Checksum,
    /// The scan was cut short: a short data line, too few characters, or the connection
    /// ended in the middle of it.
    Truncated,
    /// The scan came with an error status (e.g. `0M` unstable, hardware trouble).
    Status,
    /// Missing from the time stamps' sequence without a reply at all (lost on the way or
    /// not sent).
    Gap,
    /// Made by the sensor while the link was down or being re-established.
    Disconnected,
    /// A scan with a time stamp already delivered.
    Duplicate,
}

impl DropReason {
    /// All reasons, in report order.
    pub const ALL: [Self; 6] = [
        Self::Checksum,
        Self::Truncated,
        Self::Status,
        Self::Gap,
        Self::Disconnected,
        Self::Duplicate,
    ];

    /// A short name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Checksum => "checksum",
            Self::Truncated => "truncated",
            Self::Status => "status",
            Self::Gap => "gap",
            Self::Disconnected => "disconnected",
            Self::Duplicate => "duplicate",
        }
    }
}

/// One scan from the sensor.
#[derive(Debug, Clone, PartialEq)]
pub struct HokuyoScan {
    /// The scan: ranges in metres, `range_min`/`range_max` from `DMIN`/`DMAX` (so the error
    /// codes below `DMIN` are not valid ranges), stamp in host time (s since the epoch).
    pub scan: Scan,
    /// The readings as sent, mm (error codes included).
    pub raw_mm: Vec<u32>,
    /// The sensor's time stamp as sent, ms (24 bits).
    pub sensor_raw_ms: u32,
    /// The sensor's time stamp unwrapped, ms.
    pub sensor_ms: u64,
    /// When the scan's last byte was read.
    pub received: Instant,
    /// Remaining scans of a finite `MD`/`MS` request, as the echo said (0 for unlimited).
    pub remaining: u32,
}

impl HokuyoScan {
    /// The beams that are no return, with the reason the sensor gave.
    pub fn no_returns(
        &self,
        dmin_mm: u32,
        dmax_mm: u32,
    ) -> impl Iterator<Item = (usize, NoReturn)> + '_ {
        self.raw_mm
            .iter()
            .enumerate()
            .filter_map(move |(i, &mm)| NoReturn::classify(mm, dmin_mm, dmax_mm).map(|r| (i, r)))
    }
}

/// What [`Session::read_scan`] read.
#[derive(Debug)]
pub enum ScanEvent {
    /// A whole scan.
    Scan(Box<HokuyoScan>),
    /// A scan reply that was dropped, with the reason and what was wrong.
    Dropped(DropReason, String),
    /// Another message (the acknowledgement of `MD`, a late reply), ignored.
    Other,
}
