//! What a run shows as it goes: one [`ScanFrame`] per scan, and the simulated time.

use laserlines::math::Isometry2;
use laserlines::{Line, Scan};
use laserlines_nav::Decision;

/// What a run shows its [`RunObserver`] at each scan: everything needed to replay the run
/// (the robot's true, odometric and estimated poses, the scan, its lines, the sector objects
/// and the explorer's state).
#[derive(Debug, Clone, Copy)]
pub struct ScanFrame<'a> {
    /// Simulated time of the scan, s.
    pub time_s: f64,
    /// The robot's true pose (ground truth).
    pub world_from_robot: Isometry2,
    /// The wheel odometry's pose, in the odometry frame (the start pose).
    pub odom_from_robot: Isometry2,
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
    /// Whether the robot's centre is in the arena (ground truth, see
    /// [`crate::CoverageGrid::in_arena`]).
    pub in_arena: bool,
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
pub(crate) struct Progress<'a>(pub(crate) &'a mut dyn FnMut(f64));

impl RunObserver for Progress<'_> {
    fn on_progress(&mut self, time_s: f64) {
        (self.0)(time_s);
    }
}
