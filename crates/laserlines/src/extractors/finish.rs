//! The final step every classic extractor ends with: junctions settled, one least-squares
//! fit per run, and the same filter on points and length.

use super::breakpoints::Breakpoints;
use super::runs::{Run, fit_members};
use crate::fit::{FitSums, PolarFit};
use crate::line::Line;
use crate::params::{self, ParamsError};
use crate::scan::ScanPoint;

/// Largest number of points on each side of a junction that [`finish`] may move from one run
/// to its neighbour.
const SETTLE_MAX: usize = 16;

/// The final filter, the same for every classic extractor: the nested `filter` table of
/// their parameters (`filter.min_length = 0.1` in a params file).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct LineFilter {
    /// Lines with fewer supporting points are dropped. Default 8 (tuned). At least 2 is
    /// enforced.
    pub min_points: usize,
    /// Lines shorter than this are dropped, m. Default 0.15 (tuned): legs and debris give
    /// short lines; lower it when small features matter. Sensible: 0..0.5.
    pub min_length: f64,
}

impl Default for LineFilter {
    fn default() -> Self {
        Self {
            min_points: 8,
            min_length: 0.15,
        }
    }
}

impl LineFilter {
    /// Checks that `min_length` is finite and `>= 0`.
    ///
    /// # Errors
    /// A [`ParamsError`] naming `filter.min_length`.
    pub fn validate(&self) -> Result<(), ParamsError> {
        params::non_negative("filter.min_length", self.min_length)
    }
}

/// The final step of every extractor: sorts the disjoint `runs` by beam, settles each junction
/// between two adjacent runs (no valid point and no breakpoint between them) by moving up to
/// a third of each run, at most [`SETTLE_MAX`] points, to the side whose least-squares line
/// explains them better, then fits each run's members by least squares and appends the lines
/// that pass `filter` to `out`.
pub(crate) fn finish(
    points: &[ScanPoint],
    runs: &mut [Run],
    member: &[bool],
    rule: &Breakpoints,
    filter: LineFilter,
    out: &mut Vec<Line>,
) {
    runs.sort_unstable_by_key(|r| r.start);
    for i in 1..runs.len() {
        let (a, b) = (runs[i - 1], runs[i]);
        if let Some(cut) = settle(points, a, b, member, rule) {
            runs[i - 1].end = cut;
            runs[i].start = cut;
        }
    }
    let min_points = filter.min_points.max(2);
    for &run in runs.iter() {
        let mut sums = FitSums::new();
        let mut first = None;
        let mut last = None;
        for i in (run.start..run.end).filter(|&i| member[i]) {
            sums.add(points[i].point);
            first.get_or_insert(i);
            last = Some(i);
        }
        let (Some(first), Some(last)) = (first, last) else {
            continue;
        };
        if sums.len() < min_points {
            continue;
        }
        let Some(fit) = sums.fit() else {
            continue;
        };
        let (f, l) = (&points[first], &points[last]);
        let line = Line::from_fit(&fit, (f.index, f.point), (l.index, l.point));
        let finite = [
            line.r,
            line.alpha,
            line.rms,
            line.start.x,
            line.start.y,
            line.end.x,
            line.end.y,
        ]
        .iter()
        .all(|v| v.is_finite());
        if finite && line.length() >= filter.min_length {
            out.push(line);
        }
    }
}

/// The best junction between adjacent runs `a` and `b` (`a.end == b.start`), as the start of
/// `b`, or `None` when they are not adjacent or cannot be fitted.
fn settle(
    points: &[ScanPoint],
    a: Run,
    b: Run,
    member: &[bool],
    rule: &Breakpoints,
) -> Option<usize> {
    let e = a.end;
    if e != b.start || e == 0 || e >= points.len() || rule.is_break(points, e - 1, e) {
        return None;
    }
    let ka = (a.len() / 3).min(SETTLE_MAX);
    let kb = (b.len() / 3).min(SETTLE_MAX);
    if ka + kb == 0 {
        return None;
    }
    let (lo, hi) = (e - ka, e + kb);
    let fa = fit_members(
        points,
        Run {
            start: a.start,
            end: lo,
        },
        member,
    )?;
    let fb = fit_members(
        points,
        Run {
            start: hi,
            end: b.end,
        },
        member,
    )?;
    let sq = |f: &PolarFit, i: usize| {
        if member[i] {
            let d = f.distance(points[i].point);
            d * d
        } else {
            0.0
        }
    };
    // cost(c): points lo..c to a, c..hi to b.
    let mut cost: f64 = (lo..hi).map(|i| sq(&fb, i)).sum();
    if !cost.is_finite() {
        return None;
    }
    let mut best = (cost, lo);
    for c in lo..hi {
        cost += sq(&fa, c) - sq(&fb, c);
        let cut = c + 1;
        // Strictly better, or as good and closer to the current junction.
        if cost < best.0 || (cost == best.0 && cut.abs_diff(e) < best.1.abs_diff(e)) {
            best = (cost, cut);
        }
    }
    let cut = best.1;
    // Keep both runs non-empty.
    (cut > a.start && cut < b.end).then_some(cut)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::extractors::test_support::{RULE, l_shape, pts};

    #[test]
    fn settle_moves_absorbed_corner_points_back() {
        let (points, corner) = l_shape();
        let member = vec![true; points.len()];
        // The first run swallowed three points of the second wall.
        let mut runs = vec![
            Run {
                start: corner + 4,
                end: points.len(),
            },
            Run {
                start: 0,
                end: corner + 4,
            },
        ];
        let mut out = Vec::new();
        let filter = LineFilter {
            min_points: 3,
            min_length: 0.0,
        };
        finish(&points, &mut runs, &member, &RULE, filter, &mut out);
        assert_eq!(out.len(), 2);
        assert!(
            out[0].last == corner || out[0].last == corner - 1,
            "{:?}",
            out[0]
        );
        assert_eq!(out[1].first, out[0].last + 1);
        assert!((out[0].r - 1.0).abs() < 1e-9 && out[0].alpha.abs() < 1e-9);
        assert!((out[1].r - 0.5).abs() < 1e-9);
    }

    #[test]
    fn degenerate_runs_give_no_line() {
        let points = pts(&[(1.0, 1.0), (1.0, 1.0), (1.0, 1.0), (f64::NAN, 0.0)]);
        let member = vec![true; 4];
        let mut runs = vec![Run { start: 0, end: 4 }];
        let mut out = Vec::new();
        let filter = LineFilter {
            min_points: 2,
            min_length: 0.0,
        };
        finish(&points, &mut runs, &member, &RULE, filter, &mut out);
        assert!(out.is_empty());
    }
}
