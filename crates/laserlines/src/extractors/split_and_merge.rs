//! Split-and-merge (Pavlidis and Horowitz; as compared by Nguyen et al.) on breakpoint
//! clusters.
//!
//! 1. Cut the valid points into clusters at breakpoints (Borges and Aldon's adaptive detector)
//!    and drop clusters of fewer than `min_cluster_points`.
//! 2. Split: fit a least-squares line to the piece and find the interior point farthest from
//!    it; split there when it lies farther than the split threshold, recursively.
//! 3. Merge: join neighbouring pieces whose points all lie within the split threshold of their
//!    joint least-squares line.
//! 4. The common final step (least-squares fit, minimum points and length).
//!
//! The split differs from [`super::SplitAndMerge`] only in the line the distances are measured from:
//! the fitted line, not the chord between the end points.

use super::ParamsError;
use super::common::{SplitEngine, SplitLine, SplitSettings, split_settings};
use crate::extractor::LineExtractor;
use crate::line::Line;
use crate::scan::{RangeWindow, Scan};

/// Parameters of [`SplitAndMerge`].
///
/// Defaults marked *tuned* were chosen by `laserlines bench --tune split-and-merge --suite all --seed 1
/// --scans 100`: a coordinate search maximising the F1 score of found walls and false lines on
/// the training suite (seed 1, 100 simulated URG-04LX scans of each of the seven scene suites;
/// see `laserlines_eval::tune`). Results are reported on the test suite, seed 2.
#[derive(Debug, Clone, PartialEq)]
pub struct SplitAndMergeParams {
    /// Smallest incidence angle between beam and surface that still joins two consecutive
    /// points into one cluster, rad (`lambda` of Borges and Aldon). Default 10 deg.
    /// Sensible: 5..20 deg.
    pub breakpoint_incidence: f64,
    /// Range noise allowance of the breakpoint detector, m (added three times). Default 0.02
    /// (tuned). Sensible: 0..0.05.
    pub breakpoint_noise: f64,
    /// Most missing (invalid) beams between two consecutive points that the breakpoint detector
    /// may still join. Default 2. Sensible: 0..5.
    pub breakpoint_max_gap: usize,
    /// Clusters with fewer points are dropped. Default 8 (tuned). Sensible: 2..10.
    pub min_cluster_points: usize,
    /// Split threshold at zero range, m: a piece is split where the interior point farthest
    /// from its least-squares line lies farther than `split_distance + split_distance_per_metre * range`.
    /// Default 0.03 (tuned). Sensible: 0.01..0.05.
    pub split_distance: f64,
    /// Growth of the split threshold with the range of the farthest point, m per m.
    /// Default 0.01 (the URG-04LX's 1 %). Sensible: 0..0.03.
    pub split_distance_per_metre: f64,
    /// Merge neighbouring pieces whose points all lie within the split threshold of their joint
    /// least-squares line (the "merge" of split-and-merge). Default `true`.
    pub merge_collinear: bool,
    /// Lines with fewer supporting points are dropped. Default 8 (tuned). At least 2 is
    /// enforced.
    pub min_line_points: usize,
    /// Lines shorter than this are dropped, m. Default 0.15 (tuned): legs and debris give
    /// short lines; lower it when small features matter. Sensible: 0..0.5.
    pub min_line_length: f64,
    /// Extra limits on valid ranges, on top of the scan's own `range_min..range_max`.
    /// Default none.
    pub range_limits: Option<RangeWindow>,
}

impl Default for SplitAndMergeParams {
    fn default() -> Self {
        Self {
            breakpoint_incidence: 10.0_f64.to_radians(),
            breakpoint_noise: 0.02,
            breakpoint_max_gap: 2,
            min_cluster_points: 8,
            split_distance: 0.03,
            split_distance_per_metre: 0.01,
            merge_collinear: true,
            min_line_points: 8,
            min_line_length: 0.15,
            range_limits: None,
        }
    }
}

impl SplitAndMergeParams {
    /// Checks every field.
    ///
    /// # Errors
    /// A [`ParamsError`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ParamsError> {
        self.settings().validate()
    }

    fn settings(&self) -> SplitSettings {
        split_settings!(self)
    }
}

/// Split-and-merge on breakpoint clusters (see the module docs). Reuse one value
/// across scans: its working memory is kept.
#[derive(Debug, Clone)]
pub struct SplitAndMerge {
    params: SplitAndMergeParams,
    settings: SplitSettings,
    engine: SplitEngine,
}

impl SplitAndMerge {
    /// An extractor with validated parameters.
    ///
    /// # Errors
    /// [`ParamsError`] when a parameter is out of its domain.
    pub fn new(params: SplitAndMergeParams) -> Result<Self, ParamsError> {
        params.validate()?;
        Ok(Self {
            settings: params.settings(),
            params,
            engine: SplitEngine::default(),
        })
    }

    /// The parameters in use.
    #[must_use]
    pub fn params(&self) -> &SplitAndMergeParams {
        &self.params
    }
}

impl LineExtractor for SplitAndMerge {
    fn name(&self) -> &'static str {
        "split-and-merge"
    }

    fn extract_into(&mut self, scan: &Scan, out: &mut Vec<Line>) {
        self.engine
            .extract_into(scan, &self.settings, SplitLine::LeastSquares, out);
    }
}
