//! What the host asks for: the parameters of `MD`/`MS` and `GD`/`GS` and their command
//! lines.

use crate::codec::Encoding;

/// The largest step a command can name: `MD`, `MS`, `GD` and `GS` carry the first and last
/// step in 4 digits.
pub const MAX_STEP: u32 = 9999;

/// The steps, grouping and encoding of a scan request.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ScanRequest {
    /// First step measured (`AMIN` or later).
    pub first_step: u32,
    /// Last step measured (`AMAX` or earlier).
    pub last_step: u32,
    /// Cluster count, 0..=99: so many neighbouring steps are sent as one value, their
    /// smallest valid reading (0 and 1 both mean every step).
    pub cluster: u32,
    /// Scan interval of `MD`/`MS`, 0..=9: so many scans are skipped between two sent.
    pub skip: u32,
    /// `Three` for `MD`/`GD` (ranges up to 262 m), `Two` for `MS`/`GS` (up to 4095 mm).
    pub encoding: Encoding,
}

impl ScanRequest {
    /// Every step of `first..=last`, no skipping, 3-character encoding.
    #[must_use]
    pub fn new(first_step: u32, last_step: u32) -> Self {
        Self {
            first_step,
            last_step,
            cluster: 1,
            skip: 0,
            encoding: Encoding::Three,
        }
    }

    /// Steps per value (the cluster count, at least 1).
    #[must_use]
    pub fn cluster_steps(&self) -> u32 {
        self.cluster.max(1)
    }

    /// Values per scan.
    #[must_use]
    pub fn values(&self) -> usize {
        if self.last_step < self.first_step {
            return 0;
        }
        let steps = self.last_step - self.first_step + 1;
        steps.div_ceil(self.cluster_steps()) as usize
    }

    fn letter(&self) -> char {
        match self.encoding {
            Encoding::Two => 'S',
            _ => 'D',
        }
    }

    /// The streaming command, `MD` or `MS`, for `scans` scans (0 = until `QT`, at most 99).
    #[must_use]
    pub fn stream_command(&self, scans: u32) -> String {
        format!(
            "M{}{:04}{:04}{:02}{:01}{:02}",
            self.letter(),
            self.first_step.min(MAX_STEP),
            self.last_step.min(MAX_STEP),
            self.cluster.min(99),
            self.skip.min(9),
            scans.min(99)
        )
    }

    /// The single-scan command, `GD` or `GS`.
    #[must_use]
    pub fn single_command(&self) -> String {
        format!(
            "G{}{:04}{:04}{:02}",
            self.letter(),
            self.first_step.min(MAX_STEP),
            self.last_step.min(MAX_STEP),
            self.cluster.min(99)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn commands_are_written_as_the_specification_lays_them_out() {
        let r = ScanRequest::new(44, 725);
        assert_eq!(r.stream_command(0), "MD0044072501000");
        assert_eq!(r.single_command(), "GD0044072501");
        assert_eq!(r.values(), 682);
        let s = ScanRequest {
            cluster: 2,
            skip: 1,
            encoding: Encoding::Two,
            ..ScanRequest::new(0, 1080)
        };
        assert_eq!(s.stream_command(5), "MS0000108002105");
        assert_eq!(s.single_command(), "GS0000108002");
        assert_eq!(s.values(), 541);
        assert_eq!(ScanRequest::new(10, 5).values(), 0);
    }
}
