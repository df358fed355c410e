//! # laserlines
//!
//! Line segments from 2D laser range scans, fast and robust. The core crate: plain types and
//! algorithms, no I/O.
//!
//! Algorithms, by family:
//! - **Hough-based segmentation + split**: [`HoughSplit`], the paper's g-weighted Hough
//!   transform, data segments with removal of sparse and cluttered points, and recursive
//!   split (`Linseg`).
//!
//! Every extractor implements [`LineExtractor`] and returns [`Line`]s fitted by the same
//! least-squares fit ([`fit`]), in polar form with covariance.
//!
//! Units are SI (metres, radians); frames follow REP 103 (x forward, y left, angles
//! counter-clockwise).

pub mod extractor;
pub mod fit;
pub mod hough_split;
pub mod line;
pub mod math;
pub mod scan;

pub use extractor::LineExtractor;
pub use fit::{FitSums, PolarFit, fit_points};
pub use hough_split::{HoughSplit, HoughSplitParams, Weight};
pub use line::Line;
pub use scan::{RangeWindow, Scan, ScanError, ScanPoint};
