//! A wall-following explorer driven by the three sector objects (the paper's Chart 1, in
//! words), with a safety layer.
//!
//! The explorer sees what a real robot sees: each scan, the lines extracted from it, and the
//! wheel odometry. It never reads the world.
//!
//! **Following.** The explorer keeps a wall on one side (the *followed side*, left by
//! default). The followed side's sector object (the left object for the left side) is the
//! wall to follow when it is nearer than `follow.range` and runs within 60 deg of the
//! heading. The turn rate steers the robot parallel to it (the object's angle) and to
//! `follow.distance` from it (its distance): `w = k_heading * angle + side * k_distance *
//! (distance - follow_distance)`.
//!
//! **Corners and wall ends.** The end of the followed wall ahead of the robot is remembered
//! in the map frame (below). When the followed side's object is lost (the wall ended: a corner
//! or an opening on that side) the robot arcs around that end at `follow.distance`, so that
//! it turns into the side corridor, or around the end of a free-standing wall.
//!
//! **Obstacles in front and dead ends.** The free distance ahead is the distance from the
//! robot's front to the nearest extracted line inside the band the robot sweeps when driving
//! straight (its width plus a margin). When it falls below `follow.front_turn`, the robot turns on
//! the spot away from the followed side until the way ahead is free again: 90 deg at a
//! corner, 180 deg in a dead end.
//!
//! **The robot's own map.** Every scan is fitted onto the map built from the scans before
//! it ([`RobotMap::match_scan`], point-to-line ICP pulled toward the odometry's prediction)
//! and every `map.every`-th scan is added to it ([`RobotMap::insert_scan`]): the map frame
//! is the odometry frame at the start, corrected by the matching, so that the map stays
//! true while the wheel odometry drifts (the simulator's default odometry drifts by about
//! a metre in two minutes; the map pose stays within a few decimetres over a run). From
//! here on the explorer works in the map frame. It never reads the world: only its scans,
//! lines and odometry.
//!
//! **Leaving a wall followed all the way round.** Every 0.5 m of travel the map pose is
//! dropped as a breadcrumb. Coming back within `loops.match_radius_m` of a breadcrumb laid at least
//! `loops.min_path_m` earlier, heading the same way (within `loops.heading_rad`) on the same
//! followed side, means the wall has been followed all the way round. Then, or when wall
//! following has shown nothing new for `travel.stale_s` (it is going over ground already seen),
//! the explorer leaves the wall: it plans on its own map to the nearest *frontier* (a cell
//! where the robot fits at the edge of what it has seen, see [`crate::planner`]) not given
//! up before, drives there along the path (pure pursuit, re-planned every `travel.replan_s`, so
//! that the plan always starts from where the robot is), and when it gets there, or the
//! frontier has been seen meanwhile, resumes wall following on the wall it finds there.
//! Wall following that finds no wall for `travel.seek_s` leaves the same way. This is how it
//! reaches islands, wall groups that a pure wall follower never reaches. A frontier whose
//! path the robot does not shorten for `travel.give_up_s`, or that it reaches without seeing it, is
//! given up; when none is left, the given-up ones are tried again, at most `travel.retries` times.
//! A frontier given up while the robot stood still (within 0.5 m of where it last made
//! progress) closes the spot its path led to next, `travel.blocked_radius_m` around it for
//! `travel.blocked_s`: the map showed a way there that the safety layer did not let the robot
//! take, so the planner looks for another. When no frontier can be reached, the planner
//! tries again with `travel.tight_clearance_m` (gaps the robot passes driving straight but cannot
//! turn in), then with the blocked spots opened again.
//! When no frontier is left the exploration is complete.
//!
//! **Safety.** Before a velocity command is committed, the footprint is swept along the arc
//! the command drives over the time the robot needs to stop, and its least distance to the
//! near scan points is checked: this scan's, and those remembered in the map frame (one per
//! 3 cm square within `safety.memory_range_m`), so that obstacles beside and behind the laser's
//! field of view, and the ends of thin walls seen end-on, are not forgotten. Points not seen
//! in this scan count 6 cm nearer when the robot turns or backs (an obstacle's far side
//! may reach nearer than the side that was seen). A command is safe when the footprint
//! stays `safety.margin` clear; where the robot already stands nearer, when it comes no
//! nearer (and keeps 2 cm), so that it can leave a tight spot. Otherwise slower versions,
//! turning on the spot, creeping turns and turning the other way are tried, in that order;
//! a robot whose wanted motion stays blocked for about a second *escapes*: of short straight
//! and curved motions forward and back, it drives the safe one that leaves the most room
//! around the footprint for 1.2 s. This layer has the last word over the wall follower and
//! the path follower alike.
//!
//! **Stopping.** The explorer reports that it is done when no frontier is left (the whole
//! reachable area has been seen), or when its map has gained nothing for `idle_timeout_s`.
//!
//! **On a real robot** the loop is the simulator's without the simulator: for each scan of
//! the laser, the odometry pose at its time, the lines, one decision, one velocity command
//! to the drive. [`RobotDescription`] describes the robot (footprint, limits, the laser's mount).
//!
//! ```
//! use laserlines::math::Isometry2;
//! use laserlines::{HoughSplit, HoughSplitParams, LineExtractor, Scan};
//! use laserlines_nav::{Explorer, ExplorerParams};
//! use laserlines::robot::RobotDescription;
//!
//! let robot = RobotDescription::default(); // NAJI V: 0.5 m x 0.4 m, the laser 0.15 m ahead
//! let mut extractor = HoughSplit::new(HoughSplitParams::default()).unwrap();
//! let mut explorer = Explorer::new(ExplorerParams::default(), &robot);
//! let mut lines = Vec::new();
//! // Stand-ins for the laser driver and the wheel odometry: a wall 1 m to the left.
//! let n = 682;
//! let inc = 360.0_f64.to_radians() / 1024.0;
//! let angle_min = -inc * (n as f64 - 1.0) / 2.0;
//! let ranges = (0..n)
//!     .map(|i| {
//!         let (s, c) = (angle_min + inc * i as f64).sin_cos();
//!         // The laser is 0.15 m ahead of the axle: the wall y = 1 in its frame too.
//!         if s > 0.05 && (c / s).abs() < 3.0 { 1.0 / s } else { f64::NAN }
//!     })
//!     .collect();
//! let scan = Scan::new(angle_min, inc, 0.02, 5.6, ranges).unwrap();
//! for k in 0..20 {
//!     let t = 0.1 * f64::from(k);
//!     let odom_from_robot = Isometry2::identity(); // from the wheel encoders
//!     extractor.extract_into(&scan, &mut lines);
//!     let decision = explorer.on_scan(&scan, &lines, &odom_from_robot, t);
//!     // Send decision.command (linear_m_s, angular_rad_s) to the drive; never faster
//!     // than the robot's limits.
//!     assert!(decision.command.linear_m_s.abs() <= robot.limits.max_speed + 1e-9);
//!     assert!(decision.command.angular_rad_s.abs() <= robot.limits.max_turn_rate + 1e-9);
//! }
//! // The wall on the left is the left sector's object, about 1 m away.
//! let objects = laserlines_nav::select_objects(
//!     &lines,
//!     &robot.laser.robot_from_laser(),
//!     &Default::default(),
//! );
//! let left = objects.get(laserlines_nav::Sector::Left).unwrap();
//! assert!((left.distance_m - 1.0).abs() < 0.02);
//! ```

