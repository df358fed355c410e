//! Iterative end-point fit and split-and-merge: one engine on breakpoint clusters, in two
//! variants that differ only in the line a split measures from ([`SplitLine`]).
//!
//! 1. Cut the valid points into clusters at breakpoints (Borges and Aldon's adaptive detector,
//!    [`Breakpoints`]) and drop clusters of fewer than `min_cluster_points`.
//! 2. In each cluster, find the interior point farthest from the piece's line and split there
//!    when it lies farther than `split_distance + split_distance_per_metre * range`,
//!    recursively. The line is
//!    - [`SplitLine::Chord`], the chord between the piece's end points: the iterative
//!      end-point fit (`iepf`), the paper's `Linseg` without its Hough segmentation, so that
//!      what the Hough stage adds can be measured;
//!    - [`SplitLine::LeastSquares`], the piece's least-squares line: split-and-merge
//!      (`split-and-merge`, Pavlidis and Horowitz, as compared by Nguyen et al.).
//! 3. Optionally merge neighbouring pieces whose points all lie within the split threshold
//!    of their joint least-squares line.
//! 4. The common final step (least-squares fit, [`LineFilter`]).
//!
//! The `iepf` defaults match [`crate::HoughSplitParams`] where the two share a meaning (split
//! threshold, merge, line filters), so that the comparison isolates the segmentation.

use super::ParamsError;
use super::breakpoints::Breakpoints;
use super::finish::{LineFilter, finish};
use super::merge::merge_collinear;
use super::model::Scaled;
use super::runs::Run;
use super::split::{SplitLine, split};
use crate::extractor::LineExtractor;
use crate::line::Line;
use crate::params;
use crate::scan::{RangeWindow, ScanPoint, ScanView};

/// Parameters of [`SplitMerge`], for either variant.
///
/// The two variants have their own defaults, [`SplitMergeParams::iepf`] (also
/// [`Default`]) and [`SplitMergeParams::split_and_merge`]. Defaults marked *tuned* were
/// chosen by `laserlines bench --tune iepf` (and `--tune split-and-merge`) `--suite all --seed
/// 1 --scans 100`: a coordinate search maximising the F1 score of found walls and false lines
/// on the training suite (seed 1, 100 simulated URG-04LX scans of each of the seven scene
/// suites; see `laserlines_eval::tune`). Results are reported on the test suite, seed 2.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct SplitMergeParams {
    /// The breakpoint detector that cuts the clusters. Default 10 deg, noise 0.01 m for
    /// `iepf` and 0.02 m (tuned) for `split-and-merge`, at most 2 missing beams.
    pub breakpoints: Breakpoints,
    /// Clusters with fewer points are dropped. Default 8 (tuned). Sensible: 2..10.
    pub min_cluster_points: usize,
    /// Split threshold at zero range, m: a piece is split where the interior point farthest
    /// from its line lies farther than `split_distance + split_distance_per_metre * range`.
    /// Default 0.03 (tuned). Sensible: 0.01..0.05.
    pub split_distance: f64,
    /// Growth of the split threshold with the range of the farthest point, m per m.
    /// Default 0.01 (the URG-04LX's 1 %). Sensible: 0..0.03.
    pub split_distance_per_metre: f64,
    /// Merge neighbouring pieces whose points all lie within the split threshold of their joint
    /// least-squares line (the "merge" of split-and-merge). Default `true`.
    pub merge_collinear: bool,
    /// The final filter. Default 8 points (tuned), 0.15 m (tuned).
    pub filter: LineFilter,
    /// Extra limits on valid ranges, on top of the scan's own `range_min..range_max`.
    /// Default none.
    pub range_limits: Option<RangeWindow>,
}

impl Default for SplitMergeParams {
    fn default() -> Self {
        Self::iepf()
    }
}

impl SplitMergeParams {
    /// The defaults of the iterative end-point fit (`iepf`).
    #[must_use]
    pub fn iepf() -> Self {
        Self {
            breakpoints: Breakpoints::default(),
            min_cluster_points: 8,
            split_distance: 0.03,
            split_distance_per_metre: 0.01,
            merge_collinear: true,
            filter: LineFilter::default(),
            range_limits: None,
        }
    }

