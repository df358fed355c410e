//! Step 1-2: the g-weighted accumulator over (range ring, beam sector) cells and the
//! noise-cancelling criterion (paper eq. 1-3, read as in ALGORITHM section 1).
//!
//! Each valid point votes only in the column of its own beam sector, and there in every ring
//! whose window `|r cos(phi - gamma_k) - d_j| <= a` it meets. The grid is sparse: only cells
//! that received a vote exist, stored sector by sector in ring order.

use super::params::{HoughSplitParams, Weight};
use crate::scan::ScanPoint;

/// Beam geometry of one scan shape, cached between scans of the same shape.
#[derive(Debug, Default, Clone)]
pub(crate) struct BeamTable {
    key: Option<(u64, u64, usize, u64)>,
    /// Per beam: cos(phi), sin(phi), sector index, cos(phi - gamma_sector).
    pub(crate) beams: Vec<Beam>,
    /// Number of sectors.
    pub(crate) sectors: usize,
}

#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Beam {
    pub(crate) cos: f64,
    pub(crate) sin: f64,
    pub(crate) sector: u32,
    pub(crate) cos_to_sector: f64,
}

impl BeamTable {
    /// Makes sure the table describes beams of `angle_min + i * increment`, `i < n`.
    pub(crate) fn prepare(&mut self, angle_min: f64, increment: f64, n: usize, sector_step: f64) {
        let key = (
            angle_min.to_bits(),
            increment.to_bits(),
            n,
            sector_step.to_bits(),
        );
        if self.key == Some(key) {
            return;
        }
        self.key = Some(key);
        self.beams.clear();
        self.beams.reserve(n);
        let sign = if increment < 0.0 { -1.0 } else { 1.0 };
        let step = increment.abs();
        let mut sectors = 0usize;
        for i in 0..n {
            let phi = angle_min + i as f64 * increment;
            let (sin, cos) = phi.sin_cos();
            // Sector in the scan's own field of view, counted from the first beam. The tiny
            // epsilon keeps beams that fall exactly on a boundary in the upper sector despite
            // rounding.
            let k_f = ((i as f64 * step) / sector_step + 1e-9).floor();
            let k = if k_f.is_finite() && k_f >= 0.0 {
                (k_f as usize).min(n)
            } else {
                0
            };
            let gamma = angle_min + sign * (k as f64 + 0.5) * sector_step;
            let cos_to_sector = (phi - gamma).cos();
            sectors = sectors.max(k + 1);
            self.beams.push(Beam {
                cos,
                sin,
                sector: k as u32,
                cos_to_sector: if cos_to_sector.is_finite() {
                    cos_to_sector
                } else {
                    1.0
                },
            });
        }
        self.sectors = sectors;
    }
}

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

/// The sparse accumulator.
#[derive(Debug, Default, Clone)]
pub(crate) struct Accumulator {
    pub(crate) cells: Vec<Cell>,
    /// For each sector `k`, cells `sector_start[k]..sector_start[k + 1]` (ring order).
    pub(crate) sector_start: Vec<u32>,
    /// For each point, its first and last cell (points on a ring boundary vote twice, and
    /// their two cells are always adjacent in the same sector).
    pub(crate) point_cells: Vec<(u32, u32)>,
    /// Where each of a sector's cells goes when the sector is put in ring order.
    order: Vec<u32>,
}

const MAX_RING: f64 = (u32::MAX / 4) as f64;

/// `floor(v)` clamped to `0..=MAX_RING` (NaN gives 0), without a libm call.
#[inline]
fn floor_ring(v: f64) -> u32 {
    let c = v.clamp(0.0, MAX_RING);
    if c.is_nan() { 0 } else { c as u32 }
}

/// `ceil(v)` clamped to `0..=MAX_RING` (NaN gives 0), without a libm call.
#[inline]
fn ceil_ring(v: f64) -> u32 {
    let c = v.clamp(0.0, MAX_RING);
    if c.is_nan() {
        return 0;
    }
    let t = c as u32;
    if f64::from(t) < c { t + 1 } else { t }
}

