//! Step 0: the valid beams of a scan as points, stored as parallel arrays (beam index, range,
//! x, y), and the beam geometry they are computed from, cached per scan shape.

use crate::math::Point2;
use crate::scan::{RangeWindow, Scan};

/// Beam geometry of one scan shape, cached between scans of the same shape: per beam
/// `cos(phi)`, `sin(phi)`, the beam's sector and `cos(phi - gamma_sector)`.
#[derive(Debug, Default, Clone)]
pub(crate) struct BeamTable {
    key: Option<(u64, u64, usize, u64)>,
    pub(crate) cos: Vec<f64>,
    pub(crate) sin: Vec<f64>,
    pub(crate) sector: Vec<u32>,
    pub(crate) cos_to_sector: Vec<f64>,
    /// Per sector: the first beam after it.
    pub(crate) sector_end: Vec<usize>,
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
        self.cos.clear();
        self.sin.clear();
        self.sector.clear();
        self.cos_to_sector.clear();
        self.sector_end.clear();
        let sign = if increment < 0.0 { -1.0 } else { 1.0 };
        let step = increment.abs();
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
            self.cos.push(cos);
            self.sin.push(sin);
            self.sector.push(k as u32);
            // Sectors are non-decreasing along the beams.
            self.sector_end.resize(k + 1, i);
            self.sector_end[k] = i + 1;
            self.cos_to_sector.push(if cos_to_sector.is_finite() {
                cos_to_sector
            } else {
                1.0
            });
        }
    }
}

/// The valid points of a scan in beam order, as parallel arrays: point `k` is beam `idx[k]`
/// at range `range[k]`, at `(x[k], y[k])` in the sensor frame. The arrays keep their length
/// between scans; `n` points of them are in use.
#[derive(Debug, Default, Clone)]
pub(crate) struct Points {
    n: usize,
    idx: Vec<usize>,
    range: Vec<f64>,
    x: Vec<f64>,
    y: Vec<f64>,
}

impl Points {
    /// Number of points.
    pub(crate) fn len(&self) -> usize {
        self.n
    }

    /// Beam indices.
    pub(crate) fn idx(&self) -> &[usize] {
        &self.idx[..self.n]
    }

    /// Ranges, m.
    pub(crate) fn range(&self) -> &[f64] {
        &self.range[..self.n]
    }

    /// x coordinates, m.
    pub(crate) fn x(&self) -> &[f64] {
        &self.x[..self.n]
    }

    /// y coordinates, m.
    pub(crate) fn y(&self) -> &[f64] {
        &self.y[..self.n]
    }

    /// Removes every point and makes room for `capacity` points.
    pub(crate) fn reset(&mut self, capacity: usize) {
        self.n = 0;
        if self.idx.len() < capacity {
            self.idx.resize(capacity, 0);
            self.range.resize(capacity, 0.0);
            self.x.resize(capacity, 0.0);
            self.y.resize(capacity, 0.0);
        }
    }

    /// Points `start..end` as slices.
    pub(crate) fn slice(&self, start: usize, end: usize) -> Seg<'_> {
        Seg {
            idx: &self.idx()[start..end],
            range: &self.range()[start..end],
            x: &self.x()[start..end],
            y: &self.y()[start..end],
        }
    }

    /// The whole arrays (room made by [`Points::reset`]) to write points into, and the
    /// number of points in use, to update after writing.
    pub(crate) fn parts_mut(&mut self) -> PartsMut<'_> {
        PartsMut {
            idx: &mut self.idx,
            range: &mut self.range,
            x: &mut self.x,
            y: &mut self.y,
            n: &mut self.n,
        }
    }

    /// Fills the store with the beams of `scan` whose range is valid in `window` and at least
    /// `min_range`, and whose point is finite, using the beam geometry `table`.
    ///
    /// Every beam is written and the count advanced only for valid ones, so the loop has no
    /// branch on the data.
    pub(crate) fn fill(
        &mut self,
        scan: &Scan,
        table: &BeamTable,
        window: RangeWindow,
        min_range: f64,
    ) {
        let n = scan.ranges.len().min(table.cos.len());
        self.reset(n);
        if window.min.is_nan() || window.max.is_nan() || min_range.is_nan() {
            return;
        }
        // RangeWindow::contains and the minimum range as two comparisons: `r >= lo` implies
        // `r > 0`, `r <= hi` implies a finite `r`; NaN fails both.
        let lo = window.min.max(min_range).max(f64::from_bits(1));
        let hi = window.max.min(f64::MAX);
        let (ranges, cos, sin) = (&scan.ranges[..n], &table.cos[..n], &table.sin[..n]);
        let (idx, range) = (&mut self.idx[..n], &mut self.range[..n]);
        let (xs, ys) = (&mut self.x[..n], &mut self.y[..n]);
        let mut count = 0usize;
        for i in 0..n {
            let r = ranges[i];
            let (x, y) = (r * cos[i], r * sin[i]);
            // A finite point: `v * 0` is 0 for finite `v`, NaN otherwise.
            let valid = (r >= lo) & (r <= hi) & (x * 0.0 == 0.0) & (y * 0.0 == 0.0);
            idx[count] = i;
            range[count] = r;
            xs[count] = x;
            ys[count] = y;
            count += usize::from(valid);
        }
        self.n = count;
    }
}

#[cfg(test)]
impl Points {
    /// Points at `xy`, beam `k` for the `k`-th, their ranges from the origin.
    pub(crate) fn from_xy(xy: &[(f64, f64)]) -> Self {
        let mut p = Self::default();
        for (i, &(x, y)) in xy.iter().enumerate() {
            p.idx.push(i);
            p.range.push((x * x + y * y).sqrt());
            p.x.push(x);
            p.y.push(y);
        }
        p.n = xy.len();
        p
    }
}

/// The arrays of [`Points`] open for writing.
pub(crate) struct PartsMut<'a> {
    pub(crate) idx: &'a mut [usize],
    pub(crate) range: &'a mut [f64],
    pub(crate) x: &'a mut [f64],
    pub(crate) y: &'a mut [f64],
    pub(crate) n: &'a mut usize,
}

/// A run of points (one data segment) as parallel slices of equal length.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Seg<'a> {
    pub(crate) idx: &'a [usize],
    pub(crate) range: &'a [f64],
    pub(crate) x: &'a [f64],
    pub(crate) y: &'a [f64],
}

impl Seg<'_> {
    /// Number of points.
    pub(crate) fn len(&self) -> usize {
        self.idx.len()
    }

    /// Point `k`.
    #[inline]
    pub(crate) fn point(&self, k: usize) -> Point2 {
        Point2::new(self.x[k], self.y[k])
    }
}
