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
use super::opening;
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
    /// Per group: its last line.
    last: Vec<u32>,
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
        group_lines(
            &lines[..n],
            &candidates[..n],
            (noise, p.noise_along_beams),
            seen,
            groups,
        );
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
/// line certain on its own, else by [`SHARE_CHI2_UNANCHORED`], and then not when the beams
/// between the group's last line and this one see through the joint line over more than a
/// doorway ([`opening::seen_beyond`]): the lever arm of two uncertain pieces of different
/// surfaces would give each a certain fit several degrees off.
fn group_lines(
    lines: &[Line],
    candidates: &[Candidate],
    (noise, along): (&RangeNoise, bool),
    seen: Seen<'_>,
    groups: &mut Groups,
) {
    let Groups {
        group,
        sums: joint,
        tried,
        anchored,
        last,
        ..
    } = groups;
    group.clear();
    joint.clear();
    tried.clear();
    anchored.clear();
    last.clear();
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
            let unanchored = !(anchored[g] || c.certain);
            let limit = if unanchored {
                SHARE_CHI2_UNANCHORED
            } else {
                SHARE_CHI2
            };
            if one_line(&joint[g].0, own, noise, along, limit)
                && !(unanchored
                    && parted(
                        lines,
                        (last[g] as usize, j),
                        &joint[g].0.join(own),
                        seen,
                        noise,
                    ))
            {
                found = Some(g);
                break;
            }
        }
        match found {
            Some(g) => {
                joint[g].0 = joint[g].0.join(own);
                joint[g].1 += 1;
                anchored[g] |= c.certain;
                last[g] = j as u32;
                group.push(g as u32);
            }
            None => {
                group.push(joint.len() as u32);
                joint.push((*own, 1));
                tried.push(u32::MAX);
                anchored.push(c.certain);
                last.push(j as u32);
            }
        }
    }
}

/// True when the beams between `lines[a]` and `lines[b]` (`a` before `b`) see through the
/// line fitted to `whole` between them over more than a doorway ([`opening::OPENING`]).
fn parted(
    lines: &[Line],
    (a, b): (usize, usize),
    whole: &FitSums,
    seen: Seen<'_>,
    noise: &RangeNoise,
) -> bool {
    let (Some(la), Some(lb), Some(fit)) = (lines.get(a), lines.get(b), whole.normal_fit()) else {
        return false;
    };
    let ends = (la.end, lb.start);
    opening::seen_beyond(seen.returns, (la.last, lb.first), ends, &fit, noise) > opening::OPENING
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
#[path = "collinear_tests.rs"]
mod tests;
