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
//! **The robot's own map.** Every scan is fitted onto everything mapped before it by
//! `laserlines-slam`'s [`Tracker`] (point-to-line ICP onto a map of surface points, pulled
//! toward the odometry's prediction; settings in `matching`) and every `map.every`-th scan
//! is added to the tracker's map and to the explorer's grid ([`RobotMap::insert_scan`]):
//! the map frame is the odometry frame at the start, corrected by the matching, so that the
//! map stays true while the wheel odometry drifts (the simulator's default odometry drifts
//! by about a metre in two minutes; the map pose stays within a few decimetres over a run).
//! From here on the explorer works in the map frame. It never reads the world: only its
//! scans, lines and odometry.
//!
//! **Leaving a wall followed all the way round.** Every 0.5 m of travel the map pose is
//! dropped as a breadcrumb. Coming back within `loops.match_radius_m` of a breadcrumb laid at least
//! `loops.min_path_m` earlier, heading the same way (within `loops.heading_rad`) on the same
//! followed side, means the wall has been followed all the way round. Then, or when wall
//! following has shown nothing new for `travel.stale_s` (it is going over ground already seen),
//! the explorer leaves the wall: it plans on its own map to the nearest *frontier* (a cell
//! where the robot fits at the edge of what it has seen, see [`crate::planner`]) not given
//! up before, drives there along the path (pure pursuit, re-planned every `travel.replan_s`, so
//! that the plan always starts from where the robot is; the target `travel.lookahead_m` ahead
//! is brought nearer where the chord to it would pass a path point farther than that point's
//! room beyond the footprint's circumradius and the safety margin, so that a bend round a
//! post or a wall end is followed, not cut), and when it gets there, or the
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
//! stays `safety.margin` clear (`safety.turn_margin`, by default the same, for a turn on the
//! spot, whose corners sweep a circle about the centre: with a smaller one the robot beside a
//! wall or a post can still turn where it stands); where the robot already stands nearer,
//! when it comes no
//! nearer (and keeps 2 cm), so that it can leave a tight spot. Otherwise slower versions,
//! turning on the spot, creeping turns and turning the other way are tried, in that order;
//! a robot whose wanted motion stays blocked for about a second *escapes*: of short straight
//! and curved motions forward and back, it drives for 1.2 s the safe one that ends with the
//! most room: the footprint's clearance plus the room to turn on the spot (the least distance
//! from the robot's centre to a point, less the footprint's circumradius), so that a robot
//! that cannot turn where it stands moves to where it can. This layer has the last word over
//! the wall follower and the path follower alike.
//!
//! **Stopping.** The explorer reports that it is done when no frontier is left (the whole
//! reachable area has been seen), when it has given up `travel.fruitless_give_ups`
//! different frontiers while its map grew by less than `travel.fruitless_gain_m2` (the
//! rest lies beyond gaps it cannot pass), or when its map has gained nothing for
//! `idle_timeout_s`.
//!
//! **Fence.** With [`ExplorerParams::fence`] set, the rectangle is one more wall wherever
//! the laser would see it: its lines join the scan's for the sectors and the wall follower,
//! its points near the robot join the safety layer's, and the planner closes the ground
//! beyond it (see [`crate::fence`]).
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
//! let mut extractor = HoughSplit::new(HoughSplitParams::navigation()).unwrap();
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
use laserlines::math::{Isometry2, Point2, Vector2};
use laserlines::robot::{Footprint, RobotDescription, VelocityCommand};

use crate::fence::fence_lines;

mod follow;
mod loops;
mod mapping;
mod params;
mod safety;
mod travel;

pub use params::{
    ExplorerParams, FollowParams, LoopParams, MapParams, MatchParams, SafetyParams, TravelParams,
    WallSide,
};

use laserlines_slam::Tracker;

