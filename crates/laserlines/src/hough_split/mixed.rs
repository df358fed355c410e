//! Mixed pixels: a beam that grazes a depth edge returns a range between the two surfaces, a
//! point on neither. Left in, it halves the jump and can join the near object to the far
//! wall. Not in the paper.

use crate::noise::{NoiseEstimator, RangeNoise, lag_for};
use crate::scan::{RangeWindow, ScanView};

/// The noise the mixed-pixel test holds neighbouring beams to, given the scan's `noise` and
/// whether it was estimated: a given noise as it is; an estimate read an even number of beams
/// apart (two at 0.5 deg), the larger of it and the estimate one beam apart (by `adjacent`,
/// its own working memory). A scanner that fills its 0.5 deg steps with two interleaved 1 deg
/// sweeps (a SICK LMS) offsets neighbouring beams by a centimetre or two, which the estimate
/// within one sweep does not see: every other beam of a wall then lies off both its
/// neighbours' lines, and the test took whole stretches of wall for mixed pixels.
pub(crate) fn between_neighbours(
    adjacent: &mut NoiseEstimator,
    scan: ScanView<'_>,
    (window, floor): (RangeWindow, f64),
    (noise, estimated): (RangeNoise, bool),
) -> RangeNoise {
    if !estimated || lag_for(scan.angle_increment) % 2 == 1 {
        return noise;
    }
    adjacent
        .estimate_at(scan, window, floor, 1)
        .map_or(noise, |n| {
            RangeNoise::new(
                noise.sigma_min.max(n.sigma_min),
                noise.fraction.max(n.fraction),
            )
        })
}

/// Standard deviations of an extrapolation's error beyond which a point is on neither side.
const SIGMAS: f64 = 3.0;

/// `sqrt(6)`: the standard deviation of `r_i - (2 r_(i-1) - r_(i-2))` in units of `sigma`.
const EXTRAPOLATION: f64 = 2.449_489_742_783_178;

/// True when beam `i` of `ranges` lies on neither neighbouring surface: its range is more than
/// three standard deviations of an extrapolation (`sqrt(6) sigma(r)`) from both the line
/// through beams `i - 2, i - 1` and the line through `i + 1, i + 2` (linear extrapolation of
/// the ranges, exact enough over two beams). A corner's apex lies on both lines and a point at
/// a depth edge on its own side's, so only isolated points (mixed pixels, spikes) are found.
/// Points without two valid neighbours on each side are never isolated.
#[inline]
pub(crate) fn isolated(ranges: &[f64], i: usize, window: RangeWindow, noise: &RangeNoise) -> bool {
    // Beams `i - 2 ..= i + 2`: none when `i < 2` or `i + 2` is past the end.
    let Some(&[a, b, r, c, d]) = i.checked_sub(2).and_then(|s| ranges.get(s..s + 5)) else {
        return false;
    };
    let limit = SIGMAS * EXTRAPOLATION * noise.sigma(r);
    // The extrapolations first: almost every point fails them (so do NaN neighbours), and the
    // neighbours' validity is asked only of the few that pass.
    (r - (2.0 * b - a)).abs() > limit
        && (r - (2.0 * c - d)).abs() > limit
        && window.contains(a)
        && window.contains(b)
        && window.contains(c)
        && window.contains(d)
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: RangeWindow = RangeWindow::new(0.02, 10.0);
    const NOISE: RangeNoise = RangeNoise::new(0.005, 0.0);

    #[test]
    fn a_point_between_two_surfaces_is_isolated() {
        // A leg at 1.1 m, then a mixed pixel at 1.25 m, then the wall at 1.4 m.
        let r = [1.1, 1.1, 1.1, 1.25, 1.4, 1.4, 1.4];
        assert!(isolated(&r, 3, W, &NOISE));
        assert!(!isolated(&r, 2, W, &NOISE) && !isolated(&r, 4, W, &NOISE));
    }

    #[test]
    fn corners_grazing_walls_and_edges_are_not() {
        // A corner's apex: on both lines.
        let corner = [2.0, 1.9, 1.8, 1.7, 1.8, 1.9, 2.0];
        assert!(!isolated(&corner, 3, W, &NOISE));
        // A steep, straight run (a wall seen at a grazing angle).
        let grazing = [1.0, 1.2, 1.4, 1.6, 1.8, 2.0, 2.2];
        assert!((0..grazing.len()).all(|i| !isolated(&grazing, i, W, &NOISE)));
        // A depth edge without a mixed pixel.
        let edge = [1.1, 1.1, 1.1, 1.4, 1.4, 1.4];
        assert!((0..edge.len()).all(|i| !isolated(&edge, i, W, &NOISE)));
        // Too few valid neighbours.
        let holes = [1.1, f64::NAN, 1.1, 1.25, 1.4, 1.4];
        assert!(!isolated(&holes, 3, W, &NOISE));
    }

    #[test]
    fn invalid_neighbours_never_make_a_point_isolated() {
        // Every neighbour value, valid or not (NaN, infinities, zero, negative, beyond the
        // window), at every position around a point between two surfaces: isolated exactly
        // when all four neighbours are valid and the point is far from both extrapolations.
        let values = [
            1.1,
            1.4,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            0.0,
            -1.1,
            0.01,
            25.0,
            f64::MAX,
        ];
        let mut isolated_seen = 0;
        for &a in &values {
            for &b in &values {
                for &c in &values {
                    for &d in &values {
                        let r = [a, b, 1.25, c, d];
                        let valid = [a, b, c, d].iter().all(|&v| W.contains(v));
                        let limit = SIGMAS * EXTRAPOLATION * NOISE.sigma(1.25);
                        let far = (1.25 - (2.0 * b - a)).abs() > limit
                            && (1.25 - (2.0 * c - d)).abs() > limit;
                        assert_eq!(isolated(&r, 2, W, &NOISE), valid && far, "{r:?}");
                        isolated_seen += usize::from(valid && far);
                    }
                }
            }
        }
        assert!(isolated_seen > 0);
    }
}
