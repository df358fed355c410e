//! Step 7: lines of one surface across data segments share one fit. A wall seen on both
//! sides of a leg, a box or a missing stretch gives a line on each side; when their joint
//! line explains both sets of points as well as two lines do (a chi-square test on the rise
//! of their residuals, in variances of the noise across the joint line), each keeps its own
//! points and extent but takes the joint fit's `r`, `alpha` and covariance, which the points
//! of both pin down better than either set alone.

use std::cmp::Ordering;

use super::corners::{Seen, meeting_point};
use super::lines::{Candidate, certain, floored_covariance};
use super::linseg::{incidence_cos, variance_at};
use super::params::HoughSplitParams;
use crate::fit::FitSums;
use crate::line::Line;
use crate::math::{Point2, Vector2};
use crate::noise::RangeNoise;

/// The rise of the sum of squared residuals from two lines to one, in variances of the noise
/// across the line, beyond which two lines are two surfaces: the chi-square quantile of 2
/// degrees of freedom at the 1e-3 level. Unlike the split's `split_significance`, no search
/// over split points lies behind it.
const SHARE_CHI2: f64 = 13.82;

/// The quantile when neither the group nor the joining line has a line [`certain`] on its
/// own fit: the chi-square quantile of 2 degrees of freedom at the 1e-2 level. Two uncertain
/// pieces (short, far, noisy) pass the test for almost any line through both centroids, and
/// the joint fit then claims the certainty of their lever arm: pieces of two walls metres
/// apart, even perpendicular ones, took one fit 25 and 65 deg off both at 2 % noise. The
/// stricter level keeps such pairs apart more often, and nearly all pieces of one wall
/// together (the field suites' TP rate moves by 0.001).
const SHARE_CHI2_UNANCHORED: f64 = 9.21;

/// Most groups a line tries to join (those of the nearest lines before it): bounds the
/// work on a scan of many lines to a few tests per line; a wall's pieces lie within a few
/// lines of each other in beam order.
const MAX_TRIED: usize = 8;

/// Working memory of [`share_fits`].
#[derive(Debug, Default, Clone)]
pub(crate) struct Groups {
    /// Per line: its group.
    group: Vec<u32>,
    /// Per group: the sums of its lines' points, and its number of lines.
    sums: Vec<(FitSums, u32)>,
    /// Per group: the last line that tried to join it.
    tried: Vec<u32>,
    /// Per pair of neighbouring lines: whether they share a corner.
    corners: Vec<bool>,
    /// Per line: whether it took its group's fit.
    moved: Vec<bool>,
    /// Per group: whether one of its lines is certain on its own fit.
    anchored: Vec<bool>,
}

/// Groups `lines` (in beam order, `candidates[i]` the sums of the points of `lines[i]` and
/// whether it is certain) whose joint line is one line within the noise, and gives the lines
/// of each group of two or more the group's fit: `r`, `alpha`, the covariance (floored as
/// each line's own), the end points projected onto it and the RMS of each line's own points
/// about it. Then drops the lines that are not [`certain`] with their final covariance:
/// `lines` is truncated to the lines kept, in order.
pub(crate) fn share_fits(
    lines: &mut Vec<Line>,
    candidates: &[Candidate],
    p: &HoughSplitParams,
    noise: &RangeNoise,
    seen: Seen<'_>,
    groups: &mut Groups,
) {
    let mut n = lines.len().min(candidates.len());
    if p.share_fits && p.split_significance > 0.0 {
        group_lines(&candidates[..n], noise, p.noise_along_beams, groups);
        // Which neighbours share a corner (the end of one the start of the next).
        let Groups {
            group,
            sums: joint,
            corners,
            moved,
            ..
        } = groups;
        corners.clear();
        corners.extend((1..n).map(|k| lines[k - 1].end == lines[k].start));
        moved.clear();
        for j in 0..n {
            let (s, count) = joint[group[j] as usize];
            moved.push(count >= 2 && take_fit(&mut lines[j], &candidates[j], &s, p, noise));
        }
        if moved.contains(&true) {
            rejoin_corners(&mut lines[..n], &candidates[..n], groups, (p, noise), seen);
            n = join_followers(&mut lines[..n], &candidates[..n], groups);
        }
    }
    let mut kept = 0;
    for j in 0..n {
        if certain(&lines[j].covariance, p) {
            lines[kept] = lines[j];
            kept += 1;
        }
    }
    lines.truncate(kept);
}

