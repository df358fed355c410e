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

/// A vote of one point into one cell.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Vote {
    pub(crate) ring: u32,
    pub(crate) point: u32,
}

/// The sparse accumulator.
#[derive(Debug, Default, Clone)]
pub(crate) struct Accumulator {
    pub(crate) cells: Vec<Cell>,
    /// For each sector `k`, cells `sector_start[k]..sector_start[k + 1]` (ring order).
    pub(crate) sector_start: Vec<u32>,
    /// For each point, its first and last cell (points on a ring boundary vote twice, and
    /// their two cells are always adjacent in the same sector).
    pub(crate) point_cells: Vec<(u32, u32)>,
    votes: Vec<Vote>,
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
    /// Builds the accumulator of `points` (valid points in beam order) and applies the
    /// criterion.
    pub(crate) fn build(&mut self, points: &[ScanPoint], table: &BeamTable, p: &HoughSplitParams) {
        self.cells.clear();
        self.sector_start.clear();
        self.point_cells.clear();
        self.point_cells.resize(points.len(), (u32::MAX, u32::MAX));
        let dd = p.ring_step;
        let a = p.window;
        let mut start = 0usize;
        let mut next_sector = 0u32;
        while start < points.len() {
            let sector = table.beams[points[start].index].sector;
            let mut end = start + 1;
            while end < points.len() && table.beams[points[end].index].sector == sector {
                end += 1;
            }
            // Sectors with no points have no cells.
            while next_sector <= sector {
                self.sector_start.push(self.cells.len() as u32);
                next_sector += 1;
            }
            self.votes.clear();
            for (pi, sp) in points.iter().enumerate().take(end).skip(start) {
                let x = sp.range * table.beams[sp.index].cos_to_sector;
                let (lo, hi) = (ceil_ring((x - a) / dd), floor_ring((x + a) / dd));
                let mut j = lo;
                while j <= hi {
                    self.votes.push(Vote {
                        ring: j,
                        point: pi as u32,
                    });
                    j += 1;
                }
            }
            // A sector holds a handful of votes, in beam order: sorted by (ring, point), the
            // order in which cells are made and summed. A surface that comes nearer along
            // the sector gives them in falling ring order: reversed first, the insertion
            // sort then only swaps each point's own pair of rings.
            let key = |v: &Vote| (u64::from(v.ring) << 32) | u64::from(v.point);
            if let (Some(first), Some(last)) = (self.votes.first(), self.votes.last())
                && first.ring > last.ring
            {
                self.votes.reverse();
            }
            for i in 1..self.votes.len() {
                let mut k = i;
                while k > 0 && key(&self.votes[k - 1]) > key(&self.votes[k]) {
                    self.votes.swap(k - 1, k);
                    k -= 1;
                }
            }
            let mut vi = 0;
            while vi < self.votes.len() {
                let ring = self.votes[vi].ring;
                let cell = self.cells.len() as u32;
                let mut value = 0.0;
                while vi < self.votes.len() && self.votes[vi].ring == ring {
                    let pi = self.votes[vi].point as usize;
                    value += match p.weight {
                        Weight::One => 1.0,
                        Weight::Range => points[pi].range,
                    };
                    let pc = &mut self.point_cells[pi];
                    if pc.0 == u32::MAX {
                        pc.0 = cell;
                    }
                    pc.1 = cell;
                    vi += 1;
                }
                self.cells.push(Cell {
                    sector,
                    ring,
                    value,
                    kept: value > p.criterion,
                });
            }
            start = end;
        }
        self.sector_start.push(self.cells.len() as u32);
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
