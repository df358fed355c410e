//! The drive of a differential-drive robot: its limits, the velocity command it takes and
//! the arc it follows.

use crate::math::{Isometry2, Vector2, wrap_angle};

/// Speed and acceleration limits of the drive.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct DriveLimits {
    /// Top forward speed, m/s. Default 0.6.
    pub max_speed: f64,
    /// Top reverse speed, m/s (positive). Default 0.2.
    pub max_reverse: f64,
    /// Top turn rate, rad/s. Default 1.5.
    pub max_turn_rate: f64,
    /// Largest change of speed, m/s^2. Default 1.0.
    pub max_accel: f64,
    /// Largest change of turn rate, rad/s^2. Default 4.0.
    pub max_angular_accel: f64,
}

impl Default for DriveLimits {
    fn default() -> Self {
        Self {
            max_speed: 0.6,
            max_reverse: 0.2,
            max_turn_rate: 1.5,
            max_accel: 1.0,
            max_angular_accel: 4.0,
        }
    }
}

/// A velocity command: forward speed and turn rate in the robot frame.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct VelocityCommand {
    /// Forward speed, m/s (negative: reverse).
    pub linear_m_s: f64,
    /// Turn rate, rad/s (positive: counter-clockwise, to the left).
    pub angular_rad_s: f64,
}

impl VelocityCommand {
    /// A command.
    #[must_use]
    pub const fn new(linear_m_s: f64, angular_rad_s: f64) -> Self {
        Self {
            linear_m_s,
            angular_rad_s,
        }
    }

    /// Stop.
    pub const STOP: Self = Self::new(0.0, 0.0);
}

/// The motion along an arc of length `ds` (m) turning by `dtheta` (rad), in the frame of its
/// start.
#[inline]
#[must_use]
pub fn arc(ds: f64, dtheta: f64) -> Isometry2 {
    let (dx, dy) = if dtheta.abs() < 1e-9 {
        (ds, ds * 0.5 * dtheta)
    } else {
        let r = ds / dtheta;
        (r * dtheta.sin(), r * (1.0 - dtheta.cos()))
    };
    Isometry2::new(Vector2::new(dx, dy), wrap_angle(dtheta))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arc_is_exact() {
        let a = arc(std::f64::consts::FRAC_PI_2, std::f64::consts::FRAC_PI_2);
        assert!((a.translation.vector.x - 1.0).abs() < 1e-12);
        assert!((a.translation.vector.y - 1.0).abs() < 1e-12);
        let s = arc(1.0, 0.0);
        assert!((s.translation.vector.x - 1.0).abs() < 1e-12 && s.translation.vector.y == 0.0);
    }
}
