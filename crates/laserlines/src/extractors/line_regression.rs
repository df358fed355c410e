//! Line regression (Arras and Siegwart 1997, as compared by Nguyen et al.): sliding-window
//! fits clustered in `(r, alpha)` space.
//!
//! 1. Cut the valid points into clusters at breakpoints (Borges and Aldon's adaptive detector).
//! 2. Fit a least-squares line to every window of `window` consecutive points of a cluster,
//!    with the covariance of its `(r, alpha)` under the sensor noise model
//!    `sigma(range) = noise_sigma + noise_sigma_per_metre * range`.
//! 3. Agglomerate consecutive windows: a window joins the current group when its `(r, alpha)`
//!    is within Mahalanobis distance `similarity` (squared) of the line fitted to the group's
//!    points so far; otherwise it starts a new group. Groups of fewer than `min_windows`
//!    windows (the windows straddling a corner) are dropped.
//! 4. Neighbouring groups overlap or leave a gap of at most one window at a corner: their
//!    junction is put in the middle, then neighbours whose points all lie within the merge
//!    threshold of their joint least-squares line are merged.
//! 5. The common final step: junction points go to the line that explains them better; then
//!    the least-squares fit, minimum points and length.

use super::ParamsError;
use super::breakpoints::Breakpoints;
use super::finish::{LineFilter, finish};
use super::merge;
use super::model::Scaled;
use super::runs::Run;
use crate::extractor::LineExtractor;
use crate::fit::{FitSums, PolarFit};
use crate::line::Line;
use crate::math::{Matrix2, Point2, angle_diff, wrap_angle};
use crate::params;
use crate::scan::{RangeWindow, ScanPoint, ScanView};
use std::f64::consts::{FRAC_PI_2, PI};

/// Parameters of [`LineRegression`].
///
/// Defaults marked *tuned* were chosen by `laserlines bench --tune line-regression --suite all --seed 1
/// --scans 100`: a coordinate search maximising the F1 score of found walls and false lines on
/// the training suite (seed 1, 100 simulated URG-04LX scans of each of the seven scene suites;
/// see `laserlines_eval::tune`). Results are reported on the test suite, seed 2.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct LineRegressionParams {
    /// The breakpoint detector that cuts clusters and runs (Borges and Aldon). Default 10
    /// deg, 0.01 m of noise, at most 2 missing beams.
    pub breakpoints: Breakpoints,
    /// Points per sliding window (`N_f`). Default 9. At least 3. Sensible: 5..15.
    pub window: usize,
    /// Range noise standard deviation at zero range, m, for the window covariances.
    /// Default 0.005. Sensible: 0.001..0.02.
    pub noise_sigma: f64,
    /// Growth of the noise standard deviation with range, m per m. Default 0.0025 (tuned;
    /// the URG-04LX's +-1 % read as two standard deviations would be 0.005). Sensible: 0..0.02.
    pub noise_sigma_per_metre: f64,
    /// Largest squared Mahalanobis distance in `(r, alpha)` between a window and its group's
    /// line for the window to join. Default 4 (tuned; chi-square with 2 degrees of freedom:
    /// 86 %). Sensible: 4..30.
    pub similarity: f64,
    /// Groups of fewer windows are dropped. Default 2 (tuned). At least 1. Sensible: 1..5.
    pub min_windows: usize,
    /// Merge neighbouring groups whose points all lie within the merge threshold of their joint
    /// least-squares line. Default `true`.
    pub merge_collinear: bool,
    /// Merge threshold at zero range, m: `merge_distance + merge_distance_per_metre * range`.
    /// Default 0.02. Sensible: 0.01..0.05.
    pub merge_distance: f64,
    /// Growth of the merge threshold with range, m per m. Default 0.02 (tuned).
    /// Sensible: 0..0.03.
    pub merge_distance_per_metre: f64,
    /// The final filter. Default 8 (tuned) points, 0.15 m (tuned).
    pub filter: LineFilter,
    /// Extra limits on valid ranges, on top of the scan's own `range_min..range_max`.
    /// Default none.
    pub range_limits: Option<RangeWindow>,
}

impl Default for LineRegressionParams {
    fn default() -> Self {
        Self {
            breakpoints: Breakpoints::default(),
            window: 9,
            noise_sigma: 0.005,
            noise_sigma_per_metre: 0.0025,
            similarity: 4.0,
            min_windows: 2,
            merge_collinear: true,
            merge_distance: 0.02,
            merge_distance_per_metre: 0.02,
            filter: LineFilter::default(),
            range_limits: None,
        }
    }
}

