//! Step 4: data segments, and removal of the points outside every segment (paper section
//! II-B, ALGORITHM section 2), after the beam bridge joins the components of nearby points.
//!
//! A data segment is a maximal run of surviving points, in beam order, whose cells belong to
//! one component ([`super::components`]): this resolves interleaved components (a box in
//! front of a wall) so that every point belongs to exactly one segment, and segments never
//! overlap.

use super::accumulator::{Bin, NONE, VOID};
use super::components::Components;
use super::local_bridge::{LOCAL_MAX_SIN_INCIDENCE, LocalBridge};
use super::params::HoughSplitParams;
use super::points::Pt;
use crate::noise::{RangeNoise, SPARSE_DROPOUT};

/// A data segment: a run of surviving points `kept[start..end]` in beam order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct SegmentRun {
    pub(crate) start: u32,
    pub(crate) end: u32,
}

/// The breakpoint distance `D` of one scan ([`HoughSplitParams::breakpoint_distance`]) with
/// its trigonometry done once: `factor[g - 1] = sin(g dphi) / sin(lambda - g dphi)` for a gap
/// of `g` beams (NaN where `g dphi` exceeds `lambda / 3`).
#[derive(Debug, Default, Clone)]
pub(crate) struct Breakpoints {
    key: Option<(u64, u64, u64, u64, usize)>,
    factor: Vec<f64>,
    /// `bridge_sigmas * sqrt(2)`.
    spread: f64,
    noise: RangeNoise,
    /// The farthest reading that tells a beam saw through: `+inf` on a scan whose beams
    /// mostly return, the range limit on a sparse one ([`SPARSE_DROPOUT`]).
    see_max: f64,
    /// The bridge across a surface that returns few of its beams on a scan that returns most.
    local: LocalBridge,
}

impl Breakpoints {
    /// Makes the table right for `p`, beams `increment` apart, `noise`, the scan's
    /// `dropout` ([`HoughSplitParams::bridge_for`]) and its smallest and largest valid ranges
    /// `range_min` and `range_max`.
    pub(crate) fn prepare(
        &mut self,
        p: &HoughSplitParams,
        increment: f64,
        noise: RangeNoise,
        (dropout, range_min, range_max): (f64, f64, f64),
    ) {
        self.see_max = if dropout >= SPARSE_DROPOUT {
            range_max
        } else {
            f64::INFINITY
        };
        let bridge = p.bridge_for(increment, dropout);
        let key = (
            increment.to_bits(),
            bridge.spacing.to_bits(),
            p.bridge_incidence.to_bits(),
            p.bridge_sigmas.to_bits(),
            bridge.max_gap,
        );
        if self.key != Some(key) {
            self.key = Some(key);
            p.breakpoint_factors(increment, bridge, &mut self.factor);
            self.spread = p.bridge_sigmas * std::f64::consts::SQRT_2;
        }
        self.noise = noise;
        // Off: a local reach no longer than the scan's own is no local bridge.
        let dense = if p.local_bridge {
            self.factor.len()
        } else {
            usize::MAX
        };
        self.local.prepare(p, (increment, dense), range_min);
    }

    /// The geometric part of `D` for neighbouring beams per metre of range,
    /// `sin(dphi) / sin(lambda - dphi)` (0 when `D` joins no neighbours).
    pub(crate) fn one_beam(&self) -> f64 {
        self.factor
            .first()
            .copied()
            .filter(|f| f.is_finite())
            .unwrap_or(0.0)
    }

    /// Most beams apart two points of one segment may be by the scan's own bridge.
    pub(crate) fn reach(&self) -> usize {
        self.factor.len()
    }

    /// True when a point at `(xb, yb)`, `gap` beams after the point `a`, lies within `D` of
    /// it.
    #[inline(always)]
    pub(crate) fn joins(&self, a: &Pt, (xb, yb): (f64, f64), gap: usize) -> bool {
        let Some(&f) = self.factor.get(gap.wrapping_sub(1)) else {
            return false;
        };
        self.within(a, (xb, yb), f)
    }

