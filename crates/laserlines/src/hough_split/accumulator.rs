//! Step 1-2: the g-weighted accumulator over (range ring, beam sector) cells and the
//! noise-cancelling criterion (paper eq. 1-3, read as in ALGORITHM section 1).
//!
//! Each valid point votes only in the column of its own beam sector, and there in every ring
//! whose window `|r cos(phi - gamma_k) - d_j| <= a` it meets. The grid is sparse: only cells
//! that received a vote exist, stored sector by sector in ring order, as parallel arrays.

use super::params::{HoughSplitParams, Weight};
use std::ops::Range;

use super::points::{BeamTable, Points};

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

/// Marks a point without a kept cell.
pub(crate) const NONE: u32 = u32::MAX;

/// Rings a sector may span for its cells to be summed in the local table.
const LOCAL: u32 = 64;

/// A cell as the pipeline keeps it (its sector is implied by its position).
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Bin {
    /// Weighted value `C(d, gamma)`.
    pub(crate) value: f64,
    /// Ring index.
    pub(crate) ring: u32,
    /// Above the criterion.
    pub(crate) kept: bool,
}

/// The sector being summed in [`Accumulator::build`].
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

/// The sparse accumulator: the cells of sector `k` are
/// `bins[sector_start[k]..sector_start[k + 1]]`, in ring order.
#[derive(Debug, Clone)]
pub(crate) struct Accumulator {
    pub(crate) bins: Vec<Bin>,
    pub(crate) sector_start: Vec<u32>,
    /// Per point: the first and last ring its window meets.
    rings: Vec<(u32, u32)>,
    /// A sector's values by ring, from its base ring on (all zero between sectors).
    local: [f64; LOCAL as usize],
    /// The kept cell of each ring of `local`, or `NONE`.
    local_kept: [u32; LOCAL as usize],
    /// The distinct rings of a sector too deep for `local`.
    distinct: Vec<u32>,
}

impl Default for Accumulator {
    fn default() -> Self {
        Self {
            bins: Vec::new(),
            sector_start: Vec::new(),
            rings: Vec::new(),
            local: [0.0; LOCAL as usize],
            local_kept: [NONE; LOCAL as usize],
            distinct: Vec::new(),
        }
    }
}

