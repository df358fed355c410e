//! Messages to and from the core's types: a `LaserScan` into a [`Scan`] (with a count of the
//! ranges that are no measurement), lines into laser_line_extraction's `LineSegmentList`
//! and an RViz `LINE_LIST` marker.
//!
//! laser_line_extraction's conventions, which [`Line`] shares: the line is
//! `x cos(angle) + y sin(angle) = radius` with `radius >= 0`; `angle` in `(-pi, pi]`
//! (laser_line_extraction wraps to `[-pi, pi]`, the two differ only at exactly `pi`); the
//! covariance is that of `(radius, angle)`, row-major `[var r, cov, cov, var angle]`; `start`
//! is the end at the line's first beam, `end` the one at its last; all in the scan's frame.

use laserlines::{Line, Scan, ScanError};

use crate::msg::{ColorRgba, Header, LaserScan, LineSegment, LineSegmentList, Marker, Point};

/// Ranges of one scan that are no measurement, by kind (ROS REP 117: NaN an erroneous
/// reading, +inf no return, -inf too close; 0 and negative values are what some drivers
/// send instead).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RangeCounts {
    /// NaN ranges.
    pub nan: u64,
    /// Infinite ranges (either sign).
    pub inf: u64,
    /// Ranges equal to zero.
    pub zero: u64,
    /// Negative finite ranges.
    pub negative: u64,
}

impl RangeCounts {
    /// Counts the ranges of `ranges` that are NaN, infinite, zero or negative.
    #[must_use]
    pub fn of(ranges: &[f32]) -> Self {
        let mut c = Self::default();
        for &r in ranges {
            if r.is_nan() {
                c.nan += 1;
            } else if r.is_infinite() {
                c.inf += 1;
            } else if r == 0.0 {
                c.zero += 1;
            } else if r < 0.0 {
                c.negative += 1;
            }
        }
        c
    }

    /// All of them.
    #[must_use]
    pub fn total(&self) -> u64 {
        self.nan + self.inf + self.zero + self.negative
    }

    /// Adds `other` to these counts.
    pub fn add(&mut self, other: &Self) {
        self.nan += other.nan;
        self.inf += other.inf;
        self.zero += other.zero;
        self.negative += other.negative;
    }
}

impl std::fmt::Display for RangeCounts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} NaN, {} inf, {} zero, {} negative",
            self.nan, self.inf, self.zero, self.negative
        )
    }
}

/// Fills `scan` from a `LaserScan` message (ranges widened to `f64` exactly; intensities
/// left out, no extractor reads them) and checks its geometry. Ranges that are NaN, inf,
/// zero or out of the limits stay in the scan as "no return", as everywhere in laserlines;
/// they are counted in the result. `angle_max` is not read: the beams are
/// `angle_min + i * angle_increment` for every range given.
///
/// # Errors
/// The [`ScanError`] of a scan that cannot be used (`angle_increment` zero or not finite,
/// `angle_min` not finite or beyond +-1000 rad, bad range limits, beams over more than a
/// turn); `scan` then holds the message's values but must not be extracted from.
pub fn scan_from_msg(msg: &LaserScan, scan: &mut Scan) -> Result<RangeCounts, ScanError> {
    scan.angle_min = f64::from(msg.angle_min);
    scan.angle_increment = f64::from(msg.angle_increment);
    scan.range_min = f64::from(msg.range_min);
    scan.range_max = f64::from(msg.range_max);
    scan.ranges.clear();
    scan.ranges.extend(msg.ranges.iter().map(|&r| f64::from(r)));
    scan.intensities = None;
    scan.stamp = Some(msg.header.stamp.seconds());
    scan.validate()?;
    Ok(RangeCounts::of(&msg.ranges))
}

/// The header of the outputs: the scan's stamp, and `frame_id` when given (as
/// laser_line_extraction's `frame_id` parameter) or else the scan's frame.
#[must_use]
pub fn output_header(scan: &Header, frame_id: Option<&str>) -> Header {
    Header {
        stamp: scan.stamp,
        frame_id: frame_id.map_or_else(|| scan.frame_id.clone(), str::to_owned),
    }
}

/// One line as laser_line_extraction's `LineSegment`.
#[must_use]
#[allow(clippy::cast_possible_truncation)] // the message's fields are float32
pub fn line_segment(line: &Line) -> LineSegment {
    let c = &line.covariance;
    LineSegment {
        radius: line.r as f32,
        angle: line.alpha as f32,
        covariance: [
            c[(0, 0)] as f32,
            c[(0, 1)] as f32,
            c[(1, 0)] as f32,
            c[(1, 1)] as f32,
        ],
        start: [line.start.x as f32, line.start.y as f32],
        end: [line.end.x as f32, line.end.y as f32],
    }
}

