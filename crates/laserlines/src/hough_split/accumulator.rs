//! Step 1-2: the g-weighted accumulator over (range ring, beam sector) cells and the
//! noise-cancelling criterion (paper eq. 1-3, read as in ALGORITHM section 1).
//!
//! Each valid point votes only in the column of its own beam sector, and there in every ring
//! whose window `|r cos(phi - gamma_k) - d_j| <= a` it meets. The grid is sparse: only cells
//! that received a vote exist, stored sector by sector in ring order.

use std::ops::Range;

use super::mixed;
use super::params::{HoughSplitParams, Weight};
use super::points::{BeamTable, Pt};
use crate::noise::RangeNoise;
use crate::scan::{RangeWindow, ScanView};

/// One cell of the accumulator that received votes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cell {
    /// Sector (column) index, counted from the scan's first beam.
    pub sector: u32,
    /// Ring (row) index: the ring's centre distance is `ring * ring_step`.
    pub ring: u32,
    /// Weighted value `C(d, gamma)`.
    pub value: f64,
    /// True when the value is above the criterion (the cell survives noise cancelling).
    pub kept: bool,
}

/// Marks the absence of a cell.
pub(crate) const NONE: u32 = u32::MAX;

/// The cell of points that voted in no cell: `bins[VOID]`, in no sector and never kept.
pub(crate) const VOID: u32 = 0;

/// Rings a sector may span for its cells to be summed in the local table.
const LOCAL: u32 = 64;

/// The local slot of a point that voted in no ring.
const NO_SLOT: u32 = LOCAL;

/// A cell as the pipeline keeps it (its sector is implied by its position).
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Bin {
    /// Weighted value `C(d, gamma)`.
    pub(crate) value: f64,
    /// Ring index.
    pub(crate) ring: u32,
    /// Points whose kept cell this is (when kept).
    pub(crate) points: u32,
    /// Above the criterion.
    pub(crate) kept: bool,
}

/// The sector being summed in [`Accumulator::build`].
#[derive(Default)]
struct Sector {
    /// Its first point.
    start: usize,
    /// The first beam after it.
    stop: usize,
    /// The ring of `local[0]`.
    base: u32,
    /// The entries of `local` it touched.
    touched: u64,
    /// False when a ring lies outside `local`.
    fits: bool,
}

/// The sparse accumulator: `bins[VOID]`, then the cells of sector `k`,
/// `bins[sector_start[k]..sector_start[k + 1]]`, in ring order.
#[derive(Debug, Clone)]
pub(crate) struct Accumulator {
    pub(crate) bins: Vec<Bin>,
    pub(crate) sector_start: Vec<u32>,
    /// The highest ring of a kept cell (0 without any).
    pub(crate) top_ring: u32,
    /// Points that voted in a cell below the criterion (first cells; an upper bound of the
    /// points whose cell is not kept, which are never more).
    pub(crate) loose: u32,
    /// Per point: its distance along its sector's centre, m.
    along: Vec<f64>,
    /// Per point: the first and last ring its window meets.
    rings: Vec<(u32, u32)>,
    /// A sector's values by ring, from its base ring on (all zero between sectors).
    local: [f64; LOCAL as usize],
    /// Points per ring of `local` whose first ring it is (all zero between sectors).
    local_points: [u32; LOCAL as usize],
    /// The cell of each ring of `local`, and `VOID` for `NO_SLOT`.
    local_cell: [u32; LOCAL as usize + 1],
    /// The sector's points that vote in more than one ring.
    multi: Vec<u32>,
    /// The distinct rings of a sector too deep for `local`.
    distinct: Vec<u32>,
}

impl Default for Accumulator {
    fn default() -> Self {
        Self {
            bins: Vec::new(),
            sector_start: Vec::new(),
            top_ring: 0,
            loose: 0,
            along: Vec::new(),
            rings: Vec::new(),
            local: [0.0; LOCAL as usize],
            local_points: [0; LOCAL as usize],
            local_cell: [VOID; LOCAL as usize + 1],
            multi: Vec::new(),
            distinct: Vec::new(),
        }
    }
}

/// What makes a beam a point of step 0, and which points vote nowhere.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Valid {
    /// Valid ranges of the scan.
    pub(crate) window: RangeWindow,
    /// Beams nearer than this, m, give no point (the robot's own body).
    pub(crate) min_range: f64,
    /// With `remove_mixed_pixels`, the scan's noise: points that lie on neither neighbouring
    /// surface ([`mixed::isolated`]) vote in no cell and so are removed.
    pub(crate) mixed: Option<RangeNoise>,
}

/// What the points vote with.
#[derive(Clone, Copy)]
struct Votes {
    /// `g = 1` rather than `g = r`.
    weight_one: bool,
    /// The noise-cancelling criterion.
    criterion: f64,
}