    /// True when the point `b`, `gap` beams after the point `a`, lies within `D` of it, by
    /// the scan's own bridge or, beyond it, by the local one of a sparse surface
    /// ([`LocalBridge::factor`], which reads `ranges`).
    #[inline(always)]
    pub(crate) fn joins_across(&self, ranges: &[f64], a: &Pt, b: &Pt, gap: usize) -> bool {
        if gap <= self.factor.len() {
            self.joins(a, (b.x, b.y), gap)
        } else {
            self.joins_sparse(ranges, a, b, gap)
        }
    }

    /// The local bridge's part of [`Breakpoints::joins_across`]: a gap the scan's own bridge
    /// does not reach.
    #[cold]
    #[inline(never)]
    fn joins_sparse(&self, ranges: &[f64], a: &Pt, b: &Pt, gap: usize) -> bool {
        let Some(f) = self.local.factor(ranges, a, b.idx, gap) else {
            return false;
        };
        // The chord from `a` to `b` against `a`'s beam: the sine of the incidence of the
        // surface the two would share.
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let steep = (dx * a.x + dy * a.y).abs() > LOCAL_MAX_SIN_INCIDENCE * dx.hypot(dy) * a.range;
        !steep && self.within(a, (b.x, b.y), f)
    }

    /// True when a point at `(xb, yb)` lies within `D` of `a` for the geometric factor `f`.
    #[inline(always)]
    fn within(&self, a: &Pt, (xb, yb): (f64, f64), f: f64) -> bool {
        let limit = a.range * f + self.spread * self.noise.sigma(a.range);
        let (dx, dy) = (xb - a.x, yb - a.y);
        let d2 = dx * dx + dy * dy;
        // NaN factors and limits fail; squares that overflow (absurd ranges) never join.
        d2 < f64::INFINITY && d2 <= limit * limit
    }

    /// True when a beam between points `a` and `b` (of `ranges`) saw through the gap: its
    /// range lies beyond both of theirs by more than `bridge_sigmas` sigma (a longer finite
    /// reading, or `+inf`, REP 117's "nothing in range"; on a sparse scan only a reading
    /// within the range limit). Missing beams (NaN, 0, below the minimum) tell nothing and do
    /// not count. [`run_step`] cuts there only when the two points
    /// also lie farther apart than `D` of neighbouring beams: a single stray far reading
    /// inside a wall does not cut it.
    #[inline]
    pub(crate) fn sees_through(&self, ranges: &[f64], a: &Pt, b: &Pt) -> bool {
        let far = a.range.max(b.range);
        let beyond = far + self.spread * self.noise.sigma(far);
        ranges
            .get(a.idx + 1..b.idx)
            .is_some_and(|between| between.iter().any(|&r| r > beyond && r <= self.see_max))
    }
}

/// The fraction of a scan's returns (`points`, in beam order, of `beams` beams) whose next
/// beam returned nothing: the chance that a beam misses where its neighbour hit, which open
/// space beyond the range (one miss after each of its edges) hardly moves. Points nearer than
/// `min_range` count as missing.
pub(crate) fn dropout(points: &[Pt], beams: usize) -> f64 {
    let Some(last) = points.last() else {
        return 0.0;
    };
    let mut misses = 0usize;
    for w in points.windows(2) {
        misses += usize::from(w[1].idx != w[0].idx + 1);
    }
    // The last beam has no next one.
    let at_end = last.idx + 1 >= beams;
    let hits = points.len() - usize::from(at_end);
    misses += usize::from(!at_end);
    if hits == 0 {
        0.0
    } else {
        misses as f64 / hits as f64
    }
}

/// Gives a point whose cell fell below the criterion the cell of a neighbouring kept point
/// when it lies on the surface between two of them: the nearest points of kept cells before
/// and after it, within the bridge's gap, both join it within `D`. The criterion removes
/// sparse points, and such a point is none: near the sensor a lone point at a ring boundary
/// weighs its range, below the criterion (0.4 against 0.5 at 0.4 m), and two of them around
/// a missing beam cut a wall 0.35 m away in two. Points that voted in no cell (mixed pixels,
/// spikes) stay removed.
pub(crate) fn rescue_points(
    points: &[Pt],
    cell_of: &mut [u32],
    bins: &mut [Bin],
    bp: &Breakpoints,
) {
    let n = cell_of.len().min(points.len());
    // The last point whose own cell is kept: the points after it, up to the next such
    // point, are all below the criterion.
    let mut a = usize::MAX;
    for b in 0..n {
        if !bins[cell_of[b] as usize].kept {
            continue;
        }
        if a != usize::MAX && a + 1 < b {
            rescue_between(points, cell_of, bins, bp, a, b);
        }
        a = b;
    }
}

