//! Rigid motions of the plane, SE(2): poses, their composition, inverse, and the exponential
//! and logarithm maps.
//!
//! A pose `a_from_b` maps points of frame `b` into frame `a` (REP 103: x forward, y left,
//! angles counter-clockwise, metres and radians). `a_from_b * b_from_c = a_from_c`.

use std::ops::Mul;

use laserlines::math::{Isometry2, Point2, Vector2, wrap_angle};

/// A planar pose: translation in metres and heading in radians, the heading kept in
/// `(-pi, pi]`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Se2 {
    /// x, m.
    pub x: f64,
    /// y, m.
    pub y: f64,
    /// Heading, rad, in `(-pi, pi]`.
    pub theta: f64,
}

impl Se2 {
    /// The identity.
    pub const IDENTITY: Self = Self {
        x: 0.0,
        y: 0.0,
        theta: 0.0,
    };

    /// A pose from its parts (metres, metres, radians); the heading is wrapped.
    #[must_use]
    pub fn new(x: f64, y: f64, theta: f64) -> Self {
        Self {
            x,
            y,
            theta: wrap_angle(theta),
        }
    }

    /// The translation, m.
    #[must_use]
    pub fn translation(&self) -> Vector2 {
        Vector2::new(self.x, self.y)
    }

    /// `self * other`: first `other`, then `self` (`a_from_b * b_from_c = a_from_c`).
    #[must_use]
    pub fn compose(&self, other: &Self) -> Self {
        let (s, c) = self.theta.sin_cos();
        Self::new(
            self.x + c * other.x - s * other.y,
            self.y + s * other.x + c * other.y,
            self.theta + other.theta,
        )
    }

    /// The inverse: `b_from_a` for `a_from_b`.
    #[must_use]
    pub fn inverse(&self) -> Self {
        let (s, c) = self.theta.sin_cos();
        Self::new(
            -c * self.x - s * self.y,
            s * self.x - c * self.y,
            -self.theta,
        )
    }

    /// `self^-1 * other`: the pose of `other` seen from `self` (both in one parent frame).
    #[must_use]
    pub fn between(&self, other: &Self) -> Self {
        self.inverse().compose(other)
    }

    /// Maps a point of the posed frame into the parent frame.
    #[must_use]
    pub fn transform(&self, p: Point2) -> Point2 {
        let (s, c) = self.theta.sin_cos();
        Point2::new(self.x + c * p.x - s * p.y, self.y + s * p.x + c * p.y)
    }

    /// Rotates a vector of the posed frame into the parent frame.
    #[must_use]
    pub fn rotate(&self, v: Vector2) -> Vector2 {
        let (s, c) = self.theta.sin_cos();
        Vector2::new(c * v.x - s * v.y, s * v.x + c * v.y)
    }

    /// The exponential map: the pose reached by moving along the twist `(vx, vy, omega)`
    /// for unit time (metres and radians).
    #[must_use]
    pub fn exp(tangent: [f64; 3]) -> Self {
        let [vx, vy, w] = tangent;
        let (a, b) = v_coefficients(w);
        Self::new(a * vx - b * vy, b * vx + a * vy, w)
    }

    /// The logarithm map, inverse of [`Se2::exp`] for headings in `(-pi, pi]`.
    #[must_use]
    pub fn log(&self) -> [f64; 3] {
        let w = self.theta;
        let (a, b) = v_coefficients(w);
        let det = a * a + b * b;
        // V = [[a, -b], [b, a]], V^-1 = [[a, b], [-b, a]] / det; det > 0 for |w| <= pi.
        [
            (a * self.x + b * self.y) / det,
            (-b * self.x + a * self.y) / det,
            w,
        ]
    }

    /// The pose as an `nalgebra` isometry.
    #[must_use]
    pub fn to_isometry(&self) -> Isometry2 {
        Isometry2::new(Vector2::new(self.x, self.y), self.theta)
    }

    /// The pose of an `nalgebra` isometry.
    #[must_use]
    pub fn from_isometry(iso: &Isometry2) -> Self {
        Self::new(
            iso.translation.vector.x,
            iso.translation.vector.y,
            iso.rotation.angle(),
        )
    }

    /// True when all three parts are finite.
    #[must_use]
    pub fn is_finite(&self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.theta.is_finite()
    }

    /// Distance between the two translations, m.
    #[must_use]
    pub fn distance(&self, other: &Self) -> f64 {
        (self.x - other.x).hypot(self.y - other.y)
    }
}

