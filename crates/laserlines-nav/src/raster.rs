//! Scan-line filling of a scan's fan: the cells whose centre lies inside a polygon.
//!
//! Shared by the ground-truth coverage grid and the robot's own map: a scan sweeps the fan
//! from the laser through the end points of consecutive beams; its cells are found row by
//! row from the polygon's crossings of the rows' centre lines, in time proportional to the
//! polygon's edges plus the cells filled (where walking every beam through the grid costs
//! its length in cells, beam after beam over the same cells near the laser).

/// Reusable scratch for [`FanRaster::fill`].
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct FanRaster {
    /// The polygon's crossings of the rows' centre lines, `(row - first row, x)`.
    crossings: Vec<(u32, f32)>,
}

impl FanRaster {
    /// Calls `span(row, first, last)` for every run of cells of a `cols` x `rows` grid whose
    /// centre `(i + 0.5, j + 0.5)` lies inside the closed polygon `poly` (cell units,
    /// even-odd rule); `first..=last` are column indices of row `row`. Runs of one row come
    /// in increasing column order and never overlap.
    pub(crate) fn fill(
        &mut self,
        poly: &[(f64, f64)],
        cols: usize,
        rows: usize,
        mut span: impl FnMut(usize, usize, usize),
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
        let j0 = ((y_lo - 0.5).ceil() as i64).max(0);
        let j1 = ((y_hi - 0.5).ceil() as i64 - 1).min(rows as i64 - 1);
        if j0 > j1 {
            return;
        }
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
            let first = ((lo - 0.5).ceil() as i64).max(j0);
            let last = ((hi - 0.5).ceil() as i64 - 1).min(j1);
            let slope = (xb - xa) / (yb - ya);
            for j in first..=last {
                let yc = j as f64 + 0.5;
                crossings.push(((j - j0) as u32, (xa + (yc - ya) * slope) as f32));
            }
        }
        crossings.sort_unstable_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
        let cols = cols as i64;
        let mut k = 0;
        while k + 1 < crossings.len() {
            let (row, xa) = crossings[k];
            let (row_b, xb) = crossings[k + 1];
            if row_b != row {
                // An odd crossing left over (rounding at a vertex): skip it.
                k += 1;
                continue;
            }
            k += 2;
            // Cells whose centre x = i + 0.5 lies in [xa, xb).
            let i0 = ((f64::from(xa) - 0.5).ceil() as i64).max(0);
            let i1 = ((f64::from(xb) - 0.5).ceil() as i64 - 1).min(cols - 1);
            if i0 <= i1 {
                span((j0 + i64::from(row)) as usize, i0 as usize, i1 as usize);
            }
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