/// Neighbouring lines that shared a corner, either of which took a shared fit, meet again
/// where their lines now meet when they still do by the test of the corners
/// ([`meeting_point`]); else each ends at its own end point projected onto its line.
fn rejoin_corners(
    lines: &mut [Line],
    candidates: &[Candidate],
    groups: &Groups,
    (p, noise): (&HoughSplitParams, &RangeNoise),
    seen: Seen<'_>,
) {
    let Groups { corners, moved, .. } = groups;
    let n = lines.len().min(moved.len()).min(corners.len() + 1);
    for k in 1..n {
        if !corners[k - 1] || !(moved[k - 1] || moved[k]) {
            continue;
        }
        let (a, b) = (lines[k - 1], lines[k]);
        lines[k - 1].end = project(&a, candidates[k - 1].ends.1);
        lines[k].start = project(&b, candidates[k].ends.0);
        if let Some(corner) = meeting_point(&lines[k - 1], &lines[k], p, noise, seen) {
            lines[k - 1].end = corner;
            lines[k].start = corner;
        }
    }
}

/// Neighbouring lines of one data segment whose points follow each other
/// ([`Candidate::follows`]: none between, or a lone spike) and which both took their group's
/// fit are one line: the split between them parted points that one line explains, which the
/// merge of neighbouring pieces (by the split's test, on the pieces before their ends were
/// refined) did not see, as heavy-tailed noise leaves it. The first takes the second's end,
/// last beam and points, and the RMS of both sets of points. Compacts `lines` and returns
/// how many remain.
fn join_followers(lines: &mut [Line], candidates: &[Candidate], groups: &Groups) -> usize {
    let Groups { group, moved, .. } = groups;
    let n = lines.len().min(candidates.len()).min(moved.len());
    if n == 0 {
        return 0;
    }
    let mut w = 0;
    for k in 1..n {
        // `lines[w]` holds line `k - 1`, alone or with those it took in.
        if candidates[k].follows && moved[k - 1] && moved[k] && group[k - 1] == group[k] {
            let next = lines[k];
            take_in(&mut lines[w], &next);
        } else {
            w += 1;
            lines[w] = lines[k];
        }
    }
    w + 1
}

/// `line` takes in `next`, the piece of its surface after it: `next`'s end, last beam and
/// points, and the RMS of both sets of points.
pub(crate) fn take_in(line: &mut Line, next: &Line) {
    let (na, nb) = (line.points as f64, next.points as f64);
    line.rms = ((line.rms * line.rms * na + next.rms * next.rms * nb) / (na + nb)).sqrt();
    line.end = next.end;
    line.last = next.last;
    line.points += next.points;
}

/// `q` projected onto the line of `l`.
fn project(l: &Line, q: Point2) -> Point2 {
    let normal = Vector2::new(l.alpha.cos(), l.alpha.sin());
    q - normal * (q.coords.dot(&normal) - l.r)
}

/// Gives `line` (of the candidate `own`) the fit of the points summed in `joint`, its ends
/// its first and last points projected onto it, unless its own points' RMS about that line
/// would exceed `max_rms_sigmas` of the noise at their centroid or the segment projected
/// onto it would fall below `min_line_length` (the limits every line keeps). Returns
/// whether it took the fit.
fn take_fit(
    line: &mut Line,
    own: &Candidate,
    joint: &FitSums,
    p: &HoughSplitParams,
    noise: &RangeNoise,
) -> bool {
    let Some(fit) = joint.fit() else {
        return false;
    };
    let normal = fit.normal();
    let sums = &own.sums;
    let rms = (sums.sse_about(normal, fit.r) / sums.len().max(1) as f64).sqrt();
    let range = sums.centroid_norm_squared().sqrt();
    // NaN fails.
    let rough = rms.partial_cmp(&(p.max_rms_sigmas * noise.sigma(range)));
    if !matches!(rough, Some(Ordering::Less | Ordering::Equal)) {
        return false;
    }
    let (start, end) = (fit.project(own.ends.0), fit.project(own.ends.1));
    // Projected onto a line of another direction, the segment shortens: it stays a surface
    // and keeps its direction, or keeps its own fit.
    let long = (end - start).norm() >= p.min_line_length;
    if !(long && (end - start).dot(&(line.end - line.start)) > 0.0) {
        return false;
    }
    line.start = start;
    line.end = end;
    line.r = fit.r;
    line.alpha = fit.alpha;
    line.covariance = floored_covariance(&fit, noise, p.own_scatter);
    line.rms = rms;
    true
}

