//! The line segment every extractor returns.

use crate::fit::PolarFit;
use crate::math::{Matrix2, Point2};

/// A line segment extracted from one scan, in the sensor frame.
///
/// The supporting infinite line is `x cos(alpha) + y sin(alpha) = r` with `r >= 0`, fitted
/// to the line's supporting points (`hough-split`, with `share_fits`, its default, fits it to
/// the points of all its lines of one surface, each line keeping its own points and extent).
/// The end points are the first and last supporting points projected onto that line;
/// `hough-split` (with `refine_ends`, its default) moves the ends of two neighbouring lines
/// that meet at a corner to the lines' intersection: outward by at most the gap to the other
/// line plus its split threshold, inward by at most the split threshold. The supporting
/// points are the valid beams `first..=last` that the extractor kept (`points` of them); the
/// beam ranges of different lines of one scan never overlap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line {
    /// Start point, m (the end at beam `first`).
    pub start: Point2,
    /// End point, m (the end at beam `last`).
    pub end: Point2,
    /// Distance of the line from the sensor, m.
    pub r: f64,
    /// Direction of the line's normal, rad, in `(-pi, pi]`.
    pub alpha: f64,
    /// First supporting beam index.
    pub first: usize,
    /// Last supporting beam index (inclusive).
    pub last: usize,
    /// Number of supporting points.
    pub points: usize,
    /// Root-mean-square orthogonal residual of the supporting points, m.
    pub rms: f64,
    /// Covariance of `(r, alpha)`: `[[m^2, m rad], [m rad, rad^2]]`.
    pub covariance: Matrix2,
}

impl Line {
    /// Builds a line from a fit and the first and last supporting points (projected onto the
    /// fitted line to give the end points).
    #[must_use]
    pub fn from_fit(fit: &PolarFit, first: (usize, Point2), last: (usize, Point2)) -> Self {
        // PolarFit::project with the normal computed once (the same values).
        let normal = fit.normal();
        let project = |p: Point2| p - normal * (p.coords.dot(&normal) - fit.r);
        Self {
            start: project(first.1),
            end: project(last.1),
            r: fit.r,
            alpha: fit.alpha,
            first: first.0,
            last: last.0,
            points: fit.n,
            rms: fit.rms,
            covariance: fit.covariance,
        }
    }

    /// Length of the segment, m.
    #[must_use]
    pub fn length(&self) -> f64 {
        (self.end - self.start).norm()
    }

    /// Distance from the sensor origin to the closest point of the segment, m.
    #[must_use]
    pub fn nearest_distance(&self) -> f64 {
        distance_to_segment(Point2::origin(), self.start, self.end)
    }
}

pub use crate::geometry::distance_to_segment;
