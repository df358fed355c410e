//! Expectation-maximisation of line hypotheses (as compared by Nguyen et al.), seeded.
//!
//! One hypothesis at a time, against an outlier class, on the points not yet taken:
//!
//! 1. Initialise: pick a random free point and fit a line to it and the next `init_points - 1`
//!    free points in beam order.
//! 2. E step: the probability that point `i` belongs to the line rather than to the outliers,
//!    `w_i = pi N(d_i; 0, sigma_i) / (pi N(d_i; 0, sigma_i) + (1 - pi) u)`, with `d_i` its
//!    distance to the line, `sigma_i = noise_sigma + noise_sigma_per_metre * range_i` (the
//!    sensor's noise grows with range), `u = outlier_density` and `pi` the line's share.
//! 3. M step: the weighted total-least-squares line, and `pi` the mean weight.
//! 4. Repeat 2-3 until the line stops moving or after `iterations` steps. The first steps are
//!    annealed: their standard deviations are `anneal_sigma_scale` times the sensor's, halved
//!    at every step down to 1, so that a hypothesis started on a few points grows to its
//!    whole wall.
//! 5. Points with `w_i >= inlier_probability` are cut into runs of consecutive free beams
//!    (broken at breakpoints and after more than `max_skipped` non-members); each run with at
//!    least `filter.min_points` members, and at least `filter.min_length` from its first member
//!    to its last, becomes a line and its beams are taken. A hypothesis that yields none is a
//!    failure, and leaves its points free for the next: a hypothesis that converged across two
//!    walls, and so cut both into short runs, does not take them from the lines that fit them.
//!    A failed annealed hypothesis is tried once more from the same start without annealing:
//!    the wide first steps can settle it between two parallel walls a few centimetres apart,
//!    where neither wall keeps enough members.
//!
//! The loop ends after `max_trials` hypotheses, or `max_failures` failures in a row. Then the
//! common final step. The generator is SplitMix64 seeded with `seed` at the start of every
//! scan, so the same scan gives the same lines.

use super::ParamsError;
use super::breakpoints::Breakpoints;
use super::finish::{LineFilter, finish};
use super::model::Hypothesis;
use super::rng::SplitMix64;
use super::runs::{Run, runs_with_members};
use crate::extractor::LineExtractor;
use crate::fit::FitSums;
use crate::line::Line;
use crate::math::Vector2;
use crate::params;
use crate::scan::{RangeWindow, ScanPoint, ScanView};

/// Parameters of [`Em`].
///
/// Defaults marked *tuned* were chosen by `laserlines bench --tune em --suite all --seed 1
/// --scans 100`: a coordinate search maximising the F1 score of found walls and false lines on
/// the training suite (seed 1, 100 simulated URG-04LX scans of each of the seven scene suites;
/// see `laserlines_eval::tune`). Results are reported on the test suite, seed 2.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct EmParams {
    /// Seed of the generator, reset for every scan. Default `0x5EED`.
    pub seed: u64,
    /// Most hypotheses tried per scan. Default 100. At least 1. Sensible: 20..500.
    pub max_trials: usize,
    /// Consecutive failed hypotheses after which the scan is done. Default 20. At least 1.
    /// Sensible: 5..50.
    pub max_failures: usize,
    /// Consecutive free points whose least-squares line starts a hypothesis. Default 10 (tuned).
    /// At least 2. Sensible: 3..15.
    pub init_points: usize,
    /// Most E-M steps per hypothesis. Default 20. At least 1. Sensible: 5..50.
    pub iterations: usize,
    /// Deterministic annealing: the first E step uses standard deviations this many times the
    /// sensor's, halved at every step down to 1, so that a hypothesis initialised on a few
    /// points reaches the ends of its wall instead of settling on the stretch it started
    /// from. 1 disables it. Default 8. Sensible: 1..16.
    pub anneal_sigma_scale: f64,
    /// Range noise standard deviation at zero range, m. Default 0.005. Sensible: 0.001..0.02.
    pub noise_sigma: f64,
    /// Growth of the noise standard deviation with range, m per m. Default 0.005 (the
    /// URG-04LX's +-1 % read as two standard deviations). Sensible: 0..0.02.
    pub noise_sigma_per_metre: f64,
    /// Density of the uniform outlier class over distances to the line, 1/m. Default 1
    /// (tuned; outliers spread over about 1 m). Sensible: 0.05..5. With the default
    /// `inlier_probability`, a point then joins the line when it lies within about 2.4
    /// standard deviations of it (with `pi = 0.1` and a standard deviation of 6 mm).
    pub outlier_density: f64,
    /// Smallest posterior probability for a point to be a member of the line. Default 0.3
    /// (tuned).
    /// In (0, 1).
    pub inlier_probability: f64,
    /// Consecutive non-members tolerated inside a run (kept in its beam range, not used in its
    /// fit). Default 2. Sensible: 0..5.
    pub max_skipped: usize,
    /// The breakpoint detector that cuts clusters and runs (Borges and Aldon). Default 10
    /// deg, 0.01 m of noise, at most 2 missing beams.
    pub breakpoints: Breakpoints,
    /// The final filter. Default 8 (tuned) points, 0.15 m (tuned).
    pub filter: LineFilter,
    /// Extra limits on valid ranges, on top of the scan's own `range_min..range_max`.
    /// Default none.
    pub range_limits: Option<RangeWindow>,
}