/// Fills `groups`: each line joins the group of the nearest line before it (of the
/// `MAX_TRIED` nearest groups) whose group's points and its own one line explains, else
/// starts its own. One line explains them by [`SHARE_CHI2`] when the group or the line has a
/// line certain on its own, else by [`SHARE_CHI2_UNANCHORED`].
fn group_lines(candidates: &[Candidate], noise: &RangeNoise, along: bool, groups: &mut Groups) {
    let Groups {
        group,
        sums: joint,
        tried,
        anchored,
        ..
    } = groups;
    group.clear();
    joint.clear();
    tried.clear();
    anchored.clear();
    for (j, c) in candidates.iter().enumerate() {
        let own = &c.sums;
        let mut found = None;
        // The groups of the lines before it, the nearest first, each tried once, at most
        // `MAX_TRIED` of them.
        let mut left = MAX_TRIED;
        for back in (0..j).rev() {
            let g = group[back] as usize;
            if tried[g] == j as u32 {
                continue;
            }
            if left == 0 {
                break;
            }
            left -= 1;
            tried[g] = j as u32;
            let limit = if anchored[g] || c.certain {
                SHARE_CHI2
            } else {
                SHARE_CHI2_UNANCHORED
            };
            if one_line(&joint[g].0, own, noise, along, limit) {
                found = Some(g);
                break;
            }
        }
        match found {
            Some(g) => {
                joint[g].0 = joint[g].0.join(own);
                joint[g].1 += 1;
                anchored[g] |= c.certain;
                group.push(g as u32);
            }
            None => {
                group.push(joint.len() as u32);
                joint.push((*own, 1));
                tried.push(u32::MAX);
                anchored.push(c.certain);
            }
        }
    }
}

