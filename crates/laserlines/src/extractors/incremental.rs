//! Incremental line extraction (line tracking), as compared by Nguyen et al.
//!
//! 1. Cut the valid points into clusters at breakpoints (Borges and Aldon's adaptive detector).
//! 2. In each cluster, start a line on `seed_points` consecutive points that all lie within the
//!    tracking threshold of their least-squares line (otherwise move one point on).
//! 3. Grow the line point by point: the next point joins when its distance to the current
//!    least-squares line is within the tracking threshold, and the line is refitted (in O(1),
//!    with running sums). Up to `max_outliers` consecutive points that fail are tolerated inside
//!    the line (kept in its beam range, not used in its fit); after more, the line ends at its
//!    last accepted point and the next line starts right after it.
//! 4. The common final step: where two lines meet, the points that the first one absorbed
//!    before the turn became visible go to the line that explains them better; then the
//!    least-squares fit, minimum points and length.

use super::ParamsError;
use super::breakpoints::Breakpoints;
use super::finish::{LineFilter, finish};
use super::model::Scaled;
use super::runs::Run;
use crate::extractor::LineExtractor;
use crate::fit::FitSums;
use crate::line::Line;
use crate::params;
use crate::scan::{RangeWindow, ScanPoint, ScanView};

/// Parameters of [`Incremental`].
///
/// Defaults marked *tuned* were chosen by `laserlines bench --tune incremental --suite all --seed 1
/// --scans 100`: a coordinate search maximising the F1 score of found walls and false lines on
/// the training suite (seed 1, 100 simulated URG-04LX scans of each of the seven scene suites;
/// see `laserlines_eval::tune`). Results are reported on the test suite, seed 2.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct IncrementalParams {
    /// The breakpoint detector that cuts clusters and runs (Borges and Aldon). Default 10
    /// deg, 0.01 m of noise, at most 2 missing beams.
    pub breakpoints: Breakpoints,
    /// Consecutive points that start a line. Default 3 (tuned). At least 3. Sensible: 3..10.
    pub seed_points: usize,
    /// Tracking threshold at zero range, m: a point joins the line when its distance to the
    /// line is at most `track_distance + track_distance_per_metre * range`. Default 0.02.
    /// Sensible: 0.01..0.05.
    pub track_distance: f64,
    /// Growth of the tracking threshold with the range of the tested point, m per m.
    /// Default 0.01 (the URG-04LX's 1 %). Sensible: 0..0.03.
    pub track_distance_per_metre: f64,
    /// Consecutive failing points tolerated inside a line. Default 1. Sensible: 0..3.
    pub max_outliers: usize,
    /// The final filter. Default 8 (tuned) points, 0.15 m (tuned).
    pub filter: LineFilter,
    /// Extra limits on valid ranges, on top of the scan's own `range_min..range_max`.
    /// Default none.
    pub range_limits: Option<RangeWindow>,
}

impl Default for IncrementalParams {
    fn default() -> Self {
        Self {
            breakpoints: Breakpoints::default(),
            seed_points: 3,
            track_distance: 0.02,
            track_distance_per_metre: 0.01,
            max_outliers: 1,
            filter: LineFilter::default(),
            range_limits: None,
        }
    }
}

impl IncrementalParams {
    /// Checks every field.
    ///
    /// # Errors
    /// A [`ParamsError`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ParamsError> {
        params::range_limits(self.range_limits)?;
        self.breakpoints.validate()?;
        params::at_least("seed_points", self.seed_points, 3)?;
        params::scaled(
            ("track_distance", self.track_distance),
            ("track_distance_per_metre", self.track_distance_per_metre),
        )?;
        self.filter.validate()
    }
}

/// Line tracking (see the module docs). Reuse one value across scans: its working memory is
/// kept.
#[derive(Debug, Clone)]
pub struct Incremental {
    params: IncrementalParams,
    points: Vec<ScanPoint>,
    clusters: Vec<Run>,
    runs: Vec<Run>,
    member: Vec<bool>,
}

impl Incremental {
    /// An extractor with validated parameters.
    ///
    /// # Errors
    /// [`ParamsError`] when a parameter is out of its domain.
    pub fn new(params: IncrementalParams) -> Result<Self, ParamsError> {
        params.validate()?;
        Ok(Self {
            params,
            points: Vec::new(),
            clusters: Vec::new(),
            runs: Vec::new(),
            member: Vec::new(),
        })
    }

    /// The parameters in use.
    #[must_use]
    pub fn params(&self) -> &IncrementalParams {
        &self.params
    }

    /// Tracks lines through one cluster, appending their runs.
    fn track(&mut self, cluster: Run, threshold: Scaled) {
        let p = &self.params;
        let pts = &self.points;
        let seed = p.seed_points;
        let mut i = cluster.start;
        while cluster.end - i >= seed {
            let sums = FitSums::from_points(pts[i..i + seed].iter().map(|sp| sp.point));
            let seeded = sums.fit().filter(|fit| {
                let distance = fit.distance_fn();
                pts[i..i + seed]
                    .iter()
                    .all(|sp| distance(sp.point).abs() <= threshold.at(sp.range))
            });
            let Some(mut fit) = seeded else {
                i += 1;
                continue;
            };
            let mut sums = sums;
            self.member[i..i + seed].fill(true);
            let mut last = i + seed - 1;
            let mut failed = 0usize;
            for (j, sp) in pts.iter().enumerate().take(cluster.end).skip(i + seed) {
                if fit.distance(sp.point).abs() <= threshold.at(sp.range) {
                    sums.add(sp.point);
                    if let Some(f) = sums.fit() {
                        fit = f;
                    }
                    self.member[j] = true;
                    last = j;
                    failed = 0;
                } else {
                    failed += 1;
                    if failed > p.max_outliers {
                        break;
                    }
                }
            }
            self.runs.push(Run {
                start: i,
                end: last + 1,
            });
            i = last + 1;
        }
    }
}

impl LineExtractor for Incremental {
    fn name(&self) -> &'static str {
        "incremental"
    }

    fn extract_view_into(&mut self, scan: ScanView<'_>, out: &mut Vec<Line>) {
        out.clear();
        let p = &self.params;
        scan.points_into(scan.range_window(p.range_limits), &mut self.points);
        let rule = p.breakpoints;
        let threshold = Scaled {
            base: p.track_distance,
            per_metre: p.track_distance_per_metre,
        };
        let filter = p.filter;
        rule.clusters(&self.points, p.seed_points, &mut self.clusters);
        self.member.clear();
        self.member.resize(self.points.len(), false);
        self.runs.clear();
        for c in 0..self.clusters.len() {
            let cluster = self.clusters[c];
            self.track(cluster, threshold);
        }
        finish(
            &self.points,
            &mut self.runs,
            &self.member,
            &rule,
            filter,
            out,
        );
    }
}
