//! Scans that go once round ([`ScanView::full_turn`](crate::ScanView::full_turn)): the beam
//! to walk them from, so that no surface is cut at the seam between the last beam and the
//! first, and the lines of the walk back in the scan's own beam indices.
//!
//! The walk starts at a break that no surface crosses: after the widest gap between two
//! returns that follow each other round the turn, among those with at least
//! [`BREAK_BEAMS`] beams without a return between them (more than the beam bridge spans on a
//! dense scan), or a depth step of [`BREAK_STEP`] of the nearer range that is
//! [`STEP_PROMINENCE`] times the steps on either side of it (the edge of an object; along a
//! wall seen at a glancing angle the steps grow smoothly, and range noise of a few per cent
//! makes none). The width counts beam spacings at the nearer return: a depth step of `dr` at
//! range `r` counts `dr / (r |increment|)`, a run of `m` beams without a return `m + 1`, and
//! the two add as the sides of a right angle. Where there is no such break (a closed room),
//! the walk starts at the farthest return: a corner, in a room seen from inside. When the
//! walk still cuts a surface (its last line and its first take one fit, and nothing but
//! beams that returned nothing lies between them), the two are one line ([`join_ends`]). A
//! line across the seam has `first > last` ([`Line`](crate::Line)).

use super::collinear::take_in;
use super::lines::{SILENT_GAP, returned_nothing};
use crate::line::Line;
use crate::math::Point2;

/// Beams without a return between two returns that make a break.
pub(crate) const BREAK_BEAMS: usize = 3;

/// Depth step between two returns, as a fraction of the nearer range, that may make a break.
pub(crate) const BREAK_STEP: f64 = 0.1;

/// How many times the steps before and after it (each as a fraction of its nearer range) a
/// depth step must be to make a break.
pub(crate) const STEP_PROMINENCE: f64 = 3.0;

/// The beam to walk a full turn from (see the module docs): 0 when that is where the walk
/// would start anyway (at the first return), or the scan has fewer than three returns in
/// `lo..=hi`. `returns` is working memory.
pub(crate) fn start(
    ranges: &[f64],
    (lo, hi): (f64, f64),
    increment: f64,
    returns: &mut Vec<(usize, f64)>,
) -> usize {
    returns.clear();
    returns.extend(
        ranges
            .iter()
            .enumerate()
            .filter(|&(_, &r)| r >= lo && r <= hi)
            .map(|(i, &r)| (i, r)),
    );
    let (n, m) = (ranges.len(), returns.len());
    if m < 3 {
        return 0;
    }
    let step = increment.abs();
    let at = |k: usize| returns[k % m];
    // The depth step from return `k` to the next, as a fraction of the nearer range.
    let rel = |k: usize| {
        let (a, b) = (at(k).1, at(k + 1).1);
        (a - b).abs() / a.min(b)
    };
    let (mut widest, mut far) = (None::<(f64, usize)>, returns[0]);
    for k in 0..m {
        let ((a, ra), (b, rb)) = (at(k), at(k + 1));
        if ra > far.1 {
            far = (a, ra);
        }
        let beams = (b + n - a) % n;
        let depth = rel(k);
        let edge = depth >= BREAK_STEP && depth >= STEP_PROMINENCE * rel(k + m - 1).max(rel(k + 1));
        if beams <= BREAK_BEAMS && !edge {
            continue;
        }
        let spacings = (ra - rb).abs() / (ra.min(rb) * step);
        let width = (beams * beams) as f64 + spacings * spacings;
        if widest.is_none_or(|(w, _)| width > w) {
            widest = Some((width, b));
        }
    }
    let first = widest.map_or(far.0, |(_, b)| b);
    if first == returns[0].0 { 0 } else { first }
}

