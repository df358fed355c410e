//! The full Hough accumulator: eq. (1) of the paper read literally, every point voting in every
//! direction column (ALGORITHM section 1 keeps it for the iterative Hough baseline of
//! Nguyen et al.).
//!
//! ```text
//! C(d_j, gamma_k) = sum_i w(x_i cos(gamma_k) + y_i sin(gamma_k) - d_j) * g_i
//! w(x) = 1 if |x| <= a else 0
//! ```
//!
//! The directions `gamma_k = k * angle_step` tile the half turn `[0, pi)`; the distances
//! `d_j = j * distance_step` are signed and cover `[-max_distance, max_distance]`, so every
//! point has a projection in every column and votes there (in one row, or two when it falls on
//! a row boundary with the default window `a = distance_step / 2`). A line with `d < 0` is the
//! line `(r, alpha) = (-d, gamma + pi)`; [`HoughPeak::polar`] converts.
//!
//! This is the expensive transform (points times columns votes) that the paper's
//! sector-restricted accumulator avoids; the iterative Hough extractor rebuilds it once per
//! extracted line, as Nguyen et al. do.
//!
//! ```
//! use laserlines::hough::{HoughAccumulator, HoughGrid};
//! use laserlines::math::Point2;
//! let mut acc = HoughAccumulator::new(HoughGrid::default()).unwrap();
//! // Ten points on the line x = 2 m (r = 2, alpha = 0).
//! for i in 0..10 {
//!     acc.vote(Point2::new(2.0, -0.5 + 0.1 * i as f64), 1.0);
//! }
//! let peak = acc.peak().unwrap();
//! assert_eq!(peak.value, 10.0);
//! let (r, alpha) = peak.polar();
//! assert!((r - 2.0).abs() <= 0.01 && alpha.abs() < 1e-9);
//! ```

use crate::hough_split::Weight;
use crate::math::{Point2, wrap_angle};
use crate::scan::ScanPoint;
use std::f64::consts::PI;

/// Largest number of cells an accumulator may have (32 MiB of `f64`).
pub const MAX_CELLS: usize = 1 << 22;

/// Errors in a [`HoughGrid`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum HoughError {
    /// A field that must be finite and positive is not.
    #[error("{field} must be finite and > 0, got {}", crate::scan::Short(*value))]
    NotPositive {
        /// field name
        field: &'static str,
        /// offending value
        value: f64,
    },
    /// The grid would have more than [`MAX_CELLS`] cells.
    #[error(
        "max_distance / distance_step and angle_step give a grid of {rows} x {columns} cells, \
         beyond the limit of {max} cells (raise distance_step or angle_step, or lower \
         max_distance)"
    )]
    TooManyCells {
        /// number of distance rows (saturated)
        rows: usize,
        /// number of direction columns (saturated)
        columns: usize,
        /// the limit, [`MAX_CELLS`]
        max: usize,
    },
}

/// The grid of a full Hough accumulator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HoughGrid {
    /// Row step `dd`, m. Default 0.02. Sensible: 0.01..0.10.
    pub distance_step: f64,
    /// Largest `|d|` represented, m; lines farther from the sensor cannot be found.
    /// Default 6.0 (the URG-04LX reaches 5.6 m). Sensible: the sensor's maximum range.
    pub max_distance: f64,
    /// Column step `dgamma`, rad, rounded so that a whole number of columns tiles `[0, pi)`.
    /// Default 1 deg. Sensible: 0.25..3 deg.
    pub angle_step: f64,
    /// Half-width `a` of the rectangular window `w`, m. Default 0.01 (`distance_step / 2`:
    /// each point votes in one row per column, two on a boundary). Sensible: 0.5..1.5 row
    /// steps.
    pub window: f64,
}

impl Default for HoughGrid {
    fn default() -> Self {
        Self {
            distance_step: 0.02,
            max_distance: 6.0,
            angle_step: 1.0_f64.to_radians(),
            window: 0.01,
        }
    }
}

impl HoughGrid {
    /// Checks every field and the size of the grid.
    ///
    /// # Errors
    /// A [`HoughError`] naming the first problem.
    pub fn validate(&self) -> Result<(), HoughError> {
        self.shape().map(|_| ())
    }

