//! Step 6: from the split tree's pieces to lines: the merge of neighbours that are one line,
//! where each line ends, the least-squares fits with their covariance, and the filters that
//! keep surfaces and drop legs, posts and clutter.

use super::arcs::drop_arcs;
use super::corners::{Seen, join_corners};
use super::linseg::{rms_passes, split_is_significant, sums, within_noise};
use super::opening;
use super::params::HoughSplitParams;
use super::points::Seg;
use crate::fit::{FitSums, PolarFit};
use crate::line::Line;
use crate::math::{Matrix2, Point2, Vector2};
use crate::noise::RangeNoise;

/// Points between two lines of one data segment below which the second follows the first
/// ([`Candidate::follows`]): none, or a lone point off both (a spike that the split cut out).
const GAP_POINTS: usize = 2;

/// Longest distance, m, between the last supporting point of one line and the first of the
/// next across beams that all returned nothing for the second to follow the first across
/// data segments ([`follows_across_silence`]): a dark patch, a socket or a sticker on a
/// wall, or a cable or mast of the robot in front of it, and no doorway.
pub const SILENT_GAP: f64 = 0.2;

/// True when `next` follows `prev` (the last line of the data segment before) across beams
/// that all returned nothing: at least one beam lies between them, none of them has a range
/// of at least `lo` (the smallest valid range; a NaN, a zero, a reading nearer than the
/// robot's own body), so none saw anything in front of the surface or through it (a reading
/// beyond the range limit, `+inf`, sees through), and `next`'s first supporting point lies
/// within [`SILENT_GAP`] of `prev`'s last (`prev.ends.1`, `next.ends.0`). The bridge of the
/// data segments reaches at most `bridge_max_gap` missing beams; with one shared fit, such
/// lines are then one line ([`super::collinear`]).
pub(crate) fn follows_across_silence(
    ranges: &[f64],
    lo: f64,
    (prev, next): (&Line, &Line),
    (last, first): (Point2, Point2),
) -> bool {
    // `lo` is finite: the scan's `range_min` and `min_range` are checked.
    prev.last + 1 < next.first
        && (first - last).norm() <= SILENT_GAP
        && ranges
            .get(prev.last + 1..next.first)
            .is_some_and(|between| between.iter().all(|&r| returned_nothing(r, lo)))
}

/// True when a beam's range `r` is no return for a scan whose smallest valid range is `lo`:
/// NaN, or below `lo` (0, or the robot's own body).
#[inline]
pub(crate) fn returned_nothing(r: f64, lo: f64) -> bool {
    r.is_nan() || r < lo
}

/// Points on each side of a shared end point that [`Pieces::best_cut`] may move to the other
/// line, and most points [`Pieces::trim_ends`] cuts from an end.
pub(crate) const CUT_WINDOW: usize = 4;

/// Incidence (as `r / |centroid|`, its cosine at the line's centroid) beyond which a line
/// must show that its points advance along it with their beams (`min_advance_t`): 60 deg.
const ADVANCE_CHECK_COS: f64 = 0.5;

/// A segment's points, their prefix sums, the parameters and the noise: what every step
/// below reads.
pub(crate) struct Pieces<'a> {
    pub(crate) seg: Seg<'a>,
    pub(crate) pre: &'a [FitSums],
    pub(crate) p: &'a HoughSplitParams,
    pub(crate) noise: &'a RangeNoise,
    /// Points on each side of a split point among which [`Pieces::best_cut`] places the cut
    /// ([`cut_window`]).
    pub(crate) cut_window: usize,
    /// Fewest supporting points of a line (`min_line_points`, or fewer on a sparse scan:
    /// [`HoughSplitParams::min_points_for`]).
    pub(crate) min_points: usize,
    /// Fewest missing beams before a line's last points that dropouts leave only by chance
    /// ([`Pieces::cut_lone_ends`]).
    pub(crate) lone_gap: usize,
    /// The scan's returns and its breakpoint distance ([`Seen`]).
    pub(crate) seen: Seen<'a>,
}

#[cfg(test)]
impl<'a> Pieces<'a> {
    /// The pieces of `seg` (prefix sums `pre`) as the tests take them: the URG-04LX's cut
    /// window, `p`'s fewest points of a line, no cut of lone end points and no returns.
    pub(crate) fn for_test(
        seg: Seg<'a>,
        pre: &'a [FitSums],
        p: &'a HoughSplitParams,
        noise: &'a RangeNoise,
    ) -> Self {
        Self {
            seg,
            pre,
            p,
            noise,
            cut_window: CUT_WINDOW,
            min_points: p.min_line_points,
            lone_gap: usize::MAX,
            seen: Seen::default(),
        }
    }
}

