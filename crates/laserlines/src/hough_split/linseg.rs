//! Step 5: the recursive split `Linseg` (iterative end-point fit) with an explicit stack, its
//! criterion in units of the range noise, and the significance test that keeps noise from
//! splitting a wall.

use super::params::HoughSplitParams;
use super::points::Seg;
use crate::fit::{FitSums, NormalFit, PolarFit};
use crate::math::{Point2, Vector2};
use crate::noise::RangeNoise;

/// Working memory of the split.
#[derive(Debug, Default, Clone)]
pub(crate) struct SplitScratch {
    stack: Vec<(u32, u32)>,
    pub(crate) breaks: Vec<u32>,
    /// The segment's points (positions in it) just before each opening at which step 6 ended
    /// a line ([`super::opening::seen_through`]).
    pub(crate) openings: Vec<u32>,
    pub(crate) prefix: Vec<FitSums>,
}

/// Distance of `p` from the infinite line through `a` and `b` (or from `a` when they meet).
fn chord_distance(p: Point2, a: Point2, b: Point2) -> f64 {
    let ab = b - a;
    let len = ab.norm();
    if len <= f64::EPSILON {
        return (p - a).norm();
    }
    (ab.x * (p.y - a.y) - ab.y * (p.x - a.x)).abs() / len
}

/// Prefix sums of a segment's points: `pre[i]` holds the sums of `seg[..i]`.
pub(crate) fn prefix_sums(seg: Seg<'_>, pre: &mut Vec<FitSums>) {
    pre.resize(seg.len() + 1, FitSums::new());
    let mut acc = FitSums::new();
    pre[0] = acc;
    for (out, pt) in pre[1..].iter_mut().zip(seg.0) {
        acc.add(Point2::new(pt.x, pt.y));
        *out = acc;
    }
}

/// Sums of `seg[from..to]` from the prefix sums, O(1).
pub(crate) fn sums(pre: &[FitSums], from: usize, to: usize) -> FitSums {
    pre[to].since(&pre[from])
}

/// The smallest cosine of a beam's incidence on a surface the tests take: beams within
/// 84 deg of the surface's normal.
pub(crate) const MIN_INCIDENCE_COS: f64 = 0.1;

/// The cosine of the angle between the beam through `p` and the unit `normal` of a line,
/// clamped to `MIN_INCIDENCE_COS..=1` (1 at the origin, and without `along`: the
/// `noise_along_beams` parameter). Range noise lies along the beam: across the line it is
/// `sigma(r)` times this.
pub(crate) fn incidence_cos(p: Point2, normal: Vector2, along: bool) -> f64 {
    let d = p.coords.norm();
    if along && d > 0.0 {
        let cos = p.coords.dot(&normal).abs() / d;
        // A NaN fails the test and gives the floor.
        if cos >= MIN_INCIDENCE_COS {
            cos.min(1.0)
        } else {
            MIN_INCIDENCE_COS
        }
    } else {
        1.0
    }
}

/// `sigma(r)^2 cos^2(incidence)` at the centroid of `s`, for the line fitted to `s`: the
/// variance of the range noise across that line (`sigma(r)^2` when `s` fits no line, or
/// without `along`).
pub(crate) fn variance_across(s: &FitSums, noise: &RangeNoise, along: bool) -> f64 {
    let floor = MIN_INCIDENCE_COS * MIN_INCIDENCE_COS;
    let cos2 = if along {
        // A NaN fails the test and gives the floor.
        s.incidence_cos2()
            .map_or(1.0, |c2| if c2 >= floor { c2.min(1.0) } else { floor })
    } else {
        1.0
    };
    variance_at(s, noise) * cos2
}

/// `sigma(r)^2` at the range of the centroid of `s`: `max(sigma_min^2, fraction^2 r^2)`.
pub(crate) fn variance_at(s: &FitSums, noise: &RangeNoise) -> f64 {
    let r2 = s.centroid_norm_squared();
    let (floor, growth) = (
        noise.sigma_min * noise.sigma_min,
        noise.fraction * noise.fraction,
    );
    (growth * r2).max(floor)
}

