//! What laserlines shows in Foxglove: a scan, its lines and the robot's pose as Foxglove
//! messages, shared by the MCAP writer and the live server.
//!
//! | topic | schema | frame | content |
//! |---|---|---|---|
//! | `/scan` | `foxglove.LaserScan` | `laser` | the scan; invalid ranges as NaN |
//! | `/lines` | `foxglove.SceneUpdate` | `laser` | one entity `lines` with one `LINE_LIST` primitive: two points (start, end) per line, z = 0 |
//! | `/tf` | `foxglove.FrameTransform` | `world` -> `base_link`, `base_link` -> `laser` | the robot's pose (`world_from_robot`) and the identity (the laser at the robot's origin), only when the input has poses; with odometry `world` -> `odom` -> `base_link` instead (REP 105: the odometry, and the odometry frame placed so that the chain gives the pose) |
//!
//! Every message of a scan carries the same timestamp and log time: the scan's stamp, or, for
//! scans without one, 0.1 s after the previous scan's time (the first at 0).

use foxglove::messages::{
    Color, FrameTransform, KeyValuePair, LaserScan, LinePrimitive, Point3, SceneEntity,
    SceneUpdate, line_primitive,
};
use laserlines::Line;
use laserlines_io::{Pose2, ScanRecord};

use crate::proto;
use crate::{LASER_FRAME, LINES_ENTITY, ODOM_FRAME, ROBOT_FRAME, WORLD_FRAME};

/// Time given to a scan without a stamp, after the previous scan's, s.
pub const DEFAULT_SCAN_PERIOD: f64 = 0.1;

/// Gives each scan its time: its stamp when finite, not negative and below 2^32 s, else
/// [`DEFAULT_SCAN_PERIOD`] after the previous one.
#[derive(Debug, Clone, Default)]
pub struct SceneClock {
    last: Option<f64>,
    unusable: u64,
}

impl SceneClock {
    /// A clock before the first scan.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The time of the next scan, s.
    pub fn time_of(&mut self, stamp: Option<f64>) -> f64 {
        let t = match stamp {
            Some(s) if s.is_finite() && s >= 0.0 && s < f64::from(u32::MAX) => s,
            other => {
                self.unusable += u64::from(other.is_some());
                self.last.map_or(0.0, |l| l + DEFAULT_SCAN_PERIOD)
            }
        };
        self.last = Some(t);
        t
    }

    /// Stamps so far that were not taken (not finite, negative, or 2^32 s and more); scans
    /// without a stamp are not counted.
    #[must_use]
    pub fn unusable(&self) -> u64 {
        self.unusable
    }
}

/// Seconds to MCAP log time (ns).
#[must_use]
pub fn log_time_ns(seconds: f64) -> u64 {
    let t = proto::timestamp(seconds);
    u64::from(t.sec()) * 1_000_000_000 + u64::from(t.nsec())
}

/// The Foxglove messages of one scan.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneMessages {
    /// Time of every message, s.
    pub time: f64,
    /// The scan, on `/scan`.
    pub scan: LaserScan,
    /// The lines, on `/lines` (`None` when only scans are converted).
    pub lines: Option<SceneUpdate>,
    /// `world -> base_link` and `base_link -> laser`, on `/tf` (empty without a pose); with
    /// odometry `world -> odom -> base_link -> laser`.
    pub transforms: Vec<FrameTransform>,
}

/// Colour of the lines: orange, opaque.
const LINE_COLOR: Color = Color {
    r: 1.0,
    g: 0.45,
    b: 0.0,
    a: 1.0,
};

/// Line width on screen, pixels.
const LINE_THICKNESS_PX: f64 = 3.0;

/// The lines as one scene entity `lines` in frame `laser`.
#[must_use]
pub fn lines_update(lines: &[Line], time: f64) -> SceneUpdate {
    let points = lines
        .iter()
        .flat_map(|l| [l.start, l.end])
        .map(|p| Point3 {
            x: p.x,
            y: p.y,
            z: 0.0,
        })
        .collect();
    SceneUpdate {
        deletions: Vec::new(),
        entities: vec![SceneEntity {
            timestamp: Some(proto::timestamp(time)),
            frame_id: LASER_FRAME.to_owned(),
            id: LINES_ENTITY.to_owned(),
            lifetime: None,
            frame_locked: false,
            metadata: vec![KeyValuePair {
                key: "lines".to_owned(),
                value: lines.len().to_string(),
            }],
            lines: vec![LinePrimitive {
                r#type: line_primitive::Type::LineList as i32,
                pose: Some(proto::identity_pose()),
                thickness: LINE_THICKNESS_PX,
                scale_invariant: true,
                points,
                color: Some(LINE_COLOR),
                colors: Vec::new(),
                indices: Vec::new(),
            }],
            ..SceneEntity::default()
        }],
    }
}

