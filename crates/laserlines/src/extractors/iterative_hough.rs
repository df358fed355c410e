//! The iterative Hough transform of Nguyen et al., the baseline the paper compares against
//! (section II-C of the paper):
//!
//! ```text
//! 1. Initial: a set of N points
//! 2. Initialize the accumulator array
//! 3. Construct values for the array
//! 4. Choose the element with max. votes V_max
//! 5. If V_max is less than a threshold, terminate
//! 6. Otherwise, determine the inliers
//! 7. Fit a line through the inliers and store the line
//! 8. Remove the inliers from the set, goto 2
//! ```
//!
//! Step 2-3 is the full accumulator of [`crate::hough`] (every point votes in every column),
//! rebuilt from scratch in every round, as in the original: that is the cost the paper's
//! single-pass accumulator avoids. Reading of the other steps:
//!
//! - Inliers (6) are the points within `inlier_distance + inlier_distance_per_metre * range` of
//!   the peak cell's line. They are cut into runs of consecutive beams (broken at breakpoints
//!   of Borges and Aldon's detector, at beams already in a line, and after more than
//!   `max_skipped` consecutive non-inliers), since a line here is a segment, not an infinite
//!   line.
//! - Fit (7): the line is refined `refine_iterations` times by a least-squares fit of the
//!   largest run's inliers and a new collection of inliers, which removes the quantisation of
//!   the grid. Every run of at least `filter.min_points` inliers is stored.
//! - Remove (8): the inliers of the peak line and of the refined line leave the accumulator.
//!   A removed point that ended in no stored run may still support a later line's run (so that
//!   a wall crossed by another wall's strip is not cut in two), but never votes again.
//!
//! Then the common final step.

use super::ParamsError;
use super::breakpoints::Breakpoints;
use super::finish::{LineFilter, finish};
use super::model::{Hypothesis, Scaled};
use super::runs::{Run, fit_where, largest_run, runs_with_members};
use crate::extractor::LineExtractor;
use crate::hough::{HoughAccumulator, HoughGrid};
use crate::hough_split::Weight;
use crate::line::Line;
use crate::math::Vector2;
use crate::params;
use crate::scan::{RangeWindow, ScanPoint, ScanView};

/// Parameters of [`IterativeHough`].
///
/// Defaults marked *tuned* were chosen by `laserlines bench --tune iterative-hough --suite all --seed 1
/// --scans 100`: a coordinate search maximising the F1 score of found walls and false lines on
/// the training suite (seed 1, 100 simulated URG-04LX scans of each of the seven scene suites;
/// see `laserlines_eval::tune`). Results are reported on the test suite, seed 2.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct IterativeHoughParams {
    /// Row step of the accumulator, m. Default 0.02. Sensible: 0.01..0.10.
    pub distance_step: f64,
    /// Largest distance of a line from the sensor represented, m. Default 6.0 (the URG-04LX
    /// reaches 5.6 m). Sensible: the sensor's maximum range.
    pub max_distance: f64,
    /// Column step of the accumulator, rad (rounded to tile the half turn). Default 1 deg.
    /// Sensible: 0.25..3 deg.
    pub angle_step: f64,
    /// Half-width of the voting window, m. Default 0.01 (half the row step). Sensible: 0.5..1.5
    /// row steps.
    pub window: f64,
    /// Weight of a vote: [`Weight::One`] (count points, as Nguyen et al.) or [`Weight::Range`].
    /// Default [`Weight::One`].
    pub weight: Weight,
    /// The search stops when the peak has fewer votes (points with [`Weight::One`], metres
    /// with [`Weight::Range`]). Default 5 (tuned). Sensible: 5..30.
    pub min_votes: f64,
    /// Inlier threshold at zero range, m: inliers lie within
    /// `inlier_distance + inlier_distance_per_metre * range` of the line. It must cover the
    /// grid's quantisation as well as the noise. Default 0.015 (tuned). Sensible: 0.01..0.05.
    pub inlier_distance: f64,
    /// Growth of the inlier threshold with the range of the tested point, m per m.
    /// Default 0.01 (the URG-04LX's 1 %). Sensible: 0..0.03.
    pub inlier_distance_per_metre: f64,
    /// Least-squares refinements of the peak line. Default 2. Sensible: 0..5.
    pub refine_iterations: usize,
    /// Consecutive non-inliers tolerated inside a run (kept in its beam range, not used in its
    /// fit). Default 1 (tuned). Sensible: 0..5.
    pub max_skipped: usize,
    /// The breakpoint detector that cuts clusters and runs (Borges and Aldon). Default 10
    /// deg, 0.01 m of noise, at most 2 missing beams.
    pub breakpoints: Breakpoints,
    /// Most rounds (accumulator builds) per scan. Default 100. At least 1. Sensible: 20..500.
    pub max_iterations: usize,
    /// The final filter. Default 8 (tuned) points, 0.15 m (tuned).
    pub filter: LineFilter,
    /// Extra limits on valid ranges, on top of the scan's own `range_min..range_max`.
    /// Default none.
    pub range_limits: Option<RangeWindow>,
}

