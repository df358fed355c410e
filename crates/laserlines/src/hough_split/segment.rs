//! Step 3-4: radius grouping, merging of touching groups into data segments, and removal of
//! the points outside every segment (paper section II-B, ALGORITHM section 2).
//!
//! Grouping along a ring and merging groups that touch in a neighbouring ring is computed in
//! one union-find pass over the kept cells: two kept cells are joined when they lie in the same
//! ring at most `1 + group_gap` sectors apart, or in neighbouring rings of the same or of
//! neighbouring sectors (the 8-neighbourhood). Each connected component is one group of the
//! paper's Fig. 4b. A data segment is then a maximal run of surviving points, in beam order,
//! whose cells belong to one component: this resolves interleaved components (a box in front
//! of a wall) so that every point belongs to exactly one segment, and segments never overlap.

use super::accumulator::{Accumulator, NONE};
use super::params::HoughSplitParams;
use crate::noise::RangeNoise;
use crate::scan::ScanPoint;

/// A data segment: a run of surviving points `kept[start..end]` in beam order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct SegmentRun {
    pub(crate) start: u32,
    pub(crate) end: u32,
}

/// Union-find over cell indices.
#[derive(Debug, Default, Clone)]
pub(crate) struct Components {
    pub(crate) parent: Vec<u32>,
}

impl Components {
    fn reset(&mut self, n: usize) {
        self.parent.clear();
        self.parent.extend(0..n as u32);
    }

    pub(crate) fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] as usize != x {
            let grand = self.parent[self.parent[x] as usize];
            self.parent[x] = grand;
            x = grand as usize;
        }
        x
    }

    fn same(&mut self, a: usize, b: usize) -> bool {
        self.find(a) == self.find(b)
    }

    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            // Smaller index becomes the root: roots are then deterministic and in scan order.
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            self.parent[hi] = lo as u32;
        }
    }
}

/// Joins touching kept cells (grouping along rings and merging across rings).
pub(crate) fn connect_cells(acc: &Accumulator, p: &HoughSplitParams, uf: &mut Components) {
    uf.reset(acc.cells.len());
    let sectors = acc.sector_start.len().saturating_sub(1);
    for k in 0..sectors {
        let here = acc.sector_cells(k);
        // Same sector: neighbouring rings.
        for c in here.clone().skip(1) {
            let (a, b) = (&acc.cells[c - 1], &acc.cells[c]);
            if a.kept && b.kept && b.ring - a.ring <= 1 {
                uf.union(c - 1, c);
            }
        }
        // Earlier sectors: the neighbouring one in the 8-neighbourhood, farther ones (up to the
        // grouping gap) along the same ring only.
        for back in 1..=(1 + p.group_gap) {
            if back > k {
                break;
            }
            let there = acc.sector_cells(k - back);
            let reach = u32::from(back == 1);
            let mut lo = there.start;
            for c in here.clone() {
                let cell = acc.cells[c];
                if !cell.kept {
                    continue;
                }
                while lo < there.end && acc.cells[lo].ring + reach < cell.ring {
                    lo += 1;
                }
                let mut o = lo;
                while o < there.end && acc.cells[o].ring <= cell.ring + reach {
                    if acc.cells[o].kept {
                        uf.union(c, o);
                    }
                    o += 1;
                }
            }
        }
    }
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
                let f = p.breakpoint_distance(1.0, step * g as f64, step, 0.0);
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

    /// True when `b`, `gap` beams after `a`, lies within `D` of it.
    #[inline]
    pub(crate) fn joins(&self, a: &ScanPoint, b: &ScanPoint, gap: usize) -> bool {
        let Some(&f) = self.factor.get(gap.wrapping_sub(1)) else {
            return false;
        };
        let limit = a.range * f + self.spread * self.noise.sigma(a.range);
        let d = b.point - a.point;
        let d2 = d.x * d.x + d.y * d.y;
        // NaN factors and limits fail; squares that overflow (absurd ranges) never join.
        d2.is_finite() && d2 <= limit * limit
    }
}

/// Joins the cells of nearby surviving points that lie closer than the breakpoint distance
/// `D`: each point is compared with the points up to `bridge_max_gap` beams before it
/// (missing beams, or points of other cells in between) until one joins it, so that a single
/// outlier does not cut a wall in two.
pub(crate) fn bridge_beams(
    points: &[ScanPoint],
    cell_of: &[u32],
    bp: &Breakpoints,
    uf: &mut Components,
) {
    let reach = bp.reach();
    for pi in 0..points.len() {
        let cell = cell_of[pi];
        if cell == NONE {
            continue;
        }
        let here = &points[pi];
        for q in (0..pi).rev() {
            let gap = here.index - points[q].index;
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
            if bp.joins(&points[q], here, gap) {
                uf.union(cell as usize, other as usize);
                break;
            }
        }
    }
}

/// Cuts the surviving points into data segments and fills `kept` with the indices of the
/// points that remain.
///
/// Points whose component holds fewer than `min_segment_points` points are removed first
/// (sparse and cluttered points: the paper's `Pm[i] = 0`); the rest are cut into maximal
/// runs of one component, and (with `bridge_beams`) a run is also cut where consecutive
/// points lie more than `bridge_max_gap` missing beams or more than the breakpoint distance
/// `D` apart, so that no segment, and no line, spans empty space. Runs shorter than `min_segment_points` are
/// removed too.
#[allow(clippy::too_many_arguments)]
pub(crate) fn cut_segments(
    points: &[ScanPoint],
    cell_of: &[u32],
    p: &HoughSplitParams,
    bp: &Breakpoints,
    uf: &mut Components,
    sizes: &mut Vec<u32>,
    kept: &mut Vec<u32>,
    segments: &mut Vec<SegmentRun>,
) {
    kept.clear();
    segments.clear();
    let min = p.min_segment_points.max(1);
    // Points per component, counted at each component's root.
    sizes.clear();
    sizes.resize(uf.parent.len(), 0);
    for &cell in cell_of {
        if cell != NONE {
            let root = uf.find(cell as usize);
            sizes[root] += 1;
        }
    }
    let close = |kept: &mut Vec<u32>, segments: &mut Vec<SegmentRun>, start: usize| {
        if kept.len() - start >= min {
            segments.push(SegmentRun {
                start: start as u32,
                end: kept.len() as u32,
            });
        } else {
            kept.truncate(start);
        }
    };
    let mut run_root = usize::MAX;
    let mut run_start = 0usize;
    for (pi, &cell) in cell_of.iter().enumerate() {
        if cell == NONE {
            continue;
        }
        let root = uf.find(cell as usize);
        if (sizes[root] as usize) < min {
            continue;
        }
        let joined = run_root == root
            && (!p.bridge_beams
                || kept.last().is_some_and(|&q| {
                    let (a, b) = (&points[q as usize], &points[pi]);
                    bp.joins(a, b, b.index - a.index)
                }));
        if !joined {
            if run_root != usize::MAX {
                close(kept, segments, run_start);
            }
            run_root = root;
            run_start = kept.len();
        }
        kept.push(pi as u32);
    }
    if run_root != usize::MAX {
        close(kept, segments, run_start);
    }
}