/// True when one line explains the points of `a` and of `b` as well as two lines do.
///
/// With `along` (the `noise_along_beams` parameter): the rise of each set's sum of squared
/// residuals about the joint line, in variances of the noise across that line, adds up to
/// less than the chi-square quantile. Range noise lies along the beams, so across a line it
/// is `sigma(r) cos(incidence)` ([`incidence_cos`]): a set seen at a glancing angle of the
/// joint line must lie on it that much more closely (two objects far apart are otherwise
/// explained by a line that passes near the sensor and meets both at a grazing angle). A set
/// whose own line leaves larger residuals is judged by those (noise larger than the model
/// never keeps two lines apart). The joint line is the unweighted fit, so where the two sets'
/// variances differ (below the range where `sigma_min` gives way to `fraction * r`) the sum
/// only approximates a chi-square and errs towards two lines.
///
/// Without `along`, or when the joint points fit no line: the joint line's sum of squared
/// residuals exceeds the two lines' by less than the quantile times `sigma(r)^2` at the
/// joint centroid, or times the two lines' residual variance when larger.
fn one_line(a: &FitSums, b: &FitSums, noise: &RangeNoise, along: bool, limit: f64) -> bool {
    let whole = a.join(b);
    if let Some(joint) = along.then(|| whole.normal_fit()).flatten() {
        let mut chi2 = 0.0;
        for s in [a, b] {
            let Some(c) = s.centroid() else { continue };
            let sse = s.sse();
            let rise = s.sse_about(joint.normal, joint.r) - sse;
            let cos = incidence_cos(c, joint.normal, true);
            let own = if s.len() > 2 {
                sse / (s.len() - 2) as f64
            } else {
                0.0
            };
            chi2 += rise / (variance_at(s, noise) * cos * cos).max(own);
        }
        // A NaN (absurd sums) shares nothing.
        return chi2 <= limit;
    }
    let two = a.sse() + b.sse();
    let dof = whole.len().saturating_sub(4);
    let residual = if dof > 0 { two / dof as f64 } else { 0.0 };
    whole.sse() - two <= limit * variance_at(&whole, noise).max(residual)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A line on the points `(x, y0 + dy(i))` for `xs`, with its candidate.
    fn piece(
        xs: std::ops::Range<i32>,
        step: f64,
        y0: f64,
        noise: &RangeNoise,
    ) -> (Line, Candidate) {
        let pts: Vec<Point2> = xs
            .clone()
            .map(|i| {
                let dy = if i % 2 == 0 { 0.004 } else { -0.004 };
                Point2::new(f64::from(i) * step, y0 + dy)
            })
            .collect();
        piece_of(&pts, noise)
    }

    fn share(pieces: &[(Line, Candidate)], noise: &RangeNoise) -> Vec<Line> {
        let mut lines: Vec<Line> = pieces.iter().map(|p| p.0).collect();
        let candidates: Vec<Candidate> = pieces.iter().map(|p| p.1).collect();
        let p = HoughSplitParams::default();
        share_fits(
            &mut lines,
            &candidates,
            &p,
            noise,
            Seen::default(),
            &mut Groups::default(),
        );
        lines
    }

    #[test]
    fn two_pieces_of_a_wall_share_their_joint_fit() {
        let noise = RangeNoise::new(0.005, 0.0);
        // A wall at y = 2 seen on both sides of a leg: x = -1.0..-0.2 and 0.3..1.1.
        let pieces = [
            piece(-50..-10, 0.02, 2.0, &noise),
            piece(15..55, 0.02, 2.0, &noise),
        ];
        let lines = share(&pieces, &noise);
        assert_eq!(lines.len(), 2);
        assert_eq!((lines[0].r, lines[0].alpha), (lines[1].r, lines[1].alpha));
        assert!((lines[0].r - 2.0).abs() < 1e-3);
        // Each keeps its own beams and points; the joint fit knows the direction better.
        assert_eq!(lines[1].points, 40);
        for (shared, own) in lines.iter().zip(&pieces) {
            assert!(shared.covariance[(1, 1)] < 0.5 * own.0.covariance[(1, 1)]);
            assert!((shared.start.x - own.0.start.x).abs() < 1e-3);
        }
    }

    #[test]
    fn pieces_that_follow_each_other_with_one_fit_are_one_line() {
        let noise = RangeNoise::new(0.005, 0.0);
        // A wall at y = 2 split at x = -0.2 with nothing between the pieces.
        let mut pieces = [
            piece(-50..-10, 0.02, 2.0, &noise),
            piece(-10..30, 0.02, 2.0, &noise),
        ];
        assert_eq!(share(&pieces, &noise).len(), 2);
        pieces[1].1.follows = true;
        let lines = share(&pieces, &noise);
        assert_eq!(lines.len(), 1);
        assert_eq!(lines[0].points, 80);
        assert!((lines[0].start.x + 1.0).abs() < 1e-3 && (lines[0].end.x - 0.58).abs() < 1e-3);
        assert!((lines[0].rms - 0.004).abs() < 1e-4);
        // Its beams run from the first piece's first to the second's last; its RMS is that
        // of all the points (the second piece twice as rough: sqrt((16 + 64) / 2) mm).
        let rough: Vec<Point2> = (-10..30)
            .map(|i| {
                let dy = if i % 2 == 0 { 0.008 } else { -0.008 };
                Point2::new(f64::from(i) * 0.02, 2.0 + dy)
            })
            .collect();
        pieces[1] = piece_of(&rough, &noise);
        pieces[1].1.follows = true;
        pieces[0].0.first = 100;
        pieces[0].0.last = 139;
        pieces[1].0.first = 140;
        pieces[1].0.last = 179;
        let lines = share(&pieces, &noise);
        assert_eq!(lines.len(), 1);
        assert_eq!((lines[0].first, lines[0].last), (100, 179));
        let pooled = 40f64.sqrt() * 1e-3;
        assert!((lines[0].rms - pooled).abs() < 1e-4, "{}", lines[0].rms);
        // Pieces of two surfaces never take one fit, and stay two lines.
        let mut apart = [
            piece(-50..-10, 0.02, 2.0, &noise),
            piece(-10..30, 0.02, 1.95, &noise),
        ];
        apart[1].1.follows = true;
        assert_eq!(share(&apart, &noise).len(), 2);
        // Two walls seen in turns, each piece in the group of its own wall: neighbours of two
        // groups never join, whatever their points.
        let mut turns = [
            piece(-60..-40, 0.02, 2.0, &noise),
            piece(-40..-20, 0.02, 2.5, &noise),
            piece(-20..0, 0.02, 2.0, &noise),
            piece(0..20, 0.02, 2.5, &noise),
        ];
        for t in &mut turns[1..] {
            t.1.follows = true;
        }
        let lines = share(&turns, &noise);
        assert_eq!(lines.len(), 4);
        assert_eq!((lines[0].r, lines[0].alpha), (lines[2].r, lines[2].alpha));
    }

    #[test]
    fn parallel_surfaces_apart_keep_their_own_fits() {
        let noise = RangeNoise::new(0.005, 0.0);
        // A box face 5 cm in front of the wall: 10 standard deviations of the noise.
        let pieces = [
            piece(-50..-10, 0.02, 2.0, &noise),
            piece(15..55, 0.02, 1.95, &noise),
        ];
        let lines = share(&pieces, &noise);
        assert_eq!(lines.len(), 2);
        for (kept, own) in lines.iter().zip(&pieces) {
            assert_eq!(kept, &own.0);
        }
    }

    #[test]
    fn a_piece_too_uncertain_alone_is_kept_when_its_wall_pins_it_down() {
        // 3 cm noise: a 10-point piece 0.18 m long knows its direction to about 8 deg.
        let noise = RangeNoise::new(0.03, 0.0);
        let short = piece(60..70, 0.02, 2.0, &noise);
        assert!(!short.1.certain);
        assert!(share(std::slice::from_ref(&short), &noise).is_empty());
        let long = piece(-60..10, 0.02, 2.0, &noise);
        let lines = share(&[long, short], &noise);
        assert_eq!(lines.len(), 2);
        assert_eq!(lines[1].points, 10);
        assert!(certain(&lines[1].covariance, &HoughSplitParams::default()));
    }

    /// A line and its candidate on `points`.
    fn piece_of(points: &[Point2], noise: &RangeNoise) -> (Line, Candidate) {
        let sums = FitSums::from_points(points.iter().copied());
        let fit = sums.fit().unwrap();
        let n = points.len();
        let mut line = Line::from_fit(&fit, (0, points[0]), (n - 1, points[n - 1]));
        line.covariance = floored_covariance(&fit, noise, true);
        let certain = certain(&line.covariance, &HoughSplitParams::default());
        let ends = (points[0], points[n - 1]);
        let span = (0, n as u32);
        (
            line,
            Candidate {
                sums,
                ends,
                certain,
                span,
                follows: false,
            },
        )
    }

    #[test]
    fn uncertain_pieces_of_two_walls_share_no_fit() {
        // A 360 deg scanner of 0.5 deg steps at 2 % noise (the noise its scan gave): 17
        // beams on a wall at r 7.72 m, alpha -66.4 deg, and 8 beams on a perpendicular wall
        // at r 6.63 m, alpha 23.6 deg, 9 m further round. Each alone is too uncertain to
        // keep. One line through both centroids, 25 and 65 deg off the walls, passes the
        // test of a group with a certain line (chi-square 13.79), not the stricter one.
        let noise = RangeNoise::new(0.07, 0.0183);
        let step = std::f64::consts::PI / 360.0;
        let beams = |first: usize, ranges: &[f64]| -> Vec<Point2> {
            let bearing = |i: usize| -std::f64::consts::PI + (first + i) as f64 * step;
            let at =
                |(i, r): (usize, &f64)| Point2::new(r * bearing(i).cos(), r * bearing(i).sin());
            ranges.iter().enumerate().map(at).collect()
        };
        let a = beams(
            198,
            &[
                8.2089, 8.1877, 7.8291, 7.8637, 8.0933, 7.9215, 8.0305, 7.8365, 7.9858, 7.9725,
                7.6823, 7.6082, 7.7192, 7.9927, 7.707, 7.5798, 7.6375,
            ],
        );
        let b = beams(
            342,
            &[
                7.8821, 7.7426, 7.8797, 7.8018, 7.7763, 7.9665, 7.4543, 7.6862,
            ],
        );
        let pieces = [piece_of(&a, &noise), piece_of(&b, &noise)];
        assert!(!pieces[0].1.certain && !pieces[1].1.certain);
        let (sa, sb) = (&pieces[0].1.sums, &pieces[1].1.sums);
        assert!(one_line(sa, sb, &noise, true, SHARE_CHI2));
        assert!(!one_line(sa, sb, &noise, true, SHARE_CHI2_UNANCHORED));
        // Neither takes a joint fit, so neither is pinned down: both are dropped.
        assert!(share(&pieces, &noise).is_empty());
    }

    #[test]
    fn uncertain_pieces_of_one_wall_still_pin_each_other_down() {
        // 3 cm noise: two 10-point pieces 0.18 m long, 1.4 m apart on the wall y = 2.
        let noise = RangeNoise::new(0.03, 0.0);
        let pieces = [
            piece(-10..0, 0.02, 2.0, &noise),
            piece(60..70, 0.02, 2.0, &noise),
        ];
        assert!(!pieces[0].1.certain && !pieces[1].1.certain);
        let lines = share(&pieces, &noise);
        assert_eq!(lines.len(), 2);
        assert!((lines[0].r - 2.0).abs() < 0.01 && (lines[1].r - 2.0).abs() < 0.01);
    }

    #[test]
    fn a_group_with_a_certain_line_takes_pieces_by_the_looser_test() {
        // 3 cm noise: a 10-point piece 6 cm off the wall lies between the two quantiles of
        // its chi-square against a 70-point piece of the wall.
        let noise = RangeNoise::new(0.03, 0.0);
        let long = piece(-60..10, 0.02, 2.0, &noise);
        let off = piece(60..70, 0.02, 2.06, &noise);
        assert!(long.1.certain && !off.1.certain);
        let (a, b) = (&long.1.sums, &off.1.sums);
        assert!(one_line(a, b, &noise, true, SHARE_CHI2));
        assert!(!one_line(a, b, &noise, true, SHARE_CHI2_UNANCHORED));
        let shared = |lines: &[Line]| {
            lines
                .windows(2)
                .all(|w| (w[0].r, w[0].alpha) == (w[1].r, w[1].alpha))
        };
        // The certain line first, or joining the uncertain one.
        for pieces in [[long, off], [off, long]] {
            let lines = share(&pieces, &noise);
            assert!(lines.len() == 2 && shared(&lines), "{lines:?}");
        }
        // A group made certain by a later line: an uncertain piece on the wall, the certain
        // one, then a piece 5 cm off the wall, between the quantiles against the two.
        let before = piece(-80..-70, 0.02, 2.0, &noise);
        let off = piece(60..70, 0.02, 2.05, &noise);
        assert!(!before.1.certain);
        let group = before.1.sums.join(&long.1.sums);
        assert!(one_line(&group, &off.1.sums, &noise, true, SHARE_CHI2));
        assert!(!one_line(
            &group,
            &off.1.sums,
            &noise,
            true,
            SHARE_CHI2_UNANCHORED
        ));
        let lines = share(&[before, long, off], &noise);
        assert!(lines.len() == 3 && shared(&lines), "{lines:?}");
    }

    /// The sums of `n` points from `a` to `b`.
    fn run(a: Point2, b: Point2, n: usize) -> FitSums {
        FitSums::from_points((0..n).map(|i| a + (b - a) * (i as f64 / (n - 1) as f64)))
    }

    #[test]
    fn objects_far_apart_share_no_line_that_grazes_both() {
        let noise = RangeNoise::new(0.01, 0.01);
        // Two faces of 6 cm at 3 and 5 m, facing the sensor: the line x = 0.5 passes within
        // 3 cm of every point, well within sigma(4 m) = 4 cm, but at 80 and 84 deg of
        // incidence, where the noise across it is 5 and 4 mm.
        let a = run(Point2::new(0.47, 3.0), Point2::new(0.53, 3.0), 8);
        let b = run(Point2::new(0.47, 5.0), Point2::new(0.53, 5.0), 8);
        assert!(!one_line(&a, &b, &noise, true, SHARE_CHI2));
        assert!(one_line(&a, &b, &noise, false, SHARE_CHI2));
        // Two pieces of that line itself, as glancing as they are, do share it.
        let a = run(Point2::new(0.5, 2.9), Point2::new(0.5, 3.1), 8);
        let b = run(Point2::new(0.5, 4.9), Point2::new(0.5, 5.1), 8);
        assert!(one_line(&a, &b, &noise, true, SHARE_CHI2));
        assert!(one_line(&a, &b, &noise, false, SHARE_CHI2));
    }
}
