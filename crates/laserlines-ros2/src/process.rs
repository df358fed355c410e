//! What the node does with one scan, without any DDS: the message into a [`Scan`], the
//! extractor, the lines into the output messages; and the counts the node logs.

use std::time::Instant;

use laserlines::registry::BoxedExtractor;
use laserlines::{Line, Scan, ScanError};

use crate::convert::{
    RangeCounts, fill_line_list, fill_lines_marker, output_header, scan_from_msg,
};
use crate::msg::{LaserScan, LineSegmentList, Marker, MarkerArray};
use crate::sectors::sector_markers;

/// The messages published for one scan.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Outputs {
    /// `LineSegmentList` for `/line_segments`.
    pub lines: LineSegmentList,
    /// `LINE_LIST` marker for `/line_markers`.
    pub marker: Marker,
    /// Sector objects for `/line_sectors` (with `--sectors`).
    pub sectors: Option<MarkerArray>,
}

/// Counts of one run of the node.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Counts {
    /// `LaserScan` messages received (decoded or not).
    pub seen: u64,
    /// Scans whose lines were extracted and published.
    pub extracted: u64,
    /// Scans skipped: a geometry no extractor can use (`angle_increment` 0, ...).
    pub skipped_geometry: u64,
    /// Messages skipped: not a decodable `LaserScan`.
    pub skipped_undecodable: u64,
    /// Outputs that could not be published (one per message).
    pub publish_failed: u64,
    /// Lines over every extracted scan.
    pub lines: u64,
    /// Ranges that were no measurement, over every extracted scan.
    pub ranges: RangeCounts,
    /// Extracted scans with at least one such range.
    pub scans_with_bad_ranges: u64,
    /// Sum of extraction times, us.
    pub extract_us_sum: f64,
    /// Longest extraction, us.
    pub extract_us_max: f64,
}

impl Counts {
    /// Lines per extracted scan.
    #[must_use]
    pub fn lines_per_scan(&self) -> f64 {
        if self.extracted == 0 {
            0.0
        } else {
            self.lines as f64 / self.extracted as f64
        }
    }

    /// Mean extraction time, us.
    #[must_use]
    pub fn extract_us_mean(&self) -> f64 {
        if self.extracted == 0 {
            0.0
        } else {
            self.extract_us_sum / self.extracted as f64
        }
    }

    /// Scans skipped for any reason.
    #[must_use]
    pub fn skipped(&self) -> u64 {
        self.skipped_geometry + self.skipped_undecodable
    }
}

impl std::fmt::Display for Counts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "scans seen {}, extracted {}, skipped {} ({} bad geometry, {} undecodable); \
             {:.1} lines per scan; extraction {:.1} us mean, {:.1} us max; \
             ranges not used ({} scans): {}; outputs not published {}",
            self.seen,
            self.extracted,
            self.skipped(),
            self.skipped_geometry,
            self.skipped_undecodable,
            self.lines_per_scan(),
            self.extract_us_mean(),
            self.extract_us_max,
            self.scans_with_bad_ranges,
            self.ranges,
            self.publish_failed,
        )
    }
}

/// What happened to one scan.
#[derive(Debug, Clone, PartialEq)]
pub enum Processed {
    /// Lines extracted: the number of lines, the extraction time (us), the ranges that were
    /// no measurement.
    Extracted {
        /// Lines found.
        lines: usize,
        /// Time in `extract_into`, us.
        extract_us: f64,
        /// Ranges that were no measurement.
        ranges: RangeCounts,
    },
    /// The scan's geometry cannot be used; nothing is published.
    Skipped(ScanError),
}

/// Turns scans into output messages with one extractor, keeping the counts.
pub struct Processor {
    extractor: BoxedExtractor,
    frame_id: Option<String>,
    sectors: bool,
    scan: Scan,
    lines: Vec<Line>,
    counts: Counts,
}

impl Processor {
    /// A processor with `extractor`; outputs in `frame_id` when given (else the scan's),
    /// with sector objects when `sectors`.
    #[must_use]
    pub fn new(extractor: BoxedExtractor, frame_id: Option<String>, sectors: bool) -> Self {
        Self {
            extractor,
            frame_id,
            sectors,
            scan: Scan::default(),
            lines: Vec::new(),
            counts: Counts::default(),
        }
    }

