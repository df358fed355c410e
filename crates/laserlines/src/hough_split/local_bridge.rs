//! The bridge across a surface that returns few of its beams on a scan that returns most of
//! them: glass, a dark or shiny panel. The scan's own bridge
//! ([`HoughSplitParams::bridge_for`]) is decided by the dropouts of the whole scan, so such a
//! surface, its points two to six beams apart, fell into runs too short for a line.
//!
//! Two points further apart than that bridge reaches are joined by the bridge of a sparse
//! scan ([`LOCAL_DROPOUT`] of its returns followed by a missing beam) when all the beams
//! between them returned nothing (no range at all: NaN, 0 or below the smallest valid range;
//! a reading beyond the range limit sees through, something in front is an edge) and
//! [`LOCAL_MIN_MISSING`] of the [`LOCAL_WINDOW`] beams on each side returned nothing too: the
//! surface itself is sparse there. Their distance must still lie within that bridge's
//! breakpoint distance `D`, and the surface they would share must face the sensor at no more
//! than 70 deg of incidence ([`LOCAL_MAX_SIN_INCIDENCE`]): points strung out along the beams
//! (clutter beyond the range, legs) are no glass wall.

use super::lines::returned_nothing;
use super::params::HoughSplitParams;
use super::points::Pt;

/// The dropout rate whose bridge joins points of a locally sparse surface: gaps of up to six
/// missing beams, `D` for the mean angle between returns of twice the beam spacing.
pub const LOCAL_DROPOUT: f64 = 0.5;

/// The sine of the largest incidence (70 deg) of a surface whose points the local bridge
/// joins: a streak of points along the beams (clutter, legs, mixed pixels in open space
/// beyond the range) is no glass wall.
pub const LOCAL_MAX_SIN_INCIDENCE: f64 = 0.94;

/// Beams on each side of two points whose returns tell whether the surface is sparse there.
pub const LOCAL_WINDOW: usize = 16;

/// The share of the beams around two points that must have returned nothing for the local
/// bridge to join them.
pub const LOCAL_MIN_MISSING: f64 = 0.3;

/// The local bridge of one scan shape: `factor[g - 1]` the geometric part of `D` for two
/// points `g` beams apart (NaN where none).
#[derive(Debug, Default, Clone)]
pub(crate) struct LocalBridge {
    key: Option<(u64, u64, u64, usize)>,
    factor: Vec<f64>,
    /// The scan's own bridge reaches this many beams; the local one only beyond.
    dense_reach: usize,
    /// The smallest valid range, above 0: below it (or NaN) a beam returned nothing.
    lo: f64,
}

impl LocalBridge {
    /// Makes the table right for `p`, beams `increment` apart and a scan whose own bridge
    /// reaches `dense_reach` beams, with its smallest valid range `lo` (below it, or NaN, a
    /// beam returned nothing).
    pub(crate) fn prepare(
        &mut self,
        p: &HoughSplitParams,
        (increment, dense_reach): (f64, usize),
        lo: f64,
    ) {
        // Above 0 as a valid range is (a reading of 0 returned nothing).
        self.lo = lo.max(f64::from_bits(1));
        self.table(p, increment, dense_reach);
    }

    /// The table of `D`'s geometric part, made again only when the scan shape changed.
    fn table(&mut self, p: &HoughSplitParams, increment: f64, dense_reach: usize) {
        let bridge = p.bridge_for(increment, LOCAL_DROPOUT);
        let key = (
            increment.to_bits(),
            p.bridge_incidence.to_bits(),
            bridge.spacing.to_bits(),
            dense_reach,
        );
        if self.key == Some(key) {
            return;
        }
        self.key = Some(key);
        self.dense_reach = dense_reach;
        p.breakpoint_factors(increment, bridge, &mut self.factor);
        // Nothing beyond the scan's own reach: no local bridge.
        if self.factor.len() <= dense_reach {
            self.factor.clear();
        }
    }

    /// Most beams apart two points the local bridge may join (0 when it joins none).
    #[cfg(test)]
    fn reach(&self) -> usize {
        self.factor.len()
    }

    /// The geometric part of `D` for the point `a` and a point of beam `b`, `gap` beams
    /// apart, beyond the scan's own bridge: `None` unless the beams between them and
    /// [`LOCAL_MIN_MISSING`] of those around them returned nothing (`ranges` by beam).
    pub(crate) fn factor(&self, ranges: &[f64], a: &Pt, b: usize, gap: usize) -> Option<f64> {
        if gap <= self.dense_reach {
            return None;
        }
        let f = *self.factor.get(gap.wrapping_sub(1))?;
        let nothing = |r: &f64| returned_nothing(*r, self.lo);
        if !ranges.get(a.idx + 1..b)?.iter().all(nothing) {
            return None;
        }
        let before = ranges.get(a.idx.saturating_sub(LOCAL_WINDOW)..a.idx)?;
        let after = ranges.get(b + 1..(b + 1 + LOCAL_WINDOW).min(ranges.len()))?;
        let around = before.len() + after.len();
        let missing = before.iter().chain(after).filter(|r| nothing(r)).count();
        (around > 0 && missing as f64 >= LOCAL_MIN_MISSING * around as f64).then_some(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pt(idx: usize, r: f64) -> Pt {
        Pt {
            x: r,
            y: 0.0,
            range: r,
            idx,
        }
    }

    #[test]
    fn a_sparse_stretch_is_bridged_a_dense_one_or_an_object_between_not() {
        let p = HoughSplitParams::default();
        let mut lb = LocalBridge::default();
        // A URG-04LX's beams; the scan's own bridge reaches 3 beams.
        lb.prepare(&p, (0.00614, 3), 0.02);
        // Beams 20..=60 on a glass wall: every third returns.
        let mut ranges = vec![2.0; 80];
        for (i, r) in ranges.iter_mut().enumerate().take(61).skip(20) {
            if i % 3 != 0 {
                *r = f64::NAN;
            }
        }
        // Points 30 and 36: five missing beams between them.
        ranges[33] = f64::NAN;
        assert_eq!(lb.reach(), 7);
        let a = pt(30, 2.0);
        assert!(lb.factor(&ranges, &a, 36, 6).is_some_and(|f| f > 0.0));
        // Within the scan's own reach, or beyond the local one: not the local bridge's.
        assert!(lb.factor(&ranges, &a, 33, 3).is_none());
        assert!(lb.factor(&ranges, &a, 38, 8).is_none());
        // A beam between that returned (something in front) or saw through (+inf).
        for seen in [1.2, f64::INFINITY] {
            let mut r = ranges.clone();
            r[34] = seen;
            assert!(lb.factor(&r, &a, 36, 6).is_none());
        }
        // The same gap on a surface that returns its beams around it: a dense stretch.
        let mut dense = vec![2.0; 80];
        for r in &mut dense[31..36] {
            *r = f64::NAN;
        }
        assert!(lb.factor(&dense, &a, 36, 6).is_none());
        // At the scan's ends the window is what there is.
        assert!(lb.factor(&ranges[..40], &a, 36, 6).is_some());
    }

    #[test]
    fn a_scan_whose_own_bridge_reaches_as_far_has_none() {
        let p = HoughSplitParams::default();
        let mut lb = LocalBridge::default();
        lb.prepare(&p, (0.00614, 7), 0.02);
        assert_eq!(lb.reach(), 0);
        assert!(lb.factor(&[f64::NAN; 20], &pt(2, 2.0), 9, 7).is_none());
    }
}
