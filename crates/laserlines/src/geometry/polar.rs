//! The normal form of a line through two points.

use crate::math::{Point2, Vector2, wrap_angle};

/// The infinite line through `a` and `b` in normal form `x cos(alpha) + y sin(alpha) = r`,
/// in the frame the points are given in: `(r, alpha)` with `r >= 0` (m) and `alpha` in
/// `(-pi, pi]` (rad). `None` when `a == b` or a coordinate is not finite.
#[must_use]
pub fn polar_line(a: Point2, b: Point2) -> Option<(f64, f64)> {
    let e = b - a;
    let len = e.norm();
    if !(len > 0.0 && len.is_finite() && a.x.is_finite() && a.y.is_finite()) {
        return None;
    }
    let mut n = Vector2::new(e.y, -e.x) / len;
    let mut r = n.dot(&a.coords);
    if r < 0.0 {
        n = -n;
        r = -r;
    }
    Some((r, wrap_angle(n.y.atan2(n.x))))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_4, PI, SQRT_2};

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn polar_form_has_positive_r_and_wrapped_alpha() {
        let p = Point2::new;
        // The line x = -2 seen from the origin: normal points to -x.
        let (r, alpha) = polar_line(p(-2.0, -1.0), p(-2.0, 1.0)).unwrap();
        assert!(close(r, 2.0) && close(alpha, PI));
        let (r, alpha) = polar_line(p(1.0, -1.0), p(3.0, 1.0)).unwrap();
        assert!(close(r, SQRT_2) && close(alpha, -FRAC_PI_4));
        assert!(polar_line(p(1.0, 1.0), p(1.0, 1.0)).is_none());
    }
}