    /// Extracts the lines of `msg` into `out` (left as it was when the scan is skipped).
    pub fn process(&mut self, msg: &LaserScan, out: &mut Outputs) -> Processed {
        self.counts.seen += 1;
        let ranges = match scan_from_msg(msg, &mut self.scan) {
            Ok(r) => r,
            Err(e) => {
                self.counts.skipped_geometry += 1;
                return Processed::Skipped(e);
            }
        };
        let t0 = Instant::now();
        self.extractor.extract_into(&self.scan, &mut self.lines);
        let extract_us = t0.elapsed().as_secs_f64() * 1e6;
        let c = &mut self.counts;
        c.extracted += 1;
        c.lines += self.lines.len() as u64;
        c.extract_us_sum += extract_us;
        c.extract_us_max = c.extract_us_max.max(extract_us);
        c.ranges.add(&ranges);
        if ranges.total() > 0 {
            c.scans_with_bad_ranges += 1;
        }
        let header = output_header(&msg.header, self.frame_id.as_deref());
        fill_lines_marker(header.clone(), &self.lines, &mut out.marker);
        out.sectors = self.sectors.then(|| sector_markers(&header, &self.lines));
        fill_line_list(header, &self.lines, &mut out.lines);
        Processed::Extracted {
            lines: self.lines.len(),
            extract_us,
            ranges,
        }
    }

    /// Counts a message that did not decode as a `LaserScan`.
    pub fn count_undecodable(&mut self) {
        self.counts.seen += 1;
        self.counts.skipped_undecodable += 1;
    }

    /// Counts an output that could not be published.
    pub fn count_publish_failed(&mut self) {
        self.counts.publish_failed += 1;
    }

    /// The counts so far.
    #[must_use]
    pub fn counts(&self) -> &Counts {
        &self.counts
    }

    /// The lines of the last extracted scan.
    #[must_use]
    pub fn lines(&self) -> &[Line] {
        &self.lines
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::msg::{Header, Time};

    /// A 181-beam scan of a wall 2 m ahead (x = 2), -45..45 deg.
    fn wall_scan(angle_increment: f32) -> LaserScan {
        let inc = 0.5_f64.to_radians();
        let ranges = (0..181)
            .map(|i| (2.0 / (-45.0_f64.to_radians() + f64::from(i) * inc).cos()) as f32)
            .collect();
        LaserScan {
            header: Header {
                stamp: Time { sec: 7, nanosec: 5 },
                frame_id: "laser".to_owned(),
            },
            angle_min: (-45.0_f64).to_radians() as f32,
            angle_max: 45.0_f64.to_radians() as f32,
            angle_increment,
            range_min: 0.02,
            range_max: 5.6,
            ranges,
            ..LaserScan::default()
        }
    }

    fn processor(sectors: bool) -> Processor {
        let ex = laserlines::registry::build("hough-split").unwrap().unwrap();
        Processor::new(ex, None, sectors)
    }

    #[test]
    fn a_wall_gives_one_segment_with_the_scans_header() {
        let mut p = processor(true);
        let mut out = Outputs::default();
        let msg = wall_scan(0.5_f64.to_radians() as f32);
        let r = p.process(&msg, &mut out);
        assert!(matches!(r, Processed::Extracted { lines: 1, .. }), "{r:?}");
        assert_eq!(out.lines.header, msg.header);
        let s = out.lines.line_segments[0];
        assert!((s.radius - 2.0).abs() < 1e-3, "{s:?}");
        assert!(s.angle.abs() < 1e-3, "{s:?}");
        // Start at the first beam (-45 deg: y < 0), end at the last.
        assert!(s.start[1] < -1.9 && s.end[1] > 1.9, "{s:?}");
        assert_eq!(out.marker.points.len(), 2);
        assert!(out.sectors.is_some());
        assert_eq!(p.counts().lines, 1);
    }

    #[test]
    fn bad_scans_are_counted_and_the_next_one_goes_through() {
        let mut p = processor(false);
        let mut out = Outputs::default();
        let r = p.process(&wall_scan(0.0), &mut out);
        assert_eq!(r, Processed::Skipped(ScanError::BadAngleIncrement(0.0)));
        assert!(out.lines.line_segments.is_empty());
        let mut msg = wall_scan(0.5_f64.to_radians() as f32);
        msg.ranges[0] = f32::NAN;
        msg.ranges[1] = f32::INFINITY;
        msg.ranges[2] = 0.0;
        let r = p.process(&msg, &mut out);
        let Processed::Extracted { lines, ranges, .. } = r else {
            panic!("{r:?}")
        };
        assert_eq!(lines, 1);
        assert_eq!(ranges.total(), 3);
        p.count_undecodable();
        let c = p.counts();
        assert_eq!((c.seen, c.extracted, c.skipped()), (3, 1, 2));
        assert_eq!(c.scans_with_bad_ranges, 1);
        assert!(out.sectors.is_none());
    }
}
