//! # laserlines-sim
//!
//! The scene simulator of laserlines: 2D worlds of walls and round obstacles, exact ray
//! casting, a laser model (the Hokuyo URG-04LX of the paper by default), and for every
//! simulated scan its ground truth: which beam hit which wall, and every visible wall piece
//! with its polar line `(r, alpha)` and end points in the laser frame. The line extractors'
//! round-trip tests and the evaluation of `laserlines bench` stand on it.
//!
//! - [`World`], [`Wall`], [`Disc`], [`World::cast`]: the world and exact ray casting;
//! - [`LaserModel`], [`Noise`]: beams, range limits, noise, mixed pixels, dropouts,
//!   max-range returns, rounding;
//! - [`simulate`] → [`SimScan`] = a [`laserlines::Scan`] + its [`Truth`] ([`VisiblePiece`]s);
//! - [`scenes`]: seeded scene generators, the suites for comparing extractors, and the
//!   standard bench scan;
//! - [`Rng`]: the crate's own seeded generator (xoshiro256** seeded by splitmix64), so that
//!   a seed gives the same scan everywhere.
//!
//! Units are SI (metres, radians); frames follow REP 103 (x forward, y left, angles
//! counter-clockwise). Nothing here panics on any input; degenerate geometry is ignored or
//! reported, never turned into NaN hit points.
//!
//! ## The noise model
//!
//! The URG-04LX data sheet gives its accuracy as +-10 mm up to 1 m and +-1 % of the range
//! beyond. [`Noise::Urg04lx`] reads that band as two standard deviations of gaussian noise:
//! sigma = 5 mm up to 1 m and 0.5 % of the range beyond, so that about 95 % of returns fall
//! inside the specified band. Ranges are then rounded to the sensor's 1 mm resolution.
//!
//! ## Example
//!
//! ```
//! use laserlines_sim::{LaserModel, Rng, World, simulate};
//! use laserlines::math::{Isometry2, Point2, Vector2};
//!
//! // A 4 m square room seen from its centre.
//! let mut world = World::new();
//! world.add_polygon(&[
//!     Point2::new(-2.0, -2.0),
//!     Point2::new(2.0, -2.0),
//!     Point2::new(2.0, 2.0),
//!     Point2::new(-2.0, 2.0),
//! ]);
//! let sim = simulate(&world, Isometry2::identity(), &LaserModel::urg04lx(), &mut Rng::new(1));
//! assert_eq!(sim.scan.ranges.len(), 682);
//! // The wall ahead (x = 2) is a visible piece 2 m away with its normal straight ahead.
//! let ahead = sim.truth.pieces.iter().find(|p| p.wall == 1).unwrap();
//! assert!((ahead.r - 2.0).abs() < 1e-9 && ahead.alpha.abs() < 1e-9);
//! ```

pub mod arena;
pub mod cells;
pub mod index;
pub mod laser;
pub mod maze;
mod noise;
pub mod rng;
pub mod robot;
pub mod scenes;
pub mod simulation;
mod sweep;
pub mod world;

pub use laser::{LaserModel, MAX_BEAMS, ModelError, Noise, URG04LX_INCREMENT};
pub use rng::Rng;
pub use scenes::{SUITES, Scene, UnknownSuite, bench_scan, bench_scene, suite};
pub use simulation::{
    MIN_PIECE_BEAMS, MIN_PIECE_LENGTH, MIXED_PIXEL_MIN_JUMP, SimScan, Truth, VisiblePiece, simulate,
};
pub use world::{Disc, Hit, Target, Wall, World};
