//! The classic line extractors that Nguyen et al. (IROS 2005) compared, each behind
//! [`LineExtractor`], so that the command line and the benchmarks swap them by name.
//!
//! - [`IterativeHough`] (`iterative-hough`): full Hough accumulator, take the peak, fit its
//!   inliers, remove them, rebuild, repeat (the baseline the paper quotes).
//! - [`SplitAndMerge`] (`split-and-merge`): breakpoint clusters, recursive split on the
//!   least-squares line, merge of collinear neighbours.
//! - [`Iepf`] (`iepf`): iterative end-point fit (split on the chord) on breakpoint clusters, the
//!   paper's `Linseg` without its Hough segmentation.
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
//! [`crate::Scan::range_window`] of their `range_limits`), and end with the same step: each
//! emitted run of consecutive beams is fitted by [`crate::FitSums::fit`] and turned into a
//! [`crate::Line`] by [`crate::Line::from_fit`], then filtered by the same minimum number of points and
//! minimum length. Before that fit, where two runs meet with no gap, the few points at the
//! junction go to the side whose least-squares line explains them better. Differences between
//! extractors therefore come from the algorithms, not from the fitting. Lines come out ordered
//! by first beam, with disjoint beam ranges.
//!
//! Random extractors take a `seed` in their parameters and reseed for every scan: the same
//! scan always gives the same lines.
//!
//! Distance thresholds grow with range, as the noise of the sensor does (the URG-04LX is
//! accurate to +-10 mm up to 1 m and +-1 % beyond): each is `base + per_metre * range`, with
//! the range of the point being tested. The breakpoint detector of Borges and Aldon, used by
//! all of them to cut clusters and runs, grows with range by construction.
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

mod common;
mod em;
mod iepf;
mod incremental;
mod iterative_hough;
mod line_regression;
mod ransac;
mod split_and_merge;

pub use em::{Em, EmParams};
pub use iepf::{Iepf, IepfParams};
pub use incremental::{Incremental, IncrementalParams};
pub use iterative_hough::{IterativeHough, IterativeHoughParams};
pub use line_regression::{LineRegression, LineRegressionParams};
pub use ransac::{Ransac, RansacParams};
pub use split_and_merge::{SplitAndMerge, SplitAndMergeParams};

use crate::extractor::LineExtractor;
use crate::hough_split::{HoughSplit, HoughSplitParams};

/// Errors in the parameters of the extractors (the crate's one [`crate::ParamsError`]).
pub use crate::params::ParamsError;

/// The names of every extractor, as [`LineExtractor::name`] returns them and [`by_name`]
/// accepts them; the paper's algorithm first.
pub const ALGORITHMS: &[&str] = &[
    "hough-split",
    "iterative-hough",
    "split-and-merge",
    "iepf",
    "incremental",
    "line-regression",
    "ransac",
    "em",
];

/// The extractor called `name` (one of [`ALGORITHMS`]) with its default parameters, or `None`
/// for an unknown name.
#[must_use]
pub fn by_name(name: &str) -> Option<Box<dyn LineExtractor + Send>> {
    Some(match name {
        "hough-split" => Box::new(HoughSplit::new(HoughSplitParams::default()).ok()?),
        "iterative-hough" => Box::new(IterativeHough::new(IterativeHoughParams::default()).ok()?),
        "split-and-merge" => Box::new(SplitAndMerge::new(SplitAndMergeParams::default()).ok()?),
        "iepf" => Box::new(Iepf::new(IepfParams::default()).ok()?),
        "incremental" => Box::new(Incremental::new(IncrementalParams::default()).ok()?),
        "line-regression" => Box::new(LineRegression::new(LineRegressionParams::default()).ok()?),
        "ransac" => Box::new(Ransac::new(RansacParams::default()).ok()?),
        "em" => Box::new(Em::new(EmParams::default()).ok()?),
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_builds_and_reports_itself() {
        for name in ALGORITHMS {
            let e = by_name(name).unwrap();
            assert_eq!(e.name(), *name);
        }
        assert!(by_name("no-such-algorithm").is_none());
    }
}