    /// `(half, rows, columns, actual angle step)` of a valid grid.
    fn shape(&self) -> Result<(usize, usize, usize, f64), HoughError> {
        for (field, value) in [
            ("distance_step", self.distance_step),
            ("max_distance", self.max_distance),
            ("angle_step", self.angle_step),
            ("window", self.window),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(HoughError::NotPositive { field, value });
            }
        }
        let half = (self.max_distance / self.distance_step).floor();
        let columns = (PI / self.angle_step).round().max(1.0);
        // Saturating conversions: the size check below rejects anything too large.
        let rows_f = 2.0 * half + 1.0;
        let too_big = rows_f * columns > MAX_CELLS as f64;
        let (rows, cols) = (
            rows_f.min(usize::MAX as f64) as usize,
            columns.min(usize::MAX as f64) as usize,
        );
        if too_big {
            return Err(HoughError::TooManyCells {
                rows,
                columns: cols,
                max: MAX_CELLS,
            });
        }
        Ok((half as usize, rows, cols, PI / columns))
    }
}

/// The cell with the most votes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HoughPeak {
    /// Row index.
    pub row: usize,
    /// Column index.
    pub column: usize,
    /// Accumulated (weighted) votes.
    pub value: f64,
    /// Signed distance `d` of the cell's line, m.
    pub distance: f64,
    /// Direction `gamma` of the cell's normal, rad, in `[0, pi)`.
    pub angle: f64,
}

impl HoughPeak {
    /// The cell's line in the crate's polar form `(r, alpha)`: `r >= 0`, `alpha` in
    /// `(-pi, pi]`.
    #[must_use]
    pub fn polar(&self) -> (f64, f64) {
        if self.distance < 0.0 {
            (-self.distance, wrap_angle(self.angle + PI))
        } else {
            (self.distance, wrap_angle(self.angle))
        }
    }
}

/// A full Hough accumulator over `(d, gamma)`, reusable across scans: [`Self::clear`] and vote
/// again, or [`Self::build`], without allocating.
#[derive(Debug, Clone)]
pub struct HoughAccumulator {
    grid: HoughGrid,
    half: usize,
    rows: usize,
    columns: usize,
    angle_step: f64,
    cos: Vec<f64>,
    sin: Vec<f64>,
    /// Column-major: cell `(row, column)` at `column * rows + row`.
    values: Vec<f64>,
}

impl HoughAccumulator {
    /// An empty accumulator on `grid`.
    ///
    /// # Errors
    /// [`HoughError`] when the grid is invalid or too large.
    pub fn new(grid: HoughGrid) -> Result<Self, HoughError> {
        let (half, rows, columns, angle_step) = grid.shape()?;
        let (sin, cos) = (0..columns)
            .map(|k| (k as f64 * angle_step).sin_cos())
            .unzip();
        Ok(Self {
            grid,
            half,
            rows,
            columns,
            angle_step,
            cos,
            sin,
            values: vec![0.0; rows * columns],
        })
    }

    /// The grid.
    #[must_use]
    pub fn grid(&self) -> &HoughGrid {
        &self.grid
    }

    /// Number of distance rows (`2 * floor(max_distance / distance_step) + 1`).
    #[must_use]
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of direction columns.
    #[must_use]
    pub fn columns(&self) -> usize {
        self.columns
    }

    /// Signed distance `d` of row `row`, m.
    #[must_use]
    pub fn distance(&self, row: usize) -> f64 {
        (row as f64 - self.half as f64) * self.grid.distance_step
    }

    /// Direction `gamma` of column `column`, rad.
    #[must_use]
    pub fn angle(&self, column: usize) -> f64 {
        column as f64 * self.angle_step
    }

    /// Value of a cell (0 outside the grid).
    #[must_use]
    pub fn value(&self, row: usize, column: usize) -> f64 {
        if row < self.rows && column < self.columns {
            self.values[column * self.rows + row]
        } else {
            0.0
        }
    }

    /// All values, column-major: cell `(row, column)` at `column * rows() + row`.
    #[must_use]
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Sets every cell to zero.
    pub fn clear(&mut self) {
        self.values.fill(0.0);
    }

