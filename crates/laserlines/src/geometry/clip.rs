//! Liang-Barsky clipping: the part of a segment or a ray inside half-planes, an axis-aligned
//! box or a wedge around the origin.

use crate::math::{Point2, Vector2};

/// Liang-Barsky clipping: the parameter range `t0..=t1` within `0..=1` over which the
/// points `a + t d` of a segment keep every constraint `p t <= q`, given as `(p, q)`;
/// `None` when no part does.
///
/// ```
/// use laserlines::geometry::clip_segment;
/// // The segment from x = -1 to x = 3 (d = 4) clipped to x <= 1: -1 + 4 t <= 1.
/// assert_eq!(clip_segment(&[(4.0, 2.0)]), Some((0.0, 0.5)));
/// assert_eq!(clip_segment(&[(0.0, -1.0)]), None);
/// ```
#[inline]
#[must_use]
pub fn clip_segment(constraints: &[(f64, f64)]) -> Option<(f64, f64)> {
    let mut t0: f64 = 0.0;
    let mut t1: f64 = 1.0;
    for &(p, q) in constraints {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
            if t0 > t1 {
                return None;
            }
        }
    }
    Some((t0, t1))
}

/// True when the segment `a`-`b` meets the axis-aligned box `lo..hi` (Liang-Barsky).
#[inline]
#[must_use]
pub fn segment_touches_box(a: Point2, b: Point2, lo: Point2, hi: Point2) -> bool {
    let d = b - a;
    clip_segment(&[
        (-d.x, a.x - lo.x),
        (d.x, hi.x - a.x),
        (-d.y, a.y - lo.y),
        (d.y, hi.y - a.y),
    ])
    .is_some()
}

/// The parameters `(t_in, t_out)` (`t_in >= 0`) over which the ray from `origin` along
/// `dir` stays in the axis-aligned box `lo..hi`; `None` when it misses the box.
#[inline]
#[must_use]
pub fn clip_ray_to_box(origin: Point2, dir: Vector2, lo: Point2, hi: Point2) -> Option<(f64, f64)> {
    let mut t0: f64 = 0.0;
    let mut t1 = f64::INFINITY;
    for (o, d, l, h) in [(origin.x, dir.x, lo.x, hi.x), (origin.y, dir.y, lo.y, hi.y)] {
        if d == 0.0 {
            if o < l || o > h {
                return None;
            }
        } else {
            let (a, b) = ((l - o) / d, (h - o) / d);
            let (a, b) = if a <= b { (a, b) } else { (b, a) };
            t0 = t0.max(a);
            t1 = t1.min(b);
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

/// The part of the segment `a`-`b` whose bearing from the origin lies in `from..=to` (rad,
/// counter-clockwise, `to - from` in `(0, pi)`), as `(start, end)` with `start` the
/// clockwise end; `None` when no part does or the input is degenerate.
#[must_use]
pub fn clip_to_wedge(a: Point2, b: Point2, from: f64, to: f64) -> Option<(Point2, Point2)> {
    if !(a.x.is_finite() && a.y.is_finite() && b.x.is_finite() && b.y.is_finite()) {
        return None;
    }
    let span = to - from;
    if !(span > 0.0 && span < std::f64::consts::PI) {
        return None;
    }
    // The wedge is the intersection of two half-planes through the origin:
    // cross(d_from, p) >= 0 and cross(p, d_to) >= 0.
    let d_from = Vector2::new(from.cos(), from.sin());
    let d_to = Vector2::new(to.cos(), to.sin());
    let cross = |u: Vector2, v: Vector2| u.x * v.y - u.y * v.x;
    let e = b - a;
    let mut t0: f64 = 0.0;
    let mut t1: f64 = 1.0;
    // Each constraint f(t) = f0 + t * df >= 0.
    for (f0, df) in [
        (cross(d_from, a.coords), cross(d_from, e)),
        (cross(a.coords, d_to), cross(e, d_to)),
    ] {
        if df == 0.0 {
            if f0 < 0.0 {
                return None;
            }
        } else {
            let t = -f0 / df;
            if df > 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    let p0 = a + e * t0;
    let p1 = a + e * t1;
    // Both half-planes also hold for points behind the origin only when the wedge is wider
    // than pi, which it is not; but a piece through the origin itself has no bearing.
    if p0.coords.norm() == 0.0 && p1.coords.norm() == 0.0 {
        return None;
    }
    // Order by bearing: start is the clockwise end.
    if cross(p0.coords, p1.coords) >= 0.0 {
        Some((p0, p1))
    } else {
        Some((p1, p0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point2 {
        Point2::new(x, y)
    }

    #[test]
    fn segment_box_overlap() {
        let (lo, hi) = (p(0.0, 0.0), p(1.0, 1.0));
        assert!(segment_touches_box(p(-1.0, 0.5), p(2.0, 0.5), lo, hi));
        assert!(segment_touches_box(p(0.2, 0.2), p(0.3, 0.3), lo, hi));
        assert!(!segment_touches_box(p(-1.0, 2.0), p(2.0, 1.5), lo, hi));
        assert!(segment_touches_box(p(1.0, -1.0), p(1.0, 2.0), lo, hi));
    }

    #[test]
    fn rays_enter_and_leave_a_box() {
        let (lo, hi) = (p(1.0, -1.0), p(3.0, 1.0));
        let (t0, t1) = clip_ray_to_box(p(0.0, 0.0), Vector2::new(1.0, 0.0), lo, hi).unwrap();
        assert_eq!((t0, t1), (1.0, 3.0));
        // From inside: enters at 0.
        let (t0, _) = clip_ray_to_box(p(2.0, 0.0), Vector2::new(0.0, 1.0), lo, hi).unwrap();
        assert_eq!(t0, 0.0);
        assert!(clip_ray_to_box(p(0.0, 2.0), Vector2::new(1.0, 0.0), lo, hi).is_none());
        assert!(clip_ray_to_box(p(0.0, 0.0), Vector2::new(-1.0, 0.0), lo, hi).is_none());
    }

    #[test]
    fn wedges_by_hand() {
        // A wall at y = 1 from x = -3 to 3, clipped to 50..120 deg:
        // x from 1/tan(120 deg) = -0.577 to 1/tan(50 deg) = 0.839.
        let (from, to) = (50f64.to_radians(), 120f64.to_radians());
        let (s, e) = clip_to_wedge(p(-3.0, 1.0), p(3.0, 1.0), from, to).unwrap();
        assert!((s.x - 1.0 / 50f64.to_radians().tan()).abs() < 1e-12);
        assert!((e.x - 1.0 / 120f64.to_radians().tan()).abs() < 1e-12);
        // Behind: nothing.
        assert!(clip_to_wedge(p(-3.0, -1.0), p(3.0, -1.0), from, to).is_none());
        // Wholly inside: unchanged, ordered clockwise end first.
        let (s, e) = clip_to_wedge(p(0.0, 2.0), p(0.1, 1.0), from, to).unwrap();
        assert!((s - p(0.1, 1.0)).norm() < 1e-12 && (e - p(0.0, 2.0)).norm() < 1e-12);
        // Degenerate input.
        assert!(clip_to_wedge(p(f64::NAN, 0.0), p(1.0, 1.0), from, to).is_none());
        assert!(clip_to_wedge(p(0.0, 0.0), p(0.0, 0.0), from, to).is_none());
        assert!(clip_to_wedge(p(0.0, 1.0), p(0.0, 2.0), 0.0, 4.0).is_none());
    }
}
