//! A wall-following explorer driven by the three sector objects (the paper's Chart 1, in
//! words), with a safety layer.
//!
//! The explorer sees what a real robot sees: each scan, the lines extracted from it, and the
//! wheel odometry. It never reads the world.
//!
//! **Following.** The explorer keeps a wall on one side (the *followed side*, left by
//! default). The followed side's sector object (the left object for the left side) is the
//! wall to follow when it is nearer than `follow_range` and runs within 60 deg of the
//! heading. The turn rate steers the robot parallel to it (the object's angle) and to
//! `follow_distance` from it (its distance): `w = k_heading * angle + side * k_distance *
//! (distance - follow_distance)`.
//!
//! **Corners and wall ends.** The end of the followed wall ahead of the robot is remembered
//! in the odometry frame. When the followed side's object is lost (the wall ended: a corner
//! or an opening on that side) the robot arcs around that end at `follow_distance`, so that
//! it turns into the side corridor, or around the end of a free-standing wall.
//!
//! **Obstacles in front and dead ends.** The free distance ahead is the distance from the
//! robot's front to the nearest extracted line inside the band the robot sweeps when driving
//! straight (its width plus a margin). When it falls below `front_turn`, the robot turns on
//! the spot away from the followed side until the way ahead is free again: 90 deg at a
//! corner, 180 deg in a dead end.
//!
//! **Leaving a wall followed all the way round.** Every 0.5 m of travel the odometry pose is
//! dropped as a breadcrumb. Coming back within `loop_match` of a breadcrumb laid at least
//! `loop_min_path` earlier, heading the same way (within `loop_heading`) on the same
//! followed side, means the wall has been followed all the way round: the explorer switches
//! the followed side. From then on it takes the other branch at every junction, which leads
//! it off the wall group it circled and onto others, such as islands that a pure wall
//! follower never reaches.
//!
//! **Safety.** Before a velocity command is committed, the footprint, grown by
//! `safety_margin`, is swept along the arc the command drives over the time the robot needs
//! to stop, and checked against the points of the latest scans (kept for a short while in
//! the odometry frame, so that obstacles beside and behind the laser's field of view are
//! remembered). A command that would touch a point is slowed; if even turning on the spot
//! is unsafe the robot stops, and if it stays stuck it backs off.
//!
//! **Stopping.** The explorer keeps its own coarse map of the cells its scans have hit, in
//! the odometry frame; when no new cell has been seen for `idle_timeout_s` it reports that
//! it is done.

use laserlines::Line;
use laserlines::Scan;
use laserlines::math::{Isometry2, Point2, Vector2, wrap_angle};
use laserlines_sim::robot::{Footprint, RobotParams, VelocityCommand, arc};

use crate::sectors::{Sector, SectorObjects, SectorParams, select_objects};

/// Which side the followed wall is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WallSide {
    /// Left-hand rule: the wall on the left.
    Left,
    /// Right-hand rule: the wall on the right.
    Right,
}

impl WallSide {
    /// +1 for left, -1 for right (the sign of a turn toward the wall).
    #[must_use]
    pub fn sign(self) -> f64 {
        match self {
            Self::Left => 1.0,
            Self::Right => -1.0,
        }
    }

    /// The sector on this side.
    #[must_use]
    pub fn sector(self) -> Sector {
        match self {
            Self::Left => Sector::Left,
            Self::Right => Sector::Right,
        }
    }

    /// The other side.
    #[must_use]
    pub fn other(self) -> Self {
        match self {
            Self::Left => Self::Right,
            Self::Right => Self::Left,
        }
    }
}

