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

/// `x.floor() as i64` without a call to `floor` (which the baseline x86-64 target makes a
/// library call, costly in the hot loops of rasterising and ray casting): the same value,
/// saturating at `i64::MIN` and `i64::MAX` (infinities included), 0 for NaN.
#[inline]
#[must_use]
pub fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    if (t as f64) > x {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// `x.ceil() as i64` without a library call, as [`floor_i64`]: saturating, 0 for NaN.
#[inline]
#[must_use]
pub fn ceil_i64(x: f64) -> i64 {
    let t = x as i64;
    if (t as f64) < x {
        t.saturating_add(1)
    } else {
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn floor_and_ceil_match_the_library_and_saturate() {
        let mut xs = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.0,
            -1.0,
            0.499_999_999_999_999_94,
            -0.499_999_999_999_999_94,
            2.5e-308,
            -2.5e-308,
            4_503_599_627_370_495.5,
            -4_503_599_627_370_495.5,
            9.007_199_254_740_993e15,
            1e18,
            -1e18,
            9.3e18,
            -9.3e18,
            1e300,
            -1e300,
            f64::MAX,
            f64::MIN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        // Near every integer and half in -1000..1000.
        for k in -2000..2000 {
            let v = f64::from(k) * 0.5;
            xs.extend([v, v.next_up(), v.next_down()]);
        }
        for x in xs {
            assert_eq!(floor_i64(x), x.floor() as i64, "floor {x}");
            assert_eq!(ceil_i64(x), x.ceil() as i64, "ceil {x}");
        }
    }

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
