//! A navigation run as an MCAP file for Foxglove (`laserlines simulate --mcap FILE`): the
//! arena, the robot's true and estimated poses, each scan with its lines, the sector objects
//! and the explorer's goal. It takes plain data and the explorer's [`Decision`], so that it
//! records a real robot's run as well as a simulated one.
//!
//! | topic | schema | frame | content |
//! |---|---|---|---|
//! | `/arena` | `foxglove.SceneUpdate` | `world` | the walls (`LINE_LIST`) and round obstacles (cylinders), once at t = 0 |
//! | `/tf` | `foxglove.FrameTransform` | `world` -> `odom` -> `base_link` | the robot's true pose as the wheel odometry and the odometry frame's place in the world (REP 105), every scan; without odometry `world` -> `base_link` |
//! | `/tf` | `foxglove.FrameTransform` | `base_link` -> `laser` | the laser's mount, every scan |
//! | `/tf` | `foxglove.FrameTransform` | `world` -> `base_link_estimate` | the robot's own pose estimate (odometry corrected by scan matching), every scan |
//! | `/scan` | `foxglove.LaserScan` | `laser` | the scan |
//! | `/lines` | `foxglove.SceneUpdate` | `laser` | its lines |
//! | `/sectors` | `foxglove.SceneUpdate` | `base_link` | the footprint, the sector bounds and the selected object of each sector (left blue, front red, right green) with its distance, width and angle as text |
//! | `/explorer` | `foxglove.SceneUpdate` | `world` | the frontier goal, when the explorer has one |
//!
//! Times are simulated seconds from 0.

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use foxglove::messages::{
    CylinderPrimitive, KeyValuePair, SceneEntity, SceneUpdate, SpherePrimitive, Vector3,
};
use laserlines::math::{Isometry2, Point2};
use laserlines::robot::Footprint;
use laserlines::{Line, Scan};
use laserlines_io::{Pose2, WriteError};
use laserlines_nav::Decision;

use crate::proto::{timestamp, transform_from_pose};
use crate::sectors::sectors_update;
use crate::shapes::{color, line_list, point3, pose_at};
use crate::write::McapSceneWriter;
use crate::{LASER_FRAME, ODOM_FRAME, ROBOT_FRAME, WORLD_FRAME};

/// Topic of the arena walls.
pub const ARENA_TOPIC: &str = "/arena";
/// Topic of the footprint, sectors and selected objects (see [`crate::sectors`]).
pub use crate::sectors::SECTORS_TOPIC;
/// Topic of the explorer's frontier goal.
pub const EXPLORER_TOPIC: &str = "/explorer";
/// Frame of the robot's own pose estimate.
pub const ESTIMATE_FRAME: &str = "base_link_estimate";

/// What one scan of a run shows.
#[derive(Debug, Clone, Copy)]
pub struct NavFrame<'a> {
    /// Time of the scan, s.
    pub time_s: f64,
    /// The robot's pose (the true one in simulation).
    pub world_from_robot: Isometry2,
    /// The wheel odometry's pose in the odometry frame, when the robot has odometry: recorded
    /// as `odom` -> `base_link` under `world` -> `odom`, so that `laserlines map` reads the
    /// run back with its odometry.
    pub odom_from_robot: Option<Isometry2>,
    /// The robot's own estimate of its pose, placed in the world by the start pose.
    pub estimated_world_from_robot: Isometry2,
    /// Where the laser sits on the robot.
    pub robot_from_laser: Isometry2,
    /// The scan, laser frame.
    pub scan: &'a Scan,
    /// Its lines, laser frame.
    pub lines: &'a [Line],
    /// The explorer's decision on this scan.
    pub decision: &'a Decision,
    /// Coverage so far, 0..1, when known (ground truth).
    pub coverage: Option<f64>,
}

/// Records a run into an MCAP file; the first write error is kept and ends the recording.
pub struct NavRecorder {
    writer: McapSceneWriter<BufWriter<File>>,
    footprint: Footprint,
    world_from_map: Isometry2,
    error: Option<WriteError>,
}

fn pose2(iso: &Isometry2) -> Pose2 {
    Pose2::new(
        iso.translation.vector.x,
        iso.translation.vector.y,
        iso.rotation.angle(),
    )
}

/// The arena (walls by their end points, discs by centre and radius) as one scene update in
/// the world frame.
fn arena_update(walls: &[(Point2, Point2)], discs: &[(Point2, f64)]) -> SceneUpdate {
    let wall_points = walls
        .iter()
        .flat_map(|&(a, b)| [point3(a), point3(b)])
        .collect();
    let cylinders = discs
        .iter()
        .map(|&(centre, radius)| CylinderPrimitive {
            pose: Some(pose_at(centre.x, centre.y, 0.0)),
            size: Some(Vector3 {
                x: 2.0 * radius,
                y: 2.0 * radius,
                z: 0.3,
            }),
            bottom_scale: 1.0,
            top_scale: 1.0,
            color: Some(color(0.4, 0.4, 0.4, 1.0)),
        })
        .collect();
    SceneUpdate {
        deletions: Vec::new(),
        entities: vec![SceneEntity {
            timestamp: Some(timestamp(0.0)),
            frame_id: WORLD_FRAME.to_owned(),
            id: "arena".to_owned(),
            metadata: vec![
                KeyValuePair {
                    key: "walls".to_owned(),
                    value: walls.len().to_string(),
                },
                KeyValuePair {
                    key: "discs".to_owned(),
                    value: discs.len().to_string(),
                },
            ],
            lines: vec![line_list(wall_points, color(0.2, 0.2, 0.2, 1.0), 2.0)],
            cylinders,
            ..SceneEntity::default()
        }],
    }
}

