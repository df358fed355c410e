//! Following the wall (the paper's Chart 1): which mode the robot is in, and the command
//! of each mode; and the free distance ahead.

use laserlines::geometry::clip_segment;
use laserlines::math::{Isometry2, Point2, Vector2};
use laserlines::robot::VelocityCommand;

use super::{Explorer, Mode};
use crate::sectors::{SectorObject, SectorObjects};

impl Explorer {
    /// The wall follower (the paper's Chart 1): mode transitions and the command.
    pub(super) fn follow_wall(
        &mut self,
        objects: &SectorObjects,
        robot_lines: &[(Point2, Point2)],
        front_free: f64,
        map_from_robot: &Isometry2,
    ) -> VelocityCommand {
        let p = self.params;
        let wall = objects
            .get(self.side.sector())
            .filter(|o| o.distance_m < p.follow.range && o.angle_rad.abs() < 60f64.to_radians())
            .copied();
        if let Some(w) = wall {
            // The end of the followed wall ahead (the full line's end farther forward).
            let (a, b) = robot_lines[w.line];
            let ahead = if a.x >= b.x { a } else { b };
            self.wall_end = Some(map_from_robot * ahead);
        }
        let robot_from_map = map_from_robot.inverse();
        let end_in_robot = self.wall_end.map(|e| robot_from_map * e);
        self.mode = self.next_mode(wall.as_ref(), end_in_robot, front_free);
        if self.mode == Mode::Seek {
            self.wall_end = None;
        }
        self.mode_command(wall.as_ref(), end_in_robot, front_free)
    }

    /// The mode after this scan, from the followed wall (if any), the end of the wall ahead
    /// (robot frame) and the free distance ahead.
    fn next_mode(
        &mut self,
        wall: Option<&SectorObject>,
        end_in_robot: Option<Point2>,
        front_free: f64,
    ) -> Mode {
        let p = self.params;
        let s = self.side.sign();
        // Arcing around a wall end, or following a wall that curves toward the followed
        // side (round the end of a free-standing wall), the robot turns away from what is
        // straight ahead: only a very near obstacle stops it (the safety layer watches the
        // rest).
        let turning_to_wall = wall.is_some_and(|w| {
            let e_d = (w.distance_m - p.follow.distance).clamp(-0.4, 0.4);
            s * (p.follow.k_heading * w.angle_rad + s * p.follow.k_distance * e_d) > 0.3
        });
        let turn_at = if self.mode == Mode::Corner || turning_to_wall {
            p.follow.front_turn_corner
        } else {
            p.follow.front_turn
        };
        let blocked = front_free < turn_at;
        match self.mode {
            Mode::TurnAway
                if front_free < p.follow.front_turn + 0.4
                    && self.turned < 2.0 * std::f64::consts::PI =>
            {
                Mode::TurnAway
            }
            _ if blocked => {
                self.turned = 0.0;
                Mode::TurnAway
            }
            _ if wall.is_some() => Mode::Follow,
            _ if end_in_robot.is_some_and(|e| e.coords.norm() < p.follow.distance + 0.6) => {
                Mode::Corner
            }
            _ => Mode::Seek,
        }
    }

    /// The command of the present mode.
    fn mode_command(
        &self,
        wall: Option<&SectorObject>,
        end_in_robot: Option<Point2>,
        front_free: f64,
    ) -> VelocityCommand {
        let p = self.params;
        let s = self.side.sign();
        match self.mode {
            Mode::Follow => {
                let Some(w) = wall else {
                    return VelocityCommand::STOP;
                };
                let e_d = (w.distance_m - p.follow.distance).clamp(-0.4, 0.4);
                let omega = p.follow.k_heading * w.angle_rad + s * p.follow.k_distance * e_d;
                let omega = omega.clamp(-p.follow.turn_rate, p.follow.turn_rate);
                let v = p.follow.cruise_speed
                    * ((front_free - 0.2) / 1.0).clamp(0.25, 1.0)
                    * (1.0 - omega.abs() / (2.0 * p.follow.turn_rate)).max(0.3);
                VelocityCommand::new(v, omega)
            }
            Mode::Corner => {
                let e = end_in_robot.unwrap_or_else(Point2::origin);
                let d = e.coords.norm().max(1e-6);
                let u = e.coords / d;
                // Tangent with the end on the followed side.
                let t = Vector2::new(s * u.y, -s * u.x);
                let heading = t.y.atan2(t.x);
                let e_d = (d - p.follow.distance).clamp(-0.4, 0.4);
                let omega = (p.follow.k_heading * heading + s * p.follow.k_distance * e_d)
                    .clamp(-p.follow.turn_rate, p.follow.turn_rate);
                let v = if heading.abs() > 1.2 {
                    0.0
                } else {
                    p.follow.corner_speed
                };
                VelocityCommand::new(v, omega)
            }
            Mode::TurnAway => VelocityCommand::new(0.0, -s * p.follow.turn_rate),
            Mode::Escape => self.escape,
            Mode::Seek | Mode::Travel => VelocityCommand::new(
                p.follow.cruise_speed * ((front_free - 0.2) / 1.0).clamp(0.3, 1.0),
                0.0,
            ),
        }
    }

    /// Free distance ahead of the robot's front within the swept band, from the lines.
    pub(super) fn front_free(&self, robot_lines: &[(Point2, Point2)]) -> f64 {
        let half = self.footprint.half();
        let band = half.y + self.params.follow.front_band_margin;
        let mut best = f64::INFINITY;
        for &(a, b) in robot_lines {
            // Clip the segment to |y| <= band, x >= 0.
            let Some((c, d)) = clip_to_band(a, b, band) else {
                continue;
            };
            let x = c.x.min(d.x).max(0.0);
            best = best.min(x);
        }
        (best - half.x).max(0.0)
    }
}

/// The part of the segment `a`-`b` with `|y| <= band` and `x >= 0`.
fn clip_to_band(a: Point2, b: Point2, band: f64) -> Option<(Point2, Point2)> {
    let d = b - a;
    let (t0, t1) = clip_segment(&[(-d.x, a.x), (-d.y, a.y + band), (d.y, band - a.y)])?;
    Some((a + d * t0, a + d * t1))
}
