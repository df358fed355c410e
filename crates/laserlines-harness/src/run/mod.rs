//! One simulated exploration run: the paper's loop, sense -> extract -> decide -> act.
//!
//! At every physics step (50 Hz by default) the robot acts on the latest command. When a
//! scan is due (10 Hz):
//!
//! 1. **Sense**: the simulated laser scans the world at the robot's true pose, and the wheel
//!    odometry gives its own pose;
//! 2. **Extract**: [`HoughSplit`] extracts the scan's lines (on a second thread with
//!    [`RunConfig::extraction_thread`]), and the [`Explorer`] matches the scan onto its map
//!    ([`Explorer::sense`]) and the ground-truth coverage grid marks the cells the beams
//!    swept;
//! 3. **Decide**: the explorer turns the lines into a velocity command
//!    ([`Explorer::decide`]);
//! 4. **Record**: the observers (the recorder of the [`RunRecord`] and the caller's
//!    [`RunObserver`]) see the scan's [`ScanFrame`]. Nothing recorded flows back into the
//!    robot.
//!
//! The run is the same, bit for bit, whether the lines come from the second thread or not.
//!
//! The run ends at the time limit, or when the explorer reports that it has seen all it can
//! reach or nothing new for its idle timeout.

mod extract;
mod observe;
mod record;

use laserlines::math::Isometry2;
use laserlines::robot::VelocityCommand;
use laserlines::{HoughSplit, HoughSplitParams, Line, ParamsError, Scan};
use laserlines_nav::{Decision, Explorer, ExplorerParams, Sector};
use laserlines_sim::World;
use laserlines_sim::robot::{RobotError, RobotParams, RobotSim};

use extract::{Extraction, Inline, Worker};
use observe::Progress;
pub use observe::{RunObserver, ScanFrame};
use record::Recorder;
pub use record::{Metrics, RunRecord, Snapshot, StopReason};

use crate::coverage::CoverageGrid;

/// Errors of [`run`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RunError {
    /// The robot cannot start there (e.g. the start pose is inside a wall).
    #[error(transparent)]
    Robot(#[from] RobotError),
    /// The extractor's parameters are invalid.
    #[error("extractor parameters: {0}")]
    Extractor(ParamsError),
    /// The explorer's parameters are invalid.
    #[error("explorer parameters: {0}")]
    Explorer(ParamsError),
    /// The run's own settings are invalid.
    #[error("run settings: {0}")]
    Setting(ParamsError),
    /// The world is larger than the coverage grid holds.
    #[error(
        "the world spans {width_m:.1} m x {height_m:.1} m with its start; coverage is measured \
         on a grid of at most {most_m} m on a side (a rescue arena spans tens of metres)",
        most_m = crate::coverage::MAX_COVERAGE_CELLS as f64 * crate::coverage::COVERAGE_CELL
    )]
    TooLarge {
        /// Width of the world, m.
        width_m: f64,
        /// Height of the world, m.
        height_m: f64,
    },
    /// The laser, as mounted, does not see the robot's front sector, where the explorer
    /// looks before it drives.
    #[error(
        "the laser, turned by {yaw_deg:.1} deg (laser.yaw), sees {from_deg:.1} to {to_deg:.1} \
         deg of the robot's frame: the explorer needs the front sector, -50 to 50 deg"
    )]
    FrontUnseen {
        /// The mount's yaw, deg.
        yaw_deg: f64,
        /// The first beam's bearing in the robot's frame, deg.
        from_deg: f64,
        /// The last beam's bearing in the robot's frame, deg.
        to_deg: f64,
    },
}

/// Checks that the laser's beams, as mounted, span the front sector.
fn check_front_seen(robot: &RobotParams) -> Result<(), RunError> {
    let laser = &robot.laser_model;
    let yaw = laserlines::math::wrap_angle(robot.robot.laser.yaw);
    let last = laser.angle_min + laser.angle_increment * laser.beams.saturating_sub(1) as f64;
    let (a, b) = (
        yaw + laser.angle_min.min(last),
        yaw + laser.angle_min.max(last),
    );
    let (front_from, front_to) = Sector::Front.bounds_rad();
    // The front sector within the beams' span, a turn either way (a span across +-pi).
    let turn = std::f64::consts::TAU;
    let seen = b - a >= turn
        || [-turn, 0.0, turn]
            .iter()
            .any(|k| a + k <= front_from && b + k >= front_to);
    if seen {
        return Ok(());
    }
    Err(RunError::FrontUnseen {
        yaw_deg: yaw.to_degrees(),
        from_deg: a.to_degrees(),
        to_deg: b.to_degrees(),
    })
}

