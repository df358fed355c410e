//! The one least-squares line fit every extractor ends with: total least squares in polar form
//! `x cos(alpha) + y sin(alpha) = r`, `r >= 0`, with the 2x2 covariance of `(r, alpha)`.
//!
//! The covariance follows the usual first-order propagation for isotropic point noise
//! (Arras & Siegwart 1997; Pfister et al. 2003), with the noise variance estimated from the
//! residuals: `s2 = SSE / (n - 2)`. With `t0` the position of the centroid along the line
//! direction `(-sin alpha, cos alpha)` and `Stt` the spread of the points along the line,
//!
//! ```text
//! var(alpha)      = s2 / Stt
//! var(r)          = s2 / n + t0^2 var(alpha)
//! cov(r, alpha)   = t0 var(alpha)
//! ```

use crate::math::{Matrix2, Point2, Vector2, wrap_angle};

/// Running sums of a point set, enough for a total-least-squares fit. Points can be added
/// and removed in O(1), which incremental extractors use.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FitSums {
    n: usize,
    sx: f64,
    sy: f64,
    sxx: f64,
    syy: f64,
    sxy: f64,
}

impl FitSums {
    /// Empty sums.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            n: 0,
            sx: 0.0,
            sy: 0.0,
            sxx: 0.0,
            syy: 0.0,
            sxy: 0.0,
        }
    }

    /// Sums over the given points.
    #[must_use]
    pub fn from_points<I: IntoIterator<Item = Point2>>(points: I) -> Self {
        let mut s = Self::new();
        for p in points {
            s.add(p);
        }
        s
    }

    /// Adds a point.
    pub fn add(&mut self, p: Point2) {
        self.n += 1;
        self.sx += p.x;
        self.sy += p.y;
        self.sxx += p.x * p.x;
        self.syy += p.y * p.y;
        self.sxy += p.x * p.y;
    }

    /// Removes a point previously added.
    pub fn remove(&mut self, p: Point2) {
        self.n = self.n.saturating_sub(1);
        self.sx -= p.x;
        self.sy -= p.y;
        self.sxx -= p.x * p.x;
        self.syy -= p.y * p.y;
        self.sxy -= p.x * p.y;
    }

    /// The sums of the points in `self` but not in `earlier`, where `earlier` holds a prefix
    /// of the points added to `self` (prefix sums: `sums[to].since(&sums[from])`).
    #[must_use]
    pub fn since(&self, earlier: &Self) -> Self {
        Self {
            n: self.n.saturating_sub(earlier.n),
            sx: self.sx - earlier.sx,
            sy: self.sy - earlier.sy,
            sxx: self.sxx - earlier.sxx,
            syy: self.syy - earlier.syy,
            sxy: self.sxy - earlier.sxy,
        }
    }

    /// The sums of the points of `self` and of `other` together (two disjoint point sets).
    #[must_use]
    pub fn join(&self, other: &Self) -> Self {
        Self {
            n: self.n + other.n,
            sx: self.sx + other.sx,
            sy: self.sy + other.sy,
            sxx: self.sxx + other.sxx,
            syy: self.syy + other.syy,
            sxy: self.sxy + other.sxy,
        }
    }

    /// The sum of squared distances of the points from the line `p . normal = r` (`normal` a
    /// unit vector), m^2.
    #[must_use]
    pub fn sse_about(&self, normal: Vector2, r: f64) -> f64 {
        let (c, s) = (normal.x, normal.y);
        let sq = c * c * self.sxx + 2.0 * c * s * self.sxy + s * s * self.syy
            - 2.0 * r * (c * self.sx + s * self.sy)
            + self.n as f64 * r * r;
        sq.max(0.0)
    }

    /// Number of points.
    #[must_use]
    pub const fn len(&self) -> usize {
        self.n
    }

    /// True when no point was added.
    #[must_use]
    pub const fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// The sum of squared orthogonal residuals of the best line through the points, m^2
    /// (0 for fewer than three points or non-finite sums): what [`FitSums::fit`] would give
    /// as `n * rms^2` (to rounding), at the cost of one square root and two divisions. The smaller
    /// eigenvalue of the scatter matrix is taken as its determinant over the larger one,
    /// which keeps it accurate for nearly perfect lines far from the origin.
    #[must_use]
    pub fn sse(&self) -> f64 {
        if self.n < 3 {
            return 0.0;
        }
        let inv = 1.0 / self.n as f64;
        let (cx, cy) = (self.sx * inv, self.sy * inv);
        let mxx = (self.sxx - self.sx * cx).max(0.0);
        let myy = (self.syy - self.sy * cy).max(0.0);
        let mxy = self.sxy - self.sx * cy;
        let half_tr = 0.5 * (mxx + myy);
        let disc = (0.25 * (mxx - myy) * (mxx - myy) + mxy * mxy).sqrt();
        let big = half_tr + disc;
        let v = if big > 0.0 {
            ((mxx * myy - mxy * mxy) / big).max(0.0)
        } else {
            0.0
        };
        if v.is_finite() { v } else { 0.0 }
    }

    /// The squared cosine of the angle between the normal of the best line through the
    /// points and the direction of their centroid from the origin, `(r / |centroid|)^2` of
    /// [`FitSums::fit`], without the line: the normal's projector is `(l1 I - M) / (l1 - l2)`
    /// for the centred scatter matrix `M` of eigenvalues `l1 >= l2`. `None` where `fit` gives
    /// no line, where the scatter has no direction (`l1 = l2`) and at the origin.
    #[must_use]
    pub fn incidence_cos2(&self) -> Option<f64> {
        if self.n < 2 {
            return None;
        }
        let inv = 1.0 / self.n as f64;
        let (cx, cy) = (self.sx * inv, self.sy * inv);
        let s = self.scatter(cx, cy)?;
        let c2 = cx * cx + cy * cy;
        let gap = s.spread - s.lambda;
        if !(c2 > 0.0 && gap > 0.0) {
            return None;
        }
        let along = s.mxx * cx * cx + 2.0 * s.mxy * cx * cy + s.myy * cy * cy;
        Some(((s.spread * c2 - along) / (gap * c2)).clamp(0.0, 1.0))
    }

    /// The squared distance of the centroid from the origin, m^2 (0 when empty).
    #[must_use]
    pub fn centroid_norm_squared(&self) -> f64 {
        if self.n == 0 {
            return 0.0;
        }
        let inv = 1.0 / self.n as f64;
        let (cx, cy) = (self.sx * inv, self.sy * inv);
        cx * cx + cy * cy
    }

    /// The centroid of the points (`None` when empty).
    #[must_use]
    pub fn centroid(&self) -> Option<Point2> {
        (self.n > 0).then(|| Point2::new(self.sx / self.n as f64, self.sy / self.n as f64))
    }

    /// The fit, or `None` for fewer than two points or a degenerate set (all points equal,
    /// or non-finite sums).
    #[must_use]
    pub fn fit(&self) -> Option<PolarFit> {
        if self.n < 2 {
            return None;
        }
        let n = self.n as f64;
        let cx = self.sx / n;
        let cy = self.sy / n;
        let Scatter {
            mxx,
            myy,
            mxy,
            spread,
            sse,
            ..
        } = self.scatter(cx, cy)?;
        let mut alpha = 0.5 * (-2.0 * mxy).atan2(myy - mxx);
        // One sine and cosine: turning the normal by pi only flips their signs.
        let (mut sin, mut cos) = alpha.sin_cos();
        let mut r = cx * cos + cy * sin;
        if r < 0.0 {
            r = -r;
            alpha += std::f64::consts::PI;
            (sin, cos) = (-sin, -cos);
        }
        alpha = wrap_angle(alpha);
        let s2 = if self.n > 2 { sse / (n - 2.0) } else { 0.0 };
        let var_alpha = s2 / spread;
        let t0 = -cx * sin + cy * cos;
        let covariance = Matrix2::new(
            s2 / n + t0 * t0 * var_alpha,
            t0 * var_alpha,
            t0 * var_alpha,
            var_alpha,
        );
        Some(PolarFit {
            r,
            alpha,
            centroid: Point2::new(cx, cy),
            n: self.n,
            rms: (sse / n).sqrt(),
            covariance,
            spread,
        })
    }
}

