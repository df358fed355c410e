//! Line-to-line matching, the paper's "feature to feature": the pose that brings one scan's
//! extracted lines onto another's, from their polar forms `(r, alpha)` and covariances.
//!
//! A scan line moved by the pose `(x, y, theta)` has `alpha' = alpha + theta` and
//! `r' = r + x cos(alpha') + y sin(alpha')`. Each round pairs every scan line with the
//! reference line nearest in Mahalanobis distance (under both lines' covariances) among
//! those within the gates and overlapping it, then takes one weighted Gauss-Newton step on
//! the `(r, alpha)` differences. At least two pairs that are not parallel fix a pose.

use laserlines::Line;
use laserlines::math::{Matrix2, Point2, Vector2, wrap_angle};
use nalgebra::{Matrix2x3, Matrix3, Vector3};

use crate::se2::Se2;

/// Settings of [`match_lines`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineMatchParams {
    /// Largest difference of normals of a pair, rad (default 0.2).
    pub max_angle_rad: f64,
    /// Largest difference of `r` of a pair, m (default 0.3).
    pub max_distance_m: f64,
    /// Rounds of pairing and solving (default 8).
    pub iterations: usize,
    /// Floor of each line's standard deviations, `(m, rad)` (default 0.01 m, 0.005 rad): the
    /// covariances of long lines are tiny, their placement between scans is not.
    pub sigma_floor: (f64, f64),
}

impl Default for LineMatchParams {
    fn default() -> Self {
        Self {
            max_angle_rad: 0.2,
            max_distance_m: 0.3,
            iterations: 8,
            sigma_floor: (0.01, 0.005),
        }
    }
}

/// The pose found and how it was found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineMatch {
    /// `reference_from_scan`.
    pub pose: Se2,
    /// Covariance of `(x, y, theta)`.
    pub covariance: Matrix3<f64>,
    /// Line pairs in the final round.
    pub pairs: usize,
}

/// Matches the lines of a scan onto those of a reference, starting from `guess`
/// (`reference_from_scan`). `None` when the pairs do not fix every direction of the pose.
#[must_use]
pub fn match_lines(
    reference: &[Line],
    scan: &[Line],
    guess: Se2,
    params: &LineMatchParams,
) -> Option<LineMatch> {
    let mut pose = guess;
    let floor = Matrix2::new(
        params.sigma_floor.0.powi(2),
        0.0,
        0.0,
        params.sigma_floor.1.powi(2),
    );
    let mut last = None;
    for _ in 0..params.iterations.max(1) {
        let mut h = Matrix3::zeros();
        let mut g = Vector3::zeros();
        let mut pairs = 0;
        for l in scan {
            let (r, alpha) = moved(l, &pose);
            let (a, b) = (pose.transform(l.start), pose.transform(l.end));
            let mut best: Option<(f64, Vector3<f64>, Matrix2x3<f64>, Matrix2)> = None;
            for m in reference {
                let da = wrap_angle(alpha - m.alpha);
                let dr = r - m.r;
                if da.abs() > params.max_angle_rad
                    || dr.abs() > params.max_distance_m
                    || !overlaps(m, a, b)
                {
                    continue;
                }
                let cov = m.covariance + l.covariance + floor;
                let Some(w) = cov.try_inverse() else { continue };
                let e = nalgebra::Vector2::new(dr, da);
                let d2 = (e.transpose() * w * e)[0];
                if best.as_ref().is_none_or(|b| d2 < b.0) {
                    let j = Matrix2x3::new(
                        alpha.cos(),
                        alpha.sin(),
                        -pose.x * alpha.sin() + pose.y * alpha.cos(),
                        0.0,
                        0.0,
                        1.0,
                    );
                    best = Some((d2, Vector3::new(dr, da, 0.0), j, w));
                }
            }
            if let Some((_, e, j, w)) = best {
                let e2 = nalgebra::Vector2::new(e[0], e[1]);
                h += j.transpose() * w * j;
                g += j.transpose() * w * e2;
                pairs += 1;
            }
        }
        if pairs < 2 {
            return None;
        }
        let eig = h.symmetric_eigenvalues();
        if eig.min().partial_cmp(&(1e-9 * eig.max())) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let chol = h.cholesky()?;
        let step = chol.solve(&(-g));
        pose = Se2::new(pose.x + step[0], pose.y + step[1], pose.theta + step[2]);
        last = Some((h, pairs));
    }
    let (h, pairs) = last?;
    Some(LineMatch {
        pose,
        covariance: h.try_inverse()?,
        pairs,
    })
}

/// `(r, alpha)` of a scan line moved by `pose`.
fn moved(l: &Line, pose: &Se2) -> (f64, f64) {
    let alpha = wrap_angle(l.alpha + pose.theta);
    (l.r + pose.x * alpha.cos() + pose.y * alpha.sin(), alpha)
}

/// True when the segment `a`-`b` (reference frame) overlaps the reference line `m` along
/// its direction.
fn overlaps(m: &Line, a: Point2, b: Point2) -> bool {
    let d: Vector2 = m.end - m.start;
    let len2 = d.norm_squared();
    if len2 <= 0.0 {
        return false;
    }
    let (ta, tb) = ((a - m.start).dot(&d) / len2, (b - m.start).dot(&d) / len2);
    ta.max(tb) >= 0.0 && ta.min(tb) <= 1.0
}