/// Parameters of the explorer. Distances in metres, angles in radians, times in seconds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExplorerParams {
    /// The side of the first followed wall. Default left.
    pub side: WallSide,
    /// Distance kept from the followed wall, from the robot's origin, m. Default 0.6 (the
    /// middle of a 1.2 m arena corridor).
    pub follow_distance: f64,
    /// A wall on the followed side nearer than this is followed, m. Default 1.0.
    pub follow_range: f64,
    /// Speed along straight walls, m/s. Default 0.55.
    pub cruise_speed: f64,
    /// Speed around wall ends, m/s. Default 0.35.
    pub corner_speed: f64,
    /// Turn rate when turning on the spot, rad/s. Default 1.2.
    pub turn_rate: f64,
    /// Gain of the heading term, 1/s. Default 1.8.
    pub k_heading: f64,
    /// Gain of the distance term, rad/(s m). Default 2.0.
    pub k_distance: f64,
    /// Free distance ahead of the robot's front below which it turns away, m. Default 0.45.
    pub front_turn: f64,
    /// The same while arcing around a wall end or curving toward the followed side, m.
    /// Default 0.15.
    pub front_turn_corner: f64,
    /// Extra half-width of the band ahead checked for the free distance, m. Default 0.1.
    pub front_band_margin: f64,
    /// Margin the safety layer keeps around the footprint, m. Default 0.08.
    pub safety_margin: f64,
    /// How long scan points are remembered for the safety layer, s. Default 3.0.
    pub memory_s: f64,
    /// Breadcrumb match radius for loop detection, m. Default 0.5.
    pub loop_match: f64,
    /// Breadcrumb heading tolerance, rad. Default 0.6.
    pub loop_heading: f64,
    /// Least travel between a breadcrumb and its revisit for a loop, m. Default 8.0.
    pub loop_min_path: f64,
    /// Cell size of the explorer's own seen map, m. Default 0.3.
    pub seen_cell: f64,
    /// Done when no new cell has been seen for this long, s. Default 120.
    pub idle_timeout_s: f64,
    /// The sector selection.
    pub sectors: SectorParams,
}

impl Default for ExplorerParams {
    fn default() -> Self {
        Self {
            side: WallSide::Left,
            follow_distance: 0.6,
            follow_range: 1.0,
            cruise_speed: 0.55,
            corner_speed: 0.35,
            turn_rate: 1.2,
            k_heading: 1.8,
            k_distance: 2.0,
            front_turn: 0.45,
            front_turn_corner: 0.15,
            front_band_margin: 0.1,
            safety_margin: 0.08,
            memory_s: 3.0,
            loop_match: 0.5,
            loop_heading: 0.6,
            loop_min_path: 8.0,
            seen_cell: 0.3,
            idle_timeout_s: 120.0,
            sectors: SectorParams::default(),
        }
    }
}

/// What the explorer is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// No wall to follow: driving straight to find one.
    Seek,
    /// Following the wall on the followed side.
    Follow,
    /// Arcing around the end of the followed wall.
    Corner,
    /// Turning on the spot away from the followed side (corner ahead, dead end, obstacle).
    TurnAway,
    /// Backing off after being stuck.
    BackOff,
}

/// The explorer's decision for one scan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Decision {
    /// The velocity command, after the safety layer.
    pub command: VelocityCommand,
    /// The command the wall follower asked for, before the safety layer.
    pub wanted: VelocityCommand,
    /// The three sector objects of the scan.
    pub objects: SectorObjects,
    /// The free distance ahead of the robot's front, m.
    pub front_free_m: f64,
    /// The mode after this scan.
    pub mode: Mode,
    /// The followed side after this scan.
    pub side: WallSide,
    /// The explorer considers the exploration done.
    pub done: bool,
}

#[derive(Debug, Clone, Copy)]
struct Crumb {
    at: Point2,
    heading: f64,
    path: f64,
    side: WallSide,
}

#[derive(Debug, Clone, Copy)]
struct Remembered {
    point: Point2,
    time: f64,
}

/// The explorer (see the [module docs](self)). Feed it every scan with
/// [`Explorer::on_scan`]; hold its command until the next scan.
#[derive(Debug, Clone)]
pub struct Explorer {
    params: ExplorerParams,
    footprint: Footprint,
    robot_from_laser: Isometry2,
    max_accel: f64,
    mode: Mode,
    side: WallSide,
    /// End of the followed wall ahead, odometry frame.
    wall_end: Option<Point2>,
    /// Scan points of the last `memory_s`, odometry frame.
    memory: Vec<Remembered>,
    crumbs: Vec<Crumb>,
    last_crumb: Option<Point2>,
    path: f64,
    last_pose: Option<Isometry2>,
    turned: f64,
    stuck_since: Option<f64>,
    backoff_until: f64,
    seen: std::collections::HashSet<(i32, i32)>,
    last_new_seen: f64,
    loops: usize,
    scratch_points: Vec<Point2>,
}

