//! Where neighbouring lines of one data segment end: at their corner, as in the paper, when
//! the two lines meet there and the scan does not say the corner is not there.

use super::lines::Candidate;
use super::opening::{SHALLOW, THROUGH_SIGMAS};
use super::params::HoughSplitParams;
use super::points::Pt;
use super::segment::Breakpoints;
use crate::line::Line;
use crate::math::{Point2, Vector2};
use crate::noise::RangeNoise;

/// What the scan saw, for where lines end.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Seen<'a> {
    /// The scan's valid points (step 0), in beam order: the beams that returned.
    pub(crate) returns: &'a [Pt],
    /// The geometric part of the breakpoint distance `D` of neighbouring beams per metre of
    /// range ([`Breakpoints::one_beam`](super::segment::Breakpoints::one_beam)).
    pub(crate) step: f64,
}

impl<'a> Seen<'a> {
    /// The scan's `returns` with the breakpoint distance of `bp`.
    pub(crate) fn new(returns: &'a [Pt], bp: &Breakpoints) -> Self {
        Self {
            returns,
            step: bp.one_beam(),
        }
    }
}

/// Neighbouring lines of one segment that meet at a corner share their end point, as in the
/// paper: the intersection of the two fitted lines, when it lies near both ends (within
/// `split_sigmas * sigma(r)` plus the gap between them, which within one data segment is at
/// most the breakpoint distance), the lines are not nearly parallel, and neither line gives
/// up more than `split_sigmas * sigma(r)` of its points' extent or falls below
/// `min_line_length` for it. Where a piece between
/// them gave no line (too short, too rough or too uncertain for the filters of
/// `Pieces::line`), the lines around it are neighbours and the gap is that piece's length:
/// they meet at their intersection when it lies within it, as at a corner whose short leg gave
/// no line.
pub(crate) fn join_corners(
    lines: &mut [Line],
    candidates: &[Candidate],
    p: &HoughSplitParams,
    noise: &RangeNoise,
    seen: Seen<'_>,
) {
    // Uncertain lines may yet be dropped: the certain lines around them are neighbours.
    let mut before: Option<usize> = None;
    for k in 0..lines.len().min(candidates.len()) {
        if !candidates[k].certain {
            continue;
        }
        let Some(j) = before.replace(k) else { continue };
        if let Some(corner) = meeting_point(&lines[j], &lines[k], p, noise, seen) {
            lines[j].end = corner;
            lines[k].start = corner;
        }
    }
}

/// Where `a` and the next line `b` meet at a corner ([`join_corners`]): their lines'
/// intersection, when they are not nearly parallel, it lies within `split_sigmas * sigma(r)`
/// plus the gap between them of both ends, neither line gives up more than that of its
/// extent or falls below `min_line_length` for it, and no beam between them saw through
/// the stretch either line would gain ([`seen_through`]).
pub(crate) fn meeting_point(
    a: &Line,
    b: &Line,
    p: &HoughSplitParams,
    noise: &RangeNoise,
    seen: Seen<'_>,
) -> Option<Point2> {
    let corner = corner_of(a, b)?;
    let thr = p.split_sigmas * noise.sigma(corner.coords.norm());
    let reach = (b.start - a.end).norm() + thr;
    let near = (corner - a.end).norm() <= reach && (corner - b.start).norm() <= reach;
    let keeps =
        |far: Point2, near: Point2| keeps_its_points(far, near, corner, thr, p.min_line_length);
    let meets = near && keeps(a.start, a.end) && keeps(b.end, b.start);
    (meets && !seen_through(a, b, corner, p, noise, seen)).then_some(corner)
}

