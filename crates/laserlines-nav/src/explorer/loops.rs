//! Loop detection: breadcrumbs on the robot's map show when the followed wall has been
//! followed all the way round; and the distance driven, by the odometry.

use laserlines::math::{Isometry2, Point2, wrap_angle};

use super::{Explorer, Mode, WallSide};

/// A breadcrumb: where the robot was (map frame), its heading, the distance driven by then
/// and the side it followed.
#[derive(Debug, Clone, Copy)]
pub(super) struct Crumb {
    at: Point2,
    heading: f64,
    path: f64,
    side: WallSide,
}

impl Explorer {
    /// Adds the distance the odometry moved since the last scan to the path driven.
    pub(super) fn track_odometry(&mut self, odom_from_robot: &Isometry2) {
        if let Some(last) = self.last_pose {
            self.path += (odom_from_robot.translation.vector - last.translation.vector).norm();
        }
        self.last_pose = Some(*odom_from_robot);
    }

    /// Drops a breadcrumb every 0.5 m (map frame); true when the wall being followed has
    /// been followed all the way round.
    pub(super) fn check_loop(&mut self) -> bool {
        let p = self.params;
        let at = Point2::from(self.map_from_robot.translation.vector);
        let heading = self.map_from_robot.rotation.angle();
        if self.last_crumb.is_some_and(|c| (at - c).norm() < 0.5) {
            return false;
        }
        self.last_crumb = Some(at);
        let mut looped = false;
        if self.mode == Mode::Follow || self.mode == Mode::Corner {
            looped = self.crumbs.iter().any(|c| {
                c.side == self.side
                    && self.path - c.path >= p.loops.min_path_m
                    && (c.at - at).norm() < p.loops.match_radius_m
                    && (wrap_angle(c.heading - heading)).abs() < p.loops.heading_rad
            });
            if looped {
                self.loops += 1;
            }
            self.crumbs.push(Crumb {
                at,
                heading,
                path: self.path,
                side: self.side,
            });
        }
        looped
    }
}
