//! Scans that go once round ([`ScanView::full_turn`](crate::ScanView::full_turn)): the beam
//! to walk them from, so that no surface is cut at the seam between the last beam and the
//! first, and the lines of the walk back in the scan's own beam indices.
//!
//! The walk starts at a break that no surface crosses: after the widest gap between two
//! returns that follow each other round the turn, among those with at least
//! [`BREAK_BEAMS`] beams without a return between them or a depth step of
//! [`BREAK_STEP`] of the nearer range (range noise of a few per cent, and walls seen at less
//! than about 80 deg from their normal, make neither). The width counts beam spacings at the
//! nearer return: a depth step of `dr` at range `r` counts `dr / (r |increment|)`, a run of
//! `m` beams without a return `m + 1`, and the two add as the sides of a right angle. Where
//! there is no such break (a closed room), the walk starts at the farthest return: a corner,
//! in a room seen from inside. When the walk still cuts a surface (its last line and its
//! first take one fit and nothing lies between them), the two are one line ([`join_ends`]).
//! A line across the seam has `first > last` ([`Line`](crate::Line)).

use super::lines::SILENT_GAP;
use crate::line::Line;
use crate::math::Point2;

/// Beams without a return between two returns that make a break.
pub(crate) const BREAK_BEAMS: usize = 2;

/// Depth step between two returns, as a fraction of the nearer range, that makes a break.
pub(crate) const BREAK_STEP: f64 = 0.1;

/// The beam to walk a full turn from (see the module docs): 0 when that is where the walk
/// would start anyway (at the first return), or the scan has fewer than two returns in
/// `lo..=hi`.
pub(crate) fn start(ranges: &[f64], (lo, hi): (f64, f64), increment: f64) -> usize {
    let n = ranges.len();
    let step = increment.abs();
    // The width of the gap from `a` to `b` in beam spacings, squared, if it is a break.
    let width = |(a, ra): (usize, f64), (b, rb): (usize, f64)| -> Option<f64> {
        let beams = (b + n - a) % n;
        let near = ra.min(rb);
        let depth = (ra - rb).abs();
        let spacings = depth / (near * step);
        (beams > BREAK_BEAMS || depth >= BREAK_STEP * near)
            .then_some((beams * beams) as f64 + spacings * spacings)
    };
    let mut returns = ranges
        .iter()
        .enumerate()
        .filter(|&(_, &r)| r >= lo && r <= hi)
        .map(|(i, &r)| (i, r));
    let Some(v0) = returns.next() else {
        return 0;
    };
    let (mut prev, mut far) = (v0, v0);
    let mut widest: Option<(f64, usize)> = None;
    for next in returns.chain([v0]) {
        if let Some(w) = width(prev, next)
            && widest.is_none_or(|(best, _)| w > best)
        {
            widest = Some((w, next.0));
        }
        if next.1 > far.1 {
            far = next;
        }
        prev = next;
    }
    let first = widest.map_or(far.0, |(_, b)| b);
    if first == v0.0 { 0 } else { first }
}

/// Joins the last line of a walk to its first when the walk cut one surface: both took one
/// fit (the same `r` and `alpha`, step 7), and every beam between them round the turn
/// returned nothing or lay below `lo`, with their facing supporting points `ends` (the last
/// line's last, the first line's first) within [`SILENT_GAP`] when there is such a beam. The
/// last line takes the first's end, last beam and points (its `last` is then below its
/// `first`), and the RMS of both; the first is removed.
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
    let silent = |r: &f64| r.is_nan() || *r < lo;
    let quiet = walk[last.last + 1..]
        .iter()
        .chain(&walk[..first.first])
        .all(silent);
    let none = last.last + 1 == n && first.first == 0;
    if !quiet || !(none || (ends.1 - ends.0).norm() <= SILENT_GAP) {
        return;
    }
    let (na, nb) = (last.points as f64, first.points as f64);
    if let Some(joined) = out.last_mut() {
        joined.end = first.end;
        joined.last = first.last;
        joined.points = last.points + first.points;
        joined.rms = ((last.rms * last.rms * na + first.rms * first.rms * nb) / (na + nb)).sqrt();
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

    const INC: f64 = std::f64::consts::TAU / 8.0;

    #[test]
    fn the_walk_starts_after_the_widest_gap() {
        // Beams 2 and 3 see nothing: the gap before beam 4 is a break.
        let ranges = [1.0, 1.0, f64::NAN, f64::NAN, 1.0, 1.0, 1.0, 1.0];
        assert_eq!(start(&ranges, (0.1, 5.0), INC), 4);
        // One beam without a return is no break; the farthest return starts the walk.
        let ranges = [1.0, 1.0, f64::NAN, 1.0, 1.0, 1.05, 1.0, 1.0];
        assert_eq!(start(&ranges, (0.1, 5.0), INC), 5);
        // A depth step of 1 m at 1 m is 1 / (pi / 4) = 1.27 spacings, one of 0.5 m at 1.5 m
        // 0.42; both are breaks, the first is wider.
        let ranges = [1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 2.0, 1.5];
        assert_eq!(start(&ranges, (0.1, 5.0), -INC), 3);
        // Steps of 9 % are none: the farthest return.
        let ranges = [1.0, 1.09, 1.0, 1.09, 1.19, 1.09, 1.0, 1.09];
        assert_eq!(start(&ranges, (0.1, 5.0), INC), 4);
    }

    #[test]
    fn a_walk_already_starting_at_its_widest_gap_is_not_moved() {
        let ranges = [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, f64::NAN, f64::NAN, f64::NAN];
        assert_eq!(start(&ranges, (0.1, 5.0), INC), 0);
        assert_eq!(start(&[f64::NAN; 8], (0.1, 5.0), INC), 0);
        let one = [
            f64::NAN,
            1.0,
            f64::NAN,
            f64::NAN,
            f64::NAN,
            f64::NAN,
            f64::NAN,
            9.0,
        ];
        assert_eq!(start(&one, (0.1, 5.0), INC), 0);
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
