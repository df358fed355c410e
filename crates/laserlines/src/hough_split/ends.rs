//! Where a line of step 6 ends: the cut between neighbouring pieces, points at a piece's ends
//! that another surface bent away, and a few points beyond a gap that dropouts leave only by
//! chance.

use super::lines::{CUT_WINDOW, Pieces};
use super::linseg::{incidence_cos, sums};
use super::params::HoughSplitParams;
use crate::fit::NormalFit;
use crate::math::Point2;

/// The chi-square quantiles at the 1e-2 level for 1..=4 degrees of freedom: `k` end points
/// are cut only when their joint deviation is that unlikely as noise (and all on one side).
const CHI2_1E2: [f64; CUT_WINDOW] = [6.63, 9.21, 11.34, 13.28];

/// Most points of a line's end that [`Pieces::cut_lone_ends`] cuts beyond a gap.
const LONE_RUN: usize = 3;

impl Pieces<'_> {
    /// Where to cut between the piece `seg[lo..=b]` and the piece `seg[b..=next]`, which
    /// share the split point `b`: returns `c` such that the first piece keeps `seg[lo..c]`.
    ///
    /// The split point is the farthest point from a chord, which noise can move a few points
    /// away from the true corner. Both pieces are fitted without the `CUT_WINDOW` points
    /// around `b`, and the cut is placed where the points of the window are best explained
    /// by the line on their side: the least sum of their squared distances, each in
    /// variances of that line's noise across it at the point ([`cut_variance`], with
    /// `noise_along_beams`). A wall seen at a glancing angle scatters little across itself,
    /// so the first points of the wall it meets, a few centimetres off it, are far off in its
    /// noise: by distances alone it took 3-5 of them where a glancing wall meets a facing
    /// one. When one piece is too short to fit without the window, the other line takes the
    /// window's points for as long as they lie within `split_sigmas * sigma(r)` of it.
    pub(super) fn best_cut(&self, lo: usize, b: usize, next: usize) -> usize {
        let wlo = b.saturating_sub(self.cut_window).max(lo + 1);
        let whi = (b + self.cut_window).min(next.saturating_sub(1));
        if whi < wlo {
            return b + 1;
        }
        let left = sums(self.pre, lo, wlo).normal_fit();
        let right = sums(self.pre, whi + 1, next + 1).normal_fit();
        let near = |fit: &NormalFit, k: usize| {
            let q = self.point(k);
            fit.distance(q).abs()
                <= self.p.split_sigmas
                    * self.noise.sigma(self.seg.range(k))
                    * incidence_cos(q, fit.normal, self.p.noise_along_beams)
        };
        let (left, right) = match (left, right) {
            (Some(l), Some(r)) => (l, r),
            (Some(l), None) => {
                let mut c = wlo;
                while c <= whi && near(&l, c) {
                    c += 1;
                }
                return c.max(b + 1).min(next);
            }
            (None, Some(r)) => {
                let mut c = whi;
                while c >= wlo && near(&r, c) {
                    c -= 1;
                }
                return (c + 1).min(b + 1).max(lo + 1);
            }
            (None, None) => return b + 1,
        };
        // cost(c) = sum over window points before c of dL^2 + from c on of dR^2, each in
        // variances of its line's noise across it.
        let d2 = |fit: &NormalFit, k: usize| {
            let q = self.point(k);
            let d = fit.distance(q);
            d * d / cut_variance(fit, q, self.noise.sigma(self.seg.range(k)), self.p)
        };
        let mut cost: f64 = (wlo..=whi).map(|k| d2(&right, k)).sum();
        let mut best = (cost, wlo);
        for c in wlo..=whi {
            cost += d2(&left, c) - d2(&right, c);
            // Ties keep the cut nearest the split point.
            let better = cost < best.0
                || (cost == best.0 && (c + 1).abs_diff(b + 1) < best.1.abs_diff(b + 1));
            if better {
                best = (cost, c + 1);
            }
        }
        best.1
    }

    /// Drops points at the ends of the piece `seg[lo..hi]` that another surface bent away: a
    /// short leg of a corner too small for the split to see, or a mixed pixel.
    ///
    /// For each end, the last `k <= min(CUT_WINDOW, n / 6)` points are tested against the fit
    /// of the rest: each distance `d` is scaled by its expected spread, the point noise (the
    /// larger of `sigma(r)` and the rest's own residual spread) plus the uncertainty of the
    /// fitted line at that point (from the fit's covariance). The `k` points are cut when they
    /// bend away as a surface does (all on one side, the outermost farthest) and
    /// `sum(d^2 / var)` exceeds the chi-square quantile of `k` degrees of freedom at the 1e-2
    /// level, choosing the `k` with the largest excess `sum(d^2 / var - k)`. Returns the new
    /// bounds.
    pub(super) fn trim_ends(&self, lo: usize, hi: usize, min_points: usize) -> (usize, usize) {
        let (mut lo, mut hi) = (lo, hi);
        for from_end in [true, false] {
            let n = hi.saturating_sub(lo);
            let max_k = CUT_WINDOW
                .min(n / 6)
                .min(n.saturating_sub(min_points.max(3)));
            let mut rest = sums(self.pre, lo, hi);
            let mut best: Option<(f64, usize)> = None;
            for k in 1..=max_k {
                let idx = |j: usize| if from_end { hi - 1 - j } else { lo + j };
                rest.remove(self.point(idx(k - 1)));
                let Some(fit) = rest.normal_fit() else { break };
                let (chi2, bent) = self.end_chi2(&fit, (0..k).map(idx));
                let excess = chi2 - k as f64;
                if bent && chi2 >= CHI2_1E2[k - 1] && best.is_none_or(|(e, _)| excess > e) {
                    best = Some((excess, k));
                }
            }
            if let Some((_, k)) = best {
                if from_end {
                    hi -= k;
                } else {
                    lo += k;
                }
            }
        }
        (lo, hi)
    }

    /// Cuts from each end of `seg[lo..hi]` a run of at most [`LONE_RUN`] points that lies
    /// beyond a gap of `lone_gap` missing beams or more (beams that returned nothing: not
    /// among `returns`, the scan's valid points), a gap the scan's dropouts leave only by
    /// chance ([`HoughSplitParams::lone_gap_for`]): too few points to say that the surface
    /// goes on across it. Two walls in line on either side of a door seen at a glancing angle
    /// otherwise gave a line across the opening, held by one or two points of the far wall.
    /// Points removed as noise or by another surface in front leave no such gap. A run is cut
    /// only while `min_points` and one more remain. Returns the new bounds.
    pub(super) fn cut_lone_ends(&self, lo: usize, hi: usize, min_points: usize) -> (usize, usize) {
        let missing = |k: usize| {
            let (a, b) = (self.seg.idx(k - 1), self.seg.idx(k));
            let beams = b - a - 1;
            if beams < self.lone_gap {
                // Too few beams between them to matter, however many returned.
                return beams;
            }
            let returned = self.seen.returns.partition_point(|p| p.idx < b)
                - self.seen.returns.partition_point(|p| p.idx <= a);
            beams.saturating_sub(returned)
        };
        let keeps = |lo: usize, hi: usize, j: usize| {
            hi.saturating_sub(lo) > min_points.max(2).saturating_add(j)
        };
        let (mut lo, mut hi) = (lo, hi);
        if let Some(j) =
            (1..=LONE_RUN).find(|&j| keeps(lo, hi, j) && missing(hi - j) >= self.lone_gap)
        {
            hi -= j;
        }
        if let Some(j) =
            (1..=LONE_RUN).find(|&j| keeps(lo, hi, j) && missing(lo + j) >= self.lone_gap)
        {
            lo += j;
        }
        (lo, hi)
    }

    /// The chi-square of the points at positions `ks` (the outermost first) against `fit`
    /// (point noise plus the fit's uncertainty there), and whether they bend away from it: all
    /// on one side, the outermost farthest.
    fn end_chi2(&self, fit: &NormalFit, ks: impl Iterator<Item = usize>) -> (f64, bool) {
        let normal = fit.normal;
        let (ca, sa) = (normal.x, normal.y);
        let cov = fit.covariance;
        let residual = fit.s2;
        let (mut chi2, mut sign, mut bent) = (0.0, 0.0f64, true);
        let mut outermost = 0.0f64;
        for k in ks {
            let sp = self.point(k);
            let d = sp.coords.dot(&normal) - fit.r;
            if sign == 0.0 {
                sign = d.signum();
                outermost = d.abs();
            } else if d.signum() != sign || d.abs() > outermost {
                bent = false;
            }
            let noise = self.noise.sigma(self.seg.range(k))
                * incidence_cos(sp, normal, self.p.noise_along_beams);
            let t = -sp.x * sa + sp.y * ca;
            let line_var = cov[(0, 0)] - 2.0 * t * cov[(0, 1)] + t * t * cov[(1, 1)];
            chi2 += d * d / ((noise * noise).max(residual) + line_var.max(0.0));
        }
        (chi2, bent)
    }
}

