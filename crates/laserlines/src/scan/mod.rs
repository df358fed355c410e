//! The scan model, shaped like ROS `sensor_msgs/LaserScan`, and its conversion to points.

use crate::math::Point2;

mod window;

pub use window::{
    CLAMPED_BAND, CLAMPED_READINGS, CLAMPED_SHARE, RangeWindow, clamped, saturated_below,
    scan_window,
};

/// Errors found when validating a [`Scan`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ScanError {
    /// `angle_min` is NaN, infinite, or beyond [`MAX_ANGLE_MIN`] (where the angles of
    /// neighbouring beams would round to one).
    #[error("angle_min must be finite and within +-1000 rad, got {}", Short(*.0))]
    AngleMinNotFinite(f64),
    /// `angle_increment` is zero, NaN or infinite.
    #[error("angle_increment must be finite and non-zero, got {}", Short(*.0))]
    BadAngleIncrement(f64),
    /// The beams span more than one full turn.
    #[error("{beams} beams of {} rad span more than a full turn", Short(*increment))]
    SpanTooLarge {
        /// number of beams
        beams: usize,
        /// angle increment, rad
        increment: f64,
    },
    /// `range_min`/`range_max` are not finite, negative, or out of order.
    #[error(
        "range limits must satisfy 0 <= range_min < range_max (finite), got {}..{}",
        Short(*min),
        Short(*max)
    )]
    BadRangeLimits {
        /// range_min, m
        min: f64,
        /// range_max, m
        max: f64,
    },
    /// `intensities` is present but not as long as `ranges`.
    #[error("intensities has {intensities} values but ranges has {ranges}")]
    IntensityLength {
        /// number of ranges
        ranges: usize,
        /// number of intensities
        intensities: usize,
    },
}

/// The largest `|angle_min|` of a valid scan, rad: ROS drivers give angles within a turn or
/// two of zero; far beyond, the angles of neighbouring beams round to one value.
pub const MAX_ANGLE_MIN: f64 = 1000.0;

/// A number for a message or a text file, in its shortest exact form: as Rust prints it, but
/// in exponent form from 1e16 on (the largest finite number, "no limit", is 309 digits in
/// full) and below 1e-5 (`1e-300` would be 300).
#[derive(Debug, Clone, Copy)]
pub struct Short(pub f64);

impl std::fmt::Display for Short {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        if a.is_finite() && a != 0.0 && !(1e-5..1e16).contains(&a) {
            write!(f, "{:e}", self.0)
        } else {
            write!(f, "{}", self.0)
        }
    }
}

/// One 2D laser scan, like ROS `sensor_msgs/LaserScan`.
///
/// Beam `i` points at `angle_min + i * angle_increment` (radians, counter-clockwise, x forward
/// in the sensor frame). `angle_increment` may be negative: reversed scans exist. A range is a
/// measurement only if it lies in the scan's window ([`Scan::range_window`],
/// [`RangeWindow::contains`]); everything else (NaN, inf, 0, out of limits, `range_max`
/// itself: [`saturated_below`]) is "no return".
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Scan {
    /// Angle of the first beam, rad.
    pub angle_min: f64,
    /// Angle between consecutive beams, rad (non-zero; negative for clockwise scans).
    pub angle_increment: f64,
    /// Smallest valid range, m.
    pub range_min: f64,
    /// The range limit, m: valid ranges lie below it (a reading of the limit itself is no
    /// return, [`saturated_below`]).
    pub range_max: f64,
    /// Ranges, m; invalid values mean "no return".
    pub ranges: Vec<f64>,
    /// Optional intensities, one per range.
    pub intensities: Option<Vec<f64>>,
    /// Optional time stamp, seconds (epoch or log-relative, as the source gives it).
    pub stamp: Option<f64>,
}

impl Scan {
    /// Builds and validates a scan without intensities or stamp.
    ///
    /// # Errors
    /// Any [`ScanError`] found by [`Scan::validate`].
    pub fn new(
        angle_min: f64,
        angle_increment: f64,
        range_min: f64,
        range_max: f64,
        ranges: Vec<f64>,
    ) -> Result<Self, ScanError> {
        let scan = Self {
            angle_min,
            angle_increment,
            range_min,
            range_max,
            ranges,
            intensities: None,
            stamp: None,
        };
        scan.validate()?;
        Ok(scan)
    }