/// The angle [`Pieces::best_cut`] searches on each side of a split point: `CUT_WINDOW` beams
/// of the URG-04LX (360/1024 deg each), rad.
const CUT_ANGLE: f64 = CUT_WINDOW as f64 * std::f64::consts::TAU / 1024.0;

/// Points on each side of a split point that [`Pieces::best_cut`] searches on a scan of beams
/// `increment` apart: `CUT_WINDOW`, or as many as span `CUT_ANGLE` on finer scanners (6 at
/// 0.25 deg), so that the cut is searched over the same angle, where noise moves the split
/// point as far.
pub(crate) fn cut_window(increment: f64) -> usize {
    let beams = (CUT_ANGLE / increment.abs() - 1e-9).ceil();
    // NaN and infinite increments fail the test and give the fixed window.
    if beams > CUT_WINDOW as f64 && beams < 64.0 {
        beams as usize
    } else {
        CUT_WINDOW
    }
}

impl Pieces<'_> {
    pub(super) fn point(&self, k: usize) -> Point2 {
        self.seg.point(k)
    }

    /// The first opening in the points `seg[a..z]` ([`opening::seen_through`]): the points
    /// just before and just after it. Returns beyond the piece's line are either points of
    /// the piece, which then do not fit one line within the noise, or returns it does not
    /// hold (removed as noise), so a piece that fits one line and holds every return between
    /// its ends is not searched.
    fn opening_in(&self, a: usize, z: usize) -> Option<(usize, usize)> {
        if z < a + self.min_points.max(2) {
            return None;
        }
        let b = z - 1;
        let (first, last) = (self.seg.idx(a), self.seg.idx(b));
        let returns = self.seen.returns;
        let inner =
            returns.partition_point(|q| q.idx < last) - returns.partition_point(|q| q.idx <= first);
        if inner + a + 1 == b && within_noise(self.pre, (a, b), self.p, self.noise) {
            return None;
        }
        opening::seen_through((self.seg, self.pre), returns, (a, b), self.p, self.noise)
    }

    /// The piece `seg[a..z]`: its line, if it gives one, into `out` and `candidates`, and the
    /// piece into `spans`. When it gives none but the part of it within `tree` (the split
    /// tree's own piece, before where lines end was refined) does, that part is the piece: a
    /// cut moved onto the few points of a step beside a wall must not lose the wall.
    fn emit(
        &self,
        (a, z): (usize, usize),
        tree: Option<(usize, usize)>,
        (spans, out, candidates): (&mut Vec<Piece>, &mut Vec<Line>, &mut Vec<Candidate>),
    ) {
        let (mut a, mut z) = (a, z);
        let mut line = self.line(a, z);
        if line.is_none()
            && let Some((ta, tz)) = tree
            && (ta > a || tz < z)
        {
            let (na, nz) = (a.max(ta), z.min(tz));
            if let Some(l) = self.line(na, nz) {
                (a, z, line) = (na, nz, Some(l));
            }
        }
        spans.push(Piece {
            a: a as u32,
            z: z as u32,
            line: line.is_some(),
        });
        if let Some((line, c)) = line {
            out.push(line);
            candidates.push(c);
        }
    }

    /// Drops every break whose two pieces are one line (the split test, not significant),
    /// greedily from left to right.
    fn merge(&self, breaks: &mut Vec<u32>) {
        if breaks.len() <= 2 || self.p.split_significance <= 0.0 {
            return;
        }
        let mut w = 1;
        for r in 1..breaks.len() - 1 {
            let from = breaks[w - 1] as usize;
            let (at, to) = (breaks[r] as usize, breaks[r + 1] as usize);
            if !split_is_significant(self.seg, self.pre, (from, at, to), self.p, self.noise) {
                continue;
            }
            breaks[w] = breaks[r];
            w += 1;
        }
        let last = breaks[breaks.len() - 1];
        breaks[w] = last;
        breaks.truncate(w + 1);
    }

    /// The line of `seg[a..z]` and the sums of its points, when it has enough points, is long
    /// enough and its RMS residual lies within `max_rms_sigmas` of the noise at its centroid,
    /// and, seen at more than 60 deg of incidence, its points advance along it with their
    /// beams ([`advances`], `min_advance_t`); [`Candidate::certain`] tells whether its
    /// covariance also passes the gates ([`certain`]). Its covariance takes the point noise as
    /// the larger of the residual variance and the model's noise across the line
    /// ([`floored_covariance`]).
    fn line(&self, a: usize, z: usize) -> Option<(Line, Candidate)> {
        if z <= a || z - a < self.min_points.max(2) {
            return None;
        }
        let sums = sums(self.pre, a, z);
        let fit = sums.fit()?;
        if !rms_passes(&fit, self.p, self.noise) {
            return None;
        }
        let t = self.p.min_advance_t;
        let glancing = fit.r < ADVANCE_CHECK_COS * fit.centroid.coords.norm();
        if t > 0.0 && glancing && !advances(self.seg, a, z, fit.normal(), t) {
            return None;
        }
        let first = (self.seg.idx(a), self.point(a));
        let last = (self.seg.idx(z - 1), self.point(z - 1));
        let mut line = Line::from_fit(&fit, first, last);
        if line.length() < self.p.min_line_length {
            return None;
        }
        line.covariance = floored_covariance(&fit, self.noise, self.p.own_scatter);
        let certain = certain(&line.covariance, self.p);
        let ends = (first.1, last.1);
        Some((
            line,
            Candidate {
                sums,
                ends,
                certain,
                span: (a as u32, z as u32),
                follows: false,
            },
        ))
    }
}

