//! Whether beams see through a line: within one piece (an opening that step 6 cuts out of
//! a line, [`seen_through`]), and between two pieces (step 7's physical check on top of its
//! statistical one, [`super::collinear`]).
//!
//! Pieces of one wall lie apart because something stands in front of the wall between them
//! (its returns nearer than the wall), because the wall returned nothing there (glass, a dark
//! patch), or because of an opening in it (a doorway: returns beyond it). Beams between them
//! that see beyond their joint line for longer than a doorway show that no wall runs there.
//! Two short, uncertain pieces of different surfaces (a door leaf and a wall metres behind
//! it, seen at 6 m) pass the chi-square test for almost any line through both, and would
//! take one fit several degrees off each; collinear walls with a wide opening between them
//! are one line still, which a piece certain on its own shows.

use super::lines::SILENT_GAP;
use super::linseg::{MIN_INCIDENCE_COS, one_line_fits, sums};
use super::params::HoughSplitParams;
use super::points::{Pt, Seg};
use crate::fit::{FitSums, NormalFit};
use crate::math::Point2;
use crate::noise::RangeNoise;

/// Longest stretch of a joint line, m, that the beams between its pieces may see through: a
/// doorway, double doors included (up to about 1.8 m), or a missing arena panel (1.2 m).
pub(crate) const OPENING: f64 = 2.0;

/// Standard deviations of the range noise beyond the joint line from which a return sees
/// through it.
const BEYOND_SIGMAS: f64 = 3.0;

/// The length, m, of the stretch of the line `fit` between the pieces' facing ends `ends`
/// (projected onto it) that the returns on the beams strictly between `after` and `before`
/// (beam numbers of the last point of one piece and the first of the next; `returns` in beam
/// order) saw through: from the first to the last point of the line where a beam that
/// returned beyond it (by [`BEYOND_SIGMAS`]) meets it.
pub(crate) fn seen_beyond(
    returns: &[Pt],
    (after, before): (usize, usize),
    ends: (Point2, Point2),
    fit: &NormalFit,
    noise: &RangeNoise,
) -> f64 {
    if before <= after + 1 {
        return 0.0;
    }
    let start = returns.partition_point(|q| q.idx <= after);
    let (n, r) = (fit.normal, fit.r);
    // Along the line: the direction of the normal turned by 90 deg.
    let along = |x: f64, y: f64| y * n.x - x * n.y;
    let (a, b) = (along(ends.0.x, ends.0.y), along(ends.1.x, ends.1.y));
    let (from, to) = (a.min(b), a.max(b));
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for q in returns[start..].iter().take_while(|q| q.idx < before) {
        // The beam's direction against the normal: where the beam meets the line.
        let cos = (n.x * q.x + n.y * q.y) / q.range;
        if cos <= 0.0 {
            // The beam runs parallel to the line or away from it: it cannot meet it.
            continue;
        }
        let at = r / cos;
        if q.range <= at + BEYOND_SIGMAS * noise.sigma(at) {
            continue;
        }
        let t = along(q.x, q.y) * (at / q.range);
        // Where the beam meets the line beyond either piece: not between them.
        if from < t && t < to {
            lo = lo.min(t);
            hi = hi.max(t);
        }
    }
    (hi - lo).max(0.0)
}

/// How far beyond a piece's line, in sigma of the noise across it, a return sees through
/// it: as far as an excursion in front of one ([`super::linseg`]), about once in two million
/// returns of a wall by its noise alone.
pub(crate) const THROUGH_SIGMAS: f64 = 5.0;

/// How far beyond a piece's line, in sigma of the noise across it, the returns of a run that
/// sees through it lie, those between the ones beyond by [`THROUGH_SIGMAS`] (the far jamb
/// of a recessed door, seen next to the wall).
const RUN_SIGMAS: f64 = 3.0;

/// Depth, m, across a line that some return of a run beyond it must exceed, whatever the
/// noise: a door's frame, a skirting board, a pipe along a wall or a groove in it is no
/// opening.
pub(crate) const SHALLOW: f64 = 0.05;

