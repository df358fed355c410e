//! Step 4: data segments, and removal of the points outside every segment (paper section
//! II-B, ALGORITHM section 2), after the beam bridge joins the components of nearby points.
//!
//! A data segment is a maximal run of surviving points, in beam order, whose cells belong to
//! one component ([`super::components`]): this resolves interleaved components (a box in
//! front of a wall) so that every point belongs to exactly one segment, and segments never
//! overlap.

use super::accumulator::NONE;
use super::components::Components;
use super::params::HoughSplitParams;
use super::points::Points;
use crate::noise::RangeNoise;

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
    key: Option<(u64, u64, u64, usize)>,
    factor: Vec<f64>,
    /// `bridge_sigmas * sqrt(2)`.
    spread: f64,
    noise: RangeNoise,
}

impl Breakpoints {
    /// Makes the table right for `p`, beams `increment` apart and `noise`.
    pub(crate) fn prepare(&mut self, p: &HoughSplitParams, increment: f64, noise: RangeNoise) {
        let key = (
            increment.to_bits(),
            p.bridge_incidence.to_bits(),
            p.bridge_sigmas.to_bits(),
            p.bridge_max_gap,
        );
        if self.key != Some(key) {
            self.key = Some(key);
            let step = increment.abs();
            self.factor.clear();
            for g in 1..=p.bridge_max_gap.saturating_add(1).min(64) {
                let f = p.breakpoint_distance(1.0, step * g as f64, 0.0);
                self.factor.push(f.unwrap_or(f64::NAN));
            }
            self.spread = p.bridge_sigmas * std::f64::consts::SQRT_2;
        }
        self.noise = noise;
    }

    /// Most beams apart two points of one segment may be.
    pub(crate) fn reach(&self) -> usize {
        self.factor.len()
    }

    /// True when a point at `(xb, yb)`, `gap` beams after the point at range `ra` and
    /// `(xa, ya)`, lies within `D` of it.
    #[inline(always)]
    pub(crate) fn joins(
        &self,
        (ra, xa, ya): (f64, f64, f64),
        (xb, yb): (f64, f64),
        gap: usize,
    ) -> bool {
        let Some(&f) = self.factor.get(gap.wrapping_sub(1)) else {
            return false;
        };
        let limit = ra * f + self.spread * self.noise.sigma(ra);
        let (dx, dy) = (xb - xa, yb - ya);
        let d2 = dx * dx + dy * dy;
        // NaN factors and limits fail; squares that overflow (absurd ranges) never join.
        d2 < f64::INFINITY && d2 <= limit * limit
    }
}

/// Joins the cells of nearby surviving points that lie closer than the breakpoint distance
/// `D`: each point is compared with the points up to `bridge_max_gap` beams before it
/// (missing beams, or points of other cells in between) until one joins it, so that a single
/// outlier does not cut a wall in two.
pub(crate) fn bridge_beams(
    points: &Points,
    cell_of: &[u32],
    bp: &Breakpoints,
    uf: &mut Components,
) {
    let reach = bp.reach();
    let (idx, range) = (
        &points.idx()[..cell_of.len()],
        &points.range()[..cell_of.len()],
    );
    let (xs, ys) = (&points.x()[..cell_of.len()], &points.y()[..cell_of.len()]);
    for pi in 1..cell_of.len() {
        let (cell, before) = (cell_of[pi], cell_of[pi - 1]);
        // The usual case: the point before lies in the same component.
        if cell == NONE || (before != NONE && uf.same(cell as usize, before as usize)) {
            continue;
        }
        for q in (0..pi).rev() {
            let gap = idx[pi] - idx[q];
            if gap > reach {
                break;
            }
            let other = cell_of[q];
            if other == NONE {
                continue;
            }
            if other == cell || uf.same(cell as usize, other as usize) {
                break;
            }
            if bp.joins((range[q], xs[q], ys[q]), (xs[pi], ys[pi]), gap) {
                uf.union(cell as usize, other as usize);
                break;
            }
        }
    }
}

/// Where [`cut_segments`] puts its results and keeps its working memory.
#[derive(Debug, Default, Clone)]
pub(crate) struct Segments {
    /// The surviving points, in beam order.
    pub(crate) kept: Points,
    /// The data segments, as runs of `kept`.
    pub(crate) runs: Vec<SegmentRun>,
    /// Per point: the root of its kept cell's component, or `NONE`.
    comp: Vec<u32>,
    /// Points per component, counted at each component's root.
    sizes: Vec<u32>,
}

/// Cuts the surviving points into data segments, filling `out.kept` with the points that
/// remain and `out.runs` with the segments.
///
/// Points whose component holds fewer than `min_segment_points` points are removed first
/// (sparse and cluttered points: the paper's `Pm[i] = 0`); the rest are cut into maximal
/// runs of one component, and (with `bridge_beams`) a run is also cut where consecutive
/// points lie more than `bridge_max_gap` missing beams or more than the breakpoint distance
/// `D` apart, so that no segment, and no line, spans empty space. Runs shorter than
/// `min_segment_points` are removed too.
pub(crate) fn cut_segments(
    points: &Points,
    cell_of: &[u32],
    p: &HoughSplitParams,
    bp: &Breakpoints,
    uf: &mut Components,
    out: &mut Segments,
) {
    let Segments {
        kept,
        runs,
        comp,
        sizes,
    } = out;
    kept.reset(points.len());
    runs.clear();
    let min = p.min_segment_points.max(1);
    uf.flatten();
    sizes.clear();
    sizes.resize(uf.parent.len(), 0);
    comp.clear();
    comp.extend(cell_of.iter().map(|&cell| {
        if cell == NONE {
            NONE
        } else {
            let root = uf.parent[cell as usize];
            sizes[root as usize] += 1;
            root
        }
    }));
    let n = comp.len();
    let (idx, range) = (&points.idx()[..n], &points.range()[..n]);
    let (xs, ys) = (&points.x()[..n], &points.y()[..n]);
    let (comp, sizes) = (&comp[..n], &sizes[..]);
    let out = kept.parts_mut();
    let (kidx, krange) = (&mut out.idx[..n], &mut out.range[..n]);
    let (kx, ky) = (&mut out.x[..n], &mut out.y[..n]);
    let bridge = p.bridge_beams;
    let mut m = 0usize;
    let mut run_root = NONE;
    let mut run_start = 0usize;
    // The last kept point: beam, range, x, y.
    let mut last = (0usize, 0.0, 0.0, 0.0);
    for pi in 0..n {
        let root = comp[pi];
        if root == NONE || (sizes[root as usize] as usize) < min {
            continue;
        }
        let (i, r, x, y) = (idx[pi], range[pi], xs[pi], ys[pi]);
        let joined =
            run_root == root && (!bridge || bp.joins((last.1, last.2, last.3), (x, y), i - last.0));
        if !joined {
            if run_root != NONE {
                close_run(runs, &mut m, run_start, min);
            }
            run_root = root;
            run_start = m;
        }
        (kidx[m], krange[m], kx[m], ky[m]) = (i, r, x, y);
        m += 1;
        last = (i, r, x, y);
    }
    if run_root != NONE {
        close_run(runs, &mut m, run_start, min);
    }
    *out.n = m;
}

/// Ends the run of kept points `start..m`: a data segment when it has `min` points or more,
/// else its points are dropped (`m` goes back to `start`).
fn close_run(runs: &mut Vec<SegmentRun>, m: &mut usize, start: usize, min: usize) {
    if *m - start >= min {
        runs.push(SegmentRun {
            start: start as u32,
            end: *m as u32,
        });
    } else {
        *m = start;
    }
}