/// The variance of a point `q` (range noise `sigma`) about the line `fit` as
/// [`Pieces::best_cut`] weighs it: the range noise across the line, `sigma` times the
/// cosine of the beam's incidence ([`incidence_cos`]), or the line's own residual variance
/// when that is larger (noise larger than the model), and never below a micrometre squared.
/// Without `noise_along_beams` the noise across both lines at a point is the same
/// `sigma(r)`, and every point weighs 1: the cut by distances alone.
fn cut_variance(fit: &NormalFit, q: Point2, sigma: f64, p: &HoughSplitParams) -> f64 {
    if !p.noise_along_beams {
        return 1.0;
    }
    let across = sigma * incidence_cos(q, fit.normal, true);
    (across * across).max(fit.s2).max(1e-12)
}

#[cfg(test)]
mod tests {
    use super::super::corners::Seen;
    use super::super::linseg::prefix_sums;
    use super::super::params::HoughSplitParams;
    use super::super::points::{Pt, Seg, on_beam};
    use super::*;
    use crate::noise::RangeNoise;

    /// Points of the wall `y = 1` on beams 0.5 deg apart from 30 deg on, without the beams in
    /// `missing`.
    fn wall(n: usize, missing: &[usize]) -> Vec<Pt> {
        (0..n)
            .filter(|i| !missing.contains(i))
            .map(|i| {
                let phi = (30.0 + 0.5 * i as f64).to_radians();
                on_beam(i, phi, 1.0 / phi.sin())
            })
            .collect()
    }