impl Votes {
    #[inline]
    fn g(self, p: &Pt) -> f64 {
        if self.weight_one { 1.0 } else { p.range }
    }
}

/// The largest ring index.
const MAX_RING: f64 = (u32::MAX / 4) as f64;

/// `2^52`: adding it to a non-negative `v < 2^51` rounds `v` to the nearest integer, which
/// then sits in the low bits of the sum.
const ROUND: f64 = 4_503_599_627_370_496.0;

/// `v` clamped to `0..=MAX_RING`, NaN giving 0 (every comparison fails on NaN).
#[inline]
fn clamp_ring(v: f64) -> f64 {
    let c = if v > 0.0 { v } else { 0.0 };
    if c < MAX_RING { c } else { MAX_RING }
}

/// `ceil(v)` clamped to `0..=MAX_RING`, NaN giving 0: from the nearest integer, one up when
/// that lies below.
#[inline]
fn ceil_ring(v: f64) -> u32 {
    let c = clamp_ring(v);
    let m = c + ROUND;
    // The low 32 bits of `2^52 + k` are `k` for `k < 2^32`.
    m.to_bits() as u32 + u32::from(m - ROUND < c)
}

/// `floor(v)` clamped to `0..=MAX_RING`, NaN giving 0.
#[inline]
fn floor_ring(v: f64) -> u32 {
    // Truncation is the floor of a non-negative value.
    clamp_ring(v) as u32
}

/// The first and last ring whose window `|x - d_j| <= a` meets a point at distance `x` along
/// its sector's centre (`inv = 1 / ring_step`): `ceil((x - a) inv)` and `floor((x + a) inv)`,
/// each clamped to `0..=MAX_RING`, NaN giving 0.
#[inline]
fn ring_span(x: f64, a: f64, inv: f64) -> (u32, u32) {
    (ceil_ring((x - a) * inv), floor_ring((x + a) * inv))
}

impl Accumulator {
    /// No cells (for a scan that gives no points).
    pub(crate) fn clear(&mut self) {
        self.bins.clear();
        self.bins.push(Bin::default());
        self.sector_start.clear();
        self.top_ring = 0;
        self.loose = 0;
    }

    /// Number of cells (with `VOID`).
    pub(crate) fn len(&self) -> usize {
        self.bins.len()
    }

    /// Converts the valid beams of `scan` to `points` (step 0, see [`Valid`]), builds their
    /// accumulator, applies the criterion and fills `cell_of` with the cell of each point
    /// that the later steps join: its first cell when that is kept, else its last when that
    /// is kept, else any of its cells (not kept: the point is removed as noise), or `VOID`
    /// when it voted in none (an isolated point votes in none).
    ///
    /// A sector's points are consecutive, so its sums are kept in a table indexed by ring,
    /// summed in point order as the paper's sum over `i`, and turn into cells in ring order
    /// when the next sector begins.
    pub(crate) fn build(
        &mut self,
        scan: ScanView<'_>,
        valid: &Valid,
        table: &BeamTable,
        p: &HoughSplitParams,
        points: &mut Vec<Pt>,
        cell_of: &mut Vec<u32>,
    ) {
        self.bins.clear();
        self.bins.push(Bin::default());
        self.sector_start.clear();
        self.top_ring = 0;
        self.loose = 0;
        self.fill(scan, valid, table, points);
        let n = points.len();
        self.rings.resize(n, (0, 0));
        let (inv, a) = (1.0 / p.ring_step, p.window);
        for (ring, &x) in self.rings[..n].iter_mut().zip(&self.along[..n]) {
            *ring = ring_span(x, a, inv);
        }
        if let Some(noise) = &valid.mixed {
            // An isolated point votes nowhere: an empty span of rings (`first > last`), near
            // its own rings so that its sector's table stays where its other points vote.
            for (ring, pt) in self.rings[..n].iter_mut().zip(&points[..n]) {
                if mixed::isolated(scan.ranges, pt.idx, valid.window, noise) {
                    let first = ring.0.max(1);
                    *ring = (first, first - 1);
                }
            }
        }
        cell_of.resize(n, 0);
        self.vote(points, table, p, &mut cell_of[..n]);
        cell_of.truncate(n);
        self.sector_start.push(self.bins.len() as u32);
    }