    /// Checks the scan's geometry and limits ([`ScanView::validate`]) and that the
    /// intensities, when present, are one per range.
    ///
    /// # Errors
    /// A [`ScanError`] naming the first problem found.
    pub fn validate(&self) -> Result<(), ScanError> {
        self.view().validate()?;
        if let Some(int) = &self.intensities
            && int.len() != self.ranges.len()
        {
            return Err(ScanError::IntensityLength {
                ranges: self.ranges.len(),
                intensities: int.len(),
            });
        }
        Ok(())
    }

    /// The scan borrowed as a [`ScanView`]: its geometry, limits and ranges.
    #[must_use]
    pub fn view(&self) -> ScanView<'_> {
        ScanView {
            angle_min: self.angle_min,
            angle_increment: self.angle_increment,
            range_min: self.range_min,
            range_max: self.range_max,
            ranges: &self.ranges,
        }
    }

    /// Number of beams.
    #[must_use]
    pub fn len(&self) -> usize {
        self.ranges.len()
    }

    /// True when the scan has no beams.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.ranges.is_empty()
    }

    /// Angle of beam `i`, rad.
    #[must_use]
    pub fn angle(&self, i: usize) -> f64 {
        self.view().angle(i)
    }

    /// Angle of the last beam, rad (`angle_min` for an empty scan), as in ROS.
    #[must_use]
    pub fn angle_max(&self) -> f64 {
        self.view().angle_max()
    }

    /// True when the beams go once round ([`ScanView::full_turn`]).
    #[must_use]
    pub fn full_turn(&self) -> bool {
        self.view().full_turn()
    }

    /// The window of valid ranges for this scan: its own limits, narrowed by `extra`
    /// ([`ScanView::range_window`]: a reading of `range_max` itself is no return).
    #[must_use]
    pub fn range_window(&self, extra: Option<RangeWindow>) -> RangeWindow {
        self.view().range_window(extra)
    }

    /// Number of valid ranges in `window`.
    #[must_use]
    pub fn count_valid(&self, window: RangeWindow) -> usize {
        self.view().count_valid(window)
    }

    /// Converts the valid beams to points in the sensor frame, keeping beam indices
    /// ([`ScanView::points_into`]).
    pub fn points_into(&self, window: RangeWindow, out: &mut Vec<ScanPoint>) {
        self.view().points_into(window, out);
    }

    /// Convenience wrapper around [`Scan::points_into`] that allocates.
    #[must_use]
    pub fn points(&self, window: RangeWindow) -> Vec<ScanPoint> {
        let mut out = Vec::with_capacity(self.ranges.len());
        self.points_into(window, &mut out);
        out
    }
}

/// A scan whose ranges are borrowed: what every extractor reads
/// ([`crate::LineExtractor::extract_view_into`]). A [`Scan`] lends one ([`Scan::view`]);
/// ranges held elsewhere (a buffer of a driver, an array of another language) are read in
/// place, without a copy.
///
/// Beam `i` points at `angle_min + i * angle_increment`, as in [`Scan`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanView<'a> {
    /// Angle of the first beam, rad.
    pub angle_min: f64,
    /// Angle between consecutive beams, rad (non-zero; negative for clockwise scans).
    pub angle_increment: f64,
    /// Smallest valid range, m.
    pub range_min: f64,
    /// The range limit, m: valid ranges lie below it (a reading of the limit itself is no
    /// return, [`saturated_below`]).
    pub range_max: f64,
    /// Ranges, m; invalid values mean "no return".
    pub ranges: &'a [f64],
}

impl<'a> From<&'a Scan> for ScanView<'a> {
    fn from(scan: &'a Scan) -> Self {
        scan.view()
    }
}

impl<'a> ScanView<'a> {
    /// Borrows `ranges` with the given geometry and limits, validated.
    ///
    /// # Errors
    /// Any [`ScanError`] found by [`ScanView::validate`].
    pub fn new(
        angle_min: f64,
        angle_increment: f64,
        range_min: f64,
        range_max: f64,
        ranges: &'a [f64],
    ) -> Result<Self, ScanError> {
        let view = Self {
            angle_min,
            angle_increment,
            range_min,
            range_max,
            ranges,
        };
        view.validate()?;
        Ok(view)
    }