    /// The bounds `cut_lone_ends` leaves of the whole of `pts` with gaps of `lone_gap`, the
    /// beams of `pts` the only ones that returned.
    fn cut(pts: &[Pt], lone_gap: usize) -> (usize, usize) {
        cut_among(pts, pts, lone_gap)
    }

    /// The same with the beams of `returns` returned.
    fn cut_among(pts: &[Pt], returns: &[Pt], lone_gap: usize) -> (usize, usize) {
        cut_with(
            pts,
            returns,
            lone_gap,
            HoughSplitParams::default().min_line_points,
        )
    }

    /// The same with `min_points` for the line.
    fn cut_with(pts: &[Pt], returns: &[Pt], lone_gap: usize, min_points: usize) -> (usize, usize) {
        let seg = Seg(pts);
        let p = HoughSplitParams::default();
        let noise = RangeNoise::new(0.01, 0.0);
        let mut pre = Vec::new();
        prefix_sums(seg, &mut pre);
        let pieces = Pieces {
            min_points,
            lone_gap,
            seen: Seen { returns, step: 0.0 },
            ..Pieces::for_test(seg, &pre, &p, &noise)
        };
        pieces.cut_lone_ends(0, pts.len(), min_points)
    }

    #[test]
    fn a_few_points_beyond_an_unlikely_gap_are_cut() {
        // 40 beams; two missing before the last two points, one after the first three.
        let pts = wall(40, &[36, 37, 3]);
        let n = pts.len();
        // Where gaps of one beam are unlikely: both ends are cut.
        assert_eq!(cut(&pts, 1), (3, n - 2));
        // Gaps of two: only the last two points go.
        assert_eq!(cut(&pts, 2), (0, n - 2));
        // Gaps of two beams left by chance (dropouts of more than 10 %): nothing is cut.
        assert_eq!(cut(&pts, 3), (0, n));
        // More than three points beyond the gap are a surface's.
        let pts = wall(40, &[33, 34]);
        assert_eq!(cut(&pts, 1), (0, pts.len()));
    }