    /// Step 0: the valid beams of `scan` as points, and each point's distance along its
    /// sector's centre in `along`.
    fn fill(&mut self, scan: ScanView<'_>, valid: &Valid, table: &BeamTable, points: &mut Vec<Pt>) {
        let (window, min_range) = (valid.window, valid.min_range);
        // A full turn is walked from its seam: its beams in the order of the walk.
        let walk = table.walk();
        let n = scan.ranges.len().min(walk.len());
        points.resize(n, Pt::default());
        self.along.resize(n, 0.0);
        // RangeWindow::contains and the minimum range as two comparisons: `r >= lo` implies
        // `r > 0`, `r <= hi` implies a finite `r`; NaN fails both (and a NaN limit fails all).
        let nan = window.min.is_nan() || window.max.is_nan() || min_range.is_nan();
        let lo = if nan {
            f64::INFINITY
        } else {
            window.min.max(min_range).max(f64::from_bits(1))
        };
        let hi = window.max.min(f64::MAX);
        let (ranges, beams) = (&scan.ranges[..n], &walk[..n]);
        let (out, along) = (&mut points[..n], &mut self.along[..n]);
        let mut count = 0usize;
        // With finite beam directions, a finite range gives a finite point.
        let check = !table.finite;
        for (i, (&r, beam)) in ranges.iter().zip(beams).enumerate() {
            if !((r >= lo) & (r <= hi)) {
                continue;
            }
            let (x, y) = (r * beam.cos, r * beam.sin);
            // A finite point: `v * 0` is 0 for finite `v`, NaN otherwise.
            if check && !((x * 0.0 == 0.0) & (y * 0.0 == 0.0)) {
                continue;
            }
            out[count] = Pt {
                x,
                y,
                range: r,
                idx: i,
            };
            along[count] = r * beam.cos_to_sector;
            count += 1;
        }
        points.truncate(count);
    }

    /// Steps 1-2 for the points, whose rings are in `rings`: each adds its weight to the cell
    /// of each ring its window meets in its own sector; `cell_of` gets each point's cell.
    fn vote(
        &mut self,
        points: &[Pt],
        table: &BeamTable,
        p: &HoughSplitParams,
        cell_of: &mut [u32],
    ) {
        let votes = Votes {
            weight_one: p.weight == Weight::One,
            criterion: p.criterion_for(table.increment),
        };
        let n = points.len().min(cell_of.len()).min(self.rings.len());
        let mut sector = Sector::default();
        for k in 0..n {
            let (pt, (first, last)) = (&points[k], self.rings[k]);
            if pt.idx >= sector.stop {
                if k > 0 {
                    self.flush(&sector, &points[..k], votes, &mut cell_of[..k]);
                }
                let s = table.beams[pt.idx].sector as usize;
                while self.sector_start.len() <= s {
                    self.sector_start.push(self.bins.len() as u32);
                }
                sector = Sector {
                    start: k,
                    stop: table.sector_end[s],
                    base: first.saturating_sub(LOCAL / 2),
                    touched: 0,
                    fits: true,
                };
            }
            let j = first.wrapping_sub(sector.base);
            let g = votes.g(pt);
            cell_of[k] = if first == last && j < LOCAL {
                // The usual case: one ring.
                self.local[j as usize] += g;
                self.local_points[j as usize] += 1;
                sector.touched |= 1 << j;
                j
            } else if first > last {
                NO_SLOT
            } else if first < last && j < LOCAL && last.wrapping_sub(sector.base) < LOCAL {
                for i in j..=last - sector.base {
                    self.local[i as usize] += g;
                    sector.touched |= 1 << i;
                }
                self.local_points[j as usize] += 1;
                self.multi.push(k as u32);
                j
            } else {
                sector.fits = false;
                NO_SLOT
            };
        }
        if n > 0 {
            self.flush(&sector, &points[..n], votes, &mut cell_of[..n]);
        }
    }

    /// Turns the sums of the sector of points `sector.start..` into cells in ring order (or,
    /// when its rings did not fit in `local`, builds it by [`Accumulator::sector_sorted`]) and
    /// turns each point's local slot in `cell_of` into its cell.
    fn flush(&mut self, sector: &Sector, points: &[Pt], votes: Votes, cell_of: &mut [u32]) {
        let span = sector.start..points.len();
        let mut touched = sector.touched;
        if !sector.fits {
            while touched != 0 {
                let j = touched.trailing_zeros() as usize;
                (self.local[j], self.local_points[j]) = (0.0, 0);
                touched &= touched - 1;
            }
            self.multi.clear();
            return self.sector_sorted(span, points, votes, cell_of);
        }
        while touched != 0 {
            let j = touched.trailing_zeros() as usize;
            touched &= touched - 1;
            self.local_cell[j] = self.bins.len() as u32;
            let value = std::mem::take(&mut self.local[j]);
            let (ring, kept) = (sector.base + j as u32, value > votes.criterion);
            let points = std::mem::take(&mut self.local_points[j]);
            if kept {
                self.top_ring = self.top_ring.max(ring);
            } else {
                self.loose += points;
            }
            self.bins.push(Bin {
                value,
                ring,
                points,
                kept,
            });
        }
        let local_cell = &self.local_cell;
        for c in &mut cell_of[span] {
            *c = local_cell[(*c).min(NO_SLOT) as usize];
        }
        // A point of several rings: its first cell when kept, else its last when kept.
        for &k in &self.multi {
            let first = cell_of[k as usize] as usize;
            let last = first + (self.rings[k as usize].1 - self.rings[k as usize].0) as usize;
            if !self.bins[first].kept && self.bins[last].kept {
                cell_of[k as usize] = last as u32;
                self.bins[first].points -= 1;
                self.bins[last].points += 1;
            }
        }
        self.multi.clear();
    }