    /// Checks the geometry and limits: a finite `angle_min`, a finite non-zero
    /// `angle_increment`, beams spanning at most a full turn, `0 <= range_min < range_max`
    /// (finite).
    ///
    /// # Errors
    /// A [`ScanError`] naming the first problem found.
    pub fn validate(&self) -> Result<(), ScanError> {
        if !(self.angle_min.is_finite() && self.angle_min.abs() <= MAX_ANGLE_MIN) {
            return Err(ScanError::AngleMinNotFinite(self.angle_min));
        }
        if !self.angle_increment.is_finite() || self.angle_increment == 0.0 {
            return Err(ScanError::BadAngleIncrement(self.angle_increment));
        }
        let n = self.ranges.len();
        if n > 1 && (n - 1) as f64 * self.angle_increment.abs() > std::f64::consts::TAU + 1e-9 {
            return Err(ScanError::SpanTooLarge {
                beams: n,
                increment: self.angle_increment,
            });
        }
        if !(self.range_min.is_finite()
            && self.range_max.is_finite()
            && self.range_min >= 0.0
            && self.range_min < self.range_max)
        {
            return Err(ScanError::BadRangeLimits {
                min: self.range_min,
                max: self.range_max,
            });
        }
        Ok(())
    }

    /// Number of beams.
    #[must_use]
    pub fn len(&self) -> usize {
        self.ranges.len()
    }

    /// True when the scan has no beams.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.ranges.is_empty()
    }

    /// Angle of beam `i`, rad.
    #[must_use]
    pub fn angle(&self, i: usize) -> f64 {
        self.angle_min + i as f64 * self.angle_increment
    }

    /// Angle of the last beam, rad (`angle_min` for an empty scan), as in ROS.
    #[must_use]
    pub fn angle_max(&self) -> f64 {
        self.angle(self.ranges.len().saturating_sub(1))
    }

    /// True when the beams go once round: at least three beams spanning a full turn, less
    /// half an increment or more (`n |angle_increment| >= 2 pi - |angle_increment| / 2`): the
    /// beam after the last would point within half an increment of the first, or the last
    /// repeats the first's direction, as some drivers give it (361 beams of 1 deg). Beam
    /// `n - 1` and beam `0` are then neighbours, and a surface may be seen across the seam
    /// between them (see [`crate::Line`]). [`ScanView::validate`] refuses more than a full
    /// turn between the first beam and the last.
    #[must_use]
    pub fn full_turn(&self) -> bool {
        let (n, inc) = (self.ranges.len(), self.angle_increment.abs());
        n >= 3 && inc.is_finite() && n as f64 * inc >= std::f64::consts::TAU - 0.5 * inc
    }

    /// The window of valid ranges for this scan: its own limits, narrowed by `extra`. A
    /// reading of `range_max` itself is no return ([`saturated_below`]), and so is a band
    /// below it when the readings show a driver that clamps ([`scan_window`]).
    #[must_use]
    pub fn range_window(&self, extra: Option<RangeWindow>) -> RangeWindow {
        let own = scan_window(self.range_min, self.range_max, self.ranges);
        match extra {
            Some(e) => own.intersect(e),
            None => own,
        }
    }

    /// Number of valid ranges in `window`.
    #[must_use]
    pub fn count_valid(&self, window: RangeWindow) -> usize {
        self.ranges.iter().filter(|r| window.contains(**r)).count()
    }

    /// Converts the valid beams to points in the sensor frame, keeping beam indices.
    ///
    /// Clears `out` first; beams whose range is invalid in `window`, or whose point is not
    /// finite (e.g. a NaN angle), are left out, and a view with broken geometry or limits
    /// ([`ScanView::validate`]) gives no point. Points stay in beam order.
    pub fn points_into(&self, window: RangeWindow, out: &mut Vec<ScanPoint>) {
        out.clear();
        if self.validate().is_err() {
            return;
        }
        for (i, &r) in self.ranges.iter().enumerate() {
            if !window.contains(r) {
                continue;
            }
            let phi = self.angle(i);
            let (s, c) = phi.sin_cos();
            let p = Point2::new(r * c, r * s);
            if p.x.is_finite() && p.y.is_finite() {
                out.push(ScanPoint {
                    index: i,
                    range: r,
                    angle: phi,
                    point: p,
                });
            }
        }
    }
}

