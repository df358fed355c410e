//! One simulated exploration run: robot, laser, extraction, explorer, metrics.
//!
//! The loop, at the physics rate (50 Hz by default): when a scan is due (10 Hz) the laser
//! scans the world at the robot's true pose, [`HoughSplit`] extracts its lines, the
//! [`Explorer`] decides a command from the lines, the scan and the odometry, and the
//! coverage grid marks the beams' cells (ground truth, for the metrics only); every step the
//! robot drives the latest command. The run ends at the time limit or when the explorer
//! reports that nothing new has been seen for its idle timeout.

use std::time::Instant;

use laserlines::math::{Isometry2, Point2};
use laserlines::robot::VelocityCommand;
use laserlines::{HoughSplit, HoughSplitParams, Line, LineExtractor, Scan};
use laserlines_sim::World;
use laserlines_sim::robot::{RobotError, RobotParams, RobotSim};

use crate::coverage::CoverageGrid;
use crate::explorer::{Decision, Explorer, ExplorerParams, Mode, WallSide};
use crate::map::RobotMap;
use crate::sectors::SectorObjects;

/// Errors of [`run`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RunError {
    /// The robot cannot start there (e.g. the start pose is inside a wall).
    #[error(transparent)]
    Robot(#[from] RobotError),
    /// The extractor's parameters are invalid.
    #[error("extractor parameters: {0}")]
    Extractor(String),
    /// The run's own settings are invalid.
    #[error("run setting {field} = {value} is out of range: {expected}")]
    BadSetting {
        /// the field
        field: &'static str,
        /// its value
        value: f64,
        /// what is allowed
        expected: &'static str,
    },
}

/// Settings of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunConfig {
    /// Time limit, s of simulated time. Default 900 (15 minutes).
    pub duration_s: f64,
    /// Seed of the laser and odometry noise.
    pub seed: u64,
    /// The robot (footprint, drive, odometry, laser, rates).
    pub robot: RobotParams,
    /// The explorer.
    pub explorer: ExplorerParams,
    /// The line extractor.
    pub extractor: HoughSplitParams,
    /// Record the lines of every this many scans for the map picture (0: none). Default 10.
    pub record_lines_every: usize,
    /// Time of the snapshot for the sector picture, s. Default 20.
    pub snapshot_at_s: f64,
}

impl Default for RunConfig {
    fn default() -> Self {
        Self {
            duration_s: 900.0,
            seed: 0,
            robot: RobotParams::default(),
            explorer: ExplorerParams::default(),
            extractor: HoughSplitParams::default(),
            record_lines_every: 10,
            snapshot_at_s: 20.0,
        }
    }
}

/// Why a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// The time limit.
    TimeLimit,
    /// The explorer saw nothing new for its idle timeout.
    NothingNew,
    /// The explorer found no frontier left on its map: it has seen all it can reach.
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

/// The metrics of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metrics {
    /// Fraction of the reachable free area seen by the laser, 0..1 (see [`crate::coverage`]).
    pub coverage: f64,
    /// Collisions (see [`RobotSim::collisions`]).
    pub collisions: u64,
    /// Least distance between the footprint and any obstacle, m (capped at 1 m).
    pub min_clearance_m: f64,
    /// Distance driven, m.
    pub path_length_m: f64,
    /// Simulated time, s.
    pub sim_time_s: f64,
    /// Wall-clock time of the run, s (the only figure that differs between equal runs).
    pub wall_time_s: f64,
    /// Simulated time at which coverage reached 0.9, s; `None` if it never did.
    pub time_to_90_percent_s: Option<f64>,
    /// The reachable free area, m^2.
    pub reachable_area_m2: f64,
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