/// What a sector's points vote with.
struct Votes<'a> {
    /// Ranges of the points.
    range: &'a [f64],
    /// `g = 1` rather than `g = r`.
    weight_one: bool,
    /// The noise-cancelling criterion.
    criterion: f64,
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
    /// Number of cells.
    pub(crate) fn len(&self) -> usize {
        self.bins.len()
    }

    /// Builds the accumulator of `points` (valid points in beam order), applies the criterion
    /// and fills `cell_of` with a kept cell of each point, or [`NONE`] when the point lies in
    /// no kept cell (it is removed as noise): the first of its cells when that is kept, else
    /// the last.
    ///
    /// A sector's points are consecutive in beam order, so each sector is built in one pass
    /// over them: a point adds its weight to the cell of each ring its window meets, summed
    /// in point order as the paper's sum over `i`; the sector's cells then come out in ring
    /// order.
    pub(crate) fn build(
        &mut self,
        points: &Points,
        table: &BeamTable,
        p: &HoughSplitParams,
        cell_of: &mut Vec<u32>,
    ) {
        self.bins.clear();
        self.sector_start.clear();
        let n = points.len();
        cell_of.clear();
        cell_of.resize(n, NONE);
        self.rings.resize(n, (0, 0));
        let (inv, a) = (1.0 / p.ring_step, p.window);
        let (idx, range) = (points.idx(), points.range());
        let votes = Votes {
            range,
            weight_one: p.weight == Weight::One,
            criterion: p.criterion,
        };
        let mut sector = Sector {
            start: 0,
            stop: 0,
            base: 0,
            touched: 0,
            fits: true,
        };
        for k in 0..n {
            let (i, r) = (idx[k], range[k]);
            let (lo, hi) = ring_span(r * table.cos_to_sector[i], a, inv);
            self.rings[k] = (lo, hi);
            if i >= sector.stop {
                if k > 0 {
                    self.flush(&sector, k, &votes, cell_of);
                }
                let s = table.sector[i] as usize;
                while self.sector_start.len() <= s {
                    self.sector_start.push(self.bins.len() as u32);
                }
                sector = Sector {
                    start: k,
                    stop: table.sector_end[s],
                    base: lo.saturating_sub(LOCAL / 2),
                    touched: 0,
                    fits: true,
                };
            }
            if lo > hi {
                continue;
            }
            let (j, last) = (lo.wrapping_sub(sector.base), hi.wrapping_sub(sector.base));
            if j >= LOCAL || last >= LOCAL {
                sector.fits = false;
                continue;
            }
            let g = if votes.weight_one { 1.0 } else { r };
            self.local[j as usize] += g;
            sector.touched |= 1 << j;
            for j in j + 1..=last {
                self.local[j as usize] += g;
                sector.touched |= 1 << j;
            }
        }
        if n > 0 {
            self.flush(&sector, n, &votes, cell_of);
        }
        self.sector_start.push(self.bins.len() as u32);
    }

    /// Turns the sums of the sector of points `sector.start..end` into cells in ring order
    /// (or, when its rings did not fit in `local`, builds it by [`Accumulator::sector_sorted`])
    /// and notes each point's kept cell.
    fn flush(&mut self, sector: &Sector, end: usize, votes: &Votes, cell_of: &mut [u32]) {
        let span = sector.start..end;
        let mut touched = sector.touched;
        if !sector.fits {
            while touched != 0 {
                self.local[touched.trailing_zeros() as usize] = 0.0;
                touched &= touched - 1;
            }
            return self.sector_sorted(span, votes, cell_of);
        }
        while touched != 0 {
            let j = touched.trailing_zeros() as usize;
            touched &= touched - 1;
            let value = std::mem::take(&mut self.local[j]);
            let kept = value > votes.criterion;
            self.local_kept[j] = if kept { self.bins.len() as u32 } else { NONE };
            self.bins.push(Bin {
                value,
                ring: sector.base + j as u32,
                kept,
            });
        }
        // A point's kept cell: its first cell when kept, else its last when kept.
        let (base, local_kept) = (sector.base, &self.local_kept);
        for (c, &(lo, hi)) in cell_of[span.clone()].iter_mut().zip(&self.rings[span]) {
            if lo <= hi {
                let first = local_kept[((lo - base) as usize).min(LOCAL as usize - 1)];
                let last = local_kept[((hi - base) as usize).min(LOCAL as usize - 1)];
                *c = if first != NONE { first } else { last };
            }
        }
    }

    /// Builds a sector (points `span`) whose rings lie far apart: its distinct rings sorted,
    /// each point's cells found among them.
    fn sector_sorted(&mut self, span: Range<usize>, votes: &Votes, cell_of: &mut [u32]) {
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
            kept: false,
        }));
        let position = |d: &[u32], ring: u32| base + d.binary_search(&ring).unwrap_or(0);
        let range = &votes.range[span.clone()];
        for (&(lo, hi), &r) in self.rings[span.clone()].iter().zip(range) {
            if lo <= hi {
                let g = if votes.weight_one { 1.0 } else { r };
                let first = position(&self.distinct, lo);
                for bin in &mut self.bins[first..=first + (hi - lo) as usize] {
                    bin.value += g;
                }
            }
        }
        for bin in &mut self.bins[base..] {
            bin.kept = bin.value > votes.criterion;
        }
        for (c, &(lo, hi)) in cell_of[span.clone()].iter_mut().zip(&self.rings[span]) {
            if lo <= hi {
                let first = position(&self.distinct, lo);
                let last = first + (hi - lo) as usize;
                *c = if self.bins[first].kept {
                    first as u32
                } else if self.bins[last].kept {
                    last as u32
                } else {
                    NONE
                };
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