/// Joins the last line of a walk to its first when the walk cut one surface, as step 7
/// joins neighbours ([`super::collinear`]): both took one fit (the same `r` and `alpha`),
/// and their facing supporting points `ends` (the last line's last, the first line's first)
/// follow each other round the turn, or every beam between them returned nothing or lay
/// below `lo` and the two lie within [`SILENT_GAP`]. The last line takes the first's end, last
/// beam and points (its `last` is then below its `first`), and the RMS of both; the first is
/// removed.
pub(crate) fn join_ends(out: &mut Vec<Line>, walk: &[f64], lo: f64, ends: (Point2, Point2)) {
    let n = walk.len();
    let (Some(&first), Some(&last)) = (out.first(), out.last()) else {
        return;
    };
    let one_fit =
        first.r.to_bits() == last.r.to_bits() && first.alpha.to_bits() == last.alpha.to_bits();
    if out.len() < 2 || !one_fit || last.last >= n || first.first > last.first {
        return;
    }
    let neighbours = last.last + 1 == n && first.first == 0;
    let silent = walk[last.last + 1..]
        .iter()
        .chain(&walk[..first.first])
        .all(|&r| returned_nothing(r, lo));
    if !(neighbours || (silent && (ends.1 - ends.0).norm() <= SILENT_GAP)) {
        return;
    }
    if let Some(line) = out.last_mut() {
        take_in(line, &first);
        out.remove(0);
    }
}

