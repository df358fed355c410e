//! What a reader yields: a scan with its pose and its place in the input.

use laserlines::Scan;
use laserlines::math::{Isometry2, Vector2};
use serde::{Deserialize, Serialize};

/// A planar pose: position in metres and heading in radians (counter-clockwise from the
/// frame's x axis).
///
/// In a [`ScanRecord`] it is a pose the source gives with the scan: [`ScanRecord::pose`]
/// (the pose the log states, e.g. CARMEN's laser pose) and [`ScanRecord::odometry`] (the
/// wheel odometry's).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Pose2 {
    /// x, m.
    pub x: f64,
    /// y, m.
    pub y: f64,
    /// Heading, rad.
    pub theta: f64,
}

impl Pose2 {
    /// A pose from its parts (metres, metres, radians).
    #[must_use]
    pub const fn new(x: f64, y: f64, theta: f64) -> Self {
        Self { x, y, theta }
    }

    /// The pose as a rigid transform mapping points of the posed frame into the parent frame
    /// (e.g. `world_from_robot`).
    #[must_use]
    pub fn to_isometry(self) -> Isometry2 {
        Isometry2::new(Vector2::new(self.x, self.y), self.theta)
    }

    /// True when all three parts are finite.
    #[must_use]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.theta.is_finite()
    }
}

/// One scan read from an input, with what the source says about it.
#[derive(Debug, Clone, PartialEq)]
pub struct ScanRecord {
    /// The scan (validated by the reader with [`Scan::validate`]); `scan.stamp` is its time
    /// stamp in seconds when the source has one.
    pub scan: Scan,
    /// The pose the source states for the scan (`world_from_robot` in the source's world or
    /// odometry frame, metres and radians), when it has one: CARMEN's laser pose (the first
    /// pose triple of a laser line; SLAM-corrected in some published logs), BreezySLAM's
    /// wheel odometry, an MCAP file's `base_link` transform from a frame other than `odom`,
    /// a JSON scan's `pose`.
    pub pose: Option<Pose2>,
    /// The wheel odometry's pose at the scan (`odom_from_robot`), when the source has one:
    /// CARMEN's odometry triple (`odom_x odom_y odom_theta` of `FLASER`/`RLASER`, the robot
    /// pose of `ROBOTLASER`, the last `ODOM` message for `RAWLASER`), BreezySLAM's wheel
    /// odometry, an MCAP file's `odom` -> `base_link` transform, a JSON scan's `odometry`.
    /// Never the log's laser pose: mapping with odometry reads this field only.
    pub odometry: Option<Pose2>,
    /// The 1-based line of the input where the record starts, for text formats.
    pub line: Option<usize>,
}

impl ScanRecord {
    /// A record holding only a scan.
    #[must_use]
    pub fn new(scan: Scan) -> Self {
        Self {
            scan,
            pose: None,
            odometry: None,
            line: None,
        }
    }
}
