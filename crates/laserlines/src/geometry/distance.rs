//! Distances and nearest points between points, segments and axis-aligned boxes.

use crate::math::{Point2, Vector2};

/// The point of the segment `a`-`b` nearest to `p` (`a` for a zero-length segment).
#[inline]
#[must_use]
pub fn nearest_on_segment(p: Point2, a: Point2, b: Point2) -> Point2 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    if len2 <= 0.0 {
        return a;
    }
    let t = ((p - a).dot(&ab) / len2).clamp(0.0, 1.0);
    a + ab * t
}

/// Distance from `p` to the segment `a`-`b`, m.
#[inline]
#[must_use]
pub fn distance_to_segment(p: Point2, a: Point2, b: Point2) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    if len2 <= 0.0 {
        return (p - a).norm();
    }
    let t = ((p - a).dot(&ab) / len2).clamp(0.0, 1.0);
    (p - (a + ab * t)).norm()
}

/// Distance from `p` to the axis-aligned box of half extents `half` centred on the origin
/// (0 inside).
#[inline]
#[must_use]
pub fn distance_to_box(p: Point2, half: Vector2) -> f64 {
    let dx = (p.x.abs() - half.x).max(0.0);
    let dy = (p.y.abs() - half.y).max(0.0);
    (dx * dx + dy * dy).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point2 {
        Point2::new(x, y)
    }

    #[test]
    fn segments_and_boxes_by_hand() {
        let (a, b) = (p(0.0, 0.0), p(2.0, 0.0));
        assert_eq!(distance_to_segment(p(1.0, 1.0), a, b), 1.0);
        assert_eq!(distance_to_segment(p(3.0, 0.0), a, b), 1.0);
        assert_eq!(distance_to_segment(p(0.0, 2.0), a, a), 2.0);
        assert_eq!(nearest_on_segment(p(1.0, 1.0), a, b), p(1.0, 0.0));
        assert_eq!(nearest_on_segment(p(-1.0, 1.0), a, b), a);
        assert_eq!(nearest_on_segment(p(5.0, 5.0), a, a), a);
        let half = Vector2::new(0.25, 0.2);
        assert_eq!(distance_to_box(p(0.1, 0.1), half), 0.0);
        assert!((distance_to_box(p(0.35, 0.0), half) - 0.1).abs() < 1e-12);
        assert!((distance_to_box(p(0.55, 0.6), half) - 0.5).abs() < 1e-12);
    }
}