impl Accumulator {
    /// Builds the accumulator of `points` (valid points in beam order; those marked in
    /// `isolated` vote nowhere) and applies the criterion.
    ///
    /// A sector's points are consecutive in beam order, so each sector is built in one pass:
    /// a point adds its weight to the cell of each ring its window meets (a sector holds a
    /// handful of cells, found by a short linear search), then the sector's cells are put in
    /// ring order. A cell's value is summed in point order, as the paper's sum over `i`.
    pub(crate) fn build(
        &mut self,
        points: &[ScanPoint],
        isolated: &[bool],
        table: &BeamTable,
        p: &HoughSplitParams,
    ) {
        self.cells.clear();
        self.sector_start.clear();
        self.point_cells.clear();
        let inv = 1.0 / p.ring_step;
        let a = p.window;
        let weight_one = p.weight == Weight::One;
        let mut start = 0usize;
        let mut next_sector = 0u32;
        while start < points.len() {
            let sector = table.beams[points[start].index].sector;
            // Sectors with no points have no cells.
            while next_sector <= sector {
                self.sector_start.push(self.cells.len() as u32);
                next_sector += 1;
            }
            let first = self.cells.len();
            let mut end = start;
            while let Some(sp) = points.get(end) {
                let beam = &table.beams[sp.index];
                if beam.sector != sector {
                    break;
                }
                if isolated.get(end).copied().unwrap_or(false) {
                    // A mixed pixel or spike votes nowhere: it is removed.
                    self.point_cells.push((u32::MAX, u32::MAX));
                    end += 1;
                    continue;
                }
                let x = sp.range * beam.cos_to_sector;
                let (lo, hi) = (ceil_ring((x - a) * inv), floor_ring((x + a) * inv));
                let g = if weight_one { 1.0 } else { sp.range };
                let mut pc = (u32::MAX, u32::MAX);
                let mut j = lo;
                while j <= hi {
                    let c = match self.cells[first..].iter().position(|c| c.ring == j) {
                        Some(k) => first + k,
                        None => {
                            self.cells.push(Cell {
                                sector,
                                ring: j,
                                value: 0.0,
                                kept: false,
                            });
                            self.cells.len() - 1
                        }
                    };
                    self.cells[c].value += g;
                    if pc.0 == u32::MAX {
                        pc.0 = c as u32;
                    }
                    pc.1 = c as u32;
                    j += 1;
                }
                self.point_cells.push(pc);
                end += 1;
            }
            self.order_sector(first, start..end);
            for c in &mut self.cells[first..] {
                c.kept = c.value > p.criterion;
            }
            start = end;
        }
        self.sector_start.push(self.cells.len() as u32);
    }

    /// Puts the cells from `first` on (one sector's) in ring order, and renumbers the cells
    /// of that sector's points `points`.
    fn order_sector(&mut self, first: usize, points: std::ops::Range<usize>) {
        let cells = &mut self.cells[first..];
        if cells.windows(2).all(|w| w[0].ring < w[1].ring) {
            return;
        }
        // Insertion sort of a handful of cells, remembering where each went.
        self.order.clear();
        self.order.extend(0..cells.len() as u32);
        for i in 1..cells.len() {
            let mut k = i;
            while k > 0 && cells[k - 1].ring > cells[k].ring {
                cells.swap(k - 1, k);
                self.order.swap(k - 1, k);
                k -= 1;
            }
        }
        // order[new] = old; invert it into a map old -> new.
        let n = self.order.len();
        self.order.resize(2 * n, 0);
        for new in 0..n {
            let old = self.order[new] as usize;
            self.order[n + old] = new as u32;
        }
        let map = |c: u32| first as u32 + self.order[n + c as usize - first];
        for pc in &mut self.point_cells[points] {
            if pc.0 != u32::MAX {
                *pc = (map(pc.0), map(pc.1));
            }
        }
    }

    /// Cells of sector `k` (empty past the last sector).
    pub(crate) fn sector_cells(&self, k: usize) -> std::ops::Range<usize> {
        if k + 1 >= self.sector_start.len() {
            return 0..0;
        }
        self.sector_start[k] as usize..self.sector_start[k + 1] as usize
    }

    /// Fills `out` with a kept cell of each point, or `NONE` when the point lies in no kept
    /// cell (it is removed as noise).
    pub(crate) fn kept_cells(&self, out: &mut Vec<u32>) {
        out.clear();
        out.extend(self.point_cells.iter().map(|&(a, b)| {
            if a == u32::MAX {
                NONE
            } else if self.cells[a as usize].kept {
                a
            } else if self.cells[b as usize].kept {
                b
            } else {
                NONE
            }
        }));
    }
}