    #[test]
    fn beams_that_returned_leave_no_gap() {
        // Beams 36 and 37 returned (a leg in front, or points removed as noise) but are not
        // the line's: nothing is cut; with beam 37 missing, one beam is.
        let all = wall(40, &[]);
        let pts = wall(40, &[36, 37]);
        assert_eq!(cut_among(&pts, &all, 1), (0, pts.len()));
        let returns = wall(40, &[37]);
        assert_eq!(cut_among(&pts, &returns, 1), (0, pts.len() - 2));
        assert_eq!(cut_among(&pts, &returns, 2), (0, pts.len()));
    }

    #[test]
    fn a_short_line_keeps_its_points() {
        // A run is cut only while `min_line_points` + 1 = 9 points remain: of 11 or 10
        // points the last, beyond a gap, goes; of 9, nothing.
        let pts = wall(12, &[10]);
        assert_eq!(pts.len(), 11);
        assert_eq!(cut(&pts, 1), (0, 10));
        let pts = wall(11, &[9]);
        assert_eq!(pts.len(), 10);
        assert_eq!(cut(&pts, 1), (0, 9));
        let pts = wall(10, &[8]);
        assert_eq!(cut(&pts, 1), (0, pts.len()));
        // A huge `min_points` cuts nothing and does not overflow.
        let pts = wall(40, &[36, 37]);
        assert_eq!(cut_with(&pts, &pts, 1, usize::MAX), (0, pts.len()));
    }

    #[test]
    fn no_line_crosses_a_door_to_the_wall_beyond() {
        // The wall `y = 1` seen from 7 deg (8.1 m away) to 45 deg in 0.25 deg steps; beams 2
        // and 3 look through a door, beams 0 and 1 see the wall beyond it. The bridge joins
        // the far wall's two points to the near wall (0.74 m apart, within its reach at 8 m
        // and 4 deg of incidence), and the line crossed the door (beams 0 to 152).
        let inc = 0.25f64.to_radians();
        let extract = |door: bool| {
            let ranges: Vec<f64> = (0..153)
                .map(|k| {
                    let phi = 7f64.to_radians() + inc * k as f64;
                    if door && (k == 2 || k == 3) {
                        f64::NAN
                    } else {
                        1.0 / phi.sin()
                    }
                })
                .collect();
            let scan = crate::Scan::new(7f64.to_radians(), inc, 0.02, 30.0, ranges).unwrap();
            let mut hs = crate::HoughSplit::new(HoughSplitParams::default()).unwrap();
            crate::LineExtractor::extract(&mut hs, &scan)
        };
        let lines = extract(true);
        assert_eq!(lines.len(), 1, "{lines:?}");
        assert_eq!((lines[0].first, lines[0].last), (4, 152), "{lines:?}");
        // Without the door the wall is one line from the first beam. (One of the points near
        // its far end at 83 deg of incidence is removed from the segment; when the rule counted
        // such a point as a missing beam, it cut the first three.)
        let lines = extract(false);
        assert_eq!(lines.len(), 1, "{lines:?}");
        assert_eq!((lines[0].first, lines[0].last), (0, 152), "{lines:?}");
    }

