//! The collinear merge of neighbouring pieces.

use super::model::Scaled;
use super::runs::Run;
use crate::fit::FitSums;
use crate::scan::ScanPoint;

/// True when every point of `points[from..to]` lies within its threshold of their joint
/// least-squares line.
pub(crate) fn collinear(points: &[ScanPoint], from: usize, to: usize, threshold: Scaled) -> bool {
    let Some(fit) = FitSums::from_points(points[from..to].iter().map(|sp| sp.point)).fit() else {
        return false;
    };
    let distance = fit.distance_fn();
    points[from..to]
        .iter()
        .all(|sp| distance(sp.point).abs() <= threshold.at(sp.range))
}

/// Merges adjacent pieces (`pieces[i].end == pieces[i + 1].start`, all members) greedily from
/// left to right while all their points lie within `threshold` of the joint least-squares line.
pub(crate) fn merge_collinear(points: &[ScanPoint], pieces: &mut Vec<Run>, threshold: Scaled) {
    if pieces.len() < 2 {
        return;
    }
    let mut w = 0;
    for r in 1..pieces.len() {
        let (cur, next) = (pieces[w], pieces[r]);
        if cur.end == next.start && collinear(points, cur.start, next.end, threshold) {
            pieces[w].end = next.end;
        } else {
            w += 1;
            pieces[w] = next;
        }
    }
    pieces.truncate(w + 1);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::extractors::split::{SplitLine, split};
    use crate::extractors::test_support::l_shape;

    #[test]
    fn both_splits_cut_an_l_at_its_corner() {
        let (points, corner) = l_shape();
        for how in [SplitLine::Chord, SplitLine::LeastSquares] {
            let mut pieces = Vec::new();
            let mut stack = Vec::new();
            let cluster = Run {
                start: 0,
                end: points.len(),
            };
            let t = Scaled {
                base: 0.02,
                per_metre: 0.0,
            };
            split(&points, cluster, how, t, &mut stack, &mut pieces);
            merge_collinear(&points, &mut pieces, t);
            // The corner point may end the first piece or start the second.
            assert_eq!(pieces.len(), 2, "{how:?}: {pieces:?}");
            let cut = pieces[0].end;
            assert!(cut == corner || cut == corner + 1, "{how:?}: {pieces:?}");
            assert_eq!(
                (pieces[0].start, pieces[1].start, pieces[1].end),
                (0, cut, points.len())
            );
        }
    }
}