use laserlines::Line;
use laserlines::Scan;
use laserlines::geometry::clip_segment;
use laserlines::math::{Isometry2, Point2, Vector2, wrap_angle};
use laserlines::robot::{Footprint, RobotDescription, VelocityCommand, arc};

mod params;

pub use params::{
    ExplorerParams, FollowParams, LoopParams, MapParams, SafetyParams, TravelParams, WallSide,
};

use crate::map::{MatchPoint, RobotMap};
use crate::planner::{Plan, Planner, PlannerParams};
use crate::raster::BeamTable;
use crate::sectors::{SectorObjects, select_objects};

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
    /// Moving out of a tight spot after being stuck: the short motion that leaves the most
    /// room around the footprint.
    Escape,
    /// Driving along a planned path to a frontier.
    Travel,
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
    /// Done because no frontier is left (rather than because nothing new was seen for the
    /// idle timeout).
    pub explored: bool,
    /// The robot's pose in its map frame (the odometry corrected by scan matching).
    pub map_from_robot: Isometry2,
    /// The frontier the robot is driving to, map frame.
    pub goal: Option<Point2>,
}

#[derive(Debug, Clone, Copy)]
struct Crumb {
    at: Point2,
    heading: f64,
    path: f64,
    side: WallSide,
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
    /// End of the followed wall ahead, map frame.
    wall_end: Option<Point2>,
    /// Near scan points, map frame, one per [`MEMORY_CELL`] square (the latest), with the
    /// number of the scan that saw them.
    memory: std::collections::HashMap<(i32, i32), (Point2, u64), CellHash>,
    /// Scans seen.
    scans: u64,
    crumbs: Vec<Crumb>,
    last_crumb: Option<Point2>,
    path: f64,
    last_pose: Option<Isometry2>,
    turned: f64,
    /// Scans the safety layer found the robot stuck, recently (see `safe_command`).
    stuck_score: f64,
    escape_until: f64,
    /// The escape motion while escaping.
    escape: VelocityCommand,
    loops: usize,
    scratch_points: Vec<Point2>,
    /// Remembered points out of the laser's view, robot frame (for the safety layer).
    scratch_blind: Vec<Point2>,
    /// The laser's blind wedge, in the robot's axes: the directions of the first and the
    /// last beam, and whether the wedge is narrower than a half turn (from the last scan).
    blind: (Vector2, Vector2, bool),
    map: RobotMap,
    planner: Planner,
    map_from_odom: Isometry2,
    map_from_robot: Isometry2,
    /// Scans the map could not place (the odometry's prediction was kept).
    unmatched: u64,
    /// Time the map last gained `map.new_cells` from one scan (wall following goes stale).
    last_new: f64,
    /// Time the map last gained any cell (the idle timeout).
    last_gain: f64,
    /// Time the robot began seeking a wall (or now when it is not seeking).
    seek_since: f64,
    travel: Option<Travel>,
    /// Frontiers given up, map frame.
    avoid: Vec<Point2>,
    /// Spots the robot could not get through (map frame) and when that was found.
    blocked: Vec<(Point2, f64)>,
    /// Plans that found no frontier in a row.
    failed_plans: usize,
    /// Times the given-up frontiers were tried again.
    retries: usize,
    /// Frontiers reached or seen on the way.
    frontiers: usize,
    explored: bool,
    match_points: Vec<MatchPoint>,
    /// The scan's beam directions, laser frame.
    beams: BeamTable,
}

