//! Whether the beams between two pieces see through the line they would share: step 7's
//! physical check on top of its statistical one ([`super::collinear`]).
//!
//! Pieces of one wall lie apart because something stands in front of the wall between them
//! (its returns nearer than the wall), because the wall returned nothing there (glass, a dark
//! patch), or because of an opening in it (a doorway: returns beyond it). Beams between them
//! that see beyond their joint line for longer than a doorway show that no wall runs there.
//! Two short, uncertain pieces of different surfaces (a door leaf and a wall metres behind
//! it, seen at 6 m) pass the chi-square test for almost any line through both, and would
//! take one fit several degrees off each; collinear walls with a wide opening between them
//! are one line still, which a piece certain on its own shows.

use super::points::Pt;
use crate::fit::NormalFit;
use crate::math::Point2;
use crate::noise::RangeNoise;

/// Longest stretch of a joint line, m, that the beams between its pieces may see through: a
/// doorway, double doors included (up to about 1.8 m), or a missing arena panel (1.2 m).
pub(crate) const OPENING: f64 = 2.0;

/// Standard deviations of the range noise beyond the joint line from which a return sees
/// through it.
const BEYOND_SIGMAS: f64 = 3.0;

/// The length, m, of the stretch of the line `fit` between the pieces' facing ends `ends`
/// (projected onto it) that the returns on the beams strictly between `after` and `before`
/// (beam numbers of the last point of one piece and the first of the next; `returns` in beam
/// order) saw through: from the first to the last point of the line where a beam that
/// returned beyond it (by [`BEYOND_SIGMAS`]) meets it.
pub(crate) fn seen_beyond(
    returns: &[Pt],
    (after, before): (usize, usize),
    ends: (Point2, Point2),
    fit: &NormalFit,
    noise: &RangeNoise,
) -> f64 {
    if before <= after + 1 {
        return 0.0;
    }
    let start = returns.partition_point(|q| q.idx <= after);
    let (n, r) = (fit.normal, fit.r);
    // Along the line: the direction of the normal turned by 90 deg.
    let along = |x: f64, y: f64| y * n.x - x * n.y;
    let (a, b) = (along(ends.0.x, ends.0.y), along(ends.1.x, ends.1.y));
    let (from, to) = (a.min(b), a.max(b));
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for q in returns[start..].iter().take_while(|q| q.idx < before) {
        // The beam's direction against the normal: where the beam meets the line.
        let cos = (n.x * q.x + n.y * q.y) / q.range;
        if cos <= 0.0 {
            // The beam runs parallel to the line or away from it: it cannot meet it.
            continue;
        }
        let at = r / cos;
        if q.range <= at + BEYOND_SIGMAS * noise.sigma(at) {
            continue;
        }
        let t = along(q.x, q.y) * (at / q.range);
        // Where the beam meets the line beyond either piece: not between them.
        if from < t && t < to {
            lo = lo.min(t);
            hi = hi.max(t);
        }
    }
    (hi - lo).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A return of beam `idx` at `(x, y)`.
    fn pt(idx: usize, x: f64, y: f64) -> Pt {
        Pt {
            x,
            y,
            range: x.hypot(y),
            idx,
        }
    }

    /// The wall `y = 2` (normal `+y`, `r = 2`).
    fn wall() -> NormalFit {
        NormalFit {
            normal: crate::math::Vector2::new(0.0, 1.0),
            r: 2.0,
            n: 20,
            s2: 0.0,
            covariance: crate::math::Matrix2::zeros(),
        }
    }

    #[test]
    fn a_doorway_is_a_short_view_beyond_and_a_box_in_front_none() {
        let noise = RangeNoise::new(0.01, 0.01);
        // The pieces end at x = -5 and x = 5 of the wall.
        let ends = (Point2::new(-5.0, 2.0), Point2::new(5.0, 2.0));
        let view = |pts: &[Pt], between| seen_beyond(pts, between, ends, &wall(), &noise);
        // Beams 11..=19 see 1 m beyond the wall at x from -0.8 to 0.8: a doorway.
        let door: Vec<Pt> = (11..20)
            .map(|i| pt(i, 0.2 * (i as f64 - 15.0) * 1.5, 3.0))
            .collect();
        assert!((view(&door, (10, 20)) - 1.6).abs() < 1e-9);
        // The same beyond x from -2.4 to 2.4.
        let open: Vec<Pt> = (11..20)
            .map(|i| pt(i, 0.6 * (i as f64 - 15.0) * 1.5, 3.0))
            .collect();
        assert!((view(&open, (10, 20)) - 4.8).abs() < 1e-9);
        // Returns in front of the wall (a box), or on it within the noise: nothing beyond.
        let front: Vec<Pt> = (11..20)
            .map(|i| pt(i, 0.6 * (i as f64 - 15.0) * 0.6, 1.2))
            .collect();
        assert_eq!(view(&front, (10, 20)), 0.0);
        let on: Vec<Pt> = (11..20)
            .map(|i| pt(i, 0.6 * (i as f64 - 15.0) * 1.5, 2.02))
            .collect();
        assert_eq!(view(&on, (10, 20)), 0.0);
        // Only the beams strictly between the pieces count, and only where they meet the
        // line between the pieces' ends.
        assert_eq!(view(&open, (14, 16)), 0.0);
        assert_eq!(view(&open, (19, 20)), 0.0);
        // Pieces ending at x = -1 and 1: the beams meeting the wall at -0.6, 0 and 0.6.
        let near = (Point2::new(-1.0, 2.0), Point2::new(1.0, 2.0));
        let beyond = seen_beyond(&open, (10, 20), near, &wall(), &noise);
        assert!((beyond - 1.2).abs() < 1e-9, "{beyond}");
    }
}
