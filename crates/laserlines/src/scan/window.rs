//! Which readings of a scan are measurements: its window of valid ranges, below its limit
//! (and below a band under it when the scan shows a driver that clamps).

/// The largest valid reading of a scan whose limit is `range_max`: the float just below it
/// when it is finite and positive (else `range_max` as it is). Drivers that clamp write
/// `range_max` itself for a beam that saw nothing within range (the ROS driver of the SICK
/// LMS1xx by default, Gazebo's classic laser plugin, `max_range_returns` of the simulator):
/// taken as points, those readings lie on a circle around the sensor, which every extractor
/// cut into chords, lines across empty space. A surface exactly at the limit cannot be told
/// from nothing there, so such a reading is taken as what it most likely is: no return,
/// seen through (as `+inf`, REP 117), never a point.
#[must_use]
pub fn saturated_below(range_max: f64) -> f64 {
    if range_max.is_finite() && range_max > 0.0 {
        range_max.next_down()
    } else {
        range_max
    }
}

/// Fewest readings of the limit itself, and least share of the readings within the limits,
/// that show a driver that clamps ([`clamped`]).
pub const CLAMPED_READINGS: usize = 16;

/// See [`CLAMPED_READINGS`]: 1 in 20 of the readings within the limits.
pub const CLAMPED_SHARE: usize = 20;

/// Share of the limit below it whose readings are taken as clamped too when a scan shows a
/// driver that clamps ([`scan_window`]): a simulator that adds noise to a beam that hit
/// nothing and then clamps (Gazebo's classic laser plugin) writes the limit for half of
/// those beams and readings a few noise widths below it for the other half, which still
/// make chords of a circle.
pub const CLAMPED_BAND: f64 = 0.02;

/// True when `ranges` show a driver that clamps at `range_max`: at least
/// [`CLAMPED_READINGS`] readings, and one in [`CLAMPED_SHARE`] of those in
/// `[range_min, range_max]`, are exactly `range_max` (finite). A measured range lands exactly
/// on the limit hardly ever: the public CARMEN, BreezySLAM and ROS logs have no such reading.
/// Only the limit itself counts: a value below it that many beams share is as likely a
/// surface read through coarse steps (a depth camera's at its far end repeats its last step
/// dozens of times) as a driver's ceiling, and is left as it is.
#[must_use]
pub fn clamped(ranges: &[f64], range_min: f64, range_max: f64) -> bool {
    if !(range_max.is_finite() && range_max > 0.0) {
        return false;
    }
    let at_limit = ranges.iter().filter(|&&r| r == range_max).count();
    if at_limit < CLAMPED_READINGS {
        return false;
    }
    let limits = RangeWindow::new(range_min, range_max);
    let within = ranges.iter().filter(|&&r| limits.contains(r)).count();
    at_limit * CLAMPED_SHARE >= within
}

/// The window of valid readings of a scan with limits `range_min..range_max` and readings
/// `ranges`: from `range_min` to below `range_max` ([`saturated_below`]), or, when the
/// readings show a driver that clamps ([`clamped`]), to `range_max (1 - CLAMPED_BAND)`.
#[must_use]
pub fn scan_window(range_min: f64, range_max: f64, ranges: &[f64]) -> RangeWindow {
    let max = if clamped(ranges, range_min, range_max) {
        range_max * (1.0 - CLAMPED_BAND)
    } else {
        saturated_below(range_max)
    };
    RangeWindow::new(range_min, max)
}

/// The one definition of a valid range, used by every algorithm: finite, strictly positive,
/// and within `[min, max]` (inclusive, as in ROS). With the `serde` feature it is written
/// `[min, max]`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(from = "[f64; 2]", into = "[f64; 2]")
)]
pub struct RangeWindow {
    /// Smallest valid range, m.
    pub min: f64,
    /// Largest valid range, m.
    pub max: f64,
}

impl RangeWindow {
    /// A window `[min, max]`, metres.
    #[must_use]
    pub const fn new(min: f64, max: f64) -> Self {
        Self { min, max }
    }

    /// The window that accepts every finite positive range.
    pub const UNLIMITED: Self = Self::new(0.0, f64::INFINITY);

    /// The paper's window: ranges outside (0.03 m, 3.00 m) are noise and never used.
    pub const PAPER: Self = Self::new(0.03, 3.00);

    /// True when `r` is a measurement: finite, `> 0` and within `[min, max]`.
    #[must_use]
    pub fn contains(self, r: f64) -> bool {
        r.is_finite() && r > 0.0 && r >= self.min && r <= self.max
    }

    /// The intersection of two windows (empty windows simply contain nothing).
    #[must_use]
    pub fn intersect(self, other: Self) -> Self {
        Self::new(self.min.max(other.min), self.max.min(other.max))
    }
}

impl From<[f64; 2]> for RangeWindow {
    fn from([min, max]: [f64; 2]) -> Self {
        Self::new(min, max)
    }
}

impl From<RangeWindow> for [f64; 2] {
    fn from(w: RangeWindow) -> Self {
        [w.min, w.max]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scan::Scan;

    #[test]
    fn many_readings_of_the_limit_show_a_driver_that_clamps() {
        let scan = |at_limit: usize, others: usize| -> Vec<f64> {
            let mut r = vec![30.0; at_limit];
            r.extend((0..others).map(|i| 1.0 + 0.01 * i as f64));
            r
        };
        assert!(clamped(&scan(16, 300), 0.02, 30.0));
        // Too few, or too small a share of the readings within the limits.
        assert!(!clamped(&scan(15, 100), 0.02, 30.0));
        assert!(!clamped(&scan(16, 305), 0.02, 30.0));
        // Readings outside the limits take no part; an infinite limit is never a clamp.
        let mut outside = scan(16, 300);
        outside.extend([31.0, f64::NAN, f64::INFINITY, 0.0, -1.0]);
        assert!(clamped(&outside, 0.02, 30.0));
        assert!(!clamped(&[f64::INFINITY; 40], 0.02, f64::INFINITY));
        // A value below the limit that many beams share is left as it is.
        let mut below = vec![29.96; 40];
        below.extend(scan(0, 100));
        assert!(!clamped(&below, 0.02, 30.0));
        let s = Scan::new(0.0, 0.01, 0.02, 30.0, below).unwrap();
        assert!(s.range_window(None).contains(29.96));
        // A driver that clamps takes the band below the limit along; without one, only the
        // limit goes.
        let s = Scan::new(0.0, 0.01, 0.02, 30.0, scan(20, 100)).unwrap();
        let w = s.range_window(None);
        let edge = 30.0 * (1.0 - CLAMPED_BAND);
        assert!(!w.contains(30.0) && !w.contains(edge + 1e-9) && w.contains(edge));
        assert!(w.contains(1.0));
        let s = Scan::new(0.0, 0.01, 0.02, 30.0, scan(15, 100)).unwrap();
        let w = s.range_window(None);
        assert!(w.contains(30f64.next_down()) && !w.contains(30.0));
    }
}