/// [`rescue_points`] for the points strictly between the kept points `a` and `b`.
fn rescue_between(
    points: &[Pt],
    cell_of: &mut [u32],
    bins: &mut [Bin],
    bp: &Breakpoints,
    a: usize,
    b: usize,
) {
    let reach = bp.reach();
    let (pa, pb) = (&points[a], &points[b]);
    for u in a + 1..b {
        let here = &points[u];
        let (ga, gb) = (here.idx - pa.idx, pb.idx - here.idx);
        if cell_of[u] == VOID || ga > reach || gb > reach {
            continue;
        }
        if bp.joins(pa, (here.x, here.y), ga) && bp.joins(here, (pb.x, pb.y), gb) {
            let to = if ga <= gb { cell_of[a] } else { cell_of[b] };
            cell_of[u] = to;
            bins[to as usize].points += 1;
        }
    }
}

/// Joins the cells of nearby surviving points that lie closer than the breakpoint distance
/// `D`: each point is compared with the points up to `bridge_max_gap` beams before it
/// (missing beams, or points of other cells in between) until one joins it, so that a single
/// outlier does not cut a wall in two; and with the return before it, farther, by the local
/// bridge of a sparse surface ([`Breakpoints::joins_across`]).
pub(crate) fn bridge_beams(
    ranges: &[f64],
    points: &[Pt],
    cell_of: &[u32],
    bp: &Breakpoints,
    uf: &mut Components,
) {
    let reach = bp.reach();
    let points = &points[..cell_of.len()];
    for pi in 1..cell_of.len() {
        let (cell, before) = (cell_of[pi] as usize, cell_of[pi - 1] as usize);
        // The usual case: the point before lies in the same cell, or in the same component.
        // Points without a kept cell are skipped.
        if cell == before {
            continue;
        }
        let (pc, pb) = (uf.parent[cell], uf.parent[before]);
        if pc == NONE || (pb != NONE && (pc == pb || uf.same(cell, before))) {
            continue;
        }
        let here = points[pi];
        for q in (0..pi).rev() {
            let gap = here.idx - points[q].idx;
            if gap > reach {
                break;
            }
            let other = cell_of[q] as usize;
            if uf.parent[other] == NONE {
                continue;
            }
            if other == cell || uf.same(cell, other) {
                break;
            }
            if bp.joins(&points[q], (here.x, here.y), gap) {
                uf.union(cell, other);
                break;
            }
        }
        // Beyond the scan's own bridge only the return before, across beams that returned
        // nothing, may join it: the local bridge of a sparse surface.
        let prev = points[pi - 1];
        let gap = here.idx - prev.idx;
        if gap > reach
            && pb != NONE
            && !uf.same(cell, before)
            && bp.joins_across(ranges, &prev, &here, gap)
        {
            uf.union(cell, before);
        }
    }
}

/// Where [`cut_segments`] puts its results and keeps its working memory.
#[derive(Debug, Default, Clone)]
pub(crate) struct Segments {
    /// The surviving points, in beam order.
    pub(crate) kept: Vec<Pt>,
    /// The data segments, as runs of `kept`.
    pub(crate) runs: Vec<SegmentRun>,
    /// Points per component, counted at each component's root.
    sizes: Vec<u32>,
    /// Per cell: the root of its component when that is kept as a data segment, else `NONE`.
    root_of: Vec<u32>,
}

