//! The recursive split of a cluster into pieces: iterative end-point fit or split-and-merge.

use super::model::Scaled;
use super::runs::Run;
use crate::fit::FitSums;
use crate::math::Point2;
use crate::scan::ScanPoint;

/// How a piece is split: the line the distances of its points are measured from. The one
/// difference between [`super::SplitMerge`]'s two variants.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SplitLine {
    /// Iterative end-point fit (`iepf`): distances to the chord between the piece's end
    /// points, the paper's `Linseg`.
    Chord,
    /// Split-and-merge (`split-and-merge`): distances to the piece's least-squares line.
    LeastSquares,
}

/// Distance of `p` from the infinite line through `a` and `b` (or from `a` when they meet).
pub(crate) fn chord_distance(p: Point2, a: Point2, b: Point2) -> f64 {
    let ab = b - a;
    let len = ab.norm();
    if len.is_nan() || len <= f64::EPSILON {
        return (p - a).norm();
    }
    (ab.x * (p.y - a.y) - ab.y * (p.x - a.x)).abs() / len
}

/// Recursive split of `cluster` with an explicit stack. Appends the pieces to `pieces`, in
/// order; neighbouring pieces meet at the split point, which starts the right-hand piece
/// ([`finish`] later gives it to the line that explains it better).
pub(crate) fn split(
    points: &[ScanPoint],
    cluster: Run,
    how: SplitLine,
    threshold: Scaled,
    stack: &mut Vec<(usize, usize)>,
    pieces: &mut Vec<Run>,
) {
    if cluster.len() < 2 {
        return;
    }
    stack.clear();
    // Inclusive piece bounds; depth-first, left first: pieces come out in order.
    stack.push((cluster.start, cluster.end - 1));
    while let Some((a, b)) = stack.pop() {
        let mut best: Option<(f64, usize)> = None;
        match how {
            SplitLine::Chord => {
                let (pa, pb) = (points[a].point, points[b].point);
                for (m, sp) in points.iter().enumerate().take(b).skip(a + 1) {
                    let d = chord_distance(sp.point, pa, pb);
                    if best.is_none_or(|(bd, _)| d > bd) {
                        best = Some((d, m));
                    }
                }
            }
            SplitLine::LeastSquares => {
                if let Some(fit) =
                    FitSums::from_points(points[a..=b].iter().map(|sp| sp.point)).fit()
                {
                    // Interior points only: splitting at an end would make no progress.
                    let distance = fit.distance_fn();
                    for (m, sp) in points.iter().enumerate().take(b).skip(a + 1) {
                        let d = distance(sp.point).abs();
                        if best.is_none_or(|(bd, _)| d > bd) {
                            best = Some((d, m));
                        }
                    }
                }
            }
        }
        match best {
            Some((d, m)) if d > threshold.at(points[m].range) => {
                stack.push((m, b));
                stack.push((a, m));
            }
            _ => {
                // A leaf. Its last point starts the next piece, except at the cluster's end.
                let end = if b + 1 == cluster.end { cluster.end } else { b };
                if end > a {
                    pieces.push(Run { start: a, end });
                }
            }
        }
    }
}
