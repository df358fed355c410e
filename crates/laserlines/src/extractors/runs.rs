//! Runs of consecutive valid points: the unit every extractor hands to the final fit, and
//! how inliers are cut into them.

use super::breakpoints::Breakpoints;
use crate::fit::{FitSums, PolarFit};
use crate::scan::ScanPoint;

/// A run of consecutive valid points, `points[start..end]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Run {
    pub(crate) start: usize,
    pub(crate) end: usize,
}

impl Run {
    pub(crate) fn new(start: usize, end: usize) -> Self {
        Self { start, end }
    }

    pub(crate) fn len(self) -> usize {
        self.end.saturating_sub(self.start)
    }
}

/// Calls `f(run, members)` for every run of consecutive usable points whose members are
/// consecutive in beam order: a run ends at an unusable point, after more than `max_skip`
/// consecutive usable non-members, and at a breakpoint between two consecutive members. Runs
/// start and end at members.
pub(crate) fn for_each_run(
    points: &[ScanPoint],
    usable: impl Fn(usize) -> bool,
    member: impl Fn(usize) -> bool,
    rule: &Breakpoints,
    max_skip: usize,
    mut f: impl FnMut(Run, usize),
) {
    // (start, last member, members)
    let mut open: Option<(usize, usize, usize)> = None;
    let mut skipped = 0usize;
    for i in 0..points.len() {
        if !usable(i) {
            if let Some((s, l, m)) = open.take() {
                f(Run::new(s, l + 1), m);
            }
            continue;
        }
        if member(i) {
            match open {
                Some((s, l, m)) if skipped <= max_skip && !rule.is_break(points, l, i) => {
                    open = Some((s, i, m + 1));
                }
                Some((s, l, m)) => {
                    f(Run::new(s, l + 1), m);
                    open = Some((i, i, 1));
                }
                None => open = Some((i, i, 1)),
            }
            skipped = 0;
        } else if open.is_some() {
            skipped += 1;
            if skipped > max_skip
                && let Some((s, l, m)) = open.take()
            {
                f(Run::new(s, l + 1), m);
            }
        }
    }
    if let Some((s, l, m)) = open {
        f(Run::new(s, l + 1), m);
    }
}

/// The run with the most members (the first on ties) and its member count.
pub(crate) fn largest_run(
    points: &[ScanPoint],
    usable: impl Fn(usize) -> bool,
    member: impl Fn(usize) -> bool,
    rule: &Breakpoints,
    max_skip: usize,
) -> Option<(Run, usize)> {
    let mut best: Option<(Run, usize)> = None;
    for_each_run(points, usable, member, rule, max_skip, |run, m| {
        if best.is_none_or(|(_, b)| m > b) {
            best = Some((run, m));
        }
    });
    best
}

/// Every run with at least `min_members` members, into `found` (cleared first).
pub(crate) fn runs_with_members(
    points: &[ScanPoint],
    usable: impl Fn(usize) -> bool,
    member: impl Fn(usize) -> bool,
    rule: &Breakpoints,
    max_skip: usize,
    min_members: usize,
    found: &mut Vec<Run>,
) {
    found.clear();
    for_each_run(points, usable, member, rule, max_skip, |run, m| {
        if m >= min_members {
            found.push(run);
        }
    });
}

/// Least-squares fit of the points of `run` that satisfy `member`.
pub(crate) fn fit_where(
    points: &[ScanPoint],
    run: Run,
    member: impl Fn(usize) -> bool,
) -> Option<PolarFit> {
    FitSums::from_points(
        (run.start..run.end)
            .filter(|&i| member(i))
            .map(|i| points[i].point),
    )
    .fit()
}

/// Least-squares fit of the members of `run`.
pub(crate) fn fit_members(points: &[ScanPoint], run: Run, member: &[bool]) -> Option<PolarFit> {
    fit_where(points, run, |i| member[i])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::extractors::test_support::{RULE, l_shape};

    #[test]
    fn runs_skip_a_few_outliers_and_stop_at_unusable_points() {
        let (points, _) = l_shape();
        let mut runs = Vec::new();
        let member = |i: usize| i != 5 && i != 12 && i != 13 && i != 14;
        for_each_run(
            &points,
            |i| i != 25,
            member,
            &RULE,
            2,
            |r, m| runs.push((r, m)),
        );
        assert_eq!(
            runs,
            vec![
                (Run { start: 0, end: 12 }, 11),
                (Run { start: 15, end: 25 }, 10),
                (
                    Run {
                        start: 26,
                        end: points.len()
                    },
                    points.len() - 26
                )
            ]
        );
        let best = largest_run(&points, |_| true, |i| i < 10, &RULE, 0);
        assert_eq!(best, Some((Run { start: 0, end: 10 }, 10)));
    }
}