/// Fills `msg` with `header` and one `LineSegment` per line, in the order given.
pub fn fill_line_list(header: Header, lines: &[Line], msg: &mut LineSegmentList) {
    msg.header = header;
    msg.line_segments.clear();
    msg.line_segments.extend(lines.iter().map(line_segment));
}

/// Namespace of the lines' marker.
pub const LINES_NS: &str = "line_extraction";

/// Fills `marker` with the lines as one `LINE_LIST` (namespace `line_extraction`, id 0, as
/// laser_line_extraction's marker: start and end point of every line, z = 0), 3 cm wide,
/// red.
pub fn fill_lines_marker(header: Header, lines: &[Line], marker: &mut Marker) {
    marker.header = header;
    LINES_NS.clone_into(&mut marker.ns);
    marker.id = 0;
    marker.r#type = Marker::LINE_LIST;
    marker.action = Marker::ADD;
    marker.scale.x = 0.03;
    marker.color = ColorRgba {
        r: 1.0,
        g: 0.0,
        b: 0.0,
        a: 1.0,
    };
    marker.points.clear();
    for l in lines {
        marker.points.push(point(l.start.x, l.start.y));
        marker.points.push(point(l.end.x, l.end.y));
    }
}

/// A point in the plane (z = 0).
#[must_use]
pub fn point(x: f64, y: f64) -> Point {
    Point { x, y, z: 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::msg::Time;
    use laserlines::math::{Matrix2, Point2};

    fn msg(angle_increment: f32, ranges: Vec<f32>) -> LaserScan {
        LaserScan {
            header: Header {
                stamp: Time {
                    sec: 12,
                    nanosec: 500_000_000,
                },
                frame_id: "laser".to_owned(),
            },
            angle_min: -1.0,
            angle_max: 1.0,
            angle_increment,
            range_min: 0.02,
            range_max: 5.6,
            ranges,
            ..LaserScan::default()
        }
    }

    #[test]
    fn bad_ranges_are_counted_and_kept_as_no_return() {
        let m = msg(
            0.01,
            vec![
                1.0,
                f32::NAN,
                f32::INFINITY,
                0.0,
                -0.5,
                f32::NEG_INFINITY,
                2.0,
            ],
        );
        let mut scan = Scan::default();
        let c = scan_from_msg(&m, &mut scan).unwrap();
        assert_eq!(
            c,
            RangeCounts {
                nan: 1,
                inf: 2,
                zero: 1,
                negative: 1
            }
        );
        assert_eq!(c.total(), 5);
        assert_eq!(scan.len(), 7);
        assert_eq!(scan.stamp, Some(12.5));
        assert_eq!(scan.angle_increment, f64::from(0.01_f32));
        // Only the two real readings are measurements.
        assert_eq!(scan.count_valid(scan.range_window(None)), 2);
    }

    #[test]
    fn zero_increment_is_an_error_not_a_panic() {
        let mut scan = Scan::default();
        let e = scan_from_msg(&msg(0.0, vec![1.0; 10]), &mut scan).unwrap_err();
        assert_eq!(e, ScanError::BadAngleIncrement(0.0));
        let e = scan_from_msg(&msg(f32::NAN, vec![1.0; 10]), &mut scan).unwrap_err();
        assert!(matches!(e, ScanError::BadAngleIncrement(x) if x.is_nan()));
    }

    #[test]
    fn segment_fields_in_laser_line_extraction_order() {
        let line = Line {
            start: Point2::new(1.0, -0.5),
            end: Point2::new(1.0, 0.5),
            r: 1.0,
            alpha: 0.25,
            first: 3,
            last: 40,
            points: 38,
            rms: 0.01,
            covariance: Matrix2::new(1e-4, 2e-5, 2e-5, 3e-3),
        };
        let s = line_segment(&line);
        assert_eq!(s.radius, 1.0);
        assert_eq!(s.angle, 0.25);
        assert_eq!(s.covariance, [1e-4_f32, 2e-5, 2e-5, 3e-3]);
        assert_eq!(s.start, [1.0, -0.5]);
        assert_eq!(s.end, [1.0, 0.5]);
    }

    #[test]
    fn header_copied_frame_replaced_when_asked() {
        let h = msg(0.01, vec![]).header;
        assert_eq!(output_header(&h, None), h);
        let o = output_header(&h, Some("base_laser"));
        assert_eq!(o.stamp, h.stamp);
        assert_eq!(o.frame_id, "base_laser");
    }
}
