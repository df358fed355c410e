//! # laserlines-slam
//!
//! Mapping from 2D laser scans and the lines extracted from them, on the robot side: no
//! I/O, only the core crate, `nalgebra` and `faer`'s sparse Cholesky.
//!
//! Algorithms, by family:
//! - **Geometry**: [`Se2`], rigid motions of the plane.
//! - **Scan matching**: [`icp`], point-to-line ICP seeded by a guess, with a covariance and
//!   a stated convergence basin; [`correlative`], branch-and-bound correlative matching
//!   on a likelihood grid.
//! - **Feature matching**: [`lines`], line-to-line matching on the extractor's lines and
//!   their covariances.
//! - **Mapping**: [`submap`]s of consecutive scans, [`loops`] (loop closure: correlative
//!   search verified by ICP), the SE(2) pose [`graph`] with robust kernels, and the online
//!   [`Mapper`] that ties them together.
//! - **Maps**: the [`occupancy`] grid and the [`linemap`] (lines of all scans in the map
//!   frame, merged where they are one wall).
//! - **Evaluation**: [`eval`], the relations metric of the Freiburg SLAM benchmark.
//!
//! Units are SI (metres, radians); frames follow REP 103. A pose `a_from_b` maps points of
//! frame `b` into frame `a`.

pub mod cloud;
pub mod correlative;
pub mod eval;
pub mod graph;
pub mod icp;
pub mod linemap;
pub mod lines;
pub mod loops;
pub mod mapper;
pub mod occupancy;
pub mod params;
pub mod se2;
pub mod submap;

pub use eval::{Relation, RelationsScore, score_relations};
pub use graph::{Edge, PoseGraph, RobustKernel};
pub use icp::{IcpError, IcpParams, IcpResult};
pub use linemap::{LineMapParams, MapLine};
pub use mapper::{Mapper, MapperStats, ScanNode, ScanUpdate};
pub use occupancy::{OccupancyGrid, OccupancyParams};
pub use params::{LoopParams, MapperParams};
pub use se2::Se2;
