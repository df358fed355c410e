//! # laserlines-nav
//!
//! Navigation as on the NAJI V rescue robot (section III of the paper): the lines extracted
//! from each scan describe the robot's surroundings in three sectors, and a wall-following
//! explorer drives through a maze-like rescue arena on them. It depends on the core crate
//! and the mapping crate `laserlines-slam` alone (both without I/O): it reads what a real
//! robot has (each scan, its lines, the wheel odometry) and describes the robot with
//! [`laserlines::robot::RobotDescription`]. The closed loop in the simulator, scored
//! against ground truth, is `laserlines-harness`.
//!
//! - [`sectors`]: the three sectors (left 70 deg, front 100 deg, right 70 deg) and the
//!   "biggest and nearest" object in each, with its distance, width and angle;
//! - [`explorer`]: the wall-following explorer with loop detection, frontier travel and a
//!   safety layer; it reads only the scan, the extracted lines and the odometry;
//! - [`map`]: the robot's own map (free / occupied / unknown), its scans placed by the scan
//!   matching of `laserlines-slam` ([`laserlines_slam::Tracker`]), which corrects the
//!   odometry;
//! - [`planner`]: the nearest frontier on that map and the path there;
//! - [`raster`]: scan-line filling of a scan's fan, shared by the map and the ground-truth
//!   coverage of `laserlines-harness`.
//!
//! Units are SI (metres, radians, seconds); frames follow REP 103 (x forward, y left, angles
//! counter-clockwise) and are named in variables (`world_from_robot`, `odom_from_robot`,
//! `map_from_robot`).
//!
//! ```
//! use laserlines::math::{Isometry2, Matrix2, Point2};
//! use laserlines::Line;
//! use laserlines_nav::{Sector, SectorParams, select_objects};
//! // A wall 1 m to the left of the laser, seen from x = -1 m to 1 m.
//! let wall = Line {
//!     start: Point2::new(-1.0, 1.0), end: Point2::new(1.0, 1.0), r: 1.0,
//!     alpha: std::f64::consts::FRAC_PI_2, first: 0, last: 10, points: 11, rms: 0.0,
//!     covariance: Matrix2::zeros(),
//! };
//! let objects = select_objects(&[wall], &Isometry2::identity(), &SectorParams::default());
//! assert!((objects.get(Sector::Left).unwrap().distance_m - 1.0).abs() < 1e-12);
//! ```

pub mod explorer;
pub mod fence;
pub mod map;
pub mod planner;
pub mod raster;
pub mod sectors;

pub use explorer::{
    Decision, Explorer, ExplorerParams, FollowParams, LoopParams, MapParams, MatchParams, Mode,
    SafetyParams, TravelParams, WallSide,
};
pub use fence::Fence;
pub use map::{CellState, RobotMap};
pub use planner::{Plan, Planner, PlannerParams};
pub use sectors::{Sector, SectorObject, SectorObjects, SectorParams, select_objects};