/// A valid beam converted to a point in the sensor frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanPoint {
    /// Beam index in the scan.
    pub index: usize,
    /// Measured range, m.
    pub range: f64,
    /// Beam angle, rad.
    pub angle: f64,
    /// The point, m, sensor frame.
    pub point: Point2,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation_names_the_problem() {
        assert_eq!(
            Scan::new(0.0, 0.0, 0.0, 1.0, vec![1.0]).unwrap_err(),
            ScanError::BadAngleIncrement(0.0)
        );
        assert!(matches!(
            Scan::new(0.0, 0.1, 2.0, 1.0, vec![]),
            Err(ScanError::BadRangeLimits { .. })
        ));
        assert!(matches!(
            Scan::new(f64::NAN, 0.1, 0.0, 1.0, vec![]),
            Err(ScanError::AngleMinNotFinite(_))
        ));
        assert!(matches!(
            Scan::new(1e17, 0.1, 0.0, 1.0, vec![1.0]),
            Err(ScanError::AngleMinNotFinite(_))
        ));
        assert!(Scan::new(-MAX_ANGLE_MIN, 0.1, 0.0, 1.0, vec![1.0]).is_ok());
        assert!(matches!(
            Scan::new(0.0, 0.1, 0.0, 1.0, vec![1.0; 100]),
            Err(ScanError::SpanTooLarge { .. })
        ));
        let mut s = Scan::new(0.0, 0.1, 0.0, 1.0, vec![1.0; 3]).unwrap();
        s.intensities = Some(vec![1.0]);
        assert!(matches!(
            s.validate(),
            Err(ScanError::IntensityLength { .. })
        ));
    }

    #[test]
    fn huge_values_are_named_in_e_notation() {
        let msg = |r: Result<Scan, ScanError>| r.unwrap_err().to_string();
        assert_eq!(
            msg(Scan::new(-1e300, 0.1, 0.0, 1.0, vec![1.0])),
            "angle_min must be finite and within +-1000 rad, got -1e300"
        );
        assert_eq!(
            msg(Scan::new(0.0, 1e200, 0.0, 1.0, vec![1.0; 3])),
            "3 beams of 1e200 rad span more than a full turn"
        );
        assert_eq!(
            msg(Scan::new(0.0, f64::INFINITY, 0.0, 1.0, vec![1.0])),
            "angle_increment must be finite and non-zero, got inf"
        );
        assert_eq!(
            msg(Scan::new(0.0, 0.1, 1e300, 2.5, vec![1.0])),
            "range limits must satisfy 0 <= range_min < range_max (finite), got 1e300..2.5"
        );
    }

    #[test]
    fn a_view_borrows_the_ranges_and_checks_like_the_scan() {
        let ranges = [1.0, f64::NAN, 2.0];
        let view = ScanView::new(0.5, -0.25, 0.1, 4.0, &ranges).unwrap();
        assert!(std::ptr::eq(view.ranges, &ranges[..]));
        assert_eq!(view.angle_max(), 0.0);
        let pts: Vec<usize> = {
            let mut out = Vec::new();
            view.points_into(view.range_window(None), &mut out);
            out.iter().map(|p| p.index).collect()
        };
        assert_eq!(pts, vec![0, 2]);
        assert_eq!(
            ScanView::new(0.0, 0.1, 1.0, 1.0, &ranges).unwrap_err(),
            ScanError::BadRangeLimits { min: 1.0, max: 1.0 }
        );
        assert!(matches!(
            ScanView::new(0.0, f64::NAN, 0.0, 1.0, &ranges),
            Err(ScanError::BadAngleIncrement(x)) if x.is_nan()
        ));
        let scan = Scan::new(0.5, -0.25, 0.1, 4.0, ranges.to_vec()).unwrap();
        assert_eq!(scan.view().ranges.len(), 3);
        assert_eq!(ScanView::from(&scan).angle(1), view.angle(1));
    }

    #[test]
    fn reversed_scans_have_decreasing_angles() {
        let s = Scan::new(1.0, -0.5, 0.0, 10.0, vec![1.0, 1.0, 1.0]).unwrap();
        assert!((s.angle_max() - 0.0).abs() < 1e-12);
        let pts = s.points(s.range_window(None));
        assert!((pts[2].point.x - 1.0).abs() < 1e-12 && pts[2].point.y.abs() < 1e-12);
    }

    #[test]
    fn invalid_ranges_never_become_points() {
        let s = Scan::new(
            0.0,
            0.1,
            0.02,
            5.6,
            vec![f64::NAN, f64::INFINITY, 0.0, -1.0, 0.01, 6.0, 1.0, 5.6],
        )
        .unwrap();
        let pts = s.points(s.range_window(None));
        let idx: Vec<usize> = pts.iter().map(|p| p.index).collect();
        // 5.6 is the limit itself: a clamped "no return".
        assert_eq!(idx, vec![6]);
        let narrowed = s.range_window(Some(RangeWindow::PAPER));
        assert_eq!(s.count_valid(narrowed), 1);
    }
}