/// The scatter matrix of a point set about its centroid and its eigenvalues
/// ([`FitSums::scatter`]).
struct Scatter {
    mxx: f64,
    myy: f64,
    mxy: f64,
    /// The larger eigenvalue: the spread along the line.
    spread: f64,
    /// The smaller eigenvalue, at least 0: the squared residuals across the line.
    sse: f64,
    /// The smaller eigenvalue as computed (it may round below 0).
    lambda: f64,
}

impl FitSums {
    /// The central second moments about the centroid `(cx, cy)` and their eigenvalues;
    /// `None` when any is not finite or the points do not spread (all at one place, to
    /// rounding).
    #[inline]
    fn scatter(&self, cx: f64, cy: f64) -> Option<Scatter> {
        let mxx = (self.sxx - self.sx * cx).max(0.0);
        let myy = (self.syy - self.sy * cy).max(0.0);
        let mxy = self.sxy - self.sx * cy;
        if !(cx.is_finite()
            && cy.is_finite()
            && mxx.is_finite()
            && myy.is_finite()
            && mxy.is_finite())
        {
            return None;
        }
        let half_tr = 0.5 * (mxx + myy);
        let disc = (0.25 * (mxx - myy) * (mxx - myy) + mxy * mxy).sqrt();
        let spread = half_tr + disc;
        let lambda = half_tr - disc;
        if spread <= f64::EPSILON * (1.0 + cx.abs() + cy.abs()) {
            return None;
        }
        Some(Scatter {
            mxx,
            myy,
            mxy,
            spread,
            sse: lambda.max(0.0),
            lambda,
        })
    }
}