impl Default for IterativeHoughParams {
    fn default() -> Self {
        let grid = HoughGrid::default();
        Self {
            distance_step: grid.distance_step,
            max_distance: grid.max_distance,
            angle_step: grid.angle_step,
            window: grid.window,
            weight: Weight::One,
            min_votes: 5.0,
            inlier_distance: 0.015,
            inlier_distance_per_metre: 0.01,
            refine_iterations: 2,
            max_skipped: 1,
            breakpoints: Breakpoints::default(),
            max_iterations: 100,
            filter: LineFilter::default(),
            range_limits: None,
        }
    }
}

impl IterativeHoughParams {
    /// The accumulator's grid.
    #[must_use]
    pub fn grid(&self) -> HoughGrid {
        HoughGrid {
            distance_step: self.distance_step,
            max_distance: self.max_distance,
            angle_step: self.angle_step,
            window: self.window,
        }
    }

    /// Checks every field.
    ///
    /// # Errors
    /// A [`ParamsError`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ParamsError> {
        params::range_limits(self.range_limits)?;
        self.grid().validate()?;
        params::positive("min_votes", self.min_votes)?;
        params::scaled(
            ("inlier_distance", self.inlier_distance),
            ("inlier_distance_per_metre", self.inlier_distance_per_metre),
        )?;
        self.breakpoints.validate()?;
        params::at_least("max_iterations", self.max_iterations, 1)?;
        self.filter.validate()
    }
}

/// The iterative Hough transform (see the module docs). Reuse one value across scans: the
/// accumulator and the other working memory are kept.
#[derive(Debug, Clone)]
pub struct IterativeHough {
    params: IterativeHoughParams,
    acc: HoughAccumulator,
    points: Vec<ScanPoint>,
    voting: Vec<bool>,
    taken: Vec<bool>,
    member: Vec<bool>,
    found: Vec<Run>,
    runs: Vec<Run>,
}

impl IterativeHough {
    /// An extractor with validated parameters (allocates the accumulator).
    ///
    /// # Errors
    /// [`ParamsError`] when a parameter is out of its domain or the grid is too large.
    pub fn new(params: IterativeHoughParams) -> Result<Self, ParamsError> {
        params.validate()?;
        Ok(Self {
            acc: HoughAccumulator::new(params.grid())?,
            params,
            points: Vec::new(),
            voting: Vec::new(),
            taken: Vec::new(),
            member: Vec::new(),
            found: Vec::new(),
            runs: Vec::new(),
        })
    }

    /// The parameters in use.
    #[must_use]
    pub fn params(&self) -> &IterativeHoughParams {
        &self.params
    }

    /// The accumulator as left by the last round of the last extraction.
    #[must_use]
    pub fn accumulator(&self) -> &HoughAccumulator {
        &self.acc
    }

