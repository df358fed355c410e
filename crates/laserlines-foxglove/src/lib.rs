//! # laserlines-foxglove
//!
//! MCAP and Foxglove for [`laserlines`], in a crate of its own so that the other crates stay
//! free of its dependencies (`mcap`, `foxglove`, `prost`, `zstd`, `lz4`; `tokio` for the
//! live server).
//!
//! - [`read`]: a streaming MCAP reader of LaserScans (ROS 2 `sensor_msgs/msg/LaserScan` in
//!   CDR, ROS 1 `sensor_msgs/LaserScan`, `foxglove.LaserScan` in protobuf or JSON), giving a
//!   [`laserlines_io::ScanReader`] like every other format.
//! - [`write`]: scans, lines and poses into an MCAP file that Foxglove plays.
//! - [`files`]: the choice between MCAP and the formats of `laserlines-io`, for input
//!   ([`open_scans`]) and output ([`LinesOutput`], [`ScanOutput`]), in one place.
//! - [`navigation`]: a navigation run (arena, poses, scans, lines, sector objects, the
//!   explorer's goal) as MCAP scenes.
//! - [`live`] (feature `live`, on by default): the same messages served on a Foxglove
//!   WebSocket, paced to replay a log.
//! - [`sectors`]: the paper's three sectors and their objects as a scene (`/sectors`), for
//!   a navigation run and for a live sensor.
//! - [`scene`]: the messages themselves; [`ros`] (from `laserlines-io`), [`proto`]: the
//!   decoders; [`message`]: one LaserScan message decoded on its own.
//!
//! Channels and frames (REP 103 frames, SI units):
//!
//! | topic | schema | frame |
//! |---|---|---|
//! | [`SCAN_TOPIC`] `/scan` | `foxglove.LaserScan` | [`LASER_FRAME`] `laser` |
//! | [`LINES_TOPIC`] `/lines` | `foxglove.SceneUpdate` (entity `lines`, one `LINE_LIST`) | `laser` |
//! | [`TF_TOPIC`] `/tf` | `foxglove.FrameTransform` | [`WORLD_FRAME`] `world` -> [`ROBOT_FRAME`] `base_link` -> `laser`; with odometry `world` -> [`ODOM_FRAME`] `odom` -> `base_link` (REP 105) |
//!
//! ```
//! use laserlines::Scan;
//! use laserlines_foxglove::{read, write::McapSceneWriter};
//! use laserlines_io::{Pose2, ScanRecord};
//!
//! let mut record = ScanRecord::new(Scan::new(-0.5, 0.25, 0.1, 8.0, vec![1.0, 2.0, 9.0, 1.5, 1.0])?);
//! record.scan.stamp = Some(12.5);
//! record.pose = Some(Pose2::new(1.0, -2.0, 0.3));
//! let mut writer = McapSceneWriter::new(std::io::Cursor::new(Vec::new()), "memory")?;
//! writer.write_scan(&record)?;
//! let bytes = writer.finish()?.into_inner();
//!
//! let mut reader = read::from_reader("memory", std::io::Cursor::new(bytes), &Default::default())?;
//! let back = reader.next().expect("one scan")?;
//! assert_eq!(back.scan.stamp, Some(12.5));
//! assert_eq!(back.scan.ranges[1], 2.0);
//! assert!(back.scan.ranges[2].is_nan()); // 9 m is beyond range_max: no return
//! assert!((back.pose.expect("a pose").theta - 0.3).abs() < 1e-12);
//! assert!(reader.next().is_none());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod files;
pub mod grid;
pub mod json;
#[cfg(feature = "live")]
pub mod live;
pub mod message;
pub mod navigation;
pub mod proto;
pub mod read;
pub mod scene;
pub mod sectors;
mod shapes;
pub mod write;

pub use files::{LinesOutput, ScanOutput, open_scans};
/// The Foxglove message types and their encoding, for [`McapSceneWriter::write_message`].
pub use foxglove::{Encode, messages};
/// The ROS LaserScan decoders, shared with the ROS bag reader.
pub use laserlines_io::ros;
pub use laserlines_io::{DecodeError, LaserScanMsg};
pub use navigation::{NavFrame, NavRecorder};
pub use read::{McapReadOptions, McapScanSource, ScanEncoding};
pub use write::McapSceneWriter;

/// Topic of the scans (`foxglove.LaserScan`).
pub const SCAN_TOPIC: &str = "/scan";
/// Topic of the extracted lines (`foxglove.SceneUpdate`).
pub const LINES_TOPIC: &str = "/lines";
/// Topic of the robot's pose (`foxglove.FrameTransform`).
pub const TF_TOPIC: &str = "/tf";
/// The fixed frame the robot moves in.
pub const WORLD_FRAME: &str = "world";
/// The robot's frame (REP 105 `base_link`).
pub const ROBOT_FRAME: &str = "base_link";
/// The odometry frame (REP 105 `odom`): `odom -> base_link` is the wheel odometry.
pub const ODOM_FRAME: &str = "odom";
/// The laser's frame, in which scans and lines are given.
pub const LASER_FRAME: &str = "laser";
/// Id of the scene entity holding the lines.
pub const LINES_ENTITY: &str = "lines";
