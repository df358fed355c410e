//! Geometry aliases used across the crate (all in metres and radians, REP 103 frames:
//! x forward, y left, angles counter-clockwise).

/// A point in a 2D frame, metres.
pub type Point2 = nalgebra::Point2<f64>;
/// A vector in a 2D frame, metres.
pub type Vector2 = nalgebra::Vector2<f64>;
/// A 2x2 matrix (covariances).
pub type Matrix2 = nalgebra::Matrix2<f64>;
/// A rigid 2D transform, e.g. `world_from_robot`.
pub type Isometry2 = nalgebra::Isometry2<f64>;

/// Wraps an angle to the half-open interval `(-pi, pi]`.
#[must_use]
pub fn wrap_angle(a: f64) -> f64 {
    if !a.is_finite() {
        return a;
    }
    let two_pi = std::f64::consts::TAU;
    let mut w = a % two_pi;
    if w <= -std::f64::consts::PI {
        w += two_pi;
    } else if w > std::f64::consts::PI {
        w -= two_pi;
    }
    w
}

/// Smallest absolute difference between two angles, in `[0, pi]`.
#[must_use]
pub fn angle_diff(a: f64, b: f64) -> f64 {
    wrap_angle(a - b).abs()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn wrap_angle_maps_into_half_open_interval() {
        assert!((wrap_angle(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(-PI) - PI).abs() < 1e-12);
        assert!((wrap_angle(0.5) - 0.5).abs() < 1e-12);
        assert!((wrap_angle(-2.0 * PI + 0.25) - 0.25).abs() < 1e-12);
    }

    #[test]
    fn angle_diff_is_symmetric_and_wraps() {
        assert!((angle_diff(PI - 0.1, -PI + 0.1) - 0.2).abs() < 1e-12);
        assert!((angle_diff(0.3, 0.1) - 0.2).abs() < 1e-12);
    }
}