impl LineRegressionParams {
    /// Checks every field.
    ///
    /// # Errors
    /// A [`ParamsError`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ParamsError> {
        params::range_limits(self.range_limits)?;
        self.breakpoints.validate()?;
        params::at_least("window", self.window, 3)?;
        params::scaled(
            ("noise_sigma", self.noise_sigma),
            ("noise_sigma_per_metre", self.noise_sigma_per_metre),
        )?;
        params::positive("similarity", self.similarity)?;
        params::at_least("min_windows", self.min_windows, 1)?;
        params::scaled(
            ("merge_distance", self.merge_distance),
            ("merge_distance_per_metre", self.merge_distance_per_metre),
        )?;
        self.filter.validate()
    }
}

/// A fitted line with the covariance of its `(r, alpha)`.
#[derive(Debug, Clone, Copy)]
struct Estimate {
    r: f64,
    alpha: f64,
    cov: Matrix2,
}

/// Covariance of `(r, alpha)` of `fit` for isotropic noise `sigma` (see [`crate::fit`]), with
/// `stt` the spread of the points along the line.
fn estimate(fit: &PolarFit, sigma: f64, stt: f64) -> Option<Estimate> {
    if !(stt > 0.0 && stt.is_finite()) {
        return None;
    }
    let s2 = sigma * sigma;
    let t0 = -fit.centroid.x * fit.alpha.sin() + fit.centroid.y * fit.alpha.cos();
    let var_alpha = s2 / stt;
    let cov = Matrix2::new(
        s2 / fit.n as f64 + t0 * t0 * var_alpha,
        t0 * var_alpha,
        t0 * var_alpha,
        var_alpha,
    );
    Some(Estimate {
        r: fit.r,
        alpha: fit.alpha,
        cov,
    })
}

/// Squared Mahalanobis distance between two estimates, comparing the lines in the same
/// orientation (a line near the sensor may have its normal flipped).
fn mahalanobis2(a: &Estimate, b: &Estimate) -> f64 {
    let (mut r, mut alpha) = (a.r, a.alpha);
    if angle_diff(alpha, b.alpha) > FRAC_PI_2 {
        r = -r;
        alpha = wrap_angle(alpha + PI);
    }
    let (dr, da) = (r - b.r, wrap_angle(alpha - b.alpha));
    let s = a.cov + b.cov;
    let det = s[(0, 0)] * s[(1, 1)] - s[(0, 1)] * s[(1, 0)];
    if !(det > 0.0 && det.is_finite()) {
        return f64::INFINITY;
    }
    let d2 = (s[(1, 1)] * dr * dr - (s[(0, 1)] + s[(1, 0)]) * dr * da + s[(0, 0)] * da * da) / det;
    if d2.is_nan() { f64::INFINITY } else { d2 }
}

/// Line regression (see the module docs). Reuse one value across scans: its working memory is
/// kept.
#[derive(Debug, Clone)]
pub struct LineRegression {
    params: LineRegressionParams,
    points: Vec<ScanPoint>,
    clusters: Vec<Run>,
    groups: Vec<Run>,
    runs: Vec<Run>,
    member: Vec<bool>,
}

impl LineRegression {
    /// An extractor with validated parameters.
    ///
    /// # Errors
    /// [`ParamsError`] when a parameter is out of its domain.
    pub fn new(params: LineRegressionParams) -> Result<Self, ParamsError> {
        params.validate()?;
        Ok(Self {
            params,
            points: Vec::new(),
            clusters: Vec::new(),
            groups: Vec::new(),
            runs: Vec::new(),
            member: Vec::new(),
        })
    }

    /// The parameters in use.
    #[must_use]
    pub fn params(&self) -> &LineRegressionParams {
        &self.params
    }

    fn sigma(&self, range: f64) -> f64 {
        self.params.noise_sigma + self.params.noise_sigma_per_metre * range
    }

    /// The estimate of the window of points `start..start + window`.
    fn window_estimate(&self, start: usize) -> Option<Estimate> {
        let pts = &self.points[start..start + self.params.window];
        let fit = FitSums::from_points(pts.iter().map(|sp| sp.point)).fit()?;
        let dir = (-fit.alpha.sin(), fit.alpha.cos());
        let t = |p: Point2| (p.x - fit.centroid.x) * dir.0 + (p.y - fit.centroid.y) * dir.1;
        let stt: f64 = pts.iter().map(|sp| t(sp.point).powi(2)).sum();
        let range = pts.iter().map(|sp| sp.range).sum::<f64>() / pts.len() as f64;
        estimate(&fit, self.sigma(range), stt)
    }