/// True when two lines, `seg[a..=m]` and `seg[m..=b]` (or, at a step, with `m` on one side
/// alone: [`step_apart`], with `split_steps`), explain the points `seg[a..=b]`
/// significantly better than one: the drop of the sum of squared residuals exceeds
/// `split_significance` times the noise variance, the larger of the model's noise across the
/// joint line ([`variance_across`]) and the two lines' own residual variance (so that noise
/// larger than the model never makes a split significant); and the two lines depart from
/// the one by more than `min_bend`: in the mean square over the points (the drop over
/// their number), or else at the piece's ends or the split point, or meet at an angle no
/// bow makes ([`bends`]), or the one line would fail the RMS gate that every line must
/// pass ([`rms_passes`]).
pub(crate) fn split_is_significant(
    seg: Seg<'_>,
    pre: &[FitSums],
    (a, m, b): (usize, usize, usize),
    p: &HoughSplitParams,
    noise: &RangeNoise,
) -> bool {
    let whole = sums(pre, a, b + 1);
    let sse = whole.sse();
    let sides = (sums(pre, a, m + 1).sse(), sums(pre, m, b + 1).sse());
    let shared = sides.0 + sides.1;
    let model = variance_across(&whole, noise, p.noise_along_beams);
    let n = b - a + 1;
    // Both lines hold the shared point: n + 1 residuals, four parameters (n apart).
    let (mut two, mut variance) = (shared, noise_variance(model, shared, n.saturating_sub(3)));
    // Where the shared point hides the split: only where it bends the other line by more
    // than the noise allows (a lone outlier at the split point bends it less).
    if p.split_steps
        && sse - shared <= p.split_significance * variance
        && let Some(apart) = step_apart(pre, (a, m, b), sides, model, p.split_significance)
        && shared - apart > p.split_significance * model
    {
        (two, variance) = (apart, noise_variance(model, apart, n.saturating_sub(4)));
    }
    let drop = sse - two;
    // The drop is about the squared departure of the two lines from the one, summed over
    // the points: a mean above `min_bend^2` departs by more at its ends or split point (a
    // corner, most often), and needs no fits of its own.
    let (bend, n) = (p.min_bend, n as f64);
    drop > p.split_significance * variance
        && (bend <= 0.0
            || drop > n * bend * bend
            || bends(seg, pre, (a, m, b), bend)
            || !rms_within(
                (sse / n).sqrt(),
                whole.centroid_norm_squared().sqrt(),
                p,
                noise,
            ))
}

/// The variance a drop of squared residuals is measured in: the model's noise `model`, or
/// the two lines' own residual variance (`two` over `dof`) when larger, so that noise larger
/// than the model never makes a split significant.
fn noise_variance(model: f64, two: f64, dof: usize) -> f64 {
    let residual = if dof > 0 { two / dof as f64 } else { 0.0 };
    model.max(residual)
}

/// At a step (a door set back from its wall) the split point `m` lies on one side only, and
/// the other side's line, bent through it, hides the step. The least sum of squared
/// residuals of two lines over `seg[a..=b]` with `m` on one side alone, when the points on
/// the two sides without it are significantly better explained by two lines than by one
/// (else a lone outlier that a short line bends to reach would pass for a step); `None`
/// otherwise. `sides` are the sums of squared residuals of `seg[a..=m]` and `seg[m..=b]`.
fn step_apart(
    pre: &[FitSums],
    (a, m, b): (usize, usize, usize),
    sides: (f64, f64),
    model: f64,
    significance: f64,
) -> Option<f64> {
    let (before, after) = (sums(pre, a, m), sums(pre, m + 1, b + 1));
    let (sse_before, sse_after) = (before.sse(), after.sse());
    let two = sse_before + sse_after;
    // `n - 1` points, four parameters.
    let variance = noise_variance(model, two, (b - a).saturating_sub(4));
    if before.join(&after).sse() - two <= significance * variance {
        return None;
    }
    Some((sides.0 + sse_after).min(sse_before + sides.1))
}