impl Default for EmParams {
    fn default() -> Self {
        Self {
            seed: 0x5EED,
            max_trials: 100,
            max_failures: 20,
            init_points: 10,
            iterations: 20,
            anneal_sigma_scale: 8.0,
            noise_sigma: 0.005,
            noise_sigma_per_metre: 0.005,
            outlier_density: 1.0,
            inlier_probability: 0.3,
            max_skipped: 2,
            breakpoints: Breakpoints::default(),
            filter: LineFilter::default(),
            range_limits: None,
        }
    }
}

impl EmParams {
    /// Checks every field.
    ///
    /// # Errors
    /// A [`ParamsError`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ParamsError> {
        params::range_limits(self.range_limits)?;
        params::at_least("max_trials", self.max_trials, 1)?;
        params::at_least("max_failures", self.max_failures, 1)?;
        params::at_least("init_points", self.init_points, 2)?;
        params::at_least("iterations", self.iterations, 1)?;
        if !(self.anneal_sigma_scale.is_finite() && self.anneal_sigma_scale >= 1.0) {
            return Err(ParamsError::Below {
                field: "anneal_sigma_scale",
                value: self.anneal_sigma_scale,
                min: 1.0,
            });
        }
        params::scaled(
            ("noise_sigma", self.noise_sigma),
            ("noise_sigma_per_metre", self.noise_sigma_per_metre),
        )?;
        params::positive("outlier_density", self.outlier_density)?;
        params::inside("inlier_probability", self.inlier_probability, 0.0, 1.0)?;
        self.breakpoints.validate()?;
        self.filter.validate()
    }
}

/// Smallest standard deviation used, m (guards against ranges so small that the noise model
/// gives zero).
const MIN_SIGMA: f64 = 1e-6;
/// The line has stopped moving when neither its distance nor its normal changes by more.
const CONVERGED: f64 = 1e-9;

/// Weighted total least squares, two-pass; `None` for a degenerate or non-finite set.
fn weighted_fit(points: &[ScanPoint], weights: &[f64], free: &[usize]) -> Option<Hypothesis> {
    let (mut w, mut sx, mut sy) = (0.0, 0.0, 0.0);
    for &i in free {
        let wi = weights[i];
        if wi > 0.0 {
            w += wi;
            sx += wi * points[i].point.x;
            sy += wi * points[i].point.y;
        }
    }
    if w.is_nan() || w <= 0.0 {
        return None;
    }
    let (cx, cy) = (sx / w, sy / w);
    let (mut mxx, mut myy, mut mxy) = (0.0, 0.0, 0.0);
    for &i in free {
        let wi = weights[i];
        if wi > 0.0 {
            let (dx, dy) = (points[i].point.x - cx, points[i].point.y - cy);
            mxx += wi * dx * dx;
            myy += wi * dy * dy;
            mxy += wi * dx * dy;
        }
    }
    if !(cx.is_finite() && cy.is_finite() && mxx.is_finite() && myy.is_finite() && mxy.is_finite())
    {
        return None;
    }
    let half_tr = 0.5 * (mxx + myy);
    let disc = (0.25 * (mxx - myy) * (mxx - myy) + mxy * mxy).sqrt();
    let spread = half_tr + disc;
    if spread.is_nan() || spread <= f64::EPSILON * w * (1.0 + cx.abs() + cy.abs()) {
        return None;
    }
    let alpha = 0.5 * (-2.0 * mxy).atan2(myy - mxx);
    let normal = Vector2::new(alpha.cos(), alpha.sin());
    Some(Hypothesis {
        normal,
        d: cx * normal.x + cy * normal.y,
    })
}

/// EM line extraction (see the module docs). Reuse one value across scans: its working memory
/// is kept.
#[derive(Debug, Clone)]
pub struct Em {
    params: EmParams,
    points: Vec<ScanPoint>,
    free: Vec<usize>,
    taken: Vec<bool>,
    weight: Vec<f64>,
    member: Vec<bool>,
    found: Vec<Run>,
    runs: Vec<Run>,
}

impl Em {
    /// An extractor with validated parameters.
    ///
    /// # Errors
    /// [`ParamsError`] when a parameter is out of its domain.
    pub fn new(params: EmParams) -> Result<Self, ParamsError> {
        params.validate()?;
        Ok(Self {
            params,
            points: Vec::new(),
            free: Vec::new(),
            taken: Vec::new(),
            weight: Vec::new(),
            member: Vec::new(),
            found: Vec::new(),
            runs: Vec::new(),
        })
    }