impl Explorer {
    /// An explorer for a robot with `robot`'s footprint, laser mounting and limits.
    #[must_use]
    pub fn new(params: ExplorerParams, robot: &RobotParams) -> Self {
        Self {
            params,
            footprint: robot.footprint,
            robot_from_laser: robot.robot_from_laser,
            max_accel: robot.limits.max_accel,
            mode: Mode::Seek,
            side: params.side,
            wall_end: None,
            memory: Vec::new(),
            crumbs: Vec::new(),
            last_crumb: None,
            path: 0.0,
            last_pose: None,
            turned: 0.0,
            stuck_since: None,
            backoff_until: 0.0,
            seen: std::collections::HashSet::new(),
            last_new_seen: 0.0,
            loops: 0,
            scratch_points: Vec::new(),
        }
    }

    /// The parameters.
    #[must_use]
    pub fn params(&self) -> &ExplorerParams {
        &self.params
    }

    /// Walls followed all the way round so far (loops detected).
    #[must_use]
    pub fn loops(&self) -> usize {
        self.loops
    }

    /// The present mode.
    #[must_use]
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Decides the velocity command for one scan: `lines` were extracted from `scan`,
    /// `odom_from_robot` is the odometry pose at the scan, `time_s` its time.
    pub fn on_scan(
        &mut self,
        scan: &Scan,
        lines: &[Line],
        odom_from_robot: &Isometry2,
        time_s: f64,
    ) -> Decision {
        let p = self.params;
        self.track_odometry(odom_from_robot);
        self.remember(scan, odom_from_robot, time_s);
        let objects = select_objects(lines, &self.robot_from_laser, &p.sectors);
        let robot_lines: Vec<(Point2, Point2)> = lines
            .iter()
            .map(|l| {
                (
                    self.robot_from_laser * l.start,
                    self.robot_from_laser * l.end,
                )
            })
            .collect();
        let front_free = self.front_free(&robot_lines);
        self.check_loop(odom_from_robot);

        let s = self.side.sign();
        let wall = objects
            .get(self.side.sector())
            .filter(|o| o.distance_m < p.follow_range && o.angle_rad.abs() < 60f64.to_radians())
            .copied();
        if let Some(w) = wall {
            // The end of the followed wall ahead (the full line's end farther forward).
            let (a, b) = robot_lines[w.line];
            let ahead = if a.x >= b.x { a } else { b };
            self.wall_end = Some(odom_from_robot * ahead);
        }
        let robot_from_odom = odom_from_robot.inverse();
        let end_in_robot = self.wall_end.map(|e| robot_from_odom * e);

        // Mode transitions.
        // Arcing around a wall end, or following a wall that curves toward the followed
        // side (round the end of a free-standing wall), the robot turns away from what is
        // straight ahead: only a very near obstacle stops it (the safety layer watches the
        // rest).
        let turning_to_wall = wall.is_some_and(|w| {
            let e_d = (w.distance_m - p.follow_distance).clamp(-0.4, 0.4);
            s * (p.k_heading * w.angle_rad + s * p.k_distance * e_d) > 0.3
        });
        let turn_at = if self.mode == Mode::Corner || turning_to_wall {
            p.front_turn_corner
        } else {
            p.front_turn
        };
        let blocked = front_free < turn_at;
        self.mode = match self.mode {
            Mode::BackOff if time_s < self.backoff_until => Mode::BackOff,
            Mode::TurnAway
                if front_free < p.front_turn + 0.4 && self.turned < 2.0 * std::f64::consts::PI =>
            {
                Mode::TurnAway
            }
            _ if blocked => {
                self.turned = 0.0;
                Mode::TurnAway
            }
            _ if wall.is_some() => Mode::Follow,
            _ if end_in_robot.is_some_and(|e| e.coords.norm() < p.follow_distance + 0.6) => {
                Mode::Corner
            }
            _ => Mode::Seek,
        };
        if self.mode == Mode::Seek {
            self.wall_end = None;
        }

        let wanted = match self.mode {
            Mode::Follow => {
                let Some(w) = wall else {
                    return self.decide_stop(objects, front_free);
                };
                let e_d = (w.distance_m - p.follow_distance).clamp(-0.4, 0.4);
                let omega = p.k_heading * w.angle_rad + s * p.k_distance * e_d;
                let omega = omega.clamp(-p.turn_rate, p.turn_rate);
                let v = p.cruise_speed
                    * ((front_free - 0.2) / 1.0).clamp(0.25, 1.0)
                    * (1.0 - omega.abs() / (2.0 * p.turn_rate)).max(0.3);
                VelocityCommand::new(v, omega)
            }
            Mode::Corner => {
                let e = end_in_robot.unwrap_or_else(Point2::origin);
                let d = e.coords.norm().max(1e-6);
                let u = e.coords / d;
                // Tangent with the end on the followed side.
                let t = Vector2::new(s * u.y, -s * u.x);
                let heading = t.y.atan2(t.x);
                let e_d = (d - p.follow_distance).clamp(-0.4, 0.4);
                let omega = (p.k_heading * heading + s * p.k_distance * e_d)
                    .clamp(-p.turn_rate, p.turn_rate);
                let v = if heading.abs() > 1.2 {
                    0.0
                } else {
                    p.corner_speed
                };
                VelocityCommand::new(v, omega)
            }
            Mode::TurnAway => VelocityCommand::new(0.0, -s * p.turn_rate),
            Mode::Seek => VelocityCommand::new(
                p.cruise_speed * ((front_free - 0.2) / 1.0).clamp(0.3, 1.0),
                0.0,
            ),
            Mode::BackOff => VelocityCommand::new(-0.1, 0.0),
        };

        let command = self.safe_command(wanted, odom_from_robot, time_s);
        if self.mode == Mode::TurnAway {
            self.turned += (command.angular_rad_s * 0.1).abs();
        }
        let done = time_s - self.last_new_seen > p.idle_timeout_s;
        Decision {
            command,
            wanted,
            objects,
            front_free_m: front_free,
            mode: self.mode,
            side: self.side,
            done,
        }
    }