/// Whether the points `seg[a..z]` advance along the line of unit normal `normal` with their
/// beams: the least-squares slope of their positions along the line against their beam
/// numbers lies at least `min_t` standard errors from zero (its t statistic, from the
/// scatter about that slope). Points of a surface seen at a glancing angle move along it by
/// `r dphi / cos(incidence)` a beam, well beyond their noise; a streak of range noise along
/// the beams (a leg, a post or a depth edge seen through noise larger than the beam
/// spacing), to which the fit gives a line at a glancing angle, scatters along it in no
/// order. `t >= min_t` is `c_it^2 (n - 2) >= min_t^2 (c_ii c_tt - c_it^2)` with the centred
/// sums of products `c` (no division by them, and a NaN fails); fewer than three points have
/// no scatter about a slope and do not advance.
fn advances(seg: Seg<'_>, a: usize, z: usize, normal: Vector2, min_t: f64) -> bool {
    if z < a + 3 {
        return false;
    }
    let (ca, sa) = (normal.x, normal.y);
    let n = (z - a) as f64;
    let base = seg.idx(a);
    let (mut si, mut st, mut sii, mut sit, mut stt) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for k in a..z {
        // Beam numbers increase along a segment.
        let i = (seg.idx(k) - base) as f64;
        let q = seg.point(k);
        let t = q.y * ca - q.x * sa;
        si += i;
        st += t;
        sii += i * i;
        sit += i * t;
        stt += t * t;
    }
    let cii = sii - si * si / n;
    let cit = sit - si * st / n;
    let ctt = stt - st * st / n;
    cit * cit * (n - 2.0) >= min_t * min_t * (cii * ctt - cit * cit)
}

/// A piece of a data segment as [`emit_lines`] leaves it (after its cut and trims): its
/// points `seg[a..z]`, and whether it gave a line.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Piece {
    pub(crate) a: u32,
    pub(crate) z: u32,
    pub(crate) line: bool,
}

impl Piece {
    /// Its number of points.
    pub(crate) fn len(self) -> usize {
        self.z.saturating_sub(self.a) as usize
    }
}

/// A line as [`emit_lines`] gives it, before [`super::collinear::share_fits`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct Candidate {
    /// The sums of its points.
    pub(crate) sums: FitSums,
    /// Its first and last supporting points.
    pub(crate) ends: (Point2, Point2),
    /// Its points in its data segment, `seg[span.0..span.1]`.
    pub(crate) span: (u32, u32),
    /// Its points follow the previous line's in the same data segment with fewer than
    /// [`GAP_POINTS`] between (set by [`emit_lines`] once the segment's lines are final), or
    /// the previous segment's last line's across beams that returned nothing
    /// ([`follows_across_silence`]).
    pub(crate) follows: bool,
    /// Its direction is known to `max_alpha_sd` and its distance from the sensor to
    /// `max_r_sd` (one standard deviation each, from its own fit); an uncertain line is kept
    /// only when it shares the fit of another line that makes it certain.
    pub(crate) certain: bool,
}