/// The transforms placing the robot at `pose` in `world` and the laser at the robot.
#[must_use]
pub fn pose_transforms(pose: Pose2, time: f64) -> Vec<FrameTransform> {
    vec![
        proto::transform_from_pose(WORLD_FRAME, ROBOT_FRAME, pose, time),
        proto::transform_from_pose(ROBOT_FRAME, LASER_FRAME, Pose2::default(), time),
    ]
}

/// The transforms of a robot at `pose` in `world` whose wheel odometry says `odometry`
/// (REP 105): `world -> odom` (so that the chain places the robot at `pose`), `odom ->
/// base_link` (the odometry) and the laser at the robot.
#[must_use]
pub fn odometry_transforms(pose: Pose2, odometry: Pose2, time: f64) -> Vec<FrameTransform> {
    // The same pose and odometry place the odometry frame at the world's origin exactly, so
    // that reading the chain back gives the pose bit for bit.
    let world_from_odom = if pose == odometry {
        Pose2::default()
    } else {
        let w = pose.to_isometry() * odometry.to_isometry().inverse();
        let v = w.translation.vector;
        Pose2::new(v.x, v.y, w.rotation.angle())
    };
    vec![
        proto::transform_from_pose(WORLD_FRAME, ODOM_FRAME, world_from_odom, time),
        proto::transform_from_pose(ODOM_FRAME, ROBOT_FRAME, odometry, time),
        proto::transform_from_pose(ROBOT_FRAME, LASER_FRAME, Pose2::default(), time),
    ]
}

/// The messages of one scan at `time` (s), with its lines when given.
#[must_use]
pub fn scene_messages(record: &ScanRecord, lines: Option<&[Line]>, time: f64) -> SceneMessages {
    let finite = |p: Option<Pose2>| p.filter(|p| p.is_finite());
    let transforms = match (finite(record.pose), finite(record.odometry)) {
        (pose, Some(odometry)) => odometry_transforms(pose.unwrap_or(odometry), odometry, time),
        (Some(pose), None) => pose_transforms(pose, time),
        (None, None) => Vec::new(),
    };
    SceneMessages {
        time,
        scan: proto::foxglove_from_scan(&record.scan, LASER_FRAME, time),
        lines: lines.map(|l| lines_update(l, time)),
        transforms,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use laserlines::Scan;

    #[test]
    fn clock_uses_stamps_and_fills_gaps() {
        let mut c = SceneClock::new();
        assert_eq!(c.time_of(None), 0.0);
        assert_eq!(c.time_of(Some(5.0)), 5.0);
        assert!((c.time_of(Some(f64::NAN)) - 5.1).abs() < 1e-12);
        assert!((c.time_of(Some(-1.0)) - 5.2).abs() < 1e-12);
        assert!((c.time_of(Some(4.29497e9)) - 5.3).abs() < 1e-12);
        assert_eq!(c.unusable(), 3);
        assert_eq!(log_time_ns(1.5), 1_500_000_000);
    }

    #[test]
    fn messages_of_a_scan_with_pose_and_lines() {
        let mut r = ScanRecord::new(Scan::new(0.0, 0.1, 0.1, 5.0, vec![1.0; 10]).unwrap());
        r.pose = Some(Pose2::new(1.0, 2.0, 0.5));
        let m = scene_messages(&r, Some(&[]), 3.0);
        assert_eq!(m.scan.frame_id, LASER_FRAME);
        assert_eq!(m.transforms.len(), 2);
        assert_eq!(m.transforms[0].parent_frame_id, WORLD_FRAME);
        assert_eq!(m.transforms[0].child_frame_id, ROBOT_FRAME);
        let back = proto::pose_from_transform(&m.transforms[0]).unwrap();
        assert!((back.theta - 0.5).abs() < 1e-12 && back.x == 1.0 && back.y == 2.0);
        let lines = m.lines.unwrap();
        assert_eq!(lines.entities[0].id, LINES_ENTITY);
        assert!(lines.entities[0].lines[0].points.is_empty());
        r.pose = None;
        assert!(scene_messages(&r, None, 3.0).transforms.is_empty());
    }
}
