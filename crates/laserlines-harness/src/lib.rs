//! # laserlines-harness
//!
//! The closed loop of the paper's robot in simulation: the simulator of `laserlines-sim`
//! senses, the extractor of `laserlines` extracts, the explorer of `laserlines-nav` decides,
//! the simulated drive acts, and the run is scored against the simulator's ground truth. The
//! robot side (`laserlines-nav`) never sees the simulator: it gets what a real robot gets,
//! each scan, its lines and the wheel odometry.
//!
//! - [`run()`]: one run, returning [`Metrics`] and what the pictures need ([`RunRecord`]);
//!   [`RunObserver`] sees every scan as it happens (the MCAP recording of `laserlines
//!   simulate --mcap`, a progress bar);
//! - [`coverage`]: the ground-truth coverage grid (0.1 m cells, reachable area by flood
//!   fill);
//! - [`arenas`]: the two bundled RoboCup Rescue arenas.
//!
//! Units are SI (metres, radians, seconds); frames follow REP 103 and are named in variables
//! (`world_from_robot`, `odom_from_robot`, `map_from_robot`).
//!
//! ```
//! use laserlines_harness::{RunConfig, run};
//! use laserlines_sim::maze::{MazeParams, generate};
//! let maze = generate(&MazeParams { cols: 4, rows: 4, ..MazeParams::default() }, 1);
//! let config = RunConfig { duration_s: 60.0, seed: 1, ..RunConfig::default() };
//! let record = run(&maze.world, maze.start, &config).unwrap();
//! assert_eq!(record.metrics.collisions, 0);
//! assert!(record.metrics.coverage > 0.3);
//! ```

pub mod arenas;
pub mod coverage;
pub mod run;

pub use coverage::{COVERAGE_CELL, CoverageGrid, CoverageRegion};
pub use run::{
    Metrics, RunConfig, RunError, RunObserver, RunRecord, ScanFrame, Snapshot, StopReason, run,
    run_observed, run_with_progress,
};