/// What a run shows its [`RunObserver`] at each scan: everything needed to replay the run
/// (the robot's true and estimated poses, the scan, its lines, the sector objects and the
/// explorer's state).
#[derive(Debug, Clone, Copy)]
pub struct ScanFrame<'a> {
    /// Simulated time of the scan, s.
    pub time_s: f64,
    /// The robot's true pose (ground truth).
    pub world_from_robot: Isometry2,
    /// The robot's own estimate of its pose (odometry corrected by scan matching), placed in
    /// the world by the start pose.
    pub estimated_world_from_robot: Isometry2,
    /// Where the laser sits on the robot.
    pub robot_from_laser: Isometry2,
    /// The scan, laser frame.
    pub scan: &'a Scan,
    /// Its lines, laser frame.
    pub lines: &'a [Line],
    /// The explorer's decision on this scan (command, sector objects in the robot frame,
    /// mode, followed side, frontier goal in the map frame).
    pub decision: &'a Decision,
    /// Coverage so far (ground truth), 0..1.
    pub coverage: f64,
}

/// Sees a run as it goes: every scan and the simulated time about once per simulated
/// second. Both methods do nothing by default.
pub trait RunObserver {
    /// Called after each scan has been decided on.
    fn on_scan(&mut self, frame: &ScanFrame<'_>) {
        let _ = frame;
    }
    /// Called with the simulated time about once per simulated second and at the end, s.
    fn on_progress(&mut self, time_s: f64) {
        let _ = time_s;
    }
}

/// Observes nothing.
impl RunObserver for () {}

/// Progress only.
struct Progress<'a>(&'a mut dyn FnMut(f64));

impl RunObserver for Progress<'_> {
    fn on_progress(&mut self, time_s: f64) {
        (self.0)(time_s);
    }
}

/// Runs an exploration of `world` from `start` (see the [module docs](self)).
///
/// # Errors
/// [`RunError::Robot`] when the robot cannot start at `start` (inside a wall, bad
/// parameters), [`RunError::Extractor`] for invalid extractor parameters,
/// [`RunError::BadSetting`] for a duration that is not positive and finite.
pub fn run(world: &World, start: Isometry2, config: &RunConfig) -> Result<RunRecord, RunError> {
    run_observed(world, start, config, &mut ())
}

/// [`run`], calling `progress` with the simulated time about once per simulated second.
///
/// # Errors
/// As [`run`].
pub fn run_with_progress(
    world: &World,
    start: Isometry2,
    config: &RunConfig,
    progress: &mut dyn FnMut(f64),
) -> Result<RunRecord, RunError> {
    run_observed(world, start, config, &mut Progress(progress))
}

