//! # laserlines-nav
//!
//! Navigation as on the NAJI V rescue robot (section III of the paper): the lines extracted
//! from each scan describe the robot's surroundings in three sectors, and a wall-following
//! explorer drives through a maze-like rescue arena on them. Everything runs in the
//! simulator of `laserlines-sim` and is scored against its ground truth.
//!
//! - [`sectors`]: the three sectors (left 70 deg, front 100 deg, right 70 deg) and the
//!   "biggest and nearest" object in each, with its distance, width and angle;
//! - [`explorer`]: the wall-following explorer with loop detection, frontier travel and a
//!   safety layer; it reads only the scan, the extracted lines and the odometry;
//! - [`map`]: the robot's own map (free / occupied / unknown, and wall lines for scan
//!   matching) and the scan matching that corrects its odometry;
//! - [`planner`]: the nearest frontier on that map and the path there;
//! - [`coverage`]: the ground-truth coverage grid (0.1 m cells, reachable area by flood fill);
//! - [`run()`]: one simulated run returning [`Metrics`] and what the pictures need.
//!
//! Units are SI (metres, radians, seconds); frames follow REP 103 (x forward, y left, angles
//! counter-clockwise) and are named in variables (`world_from_robot`, `odom_from_robot`,
//! `map_from_robot`).
//!
//! ```
//! use laserlines_nav::{RunConfig, run};
//! use laserlines_sim::maze::{MazeParams, generate};
//! let maze = generate(&MazeParams { cols: 4, rows: 4, ..MazeParams::default() }, 1);
//! let config = RunConfig { duration_s: 60.0, seed: 1, ..RunConfig::default() };
//! let record = run(&maze.world, maze.start, &config).unwrap();
//! assert_eq!(record.metrics.collisions, 0);
//! assert!(record.metrics.coverage > 0.3);
//! ```

pub mod arenas;
pub mod coverage;
pub mod explorer;
pub mod map;
pub mod planner;
mod raster;
pub mod run;
pub mod sectors;

pub use coverage::{COVERAGE_CELL, CoverageGrid};
pub use explorer::{Decision, Explorer, ExplorerParams, Mode, WallSide};
pub use map::{CellState, MatchParams, MatchPoint, RobotMap};
pub use planner::{Plan, Planner, PlannerParams};
pub use run::{
    Metrics, RunConfig, RunError, RunObserver, RunRecord, ScanFrame, Snapshot, StopReason, run,
    run_observed, run_with_progress,
};
pub use sectors::{Sector, SectorObject, SectorObjects, SectorParams, select_objects};
