//! Metrics that need no ground truth, for real logs: how much of a scan the lines explain,
//! and how tightly.
//!
//! - A valid point (a range within the scan's own window, `Scan::range_window`) is **explained**
//!   when its distance to the nearest extracted line *segment* (not the infinite line) is at
//!   most `max(distance, distance_per_metre * range)`; by default three standard deviations of
//!   the URG-04LX range noise, 15 mm up to 1 m and 1.5 % of the range beyond.
//! - The **residual RMS** is the root mean square of the orthogonal residuals of the lines'
//!   own supporting points about their fitted lines, over all lines of all scans
//!   (`sqrt(sum(rms_i^2 * points_i) / sum(points_i))`).

use laserlines::line::distance_to_segment;
use laserlines::{Line, Scan};
use serde::Serialize;

/// The threshold of an explained point (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ExplainParams {
    /// Smallest threshold, m. Default 0.015.
    pub distance: f64,
    /// Growth with the point's range, m per m. Default 0.015.
    pub distance_per_metre: f64,
}

impl Default for ExplainParams {
    fn default() -> Self {
        Self {
            distance: 0.015,
            distance_per_metre: 0.015,
        }
    }
}

impl ExplainParams {
    /// The threshold for a point at `range`, m.
    #[must_use]
    pub fn threshold(&self, range: f64) -> f64 {
        self.distance.max(self.distance_per_metre * range)
    }
}

/// Coverage counts of one or more scans; add them up with [`Coverage::add`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Coverage {
    /// Valid points.
    pub points: usize,
    /// Valid points within the threshold of a line segment.
    pub explained: usize,
    /// Supporting points of the lines.
    pub support: usize,
    /// Sum over lines of `rms^2 * points`, m^2.
    pub sum_sq_residual: f64,
}

impl Coverage {
    /// The coverage of `lines` over `scan`.
    #[must_use]
    pub fn of_scan(scan: &Scan, lines: &[Line], params: &ExplainParams) -> Self {
        let window = scan.range_window(None);
        let mut c = Self::default();
        for (i, &range) in scan.ranges.iter().enumerate() {
            if !window.contains(range) {
                continue;
            }
            let (s, co) = scan.angle(i).sin_cos();
            let p = laserlines::math::Point2::new(range * co, range * s);
            if !(p.x.is_finite() && p.y.is_finite()) {
                continue;
            }
            c.points += 1;
            let t = params.threshold(range);
            if lines
                .iter()
                .any(|l| distance_to_segment(p, l.start, l.end) <= t)
            {
                c.explained += 1;
            }
        }
        for l in lines {
            if l.rms.is_finite() {
                c.support += l.points;
                c.sum_sq_residual += l.rms * l.rms * l.points as f64;
            }
        }
        c
    }

    /// Adds the counts of `other`.
    pub fn add(&mut self, other: &Self) {
        self.points += other.points;
        self.explained += other.explained;
        self.support += other.support;
        self.sum_sq_residual += other.sum_sq_residual;
    }

    /// Fraction of valid points explained (0 when there are none).
    #[must_use]
    pub fn explained_fraction(&self) -> f64 {
        ratio(self.explained, self.points)
    }

    /// Residual RMS of the supporting points, m (0 without lines).
    #[must_use]
    pub fn residual_rms(&self) -> f64 {
        if self.support == 0 {
            0.0
        } else {
            (self.sum_sq_residual / self.support as f64).sqrt()
        }
    }
}

/// `a / b`, 0 when `b == 0`.
pub(crate) fn ratio(a: usize, b: usize) -> f64 {
    if b == 0 { 0.0 } else { a as f64 / b as f64 }
}