impl FitSums {
    /// The same line as [`FitSums::fit`] without its angle: the unit normal is the
    /// eigenvector of the scatter matrix's smaller eigenvalue (one square root more than the
    /// eigenvalues), so no trigonometry is needed. `None` in the same cases as
    /// [`FitSums::fit`]. The normal agrees with `fit`'s to rounding.
    #[must_use]
    pub fn normal_fit(&self) -> Option<NormalFit> {
        if self.n < 2 {
            return None;
        }
        let n = self.n as f64;
        let inv = 1.0 / n;
        let (cx, cy) = (self.sx * inv, self.sy * inv);
        let Scatter {
            mxx,
            myy,
            mxy,
            spread,
            sse,
            lambda,
        } = self.scatter(cx, cy)?;
        // (M - lambda I) v = 0 for the smaller eigenvalue lambda, from the row whose diagonal
        // term is farther from lambda (no cancellation: both terms have one sign).
        let (vx, vy) = if mxx >= myy {
            (mxy, lambda - mxx)
        } else {
            (lambda - myy, mxy)
        };
        let scale = 1.0 / (vx * vx + vy * vy).sqrt();
        let (mut cos, mut sin) = (vx * scale, vy * scale);
        let mut r = cx * cos + cy * sin;
        if r < 0.0 {
            r = -r;
            (cos, sin) = (-cos, -sin);
        }
        let s2 = if self.n > 2 { sse / (n - 2.0) } else { 0.0 };
        let var_alpha = s2 / spread;
        let t0 = -cx * sin + cy * cos;
        Some(NormalFit {
            normal: Vector2::new(cos, sin),
            r,
            n: self.n,
            s2,
            covariance: Matrix2::new(
                s2 * inv + t0 * t0 * var_alpha,
                t0 * var_alpha,
                t0 * var_alpha,
                var_alpha,
            ),
        })
    }
}

/// A fitted infinite line `p . normal = r` without its angle ([`FitSums::normal_fit`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalFit {
    /// Unit normal `(cos alpha, sin alpha)`.
    pub normal: Vector2,
    /// Distance of the line from the origin, m (`>= 0`).
    pub r: f64,
    /// Number of fitted points.
    pub n: usize,
    /// Residual variance `SSE / (n - 2)`, m^2 (0 for two points).
    pub s2: f64,
    /// Covariance of `(r, alpha)`: m^2, m rad, rad^2.
    pub covariance: Matrix2,
}

impl NormalFit {
    /// Signed orthogonal distance of `p` from the line, m.
    #[inline]
    #[must_use]
    pub fn distance(&self, p: Point2) -> f64 {
        p.coords.dot(&self.normal) - self.r
    }
}

/// A fitted infinite line in polar form.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PolarFit {
    /// Distance of the line from the origin, m (`>= 0`).
    pub r: f64,
    /// Direction of the line's normal, rad, in `(-pi, pi]`.
    pub alpha: f64,
    /// Centroid of the fitted points, m.
    pub centroid: Point2,
    /// Number of fitted points.
    pub n: usize,
    /// Root-mean-square orthogonal residual, m.
    pub rms: f64,
    /// Covariance of `(r, alpha)`: m^2, m rad, rad^2.
    pub covariance: Matrix2,
    /// Scatter of the points along the line (sum of squared distances of the points from
    /// their centroid, along the line), m^2.
    pub spread: f64,
}

impl PolarFit {
    /// Unit normal `(cos alpha, sin alpha)`.
    #[must_use]
    pub fn normal(&self) -> Vector2 {
        Vector2::new(self.alpha.cos(), self.alpha.sin())
    }

