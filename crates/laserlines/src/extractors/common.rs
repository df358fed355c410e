//! Pieces shared by the classic extractors, written once: the seeded PRNG, breakpoint
//! clustering, cutting inliers into runs of consecutive beams, the split of a cluster, the
//! collinear merge, the settling of junctions between adjacent runs, and the final step every
//! extractor ends with (least-squares fit, minimum points and length).
//!
//! Points are always the scan's valid points in beam order ([`crate::Scan::points_into`]);
//! a [`Run`] is a contiguous slice `points[start..end]` of them. Every extractor turns its
//! algorithm's output into disjoint runs plus a per-point member flag (the points of the run
//! used in the fit), and [`finish`] does the rest. Disjoint runs give disjoint beam ranges.

use super::ParamsError;
use crate::fit::{FitSums, PolarFit};
use crate::line::Line;
use crate::math::{Point2, Vector2};
use crate::scan::ScanPoint;

/// Largest number of points on each side of a junction that [`finish`] may move from one run
/// to its neighbour.
const SETTLE_MAX: usize = 16;

/// SplitMix64 (Steele, Lea and Flood 2014): a tiny, fast, deterministic generator, enough for
/// sampling hypotheses. Extractors reseed it from their `seed` parameter for every scan.
#[derive(Debug, Clone)]
pub(crate) struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    pub(crate) fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A uniform integer in `0..n` (0 when `n == 0`).
    pub(crate) fn below(&mut self, n: usize) -> usize {
        ((u128::from(self.next_u64()) * n as u128) >> 64) as usize
    }
}

/// A threshold that grows linearly with range: `base + per_metre * range`, metres.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Scaled {
    pub(crate) base: f64,
    pub(crate) per_metre: f64,
}

impl Scaled {
    pub(crate) fn at(self, range: f64) -> f64 {
        self.base + self.per_metre * range
    }
}

/// The adaptive breakpoint detector of Borges and Aldon (2004): consecutive valid points `a`,
/// `b` belong to different clusters when `|b - a| > r_a sin(dphi) / sin(lambda - dphi) + 3
/// sigma`. The limit grows linearly with range (the distance between beams does), and with the
/// angle between the two beams, so that a few dropped beams do not break a wall; more than
/// `max_gap` missing (invalid) beams between them always do, since the limit grows without
/// bound as `dphi` nears `lambda`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Breakpoints {
    /// `lambda`, rad: the smallest incidence angle of a surface that still counts as joined.
    pub(crate) incidence: f64,
    /// `sigma`, m: range noise allowance.
    pub(crate) noise: f64,
    /// Most missing beams between two points that can still be joined.
    pub(crate) max_gap: usize,
}

impl Breakpoints {
    /// True when `points[a]` and `points[b]` (`a < b`) are not neighbours on one surface. The
    /// valid points between them, if any, are skipped, not missing.
    pub(crate) fn is_break(&self, points: &[ScanPoint], a: usize, b: usize) -> bool {
        let (a, b, between) = (&points[a], &points[b], b.abs_diff(a));
        let missing = b.index.abs_diff(a.index).saturating_sub(between);
        if missing > self.max_gap {
            return true;
        }
        let dphi = (b.angle - a.angle).abs();
        let denom = (self.incidence - dphi).sin();
        if !(dphi.is_finite() && dphi < self.incidence && denom > 0.0) {
            return true;
        }
        let limit = a.range * dphi.sin() / denom + 3.0 * self.noise;
        let dist = (b.point - a.point).norm();
        dist.is_nan() || limit.is_nan() || dist > limit
    }

    /// Cuts `points` into clusters at every breakpoint; keeps those of at least `min_points`.
    pub(crate) fn clusters(&self, points: &[ScanPoint], min_points: usize, out: &mut Vec<Run>) {
        out.clear();
        let mut start = 0;
        for i in 1..=points.len() {
            if i == points.len() || self.is_break(points, i - 1, i) {
                if i - start >= min_points.max(1) {
                    out.push(Run { start, end: i });
                }
                start = i;
            }
        }
    }
}

/// Checks that `value` is finite and `> 0`.
pub(crate) fn positive(field: &'static str, value: f64) -> Result<(), ParamsError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(ParamsError::NotPositive { field, value })
    }
}

/// Checks that `value` is finite and `>= 0`.
pub(crate) fn non_negative(field: &'static str, value: f64) -> Result<(), ParamsError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(ParamsError::Negative { field, value })
    }
}