/// True when a return of a beam from the first of `a` to the last of `b` (those of the lines
/// too: past a wall's end, the wall behind may take the beams the line would gain) lies
/// beyond the stretch from `a`'s end to `corner` or from `corner` to `b`'s start by more than
/// the breakpoint distance `D` of neighbouring beams there (with the line's own uncertainty
/// where the beam meets it added to the range noise): the beam saw through where the line
/// would pass, as beams past the end of a wall see the wall behind it. Drawn to the corner,
/// such a line would cross that empty space. With `cut_excursions`, two or more consecutive
/// returns beyond it by [`THROUGH_SIGMAS`] standard deviations of that difference, one of
/// them by [`SHALLOW`] across it, see through it as well (an opening seen at a glancing
/// angle, where `D` spans it; see [`super::opening::seen_through`]). A surface that bends a
/// little before its corner stays well within `D`. Only a line that gains more than `D` (at
/// the corner's range) is looked at.
fn seen_through(
    a: &Line,
    b: &Line,
    corner: Point2,
    p: &HoughSplitParams,
    noise: &RangeNoise,
    seen: Seen<'_>,
) -> bool {
    let spread = p.bridge_sigmas * std::f64::consts::SQRT_2;
    // A line that gains less than `D` at the corner spans no gap `D` would see: the usual
    // corner, whose lines end within the noise of it, is not searched.
    let range = corner.coords.norm();
    let reach = range * seen.step + spread * noise.sigma(range);
    let stretches = [(a, a.end, corner), (b, corner, b.start)];
    let gains = stretches.map(|(_, p0, p1)| (p1 - p0).norm() > reach);
    if gains == [false, false] {
        return false;
    }
    let from = seen.returns.partition_point(|q| q.idx < a.first);
    // Consecutive returns that lie beyond a stretch by `THROUGH_SIGMAS`, and whether one of
    // them lies beyond it by `SHALLOW`.
    let (mut run, mut deep) = (0, false);
    seen.returns[from..]
        .iter()
        .take_while(|q| q.idx <= b.last)
        .any(|q| {
            let (mut far, mut through, mut deep_here) = (false, false, false);
            for (&(l, p0, p1), gains) in stretches.iter().zip(gains) {
                if let Some((along, sd, facing)) =
                    gains.then(|| beyond(l, (p0, p1), q, noise)).flatten()
                {
                    let excess = q.range - along;
                    far |= excess > along * seen.step + spread * sd;
                    if p.cut_excursions && excess > THROUGH_SIGMAS * sd {
                        through = true;
                        deep_here |= excess * facing > SHALLOW;
                    }
                }
            }
            (run, deep) = if through {
                (run + 1, deep || deep_here)
            } else {
                (0, false)
            };
            far || (run >= 2 && deep)
        })
}

/// When the beam of `q` crosses the stretch `p0..p1` of the line of `l`: the range at which
/// it meets the line, the standard deviation of the difference of `q`'s range from it (the
/// range noise and the line's own uncertainty at the crossing, from its covariance, seen
/// along the beam: a line met at a grazing angle is known there the less) and the cosine of
/// the beam's incidence on the line. `q` lies beyond the line by more than `D` of
/// neighbouring beams when `q.range - along > step along + spread sd`.
fn beyond(
    l: &Line,
    (p0, p1): (Point2, Point2),
    q: &Pt,
    noise: &RangeNoise,
) -> Option<(f64, f64, f64)> {
    let u = Vector2::new(q.x, q.y) / q.range;
    let cross = |v: Point2| v.x * u.y - v.y * u.x;
    // The beam passes between the stretch's ends (their cross products differ in sign) on
    // the side of the sensor the stretch lies on.
    let crosses = cross(p0) * cross(p1) <= 0.0 && (p0.coords + p1.coords).dot(&u) > 0.0;
    let (sin, cos) = l.alpha.sin_cos();
    let facing = u.x * cos + u.y * sin;
    if !crosses || facing <= 0.0 {
        return None;
    }
    let along = l.r / facing;
    // The crossing's coordinate along the line; its offset across the line varies by
    // `dr - t dalpha`.
    let t = along * (u.y * cos - u.x * sin);
    let c = &l.covariance;
    let across = (c[(0, 0)] - 2.0 * t * c[(0, 1)] + t * t * c[(1, 1)]).max(0.0);
    let sigma = noise.sigma(along);
    let sd = (sigma * sigma + across / (facing * facing)).sqrt();
    Some((along, sd, facing))
}

/// The intersection of the infinite lines of `a` and `b`, or `None` when they lie closer
/// than 15 deg to parallel (no well-defined corner).
fn corner_of(a: &Line, b: &Line) -> Option<Point2> {
    let (sa, ca) = a.alpha.sin_cos();
    let (sb, cb) = b.alpha.sin_cos();
    let det = ca * sb - sa * cb;
    if det.abs() < 15f64.to_radians().sin() {
        return None;
    }
    let x = (a.r * sb - b.r * sa) / det;
    let y = (ca * b.r - cb * a.r) / det;
    Some(Point2::new(x, y))
}