/// Cuts the surviving points into data segments, filling `out.kept` with the points that
/// remain and `out.runs` with the segments.
///
/// Points whose component holds fewer than `min` points (`min_segment_points`, or fewer on
/// a sparse scan: [`HoughSplitParams::min_points_for`]) are removed first
/// (sparse and cluttered points: the paper's `Pm[i] = 0`); the rest are cut into maximal
/// runs of one component, and (with `bridge_beams`) a run is also cut where consecutive
/// points lie more than the bridge's missing beams ([`HoughSplitParams::bridge_for`]) or more than the breakpoint distance
/// `D` apart, or where a beam between them saw through ([`Breakpoints::sees_through`]), so
/// that no segment, and no line, spans empty space; a lone jump of the noise ([`lone`]) is
/// dropped instead of cutting. Runs shorter than `min` are removed too.
#[allow(clippy::too_many_arguments)]
pub(crate) fn cut_segments(
    ranges: &[f64],
    points: &[Pt],
    cell_of: &[u32],
    bins: &[Bin],
    (p, min): (&HoughSplitParams, usize),
    bp: &Breakpoints,
    uf: &mut Components,
    out: &mut Segments,
) {
    let Segments {
        kept,
        runs,
        sizes,
        root_of,
    } = out;
    runs.clear();
    let min = min.max(1);
    uf.flatten();
    // Points per component, from the points of each kept cell; then each cell's root when
    // its component is large enough.
    sizes.clear();
    sizes.resize(uf.parent.len(), 0);
    for (b, &root) in bins.iter().zip(&uf.parent) {
        if root != NONE {
            sizes[root as usize] += b.points;
        }
    }
    root_of.clear();
    root_of.extend(uf.parent.iter().map(|&root| {
        if root != NONE && sizes[root as usize] as usize >= min {
            root
        } else {
            NONE
        }
    }));
    let n = points.len().min(cell_of.len());
    // Every point is written at the end of `kept`, which advances when it survives.
    kept.resize(n, Pt::default());
    let input = RunInput {
        ranges,
        points: &points[..n],
        cell_of: &cell_of[..n],
        root_of,
        bp,
        min,
    };
    let m = if p.bridge_beams {
        runs_of::<true>(&input, kept, runs)
    } else {
        runs_of::<false>(&input, kept, runs)
    };
    kept.truncate(m);
}

/// What the run loop of [`cut_segments`] reads.
#[derive(Clone, Copy)]
struct RunInput<'a> {
    /// The scan's ranges, by beam.
    ranges: &'a [f64],
    points: &'a [Pt],
    cell_of: &'a [u32],
    /// Per cell: the root of its component when that is kept, else `NONE`.
    root_of: &'a [u32],
    bp: &'a Breakpoints,
    /// Fewest points of a data segment.
    min: usize,
}

/// Where the run loop of [`cut_segments`] stands: the points kept so far (`kept[..m]`), the
/// component of the open run (`NONE` before the first) and where it starts, and the last
/// kept point.
struct RunState {
    m: usize,
    run_root: u32,
    run_start: usize,
    last: Pt,
}

/// The run loop of [`cut_segments`]: writes the surviving points to `kept` (as long as
/// `points`) and their runs to `runs`; returns the number of surviving points.
///
/// The usual point (the next beam, in the open run's component and, with the beam bridge,
/// within `D` of the last kept point) goes on the run at once; every other point takes
/// [`run_step`].
fn runs_of<const BRIDGE: bool>(
    input: &RunInput<'_>,
    kept: &mut [Pt],
    runs: &mut Vec<SegmentRun>,
) -> usize {
    let RunInput {
        points,
        cell_of,
        root_of,
        bp,
        min,
        ..
    } = *input;
    let mut st = RunState {
        m: 0,
        run_root: NONE,
        run_start: 0,
        last: Pt::default(),
    };
    // Without a factor for neighbouring beams every step goes through `run_step` (`joins`
    // would say no as well; asked once here, the loop's own test is shorter: 1.1k fewer
    // instructions per bench scan).
    let quick = bp.reach() >= 1;
    for (i, (&pt, &cell)) in points.iter().zip(cell_of).enumerate() {
        let root = root_of[cell as usize];
        if root == NONE {
            continue;
        }
        let joined = root == st.run_root
            && pt.idx == st.last.idx + 1
            && (!BRIDGE || (quick && bp.joins(&st.last, (pt.x, pt.y), 1)));
        if !joined {
            st = run_step::<BRIDGE>(input, (i, root), kept, runs, st);
            continue;
        }
        kept[st.m] = pt;
        st.m += 1;
        st.last = pt;
    }
    if st.run_root != NONE {
        st.m = close_run(runs, st.m, st.run_start, min);
    }
    st.m
}

