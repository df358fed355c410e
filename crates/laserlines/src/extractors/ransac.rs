//! RANSAC (Fischler and Bolles 1981, as compared by Nguyen et al.), seeded, with a minimum
//! number of inliers and a consistent-run check so that it yields segments, not infinite lines.
//!
//! Repeat, at most `max_lines` times, on the points not yet taken:
//!
//! 1. Draw `iterations` hypotheses, each the line through two points: the first anywhere, the
//!    second among the `sample_span` free points on either side of it in beam order (0: anywhere).
//! 2. Score a hypothesis by its largest consistent run: its inliers (points within
//!    `inlier_distance + inlier_distance_per_metre * range`) cut into runs of consecutive free
//!    beams, broken at breakpoints (Borges and Aldon's adaptive detector) and after more than
//!    `max_skipped` consecutive non-inliers. Keep the best.
//! 3. Stop when the best run has fewer than `min_inliers` inliers.
//! 4. Refine `refine_iterations` times: refit the best run's inliers by least squares and
//!    collect the inliers of that line again.
//! 5. Every run of the refined line with at least `min_inliers` inliers becomes a line; its
//!    beams are taken. (If none does, the best run is taken without a line, so the loop always
//!    progresses.)
//!
//! Then the common final step. The generator is SplitMix64 seeded with `seed` at the start of
//! every scan, so the same scan gives the same lines.

use super::ParamsError;
use super::breakpoints::Breakpoints;
use super::finish::{LineFilter, finish};
use super::model::{Hypothesis, Scaled};
use super::rng::SplitMix64;
use super::runs::{Run, fit_where, largest_run, runs_with_members};
use crate::extractor::LineExtractor;
use crate::line::Line;
use crate::params;
use crate::scan::{RangeWindow, ScanPoint, ScanView};

/// Parameters of [`Ransac`].
///
/// Defaults marked *tuned* were chosen by `laserlines bench --tune ransac --suite all --seed 1
/// --scans 100`: a coordinate search maximising the F1 score of found walls and false lines on
/// the training suite (seed 1, 100 simulated URG-04LX scans of each of the seven scene suites;
/// see `laserlines_eval::tune`). Results are reported on the test suite, seed 2.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct RansacParams {
    /// Seed of the generator, reset for every scan. Default `0x5EED`.
    pub seed: u64,
    /// Hypotheses drawn per extracted line. Default 100. At least 1. Sensible: 20..1000.
    pub iterations: usize,
    /// The second point of a sample lies within this many free points of the first, in beam
    /// order; 0 draws it anywhere (the textbook sampler, poor on scans of many short walls).
    /// Default 30. Sensible: 0 or 10..100.
    pub sample_span: usize,
    /// Inlier threshold at zero range, m: inliers lie within
    /// `inlier_distance + inlier_distance_per_metre * range` of the line. Default 0.01
    /// (tuned). Sensible: 0.01..0.05.
    pub inlier_distance: f64,
    /// Growth of the inlier threshold with the range of the tested point, m per m.
    /// Default 0.01 (the URG-04LX's 1 %). Sensible: 0..0.03.
    pub inlier_distance_per_metre: f64,
    /// Fewest inliers in a consistent run for a line to be accepted. Default 10. At least 2.
    /// Sensible: 5..30.
    pub min_inliers: usize,
    /// Consecutive non-inliers tolerated inside a run (kept in its beam range, not used in its
    /// fit). Default 1 (tuned). Sensible: 0..5.
    pub max_skipped: usize,
    /// Least-squares refinements of the best hypothesis. Default 2. Sensible: 0..5.
    pub refine_iterations: usize,
    /// The breakpoint detector that cuts clusters and runs (Borges and Aldon). Default 10
    /// deg, 0.01 m of noise, at most 2 missing beams.
    pub breakpoints: Breakpoints,
    /// Most rounds of sampling (lines) per scan. Default 64. At least 1. Sensible: 16..256.
    pub max_lines: usize,
    /// The final filter. Default 6 points, 0.15 m (tuned).
    pub filter: LineFilter,
    /// Extra limits on valid ranges, on top of the scan's own `range_min..range_max`.
    /// Default none.
    pub range_limits: Option<RangeWindow>,
}

impl Default for RansacParams {
    fn default() -> Self {
        Self {
            seed: 0x5EED,
            iterations: 100,
            sample_span: 30,
            inlier_distance: 0.01,
            inlier_distance_per_metre: 0.01,
            min_inliers: 10,
            max_skipped: 1,
            refine_iterations: 2,
            breakpoints: Breakpoints::default(),
            max_lines: 64,
            filter: LineFilter {
                min_points: 6,
                ..LineFilter::default()
            },
            range_limits: None,
        }
    }
}

impl RansacParams {
    /// Checks every field.
    ///
    /// # Errors
    /// A [`ParamsError`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ParamsError> {
        params::range_limits(self.range_limits)?;
        params::at_least("iterations", self.iterations, 1)?;
        params::scaled(
            ("inlier_distance", self.inlier_distance),
            ("inlier_distance_per_metre", self.inlier_distance_per_metre),
        )?;
        params::at_least("min_inliers", self.min_inliers, 2)?;
        self.breakpoints.validate()?;
        params::at_least("max_lines", self.max_lines, 1)?;
        self.filter.validate()
    }
}