/// Whether a line from `far` to `near` may end at `corner` instead of `near`: the corner lies
/// on the same side of `far` as `near`, the line stays `min_length` long, and it gives up at
/// most `thr` of its own points' extent (a corner beyond the line's other end, or far inside
/// it, belongs to lines that do not meet there).
fn keeps_its_points(far: Point2, near: Point2, corner: Point2, thr: f64, min_length: f64) -> bool {
    let length = (near - far).norm();
    if length <= 0.0 {
        return false;
    }
    let along = (corner - far).dot(&(near - far)) / length;
    along > 0.0 && along >= length - thr && along >= min_length
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Matrix2;

    /// A line from `start` (beam `first`) to `end` (beam `last`).
    fn line(start: Point2, end: Point2, (first, last): (usize, usize)) -> Line {
        let d = (end - start).normalize();
        let normal = Vector2::new(d.y, -d.x);
        let (normal, r) = if normal.dot(&start.coords) < 0.0 {
            (-normal, -normal.dot(&start.coords))
        } else {
            (normal, normal.dot(&start.coords))
        };
        Line {
            start,
            end,
            r,
            alpha: normal.y.atan2(normal.x),
            first,
            last,
            points: last - first + 1,
            rms: 0.005,
            covariance: Matrix2::identity() * 1e-6,
        }
    }

    /// Returns on beams `11..20` along the stretch from `(0.5, 1.5)` through the corner
    /// `(0.5, 2)` to `(-0.2, 2)`, at `scale` times the range of the stretch.
    fn returns(scale: f64) -> Vec<Pt> {
        (11..20)
            .map(|idx| {
                let t = (idx - 10) as f64 / 10.0;
                let q = if t < 0.4 {
                    Point2::new(0.5, 1.5 + 0.5 * t / 0.4)
                } else {
                    Point2::new(0.5 - 0.7 * (t - 0.4) / 0.6, 2.0)
                };
                let (x, y) = (q.x * scale, q.y * scale);
                Pt {
                    x,
                    y,
                    range: x.hypot(y),
                    idx,
                }
            })
            .collect()
    }

    /// The returns as a URG-04LX's scan sees them (`D` of neighbouring beams 0.096 m per
    /// metre of range).
    fn seen(returns: &[Pt]) -> Seen<'_> {
        Seen {
            returns,
            step: 0.096,
        }
    }

    /// The two walls of a room's corner at (0.5, 2), seen from inside: one along x = 0.5 up
    /// to y = 1.5, one along y = 2 from x = -0.2 on, and beams 11-19 between them.
    fn room_corner() -> (Line, Line) {
        (
            line(Point2::new(0.5, 0.5), Point2::new(0.5, 1.5), (0, 10)),
            line(Point2::new(-0.2, 2.0), Point2::new(-1.0, 2.0), (20, 40)),
        )
    }

    #[test]
    fn lines_meet_at_their_corner_unless_beams_saw_through_it() {
        let (p, noise) = (HoughSplitParams::default(), RangeNoise::new(0.01, 0.01));
        let (a, b) = room_corner();
        let corner = meeting_point(&a, &b, &p, &noise, seen(&returns(1.0))).unwrap();
        assert!((corner - Point2::new(0.5, 2.0)).norm() < 1e-9);
        // Without returns between them (missing beams) the corner stands too.
        assert!(meeting_point(&a, &b, &p, &noise, seen(&[])).is_some());
        // The beams between them saw a surface 30 % farther (0.6 m at 2 m, where `D` is
        // 0.28 m): no wall is at the corner.
        assert!(meeting_point(&a, &b, &p, &noise, seen(&returns(1.3))).is_none());
        // A surface 5 % farther (a wall that bends before its corner) lies within `D`.
        assert!(meeting_point(&a, &b, &p, &noise, seen(&returns(1.05))).is_some());
        // A far return whose beam meets neither stretch (a stray reading on a beam of the
        // first line itself, three times its range) says nothing about the corner.
        let stray = Pt {
            x: 1.5,
            y: 3.0,
            range: 1.5f64.hypot(3.0),
            idx: 5,
        };
        assert!(meeting_point(&a, &b, &p, &noise, seen(&[stray])).is_some());
    }

    #[test]
    fn a_line_known_loosely_is_judged_by_its_own_uncertainty_along_the_beam() {
        let (p, noise) = (HoughSplitParams::default(), RangeNoise::new(0.01, 0.01));
        let (a, b) = room_corner();
        // Returns 30 % beyond the first line's stretch alone (0.5 m beyond at 1.7 m, met at
        // 73 deg of incidence).
        let beyond_a: Vec<Pt> = returns(1.3).into_iter().filter(|q| q.idx < 14).collect();
        assert!(meeting_point(&a, &b, &p, &noise, seen(&beyond_a)).is_none());
        // A line whose direction is known to 0.1 rad is known along that beam to 0.55 m
        // there: the returns no longer say it ends short of the corner.
        let mut loose = a;
        loose.covariance[(1, 1)] = 0.01;
        assert!(meeting_point(&loose, &b, &p, &noise, seen(&beyond_a)).is_some());
    }
}