    /// Builds a sector (points `span`) whose rings lie far apart: its distinct rings sorted,
    /// each point's cells found among them.
    fn sector_sorted(
        &mut self,
        span: Range<usize>,
        points: &[Pt],
        votes: Votes,
        cell_of: &mut [u32],
    ) {
        self.distinct.clear();
        for &(lo, hi) in &self.rings[span.clone()] {
            if lo <= hi {
                self.distinct.extend(lo..=hi);
            }
        }
        self.distinct.sort_unstable();
        self.distinct.dedup();
        let base = self.bins.len();
        self.bins.extend(self.distinct.iter().map(|&ring| Bin {
            value: 0.0,
            ring,
            points: 0,
            kept: false,
        }));
        let position = |d: &[u32], ring: u32| base + d.binary_search(&ring).unwrap_or(0);
        for (&(lo, hi), pt) in self.rings[span.clone()].iter().zip(&points[span.clone()]) {
            if lo <= hi {
                let g = votes.g(pt);
                let first = position(&self.distinct, lo);
                for bin in &mut self.bins[first..=first + (hi - lo) as usize] {
                    bin.value += g;
                }
            }
        }
        for bin in &mut self.bins[base..] {
            bin.kept = bin.value > votes.criterion;
            if bin.kept {
                self.top_ring = self.top_ring.max(bin.ring);
            }
        }
        for (c, &(lo, hi)) in cell_of[span.clone()].iter_mut().zip(&self.rings[span]) {
            *c = VOID;
            if lo <= hi {
                let first = position(&self.distinct, lo);
                let last = first + (hi - lo) as usize;
                let cell = if self.bins[last].kept && !self.bins[first].kept {
                    last
                } else {
                    first
                };
                self.bins[cell].points += 1;
                self.loose += u32::from(!self.bins[cell].kept);
                *c = cell as u32;
            }
        }
    }

    /// Cells of sector `k` (empty past the last sector).
    pub(crate) fn sector_cells(&self, k: usize) -> Range<usize> {
        if k + 1 >= self.sector_start.len() {
            return 0..0;
        }
        self.sector_start[k] as usize..self.sector_start[k + 1] as usize
    }

    /// Every cell, sector by sector in ring order.
    pub(crate) fn cells(&self) -> Vec<Cell> {
        let mut out = Vec::with_capacity(self.len());
        for k in 0..self.sector_start.len().saturating_sub(1) {
            out.extend(self.bins[self.sector_cells(k)].iter().map(|b| Cell {
                sector: k as u32,
                ring: b.ring,
                value: b.value,
                kept: b.kept,
            }));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rings by the library's `ceil` and `floor`, clamped as documented.
    fn slow(x: f64, a: f64, inv: f64) -> (u32, u32) {
        let clamp = |v: f64| {
            if v.is_nan() {
                0.0
            } else {
                v.clamp(0.0, MAX_RING)
            }
        };
        (
            clamp((x - a) * inv).ceil() as u32,
            clamp((x + a) * inv).floor() as u32,
        )
    }

    #[test]
    fn ring_span_matches_ceil_and_floor() {
        let (a, inv) = (0.015, 1.0 / 0.03);
        let mut xs = vec![
            0.0,
            -0.0,
            -1.0,
            0.015,
            0.045,
            1e300,
            -1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            MAX_RING * 0.03,
        ];
        // Around every ring boundary up to 40 m, and in between.
        for k in 0..1400 {
            let b = f64::from(k) * 0.03 + 0.015;
            xs.extend([b, b.next_up(), b.next_down(), b + 0.01, b - 0.007]);
        }
        for x in xs {
            assert_eq!(ring_span(x, a, inv), slow(x, a, inv), "{x}");
            assert_eq!(ring_span(x, 0.04, inv), slow(x, 0.04, inv), "{x}");
            assert_eq!(ring_span(x, 0.001, 7.0), slow(x, 0.001, 7.0), "{x}");
        }
    }
}