/// Checks that the wall the explorer follows lies within the laser's reach.
fn check_follow_seen(config: &RunConfig) -> Result<(), RunError> {
    let reach = config.robot.laser_model.range_max;
    let follow = &config.explorer.follow;
    for (field, value) in [
        ("follow.distance", follow.distance),
        ("follow.range", follow.range),
    ] {
        if value > reach {
            return Err(RunError::Explorer(ParamsError::AboveField {
                field,
                value,
                limit_field: "the laser's range_max",
                limit: reach,
            }));
        }
    }
    Ok(())
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
    /// The line extractor. Default [`HoughSplitParams::navigation`]: posts and legs are
    /// obstacles.
    pub extractor: HoughSplitParams,
    /// Record the lines of every this many scans for the map picture (0: none). Default 10.
    pub record_lines_every: usize,
    /// Time of the snapshot for the sector picture, s. Default 20.
    pub snapshot_at_s: f64,
    /// Extract each scan's lines on a second thread while the robot side senses the same
    /// scan (when the machine has two cores or more). Default false: on the 2-core virtual
    /// machines measured, waking the thread twice a scan cost more than the overlap saved
    /// (`simulate --arena maze_10m_x_14m`: 796-835x real time with the thread, 1030-1086x
    /// without). The run is the same either way.
    pub extraction_thread: bool,
}

impl RunConfig {
    /// The checks a run makes before it starts that need no obstacle index: the run's
    /// duration, the explorer's and the robot's parameters, the laser's view of the front
    /// sector and of the followed wall, the robot placed at `start` (not on a wall or a
    /// disc), and the world's size against the coverage grid. A caller that writes
    /// files for a run can call it before it makes them.
    ///
    /// # Errors
    /// The [`RunError`] the run would end with at once.
    pub fn check(&self, world: &World, start: Isometry2) -> Result<(), RunError> {
        laserlines::params::positive("duration_s", self.duration_s).map_err(RunError::Setting)?;
        self.explorer.validate().map_err(RunError::Explorer)?;
        self.robot.validate()?;
        check_front_seen(&self.robot)?;
        check_follow_seen(self)?;
        // A start on a wall or a disc.
        RobotSim::new(world, start, self.robot, self.seed)?;
        let origin = laserlines::math::Point2::from(start.translation.vector);
        if let Some((width_m, height_m)) = CoverageGrid::too_large(world, origin) {
            return Err(RunError::TooLarge { width_m, height_m });
        }
        Ok(())
    }
}

impl Default for RunConfig {
    fn default() -> Self {
        Self {
            duration_s: 900.0,
            seed: 0,
            robot: RobotParams::default(),
            explorer: ExplorerParams::default(),
            extractor: HoughSplitParams::navigation(),
            record_lines_every: 10,
            snapshot_at_s: 20.0,
            extraction_thread: false,
        }
    }
}

impl RunConfig {
    /// The time of the run's last scan when it goes on to its time limit, s: scans come every
    /// `scan_period_s` (rounded to physics steps) from time 0, and the run takes
    /// `duration_s / physics_dt_s` steps (rounded). 0 for a run of no step.
    #[must_use]
    pub fn last_scan_s(&self) -> f64 {
        let dt = self.robot.physics_dt_s;
        let steps = (self.duration_s / dt).round();
        let per_scan = (self.robot.scan_period_s / dt).round().max(1.0);
        if steps.is_finite() && steps >= 1.0 && per_scan.is_finite() {
            ((steps - 1.0) / per_scan).floor() * per_scan * dt
        } else {
            0.0
        }
    }
}

/// Runs an exploration of `world` from `start` (see the [module docs](self)).
///
/// # Errors
/// [`RunError::Robot`] when the robot cannot start at `start` (inside a wall, bad
/// parameters), [`RunError::Extractor`] and [`RunError::Explorer`] for invalid extractor and
/// explorer parameters, [`RunError::Setting`] for a duration that is not positive and finite.
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
    let setup = std::time::Instant::now();
    let (mut run, extractor) = Loop::new(world, start, config)?;
    run.recorder.start_clock(setup.elapsed().as_secs_f64());
    let two_cores = std::thread::available_parallelism().is_ok_and(|n| n.get() > 1);
    let stop = if config.extraction_thread && two_cores {
        std::thread::scope(|scope| {
            let mut worker = Worker::spawn(scope, extractor);
            run.steps(config, observer, &mut worker)
        })
    } else {
        run.steps(config, observer, &mut Inline::new(extractor))
    };
    let record = run
        .recorder
        .finish(&run.robot, &run.explorer, &run.coverage, stop);
    observer.on_progress(run.robot.time_s());
    Ok(record)
}

