//! # laserlines
//!
//! Line segments from 2D laser range scans, fast and robust. The core crate: plain types and
//! algorithms, no I/O.
//!
//! Algorithms, by family:
//! - **Hough-based segmentation + split**: [`HoughSplit`], the paper's g-weighted Hough
//!   transform, data segments with removal of sparse and cluttered points, and recursive
//!   split (`Linseg`).
//! - **Classic extractors compared by Nguyen et al.** ([`extractors`], selectable by name):
//!   iterative Hough on the full accumulator ([`hough`]), split-and-merge, iterative end-point
//!   fit, incremental line tracking, line regression, RANSAC and EM.
//!
//! Every extractor implements [`LineExtractor`] and returns [`Line`]s fitted by the same
//! least-squares fit ([`fit`]), in polar form with covariance.
//!
//! For the robot side: [`robot`] describes a robot (footprint, drive limits, velocity
//! command and arc motion, the laser's mount) and [`geometry`] holds the plane's primitives
//! (clipping, ray hits, distances). Every parameter check reports a [`ParamsError`].
//!
//! Units are SI (metres, radians); frames follow REP 103 (x forward, y left, angles
//! counter-clockwise).

pub mod bearings;
pub mod extractor;
pub mod extractors;
pub mod fit;
pub mod geometry;
pub mod hough;
pub mod hough_split;
pub mod line;
pub mod math;
pub mod noise;
pub mod params;
pub mod registry;
pub mod robot;
pub mod scan;

pub use extractor::LineExtractor;
pub use fit::{FitSums, PolarFit, fit_points};
pub use hough_split::{HoughSplit, HoughSplitParams, Weight};
pub use line::Line;
pub use noise::{NoiseEstimator, NoiseModel, RangeNoise};
pub use params::ParamsError;
pub use scan::{RangeWindow, Scan, ScanError, ScanPoint, ScanView};

/// The README's Rust examples, compiled and run as doc tests.
#[doc = include_str!("../../../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