    /// A stop decision (never taken in practice: follow mode always has its wall).
    fn decide_stop(&self, objects: SectorObjects, front_free: f64) -> Decision {
        Decision {
            command: VelocityCommand::STOP,
            wanted: VelocityCommand::STOP,
            objects,
            front_free_m: front_free,
            mode: self.mode,
            side: self.side,
            done: false,
        }
    }

    fn track_odometry(&mut self, odom_from_robot: &Isometry2) {
        if let Some(last) = self.last_pose {
            self.path += (odom_from_robot.translation.vector - last.translation.vector).norm();
        }
        self.last_pose = Some(*odom_from_robot);
    }

    /// Keeps the scan's points (odometry frame) for the safety layer and marks the
    /// explorer's own seen map.
    fn remember(&mut self, scan: &Scan, odom_from_robot: &Isometry2, time_s: f64) {
        let keep = self.params.memory_s;
        self.memory.retain(|m| time_s - m.time <= keep);
        let odom_from_laser = odom_from_robot * self.robot_from_laser;
        let window = scan.range_window(None);
        let cell = self.params.seen_cell.max(0.05);
        let mut new_cell = false;
        let (s0, c0) = scan.angle_min.sin_cos();
        let (s_inc, c_inc) = scan.angle_increment.sin_cos();
        let mut dir = Vector2::new(c0, s0);
        for (i, &r) in scan.ranges.iter().enumerate() {
            if i > 0 {
                dir = Vector2::new(c_inc * dir.x - s_inc * dir.y, s_inc * dir.x + c_inc * dir.y);
            }
            if !window.contains(r) {
                continue;
            }
            let p = odom_from_laser * Point2::from(dir * r);
            // Keep near points only: only they matter to the safety layer.
            if r < 1.2 && i % 3 == 0 {
                self.memory.push(Remembered {
                    point: p,
                    time: time_s,
                });
            }
            if i % 4 == 0 {
                let key = ((p.x / cell).floor() as i32, (p.y / cell).floor() as i32);
                if self.seen.insert(key) {
                    new_cell = true;
                }
            }
        }
        if new_cell {
            self.last_new_seen = time_s;
        }
    }