    /// The estimate of a group's points `from..to` summed in `sums`. The spread along the line
    /// is that of evenly spaced points between the projections of the first and last point.
    fn group_estimate(&self, sums: &FitSums, from: usize, to: usize) -> Option<Estimate> {
        let fit = sums.fit()?;
        let (a, b) = (self.points[from].point, self.points[to - 1].point);
        let len = (fit.project(b) - fit.project(a)).norm();
        let n = fit.n as f64;
        let stt = n * len * len / 12.0;
        estimate(&fit, self.sigma(fit.centroid.coords.norm()), stt)
    }

    /// Groups the windows of one cluster into runs appended to `self.groups`.
    fn group_windows(&mut self, cluster: Run) {
        let nf = self.params.window;
        if cluster.len() < nf {
            return;
        }
        let last_window = cluster.end - nf;
        let mut from = cluster.start;
        let mut sums = FitSums::from_points(self.points[from..from + nf].iter().map(|sp| sp.point));
        let min_windows = self.params.min_windows;
        let close = |groups: &mut Vec<Run>, from: usize, last: usize| {
            if last + 1 - from >= min_windows {
                groups.push(Run {
                    start: from,
                    end: last + nf,
                });
            }
        };
        for w in cluster.start + 1..=last_window {
            let to = w + nf;
            let similar = match (
                self.window_estimate(w),
                self.group_estimate(&sums, from, to - 1),
            ) {
                (Some(we), Some(ge)) => mahalanobis2(&we, &ge) <= self.params.similarity,
                _ => false,
            };
            if similar {
                sums.add(self.points[to - 1].point);
            } else {
                close(&mut self.groups, from, w - 1);
                from = w;
                sums = FitSums::from_points(self.points[w..to].iter().map(|sp| sp.point));
            }
        }
        close(&mut self.groups, from, last_window);
    }

    /// Puts the junction of neighbouring groups that overlap, or leave a gap of at most one
    /// window, in the middle.
    fn meet(&mut self) {
        let nf = self.params.window;
        for k in 1..self.groups.len() {
            let (a, b) = (self.groups[k - 1], self.groups[k]);
            if b.start <= a.end.saturating_add(nf) {
                // a.start < a.end < b.end, so the interval is never empty.
                let j = (a.end + b.start) / 2;
                let j = j.clamp(a.start + 1, b.end - 1);
                self.groups[k - 1].end = j;
                self.groups[k].start = j;
            }
        }
    }
}

impl LineExtractor for LineRegression {
    fn name(&self) -> &'static str {
        "line-regression"
    }

    fn extract_view_into(&mut self, scan: ScanView<'_>, out: &mut Vec<Line>) {
        out.clear();
        let p = &self.params;
        scan.points_into(scan.range_window(p.range_limits), &mut self.points);
        let rule = p.breakpoints;
        let merge = Scaled {
            base: p.merge_distance,
            per_metre: p.merge_distance_per_metre,
        };
        let filter = p.filter;
        let merge_collinear = p.merge_collinear;
        rule.clusters(&self.points, p.window, &mut self.clusters);
        self.runs.clear();
        for c in 0..self.clusters.len() {
            self.groups.clear();
            self.group_windows(self.clusters[c]);
            self.meet();
            if merge_collinear {
                merge::merge_collinear(&self.points, &mut self.groups, merge);
            }
            self.runs.extend_from_slice(&self.groups);
        }
        self.member.clear();
        self.member.resize(self.points.len(), true);
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mahalanobis_compares_flipped_normals() {
        let cov = Matrix2::new(1e-4, 0.0, 0.0, 1e-4);
        let a = Estimate {
            r: 0.001,
            alpha: 0.3,
            cov,
        };
        let b = Estimate {
            r: 0.001,
            alpha: wrap_angle(0.3 + PI),
            cov,
        };
        // The same line through (almost) the origin, normals opposite: r differs by 0.002.
        let d2 = mahalanobis2(&a, &b);
        assert!((d2 - 0.002f64.powi(2) / 2e-4).abs() < 1e-9, "{d2}");
        let singular = Estimate {
            cov: Matrix2::zeros(),
            ..a
        };
        assert!(mahalanobis2(&singular, &singular).is_infinite());
    }
}
