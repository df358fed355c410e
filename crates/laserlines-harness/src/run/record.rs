//! What a run gives: its [`Metrics`] and what the pictures need ([`RunRecord`]), kept by
//! the [`Recorder`], the observer every run has.

use std::time::Instant;

use laserlines::math::{Isometry2, Point2, wrap_angle};
use laserlines_nav::{Explorer, Mode, RobotMap, SectorObjects, WallSide};
use laserlines_sim::robot::RobotSim;

use super::observe::{RunObserver, ScanFrame};
use crate::coverage::{CoverageGrid, CoverageRegion};

/// Why a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// The time limit.
    TimeLimit,
    /// The explorer saw nothing new for its idle timeout.
    NothingNew,
    /// The explorer found no way to a frontier of its map: it has seen all it can reach
    /// (from a start that leaves the planner no way out, nothing beyond the start).
    Explored,
}

impl StopReason {
    /// `time_limit`, `nothing_new` or `explored`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::TimeLimit => "time_limit",
            Self::NothingNew => "nothing_new",
            Self::Explored => "explored",
        }
    }
}

/// The metrics of a run (serialized with the field names, as `metrics.json` of `laserlines
/// simulate` has them).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Metrics {
    /// Fraction of the arena's free area seen by the laser, 0..1 (see [`crate::coverage`]).
    pub coverage: f64,
    /// What coverage is taken over: the free area the arena's walls enclose, or (when they
    /// do not enclose the start) the free area inside their bounding box.
    pub coverage_region: CoverageRegion,
    /// That free area, m^2.
    pub arena_area_m2: f64,
    /// Whether the robot's centre ever left the arena (the area its walls enclose, or their
    /// bounding box).
    pub left_arena: bool,
    /// Simulated time at which it first did, s.
    pub left_arena_at_s: Option<f64>,
    /// Collisions (see [`RobotSim::collisions`]).
    pub collisions: u64,
    /// Least distance between the footprint and any obstacle, m (capped at 1 m).
    pub min_clearance_m: f64,
    /// Distance driven, m.
    pub path_length_m: f64,
    /// Simulated time, s.
    pub sim_time_s: f64,
    /// Wall-clock time of the closed loop, s: from the first scan to the last physics step,
    /// all of sensing, extraction, the explorer, physics, the ground-truth coverage and
    /// every observer's work on each scan (a progress bar, an MCAP recording). Not in it:
    /// [`Metrics::setup_time_s`], loading the arena and writing the outputs. With the set-up
    /// time, the only figures that differ between equal runs.
    pub wall_time_s: f64,
    /// Wall-clock time of the run's set-up, s: the simulated robot's obstacle index, the
    /// extractor, the explorer and the ground-truth coverage grid (its clearances and
    /// flood fills).
    pub setup_time_s: f64,
    /// Simulated time at which coverage reached 0.9, s; `None` if it never did.
    pub time_to_90_percent_s: Option<f64>,
    /// The free area connected to the start (where the robot can drive from it), m^2.
    pub reachable_area_m2: f64,
    /// Fraction of that area seen by the laser, 0..1.
    pub reachable_coverage: f64,
    /// Scans taken (and lines extracted from).
    pub scans: u64,
    /// Lines extracted, over all scans.
    pub lines: u64,
    /// Walls followed all the way round (the explorer's loop detections).
    pub loops: usize,
    /// Frontiers the explorer reached (or saw on its way there).
    pub frontiers: usize,
    /// Largest distance between the robot's own position estimate (odometry corrected by
    /// scan matching against its map) and the true position, m.
    pub max_pose_error_m: f64,
    /// Largest error of the robot's own heading estimate, rad.
    pub max_heading_error_rad: f64,
    /// Scans the robot could not place on its map (their pose came from the odometry).
    pub unmatched_scans: u64,
    /// Why the run ended.
    pub stop: StopReason,
}
/// The moment pictured by the sector figure (the paper's Fig. 7).
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Simulated time, s.
    pub time_s: f64,
    /// The robot's true pose.
    pub world_from_robot: Isometry2,
    /// The scan's valid points, robot frame.
    pub points: Vec<Point2>,
    /// The extracted lines as end points, robot frame.
    pub lines: Vec<(Point2, Point2)>,
    /// The three selected objects.
    pub objects: SectorObjects,
    /// The explorer's mode.
    pub mode: Mode,
    /// The followed side.
    pub side: WallSide,
}