/// The largest angle between two lines that a bow can make, rad: 5 deg. A scanner's slowly
/// changing range error bends a wall's pieces by a degree or two; two sides of a small
/// object meet at more, however little they depart from one line.
const BOW_ANGLE: f64 = 0.087_155_742_747_658_17; // sin(5 deg)

/// True when the two lines of `seg[a..=m]` and `seg[m..=b]` bend away from the one line of
/// `seg[a..=b]` by more than a bow `depth` deep (m): the two lie farther apart than `depth`
/// at the shared point, or the points where they pass the piece's ends and the shared point
/// lie farther than `depth` from the one line, or the two meet at more than [`BOW_ANGLE`]
/// (or a line cannot be fitted). A corner or a step departs by its depth; a wall bowed by a
/// few millimetres, or read through a scanner's slowly changing range error, by no more
/// than that, however many its points.
pub(crate) fn bends(
    seg: Seg<'_>,
    pre: &[FitSums],
    (a, m, b): (usize, usize, usize),
    depth: f64,
) -> bool {
    let fits = (
        sums(pre, a, b + 1).normal_fit(),
        sums(pre, a, m + 1).normal_fit(),
        sums(pre, m, b + 1).normal_fit(),
    );
    let (Some(whole), Some(first), Some(second)) = fits else {
        return true;
    };
    let (u, v) = (first.normal, second.normal);
    if (u.x * v.y - u.y * v.x).abs() > BOW_ANGLE || u.dot(&v) < 0.0 {
        return true;
    }
    let on = |line: &NormalFit, k: usize| {
        let q = seg.point(k);
        q - line.normal * line.distance(q)
    };
    let departs = |line: &NormalFit, k: usize| whole.distance(on(line, k)).abs() > depth;
    // A step departs from the joint line by half its height on each side: the two lines'
    // own distance at the split point tells it whole.
    second.distance(on(&first, m)).abs() > depth
        || departs(&first, a)
        || departs(&first, m)
        || departs(&second, m)
        || departs(&second, b)
}

/// The position in `a + 1..b` where two lines fit `seg[a..=b]` best (least total squared
/// residual), or `None` for fewer than five points.
fn best_split(pre: &[FitSums], a: usize, b: usize) -> Option<usize> {
    if b < a + 4 {
        return None;
    }
    let mut best = (f64::INFINITY, None);
    for m in a + 2..b - 1 {
        let sse = sums(pre, a, m + 1).sse() + sums(pre, m, b + 1).sse();
        if sse < best.0 {
            best = (sse, Some(m));
        }
    }
    best.1
}

/// How far from the chord, in sigma of the noise across it, the points of an excursion
/// ([`excursion`]) lie: as far as a lone jump the segments drop as noise may lie
/// (`SPIKE_SIGMAS` of `segment.rs`), so that the noise of a wall makes one about once in two
/// million points.
const EXCURSION_SIGMAS: f64 = 5.0;

/// How `Linseg` divides a piece.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Split {
    /// Two pieces sharing this point.
    At(usize),
    /// Three pieces: up to the first point, the excursion between the two, from the second on.
    Around(usize, usize),
}

