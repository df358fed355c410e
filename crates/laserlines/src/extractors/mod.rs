//! The classic line extractors that Nguyen et al. (IROS 2005) compared, each behind
//! [`LineExtractor`](crate::LineExtractor), so that the command line and the benchmarks swap them by name.
//!
//! - [`IterativeHough`] (`iterative-hough`): full Hough accumulator, take the peak, fit its
//!   inliers, remove them, rebuild, repeat (the baseline the paper quotes).
//! - [`SplitMerge`] with [`SplitLine::LeastSquares`] (`split-and-merge`): breakpoint
//!   clusters, recursive split on the least-squares line, merge of collinear neighbours.
//! - [`SplitMerge`] with [`SplitLine::Chord`] (`iepf`): iterative end-point fit (split on the
//!   chord) on breakpoint clusters, the paper's `Linseg` without its Hough segmentation.
//! - [`Incremental`] (`incremental`): line tracking, growing a line point by point while the
//!   fit holds.
//! - [`LineRegression`] (`line-regression`): sliding-window fits clustered in `(r, alpha)`
//!   space (Arras and Siegwart).
//! - [`Ransac`] (`ransac`): seeded random sampling with a minimum number of inliers and a
//!   consistent-run check.
//! - [`Em`] (`em`): expectation-maximisation of line hypotheses against an outlier class,
//!   seeded.
//!
//! All of them take the scan's valid points ([`crate::Scan::points_into`] within
//! [`crate::Scan::range_window`] of their `range_limits`), and end with the same step:
//! each emitted run of consecutive beams is fitted by [`crate::FitSums::fit`]
//! and turned into a [`crate::Line`] by [`crate::Line::from_fit`], then filtered by the same
//! [`LineFilter`] (minimum number of points and length). Before that fit, where two runs meet
//! with no gap, the few points at the junction go to the side whose least-squares line
//! explains them better. Differences between extractors therefore come from the algorithms,
//! not from the fitting. Lines come out ordered by first beam, with disjoint beam ranges.
//!
//! Their parameters nest what they share: [`Breakpoints`] (the adaptive breakpoint detector
//! of Borges and Aldon, which cuts clusters and runs) and [`LineFilter`]. Every extractor is
//! listed, with its defaults and tuning knobs, in [`crate::registry`].
//!
//! Random extractors take a `seed` in their parameters and reseed for every scan: the same
//! scan always gives the same lines.
//!
//! Distance thresholds grow with range, as the noise of the sensor does (the URG-04LX is
//! accurate to +-10 mm up to 1 m and +-1 % beyond): each is `base + per_metre * range`, with
//! the range of the point being tested. The breakpoint detector grows with range by
//! construction.
//!
//! ```
//! use laserlines::extractors::{self, ALGORITHMS};
//! use laserlines::Scan;
//! // A wall at x = 2 m seen by 181 beams from -45 to +45 deg.
//! let inc = 0.5_f64.to_radians();
//! let ranges = (0..181)
//!     .map(|i| 2.0 / (-45.0_f64.to_radians() + i as f64 * inc).cos())
//!     .collect();
//! let scan = Scan::new(-45.0_f64.to_radians(), inc, 0.02, 5.6, ranges).unwrap();
//! for name in ALGORITHMS {
//!     let mut extractor = extractors::by_name(name).unwrap();
//!     assert_eq!(extractor.name(), *name);
//!     let lines = extractor.extract(&scan);
//!     assert_eq!(lines.len(), 1, "{name}");
//!     assert!((lines[0].r - 2.0).abs() < 1e-6 && lines[0].alpha.abs() < 1e-6, "{name}");
//! }
//! ```

mod breakpoints;
mod em;
mod finish;
mod incremental;
mod iterative_hough;
mod line_regression;
mod merge;
mod model;
mod ransac;
mod rng;
mod runs;
mod split;
mod split_merge;
#[cfg(test)]
mod test_support;

pub use breakpoints::Breakpoints;
pub use em::{Em, EmParams};
pub use finish::LineFilter;
pub use incremental::{Incremental, IncrementalParams};
pub use iterative_hough::{IterativeHough, IterativeHoughParams};
pub use line_regression::{LineRegression, LineRegressionParams};
pub use ransac::{Ransac, RansacParams};
pub use split::SplitLine;
pub use split_merge::{SplitMerge, SplitMergeParams};

/// The names of every extractor and the extractor of a name, from [`crate::registry`].
pub use crate::registry::{ALGORITHMS, by_name};

/// Errors in the parameters of the extractors (the crate's one [`crate::ParamsError`]).
pub use crate::params::ParamsError;