/// [`run`], showing `observer` every scan and the simulated time as the run goes (e.g. to
/// record the run as MCAP or draw a progress bar).
///
/// # Errors
/// As [`run`].
pub fn run_observed(
    world: &World,
    start: Isometry2,
    config: &RunConfig,
    observer: &mut dyn RunObserver,
) -> Result<RunRecord, RunError> {
    if !(config.duration_s.is_finite() && config.duration_s > 0.0) {
        return Err(RunError::BadSetting {
            field: "duration_s",
            value: config.duration_s,
            expected: "positive and finite",
        });
    }
    let wall_clock = Instant::now();
    let mut robot = RobotSim::new(world, start, config.robot, config.seed)?;
    let mut extractor = HoughSplit::new(config.extractor.clone())
        .map_err(|e| RunError::Extractor(e.to_string()))?;
    let mut explorer = Explorer::new(config.explorer, &config.robot.robot);
    let start_point = Point2::from(start.translation.vector);
    let mut coverage = CoverageGrid::new(
        robot.index(),
        start_point,
        config.robot.robot.footprint.circumradius(),
    );
    let laser = config.robot.laser_model;
    let robot_from_laser = config.robot.robot.laser.robot_from_laser();

    let mut scan = Scan::default();
    let mut true_ranges = Vec::new();
    let mut lines: Vec<Line> = Vec::new();
    let mut command = VelocityCommand::STOP;
    let mut record = RunRecord {
        metrics: Metrics {
            coverage: 0.0,
            collisions: 0,
            min_clearance_m: 0.0,
            path_length_m: 0.0,
            sim_time_s: 0.0,
            wall_time_s: 0.0,
            time_to_90_percent_s: None,
            reachable_area_m2: coverage.reachable_area_m2(),
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
    };
    let steps = (config.duration_s / config.robot.physics_dt_s).round() as u64;
    let mut next_report = 0.0;
    let mut stop = StopReason::TimeLimit;
    for _ in 0..steps {
        if robot.scan_due() {
            let t = robot.time_s();
            robot.scan_into(&mut scan, &mut true_ranges);
            extractor.extract_into(&scan, &mut lines);
            let odom = robot.odom_from_robot();
            let decision = explorer.on_scan(&scan, &lines, &odom, t);
            // How far the robot's own pose estimate (its map frame is the start pose) is
            // from the truth: evaluation only.
            let believed = start * decision.map_from_robot;
            let world_from_robot_now = robot.world_from_robot();
            let pose_error =
                (believed.translation.vector - world_from_robot_now.translation.vector).norm();
            let m = &mut record.metrics;
            m.max_pose_error_m = m.max_pose_error_m.max(pose_error);
            m.max_heading_error_rad = m.max_heading_error_rad.max(
                laserlines::math::wrap_angle(
                    believed.rotation.angle() - world_from_robot_now.rotation.angle(),
                )
                .abs(),
            );
            command = decision.command;
            coverage.mark_scan(
                &robot.world_from_laser(),
                laser.angle_min,
                laser.angle_increment,
                &true_ranges,
                laser.range_max,
            );
            let m = &mut record.metrics;
            m.scans += 1;
            m.lines += lines.len() as u64;
            if m.time_to_90_percent_s.is_none() && coverage.coverage() >= 0.9 {
                m.time_to_90_percent_s = Some(t);
            }
            let world_from_robot = robot.world_from_robot();
            record
                .path
                .push(Point2::from(world_from_robot.translation.vector));
            let world_from_odom_robot = start * odom;
            record
                .odometry_path
                .push(Point2::from(world_from_odom_robot.translation.vector));
            record
                .estimated_path
                .push(Point2::from(believed.translation.vector));
            if config.record_lines_every > 0 && m.scans % config.record_lines_every as u64 == 1 {
                let world_from_laser = believed * robot_from_laser;
                record.lines_seen.extend(
                    lines
                        .iter()
                        .map(|l| (world_from_laser * l.start, world_from_laser * l.end)),
                );
            }
            if record.snapshot.is_none() && t >= config.snapshot_at_s {
                record.snapshot = Some(Snapshot {
                    time_s: t,
                    world_from_robot,
                    points: scan
                        .points(scan.range_window(None))
                        .iter()
                        .map(|p| robot_from_laser * p.point)
                        .collect(),
                    lines: lines
                        .iter()
                        .map(|l| (robot_from_laser * l.start, robot_from_laser * l.end))
                        .collect(),
                    objects: decision.objects,
                    mode: decision.mode,
                    side: decision.side,
                });
            }
            observer.on_scan(&ScanFrame {
                time_s: t,
                world_from_robot,
                estimated_world_from_robot: believed,
                robot_from_laser,
                scan: &scan,
                lines: &lines,
                decision: &decision,
                coverage: coverage.coverage(),
            });
            if t >= next_report {
                record.coverage_curve.push((t, coverage.coverage()));
                observer.on_progress(t);
                next_report += 1.0;
            }
            if decision.done {
                stop = if decision.explored {
                    StopReason::Explored
                } else {
                    StopReason::NothingNew
                };
                break;
            }
        }
        robot.step(command);
    }
    let m = &mut record.metrics;
    m.coverage = coverage.coverage();
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
    observer.on_progress(robot.time_s());
    record.unseen = coverage.unseen();
    record.given_up = explorer.given_up().iter().map(|p| start * p).collect();
    record.map = explorer.map().clone();
    m.wall_time_s = wall_clock.elapsed().as_secs_f64();
    Ok(record)
}
