//! Scan-line filling of a scan's fan: the cells whose centre lies inside a polygon.
//!
//! Shared by the robot's own map and the ground-truth coverage grid of `laserlines-harness`:
//! a scan sweeps the fan from the laser through the end points of consecutive beams; its
//! cells are found row by row from the polygon's crossings of the rows' centre lines, in
//! time proportional to the polygon's edges plus the cells filled (where walking every beam
//! through the grid costs its length in cells, beam after beam over the same cells near the
//! laser).

pub(crate) use laserlines::math::{ceil_i64, floor_i64};

/// The unit directions of a scan's beams in the laser frame, kept while the scan's
/// geometry stays the same: a loop over the beams then needs no chain of rotations.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BeamTable {
    key: (u64, u64, usize),
    dirs: Vec<laserlines::math::Vector2>,
}

impl BeamTable {
    /// The directions of `n` beams from `angle_min` by `increment` (rad).
    pub fn get(
        &mut self,
        angle_min: f64,
        increment: f64,
        n: usize,
    ) -> &[laserlines::math::Vector2] {
        let key = (angle_min.to_bits(), increment.to_bits(), n);
        if key != self.key || self.dirs.len() != n {
            self.key = key;
            self.dirs.clear();
            self.dirs.extend((0..n).map(|i| {
                let (s, c) = (angle_min + i as f64 * increment).sin_cos();
                laserlines::math::Vector2::new(c, s)
            }));
        }
        &self.dirs
    }
}

/// Reusable scratch for [`FanRaster::fill`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FanRaster {
    /// The polygon's crossings of the rows' centre lines, `(row - first row, x)`.
    crossings: Vec<(u32, f32)>,
    /// Where each row's crossings start in `xs` (a counting sort by row).
    starts: Vec<u32>,
    /// The crossings' x, row by row.
    xs: Vec<f32>,
    /// Scratch of the counting sort: the next free slot of each row.
    next: Vec<u32>,
}