/// The excursion around `middle`, the farthest point of `seg[a..=b]` from the chord `pa`-`pb`:
/// the run of consecutive points around it that all lie more than [`EXCURSION_SIGMAS`] from
/// the chord, returned as the points just before and just after it. Only a run of fewer
/// than `min_points` points (too few for a line of its own) with at least two points on each
/// side counts: a leg or a post in front of a wall, near enough to it that the breakpoint
/// distance joined their points into one data segment. Both of its neighbours share it: a
/// split at its farthest point leaves it in both pieces, neither fits a line, and no split
/// is significant, though the wall on both sides is one line. It is cut out only when the
/// piece with it fails the RMS gate of a line ([`fits_a_line`]): a wall with a spike it
/// can carry stays one line.
fn excursion(
    seg: Seg<'_>,
    (a, middle, b): (usize, usize, usize),
    p: &HoughSplitParams,
    noise: &RangeNoise,
    min_points: usize,
) -> Option<(usize, usize)> {
    let (pa, pb) = (seg.point(a), seg.point(b));
    let ab = pb - pa;
    // Degenerate as `split_point` takes it: then the farthest point is no excursion.
    if ab.norm_squared() <= f64::EPSILON {
        return None;
    }
    let normal = Vector2::new(-ab.y, ab.x) / ab.norm();
    let off = |k: usize| {
        let q = seg.point(k);
        chord_distance(q, pa, pb)
            > EXCURSION_SIGMAS
                * noise.sigma(seg.range(k))
                * incidence_cos(q, normal, p.noise_along_beams)
    };
    if !off(middle) {
        return None;
    }
    let (mut s, mut e) = (middle, middle);
    while s > a && off(s - 1) {
        s -= 1;
    }
    while e < b && off(e + 1) {
        e += 1;
    }
    let short = e - s + 1 < min_points.max(2);
    // The chord passes through both ends, which are never off: a < s <= e < b.
    (short && s >= a + 2 && e + 2 <= b).then(|| (s - 1, e + 1))
}

/// True when one line fits `seg[a..=b]` within the noise: its sum of squared residuals, in
/// variances of the noise across it at its centroid ([`variance_across`]), passes a
/// chi-square test at the 1e-4 level.
pub(crate) fn within_noise(
    pre: &[FitSums],
    (a, b): (usize, usize),
    p: &HoughSplitParams,
    noise: &RangeNoise,
) -> bool {
    one_line_fits(&sums(pre, a, b + 1), p, noise)
}

/// [`within_noise`] for the points summed in `s`.
pub(crate) fn one_line_fits(s: &FitSums, p: &HoughSplitParams, noise: &RangeNoise) -> bool {
    let dof = s.len().saturating_sub(2) as f64;
    let one_line = s.sse() / variance_across(s, noise, p.noise_along_beams);
    one_line <= dof + 5.3 * (2.0 * dof).sqrt()
}

/// True when `fit` passes the gate of its RMS residual that every line must pass:
/// `max_rms_sigmas` of the noise at its centroid (a NaN fails).
pub(crate) fn rms_passes(fit: &PolarFit, p: &HoughSplitParams, noise: &RangeNoise) -> bool {
    rms_within(fit.rms, fit.centroid.coords.norm(), p, noise)
}

/// The gate of [`rms_passes`] for an RMS residual `rms` at a centroid `distance` m from the
/// sensor (a bow merged into one line must still give a line: [`split_is_significant`]).
fn rms_within(rms: f64, distance: f64, p: &HoughSplitParams, noise: &RangeNoise) -> bool {
    rms <= p.max_rms_sigmas * noise.sigma(distance)
}

/// True when the line of `seg[a..=b]` passes the RMS gate ([`rms_passes`]).
fn fits_a_line(
    pre: &[FitSums],
    (a, b): (usize, usize),
    p: &HoughSplitParams,
    noise: &RangeNoise,
) -> bool {
    sums(pre, a, b + 1)
        .fit()
        .is_some_and(|fit| rms_passes(&fit, p, noise))
}