/// Everything a run gives: metrics and what the pictures need.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRecord {
    /// The metrics.
    pub metrics: Metrics,
    /// The robot's true path, one point per scan, world frame.
    pub path: Vec<Point2>,
    /// The odometry path, one point per scan, in the world frame (odometry frame placed at
    /// the start pose): the wheel odometry alone, drifting.
    pub odometry_path: Vec<Point2>,
    /// The robot's own estimate of its path (odometry corrected by scan matching), one
    /// point per scan, world frame (its map frame placed at the start pose).
    pub estimated_path: Vec<Point2>,
    /// Lines seen (every `record_lines_every` scans), placed in the world by the robot's own
    /// pose estimate (odometry corrected by scan matching), as the robot maps them.
    pub lines_seen: Vec<(Point2, Point2)>,
    /// The sector snapshot, if the run lasted until its time.
    pub snapshot: Option<Snapshot>,
    /// Coverage over time: `(sim time s, coverage)` once per simulated second.
    pub coverage_curve: Vec<(f64, f64)>,
    /// Centres of the reachable coverage cells never seen, world frame.
    pub unseen: Vec<Point2>,
    /// The robot's own map at the end; its map frame is the start pose (`world_from_map` =
    /// the start).
    pub map: RobotMap,
    /// The frontiers the explorer gave up, world frame.
    pub given_up: Vec<Point2>,
}
/// Keeps the record of a run from its frames: the paths, the lines seen, the snapshot, the
/// coverage curve and the metrics that build up scan by scan.
pub(crate) struct Recorder {
    record: RunRecord,
    start: Isometry2,
    record_lines_every: usize,
    snapshot_at_s: f64,
    /// Coverage after the latest scan.
    coverage: f64,
    wall_clock: Instant,
}

impl Recorder {
    /// A recorder for a run from `start` scored on `coverage`.
    pub(crate) fn new(
        start: Isometry2,
        coverage: &CoverageGrid,
        record_lines_every: usize,
        snapshot_at_s: f64,
    ) -> Self {
        Self {
            record: RunRecord {
                metrics: Metrics {
                    coverage: 0.0,
                    coverage_region: coverage.region_kind(),
                    arena_area_m2: coverage.region_area_m2(),
                    left_arena: false,
                    left_arena_at_s: None,
                    collisions: 0,
                    min_clearance_m: 0.0,
                    path_length_m: 0.0,
                    sim_time_s: 0.0,
                    wall_time_s: 0.0,
                    setup_time_s: 0.0,
                    time_to_90_percent_s: None,
                    reachable_area_m2: coverage.reachable_area_m2(),
                    reachable_coverage: 0.0,
                    scans: 0,
                    lines: 0,
                    loops: 0,
                    frontiers: 0,
                    max_pose_error_m: 0.0,
                    max_heading_error_rad: 0.0,
                    unmatched_scans: 0,
                    stop: StopReason::TimeLimit,
                },
                path: Vec::new(),
                odometry_path: Vec::new(),
                estimated_path: Vec::new(),
                lines_seen: Vec::new(),
                snapshot: None,
                coverage_curve: Vec::new(),
                unseen: Vec::new(),
                map: RobotMap::new(),
                given_up: Vec::new(),
            },
            start,
            record_lines_every,
            snapshot_at_s,
            coverage: 0.0,
            wall_clock: Instant::now(),
        }
    }

    /// Records the set-up time and starts the loop's clock.
    pub(crate) fn start_clock(&mut self, setup_time_s: f64) {
        self.record.metrics.setup_time_s = setup_time_s;
        self.wall_clock = Instant::now();
    }