/// Checks that `value` lies in the open interval `(lo, hi)`.
pub(crate) fn inside(field: &'static str, value: f64, lo: f64, hi: f64) -> Result<(), ParamsError> {
    if value > lo && value < hi {
        Ok(())
    } else {
        Err(ParamsError::OutOfRange {
            field,
            value,
            lo,
            hi,
        })
    }
}

/// Checks that a count is at least `min`.
pub(crate) fn at_least(field: &'static str, value: usize, min: usize) -> Result<(), ParamsError> {
    if value >= min {
        Ok(())
    } else {
        Err(ParamsError::TooFew { field, value, min })
    }
}

/// Checks the breakpoint detector's parameters (`max_gap` needs no check).
pub(crate) fn check_breakpoints(incidence: f64, noise: f64) -> Result<(), ParamsError> {
    inside(
        "breakpoint_incidence",
        incidence,
        0.0,
        std::f64::consts::FRAC_PI_2,
    )?;
    non_negative("breakpoint_noise", noise)
}

/// Checks the final filters.
pub(crate) fn check_filter(min_line_length: f64) -> Result<(), ParamsError> {
    non_negative("min_line_length", min_line_length)
}

/// Checks a range-scaled distance threshold.
pub(crate) fn check_scaled(
    base: (&'static str, f64),
    per_metre: (&'static str, f64),
) -> Result<(), ParamsError> {
    non_negative(base.0, base.1)?;
    non_negative(per_metre.0, per_metre.1)?;
    if base.1 + per_metre.1 > 0.0 {
        Ok(())
    } else {
        Err(ParamsError::NotPositive {
            field: base.0,
            value: base.1,
        })
    }
}

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

/// A line as a unit normal `n` and distance `d`: points `p` with `n . p = d`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Hypothesis {
    pub(crate) normal: Vector2,
    pub(crate) d: f64,
}

impl Hypothesis {
    pub(crate) fn from_fit(fit: &PolarFit) -> Self {
        Self {
            normal: fit.normal(),
            d: fit.r,
        }
    }

    /// The line through two points, or `None` when they (nearly) coincide.
    pub(crate) fn through(a: Point2, b: Point2) -> Option<Self> {
        let ab = b - a;
        let len = ab.norm();
        if !(len.is_finite() && len > 1e-9) {
            return None;
        }
        let normal = Vector2::new(-ab.y / len, ab.x / len);
        Some(Self {
            normal,
            d: normal.dot(&a.coords),
        })
    }

    pub(crate) fn distance(&self, p: Point2) -> f64 {
        (self.normal.dot(&p.coords) - self.d).abs()
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

/// How a cluster is split.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SplitLine {
    /// Iterative end-point fit: distances to the chord between the piece's end points.
    Chord,
    /// Split-and-merge: distances to the piece's least-squares line.
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

/// Final filters, the same for every extractor.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LineFilter {
    /// Lines with fewer supporting points are dropped (at least 2 is enforced).
    pub(crate) min_points: usize,
    /// Lines shorter than this are dropped, m.
    pub(crate) min_length: f64,
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

/// The settings of the split-based extractors ([`super::Iepf`], [`super::SplitAndMerge`]),
/// which differ only in the line a split measures from and in their defaults.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SplitSettings {
    pub(crate) breakpoints: Breakpoints,
    pub(crate) min_cluster_points: usize,
    pub(crate) threshold: Scaled,
    pub(crate) merge_collinear: bool,
    pub(crate) filter: LineFilter,
    pub(crate) range_limits: Option<crate::scan::RangeWindow>,
}

impl SplitSettings {
    /// Checks every setting, naming the parameter fields.
    pub(crate) fn validate(&self) -> Result<(), ParamsError> {
        check_breakpoints(self.breakpoints.incidence, self.breakpoints.noise)?;
        check_scaled(
            ("split_distance", self.threshold.base),
            ("split_distance_per_metre", self.threshold.per_metre),
        )?;
        check_filter(self.filter.min_length)
    }
}

/// The [`SplitSettings`] of a parameter struct with the split extractors' field names.
macro_rules! split_settings {
    ($p:expr) => {
        $crate::extractors::common::SplitSettings {
            breakpoints: $crate::extractors::common::Breakpoints {
                incidence: $p.breakpoint_incidence,
                noise: $p.breakpoint_noise,
                max_gap: $p.breakpoint_max_gap,
            },
            min_cluster_points: $p.min_cluster_points,
            threshold: $crate::extractors::common::Scaled {
                base: $p.split_distance,
                per_metre: $p.split_distance_per_metre,
            },
            merge_collinear: $p.merge_collinear,
            filter: $crate::extractors::common::LineFilter {
                min_points: $p.min_line_points,
                min_length: $p.min_line_length,
            },
            range_limits: $p.range_limits,
        }
    };
}
pub(crate) use split_settings;

/// Breakpoint clusters, recursive split, optional merge and the common finish, with working
/// memory kept between scans.
#[derive(Debug, Clone, Default)]
pub(crate) struct SplitEngine {
    points: Vec<ScanPoint>,
    clusters: Vec<Run>,
    pieces: Vec<Run>,
    runs: Vec<Run>,
    stack: Vec<(usize, usize)>,
    member: Vec<bool>,
}

impl SplitEngine {
    /// The lines of `scan` into `out` (cleared first).
    pub(crate) fn extract_into(
        &mut self,
        scan: &crate::scan::Scan,
        s: &SplitSettings,
        line: SplitLine,
        out: &mut Vec<Line>,
    ) {
        out.clear();
        scan.points_into(scan.range_window(s.range_limits), &mut self.points);
        s.breakpoints
            .clusters(&self.points, s.min_cluster_points, &mut self.clusters);
        self.runs.clear();
        for &cluster in &self.clusters {
            self.pieces.clear();
            split(
                &self.points,
                cluster,
                line,
                s.threshold,
                &mut self.stack,
                &mut self.pieces,
            );
            if s.merge_collinear {
                merge_collinear(&self.points, &mut self.pieces, s.threshold);
            }
            self.runs.extend_from_slice(&self.pieces);
        }
        self.member.clear();
        self.member.resize(self.points.len(), true);
        finish(
            &self.points,
            &mut self.runs,
            &self.member,
            &s.breakpoints,
            s.filter,
            out,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(xy: &[(f64, f64)]) -> Vec<ScanPoint> {
        xy.iter()
            .enumerate()
            .map(|(i, &(x, y))| ScanPoint {
                index: i,
                range: (x * x + y * y).sqrt(),
                angle: y.atan2(x),
                point: Point2::new(x, y),
            })
            .collect()
    }

    /// An L seen from the origin: wall x = 1 from y = -1 to the corner (1, 0.5), then wall
    /// y = 0.5 back towards x = 0.2. Points every 0.05 m, corner at position `corner`.
    fn l_shape() -> (Vec<ScanPoint>, usize) {
        let mut xy = Vec::new();
        for i in 0..=30 {
            xy.push((1.0, -1.0 + 0.05 * i as f64));
        }
        for i in 1..=16 {
            xy.push((1.0 - 0.05 * i as f64, 0.5));
        }
        (pts(&xy), 30)
    }

    const RULE: Breakpoints = Breakpoints {
        incidence: 0.6,
        noise: 0.01,
        max_gap: 2,
    };

    #[test]
    fn splitmix_is_deterministic_and_bounded() {
        let mut a = SplitMix64::new(7);
        let mut b = SplitMix64::new(7);
        for _ in 0..100 {
            let x = a.below(13);
            assert_eq!(x, b.below(13));
            assert!(x < 13);
        }
        assert_eq!(SplitMix64::new(1).below(0), 0);
        // Reference value of SplitMix64 seeded with 0.
        assert_eq!(SplitMix64::new(0).next_u64(), 0xE220_A839_7B1D_CDAF);
    }

    #[test]
    fn breakpoints_cut_at_depth_jumps_only() {
        let inc = 0.01f64;
        let mut pts = Vec::new();
        for i in 0..40 {
            let phi = -0.2 + i as f64 * inc;
            let r = if i < 20 {
                2.0 / phi.cos()
            } else {
                1.0 / phi.cos()
            };
            pts.push(ScanPoint {
                index: i,
                range: r,
                angle: phi,
                point: Point2::new(r * phi.cos(), r * phi.sin()),
            });
        }
        let rule = Breakpoints {
            incidence: 10f64.to_radians(),
            noise: 0.01,
            max_gap: 0,
        };
        let mut out = Vec::new();
        rule.clusters(&pts, 1, &mut out);
        assert_eq!(
            out,
            vec![Run { start: 0, end: 20 }, Run { start: 20, end: 40 }]
        );
        rule.clusters(&pts, 21, &mut out);
        assert!(out.is_empty());
    }

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
