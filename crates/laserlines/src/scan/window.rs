//! Which readings of a scan are measurements: its window of valid ranges, below its limit
//! and a clamping driver's ceiling.

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

/// Fewest readings of a scan's largest value, and least share of its valid readings, that
/// make that value a driver's ceiling ([`clamp_ceiling`]). Real scans repeat their largest
/// reading at most 10 times (of 181-682 beams, in ranges quantised to 1 mm or 1 cm: the
/// public CARMEN, BreezySLAM and ROS logs), a clamping driver as often as the scene is
/// open.
pub const CEILING_TIES: usize = 16;

/// See [`CEILING_TIES`]: 1 in 20 of the valid readings.
pub const CEILING_SHARE: usize = 20;

/// How near the declared limit a ceiling lies, at least, as a share of it
/// ([`clamp_ceiling`]): a scan of one range everywhere far inside the limit (a made-up
/// circle) keeps its readings.
pub const CEILING_NEAR: f64 = 0.9;

/// Share of a driver's ceiling below it whose readings are taken as clamped too
/// ([`scan_window`]): a simulator that adds noise to a beam that hit nothing and then clamps
/// (Gazebo's classic laser plugin) writes the limit for half of those beams and readings a
/// few noise widths below it for the other half, which still make chords of a circle.
pub const CEILING_BAND: f64 = 0.02;

/// The value a driver writes for a beam that saw nothing: the largest reading within
/// `limits` (the scan's own `[range_min, range_max]`), when it lies within the top tenth of
/// the limit ([`CEILING_NEAR`]) and at least [`CEILING_TIES`] readings and one in
/// [`CEILING_SHARE`] of those within `limits` have exactly that value (the limit itself, or
/// a little below the `range_max` a driver declares: a SICK S300 at 29.96 m of its 30 m;
/// never with an infinite limit). Measured ranges, under noise or quantised, hardly ever repeat the
/// largest of them; readings that all stop at one value are a circle around the sensor, the
/// chords of which would be lines across empty space. `None` when no value repeats that
/// often.
#[must_use]
pub fn clamp_ceiling(ranges: &[f64], limits: RangeWindow) -> Option<f64> {
    // `contains` as two comparisons (`r >= lo` implies `r > 0`, `r <= hi` a finite `r`; NaN
    // fails both).
    if limits.min.is_nan() || limits.max.is_nan() {
        return None;
    }
    let (lo, hi) = (limits.min.max(f64::from_bits(1)), limits.max.min(f64::MAX));
    // The largest reading up to `hi` (a NaN is none), in four lanes the compiler keeps in
    // vector registers; below `lo` it is no valid reading at all.
    let mut lanes = [0.0f64; 4];
    let chunks = ranges.chunks_exact(4);
    let rest = chunks.remainder();
    for c in chunks {
        for (t, &r) in lanes.iter_mut().zip(c) {
            let v = if r <= hi { r } else { 0.0 };
            *t = if v > *t { v } else { *t };
        }
    }
    let mut top = lanes.into_iter().fold(0.0, f64::max);
    for &r in rest {
        if r <= hi && r > top {
            top = r;
        }
    }
    if top < lo || top < CEILING_NEAR * limits.max {
        return None;
    }
    let ties = ranges.iter().filter(|&&r| r == top).count();
    if ties < CEILING_TIES {
        return None;
    }
    let valid = ranges.iter().filter(|&&r| (r >= lo) & (r <= hi)).count();
    (ties * CEILING_SHARE >= valid).then_some(top)
}

/// The window of valid readings of a scan with limits `range_min..range_max` and readings
/// `ranges`: from `range_min` to below `range_max` ([`saturated_below`]), or, when the
/// readings show a driver's ceiling `c` ([`clamp_ceiling`]), to `c (1 - CEILING_BAND)`.
#[must_use]
pub fn scan_window(range_min: f64, range_max: f64, ranges: &[f64]) -> RangeWindow {
    let below = saturated_below(range_max);
    let max = match clamp_ceiling(ranges, RangeWindow::new(range_min, range_max)) {
        Some(c) => (c * (1.0 - CEILING_BAND)).min(below),
        None => below,
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
    fn a_value_many_beams_stop_at_is_a_ceiling() {
        let window = RangeWindow::new(0.02, 30.0);
        let scan = |ties: usize, others: usize| -> Vec<f64> {
            let mut r = vec![29.96; ties];
            r.extend((0..others).map(|i| 1.0 + 0.01 * i as f64));
            r
        };
        assert_eq!(clamp_ceiling(&scan(16, 300), window), Some(29.96));
        // Too few, or too small a share of the valid readings.
        assert_eq!(clamp_ceiling(&scan(15, 100), window), None);
        assert_eq!(clamp_ceiling(&scan(16, 305), window), None);
        // The largest reading repeated: a ceiling only if it is the largest.
        let mut above = scan(40, 100);
        above.push(29.97);
        assert_eq!(clamp_ceiling(&above, window), None);
        // Readings outside the window take no part.
        let mut outside = scan(20, 100);
        outside.extend([31.0, f64::NAN, f64::INFINITY]);
        assert_eq!(clamp_ceiling(&outside, window), Some(29.96));
        // Far inside the limit, one range everywhere is no ceiling.
        assert_eq!(
            clamp_ceiling(&[2.5; 100], RangeWindow::new(0.02, 5.6)),
            None
        );
        assert_eq!(
            clamp_ceiling(&[5.1; 100], RangeWindow::new(0.02, 5.6)),
            Some(5.1)
        );
        assert_eq!(clamp_ceiling(&[5.1; 100], RangeWindow::UNLIMITED), None);
        // The limit itself counts among the ties.
        let mut at_limit = vec![30.0; 16];
        at_limit.extend(scan(0, 100));
        assert_eq!(clamp_ceiling(&at_limit, window), Some(30.0));
        // A ceiling takes the band below it along; without one, only the limit goes.
        let s = Scan::new(0.0, 0.01, 0.02, 30.0, scan(20, 100)).unwrap();
        let w = s.range_window(None);
        let edge = 29.96 * (1.0 - CEILING_BAND);
        assert!(!w.contains(29.96) && !w.contains(edge + 1e-9) && w.contains(edge));
        assert!(w.contains(1.0));
        let s = Scan::new(0.0, 0.01, 0.02, 30.0, scan(15, 100)).unwrap();
        let w = s.range_window(None);
        assert!(w.contains(29.96) && w.contains(30f64.next_down()) && !w.contains(30.0));
    }
}
