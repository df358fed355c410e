//! The growable grids of the map.

use laserlines::math::Point2;

use super::{GROW_STEP, MAX_EXTENT};
use crate::raster::floor_i64;

/// A growable grid over the map frame; cell `(i, j)` spans `origin + cell * [i, i + 1] x
/// [j, j + 1]`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Grid<T> {
    pub(crate) origin: Point2,
    pub(crate) cell: f64,
    pub(crate) cols: usize,
    pub(crate) rows: usize,
    pub(crate) cells: Vec<T>,
    pub(super) fill: T,
}

impl<T: Copy> Grid<T> {
    pub(super) fn new(cell: f64, fill: T) -> Self {
        Self {
            origin: Point2::origin(),
            cell,
            cols: 0,
            rows: 0,
            cells: Vec::new(),
            fill,
        }
    }

    /// `p` in continuous cell units (cell `(i, j)` spans `[i, i + 1] x [j, j + 1]`).
    pub(crate) fn to_cells(&self, p: Point2) -> (f64, f64) {
        (
            (p.x - self.origin.x) / self.cell,
            (p.y - self.origin.y) / self.cell,
        )
    }

    /// The index of cell `(i, j)`, if it is in the grid.
    pub(crate) fn index_of(&self, i: i64, j: i64) -> Option<usize> {
        (i >= 0 && j >= 0 && i < self.cols as i64 && j < self.rows as i64)
            .then(|| j as usize * self.cols + i as usize)
    }

    /// The index of the cell holding `p`, if any.
    pub(crate) fn index(&self, p: Point2) -> Option<usize> {
        let (u, v) = self.to_cells(p);
        if !(u.is_finite() && v.is_finite()) {
            return None;
        }
        self.index_of(floor_i64(u), floor_i64(v))
    }

    /// The centre of cell `index`, map frame.
    pub(crate) fn centre(&self, index: usize) -> Point2 {
        let (i, j) = (index % self.cols.max(1), index / self.cols.max(1));
        Point2::new(
            self.origin.x + (i as f64 + 0.5) * self.cell,
            self.origin.y + (j as f64 + 0.5) * self.cell,
        )
    }

    /// Grows the grid to hold the box `lo..hi` (map frame), in whole [`GROW_STEP`]s on a
    /// lattice through the map origin; growth beyond [`MAX_EXTENT`] is refused (the grid
    /// stays as it is).
    pub(crate) fn ensure(&mut self, lo: Point2, hi: Point2) {
        if !(lo.x.is_finite() && lo.y.is_finite() && hi.x.is_finite() && hi.y.is_finite()) {
            return;
        }
        let have_lo = self.origin;
        let have_hi = Point2::new(
            self.origin.x + self.cols as f64 * self.cell,
            self.origin.y + self.rows as f64 * self.cell,
        );
        let empty = self.cols == 0 || self.rows == 0;
        if !empty
            && lo.x >= have_lo.x
            && lo.y >= have_lo.y
            && hi.x <= have_hi.x
            && hi.y <= have_hi.y
        {
            return;
        }
        let snap_lo = |v: f64| (v / GROW_STEP).floor() * GROW_STEP;
        let snap_hi = |v: f64| (v / GROW_STEP).ceil() * GROW_STEP;
        let (mut new_lo, mut new_hi) = (
            Point2::new(snap_lo(lo.x), snap_lo(lo.y)),
            Point2::new(snap_hi(hi.x), snap_hi(hi.y)),
        );
        if !empty {
            new_lo = Point2::new(new_lo.x.min(have_lo.x), new_lo.y.min(have_lo.y));
            new_hi = Point2::new(new_hi.x.max(have_hi.x), new_hi.y.max(have_hi.y));
        }
        if new_hi.x - new_lo.x > MAX_EXTENT || new_hi.y - new_lo.y > MAX_EXTENT {
            return;
        }
        let cols = ((new_hi.x - new_lo.x) / self.cell).round() as usize;
        let rows = ((new_hi.y - new_lo.y) / self.cell).round() as usize;
        let mut cells = vec![self.fill; cols * rows];
        if !empty {
            let di = ((have_lo.x - new_lo.x) / self.cell).round() as usize;
            let dj = ((have_lo.y - new_lo.y) / self.cell).round() as usize;
            for j in 0..self.rows {
                let from = j * self.cols;
                let to = (j + dj) * cols + di;
                cells[to..to + self.cols].copy_from_slice(&self.cells[from..from + self.cols]);
            }
        }
        self.origin = new_lo;
        self.cols = cols;
        self.rows = rows;
        self.cells = cells;
    }
}