    /// Signed orthogonal distance of `p` from the line, m.
    #[must_use]
    pub fn distance(&self, p: Point2) -> f64 {
        p.coords.dot(&self.normal()) - self.r
    }

    /// [`PolarFit::distance`] as a function with the normal computed once, for loops over
    /// many points (the same values, bit for bit).
    pub fn distance_fn(&self) -> impl Fn(Point2) -> f64 + Copy + use<> {
        let (normal, r) = (self.normal(), self.r);
        move |p: Point2| p.coords.dot(&normal) - r
    }

    /// The covariance of `(r, alpha)` for point noise of variance `s2` (m^2) across the line
    /// (the formulas of the module docs with `s2` in place of the residual variance).
    #[must_use]
    pub fn covariance_for(&self, s2: f64) -> Matrix2 {
        let var_alpha = s2 / self.spread;
        let (sin, cos) = self.alpha.sin_cos();
        let t0 = -self.centroid.x * sin + self.centroid.y * cos;
        Matrix2::new(
            s2 / self.n as f64 + t0 * t0 * var_alpha,
            t0 * var_alpha,
            t0 * var_alpha,
            var_alpha,
        )
    }

    /// Orthogonal projection of `p` onto the line.
    #[must_use]
    pub fn project(&self, p: Point2) -> Point2 {
        p - self.normal() * self.distance(p)
    }
}