/// Where `Linseg` divides `seg[a..=b]`, or `None` when the piece is one line.
///
/// The paper's rule first: the point farthest from the chord, when it lies beyond
/// `split_sigmas * sigma(r)`. With a significance test (`split_significance > 0`), the split
/// must also be significant; when it is not but the piece as a whole does not fit one line
/// within the noise (a chi-square test at the 1e-4 level), an [`excursion`] around the
/// farthest point is cut out, or else the best split by least squares is tried (the
/// farthest point can be an outlier while a shallow corner lies elsewhere).
fn split_point(
    seg: Seg<'_>,
    pre: &[FitSums],
    (a, b): (usize, usize),
    p: &HoughSplitParams,
    (noise, min_points): (&RangeNoise, usize),
) -> Option<Split> {
    if b < a + 2 {
        return None;
    }
    let (pa, pb) = (seg.point(a), seg.point(b));
    // Farthest point from the chord, compared by |cross product| (distance times chord
    // length) so that only the winner needs a division. When the chord's ends coincide, the
    // farthest point from them is taken instead.
    let ab = pb - pa;
    let degenerate = ab.norm_squared() <= f64::EPSILON;
    let mut best = (0.0f64, a);
    for (m, pt) in seg.0[a + 1..b].iter().enumerate() {
        let (apx, apy) = (pt.x - pa.x, pt.y - pa.y);
        let c = if degenerate {
            apx * apx + apy * apy
        } else {
            (ab.x * apy - ab.y * apx).abs()
        };
        if c > best.0 {
            best = (c, a + 1 + m);
        }
    }
    let middle = best.1;
    if middle == a {
        return None;
    }
    let far = seg.point(middle);
    // The noise across the chord at the farthest point.
    let cos = if degenerate {
        1.0
    } else {
        incidence_cos(
            far,
            Vector2::new(-ab.y, ab.x) / ab.norm(),
            p.noise_along_beams,
        )
    };
    if chord_distance(far, pa, pb) <= p.split_sigmas * noise.sigma(seg.range(middle)) * cos {
        return None;
    }
    if p.split_significance <= 0.0 || split_is_significant(seg, pre, (a, middle, b), p, noise) {
        return Some(Split::At(middle));
    }
    if within_noise(pre, (a, b), p, noise) {
        return None;
    }
    if p.cut_excursions
        && !fits_a_line(pre, (a, b), p, noise)
        && let Some((s, e)) = excursion(seg, (a, middle, b), p, noise, min_points)
    {
        return Some(Split::Around(s, e));
    }
    best_split(pre, a, b)
        .filter(|&m| split_is_significant(seg, pre, (a, m, b), p, noise))
        .map(Split::At)
}

/// Runs `Linseg(start, end)` over the points of `seg` (in beam order), whose prefix
/// sums are `scratch.prefix`, and leaves the split tree's end points in `scratch.breaks`, as
/// positions in `seg`, ascending, first and last included. Neighbouring pieces share their
/// end point, as in the paper. `min_points` is the fewest points of a line.
pub(crate) fn linseg(
    seg: Seg<'_>,
    p: &HoughSplitParams,
    noise: &RangeNoise,
    min_points: usize,
    scratch: &mut SplitScratch,
) {
    scratch.breaks.clear();
    scratch.stack.clear();
    if seg.len() == 0 {
        return;
    }
    let last = (seg.len() - 1) as u32;
    scratch.breaks.push(0);
    scratch.stack.push((0, last));
    // Depth-first, left piece first: breaks come out in ascending order.
    while let Some((a, b)) = scratch.stack.pop() {
        let piece = (a as usize, b as usize);
        match split_point(seg, &scratch.prefix, piece, p, (noise, min_points)) {
            Some(Split::At(m)) => {
                scratch.stack.push((m as u32, b));
                scratch.stack.push((a, m as u32));
            }
            Some(Split::Around(s, e)) => {
                scratch.stack.push((e as u32, b));
                scratch.stack.push((s as u32, e as u32));
                scratch.stack.push((a, s as u32));
            }
            None => {
                if b != 0 {
                    scratch.breaks.push(b);
                }
            }
        }
    }
}

#[cfg(test)]
#[path = "linseg_tests.rs"]
mod tests;