    /// Free distance ahead of the robot's front within the swept band, from the lines.
    fn front_free(&self, robot_lines: &[(Point2, Point2)]) -> f64 {
        let half = self.footprint.half();
        let band = half.y + self.params.front_band_margin;
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

    fn check_loop(&mut self, odom_from_robot: &Isometry2) {
        let p = self.params;
        let at = Point2::from(odom_from_robot.translation.vector);
        let heading = odom_from_robot.rotation.angle();
        if self.last_crumb.is_some_and(|c| (at - c).norm() < 0.5) {
            return;
        }
        self.last_crumb = Some(at);
        if self.mode == Mode::Follow || self.mode == Mode::Corner {
            let looped = self.crumbs.iter().any(|c| {
                c.side == self.side
                    && self.path - c.path >= p.loop_min_path
                    && (c.at - at).norm() < p.loop_match
                    && (wrap_angle(c.heading - heading)).abs() < p.loop_heading
            });
            if looped {
                self.loops += 1;
                self.side = self.side.other();
                // Breadcrumbs of the wall just finished stay: coming back onto it with the
                // same side is a loop again.
            }
            self.crumbs.push(Crumb {
                at,
                heading,
                path: self.path,
                side: self.side,
            });
        }
    }

    /// The safety layer: checks `wanted` against the remembered points and returns the
    /// command to commit.
    fn safe_command(
        &mut self,
        wanted: VelocityCommand,
        odom_from_robot: &Isometry2,
        time_s: f64,
    ) -> VelocityCommand {
        let robot_from_odom = odom_from_robot.inverse();
        let mut pts = std::mem::take(&mut self.scratch_points);
        pts.clear();
        let reach = self.footprint.circumradius() + 0.5;
        for m in &self.memory {
            let q = robot_from_odom * m.point;
            if q.coords.norm() < reach {
                pts.push(q);
            }
        }
        let s = self.side.sign();
        let candidates = [
            wanted,
            VelocityCommand::new(wanted.linear_m_s * 0.5, wanted.angular_rad_s),
            VelocityCommand::new(wanted.linear_m_s * 0.25, wanted.angular_rad_s * 0.5),
            VelocityCommand::new(0.0, wanted.angular_rad_s),
            VelocityCommand::new(0.0, -s * self.params.turn_rate),
            VelocityCommand::new(0.0, s * self.params.turn_rate),
        ];
        let mut chosen = VelocityCommand::STOP;
        for c in candidates {
            if self.sweep_is_free(&pts, c) {
                chosen = c;
                break;
            }
        }
        self.scratch_points = pts;
        if chosen == VelocityCommand::STOP && wanted != VelocityCommand::STOP {
            let since = *self.stuck_since.get_or_insert(time_s);
            if time_s - since > 1.0 {
                self.mode = Mode::BackOff;
                self.backoff_until = time_s + 1.0;
                self.stuck_since = None;
            }
            if self.mode == Mode::BackOff {
                let back = VelocityCommand::new(-0.1, 0.0);
                if self.sweep_is_free(&self.scratch_points.clone(), back) {
                    return back;
                }
            }
        } else {
            self.stuck_since = None;
        }
        chosen
    }

    /// True when the footprint, grown by the safety margin, stays clear of `pts` (robot
    /// frame) while driving `c` for the time to react and stop.
    fn sweep_is_free(&self, pts: &[Point2], c: VelocityCommand) -> bool {
        let margin = self.params.safety_margin;
        let half = self.footprint.half() + Vector2::new(margin, margin);
        let v = c.linear_m_s.abs();
        // One scan period to react, then braking.
        let horizon = 0.15 + v / self.max_accel.max(1e-3);
        let steps = 6;
        for k in 1..=steps {
            let t = horizon * f64::from(k) / f64::from(steps);
            let pose = arc(c.linear_m_s * t, c.angular_rad_s * t.min(0.3));
            let inv = pose.inverse();
            for q in pts {
                let l = inv * q;
                if l.x.abs() <= half.x && l.y.abs() <= half.y {
                    return false;
                }
            }
        }
        true
    }
}

/// The part of the segment `a`-`b` with `|y| <= band` and `x >= 0`.
fn clip_to_band(a: Point2, b: Point2, band: f64) -> Option<(Point2, Point2)> {
    let d = b - a;
    let mut t0: f64 = 0.0;
    let mut t1: f64 = 1.0;
    for (p, q) in [(-d.x, a.x), (-d.y, a.y + band), (d.y, band - a.y)] {
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
    Some((a + d * t0, a + d * t1))
}