use crate::map::RobotMap;
use crate::planner::Planner;
use crate::raster::BeamTable;
use crate::sectors::{SectorObjects, select_objects};
use loops::Crumb;
use safety::CellHash;
use travel::Travel;

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
    /// The pose estimate: scan matching onto its own map of surface points.
    tracker: Tracker,
    map_from_robot: Isometry2,
    /// Time the map last gained `map.new_cells` from one scan (wall following goes stale).
    last_new: f64,
    /// Time the map last gained any cell (the idle timeout).
    last_gain: f64,
    /// Cells the map has made known so far.
    known: u64,
    /// The different frontiers given up since the map last grew by
    /// `travel.fruitless_gain_m2`, and the cells it knew then.
    fruitless: (Vec<Point2>, u64),
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
    /// The scan's beam directions, laser frame.
    beams: BeamTable,
    /// The fence as the last scan sees it, laser frame (see [`crate::fence`]).
    fence_lines: Vec<Line>,
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
            planner: {
                let mut planner = Planner::new();
                planner.set_fence(params.fence);
                planner
            },
            tracker: Tracker::new(
                params
                    .matching
                    .tracker(&robot.laser.robot_from_laser(), params.map.every),
            ),
            map_from_robot: Isometry2::identity(),
            last_new: 0.0,
            last_gain: 0.0,
            known: 0,
            fruitless: (Vec::new(), 0),
            seek_since: 0.0,
            travel: None,
            avoid: Vec::new(),
            blocked: Vec::new(),
            failed_plans: 0,
            retries: 0,
            frontiers: 0,
            explored: false,
            beams: BeamTable::default(),
            fence_lines: Vec::new(),
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
        self.tracker.unmatched() as u64
    }

    /// The tracker that places each scan, with the map of surface points it matches onto.
    #[must_use]
    pub fn tracker(&self) -> &Tracker {
        &self.tracker
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
    /// `odom_from_robot` is the odometry pose at the scan, `time_s` its time. The same as
    /// [`Explorer::sense`] then [`Explorer::decide`].
    pub fn on_scan(
        &mut self,
        scan: &Scan,
        lines: &[Line],
        odom_from_robot: &Isometry2,
        time_s: f64,
    ) -> Decision {
        self.sense(scan, odom_from_robot, time_s);
        self.decide(lines, time_s)
    }

    /// The first half of [`Explorer::on_scan`], which needs no lines: the odometry, the
    /// scan matched onto the map and added to it, the near points remembered. A robot can
    /// run it while the lines of the same scan are being extracted.
    pub fn sense(&mut self, scan: &Scan, odom_from_robot: &Isometry2, time_s: f64) {
        self.track_odometry(odom_from_robot);
        self.note_field_of_view(scan);
        self.localise_and_map(scan, odom_from_robot, time_s);
        let map_from_robot = self.map_from_robot;
        self.remember(scan, &map_from_robot);
        self.fence_lines.clear();
        if let Some(fence) = &self.params.fence {
            let map_from_laser = map_from_robot * self.robot_from_laser;
            fence_lines(fence, scan, &map_from_laser, &mut self.fence_lines);
        }
    }

    /// The second half of [`Explorer::on_scan`], after [`Explorer::sense`] of the scan
    /// `lines` were extracted from: the sector objects, the wall follower or the way to a
    /// frontier, the safety layer.
    pub fn decide(&mut self, lines: &[Line], time_s: f64) -> Decision {
        // From here on the robot works in its map frame: the scan-matched pose is true to
        // the millimetre where the odometry slips by centimetres (turning on the spot).
        let map_from_robot = self.map_from_robot;
        // The fence, where the laser would see it, is one more wall.
        let fenced: Vec<Line>;
        let lines = if self.fence_lines.is_empty() {
            lines
        } else {
            fenced = lines.iter().chain(&self.fence_lines).copied().collect();
            &fenced
        };
        let objects = select_objects(lines, &self.robot_from_laser, &self.params.sectors);
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
        let wanted = match self.escape_or_travel(looped, time_s, front_free) {
            Some(w) => w,
            None => self.follow_wall(&objects, &robot_lines, front_free, &map_from_robot),
        };
        let command = self.safe_command(wanted, &map_from_robot, time_s);
        if self.mode == Mode::TurnAway {
            self.turned += (command.angular_rad_s * 0.1).abs();
        }
        let idle = time_s - self.last_gain > self.params.idle_timeout_s;
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

    /// The laser's blind wedge from the scan's first and last beam, in the robot's axes.
    fn note_field_of_view(&mut self, scan: &Scan) {
        let last_beam =
            scan.angle_min + scan.angle_increment * scan.ranges.len().saturating_sub(1) as f64;
        let (lo, hi) = (scan.angle_min.min(last_beam), scan.angle_min.max(last_beam));
        let yaw = self.robot_from_laser.rotation.angle();
        self.blind = (
            Vector2::new((lo + yaw).cos(), (lo + yaw).sin()),
            Vector2::new((hi + yaw).cos(), (hi + yaw).sin()),
            hi - lo >= std::f64::consts::PI,
        );
    }

    /// The wanted command when escaping has the first say, then the way to a frontier (going
    /// on, or starting after a loop, a stale spell or a long seek); `None` when the wall
    /// follower decides.
    fn escape_or_travel(
        &mut self,
        looped: bool,
        time_s: f64,
        front_free: f64,
    ) -> Option<VelocityCommand> {
        let p = self.params;
        // Seeking a wall in the open for long: no wall is near, go to a frontier.
        if self.mode != Mode::Seek {
            self.seek_since = time_s;
        }
        if self.mode == Mode::Escape && time_s < self.escape_until {
            return Some(self.escape);
        }
        if self.travel.is_some() {
            let step = self.travel_step(time_s, front_free);
            if step.is_none() {
                // Arrived (or the frontier was seen on the way): back to the wall.
                self.mode = Mode::Seek;
                self.wall_end = None;
                self.last_new = time_s;
            }
            return step;
        }
        let stale = time_s - self.last_new > p.travel.stale_s;
        let lost = time_s - self.seek_since > p.travel.seek_s;
        if (looped || stale || lost) && !self.explored {
            return self.start_travel(time_s, front_free);
        }
        None
    }
}