/// Everything in the loop: the simulated robot, the explorer (the robot side), the ground
/// truth and the recorder, and the scan's buffers.
struct Loop {
    start: Isometry2,
    robot: RobotSim,
    explorer: Explorer,
    coverage: CoverageGrid,
    recorder: Recorder,
    robot_from_laser: Isometry2,
    scan: Scan,
    true_ranges: Vec<f64>,
    lines: Vec<Line>,
    odom_from_robot: Isometry2,
}

impl Loop {
    /// The loop and its line extractor.
    fn new(
        world: &World,
        start: Isometry2,
        config: &RunConfig,
    ) -> Result<(Self, HoughSplit), RunError> {
        config.check(world, start)?;
        let robot = RobotSim::new(world, start, config.robot, config.seed)?;
        let extractor = HoughSplit::new(config.extractor.clone()).map_err(RunError::Extractor)?;
        let origin = laserlines::math::Point2::from(start.translation.vector);
        let coverage = CoverageGrid::new(
            robot.index(),
            origin,
            config.robot.robot.footprint.circumradius(),
        );
        let recorder = Recorder::new(
            start,
            &coverage,
            config.record_lines_every,
            config.snapshot_at_s,
        );
        let run = Self {
            start,
            robot,
            explorer: Explorer::new(config.explorer, &config.robot.robot),
            coverage,
            recorder,
            robot_from_laser: config.robot.robot.laser.robot_from_laser(),
            scan: Scan::default(),
            true_ranges: Vec::new(),
            lines: Vec::new(),
            odom_from_robot: Isometry2::identity(),
        };
        Ok((run, extractor))
    }

    /// The physics steps of the run, with a scan whenever one is due, until the time
    /// limit or the explorer is done; why it ended.
    fn steps(
        &mut self,
        config: &RunConfig,
        observer: &mut dyn RunObserver,
        extraction: &mut dyn Extraction,
    ) -> StopReason {
        let steps = (config.duration_s / config.robot.physics_dt_s).round() as u64;
        let mut command = VelocityCommand::STOP;
        let mut next_report = 0.0;
        for _ in 0..steps {
            if self.robot.scan_due() {
                let t = self.robot.time_s();
                let decision = self.sense_extract_decide(t, extraction);
                command = decision.command;
                self.record(&decision, t, observer);
                if t >= next_report {
                    self.recorder.on_progress(t);
                    observer.on_progress(t);
                    next_report += 1.0;
                }
                if decision.done {
                    return if decision.explored {
                        StopReason::Explored
                    } else {
                        StopReason::NothingNew
                    };
                }
            }
            // Act.
            self.robot.step(command);
        }
        StopReason::TimeLimit
    }

    /// The robot side's turn at time `t`: the laser scans and the odometry reads; the lines
    /// are extracted while the explorer matches the scan onto its map and the ground truth
    /// marks it; the explorer decides.
    fn sense_extract_decide(&mut self, t: f64, extraction: &mut dyn Extraction) -> Decision {
        // Sense.
        self.robot.scan_into(&mut self.scan, &mut self.true_ranges);
        self.odom_from_robot = self.robot.odom_from_robot();
        // Extract, meanwhile localise and map, and mark the ground truth.
        extraction.start(&self.scan);
        self.explorer.sense(&self.scan, &self.odom_from_robot, t);
        let laser = self.robot.params().laser_model;
        self.coverage.mark_scan(
            &self.robot.world_from_laser(),
            laser.angle_min,
            laser.angle_increment,
            &self.true_ranges,
            laser.range_max,
        );
        extraction.finish(&self.scan, &mut self.lines);
        // Decide.
        self.explorer.decide(&self.lines, t)
    }

    /// Records the scan: the recorder and `observer` see its frame. Nothing recorded flows
    /// back into the robot.
    fn record(&mut self, decision: &Decision, t: f64, observer: &mut dyn RunObserver) {
        let world_from_robot = self.robot.world_from_robot();
        let frame = ScanFrame {
            time_s: t,
            world_from_robot,
            odom_from_robot: self.odom_from_robot,
            estimated_world_from_robot: self.start * decision.map_from_robot,
            robot_from_laser: self.robot_from_laser,
            scan: &self.scan,
            lines: &self.lines,
            decision,
            coverage: self.coverage.coverage(),
            in_arena: self.coverage.in_arena(laserlines::math::Point2::from(
                world_from_robot.translation.vector,
            )),
        };
        self.recorder.on_scan(&frame);
        observer.on_scan(&frame);
    }
}