/// Fits a line to a slice of points. See [`FitSums::fit`].
#[must_use]
pub fn fit_points(points: &[Point2]) -> Option<PolarFit> {
    FitSums::from_points(points.iter().copied()).fit()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_a_known_line_exactly() {
        // Points on x = 2 (r = 2, alpha = 0).
        let pts: Vec<Point2> = (0..10)
            .map(|i| Point2::new(2.0, -1.0 + 0.2 * i as f64))
            .collect();
        let f = fit_points(&pts).unwrap();
        assert!((f.r - 2.0).abs() < 1e-12);
        assert!(f.alpha.abs() < 1e-12);
        assert!(f.rms < 1e-12);
        // Points on y = -3 (r = 3, alpha = -pi/2).
        let pts: Vec<Point2> = (0..10).map(|i| Point2::new(i as f64, -3.0)).collect();
        let f = fit_points(&pts).unwrap();
        assert!((f.r - 3.0).abs() < 1e-12);
        assert!((f.alpha + std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }

    #[test]
    fn distance_fn_gives_distance_bit_for_bit() {
        let pts: Vec<Point2> = (0..12)
            .map(|i| Point2::new(1.0 + 0.3 * f64::from(i), -2.0 + 0.11 * f64::from(i * i % 5)))
            .collect();
        let f = fit_points(&pts).unwrap();
        let d = f.distance_fn();
        for p in pts
            .iter()
            .chain([Point2::origin(), Point2::new(-7.5, 3.25)].iter())
        {
            assert_eq!(d(*p).to_bits(), f.distance(*p).to_bits(), "{p}");
        }
    }

    #[test]
    fn covariance_matches_hand_computed_values() {
        // Three points on y = 1 with residuals +e, -2e, +e: SSE = 6e^2, s2 = 6e^2, Stt = 2.
        let e = 0.01;
        let pts = [
            Point2::new(-1.0, 1.0 + e),
            Point2::new(0.0, 1.0 - 2.0 * e),
            Point2::new(1.0, 1.0 + e),
        ];
        let f = fit_points(&pts).unwrap();
        assert!((f.r - 1.0).abs() < 1e-12);
        let s2 = 6.0 * e * e;
        assert!((f.covariance[(1, 1)] - s2 / 2.0).abs() < 1e-12);
        // Centroid at the foot of the normal: t0 = 0, so var(r) = s2 / 3, no correlation.
        assert!((f.covariance[(0, 0)] - s2 / 3.0).abs() < 1e-12);
        assert!(f.covariance[(0, 1)].abs() < 1e-12);
        assert!((f.rms - (6.0 * e * e / 3.0f64).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn removing_points_restores_sums() {
        let mut s = FitSums::new();
        s.add(Point2::new(1.0, 2.0));
        s.add(Point2::new(3.0, 4.0));
        let before = s;
        s.add(Point2::new(5.0, -1.0));
        s.remove(Point2::new(5.0, -1.0));
        assert_eq!(s.len(), before.len());
        assert!((s.sxx - before.sxx).abs() < 1e-12);
    }

    #[test]
    fn sse_matches_the_fit() {
        let pts: Vec<Point2> = (0..20)
            .map(|i| {
                let t = f64::from(i) * 0.1;
                Point2::new(30.0 + t, 20.0 - 0.5 * t + 0.003 * f64::from(i % 3))
            })
            .collect();
        let s = FitSums::from_points(pts.iter().copied());
        let f = s.fit().unwrap();
        let by_fit = f.rms * f.rms * 20.0;
        assert!(
            (s.sse() - by_fit).abs() < 1e-9 * (1.0 + by_fit),
            "{} {by_fit}",
            s.sse()
        );
        let direct: f64 = pts.iter().map(|p| f.distance(*p).powi(2)).sum();
        assert!((s.sse() - direct).abs() < 1e-9);
        assert_eq!(FitSums::from_points(pts[..2].iter().copied()).sse(), 0.0);
    }

    #[test]
    fn covariance_for_a_given_noise() {
        let pts: Vec<Point2> = (0..10)
            .map(|i| Point2::new(2.0, f64::from(i) * 0.1))
            .collect();
        let f = fit_points(&pts).unwrap();
        assert!(f.covariance[(1, 1)] < 1e-20);
        let c = f.covariance_for(1e-4);
        // var(alpha) = s2 / Stt with Stt = 0.825 m^2; t0 = 0.45 m (centroid along the line).
        assert!((f.spread - 0.825).abs() < 1e-12);
        assert!((c[(1, 1)] - 1e-4 / 0.825).abs() < 1e-12);
        assert!((c[(0, 0)] - (1e-5 + 0.45 * 0.45 * 1e-4 / 0.825)).abs() < 1e-12);
        // With the residual variance, the fit's own covariance.
        let noisy: Vec<Point2> = (0..10)
            .map(|i| Point2::new(2.0 + 0.01 * f64::from(i % 2), f64::from(i) * 0.1))
            .collect();
        let g = fit_points(&noisy).unwrap();
        let s2 = g.rms * g.rms * 10.0 / 8.0;
        assert!((g.covariance_for(s2) - g.covariance).norm() < 1e-15);
    }

    #[test]
    fn normal_fit_agrees_with_the_fit() {
        for (k, slope) in [0.0, 0.3, -2.0, 1e3, -1e-3].iter().enumerate() {
            let pts: Vec<Point2> = (0..25)
                .map(|i| {
                    let t = f64::from(i) * 0.07;
                    let wiggle = 0.004 * f64::from((i * 7 + k as i32) % 5) - 0.008;
                    Point2::new(1.5 + t, -0.7 + slope * t + wiggle)
                })
                .collect();
            let s = FitSums::from_points(pts.iter().copied());
            let (f, g) = (s.fit().unwrap(), s.normal_fit().unwrap());
            assert!((g.normal - f.normal()).norm() < 1e-12, "{slope}");
            assert!((g.r - f.r).abs() < 1e-12 && g.n == f.n);
            let s2 = f.rms * f.rms * 25.0 / 23.0;
            assert!((g.s2 - s2).abs() < 1e-12 * (1.0 + s2));
            assert!((g.covariance - f.covariance).norm() < 1e-12 * (1.0 + f.covariance.norm()));
            for p in &pts {
                assert!((g.distance(*p) - f.distance(*p)).abs() < 1e-12);
            }
            let c = f.centroid.coords;
            let cos2 = (c.dot(&f.normal()) / c.norm()).powi(2);
            assert!((s.incidence_cos2().unwrap() - cos2).abs() < 1e-9, "{slope}");
        }
        // Points on a line through the origin: the beams run along it.
        let radial =
            FitSums::from_points((1..9).map(|i| Point2::new(f64::from(i), 2.0 * f64::from(i))));
        assert!(radial.incidence_cos2().unwrap() < 1e-12);
        assert!(
            FitSums::from_points([Point2::new(1.0, 1.0); 3])
                .incidence_cos2()
                .is_none()
        );
        assert!(fit_points(&[Point2::new(1.0, 1.0); 3]).is_none());
        assert!(
            FitSums::from_points([Point2::new(1.0, 1.0); 3])
                .normal_fit()
                .is_none()
        );
    }

    #[test]
    fn degenerate_sets_give_none() {
        assert!(fit_points(&[]).is_none());
        assert!(fit_points(&[Point2::new(1.0, 1.0)]).is_none());
        assert!(fit_points(&[Point2::new(1.0, 1.0), Point2::new(1.0, 1.0)]).is_none());
        assert!(fit_points(&[Point2::new(f64::NAN, 1.0), Point2::new(1.0, 1.0)]).is_none());
    }
}