/// Maps the lines of a walk from beam `seam` of `n` back to the scan's beam indices, in
/// ascending order of `first` (a line across the seam, `first > last`, comes last), and the
/// split points likewise.
pub(crate) fn unwalk(out: &mut [Line], split_points: &mut [usize], seam: usize, n: usize) {
    if seam == 0 || n == 0 {
        return;
    }
    let beam = |w: usize| (w + seam) % n;
    // Lines that start before the walk reaches beam 0 keep their order and come last.
    let before_zero = out.iter().take_while(|l| l.first < n - seam).count();
    for l in out.iter_mut() {
        (l.first, l.last) = (beam(l.first), beam(l.last));
    }
    out.rotate_left(before_zero);
    for b in split_points.iter_mut() {
        *b = beam(*b);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const INC: f64 = std::f64::consts::TAU / 10.0;

    fn start_of(ranges: &[f64], increment: f64) -> usize {
        start(ranges, (0.1, 5.0), increment, &mut Vec::new())
    }

    #[test]
    fn the_walk_starts_after_the_widest_gap() {
        // Beams 2 to 4 see nothing: the gap before beam 5 is a break.
        let ranges = [
            1.0,
            1.0,
            f64::NAN,
            f64::NAN,
            f64::NAN,
            1.0,
            1.0,
            1.0,
            1.0,
            1.0,
        ];
        assert_eq!(start_of(&ranges, INC), 5);
        // Two beams without a return are no break (the beam bridge spans them); the farthest
        // return starts the walk.
        let ranges = [1.0, 1.0, f64::NAN, f64::NAN, 1.0, 1.05, 1.0, 1.0, 1.0, 1.0];
        assert_eq!(start_of(&ranges, INC), 5);
        // Depth steps of 1 m at 1 m and of 0.5 m at 1.5 m beside steps of 0: both are
        // breaks, the first is wider (1.59 spacings against 0.53).
        let ranges = [1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 2.0, 1.5, 1.5, 1.5];
        assert_eq!(start_of(&ranges, -INC), 3);
        // Steps of 9 % are none: the farthest return.
        let ranges = [1.0, 1.09, 1.0, 1.09, 1.19, 1.09, 1.0, 1.09, 1.0, 1.09];
        assert_eq!(start_of(&ranges, INC), 4);
        // Walls seen at a glancing angle: steps of 20-30 % that change smoothly, none a
        // break; the farthest return.
        let ranges = [1.0, 1.2, 1.5, 1.9, 2.4, 3.1, 2.4, 1.9, 1.5, 1.2];
        assert_eq!(start_of(&ranges, INC), 5);
        // An object's edge among them, three times the steps beside it, is one.
        let ranges = [1.0, 1.2, 1.5, 1.9, 2.4, 3.1, 1.0, 1.0, 1.0, 1.0];
        assert_eq!(start_of(&ranges, INC), 6);
    }

    #[test]
    fn a_walk_already_starting_at_its_widest_gap_is_not_moved() {
        let ranges = [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, f64::NAN, f64::NAN, f64::NAN];
        assert_eq!(start_of(&ranges, INC), 0);
        assert_eq!(start_of(&[f64::NAN; 8], INC), 0);
        let two = [
            f64::NAN,
            1.0,
            f64::NAN,
            f64::NAN,
            f64::NAN,
            f64::NAN,
            f64::NAN,
            1.0,
        ];
        assert_eq!(start_of(&two, INC), 0);
    }

    /// Lines of one fit on beams `first..=last` of a walk, with end points `start`, `end`.
    fn on_wall(first: usize, last: usize, start: (f64, f64), end: (f64, f64)) -> Line {
        Line {
            start: Point2::new(start.0, start.1),
            end: Point2::new(end.0, end.1),
            r: 2.0,
            alpha: 0.0,
            first,
            last,
            points: last - first + 1,
            rms: 0.01,
            covariance: crate::math::Matrix2::zeros(),
        }
    }

    #[test]
    fn the_walks_ends_are_joined_when_nothing_parts_them() {
        // A walk of 20 beams: one line of beams 0-5, one of 14-18 on the same wall.
        let join = |walk: &[f64], ends: (Point2, Point2)| -> Vec<(usize, usize)> {
            let mut out = vec![
                on_wall(0, 5, (2.0, 0.3), (2.0, 0.8)),
                on_wall(8, 11, (2.0, 1.0), (2.0, 1.5)),
                on_wall(14, 18, (2.0, -0.8), (2.0, -0.1)),
            ];
            join_ends(&mut out, walk, 0.1, ends);
            out.iter().map(|l| (l.first, l.last)).collect()
        };
        let mut walk = [2.0; 20];
        walk[19] = f64::NAN;
        let near = (Point2::new(2.0, -0.1), Point2::new(2.0, 0.05));
        let far = (Point2::new(2.0, -0.1), Point2::new(2.0, 0.3));
        // Beam 19 returned nothing, and the two ends lie 15 cm apart: one line, 14 to 5.
        assert_eq!(join(&walk, near), [(8, 11), (14, 5)]);
        // 40 cm apart, or beam 19 saw something: two lines.
        assert_eq!(join(&walk, far), [(0, 5), (8, 11), (14, 18)]);
        walk[19] = 0.05;
        assert_eq!(join(&walk, near), [(8, 11), (14, 5)]);
        walk[19] = 1.0;
        assert_eq!(join(&walk, near), [(0, 5), (8, 11), (14, 18)]);
        // Lines of two fits are never joined.
        let mut out = vec![
            on_wall(0, 5, (2.0, 0.3), (2.0, 0.8)),
            on_wall(14, 19, (2.0, -0.8), (2.0, 0.0)),
        ];
        out[1].r = 2.1;
        join_ends(&mut out, &walk, 0.1, near);
        assert_eq!(out.len(), 2);
        // Neighbours round the turn are joined, with both lines' points and RMS.
        out[1].r = 2.0;
        out[1].rms = 0.02;
        join_ends(&mut out, &walk, 0.1, far);
        assert_eq!(
            (out.len(), out[0].first, out[0].last, out[0].points),
            (1, 14, 5, 12)
        );
        assert!((out[0].rms - (0.5f64 * (0.0001 + 0.0004)).sqrt()).abs() < 1e-12);
        assert_eq!(out[0].end, Point2::new(2.0, 0.8));
    }

    #[test]
    fn lines_of_a_walk_come_back_in_beam_order() {
        let line = |first, last| Line {
            start: crate::math::Point2::new(1.0, 0.0),
            end: crate::math::Point2::new(1.0, 1.0),
            r: 1.0,
            alpha: 0.0,
            first,
            last,
            points: 3,
            rms: 0.0,
            covariance: crate::math::Matrix2::zeros(),
        };
        // A walk of 10 beams from beam 6: walk beams 0-2 are 6-8, 3-5 are 9, 0, 1, 6-9 are 2-5.
        let mut out = [line(0, 2), line(3, 5), line(6, 9)];
        let mut splits = [0, 2, 3, 5, 6, 9];
        unwalk(&mut out, &mut splits, 6, 10);
        let beams: Vec<_> = out.iter().map(|l| (l.first, l.last)).collect();
        assert_eq!(beams, [(2, 5), (6, 8), (9, 1)]);
        assert_eq!(splits, [6, 8, 9, 1, 2, 5]);
        assert!(out[2].wraps() && out[2].covers(0) && !out[2].covers(2));
        assert_eq!(out[2].beam_span(10), 3);
    }
}