/// One point of [`runs_of`], `points[i]` of the kept component `root`, in general: a jump
/// beyond `D`, a gap, another component.
#[inline(never)]
fn run_step<const BRIDGE: bool>(
    input: &RunInput<'_>,
    (i, root): (usize, u32),
    kept: &mut [Pt],
    runs: &mut Vec<SegmentRun>,
    mut st: RunState,
) -> RunState {
    let RunInput {
        ranges,
        points,
        bp,
        min,
        ..
    } = *input;
    let pt = points[i];
    let mut gap = pt.idx - st.last.idx;
    let mut far = BRIDGE && st.run_root != NONE && !bp.joins_across(ranges, &st.last, &pt, gap);
    if far
        && root == st.run_root
        && st.m >= st.run_start + 2
        && lone(bp, &kept[st.m - 2], &st.last, &pt)
        && next_in(input, i, root, &kept[st.m - 2])
            .is_some_and(|d| bp.joins(&kept[st.m - 2], (d.x, d.y), 1))
    {
        // The last point was the jump: it goes, and the point before it, which `pt`
        // and the point after `pt` join, is the last.
        st.m -= 1;
        st.last = kept[st.m - 1];
        gap = pt.idx - st.last.idx;
        far = false;
    } else if far
        && next_in(input, i, st.run_root, &st.last).is_some_and(|c| lone(bp, &st.last, &pt, c))
    {
        return st;
    }
    let cut = BRIDGE
        && (far
            || (gap > 1
                && st.run_root != NONE
                && !bp.joins(&st.last, (pt.x, pt.y), 1)
                && bp.sees_through(ranges, &st.last, &pt)));
    if root != st.run_root || cut {
        if st.run_root != NONE {
            st.m = close_run(runs, st.m, st.run_start, min);
        }
        st.run_root = root;
        st.run_start = st.m;
    }
    kept[st.m] = pt;
    st.m += 1;
    st.last = pt;
    st
}

/// How far, in sigma of the range noise, a dropped lone jump may lie from the range between
/// its neighbours: beyond, it is something in front of or behind the surface (a leg, a
/// mixed pixel), and the run is cut there as at any edge.
const SPIKE_SIGMAS: f64 = 5.0;

/// The next surviving point after `points[i]`, when it lies within the bridge's reach of
/// `from` and belongs to the component `root`.
fn next_in<'a>(input: &RunInput<'a>, i: usize, root: u32, from: &Pt) -> Option<&'a Pt> {
    let RunInput {
        points,
        cell_of,
        root_of,
        bp,
        ..
    } = *input;
    let reach = from.idx + bp.reach();
    points
        .iter()
        .zip(cell_of)
        .skip(i + 1)
        .take_while(|(q, _)| q.idx <= reach)
        .find(|(_, c)| root_of[**c as usize] != NONE)
        .and_then(|(q, c)| (root_of[*c as usize] == root).then_some(q))
}

/// True when `b`, between `a` and `c` in beam order, is a lone jump of the noise rather than
/// an edge: `c` lies within the breakpoint distance of neighbouring beams from `a` (not of
/// beams two apart: across an edge between two surfaces nearer than that, a mixed pixel
/// would look like such a jump), and `b` lies within
/// [`SPIKE_SIGMAS`] of the range between theirs. Such a point is dropped and the run goes
/// on. A wall seen by thousands of beams has pairs of neighbours whose noise differs by more
/// than the breakpoint distance's `bridge_sigmas` (one pair in 370 at 3 sigma), and cutting
/// there broke it into pieces; an edge keeps the points after it away.
fn lone(bp: &Breakpoints, a: &Pt, b: &Pt, c: &Pt) -> bool {
    let t = (b.idx - a.idx) as f64 / (c.idx - a.idx) as f64;
    let between = a.range + t * (c.range - a.range);
    (b.range - between).abs() <= SPIKE_SIGMAS * bp.noise.sigma(between)
        && bp.joins(a, (c.x, c.y), 1)
}

/// Ends the run of kept points `start..m`: a data segment when it has `min` points or more,
/// else its points are dropped. Returns the number of kept points.
fn close_run(runs: &mut Vec<SegmentRun>, m: usize, start: usize, min: usize) -> usize {
    if m - start >= min {
        runs.push(SegmentRun {
            start: start as u32,
            end: m as u32,
        });
        m
    } else {
        start
    }
}

#[cfg(test)]
#[path = "segment_tests.rs"]
mod tests;
