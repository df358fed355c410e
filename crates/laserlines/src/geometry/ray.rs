//! Where a ray meets a segment or a circle: exact intersections, with the conventions of the
//! simulator's ray casting (an origin on the obstacle hits at 0; a ray along a segment's own
//! line meets it at its nearer end).

use crate::math::{Point2, Vector2};

/// A hit this far behind the origin (m, along the ray) still counts, at 0.
const BEHIND_TOLERANCE: f64 = 1e-9;
/// A hit this far beyond a segment's end (as a fraction of its length) still counts.
const END_TOLERANCE: f64 = 1e-12;

/// The z component of the cross product of two planar vectors.
#[inline]
fn cross(u: Vector2, v: Vector2) -> f64 {
    u.x * v.y - u.y * v.x
}

/// The ray parameter (m along the unit direction `dir` from `origin`) at which the ray
/// meets the segment `a`-`b`, if it does; `None` for a segment of zero or non-finite length.
///
/// ```
/// use laserlines::geometry::segment_ray_hit;
/// use laserlines::math::{Point2, Vector2};
/// let t = segment_ray_hit(Point2::new(2.0, -1.0), Point2::new(2.0, 1.0), Point2::origin(), Vector2::x());
/// assert_eq!(t, Some(2.0));
/// ```
#[inline]
#[must_use]
pub fn segment_ray_hit(a: Point2, b: Point2, origin: Point2, dir: Vector2) -> Option<f64> {
    let e = b - a;
    let len = e.norm();
    if !(len > 0.0 && len.is_finite()) {
        return None;
    }
    segment_ray_hit_prepared(a, b, e, len, origin, dir)
}

/// [`segment_ray_hit`] with the segment's direction `e = b - a` and length `len` (positive
/// and finite) computed once by the caller.
#[inline]
#[must_use]
pub fn segment_ray_hit_prepared(
    a: Point2,
    b: Point2,
    e: Vector2,
    len: f64,
    origin: Point2,
    dir: Vector2,
) -> Option<f64> {
    let ao = a - origin;
    let denom = cross(dir, e);
    if denom.abs() <= 1e-12 * len {
        // Parallel. Only a ray running along the segment's own line meets it, at the nearer
        // end (or at 0 when the origin is on the segment).
        let offset = cross(dir, ao).abs();
        if offset > 1e-9 * (1.0 + ao.norm()) {
            return None;
        }
        let ta = ao.dot(&dir);
        let tb = (b - origin).dot(&dir);
        let (near, far) = if ta <= tb { (ta, tb) } else { (tb, ta) };
        if far < -BEHIND_TOLERANCE {
            return None;
        }
        return Some(near.max(0.0));
    }
    let t = cross(ao, e) / denom;
    let s = cross(ao, dir) / denom;
    if t >= -BEHIND_TOLERANCE && (-END_TOLERANCE..=1.0 + END_TOLERANCE).contains(&s) {
        Some(t.max(0.0))
    } else {
        None
    }
}

/// The ray parameter at which the ray from `origin` along unit `dir` meets the circle of
/// `radius` around `centre`, if it does (0 from inside or on the rim); `None` for a radius
/// that is not positive and finite.
#[inline]
#[must_use]
pub fn circle_ray_hit(centre: Point2, radius: f64, origin: Point2, dir: Vector2) -> Option<f64> {
    let r = radius;
    if !(r > 0.0 && r.is_finite()) {
        return None;
    }
    let f = origin - centre;
    let c = f.norm_squared() - r * r;
    if !c.is_finite() {
        return None;
    }
    if c <= 0.0 {
        // The origin is inside the disc or on its rim.
        return Some(0.0);
    }
    let b = f.dot(&dir);
    if b >= 0.0 {
        return None;
    }
    let perp = cross(f, dir);
    let disc = r * r - perp * perp;
    if disc < 0.0 {
        return None;
    }
    // The nearer root -b - sqrt(disc), computed as c / (-b + sqrt(disc)) so that it stays
    // accurate when the origin is close to the rim.
    Some(c / (-b + disc.sqrt()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point2 {
        Point2::new(x, y)
    }

    #[test]
    fn segments_by_hand() {
        let x = Vector2::x();
        // Straight ahead, obliquely, behind, past the end.
        assert_eq!(
            segment_ray_hit(p(2.0, -1.0), p(2.0, 1.0), p(0.0, 0.0), x),
            Some(2.0)
        );
        let d = Vector2::new(1.0, 1.0).normalize();
        let t = segment_ray_hit(p(2.0, -5.0), p(2.0, 5.0), p(0.0, 0.0), d).unwrap();
        assert!((t - 2.0 * 2f64.sqrt()).abs() < 1e-12);
        assert_eq!(
            segment_ray_hit(p(-2.0, -1.0), p(-2.0, 1.0), p(0.0, 0.0), x),
            None
        );
        assert_eq!(
            segment_ray_hit(p(2.0, 1.0), p(2.0, 3.0), p(0.0, 0.0), x),
            None
        );
        // Along the segment's own line: its nearer end; on it: 0.
        assert_eq!(
            segment_ray_hit(p(3.0, 0.0), p(5.0, 0.0), p(0.0, 0.0), x),
            Some(3.0)
        );
        assert_eq!(
            segment_ray_hit(p(-1.0, 0.0), p(5.0, 0.0), p(0.0, 0.0), x),
            Some(0.0)
        );
        // Degenerate.
        assert_eq!(
            segment_ray_hit(p(1.0, 1.0), p(1.0, 1.0), p(0.0, 0.0), x),
            None
        );
        assert_eq!(
            segment_ray_hit(p(f64::NAN, 1.0), p(1.0, 1.0), p(0.0, 0.0), x),
            None
        );
    }

    #[test]
    fn circles_by_hand() {
        let x = Vector2::x();
        let t = circle_ray_hit(p(3.0, 0.0), 0.5, p(0.0, 0.0), x).unwrap();
        assert!((t - 2.5).abs() < 1e-12);
        assert_eq!(circle_ray_hit(p(3.0, 0.0), 0.5, p(3.1, 0.0), x), Some(0.0));
        assert_eq!(circle_ray_hit(p(-3.0, 0.0), 0.5, p(0.0, 0.0), x), None);
        assert_eq!(circle_ray_hit(p(3.0, 1.0), 0.5, p(0.0, 0.0), x), None);
        assert_eq!(circle_ray_hit(p(3.0, 0.0), 0.0, p(0.0, 0.0), x), None);
        assert_eq!(circle_ray_hit(p(3.0, 0.0), f64::NAN, p(0.0, 0.0), x), None);
    }
}