impl Mul for Se2 {
    type Output = Self;
    fn mul(self, rhs: Self) -> Self {
        self.compose(&rhs)
    }
}

impl Mul<Point2> for Se2 {
    type Output = Point2;
    fn mul(self, rhs: Point2) -> Point2 {
        self.transform(rhs)
    }
}

/// `(sin w / w, (1 - cos w) / w)`, with their series near zero.
fn v_coefficients(w: f64) -> (f64, f64) {
    if w.abs() < 1e-6 {
        (1.0 - w * w / 6.0, w / 2.0 - w * w * w / 24.0)
    } else {
        (w.sin() / w, (1.0 - w.cos()) / w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::f64::consts::PI;

    fn close(a: &Se2, b: &Se2, tol: f64) -> bool {
        (a.x - b.x).abs() < tol
            && (a.y - b.y).abs() < tol
            && wrap_angle(a.theta - b.theta).abs() < tol
    }

    fn pose() -> impl Strategy<Value = Se2> {
        (-50.0..50.0f64, -50.0..50.0f64, -PI..PI).prop_map(|(x, y, t)| Se2::new(x, y, t))
    }

    #[test]
    fn a_quarter_turn_maps_x_to_y() {
        let p = Se2::new(1.0, 2.0, PI / 2.0);
        let q = p.transform(Point2::new(1.0, 0.0));
        assert!((q.x - 1.0).abs() < 1e-12 && (q.y - 3.0).abs() < 1e-12);
        let back = p.inverse().transform(q);
        assert!((back.x - 1.0).abs() < 1e-12 && back.y.abs() < 1e-12);
    }

    #[test]
    fn heading_wraps_on_composition() {
        let a = Se2::new(0.0, 0.0, 3.0);
        let b = a.compose(&a);
        assert!((b.theta - wrap_angle(6.0)).abs() < 1e-12);
        assert!(b.theta > -PI && b.theta <= PI);
    }

    #[test]
    fn exp_of_a_pure_rotation_and_translation() {
        let r = Se2::exp([0.0, 0.0, 0.5]);
        assert!(close(&r, &Se2::new(0.0, 0.0, 0.5), 1e-12));
        let t = Se2::exp([1.5, -2.0, 0.0]);
        assert!(close(&t, &Se2::new(1.5, -2.0, 0.0), 1e-12));
        // A half turn along an arc of length pi/2 * 2 = pi: ends 2 m to the left.
        let arc = Se2::exp([PI, 0.0, PI]);
        assert!(close(&arc, &Se2::new(0.0, 2.0, PI), 1e-9));
    }

    proptest! {
        #[test]
        fn inverse_undoes_compose(a in pose(), b in pose()) {
            let ab = a.compose(&b);
            prop_assert!(close(&a.inverse().compose(&ab), &b, 1e-9));
            prop_assert!(close(&ab.compose(&b.inverse()), &a, 1e-9));
            prop_assert!(close(&a.compose(&a.inverse()), &Se2::IDENTITY, 1e-9));
        }

        #[test]
        fn composition_is_associative(a in pose(), b in pose(), c in pose()) {
            prop_assert!(close(&((a * b) * c), &(a * (b * c)), 1e-9));
        }

        #[test]
        fn transform_agrees_with_nalgebra(a in pose(), x in -10.0..10.0f64, y in -10.0..10.0f64) {
            let p = Point2::new(x, y);
            let ours = a.transform(p);
            let theirs = a.to_isometry() * p;
            prop_assert!((ours - theirs).norm() < 1e-9);
            prop_assert!(close(&Se2::from_isometry(&a.to_isometry()), &a, 1e-12));
            let composed = (a * Se2::new(x, y, 0.3)).transform(p);
            let twice = a.transform(Se2::new(x, y, 0.3).transform(p));
            prop_assert!((composed - twice).norm() < 1e-9);
        }

        #[test]
        fn between_is_the_relative_pose(a in pose(), b in pose()) {
            prop_assert!(close(&a.compose(&a.between(&b)), &b, 1e-9));
        }

        #[test]
        fn log_inverts_exp(vx in -5.0..5.0f64, vy in -5.0..5.0f64, w in -3.1..3.1f64) {
            let l = Se2::exp([vx, vy, w]).log();
            prop_assert!((l[0] - vx).abs() < 1e-9 && (l[1] - vy).abs() < 1e-9 && (l[2] - w).abs() < 1e-12);
        }

        #[test]
        fn exp_inverts_log(a in pose()) {
            prop_assert!(close(&Se2::exp(a.log()), &a, 1e-9));
        }
    }
}