/// Seeded RANSAC with consistent runs (see the module docs). Reuse one value across scans: its
/// working memory is kept.
#[derive(Debug, Clone)]
pub struct Ransac {
    params: RansacParams,
    points: Vec<ScanPoint>,
    free: Vec<usize>,
    taken: Vec<bool>,
    member: Vec<bool>,
    found: Vec<Run>,
    runs: Vec<Run>,
}

impl Ransac {
    /// An extractor with validated parameters.
    ///
    /// # Errors
    /// [`ParamsError`] when a parameter is out of its domain.
    pub fn new(params: RansacParams) -> Result<Self, ParamsError> {
        params.validate()?;
        Ok(Self {
            params,
            points: Vec::new(),
            free: Vec::new(),
            taken: Vec::new(),
            member: Vec::new(),
            found: Vec::new(),
            runs: Vec::new(),
        })
    }

    /// The parameters in use.
    #[must_use]
    pub fn params(&self) -> &RansacParams {
        &self.params
    }

    /// Largest consistent run of hypothesis `h` among the free points.
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

    /// Draws a sample from the free points.
    fn sample(&self, rng: &mut SplitMix64) -> Option<Hypothesis> {
        let n = self.free.len();
        let a = rng.below(n);
        let span = self.params.sample_span;
        let (lo, hi) = if span == 0 {
            (0, n - 1)
        } else {
            (a.saturating_sub(span), a.saturating_add(span).min(n - 1))
        };
        if hi <= lo {
            return None;
        }
        let mut b = lo + rng.below(hi - lo);
        if b >= a {
            b += 1;
        }
        Hypothesis::through(
            self.points[self.free[a]].point,
            self.points[self.free[b]].point,
        )
    }
}

impl Ransac {
    /// Of `iterations` sampled hypotheses, the one with the largest run of inliers, the run
    /// and its member count.
    fn best_hypothesis(
        &self,
        rng: &mut SplitMix64,
        t: Scaled,
        rule: &Breakpoints,
    ) -> Option<(Hypothesis, Run, usize)> {
        let mut best: Option<(Hypothesis, Run, usize)> = None;
        for _ in 0..self.params.iterations {
            let Some(h) = self.sample(rng) else {
                continue;
            };
            if let Some((run, m)) = self.best_run(&h, t, rule)
                && best.is_none_or(|(_, _, b)| m > b)
            {
                best = Some((h, run, m));
            }
        }
        best
    }

    /// `h` refined by least squares on its largest run (starting at `run`), while that run
    /// keeps `min_inliers` points.
    fn refine(&self, mut h: Hypothesis, mut run: Run, t: Scaled, rule: &Breakpoints) -> Hypothesis {
        for _ in 0..self.params.refine_iterations {
            let pts = &self.points;
            let fit = fit_where(pts, run, |i| h.distance(pts[i].point) <= t.at(pts[i].range));
            let Some(fit) = fit else { break };
            let refined = Hypothesis::from_fit(&fit);
            match self.best_run(&refined, t, rule) {
                Some((r, m)) if m >= self.params.min_inliers => {
                    h = refined;
                    run = r;
                }
                _ => break,
            }
        }
        h
    }

    /// Takes every run of at least `min_inliers` inliers of `h` among the points not taken
    /// yet; false when there is none.
    fn take_runs(&mut self, h: &Hypothesis, t: Scaled, rule: &Breakpoints) -> bool {
        let (pts, taken) = (&self.points, &self.taken);
        runs_with_members(
            pts,
            |i| !taken[i],
            |i| h.distance(pts[i].point) <= t.at(pts[i].range),
            rule,
            self.params.max_skipped,
            self.params.min_inliers,
            &mut self.found,
        );
        if self.found.is_empty() {
            return false;
        }
        for &r in &self.found {
            for i in r.start..r.end {
                self.member[i] = h.distance(self.points[i].point) <= t.at(self.points[i].range);
                self.taken[i] = true;
            }
            self.runs.push(r);
        }
        true
    }
}

impl LineExtractor for Ransac {
    fn name(&self) -> &'static str {
        "ransac"
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
        self.taken.clear();
        self.taken.resize(n, false);
        self.member.clear();
        self.member.resize(n, false);
        self.runs.clear();
        let mut rng = SplitMix64::new(p.seed);
        for _ in 0..p.max_lines {
            self.free.clear();
            self.free.extend((0..n).filter(|&i| !self.taken[i]));
            if self.free.len() < p.min_inliers {
                break;
            }
            let Some((h, first_run, m)) = self.best_hypothesis(&mut rng, t, &rule) else {
                break;
            };
            if m < p.min_inliers {
                break;
            }
            let h = self.refine(h, first_run, t, &rule);
            if !self.take_runs(&h, t, &rule) {
                self.taken[first_run.start..first_run.end].fill(true);
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