impl NavRecorder {
    /// Creates `path` and writes the arena: walls by their end points, discs by centre and
    /// radius (world frame). `world_from_map` places the explorer's map frame (its goals).
    ///
    /// # Errors
    /// When the file cannot be created or written.
    pub fn create(
        path: &Path,
        walls: &[(Point2, Point2)],
        discs: &[(Point2, f64)],
        footprint: Footprint,
        world_from_map: Isometry2,
    ) -> Result<Self, WriteError> {
        let mut writer = McapSceneWriter::create(path)?;
        writer.write_message(ARENA_TOPIC, &arena_update(walls, discs), 0.0)?;
        Ok(Self {
            writer,
            footprint,
            world_from_map,
            error: None,
        })
    }

    /// Writes the explorer's fence (its corners in order, world frame) to the arena topic as
    /// the entity `fence`: a closed purple line.
    ///
    /// # Errors
    /// When the file cannot be written.
    pub fn write_fence(&mut self, corners: &[Point2]) -> Result<(), WriteError> {
        let points = corners
            .iter()
            .zip(corners.iter().cycle().skip(1))
            .flat_map(|(&a, &b)| [point3(a), point3(b)])
            .collect();
        let update = SceneUpdate {
            deletions: Vec::new(),
            entities: vec![SceneEntity {
                timestamp: Some(timestamp(0.0)),
                frame_id: WORLD_FRAME.to_owned(),
                id: "fence".to_owned(),
                lines: vec![line_list(points, color(0.56, 0.27, 0.68, 1.0), 2.0)],
                ..SceneEntity::default()
            }],
        };
        self.writer.write_message(ARENA_TOPIC, &update, 0.0)
    }

    /// Writes the summary; returns the first error of the recording, if any, and the number
    /// of scans written.
    ///
    /// # Errors
    /// The first write error.
    pub fn finish(self) -> Result<u64, WriteError> {
        if let Some(e) = self.error {
            return Err(e);
        }
        let scans = self.writer.scans();
        self.writer.finish()?;
        Ok(scans)
    }

    fn sectors_update(&self, frame: &NavFrame<'_>) -> SceneUpdate {
        let mut update = sectors_update(
            &frame.decision.objects,
            ROBOT_FRAME,
            Some(&self.footprint),
            frame.time_s,
        );
        let metadata = &mut update.entities[0].metadata;
        metadata.push(KeyValuePair {
            key: "mode".to_owned(),
            value: format!("{:?}", frame.decision.mode),
        });
        metadata.push(KeyValuePair {
            key: "side".to_owned(),
            value: format!("{:?}", frame.decision.side),
        });
        update
    }

    fn explorer_update(&self, frame: &NavFrame<'_>) -> SceneUpdate {
        let spheres = frame
            .decision
            .goal
            .map(|g| {
                let w = self.world_from_map * g;
                SpherePrimitive {
                    pose: Some(pose_at(w.x, w.y, 0.0)),
                    size: Some(Vector3 {
                        x: 0.2,
                        y: 0.2,
                        z: 0.2,
                    }),
                    color: Some(color(0.58, 0.4, 0.74, 0.9)),
                }
            })
            .into_iter()
            .collect();
        SceneUpdate {
            deletions: Vec::new(),
            entities: vec![SceneEntity {
                timestamp: Some(timestamp(frame.time_s)),
                frame_id: WORLD_FRAME.to_owned(),
                id: "goal".to_owned(),
                metadata: frame
                    .coverage
                    .map(|c| KeyValuePair {
                        key: "coverage".to_owned(),
                        value: format!("{c:.3}"),
                    })
                    .into_iter()
                    .collect(),
                spheres,
                ..SceneEntity::default()
            }],
        }
    }

    fn write_frame(&mut self, frame: &NavFrame<'_>) -> Result<(), WriteError> {
        let t = frame.time_s;
        let robot = match frame.odom_from_robot {
            Some(odom) => vec![
                transform_from_pose(
                    WORLD_FRAME,
                    ODOM_FRAME,
                    pose2(&(frame.world_from_robot * odom.inverse())),
                    t,
                ),
                transform_from_pose(ODOM_FRAME, ROBOT_FRAME, pose2(&odom), t),
            ],
            None => vec![transform_from_pose(
                WORLD_FRAME,
                ROBOT_FRAME,
                pose2(&frame.world_from_robot),
                t,
            )],
        };
        for tf in robot.into_iter().chain([
            transform_from_pose(ROBOT_FRAME, LASER_FRAME, pose2(&frame.robot_from_laser), t),
            transform_from_pose(
                WORLD_FRAME,
                ESTIMATE_FRAME,
                pose2(&frame.estimated_world_from_robot),
                t,
            ),
        ]) {
            self.writer.write_transform(&tf)?;
        }
        self.writer
            .write_scan_lines_at(frame.scan, frame.lines, t)?;
        let sectors = self.sectors_update(frame);
        self.writer.write_message(SECTORS_TOPIC, &sectors, t)?;
        let explorer = self.explorer_update(frame);
        self.writer.write_message(EXPLORER_TOPIC, &explorer, t)
    }
}

impl NavRecorder {
    /// Records one scan; after a write error nothing more is written (see
    /// [`NavRecorder::finish`]).
    pub fn record(&mut self, frame: &NavFrame<'_>) {
        if self.error.is_none()
            && let Err(e) = self.write_frame(frame)
        {
            self.error = Some(e);
        }
    }
}