    /// The parameters in use.
    #[must_use]
    pub fn params(&self) -> &EmParams {
        &self.params
    }

    /// E step: posterior weights of the free points for line `h` with share `pi`, standard
    /// deviations scaled by `scale`; returns the sum of the weights.
    fn expect(&mut self, h: &Hypothesis, pi: f64, scale: f64) -> f64 {
        let p = &self.params;
        let norm = (2.0 * std::f64::consts::PI).sqrt();
        let mut total = 0.0;
        for &i in &self.free {
            let sp = &self.points[i];
            let sigma =
                (scale * (p.noise_sigma + p.noise_sigma_per_metre * sp.range)).max(MIN_SIGMA);
            let d = h.distance(sp.point) / sigma;
            let line = pi * (-0.5 * d * d).exp() / (norm * sigma);
            let w = line / (line + (1.0 - pi) * p.outlier_density);
            let w = if w.is_finite() { w } else { 0.0 };
            self.weight[i] = w;
            total += w;
        }
        total
    }

    /// Runs EM from hypothesis `h`, the first E step's standard deviations `scale` times the
    /// sensor's; returns the final line (weights left in `self.weight`).
    fn converge(&mut self, mut h: Hypothesis, mut scale: f64) -> Option<Hypothesis> {
        let mut pi = 0.5;
        for _ in 0..self.params.iterations {
            let total = self.expect(&h, pi, scale);
            let next = weighted_fit(&self.points, &self.weight, &self.free)?;
            pi = (total / self.free.len() as f64).clamp(1e-9, 1.0 - 1e-9);
            // Compare in the same orientation of the normal.
            let (n, d) = if next.normal.dot(&h.normal) < 0.0 {
                (-next.normal, -next.d)
            } else {
                (next.normal, next.d)
            };
            let moved = (d - h.d).abs() + (n - h.normal).norm();
            h = Hypothesis { normal: n, d };
            if scale > 1.0 {
                scale = (0.5 * scale).max(1.0);
            } else if moved < CONVERGED {
                break;
            }
        }
        self.expect(&h, pi, 1.0);
        Some(h)
    }

    /// One hypothesis from `init`: converges it and leaves its runs in `self.found`.
    fn hypothesis(&mut self, init: Option<Hypothesis>, scale: f64, min_members: usize) {
        self.found.clear();
        if init.and_then(|h| self.converge(h, scale)).is_none() {
            return;
        }
        let p = &self.params;
        let (points, taken, weight) = (&self.points, &self.taken, &self.weight);
        runs_with_members(
            points,
            |i| !taken[i],
            |i| weight[i] >= p.inlier_probability,
            &p.breakpoints,
            p.max_skipped,
            min_members,
            &mut self.found,
        );
        // Runs start and end at members, so their ends give the line's length.
        let min_length = p.filter.min_length;
        self.found
            .retain(|r| (points[r.end - 1].point - points[r.start].point).norm() >= min_length);
    }
}

impl LineExtractor for Em {
    fn name(&self) -> &'static str {
        "em"
    }

    fn extract_view_into(&mut self, scan: ScanView<'_>, out: &mut Vec<Line>) {
        out.clear();
        let p = self.params.clone();
        scan.points_into(scan.range_window(p.range_limits), &mut self.points);
        let n = self.points.len();
        let rule = p.breakpoints;
        self.taken.clear();
        self.taken.resize(n, false);
        self.member.clear();
        self.member.resize(n, false);
        self.weight.clear();
        self.weight.resize(n, 0.0);
        self.runs.clear();
        let min_members = p.filter.min_points.max(2);
        let mut rng = SplitMix64::new(p.seed);
        let mut failures = 0;
        for _ in 0..p.max_trials {
            self.free.clear();
            self.free.extend((0..n).filter(|&i| !self.taken[i]));
            let len = self.free.len();
            if len < min_members.max(p.init_points) {
                break;
            }
            let start = rng.below(len).min(len - p.init_points);
            let init = FitSums::from_points(
                self.free[start..start + p.init_points]
                    .iter()
                    .map(|&i| self.points[i].point),
            )
            .fit();
            let init = init.map(|fit| Hypothesis::from_fit(&fit));
            self.hypothesis(init, p.anneal_sigma_scale, min_members);
            if self.found.is_empty() && p.anneal_sigma_scale > 1.0 {
                // The annealed line may have settled between two close walls: once more
                // from the same start without annealing.
                self.hypothesis(init, 1.0, min_members);
            }
            if self.found.is_empty() {
                failures += 1;
                if failures >= p.max_failures {
                    break;
                }
                continue;
            }
            failures = 0;
            for &r in &self.found {
                for i in r.start..r.end {
                    self.member[i] = self.weight[i] >= p.inlier_probability;
                    self.taken[i] = true;
                }
                self.runs.push(r);
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