    /// The hypothesis `h0` refined by least squares on its largest run of inliers, while
    /// that run keeps `min_members` points.
    fn refine(
        &self,
        h0: Hypothesis,
        t: Scaled,
        rule: &Breakpoints,
        min_members: usize,
    ) -> Hypothesis {
        let mut h = h0;
        if let Some((mut run, _)) = self.best_run(&h, t, rule) {
            for _ in 0..self.params.refine_iterations {
                let pts = &self.points;
                let fit = fit_where(pts, run, |i| h.distance(pts[i].point) <= t.at(pts[i].range));
                let Some(fit) = fit else { break };
                let refined = Hypothesis::from_fit(&fit);
                match self.best_run(&refined, t, rule) {
                    Some((r, m)) if m >= min_members => {
                        h = refined;
                        run = r;
                    }
                    _ => break,
                }
            }
        }
        h
    }

    /// Takes every run of at least `min_members` inliers of `h` among the points not taken
    /// yet: its inliers become members, its points leave the vote.
    fn take_runs(&mut self, h: &Hypothesis, t: Scaled, rule: &Breakpoints, min_members: usize) {
        let (pts, taken) = (&self.points, &self.taken);
        runs_with_members(
            pts,
            |i| !taken[i],
            |i| h.distance(pts[i].point) <= t.at(pts[i].range),
            rule,
            self.params.max_skipped,
            min_members,
            &mut self.found,
        );
        for &r in &self.found {
            for i in r.start..r.end {
                self.member[i] = h.distance(self.points[i].point) <= t.at(self.points[i].range);
                self.taken[i] = true;
                self.voting[i] = false;
            }
            self.runs.push(r);
        }
    }

    fn best_run(&self, h: &Hypothesis, t: Scaled, rule: &Breakpoints) -> Option<(Run, usize)> {
        let pts = &self.points;
        largest_run(
            pts,
            |i| !self.taken[i],
            |i| h.distance(pts[i].point) <= t.at(pts[i].range),
            rule,
            self.params.max_skipped,
        )
    }
}

impl LineExtractor for IterativeHough {
    fn name(&self) -> &'static str {
        "iterative-hough"
    }

    fn extract_view_into(&mut self, scan: ScanView<'_>, out: &mut Vec<Line>) {
        out.clear();
        let p = self.params.clone();
        scan.points_into(scan.range_window(p.range_limits), &mut self.points);
        let n = self.points.len();
        let rule = p.breakpoints;
        let t = Scaled {
            base: p.inlier_distance,
            per_metre: p.inlier_distance_per_metre,
        };
        let min_members = p.filter.min_points.max(2);
        self.voting.clear();
        self.voting.resize(n, true);
        self.taken.clear();
        self.taken.resize(n, false);
        self.member.clear();
        self.member.resize(n, false);
        self.runs.clear();
        for _ in 0..p.max_iterations {
            // 2-3. The full accumulator of the points still in the set.
            let voting = &self.voting;
            self.acc.build(
                self.points
                    .iter()
                    .enumerate()
                    .filter(|(i, _)| voting[*i])
                    .map(|(_, sp)| sp),
                p.weight,
            );
            // 4-5. The peak.
            let Some(peak) = self.acc.peak() else { break };
            if peak.value < p.min_votes {
                break;
            }
            let (s, c) = peak.angle.sin_cos();
            let h0 = Hypothesis {
                normal: Vector2::new(c, s),
                d: peak.distance,
            };
            // 6-7. Inliers, refined by least squares on the largest run.
            let h = self.refine(h0, t, &rule, min_members);
            self.take_runs(&h, t, &rule, min_members);
            // 8. Remove the inliers (of the peak line, which include the peak's voters, and of
            // the refined line) from the set.
            let a = p.window * (1.0 + 1e-9) + 1e-12;
            for (i, sp) in self.points.iter().enumerate() {
                let limit = t.at(sp.range);
                if h0.distance(sp.point) <= limit.max(a) || h.distance(sp.point) <= limit {
                    self.voting[i] = false;
                }
            }
        }
        let filter = p.filter;
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
