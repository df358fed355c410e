//! What the robot side needs to know about a robot, whatever drives it (the simulator or a
//! real base): its outline, its drive limits, where its laser sits, and the velocity command
//! and arc motion of a differential drive.
//!
//! - [`Footprint`]: the rectangle checked against obstacles, with exact distances;
//! - [`DriveLimits`], [`VelocityCommand`], [`arc`]: the drive;
//! - [`LaserMount`]: the laser's pose on the robot (`robot_from_laser`);
//! - [`RobotDescription`]: all of them, NAJI V's by default.
//!
//! Frames follow REP 103 (x forward, y left); the robot frame's origin is the point midway
//! between the wheels.
//!
//! ```
//! use laserlines::robot::{RobotDescription, VelocityCommand, arc};
//! let robot = RobotDescription::default(); // NAJI V: 0.5 m x 0.4 m, the laser 0.15 m ahead
//! robot.validate().unwrap();
//! assert!((robot.footprint.circumradius() - 0.320).abs() < 1e-3);
//! assert_eq!(robot.laser.robot_from_laser().translation.vector.x, 0.15);
//! // A quarter circle of radius 1 m to the left.
//! let c = VelocityCommand::new(0.5, 0.5);
//! let t = std::f64::consts::FRAC_PI_2 / c.angular_rad_s;
//! let moved = arc(c.linear_m_s * t, c.angular_rad_s * t);
//! assert!((moved.translation.vector.x - 1.0).abs() < 1e-12);
//! assert!((moved.translation.vector.y - 1.0).abs() < 1e-12);
//! ```

mod drive;
mod footprint;

pub use drive::{DriveLimits, VelocityCommand, arc};
pub use footprint::Footprint;

use crate::math::{Isometry2, Vector2};
use crate::params::{self, ParamsError};

/// Where the laser sits on the robot: its position in the robot frame and its yaw.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct LaserMount {
    /// Ahead of the robot's origin, m. Default 0.15. The laser must lie within the
    /// footprint's circumradius plus [`MAX_LASER_OVERHANG`] of the origin.
    pub x: f64,
    /// To the left of the robot's origin, m. Default 0.
    pub y: f64,
    /// Turned counter-clockwise from the robot's heading, rad. Default 0.
    pub yaw: f64,
}

impl Default for LaserMount {
    fn default() -> Self {
        Self {
            x: 0.15,
            y: 0.0,
            yaw: 0.0,
        }
    }
}

impl LaserMount {
    /// The laser's pose in the robot frame.
    #[must_use]
    pub fn robot_from_laser(&self) -> Isometry2 {
        Isometry2::new(Vector2::new(self.x, self.y), self.yaw)
    }
}

/// How far beyond its footprint's circle a laser may be mounted, m (a mast or a bracket).
pub const MAX_LASER_OVERHANG: f64 = 0.25;

/// A robot as the robot side sees it. [`RobotDescription::default`] is NAJI V: 0.50 m x
/// 0.40 m, at most 0.6 m/s and 1.5 rad/s, wheels 0.36 m apart, the laser 0.15 m ahead of
/// the axle facing forward.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct RobotDescription {
    /// The outline checked against obstacles.
    pub footprint: Footprint,
    /// Speed and acceleration limits.
    pub limits: DriveLimits,
    /// Distance between the wheels, m. Default 0.36.
    pub wheel_base: f64,
    /// Where the laser sits.
    pub laser: LaserMount,
}

impl Default for RobotDescription {
    fn default() -> Self {
        Self::naji_v()
    }
}

impl RobotDescription {
    /// NAJI V (the default).
    #[must_use]
    pub fn naji_v() -> Self {
        Self {
            footprint: Footprint::naji_v(),
            limits: DriveLimits::default(),
            wheel_base: 0.36,
            laser: LaserMount::default(),
        }
    }

    /// Checks that every length and limit is positive and finite (the reverse speed may be
    /// 0) and that the laser's mount is finite.
    ///
    /// # Errors
    /// A [`ParamsError`] naming the first field out of range (`footprint.length`,
    /// `limits.max_speed`, `laser.yaw`, ...).
    pub fn validate(&self) -> Result<(), ParamsError> {
        params::positive("footprint.length", self.footprint.length)?;
        params::positive("footprint.width", self.footprint.width)?;
        params::positive("limits.max_speed", self.limits.max_speed)?;
        params::non_negative("limits.max_reverse", self.limits.max_reverse)?;
        params::positive("limits.max_turn_rate", self.limits.max_turn_rate)?;
        params::positive("limits.max_accel", self.limits.max_accel)?;
        params::positive("limits.max_angular_accel", self.limits.max_angular_accel)?;
        params::positive("wheel_base", self.wheel_base)?;
        params::finite("laser.x", self.laser.x)?;
        params::finite("laser.y", self.laser.y)?;
        params::finite("laser.yaw", self.laser.yaw)?;
        // The laser sits on the robot: within its footprint's circle, plus a mast's reach.
        let reach = self.footprint.circumradius() + MAX_LASER_OVERHANG;
        let off = self.laser.x.hypot(self.laser.y);
        if off > reach {
            return Err(ParamsError::AboveField {
                field: "laser.x, laser.y (the laser's distance from the robot's centre)",
                value: off,
                limit_field: "the footprint's circumradius + 0.25 m",
                limit: reach,
            });
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_descriptions_name_the_field() {
        assert!(RobotDescription::default().validate().is_ok());
        let mut r = RobotDescription::default();
        r.footprint.width = -0.4;
        assert!(matches!(
            r.validate(),
            Err(ParamsError::NotPositive {
                field: "footprint.width",
                ..
            })
        ));
        let mut r = RobotDescription::default();
        r.laser.yaw = f64::NAN;
        assert!(
            r.validate()
                .unwrap_err()
                .to_string()
                .starts_with("laser.yaw")
        );
        let mut r = RobotDescription::default();
        r.limits.max_reverse = 0.0;
        assert!(r.validate().is_ok());
        // A laser 5 m from the robot is not on it; at the footprint's corner it is.
        let mut r = RobotDescription::default();
        r.laser.x = 5.0;
        let e = r.validate().unwrap_err().to_string();
        assert!(
            e.starts_with("laser.x, laser.y") && e.contains("got 5"),
            "{e}"
        );
        r.laser.x = 0.25;
        r.laser.y = 0.2;
        assert!(r.validate().is_ok());
    }
}