    /// The record, completed from the robot, the explorer and the coverage grid at the end.
    pub(crate) fn finish(
        mut self,
        robot: &RobotSim,
        explorer: &Explorer,
        coverage: &CoverageGrid,
        stop: StopReason,
    ) -> RunRecord {
        let record = &mut self.record;
        let m = &mut record.metrics;
        m.coverage = coverage.coverage();
        m.reachable_coverage = coverage.reachable_coverage();
        m.collisions = robot.collisions();
        m.min_clearance_m = robot.min_clearance();
        m.path_length_m = robot.path_length();
        m.sim_time_s = robot.time_s();
        m.loops = explorer.loops();
        m.frontiers = explorer.frontiers();
        m.unmatched_scans = explorer.unmatched_scans();
        m.stop = stop;
        record
            .coverage_curve
            .push((robot.time_s(), coverage.coverage()));
        record.unseen = coverage.unseen();
        let start = self.start;
        record.given_up = explorer.given_up().iter().map(|p| start * p).collect();
        record.map = explorer.map().clone();
        m.wall_time_s = self.wall_clock.elapsed().as_secs_f64();
        self.record
    }

    /// How far the robot's own pose estimate is from the truth: evaluation only.
    fn pose_errors(&mut self, frame: &ScanFrame<'_>) {
        let believed = frame.estimated_world_from_robot;
        let truth = frame.world_from_robot;
        let m = &mut self.record.metrics;
        let pose_error = (believed.translation.vector - truth.translation.vector).norm();
        m.max_pose_error_m = m.max_pose_error_m.max(pose_error);
        m.max_heading_error_rad = m
            .max_heading_error_rad
            .max(wrap_angle(believed.rotation.angle() - truth.rotation.angle()).abs());
    }

    /// The moment of the sector picture.
    fn snapshot(frame: &ScanFrame<'_>) -> Snapshot {
        let (scan, robot_from_laser) = (frame.scan, frame.robot_from_laser);
        Snapshot {
            time_s: frame.time_s,
            world_from_robot: frame.world_from_robot,
            points: scan
                .points(scan.range_window(None))
                .iter()
                .map(|p| robot_from_laser * p.point)
                .collect(),
            lines: frame
                .lines
                .iter()
                .map(|l| (robot_from_laser * l.start, robot_from_laser * l.end))
                .collect(),
            objects: frame.decision.objects,
            mode: frame.decision.mode,
            side: frame.decision.side,
        }
    }
}

impl RunObserver for Recorder {
    fn on_scan(&mut self, frame: &ScanFrame<'_>) {
        self.pose_errors(frame);
        self.coverage = frame.coverage;
        let t = frame.time_s;
        let m = &mut self.record.metrics;
        m.scans += 1;
        m.lines += frame.lines.len() as u64;
        if !frame.in_arena && !m.left_arena {
            m.left_arena = true;
            m.left_arena_at_s = Some(t);
        }
        if m.time_to_90_percent_s.is_none() && frame.coverage >= 0.9 {
            m.time_to_90_percent_s = Some(t);
        }
        let scans = m.scans;
        let record = &mut self.record;
        let believed = frame.estimated_world_from_robot;
        let point = |pose: Isometry2| Point2::from(pose.translation.vector);
        record.path.push(point(frame.world_from_robot));
        record
            .odometry_path
            .push(point(self.start * frame.odom_from_robot));
        record.estimated_path.push(point(believed));
        if self.record_lines_every > 0 && scans % self.record_lines_every as u64 == 1 {
            let world_from_laser = believed * frame.robot_from_laser;
            record.lines_seen.extend(
                frame
                    .lines
                    .iter()
                    .map(|l| (world_from_laser * l.start, world_from_laser * l.end)),
            );
        }
        if record.snapshot.is_none() && t >= self.snapshot_at_s {
            record.snapshot = Some(Self::snapshot(frame));
        }
    }

    fn on_progress(&mut self, time_s: f64) {
        self.record.coverage_curve.push((time_s, self.coverage));
    }
}
