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
//! - **Tracking**: the [`Tracker`], a pose at every scan that never moves afterwards, by
//!   matching each scan onto one growing [`SurfaceMap`] of everything seen (for a robot that
//!   plans on its own map as it drives).
//! - **Maps**: the [`occupancy`] grid and the [`linemap`] (lines of all scans in the map
//!   frame, merged where they are one wall).
//! - **Evaluation**: [`eval`], the relations metric of the Freiburg SLAM benchmark.
//!
//! Units are SI (metres, radians); frames follow REP 103. A pose `a_from_b` maps points of
//! frame `b` into frame `a`.
//!
//! ## Online use
//!
//! A robot gives the [`Mapper`] each scan as it comes, with the lines extracted from it and
//! the wheel odometry's pose at the scan's time (or `None` without odometry), and gets the
//! scan's pose in the map frame back at once; the map frame is the first scan's. The mapper
//! matches the scan onto its submaps, searches for loop closures every few scans and
//! optimises its pose graph when it found some, so a pose it returned earlier may move
//! later: [`Mapper::poses`] holds the current estimate of every scan, and
//! [`Mapper::occupancy_grid`] and [`Mapper::line_map`] build the maps from them at any
//! time. [`MapperParams::robot_from_sensor`] tells where the laser sits on the robot
//! (odometry is the robot's; scans and poses are the laser's; [`Mapper::robot_pose`] gives
//! the robot's).
//!
//! ```
//! use laserlines::{HoughSplit, HoughSplitParams, LineExtractor, Scan};
//! use laserlines_slam::{Mapper, MapperParams, Se2};
//!
//! /// A 6 m x 4 m room (walls at x = +-3 m, y = +-2 m) seen from `pose`: 361 beams over 180 deg.
//! fn scan_in_room(pose: Se2) -> Scan {
//!     let inc = 0.5_f64.to_radians();
//!     let wall = |p: f64, d: f64, at: f64| if d.abs() < 1e-12 { f64::INFINITY } else { (at.copysign(d) - p) / d };
//!     let ranges = (0..361)
//!         .map(|i| {
//!             let (s, c) = (pose.theta - std::f64::consts::FRAC_PI_2 + f64::from(i) * inc).sin_cos();
//!             wall(pose.x, c, 3.0).min(wall(pose.y, s, 2.0))
//!         })
//!         .collect();
//!     Scan::new(-std::f64::consts::FRAC_PI_2, inc, 0.1, 30.0, ranges).unwrap()
//! }
//!
//! let mut mapper = Mapper::new(MapperParams::default());
//! let mut extractor = HoughSplit::new(HoughSplitParams::mapping())?;
//! let mut lines = Vec::new();
//! let truth: Vec<Se2> = (0..20).map(|k| Se2::new(-1.0 + 0.1 * f64::from(k), 0.2, 0.05 * f64::from(k))).collect();
//! for t in &truth {
//!     // Wheel odometry that overestimates distance by 5 % and turns by 10 % too little.
//!     let odometry = Se2::new(1.05 * t.x, t.y, 0.9 * t.theta);
//!     let scan = scan_in_room(*t);
//!     extractor.extract_into(&scan, &mut lines);
//!     let update = mapper.add_scan(&scan, &lines, Some(odometry))?;
//!     // update.pose: where the laser is now, in the map frame.
//!     let expected = truth[0].between(t);
//!     assert!(update.pose.distance(&expected) < 0.01, "{update:?}");
//! }
//! mapper.optimize()?;
//! let grid = mapper.occupancy_grid(&Default::default())?;
//! // The wall x = 3 m, 4 m ahead of the first pose: occupied.
//! let cell = |x: f64, y: f64| (((x - grid.origin.x) / grid.resolution) as usize, ((y - grid.origin.y) / grid.resolution) as usize);
//! let (i, j) = cell(4.0 + 0.01, 0.5);
//! assert_eq!(grid.cell(i, j), laserlines_slam::occupancy::Cell::Occupied);
//! let (i, j) = cell(3.0, 0.5);
//! assert_eq!(grid.cell(i, j), laserlines_slam::occupancy::Cell::Free);
//! let walls = mapper.line_map(&Default::default());
//! // The same wall in the line map: 4 m from the map origin along +x; and the side walls.
//! let has = |r: f64, alpha: f64| walls.iter().any(|w| (w.r - r).abs() < 0.02 && (w.alpha - alpha).abs() < 0.01);
//! assert!(has(4.0, 0.0) && has(1.8, std::f64::consts::FRAC_PI_2) && has(2.2, -std::f64::consts::FRAC_PI_2));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

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
pub mod surface_map;
pub mod tracker;

pub use eval::{Relation, RelationsScore, score_relations};
pub use graph::{Edge, PoseGraph, RobustKernel};
pub use icp::{IcpError, IcpParams, IcpResult};
pub use linemap::{LineMapParams, MapLine};
pub use mapper::{Mapper, MapperError, MapperStats, ScanNode, ScanUpdate};
pub use occupancy::{OccupancyGrid, OccupancyParams};
pub use params::{LoopParams, MapperParams};
pub use se2::Se2;
pub use surface_map::SurfaceMap;
pub use tracker::{TrackUpdate, Tracker, TrackerError, TrackerParams};
