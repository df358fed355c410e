//! Step 5-6: the recursive split `Linseg` (iterative end-point fit) with an explicit stack,
//! the optional merge of collinear neighbours, and the final least-squares fits.

use super::params::HoughSplitParams;
use crate::fit::FitSums;
use crate::line::Line;
use crate::math::Point2;
use crate::scan::ScanPoint;

/// Working memory of the split.
#[derive(Debug, Default, Clone)]
pub(crate) struct SplitScratch {
    stack: Vec<(u32, u32)>,
    pub(crate) breaks: Vec<u32>,
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

/// Runs `Linseg(start, end)` over `seg` (indices into `points`, in beam order) and leaves the
/// split tree's end points in `scratch.breaks`, as positions in `seg`, ascending, first and
/// last included. Neighbouring pieces share their end point, as in the paper.
pub(crate) fn linseg(
    points: &[ScanPoint],
    seg: &[u32],
    p: &HoughSplitParams,
    scratch: &mut SplitScratch,
) {
    scratch.breaks.clear();
    scratch.stack.clear();
    if seg.is_empty() {
        return;
    }
    let last = (seg.len() - 1) as u32;
    scratch.breaks.push(0);
    scratch.stack.push((0, last));
    // Depth-first, left piece first: breaks come out in ascending order.
    while let Some((a, b)) = scratch.stack.pop() {
        let pa = points[seg[a as usize] as usize].point;
        let pb = points[seg[b as usize] as usize].point;
        // Farthest point from the chord, compared by |cross product| (distance times chord
        // length) so that only the winner needs a division.
        // When the chord's ends coincide, the farthest point from them is taken instead.
        let ab = pb - pa;
        let degenerate = ab.norm_squared() <= f64::EPSILON;
        let mut best = (0.0f64, a);
        for (m, &i) in seg.iter().enumerate().take(b as usize).skip(a as usize + 1) {
            let ap = points[i as usize].point - pa;
            let c = if degenerate {
                ap.norm_squared()
            } else {
                (ab.x * ap.y - ab.y * ap.x).abs()
            };
            if c > best.0 {
                best = (c, m as u32);
            }
        }
        let middle = best.1;
        let dist = chord_distance(points[seg[middle as usize] as usize].point, pa, pb);
        let range = points[seg[middle as usize] as usize].range;
        if middle == a || dist <= p.split_threshold(range) {
            if b != 0 {
                scratch.breaks.push(b);
            }
        } else {
            scratch.stack.push((middle, b));
            scratch.stack.push((a, middle));
        }
    }
}

/// Prefix sums of a segment's points: `pre[i]` holds the sums of `seg[..i]`.
pub(crate) fn prefix_sums(points: &[ScanPoint], seg: &[u32], pre: &mut Vec<FitSums>) {
    pre.clear();
    let mut acc = FitSums::new();
    pre.push(acc);
    for &i in seg {
        acc.add(points[i as usize].point);
        pre.push(acc);
    }
}

/// Sums of `seg[from..to]` from the prefix sums, O(1).
fn sums(pre: &[FitSums], from: usize, to: usize) -> FitSums {
    pre[to].since(&pre[from])
}

/// True when every point of `seg[from..to]` lies within its split threshold of the pieces'
/// joint least-squares line.
fn collinear(
    points: &[ScanPoint],
    seg: &[u32],
    pre: &[FitSums],
    from: usize,
    to: usize,
    p: &HoughSplitParams,
) -> bool {
    let Some(fit) = sums(pre, from, to).fit() else {
        return false;
    };
    let distance = fit.distance_fn();
    seg[from..to].iter().all(|&i| {
        let sp = &points[i as usize];
        distance(sp.point).abs() <= p.split_threshold(sp.range)
    })
}

/// Points on each side of a shared end point that [`best_cut`] may move to the other line.
const CUT_WINDOW: usize = 4;

/// Where to cut between the piece `seg[lo..=b]` and the piece `seg[b..=next]`, which share the
/// split point `b`: returns `c` such that the first piece keeps `seg[lo..c]`.
///
/// The split point is the farthest point from a chord, which noise can move a few points away
/// from the true corner. Both pieces are fitted without the `CUT_WINDOW` points around `b`,
/// and the cut is placed where the points of the window are best explained (least sum of
/// squared distances) by the line on their side.
fn best_cut(
    points: &[ScanPoint],
    seg: &[u32],
    pre: &[FitSums],
    lo: usize,
    b: usize,
    next: usize,
) -> usize {
    let wlo = b.saturating_sub(CUT_WINDOW).max(lo + 1);
    let whi = (b + CUT_WINDOW).min(next.saturating_sub(1));
    let left = sums(pre, lo, wlo).fit();
    let right = sums(pre, whi + 1, next + 1).fit();
    let (Some(left), Some(right)) = (left, right) else {
        // Pieces too short to fit without the window: the split point stays with the first.
        return b + 1;
    };
    if whi < wlo {
        return b + 1;
    }
    // cost(c) = sum over window points before c of dL^2 + from c on of dR^2.
    let (dl, dr) = (left.distance_fn(), right.distance_fn());
    let mut cost: f64 = seg[wlo..=whi]
        .iter()
        .map(|&k| dr(points[k as usize].point).powi(2))
        .sum();
    let mut best = (cost, wlo);
    for c in wlo..=whi {
        let q = points[seg[c] as usize].point;
        cost += dl(q).powi(2) - dr(q).powi(2);
        // Ties keep the cut nearest the split point.
        let better =
            cost < best.0 || (cost == best.0 && (c + 1).abs_diff(b + 1) < best.1.abs_diff(b + 1));
        if better {
            best = (cost, c + 1);
        }
    }
    best.1
}

/// Drops points at the ends of the piece `seg[lo..hi]` that another surface bent away: a short
/// leg of a corner too small for the split to see, or a mixed pixel.
///
/// For each end, the last `k <= min(CUT_WINDOW, n / 6)` points are tested against the fit of
/// the rest: each distance `d` is scaled by its expected spread, the point noise
/// (`split_threshold / 4`, the threshold being about four standard deviations) plus the
/// uncertainty of the fitted line at that point (from the fit's covariance). The `k` points are
/// cut when they all lie on one side and `sum(d^2 / var) >= 9` (three standard deviations
/// jointly), choosing the `k` with the largest excess `sum(d^2 / var - 1)`. Returns the new
/// bounds.
fn trim_ends(
    points: &[ScanPoint],
    seg: &[u32],
    pre: &[FitSums],
    lo: usize,
    hi: usize,
    min_points: usize,
    p: &HoughSplitParams,
) -> (usize, usize) {
    let (mut lo, mut hi) = (lo, hi);
    for from_end in [true, false] {
        let n = hi.saturating_sub(lo);
        let max_k = CUT_WINDOW
            .min(n / 6)
            .min(n.saturating_sub(min_points.max(3)));
        let mut rest = sums(pre, lo, hi);
        let mut best: Option<(f64, usize)> = None;
        for k in 1..=max_k {
            let idx = |j: usize| if from_end { hi - 1 - j } else { lo + j };
            rest.remove(points[seg[idx(k - 1)] as usize].point);
            let Some(fit) = rest.fit() else { break };
            // The normal once, for the distances and the positions along the line.
            let normal = fit.normal();
            let (ca, sa) = (normal.x, normal.y);
            let distance = |q: Point2| q.coords.dot(&normal) - fit.r;
            let cov = fit.covariance;
            let (mut chi2, mut sign) = (0.0, 0.0f64);
            let mut one_side = true;
            for j in 0..k {
                let sp = &points[seg[idx(j)] as usize];
                let d = distance(sp.point);
                if sign == 0.0 {
                    sign = d.signum();
                } else if d.signum() != sign {
                    one_side = false;
                }
                let noise = p.split_threshold(sp.range) / 4.0;
                let t = -sp.point.x * sa + sp.point.y * ca;
                let line_var = cov[(0, 0)] - 2.0 * t * cov[(0, 1)] + t * t * cov[(1, 1)];
                chi2 += d * d / (noise * noise + line_var.max(0.0));
            }
            let excess = chi2 - k as f64;
            if one_side && chi2 >= 9.0 && best.is_none_or(|(e, _)| excess > e) {
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

/// Turns the split tree's end points of one segment into lines appended to `out`.
///
/// Neighbouring pieces share their end point after the split; [`best_cut`] decides which
/// line each point near it supports, so that every point supports at most one line.
pub(crate) fn emit_lines(
    points: &[ScanPoint],
    seg: &[u32],
    pre: &[FitSums],
    breaks: &mut Vec<u32>,
    p: &HoughSplitParams,
    out: &mut Vec<Line>,
) {
    if breaks.len() < 2 {
        return;
    }
    if p.merge_collinear && breaks.len() > 2 {
        // Greedy left to right: drop a break when the pieces on both sides are one line.
        let mut w = 1;
        for r in 1..breaks.len() - 1 {
            let from = breaks[w - 1] as usize;
            let to = breaks[r + 1] as usize + 1;
            if collinear(points, seg, pre, from, to, p) {
                continue;
            }
            breaks[w] = breaks[r];
            w += 1;
        }
        let last = breaks[breaks.len() - 1];
        breaks[w] = last;
        breaks.truncate(w + 1);
    }
    let min_points = p.min_line_points.max(2);
    let first_line = out.len();
    // Piece i covers seg[lo..hi] with disjoint bounds.
    let mut lo = 0usize;
    for i in 1..breaks.len() {
        let b = breaks[i] as usize;
        let hi = if i + 1 == breaks.len() {
            seg.len()
        } else {
            best_cut(points, seg, pre, lo, b, breaks[i + 1] as usize)
        };
        let (a, z) = trim_ends(points, seg, pre, lo, hi, min_points, p);
        if z > a
            && z - a >= min_points
            && let Some(fit) = sums(pre, a, z).fit()
        {
            let first = &points[seg[a] as usize];
            let last = &points[seg[z - 1] as usize];
            let line = Line::from_fit(&fit, (first.index, first.point), (last.index, last.point));
            if line.length() >= p.min_line_length {
                out.push(line);
            }
        }
        lo = hi;
    }
    join_corners(&mut out[first_line..], p);
}

/// Neighbouring lines of one segment that meet at a corner share their end point, as in the
/// paper: the intersection of the two fitted lines, when it lies near both ends (within the
/// split threshold plus the gap between them) and the lines are not nearly parallel.
fn join_corners(lines: &mut [Line], p: &HoughSplitParams) {
    for k in 1..lines.len() {
        let (a, b) = (lines[k - 1], lines[k]);
        let (sa, ca) = a.alpha.sin_cos();
        let (sb, cb) = b.alpha.sin_cos();
        let det = ca * sb - sa * cb;
        // Lines closer than 15 deg to parallel: no well-defined corner.
        if det.abs() < 15f64.to_radians().sin() {
            continue;
        }
        let x = (a.r * sb - b.r * sa) / det;
        let y = (ca * b.r - cb * a.r) / det;
        let corner = crate::math::Point2::new(x, y);
        // Ends apart (a depth jump, not a corner) are left alone.
        let thr = p.split_threshold(corner.coords.norm());
        let gap = (b.start - a.end).norm();
        let reach = gap + thr;
        if gap <= 2.0 * thr
            && (corner - a.end).norm() <= reach
            && (corner - b.start).norm() <= reach
        {
            lines[k - 1].end = corner;
            lines[k].start = corner;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(xy: &[(f64, f64)]) -> Vec<ScanPoint> {
        xy.iter()
            .enumerate()
            .map(|(i, &(x, y))| ScanPoint {
                index: i,
                range: (x * x + y * y).sqrt(),
                angle: y.atan2(x),
                point: Point2::new(x, y),
            })
            .collect()
    }

    #[test]
    fn linseg_splits_an_l_at_its_corner() {
        // An L: wall x = 1 from y = -1 up to the corner (1, 0), then wall y = 0 towards x = 0.5.
        let mut xy = Vec::new();
        for i in 0..=10 {
            xy.push((1.0, -1.0 + 0.1 * i as f64));
        }
        for i in 1..=10 {
            xy.push((1.0 - 0.05 * i as f64, 0.0));
        }
        let points = pts(&xy);
        let seg: Vec<u32> = (0..points.len() as u32).collect();
        let p = HoughSplitParams::default();
        let mut scratch = SplitScratch::default();
        linseg(&points, &seg, &p, &mut scratch);
        assert_eq!(scratch.breaks, vec![0, 10, 20]);
        let mut out = Vec::new();
        let mut breaks = scratch.breaks.clone();
        let mut pre = Vec::new();
        prefix_sums(&points, &seg, &mut pre);
        emit_lines(&points, &seg, &pre, &mut breaks, &p, &mut out);
        assert_eq!(out.len(), 2);
        assert!((out[0].r - 1.0).abs() < 1e-9 && out[0].alpha.abs() < 1e-9);
        assert!(out[1].r.abs() < 1e-9);
        // The corner point went to exactly one line.
        assert_eq!(out[0].last + 1, out[1].first);
    }

    #[test]
    fn linseg_keeps_a_straight_run_whole() {
        let xy: Vec<(f64, f64)> = (0..50).map(|i| (2.0, -1.0 + 0.04 * i as f64)).collect();
        let points = pts(&xy);
        let seg: Vec<u32> = (0..50).collect();
        let mut scratch = SplitScratch::default();
        linseg(&points, &seg, &HoughSplitParams::default(), &mut scratch);
        assert_eq!(scratch.breaks, vec![0, 49]);
    }
}
