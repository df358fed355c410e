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

fn sums(points: &[ScanPoint], seg: &[u32], from: usize, to: usize) -> FitSums {
    FitSums::from_points(seg[from..to].iter().map(|&i| points[i as usize].point))
}

/// True when every point of `seg[from..to]` lies within its split threshold of the pieces'
/// joint least-squares line.
fn collinear(
    points: &[ScanPoint],
    seg: &[u32],
    from: usize,
    to: usize,
    p: &HoughSplitParams,
) -> bool {
    let Some(fit) = sums(points, seg, from, to).fit() else {
        return false;
    };
    seg[from..to].iter().all(|&i| {
        let sp = &points[i as usize];
        fit.distance(sp.point).abs() <= p.split_threshold(sp.range)
    })
}

/// Turns the split tree's end points of one segment into lines appended to `out`.
///
/// The shared end point of two neighbouring pieces goes to the piece whose least-squares line
/// (fitted without it) passes closer, so that every point supports at most one line.
pub(crate) fn emit_lines(
    points: &[ScanPoint],
    seg: &[u32],
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
            if collinear(points, seg, from, to, p) {
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
    // Piece i covers seg[lo..hi] with disjoint bounds.
    let mut lo = 0usize;
    for i in 1..breaks.len() {
        let b = breaks[i] as usize;
        let hi = if i + 1 == breaks.len() {
            seg.len()
        } else {
            // Give the shared point b to this piece or to the next one.
            let next = breaks[i + 1] as usize;
            let here = sums(points, seg, lo, b).fit();
            let there = sums(points, seg, b + 1, next + 1).fit();
            let pt = points[seg[b] as usize].point;
            match (here, there) {
                (Some(h), Some(t)) if t.distance(pt).abs() < h.distance(pt).abs() => b,
                _ => b + 1,
            }
        };
        if hi > lo
            && hi - lo >= min_points
            && let Some(fit) = sums(points, seg, lo, hi).fit()
        {
            let first = &points[seg[lo] as usize];
            let last = &points[seg[hi - 1] as usize];
            let line = Line::from_fit(&fit, (first.index, first.point), (last.index, last.point));
            if line.length() >= p.min_line_length {
                out.push(line);
            }
        }
        lo = hi;
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
        emit_lines(&points, &seg, &mut breaks, &p, &mut out);
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