    /// Adds `weight` to every cell whose line passes within `window` of `p`, one or two cells
    /// in every column. A non-finite point or weight is ignored.
    pub fn vote(&mut self, p: Point2, weight: f64) {
        if !(p.x.is_finite() && p.y.is_finite() && weight.is_finite()) {
            return;
        }
        let inv_step = 1.0 / self.grid.distance_step;
        let a = self.grid.window;
        let half = self.half as f64;
        let top = (self.rows - 1) as f64;
        let columns = self.values.chunks_exact_mut(self.rows);
        for ((column, &c), &s) in columns.zip(&self.cos).zip(&self.sin) {
            let x = p.x * c + p.y * s;
            let lo = ((x - a) * inv_step).ceil() + half;
            let hi = ((x + a) * inv_step).floor() + half;
            if !(lo <= top && hi >= 0.0) {
                continue;
            }
            let (lo, hi) = (lo.max(0.0) as usize, hi.min(top) as usize);
            if let Some(cells) = column.get_mut(lo..=hi) {
                for v in cells {
                    *v += weight;
                }
            }
        }
    }

    /// Clears the accumulator and lets every point vote, weighted by `weight`.
    pub fn build<'a, I: IntoIterator<Item = &'a ScanPoint>>(&mut self, points: I, weight: Weight) {
        self.clear();
        for sp in points {
            let g = match weight {
                Weight::One => 1.0,
                Weight::Range => sp.range,
            };
            self.vote(sp.point, g);
        }
    }

    /// The cell with the most votes (the first in column-major order on ties), or `None` when
    /// no cell is above zero.
    #[must_use]
    pub fn peak(&self) -> Option<HoughPeak> {
        let mut best: Option<(usize, f64)> = None;
        for (i, &v) in self.values.iter().enumerate() {
            if v > 0.0 && best.is_none_or(|(_, b)| v > b) {
                best = Some((i, v));
            }
        }
        let (i, value) = best?;
        let (row, column) = (i % self.rows, i / self.rows);
        Some(HoughPeak {
            row,
            column,
            value,
            distance: self.distance(row),
            angle: self.angle(column),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_point_votes_in_every_column() {
        let mut acc = HoughAccumulator::new(HoughGrid::default()).unwrap();
        acc.vote(Point2::new(1.234, -0.567), 1.0);
        for k in 0..acc.columns() {
            let s: f64 = (0..acc.rows()).map(|j| acc.value(j, k)).sum();
            assert!((1.0..=2.0).contains(&s), "column {k} has {s} votes");
        }
    }

    #[test]
    fn peak_of_a_line_behind_the_sensor_converts_to_polar() {
        let mut acc = HoughAccumulator::new(HoughGrid::default()).unwrap();
        for i in 0..20 {
            acc.vote(Point2::new(-1.0 + 0.1 * i as f64, -1.5), 1.0);
        }
        let peak = acc.peak().unwrap();
        assert_eq!(peak.value, 20.0);
        let (r, alpha) = peak.polar();
        assert!((r - 1.5).abs() <= 0.01);
        assert!((alpha + PI / 2.0).abs() < 1e-9);
    }

    #[test]
    fn bad_and_huge_grids_are_rejected() {
        let g = HoughGrid {
            distance_step: 0.0,
            ..HoughGrid::default()
        };
        assert!(matches!(g.validate(), Err(HoughError::NotPositive { .. })));
        let g = HoughGrid {
            distance_step: 1e-9,
            ..HoughGrid::default()
        };
        assert!(matches!(g.validate(), Err(HoughError::TooManyCells { .. })));
        let e = g.validate().unwrap_err().to_string();
        assert!(
            e.starts_with("max_distance / distance_step and angle_step give"),
            "{e}"
        );
        let g = HoughGrid {
            angle_step: f64::NAN,
            ..HoughGrid::default()
        };
        assert!(g.validate().is_err());
    }

    #[test]
    fn non_finite_votes_are_ignored_and_empty_has_no_peak() {
        let mut acc = HoughAccumulator::new(HoughGrid::default()).unwrap();
        acc.vote(Point2::new(f64::NAN, 1.0), 1.0);
        acc.vote(Point2::new(1.0, 1.0), f64::INFINITY);
        acc.vote(Point2::new(1e300, 1.0), 1.0);
        assert!(acc.peak().is_none());
    }
}