impl FanRaster {
    /// Calls `span(row, first, last)` for every run of cells of a `cols` x `rows` grid whose
    /// centre `(i + 0.5, j + 0.5)` lies inside the closed polygon `poly` (cell units,
    /// even-odd rule); `first..=last` are column indices of row `row`. Runs of one row come
    /// in increasing column order and never overlap.
    pub fn fill(
        &mut self,
        poly: &[(f64, f64)],
        cols: usize,
        rows: usize,
        mut span_fn: impl FnMut(usize, usize, usize),
    ) {
        if poly.len() < 3 || cols == 0 || rows == 0 {
            return;
        }
        let (mut y_lo, mut y_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &(x, y) in poly {
            if !(x.is_finite() && y.is_finite()) {
                return;
            }
            y_lo = y_lo.min(y);
            y_hi = y_hi.max(y);
        }
        // Rows whose centre line y = j + 0.5 lies within the polygon's extent.
        let j0 = ceil_i64(y_lo - 0.5).max(0);
        let j1 = ceil_i64(y_hi - 0.5).saturating_sub(1).min(rows as i64 - 1);
        if j0 > j1 {
            return;
        }
        self.cross_rows(poly, j0, j1);
        let span = (j1 - j0 + 1) as usize;
        self.sort_by_row(span);
        let cols = cols as i64;
        for row in 0..span {
            let run = &mut self.xs[self.starts[row] as usize..self.starts[row + 1] as usize];
            // Insertion sort: a row of a fan has a handful of crossings.
            for k in 1..run.len() {
                let mut m = k;
                while m > 0 && run[m - 1] > run[m] {
                    run.swap(m - 1, m);
                    m -= 1;
                }
            }
            // Pairs of crossings bound the runs inside; an odd one left over (rounding at
            // a vertex) is skipped.
            for pair in run.chunks_exact(2) {
                // Cells whose centre x = i + 0.5 lies in [xa, xb).
                let i0 = ceil_i64(f64::from(pair[0]) - 0.5).max(0);
                let i1 = ceil_i64(f64::from(pair[1]) - 0.5)
                    .saturating_sub(1)
                    .min(cols - 1);
                if i0 <= i1 {
                    span_fn((j0 + row as i64) as usize, i0 as usize, i1 as usize);
                }
            }
        }
    }

    /// The polygon's crossings of the centre lines of rows `j0..=j1`, as `(row - j0, x)`.
    fn cross_rows(&mut self, poly: &[(f64, f64)], j0: i64, j1: i64) {
        let crossings = &mut self.crossings;
        crossings.clear();
        let mut prev = poly[poly.len() - 1];
        for &cur in poly {
            let ((xa, ya), (xb, yb)) = (prev, cur);
            prev = cur;
            if ya == yb {
                continue;
            }
            let (lo, hi) = if ya < yb { (ya, yb) } else { (yb, ya) };
            // Half-open in y, so that a vertex on a centre line counts once.
            let first = ceil_i64(lo - 0.5).max(j0);
            let last = ceil_i64(hi - 0.5).saturating_sub(1).min(j1);
            let slope = (xb - xa) / (yb - ya);
            for j in first..=last {
                let yc = j as f64 + 0.5;
                crossings.push(((j - j0) as u32, (xa + (yc - ya) * slope) as f32));
            }
        }
    }

    /// The crossings' x row by row into `xs` (a counting sort over `span` rows; row `r`'s
    /// are `xs[starts[r]..starts[r + 1]]`).
    fn sort_by_row(&mut self, span: usize) {
        let starts = &mut self.starts;
        starts.clear();
        starts.resize(span + 1, 0);
        for &(row, _) in &self.crossings {
            starts[row as usize + 1] += 1;
        }
        for k in 0..span {
            starts[k + 1] += starts[k];
        }
        let xs = &mut self.xs;
        xs.clear();
        xs.resize(self.crossings.len(), 0.0);
        let next = &mut self.next;
        next.clear();
        next.extend_from_slice(&starts[..span]);
        for &(row, x) in &self.crossings {
            let slot = &mut next[row as usize];
            xs[*slot as usize] = x;
            *slot += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_square_and_a_triangle() {
        let mut r = FanRaster::default();
        let mut cells = Vec::new();
        // The square [1, 3] x [1, 3]: centres 1.5 and 2.5 on both axes.
        let square = [(1.0, 1.0), (3.0, 1.0), (3.0, 3.0), (1.0, 3.0)];
        r.fill(&square, 10, 10, |j, a, b| {
            cells.extend((a..=b).map(|i| (i, j)))
        });
        assert_eq!(cells, vec![(1, 1), (2, 1), (1, 2), (2, 2)]);
        // Clipped to the grid.
        cells.clear();
        r.fill(&square, 2, 2, |j, a, b| {
            cells.extend((a..=b).map(|i| (i, j)))
        });
        assert_eq!(cells, vec![(1, 1)]);
        // The triangle below y = x / 2 up to x = 4: on row y = 0.5 the centres x = 1.5 ..
        // 3.5 are inside (x >= 1), on row y = 1.5 only x = 3.5 (x >= 3).
        cells.clear();
        let tri = [(0.0, 0.0), (4.0, 0.0), (4.0, 2.0)];
        r.fill(&tri, 10, 10, |j, a, b| {
            cells.extend((a..=b).map(|i| (i, j)))
        });
        assert_eq!(cells, vec![(1, 0), (2, 0), (3, 0), (3, 1)]);
        // Degenerate input fills nothing.
        cells.clear();
        r.fill(&[(0.0, 0.0), (1.0, 1.0)], 10, 10, |_, _, _| {
            cells.push((0, 0))
        });
        r.fill(
            &[(0.0, 0.0), (f64::NAN, 1.0), (3.0, 3.0)],
            10,
            10,
            |_, _, _| {
                cells.push((0, 0));
            },
        );
        assert!(cells.is_empty());
    }
}