/// Whether a line of covariance `cov` passes the gates `max_alpha_sd` and `max_r_sd`.
pub(crate) fn certain(cov: &Matrix2, p: &HoughSplitParams) -> bool {
    cov[(1, 1)] <= p.max_alpha_sd * p.max_alpha_sd && cov[(0, 0)] <= p.max_r_sd * p.max_r_sd
}

/// The covariance of `fit` with the point noise taken as the larger of its residual
/// variance and the range noise seen across the line, `sigma cos(incidence)` at its centroid
/// (`cos = r / |centroid|`); with `own` (`own_scatter`), unless the points refuse that noise:
/// their sum of squared residuals in its variances below the chi-square quantile of `n - 2`
/// degrees of freedom at the 1e-3 level ([`chi2_low`]) bounds the variance by the sum over
/// that quantile instead.
pub(crate) fn floored_covariance(fit: &PolarFit, noise: &RangeNoise, own: bool) -> Matrix2 {
    let range = fit.centroid.coords.norm();
    let sigma = noise.sigma(range);
    let across = if range > 0.0 {
        sigma * fit.r / range
    } else {
        sigma
    };
    let n = fit.n as f64;
    let k = n - 2.0;
    let residual = fit.rms * fit.rms * n / k.max(1.0);
    if across * across <= residual {
        return fit.covariance;
    }
    let floor = match chi2_low(k) {
        // The model, read off other surfaces or extrapolated past them, does not hold here.
        Some(q) if own && residual * k < q * across * across => residual * k / q,
        _ => across * across,
    };
    fit.covariance_for(floor)
}

/// The lower 1e-3 quantile of the chi-square distribution of `k` degrees of freedom
/// (Wilson-Hilferty; within 11 % of the tables at 8, 0.2 % from 50 on), for `k` of 8 or
/// more.
fn chi2_low(k: f64) -> Option<f64> {
    if k.is_nan() || k < 8.0 {
        return None;
    }
    let a = 2.0 / (9.0 * k);
    let c = 1.0 - a - 3.090_232 * a.sqrt();
    Some(k * c * c * c)
}