    #[test]
    fn the_gap_that_makes_a_cut_grows_with_the_dropouts() {
        let p = HoughSplitParams::default();
        // One missing beam is never enough; two are from no dropouts to 10 %.
        for d in [0.0, 0.005, 0.01, 0.011, 0.03, 0.1, f64::NAN] {
            assert_eq!(p.lone_gap_for(d), 2, "{d}");
        }
        // Above 10 %, two missing beams happen by chance more than once in a hundred.
        assert_eq!(p.lone_gap_for(0.11), 3);
        assert_eq!(p.lone_gap_for(0.5), 7);
        assert_eq!(p.lone_gap_for(0.7), 13);
    }

    /// A facing wall `x = 3.7` on beams 0.25 deg apart from 6 deg on, meeting at its corner
    /// the wall `y = 1` that the beams after it see at a glancing angle (75 deg of incidence
    /// at the corner, near 15.1 deg), up to 25 deg; the facing wall's beams `far` lie 1.2
    /// sigma of range noise beyond it, the others on their walls. Returns the points and the
    /// index of the facing wall's last beam.
    fn glancing_corner(far: &[usize], sigma: f64) -> (Vec<Pt>, usize) {
        let step = 0.25f64.to_radians();
        let corner = (1.0f64 / 3.7).atan();
        let mut last_facing = 0;
        let pts = (0..=76)
            .map(|i| {
                let phi = 6f64.to_radians() + step * i as f64;
                let (r, facing) = if phi < corner {
                    (3.7 / phi.cos(), true)
                } else {
                    (1.0 / phi.sin(), false)
                };
                if facing {
                    last_facing = i;
                }
                let off = if far.contains(&i) { 1.2 * sigma } else { 0.0 };
                on_beam(i, phi, r + off)
            })
            .collect();
        (pts, last_facing)
    }

    #[test]
    fn a_glancing_wall_does_not_take_the_first_points_of_the_wall_it_meets() {
        let noise = RangeNoise::new(0.01, 0.01);
        let sigma = noise.sigma(3.8);
        // The facing wall's beams 2-4 before the corner read 1.2 sigma long: they lie 3.2, 4.9
        // and 6.7 cm off the glancing wall's line and 4.4 cm off their own. By distances alone
        // the cut fell at beam 34, the glancing wall taking beams 34-36; across the glancing
        // wall the noise is 1 cm, across the facing wall 3.7 cm.
        let (pts, last) = glancing_corner(&[34, 33, 32], sigma);
        assert_eq!(last, 36);
        let seg = Seg(&pts);
        let p = HoughSplitParams::default();
        let mut pre = Vec::new();
        prefix_sums(seg, &mut pre);
        let pieces = Pieces {
            cut_window: 6,
            ..Pieces::for_test(seg, &pre, &p, &noise)
        };
        // Wherever the split fell near the corner, the facing wall keeps its beams 0..=36.
        for b in 33..=40 {
            assert_eq!(
                pieces.best_cut(0, b, pts.len() - 1),
                last + 1,
                "split at {b}"
            );
        }
        // Without `noise_along_beams`, by distances alone, as the `navigation` and `mapping`
        // presets cut.
        let plain = HoughSplitParams {
            noise_along_beams: false,
            ..HoughSplitParams::default()
        };
        let by_distance = Pieces {
            p: &plain,
            ..pieces
        };
        assert_eq!(by_distance.best_cut(0, 36, pts.len() - 1), 34);
        // Without noise off the walls, the same.
        let (pts, _) = glancing_corner(&[], sigma);
        let mut pre = Vec::new();
        prefix_sums(Seg(&pts), &mut pre);
        let pieces = Pieces {
            seg: Seg(&pts),
            pre: &pre,
            ..pieces
        };
        assert_eq!(pieces.best_cut(0, 36, pts.len() - 1), last + 1);
    }
}