/// The way to a frontier.
#[derive(Debug, Clone)]
struct Travel {
    plan: Plan,
    /// Index of the path point nearest the robot at the last scan.
    along: usize,
    planned_at: f64,
    /// The least length of path left so far, m, when it was reached and where the robot
    /// was then (map frame).
    best: f64,
    best_at: f64,
    best_from: Point2,
    /// Planned with [`ExplorerParams::tight_clearance_m`].
    tight: bool,
}

impl Explorer {
    /// An explorer for a robot with `robot`'s footprint, laser mounting and limits.
    #[must_use]
    pub fn new(params: ExplorerParams, robot: &RobotDescription) -> Self {
        Self {
            params,
            footprint: robot.footprint,
            robot_from_laser: robot.laser.robot_from_laser(),
            max_accel: robot.limits.max_accel,
            mode: Mode::Seek,
            side: params.side,
            wall_end: None,
            memory: std::collections::HashMap::default(),
            scans: 0,
            crumbs: Vec::new(),
            last_crumb: None,
            path: 0.0,
            last_pose: None,
            turned: 0.0,
            stuck_score: 0.0,
            escape_until: 0.0,
            escape: VelocityCommand::STOP,
            loops: 0,
            scratch_points: Vec::new(),
            scratch_blind: Vec::new(),
            blind: (Vector2::zeros(), Vector2::zeros(), false),
            map: RobotMap::new(),
            planner: Planner::new(),
            map_from_odom: Isometry2::identity(),
            map_from_robot: Isometry2::identity(),
            unmatched: 0,
            last_new: 0.0,
            last_gain: 0.0,
            seek_since: 0.0,
            travel: None,
            avoid: Vec::new(),
            blocked: Vec::new(),
            failed_plans: 0,
            retries: 0,
            frontiers: 0,
            explored: false,
            match_points: Vec::new(),
            beams: BeamTable::default(),
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

    /// The robot's own map.
    #[must_use]
    pub fn map(&self) -> &RobotMap {
        &self.map
    }

    /// The robot's pose in its map frame.
    #[must_use]
    pub fn map_from_robot(&self) -> Isometry2 {
        self.map_from_robot
    }

    /// Scans the map could not place, whose pose came from the odometry alone.
    #[must_use]
    pub fn unmatched_scans(&self) -> u64 {
        self.unmatched
    }

    /// The frontiers given up so far, map frame.
    #[must_use]
    pub fn given_up(&self) -> &[Point2] {
        &self.avoid
    }

    /// Frontiers reached (or seen on the way) so far.
    #[must_use]
    pub fn frontiers(&self) -> usize {
        self.frontiers
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
        let last_beam =
            scan.angle_min + scan.angle_increment * scan.ranges.len().saturating_sub(1) as f64;
        let (lo, hi) = (scan.angle_min.min(last_beam), scan.angle_min.max(last_beam));
        let yaw = self.robot_from_laser.rotation.angle();
        self.blind = (
            Vector2::new((lo + yaw).cos(), (lo + yaw).sin()),
            Vector2::new((hi + yaw).cos(), (hi + yaw).sin()),
            hi - lo >= std::f64::consts::PI,
        );
        self.localise_and_map(scan, odom_from_robot, time_s);
        // From here on the robot works in its map frame: the scan-matched pose is true to
        // the millimetre where the odometry slips by centimetres (turning on the spot).
        let map_from_robot = self.map_from_robot;
        self.remember(scan, &map_from_robot);
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
        let looped = self.check_loop();

        // Seeking a wall in the open for long: no wall is near, go to a frontier.
        if self.mode != Mode::Seek {
            self.seek_since = time_s;
        }
        // Escaping has the first say, then the way to a frontier, then the wall.
        let mut wanted = None;
        if self.mode == Mode::Escape && time_s < self.escape_until {
            wanted = Some(self.escape);
        } else if self.travel.is_some() {
            wanted = self.travel_step(time_s, front_free);
            if wanted.is_none() {
                // Arrived (or the frontier was seen on the way): back to the wall.
                self.mode = Mode::Seek;
                self.wall_end = None;
                self.last_new = time_s;
            }
        } else {
            let stale = time_s - self.last_new > p.travel.stale_s;
            let lost = time_s - self.seek_since > p.travel.seek_s;
            if (looped || stale || lost) && !self.explored {
                wanted = self.start_travel(time_s, front_free);
            }
        }
        let wanted = match wanted {
            Some(w) => w,
            None => self.follow_wall(&objects, &robot_lines, front_free, &map_from_robot),
        };

        let command = self.safe_command(wanted, &map_from_robot, time_s);
        if self.mode == Mode::TurnAway {
            self.turned += (command.angular_rad_s * 0.1).abs();
        }
        let idle = time_s - self.last_gain > p.idle_timeout_s;
        Decision {
            command,
            wanted,
            objects,
            front_free_m: front_free,
            mode: self.mode,
            side: self.side,
            done: self.explored || idle,
            explored: self.explored,
            map_from_robot: self.map_from_robot,
            goal: self.travel.as_ref().map(|t| t.plan.goal),
        }
    }

    /// The wall follower (the paper's Chart 1): mode transitions and the command.
    fn follow_wall(
        &mut self,
        objects: &SectorObjects,
        robot_lines: &[(Point2, Point2)],
        front_free: f64,
        map_from_robot: &Isometry2,
    ) -> VelocityCommand {
        let p = self.params;
        let s = self.side.sign();
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
        self.mode = match self.mode {
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
        };
        if self.mode == Mode::Seek {
            self.wall_end = None;
        }
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

    /// Places the scan on the map (scan matching) and adds it.
    fn localise_and_map(&mut self, scan: &Scan, odom_from_robot: &Isometry2, time_s: f64) {
        let predicted = self.map_from_odom * odom_from_robot;
        // Scan points in the robot frame, at least 5 cm apart along the scan.
        let mut pts = std::mem::take(&mut self.match_points);
        pts.clear();
        let mut outline = std::mem::take(&mut self.scratch_points);
        outline.clear();
        let window = scan.range_window(None);
        let dirs = self
            .beams
            .get(scan.angle_min, scan.angle_increment, scan.ranges.len());
        for (&r, dir) in scan.ranges.iter().zip(dirs).step_by(MATCH_STRIDE) {
            if !window.contains(r) || r > 5.0 {
                continue;
            }
            outline.push(self.robot_from_laser * Point2::from(dir * r));
        }
        // The outline's normal at each point from its neighbours, where they are near
        // (within 15 cm): a point pairs only with map lines of about its direction.
        for (k, &q) in outline.iter().enumerate() {
            let prev = k.checked_sub(1).map(|i| outline[i]);
            let next = outline.get(k + 1).copied();
            let near = |o: Option<Point2>| o.filter(|o| (o - q).norm_squared() < 0.15 * 0.15);
            let tangent = match (near(prev), near(next)) {
                (Some(a), Some(b)) => Some(b - a),
                (Some(a), None) => Some(q - a),
                (None, Some(b)) => Some(b - q),
                (None, None) => None,
            };
            let normal = tangent
                .filter(|t| t.norm_squared() > 1e-8)
                .map(|t| Vector2::new(-t.y, t.x).normalize());
            // The URG-04LX's noise: 5 mm to 1 m, 0.5 % of the range beyond.
            let range = (q - self.robot_from_laser.translation.vector).coords.norm();
            let weight = 1.0 / range.max(1.0).powi(2);
            pts.push(MatchPoint {
                point: q,
                normal,
                weight,
            });
        }
        self.scratch_points = outline;
        let matched = if self.map.scans() > 0 {
            self.map.match_scan(&pts, &predicted, &self.params.matching)
        } else {
            None
        };
        self.match_points = pts;
        if matched.is_none() && self.map.scans() > 0 {
            self.unmatched += 1;
        }
        self.map_from_robot = matched.unwrap_or(predicted);
        self.map_from_odom = self.map_from_robot * odom_from_robot.inverse();
        // Every `map.every`-th scan goes into the map (all are matched against it).
        let every = self.params.map.every.max(1) as u64;
        if !self.scans.is_multiple_of(every) {
            return;
        }
        let newly = self
            .map
            .insert_scan(&(self.map_from_robot * self.robot_from_laser), scan);
        if newly >= self.params.map.new_cells {
            self.last_new = time_s;
        }
        if newly > 0 {
            self.last_gain = time_s;
        }
    }

    /// Plans to the nearest frontier and starts driving there; `None` when there is none
    /// (then wall following goes on, and after a few such plans the exploration is
    /// complete).
    fn start_travel(&mut self, time_s: f64, front_free: f64) -> Option<VelocityCommand> {
        let from = Point2::from(self.map_from_robot.translation.vector);
        self.update_blocked(time_s);
        let mut plan = self.plan_from(from, false);
        // No frontier left but some given up: try those again (from wherever the robot is
        // now), a limited number of times.
        if plan.is_none() && !self.avoid.is_empty() && self.retries < self.params.travel.retries {
            self.retries += 1;
            self.avoid.clear();
            plan = self.plan_from(from, false);
        }
        // None with the usual clearance: through gaps where the robot cannot turn.
        let mut tight = false;
        if plan.is_none() {
            plan = self.plan_from(from, true);
            tight = plan.is_some();
        }
        // Still none, with spots closed: open them again (a spot may be the only way on)
        // rather than call the exploration complete.
        if plan.is_none() && !self.blocked.is_empty() {
            self.blocked.clear();
            self.planner.set_blocked(&[], 0.0);
            for t in [false, true] {
                plan = self.plan_from(from, t);
                tight = t;
                if plan.is_some() {
                    break;
                }
            }
        }
        let Some(plan) = plan else {
            self.failed_plans += 1;
            // Try again after another stale spell; three empty plans in a row: done.
            self.last_new = time_s;
            if self.failed_plans >= 3 {
                self.explored = true;
            }
            return None;
        };
        self.failed_plans = 0;
        let best = plan.length_m;
        self.travel = Some(Travel {
            plan,
            along: 0,
            planned_at: time_s,
            best,
            best_at: time_s,
            best_from: from,
            tight,
        });
        self.mode = Mode::Travel;
        let step = self.travel_step(time_s, front_free);
        if step.is_none() {
            // Done at once (the frontier seen already): wall following for another spell.
            self.mode = Mode::Seek;
            self.last_new = time_s;
        }
        step
    }

    /// The path from `from` to the nearest frontier not given up, with the tight clearance
    /// when `tight`.
    fn plan_from(&mut self, from: Point2, tight: bool) -> Option<Plan> {
        let params = self.planner_params(tight);
        self.planner.nearest_frontier(
            &self.map,
            from,
            &self.avoid,
            self.params.travel.avoid_radius_m,
            None,
            &params,
        )
    }

    /// The planner's settings, with the tight clearance when `tight`.
    fn planner_params(&self, tight: bool) -> PlannerParams {
        let mut p = self.params.planner;
        if tight {
            p.clearance_m = p.clearance_m.min(self.params.travel.tight_clearance_m);
        }
        p
    }

    /// Drops the blocked spots older than `travel.blocked_s` and hands the rest to the planner.
    fn update_blocked(&mut self, time_s: f64) {
        let keep_for = self.params.travel.blocked_s;
        self.blocked.retain(|&(_, at)| time_s - at <= keep_for);
        let spots: Vec<Point2> = self.blocked.iter().map(|&(p, _)| p).collect();
        self.planner
            .set_blocked(&spots, self.params.travel.blocked_radius_m);
    }

    /// One step on the way to the frontier: re-plans when due, gives up a frontier without
    /// progress, and steers along the path. `None` when the way has ended (arrived, the
    /// frontier seen on the way, or no frontier left).
    fn travel_step(&mut self, time_s: f64, front_free: f64) -> Option<VelocityCommand> {
        let p = self.params;
        let from = Point2::from(self.map_from_robot.translation.vector);
        let mut travel = self.travel.take()?;
        let goal = travel.plan.goal;
        let dist = (from - goal).norm();
        // Arrived, or the frontier is no longer one (seen on the way, or blocked).
        let resolved = self.map.unknown_around(goal, 2) < p.planner.min_unknown
            || self.map.state(goal) != crate::map::CellState::Free;
        if resolved {
            self.frontiers += 1;
            return None;
        }
        if dist < 0.3 {
            // There, and still unknown around it: the robot cannot see it from where it
            // can stand (behind a post, in a wall's shadow). Not a frontier to come back to.
            self.avoid.push(goal);
            return None;
        }
        // Progress is measured along the path: what is left of it.
        let left = remaining(&travel.plan.path, travel.along, from);
        if left < travel.best - 0.2 {
            travel.best = left;
            travel.best_at = time_s;
            travel.best_from = from;
        }
        // Seeing new ground on the way is progress too.
        if self.last_new >= time_s {
            travel.best_at = time_s;
            travel.best_from = from;
        }
        let give_up = time_s - travel.best_at > p.travel.give_up_s;
        if give_up {
            self.avoid.push(goal);
            // Stuck where the map shows a way: close the spot the path led to next.
            if (from - travel.best_from).norm() < 0.5 {
                let path = &travel.plan.path;
                let ahead = path
                    .iter()
                    .skip(travel.along)
                    .find(|q| (*q - from).norm() >= 0.4)
                    .copied();
                if let Some(spot) = ahead {
                    self.blocked.push((spot, time_s));
                }
            }
            travel.best_at = time_s;
            travel.best_from = from;
        }
        if give_up || time_s - travel.planned_at >= p.travel.replan_s {
            self.update_blocked(time_s);
            let keep = (!give_up).then_some((goal, p.travel.hysteresis_m));
            let plan = self.planner.nearest_frontier(
                &self.map,
                from,
                &self.avoid,
                p.travel.avoid_radius_m,
                keep,
                &self.planner_params(travel.tight),
            )?;
            if (plan.goal - goal).norm() > 0.3 {
                // Another frontier: its path is measured from here on, but the clock runs on.
                travel.best = plan.length_m;
            }
            travel.plan = plan;
            travel.along = 0;
            travel.planned_at = time_s;
        }
        // Pure pursuit: the path point nearest the robot (searched ahead of the last one),
        // then the first one at least the lookahead away.
        let path = &travel.plan.path;
        let mut along = travel.along.min(path.len().saturating_sub(1));
        let mut best = f64::INFINITY;
        for (k, q) in path.iter().enumerate().skip(travel.along).take(40) {
            let d = (q - from).norm_squared();
            if d < best {
                best = d;
                along = k;
            }
        }
        travel.along = along;
        let target = path
            .iter()
            .skip(along)
            .find(|q| (*q - from).norm() >= p.travel.lookahead_m)
            .or(path.last())
            .copied()
            .unwrap_or(goal);
        self.travel = Some(travel);
        self.mode = Mode::Travel;
        let local = self.map_from_robot.inverse() * target;
        let alpha = local.y.atan2(local.x);
        Some(if alpha.abs() > 0.5 {
            VelocityCommand::new(0.0, alpha.signum() * p.follow.turn_rate)
        } else {
            let omega = (2.5 * alpha).clamp(-p.follow.turn_rate, p.follow.turn_rate);
            let v = p.travel.speed
                * (1.0 - alpha.abs() / 0.7).max(0.2)
                * ((front_free - 0.1) / 0.8).clamp(0.25, 1.0);
            VelocityCommand::new(v, omega)
        })
    }

    fn track_odometry(&mut self, odom_from_robot: &Isometry2) {
        if let Some(last) = self.last_pose {
            self.path += (odom_from_robot.translation.vector - last.translation.vector).norm();
        }
        self.last_pose = Some(*odom_from_robot);
    }

    /// Keeps the scan's near points (map frame) for the safety layer: one per
    /// [`MEMORY_CELL`] square, the latest, while within `safety.memory_range_m` of the robot.
    /// Points stay when the laser no longer sees them, behind the robot or in view (the
    /// end of a thin wall seen end-on is between beams).
    fn remember(&mut self, scan: &Scan, map_from_robot: &Isometry2) {
        self.scans += 1;
        let map_from_laser = map_from_robot * self.robot_from_laser;
        let robot_at = Point2::from(map_from_robot.translation.vector);
        let keep2 = self.params.safety.memory_range_m * self.params.safety.memory_range_m;
        self.memory
            .retain(|_, (m, _)| (*m - robot_at).norm_squared() <= keep2);
        let window = scan.range_window(None);
        let dirs = self
            .beams
            .get(scan.angle_min, scan.angle_increment, scan.ranges.len());
        // Near points only (only they matter to the safety layer), every third beam (2 cm
        // apart at 1 m).
        for (&r, dir) in scan.ranges.iter().zip(dirs).step_by(3) {
            if r >= 1.2 || !window.contains(r) {
                continue;
            }
            let p = map_from_laser * Point2::from(dir * r);
            let key = (floor_i32(p.x / MEMORY_CELL), floor_i32(p.y / MEMORY_CELL));
            self.memory.insert(key, (p, self.scans));
        }
    }

    /// True when the direction `v` (from the laser, in the robot's axes) lies outside the
    /// laser's field of view.
    fn in_blind_wedge(&self, v: Vector2) -> bool {
        let (d_first, d_last, narrow) = self.blind;
        let cross = |a: Vector2, b: Vector2| a.x * b.y - a.y * b.x;
        // The blind wedge runs counter-clockwise from the last beam round to the first.
        let after_last = cross(d_last, v) >= 0.0;
        let before_first = cross(v, d_first) >= 0.0;
        if narrow {
            after_last && before_first
        } else {
            after_last || before_first
        }
    }

    /// Free distance ahead of the robot's front within the swept band, from the lines.
    fn front_free(&self, robot_lines: &[(Point2, Point2)]) -> f64 {
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

    /// Drops a breadcrumb every 0.5 m (map frame); true when the wall being followed has
    /// been followed all the way round.
    fn check_loop(&mut self) -> bool {
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

    /// The safety layer: checks `wanted` against the remembered points and returns the
    /// command to commit.
    fn safe_command(
        &mut self,
        wanted: VelocityCommand,
        map_from_robot: &Isometry2,
        time_s: f64,
    ) -> VelocityCommand {
        let robot_from_map = map_from_robot.inverse();
        let mut pts = std::mem::take(&mut self.scratch_points);
        let mut blind = std::mem::take(&mut self.scratch_blind);
        pts.clear();
        blind.clear();
        let reach = self.footprint.circumradius() + 0.5;
        let laser = self.robot_from_laser.translation.vector;
        for (m, seen) in self.memory.values() {
            let q = robot_from_map * m;
            if q.coords.norm_squared() < reach * reach {
                // This scan's points in view are sure; the others were seen from elsewhere.
                if *seen < self.scans || self.in_blind_wedge(q.coords - laser) {
                    blind.push(q);
                } else {
                    pts.push(q);
                }
            }
        }
        self.scratch_blind = blind;
        let s = self.side.sign();
        // Slower, then turning on the spot, then turning while creeping forward or back
        // (a corner too tight to turn in), then turning either way. When none of these
        // will do for a while, the robot escapes (below).
        let candidates = [
            wanted,
            VelocityCommand::new(wanted.linear_m_s * 0.5, wanted.angular_rad_s),
            VelocityCommand::new(wanted.linear_m_s * 0.25, wanted.angular_rad_s * 0.5),
            VelocityCommand::new(0.0, wanted.angular_rad_s),
            VelocityCommand::new(0.1, wanted.angular_rad_s),
            VelocityCommand::new(-0.1, wanted.angular_rad_s),
            VelocityCommand::new(0.0, -s * self.params.follow.turn_rate),
            VelocityCommand::new(0.0, s * self.params.follow.turn_rate),
        ];
        // A command is safe when the footprint stays the safety margin clear of everything
        // along its sweep; or, where the robot already stands closer than that, when the
        // sweep never comes closer than the robot is now (and keeps 2 cm), so that it can
        // turn or back out of a tight spot.
        // Where the robot stands now, as a command that keeps the extra margin for points
        // out of view sees it, and as one that does not.
        let now_plain = self.sweep_clearance(&pts, VelocityCommand::STOP, 0.0);
        let now_turning = self.sweep_clearance(&pts, VelocityCommand::new(0.0, 1.0), 0.0);
        let margin = self.params.safety.margin;
        let safe = |c: VelocityCommand, clearance: f64| {
            let now = if toward_blind(c) {
                now_turning
            } else {
                now_plain
            };
            clearance >= margin
                || (clearance >= now.min(margin) - 1e-3 && clearance >= now.min(0.02))
        };
        let mut chosen = VelocityCommand::STOP;
        let mut blocked = wanted != VelocityCommand::STOP;
        for (k, c) in candidates.into_iter().enumerate() {
            if safe(c, self.sweep_clearance(&pts, c, 1.0)) {
                chosen = c;
                // Only a slower version of the wanted motion: not blocked.
                blocked = k > 2 && c != wanted;
                break;
            }
        }
        // Stuck: the wanted motion blocked (nothing safe, or only a way round it) for about
        // a second: escape.
        let stuck = blocked && self.mode != Mode::Escape;
        // Stuck scans add up, free ones count half back: a robot that keeps switching
        // between a blocked turn and a way out is stuck too.
        self.stuck_score = if stuck {
            self.stuck_score + 1.0
        } else {
            (self.stuck_score - 0.5).max(0.0)
        };
        if stuck && self.stuck_score > 10.0 {
            // Of short straight and curved motions either way, the safe one that ends with
            // the most room around the footprint, held for ESCAPE_S.
            let mut best: Option<(f64, VelocityCommand)> = None;
            for v in [0.15, -0.15] {
                for w in [0.0, 0.8, -0.8] {
                    let c = VelocityCommand::new(v, w);
                    if !safe(c, self.sweep_clearance(&pts, c, 1.0)) {
                        continue;
                    }
                    let end = self.clearance_after(&pts, c, ESCAPE_S);
                    if best.is_none_or(|(b, _)| end > b + 1e-9) {
                        best = Some((end, c));
                    }
                }
            }
            if let Some((_, c)) = best {
                self.mode = Mode::Escape;
                self.escape = c;
                self.escape_until = time_s + ESCAPE_S;
                chosen = c;
            }
            self.stuck_score = 0.0;
        }
        self.scratch_points = pts;
        chosen
    }

    /// The least distance between the footprint and the points `pts` (robot frame) after
    /// driving `c` for `t` seconds (the points out of view counting `BLIND_MARGIN` nearer).
    fn clearance_after(&self, pts: &[Point2], c: VelocityCommand, t: f64) -> f64 {
        let half = self.footprint.half();
        let inv = arc(c.linear_m_s * t, c.angular_rad_s * t).inverse();
        let gap = |q: &Point2| {
            let l = inv * q;
            let dx = (l.x.abs() - half.x).max(0.0);
            let dy = (l.y.abs() - half.y).max(0.0);
            (dx * dx + dy * dy).sqrt()
        };
        let seen = pts.iter().map(gap).fold(1.0, f64::min);
        let blind = self
            .scratch_blind
            .iter()
            .map(|q| gap(q) - BLIND_MARGIN)
            .fold(1.0, f64::min);
        seen.min(blind)
    }

    /// The least distance between the footprint and the points `pts` (robot frame) while
    /// driving `c` for the time to react and stop (`horizon` 0: where the robot stands
    /// now); at most 1 m.
    fn sweep_clearance(&self, pts: &[Point2], c: VelocityCommand, horizon: f64) -> f64 {
        let half = self.footprint.half();
        // Points remembered out of the laser's view were seen from elsewhere: an obstacle
        // may reach nearer on its unseen side (the far side of a barrel). Turning or
        // backing toward them keeps BLIND_MARGIN more.
        let extra = if toward_blind(c) { BLIND_MARGIN } else { 0.0 };
        let v = c.linear_m_s.abs();
        // One scan period to react, then braking.
        let span = horizon * (0.15 + v / self.max_accel.max(1e-3));
        let steps = if horizon > 0.0 { 6 } else { 1 };
        let mut least2: f64 = 1.0;
        let mut least_blind2: f64 = (1.0 + extra) * (1.0 + extra);
        for k in 1..=steps {
            let t = span * f64::from(k) / f64::from(steps);
            let pose = arc(c.linear_m_s * t, c.angular_rad_s * t.min(0.3));
            let inv = pose.inverse();
            for q in pts {
                let l = inv * q;
                let dx = (l.x.abs() - half.x).max(0.0);
                let dy = (l.y.abs() - half.y).max(0.0);
                least2 = least2.min(dx * dx + dy * dy);
            }
            for q in &self.scratch_blind {
                let l = inv * q;
                let dx = (l.x.abs() - half.x).max(0.0);
                let dy = (l.y.abs() - half.y).max(0.0);
                least_blind2 = least_blind2.min(dx * dx + dy * dy);
            }
        }
        least2.sqrt().min((least_blind2.sqrt() - extra).max(0.0))
    }
}

/// Side of the squares in which the safety layer remembers one scan point, m.
const MEMORY_CELL: f64 = 0.03;

/// A hasher for small integer keys (multiply and fold): deterministic, and far cheaper than
/// the default for the safety layer's few hundred points a scan.
#[derive(Debug, Clone, Copy, Default)]
struct CellHasher(u64);

impl std::hash::Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }

    fn write_i32(&mut self, v: i32) {
        self.write_u64(u64::from(v as u32));
    }

    fn write_u64(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

/// The [`CellHasher`] for the remembered points.
type CellHash = std::hash::BuildHasherDefault<CellHasher>;

/// `x.floor() as i32`, saturating, without a library call.
fn floor_i32(x: f64) -> i32 {
    let t = x as i32;
    if f64::from(t) > x {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// How long an escape from a tight spot lasts, s.
const ESCAPE_S: f64 = 1.2;

/// Extra margin the safety layer keeps from points it remembers but does not see in this
/// scan when turning or backing, m.
const BLIND_MARGIN: f64 = 0.06;

/// True for a command that turns or backs: toward points out of the laser's view.
fn toward_blind(c: VelocityCommand) -> bool {
    c.linear_m_s < 0.0 || c.angular_rad_s.abs() > 0.05
}

/// Every this many beams give a point to the scan matching (a stride, not a spacing: a
/// choice that depended on the points' noise would bias the match).
const MATCH_STRIDE: usize = 4;

/// The length of `path` left from point `along` on, plus the way from `from` to that point.
fn remaining(path: &[Point2], along: usize, from: Point2) -> f64 {
    let rest = path.get(along..).unwrap_or(&[]);
    let to_path = rest.first().map_or(0.0, |p| (p - from).norm());
    to_path + rest.windows(2).map(|s| (s[1] - s[0]).norm()).sum::<f64>()
}

/// The part of the segment `a`-`b` with `|y| <= band` and `x >= 0`.
fn clip_to_band(a: Point2, b: Point2, band: f64) -> Option<(Point2, Point2)> {
    let d = b - a;
    let (t0, t1) = clip_segment(&[(-d.x, a.x), (-d.y, a.y + band), (d.y, band - a.y)])?;
    Some((a + d * t0, a + d * t1))
}