/// Turns the split tree's end points of one segment into lines appended to `out`, and
/// leaves the segment's pieces in `spans`.
///
/// Neighbouring pieces share their end point after the split; with `refine_ends`,
/// [`Pieces::best_cut`] decides which line each point near it supports, so that every point
/// supports at most one line; without, the shared point goes to the first.
pub(crate) fn emit_lines(
    pieces: &Pieces<'_>,
    (breaks, openings, spans): (&mut Vec<u32>, &mut Vec<u32>, &mut Vec<Piece>),
    out: &mut Vec<Line>,
    candidates: &mut Vec<Candidate>,
) {
    spans.clear();
    openings.clear();
    if breaks.len() < 2 {
        return;
    }
    let p = pieces.p;
    if p.merge_collinear {
        pieces.merge(breaks);
    }
    let min_points = pieces.min_points.max(2);
    let first_line = out.len();
    // Piece i covers seg[lo..hi] with disjoint bounds.
    let mut lo = 0usize;
    for i in 1..breaks.len() {
        let b = breaks[i] as usize;
        let hi = if i + 1 == breaks.len() {
            pieces.seg.len()
        } else if p.refine_ends {
            pieces.best_cut(lo, b, breaks[i + 1] as usize)
        } else {
            b + 1
        };
        let (mut a, z) = if p.refine_ends {
            let (a, z) = pieces.trim_ends(lo, hi, min_points);
            pieces.cut_lone_ends(a, z, min_points)
        } else {
            (lo, hi)
        };
        // Each opening the beams see through the piece's line ends a piece; the last part, if
        // it gives no line, is taken within the split tree's piece (`keep_split_bounds`).
        let mut tree = p.keep_split_bounds.then(|| (breaks[i - 1] as usize, b + 1));
        while let Some((s, e)) = p.cut_excursions.then(|| pieces.opening_in(a, z)).flatten() {
            pieces.emit((a, s + 1), None, (spans, out, candidates));
            openings.push(s as u32);
            (a, tree) = (e, None);
        }
        pieces.emit((a, z), tree, (spans, out, candidates));
        lo = hi;
    }
    if p.arc_significance > 0.0 {
        drop_arcs(pieces, spans, out, candidates, first_line);
    }
    for k in first_line + 1..candidates.len() {
        let between = candidates[k]
            .span
            .0
            .saturating_sub(candidates[k - 1].span.1);
        // Lines on both sides of an opening never follow each other.
        let (from, to) = (candidates[k - 1].span.0, candidates[k].span.1);
        candidates[k].follows =
            (between as usize) < GAP_POINTS && !openings.iter().any(|&o| from <= o && o < to);
    }
    if p.refine_ends {
        join_corners(
            &mut out[first_line..],
            &candidates[first_line..],
            p,
            pieces.noise,
            pieces.seen,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::super::linseg::{SplitScratch, linseg, prefix_sums};
    use super::super::points::{Pt, Seg, on_beam, points_at};
    use super::*;

    #[test]
    fn the_chi_square_quantile_is_within_a_few_percent_of_the_tables() {
        // Lower 1e-3 quantiles of the chi-square distribution (published tables).
        for (k, q) in [(8.0, 0.857), (10.0, 1.479), (20.0, 5.921), (50.0, 24.674)] {
            let got = chi2_low(k).unwrap();
            assert!((got / q - 1.0).abs() < 0.11, "{k}: {got} against {q}");
        }
        assert!((chi2_low(100.0).unwrap() / 61.918 - 1.0).abs() < 0.002);
        assert_eq!(chi2_low(7.0), None);
        assert_eq!(chi2_low(f64::NAN), None);
    }

    /// The fit of `n` points along y = 3 (x from -1 to 1) whose offsets alternate
    /// `+-offset`: RMS residual about `offset`.
    fn flat_fit(n: usize, offset: f64) -> PolarFit {
        let mut sums = FitSums::new();
        for i in 0..n {
            let x = -1.0 + 2.0 * i as f64 / (n - 1) as f64;
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            sums.add(Point2::new(x, 3.0 + sign * offset));
        }
        sums.fit().unwrap()
    }

    #[test]
    fn a_line_whose_points_refuse_the_noise_model_is_judged_by_its_own_scatter() {
        let model = RangeNoise::new(0.03, 0.0);
        let alpha_var = |fit: &PolarFit, own| floored_covariance(fit, &model, own)[(1, 1)];
        // 20 points 1 mm off their line under a model of 3 cm: the model is refused, and
        // the variance is bounded by the points' scatter at the 1e-3 level.
        let fit = flat_fit(20, 0.001);
        let var = alpha_var(&fit, true) * fit.spread;
        let bound = fit.rms * fit.rms * 20.0 / chi2_low(18.0).unwrap();
        assert!((var / bound - 1.0).abs() < 1e-9, "{var} against {bound}");
        assert!(var < 0.03 * 0.03 / 10.0 && var > fit.rms * fit.rms);
        // Without `own_scatter` (scan matching), the model's floor.
        let across = 0.03 * fit.r / fit.centroid.coords.norm();
        let var = alpha_var(&fit, false) * fit.spread;
        assert!((var / (across * across) - 1.0).abs() < 1e-9, "{var}");
        // 2.5 cm of scatter under the same model: within it, so the model's noise floors it.
        let fit = flat_fit(20, 0.025);
        let var = alpha_var(&fit, true) * fit.spread;
        let across = 0.03 * fit.r / fit.centroid.coords.norm();
        assert!((var / (across * across) - 1.0).abs() < 1e-9, "{var}");
        // Too few points to refuse it: the model's floor.
        let fit = flat_fit(9, 0.001);
        let var = alpha_var(&fit, true) * fit.spread;
        let across = 0.03 * fit.r / fit.centroid.coords.norm();
        assert!((var / (across * across) - 1.0).abs() < 1e-9, "{var}");
    }

    #[test]
    fn the_cut_window_spans_the_urg_04lx_s_angle() {
        let urg = std::f64::consts::TAU / 1024.0;
        assert_eq!(cut_window(urg), CUT_WINDOW);
        assert_eq!(cut_window(-urg), CUT_WINDOW);
        assert_eq!(cut_window(1f64.to_radians()), CUT_WINDOW);
        assert_eq!(cut_window(0.25f64.to_radians()), 6);
        assert_eq!(cut_window(0.1f64.to_radians()), 15);
        for bad in [0.0, f64::NAN, f64::INFINITY, 1e-12] {
            assert_eq!(cut_window(bad), CUT_WINDOW, "{bad}");
        }
    }

    /// Points on beams `0.25 deg` apart around the y axis, at ranges `range(i)`, numbered
    /// from beam 0.
    fn on_beams(n: usize, range: impl Fn(usize) -> f64) -> Vec<Pt> {
        let step = 0.25f64.to_radians();
        (0..n)
            .map(|i| {
                let phi = std::f64::consts::FRAC_PI_2 + step * i as f64;
                on_beam(i, phi, range(i))
            })
            .collect()
    }

    /// The unit normal of the least-squares line of `pts`.
    fn fitted_normal(pts: &[Pt]) -> Vector2 {
        let sums = FitSums::from_points(pts.iter().map(|p| Point2::new(p.x, p.y)));
        sums.fit().unwrap().normal()
    }

    #[test]
    fn a_streak_of_range_noise_does_not_advance_but_a_glancing_wall_does() {
        // Fixed deviates in units of sigma, in no order.
        let dev = [0.9, -1.3, 0.2, 1.6, -0.7, -1.8, 1.1, -0.1, 0.5, -1.0, 1.4];
        // A leg at 0.8 m under 40 mm of noise (a UST-10LX): 11 beams, 35 mm across, ranges
        // spread 14 cm along the beams. The fit takes the streak for a line along them.
        let leg = on_beams(11, |i| 0.8 + 0.04 * dev[i]);
        let normal = fitted_normal(&leg);
        assert!(!advances(Seg(&leg), 0, 11, normal, 8.0));
        // The same beams in order of range do advance: a surface.
        let mut sorted = dev;
        sorted.sort_by(f64::total_cmp);
        let ramp = on_beams(11, |i| 0.8 + 0.04 * sorted[i]);
        assert!(advances(Seg(&ramp), 0, 11, fitted_normal(&ramp), 8.0));
        // A wall 0.3 m from the sensor seen at 80 deg of incidence, 1.7 m away, under the same
        // noise: its points move 5-7 cm along it a beam, 0.58 m in all.
        let wall_alpha: f64 = 10f64.to_radians();
        let wall = on_beams(11, |i| {
            let phi = std::f64::consts::FRAC_PI_2 + 0.25f64.to_radians() * i as f64;
            0.3 / (phi - wall_alpha).cos().abs() + 0.04 * dev[i]
        });
        assert!(advances(Seg(&wall), 0, 11, fitted_normal(&wall), 8.0));
        // Too few points for a slope: none advances.
        assert!(!advances(Seg(&wall), 0, 2, fitted_normal(&wall), 8.0));
        // However strict the threshold, a scattered set never passes.
        assert!(!advances(Seg(&leg), 0, 11, normal, f64::MAX));
    }

    #[test]
    fn an_l_gives_two_lines_sharing_the_corner_point_once() {
        let mut xy = Vec::new();
        for i in 0..=20 {
            xy.push((1.0, -1.0 + 0.05 * f64::from(i)));
        }
        for i in 1..=20 {
            xy.push((1.0 - 0.025 * f64::from(i), 0.0));
        }
        let points = points_at(&xy);
        let seg = Seg(&points);
        let p = HoughSplitParams::default();
        let noise = RangeNoise::new(0.002, 0.0);
        let mut scratch = SplitScratch::default();
        prefix_sums(seg, &mut scratch.prefix);
        linseg(seg, &p, &noise, 8, &mut scratch);
        let pieces = Pieces::for_test(seg, &scratch.prefix, &p, &noise);
        let mut out = Vec::new();
        let mut breaks = scratch.breaks.clone();
        emit_lines(
            &pieces,
            (&mut breaks, &mut Vec::new(), &mut Vec::new()),
            &mut out,
            &mut Vec::new(),
        );
        assert_eq!(out.len(), 2);
        assert!((out[0].r - 1.0).abs() < 1e-9 && out[0].alpha.abs() < 1e-9);
        assert!(out[1].r.abs() < 1e-9);
        // The corner point went to exactly one line, and both lines end at the corner.
        assert_eq!(out[0].last + 1, out[1].first);
        assert!((out[0].end - Point2::new(1.0, 0.0)).norm() < 1e-9);
        assert!((out[1].start - Point2::new(1.0, 0.0)).norm() < 1e-9);
    }
}