/// Points on each side of a run that must fit one line for it to see through a surface.
const SIDE: usize = 4;

/// Widest gap, m, between a piece's points around a run that sees through its line that
/// does not cut the line: a groove, a gap between two panels or a door's frame, as narrow
/// as the stretch of silence a line may follow across ([`super::lines::SILENT_GAP`]).
const NARROW: f64 = SILENT_GAP;

/// The first run of returns that sees through the line of the points `seg[a..=b]`, as the
/// piece's points just before and just after it; `None` without one.
///
/// A run is a stretch of consecutive returns (`returns`: all the scan's, in beam order, those
/// removed as noise too) between the piece's first and last beams, each more than
/// [`RUN_SIGMAS`] of the noise across the line beyond it (farther from the sensor), two or
/// more of them by [`THROUGH_SIGMAS`] and one by [`SHALLOW`]. A return from beyond a surface
/// shows that the surface is not there: a doorway or a recess in a wall seen at a glancing
/// angle, whose few returns a line across it carries within its noise, or whose returns the
/// data segments dropped as sparse. A run sees through only where the surface goes on after
/// it: the piece's points next to it ([`SIDE`] on each side at most, [`SIDE`] in all at
/// least) fit one line within the noise ([`one_line_fits`]), its returns all lie beyond
/// that line by [`RUN_SIGMAS`] too, and the points around it lie more than [`NARROW`] apart.
/// Beyond a step in a wall, the points of the farther surface are no opening.
pub(crate) fn seen_through(
    (seg, pre): (Seg<'_>, &[FitSums]),
    returns: &[Pt],
    (a, b): (usize, usize),
    p: &HoughSplitParams,
    noise: &RangeNoise,
) -> Option<(usize, usize)> {
    let fit = sums(pre, a, b + 1).normal_fit()?;
    let (first, last) = (seg.idx(a), seg.idx(b));
    let from = returns.partition_point(|q| q.idx <= first);
    let inside = &returns[from..];
    let beyond = Beyond::new(&fit, noise, p.noise_along_beams);
    // The run as an opening: the piece's points around it.
    let opening = |run: &Run| {
        let points = &seg.0[..=b];
        let s = points
            .partition_point(|q| q.idx < run.start)
            .checked_sub(1)?;
        let e = points.partition_point(|q| q.idx <= run.end);
        let wide = (seg.point(e) - seg.point(s)).norm() > NARROW;
        if !(s >= a && e <= b && wide) {
            return None;
        }
        let before = sums(pre, (s + 1).saturating_sub(SIDE).max(a), s + 1);
        let sides = before.join(&sums(pre, e, (e + SIDE).min(b + 1)));
        if sides.len() < SIDE || !one_line_fits(&sides, p, noise) {
            return None;
        }
        let wall = Beyond::new(&sides.normal_fit()?, noise, p.noise_along_beams);
        let run_returns = inside.iter().skip_while(|q| q.idx < run.start);
        run_returns
            .take_while(|q| q.idx <= run.end)
            .all(|q| wall.depth(q).is_some())
            .then_some((s, e))
    };
    let mut run: Option<Run> = None;
    let ends = inside.iter().take_while(|q| q.idx < last).map(Some);
    for q in ends.chain(std::iter::once(None)) {
        if let Some(q) = q
            && let Some((z, depth)) = beyond.depth(q)
        {
            match &mut run {
                Some(run) => run.add(q.idx, z, depth),
                None => run = Some(Run::new(q.idx, z, depth)),
            }
            continue;
        }
        if let Some(run) = run.take()
            && run.strong >= 2
            && run.metres > SHALLOW
            && let Some(o) = opening(&run)
        {
            return Some(o);
        }
    }
    None
}

/// Consecutive returns beyond a line by [`RUN_SIGMAS`].
struct Run {
    /// The beams of the first and the last.
    start: usize,
    end: usize,
    /// How many lie beyond by [`THROUGH_SIGMAS`].
    strong: usize,
    /// The farthest beyond, m.
    metres: f64,
}

impl Run {
    /// A run of the return of beam `idx`, `z` sigma and `depth` m beyond.
    fn new(idx: usize, z: f64, depth: f64) -> Self {
        Self {
            start: idx,
            end: idx,
            strong: usize::from(z > THROUGH_SIGMAS),
            metres: depth,
        }
    }

    /// The run goes on with the return of beam `idx`, `z` sigma and `depth` m beyond.
    fn add(&mut self, idx: usize, z: f64, depth: f64) {
        self.end = idx;
        self.strong += usize::from(z > THROUGH_SIGMAS);
        self.metres = self.metres.max(depth);
    }
}

/// The test of a return beyond a line by [`RUN_SIGMAS`].
struct Beyond {
    normal: (f64, f64),
    r: f64,
    noise: RangeNoise,
    along: bool,
}

impl Beyond {
    fn new(fit: &NormalFit, noise: &RangeNoise, along: bool) -> Self {
        Self {
            normal: (fit.normal.x, fit.normal.y),
            r: fit.r,
            noise: *noise,
            along,
        }
    }

    /// How far beyond the line `q` lies, in sigma of the noise across it and in metres, when
    /// by more than [`RUN_SIGMAS`]. The noise across the line is `sigma(range)
    /// cos(incidence)`, the cosine `dot / range` (at most 1) floored at `MIN_INCIDENCE_COS`
    /// ([`super::linseg::incidence_cos`]), or 1 without `noise_along_beams`: the test is
    /// `depth range > k sigma max(dot, floor range)`, free of divisions.
    #[inline]
    fn depth(&self, q: &Pt) -> Option<(f64, f64)> {
        let dot = q.x * self.normal.0 + q.y * self.normal.1;
        let depth = dot - self.r;
        let sigma = self.noise.sigma(q.range);
        let across = if self.along {
            dot.max(MIN_INCIDENCE_COS * q.range)
        } else {
            q.range
        };
        // A NaN fails.
        (depth * q.range > RUN_SIGMAS * sigma * across)
            .then(|| (depth * q.range / (sigma * across), depth))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A return of beam `idx` at `(x, y)`.
    fn pt(idx: usize, x: f64, y: f64) -> Pt {
        Pt {
            x,
            y,
            range: x.hypot(y),
            idx,
        }
    }

    /// The wall `y = 2` (normal `+y`, `r = 2`).
    fn wall() -> NormalFit {
        NormalFit {
            normal: crate::math::Vector2::new(0.0, 1.0),
            r: 2.0,
            n: 20,
            s2: 0.0,
            covariance: crate::math::Matrix2::zeros(),
        }
    }

    /// The points and returns of the wall `y = 2` seen from the origin on beams 0.5 deg apart
    /// from 30 deg on (60 beams, 2 cm of alternating noise), where the beams `off` meet
    /// `y = 2 + depth` instead, and those of `removed` are returns the piece does not hold.
    /// Returns the piece's points and the returns.
    fn wall_with(off: std::ops::Range<usize>, depth: f64, removed: &[usize]) -> (Vec<Pt>, Vec<Pt>) {
        let returns: Vec<Pt> = (0..60)
            .map(|i| {
                let phi = (30.0 + 0.5 * i as f64).to_radians();
                let y = if off.contains(&i) { 2.0 + depth } else { 2.0 };
                let r = y / phi.sin() + if i % 2 == 0 { 0.02 } else { -0.02 };
                pt(i, r * phi.cos(), r * phi.sin())
            })
            .collect();
        let points = returns
            .iter()
            .filter(|q| !removed.contains(&q.idx))
            .copied()
            .collect();
        (points, returns)
    }

    /// The opening [`seen_through`] finds in the whole piece, as beams.
    fn opening_of((points, returns): &(Vec<Pt>, Vec<Pt>)) -> Option<(usize, usize)> {
        let seg = Seg(points);
        let mut pre = Vec::new();
        super::super::linseg::prefix_sums(seg, &mut pre);
        let p = HoughSplitParams::default();
        let noise = RangeNoise::new(0.02, 0.0);
        seen_through((seg, &pre), returns, (0, points.len() - 1), &p, &noise)
            .map(|(s, e)| (seg.idx(s), seg.idx(e)))
    }

    #[test]
    fn a_recess_in_a_wall_ends_its_line_and_a_step_a_groove_or_a_lone_return_do_not() {
        // A doorway 0.3 m deep seen by beams 20 to 26 (0.31 m of wall between the beams
        // around it): the piece ends at beam 19 and goes on from 27, whether the piece holds
        // those returns or not.
        let door = 20..27;
        assert_eq!(
            opening_of(&wall_with(door.clone(), 0.3, &[])),
            Some((19, 27))
        );
        let removed: Vec<usize> = door.clone().collect();
        assert_eq!(
            opening_of(&wall_with(door.clone(), 0.3, &removed)),
            Some((19, 27))
        );
        assert_eq!(
            opening_of(&wall_with(door.clone(), 0.3, &[21, 22])),
            Some((19, 27))
        );
        // One return beyond is no run; a groove 4 cm deep is no opening, whatever the noise.
        assert_eq!(opening_of(&wall_with(20..21, 0.3, &[])), None);
        assert_eq!(opening_of(&wall_with(door.clone(), 0.04, &[])), None);
        // A step: the wall goes on 0.3 m farther from beam 20 to the end, no wall after it.
        assert_eq!(opening_of(&wall_with(20..60, 0.3, &[])), None);
        // A surface in front of the wall is no view through it.
        assert_eq!(opening_of(&wall_with(door, -0.3, &[])), None);
        // Beams 50 and 51, at 55 deg, meet the wall 3 cm apart: the points around them lie
        // 8 cm apart, narrower than an opening.
        assert_eq!(opening_of(&wall_with(50..52, 0.3, &[])), None);
    }

    #[test]
    fn a_doorway_is_a_short_view_beyond_and_a_box_in_front_none() {
        let noise = RangeNoise::new(0.01, 0.01);
        // The pieces end at x = -5 and x = 5 of the wall.
        let ends = (Point2::new(-5.0, 2.0), Point2::new(5.0, 2.0));
        let view = |pts: &[Pt], between| seen_beyond(pts, between, ends, &wall(), &noise);
        // Beams 11..=19 see 1 m beyond the wall at x from -0.8 to 0.8: a doorway.
        let door: Vec<Pt> = (11..20)
            .map(|i| pt(i, 0.2 * (i as f64 - 15.0) * 1.5, 3.0))
            .collect();
        assert!((view(&door, (10, 20)) - 1.6).abs() < 1e-9);
        // The same beyond x from -2.4 to 2.4.
        let open: Vec<Pt> = (11..20)
            .map(|i| pt(i, 0.6 * (i as f64 - 15.0) * 1.5, 3.0))
            .collect();
        assert!((view(&open, (10, 20)) - 4.8).abs() < 1e-9);
        // Returns in front of the wall (a box), or on it within the noise: nothing beyond.
        let front: Vec<Pt> = (11..20)
            .map(|i| pt(i, 0.6 * (i as f64 - 15.0) * 0.6, 1.2))
            .collect();
        assert_eq!(view(&front, (10, 20)), 0.0);
        let on: Vec<Pt> = (11..20)
            .map(|i| pt(i, 0.6 * (i as f64 - 15.0) * 1.5, 2.02))
            .collect();
        assert_eq!(view(&on, (10, 20)), 0.0);
        // Only the beams strictly between the pieces count, and only where they meet the
        // line between the pieces' ends.
        assert_eq!(view(&open, (14, 16)), 0.0);
        assert_eq!(view(&open, (19, 20)), 0.0);
        // Pieces ending at x = -1 and 1: the beams meeting the wall at -0.6, 0 and 0.6.
        let near = (Point2::new(-1.0, 2.0), Point2::new(1.0, 2.0));
        let beyond = seen_beyond(&open, (10, 20), near, &wall(), &noise);
        assert!((beyond - 1.2).abs() < 1e-9, "{beyond}");
    }
}
