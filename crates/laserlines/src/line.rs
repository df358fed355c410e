//! The line segment every extractor returns.

use std::ops::Range;

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
/// points are the valid beams `first..=last` that the extractor kept (`points` of them; with
/// `hough-split`, a lone spike between two pieces of one surface that it joined is kept but
/// is none of them); the beam ranges of different lines of one scan never overlap.
///
/// In a scan that goes once round ([`ScanView::full_turn`](crate::ScanView::full_turn)), a
/// line of `hough-split` may run across the seam between the last beam and the first: then
/// `first > last`, and its beams are `first..n` followed by `0..=last` ([`Line::covers`],
/// [`Line::beam_span`]). Every other line has `first <= last`.
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

    /// True when beam `i` lies between `first` and `last` (inclusive), across the seam of a
    /// full turn when `first > last`.
    #[must_use]
    pub fn covers(&self, i: usize) -> bool {
        covers(self.first, self.last, i)
    }

    /// True when the line runs across the seam of a full turn (`first > last`).
    #[must_use]
    pub fn wraps(&self) -> bool {
        self.first > self.last
    }

    /// Number of beams from `first` to `last` (inclusive) in a scan of `n` beams
    /// ([`beam_span`]).
    #[must_use]
    pub fn beam_span(&self, n: usize) -> usize {
        beam_span(self.first, self.last, n)
    }
}

/// The beams of the inclusive range `first..=last` of a scan of `n` beams as two runs: the
/// range itself and an empty one, or, across the seam of a full turn (`last < first`),
/// `first..n` and `0..=last` (none when `first >= n`).
fn runs(first: usize, last: usize, n: usize) -> [Range<usize>; 2] {
    if first <= last {
        [first..last.saturating_add(1), 0..0]
    } else if first < n {
        [first..n, 0..last.min(first - 1) + 1]
    } else {
        [0..0, 0..0]
    }
}

/// Number of beams of the inclusive range `first..=last` of a scan of `n` beams. When
/// `last < first` the range runs across the seam of a full turn, `first..n` then `0..=last`,
/// and has `n - first + last + 1` beams (0 when `first >= n`, or `n` is 0).
#[must_use]
pub fn beam_span(first: usize, last: usize, n: usize) -> usize {
    runs(first, last, n)
        .iter()
        .map(ExactSizeIterator::len)
        .sum()
}

/// True when beam `i` lies in the inclusive range `first..=last`, which runs across the seam
/// of a full turn when `last < first` ([`beam_span`]).
#[must_use]
pub fn covers(first: usize, last: usize, i: usize) -> bool {
    if first <= last {
        (first..=last).contains(&i)
    } else {
        i >= first || i <= last
    }
}

/// The beams of the inclusive range `first..=last` of a scan of `n` beams, in order: across
/// the seam of a full turn when `last < first` ([`beam_span`]).
pub fn beams(first: usize, last: usize, n: usize) -> std::iter::Chain<Range<usize>, Range<usize>> {
    let [a, b] = runs(first, last, n);
    a.chain(b)
}

/// Beams shared by the inclusive ranges `a` and `b` of a scan of `n` beams, either of which
/// may run across the seam of a full turn ([`beam_span`]).
#[must_use]
pub fn beams_shared(a: (usize, usize), b: (usize, usize), n: usize) -> usize {
    let (ra, rb) = (runs(a.0, a.1, n), runs(b.0, b.1, n));
    ra.iter()
        .flat_map(|x| {
            rb.iter()
                .map(move |y| y.end.min(x.end).saturating_sub(y.start.max(x.start)))
        })
        .sum()
}

pub use crate::geometry::distance_to_segment;