    /// The defaults of split-and-merge: those of `iepf` with a breakpoint noise of 0.02 m
    /// (tuned).
    #[must_use]
    pub fn split_and_merge() -> Self {
        Self {
            breakpoints: Breakpoints {
                noise: 0.02,
                ..Breakpoints::default()
            },
            ..Self::iepf()
        }
    }

    /// Checks every field.
    ///
    /// # Errors
    /// A [`ParamsError`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ParamsError> {
        params::range_limits(self.range_limits)?;
        self.breakpoints.validate()?;
        params::scaled(
            ("split_distance", self.split_distance),
            ("split_distance_per_metre", self.split_distance_per_metre),
        )?;
        self.filter.validate()
    }

    fn threshold(&self) -> Scaled {
        Scaled {
            base: self.split_distance,
            per_metre: self.split_distance_per_metre,
        }
    }
}

/// Breakpoint clusters, recursive split, optional merge and the common finish (see the
/// module docs), in the variant `line`. Reuse one value across scans: its working memory is
/// kept.
///
/// ```
/// use laserlines::LineExtractor;
/// use laserlines::extractors::{SplitLine, SplitMerge, SplitMergeParams};
/// let iepf = SplitMerge::new(SplitLine::Chord, SplitMergeParams::iepf()).unwrap();
/// assert_eq!(iepf.name(), "iepf");
/// let sam = SplitMerge::new(SplitLine::LeastSquares, SplitMergeParams::split_and_merge());
/// assert_eq!(sam.unwrap().name(), "split-and-merge");
/// ```
#[derive(Debug, Clone)]
pub struct SplitMerge {
    line: SplitLine,
    params: SplitMergeParams,
    points: Vec<ScanPoint>,
    clusters: Vec<Run>,
    pieces: Vec<Run>,
    runs: Vec<Run>,
    stack: Vec<(usize, usize)>,
    member: Vec<bool>,
}

impl SplitMerge {
    /// An extractor of variant `line` with validated parameters.
    ///
    /// # Errors
    /// [`ParamsError`] when a parameter is out of its domain.
    pub fn new(line: SplitLine, params: SplitMergeParams) -> Result<Self, ParamsError> {
        params.validate()?;
        Ok(Self {
            line,
            params,
            points: Vec::new(),
            clusters: Vec::new(),
            pieces: Vec::new(),
            runs: Vec::new(),
            stack: Vec::new(),
            member: Vec::new(),
        })
    }

    /// The parameters in use.
    #[must_use]
    pub fn params(&self) -> &SplitMergeParams {
        &self.params
    }

    /// The variant: the line a split measures from.
    #[must_use]
    pub fn split_line(&self) -> SplitLine {
        self.line
    }
}

impl LineExtractor for SplitMerge {
    fn name(&self) -> &'static str {
        match self.line {
            SplitLine::Chord => "iepf",
            SplitLine::LeastSquares => "split-and-merge",
        }
    }

    fn extract_view_into(&mut self, scan: ScanView<'_>, out: &mut Vec<Line>) {
        out.clear();
        let p = &self.params;
        let threshold = p.threshold();
        scan.points_into(scan.range_window(p.range_limits), &mut self.points);
        p.breakpoints
            .clusters(&self.points, p.min_cluster_points, &mut self.clusters);
        self.runs.clear();
        for &cluster in &self.clusters {
            self.pieces.clear();
            split(
                &self.points,
                cluster,
                self.line,
                threshold,
                &mut self.stack,
                &mut self.pieces,
            );
            if p.merge_collinear {
                merge_collinear(&self.points, &mut self.pieces, threshold);
            }
            self.runs.extend_from_slice(&self.pieces);
        }
        self.member.clear();
        self.member.resize(self.points.len(), true);
        finish(
            &self.points,
            &mut self.runs,
            &self.member,
            &p.breakpoints,
            p.filter,
            out,
        );
    }
}
