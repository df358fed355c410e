//! The occupancy grid: every beam of every scan traced from the sensor at its estimated pose
//! to its end, the cells it crosses made likelier free and the cell it ends in likelier
//! occupied (log-odds, clamped so that the map keeps changing with what is seen).

use laserlines::math::{Point2, floor_i64};

use crate::se2::Se2;

/// Settings of [`OccupancyGrid::build`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OccupancyParams {
    /// Side of a cell, m (default 0.05).
    pub resolution_m: f64,
    /// Log-odds added to a cell a beam ends in (default 0.85).
    pub hit: f32,
    /// Log-odds added to a cell a beam passes through (default -0.4).
    pub miss: f32,
    /// Log-odds are clamped to `+-clamp` (default 5).
    pub clamp: f32,
    /// Largest side of the grid, cells (default 20000): a larger map is refused.
    pub max_side_cells: usize,
}

impl Default for OccupancyParams {
    fn default() -> Self {
        Self {
            resolution_m: 0.05,
            hit: 0.85,
            miss: -0.4,
            clamp: 5.0,
            max_side_cells: 20_000,
        }
    }
}

/// What a cell is believed to be.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cell {
    /// No beam reached it.
    Unknown,
    /// Probably free (log-odds below zero).
    Free,
    /// Probably occupied (log-odds above zero).
    Occupied,
}

/// A grid of log-odds in the map frame; cell `(i, j)` covers
/// `origin + [i, i+1) x [j, j+1) * resolution`.
#[derive(Debug, Clone, PartialEq)]
pub struct OccupancyGrid {
    /// The map-frame position of the corner of cell `(0, 0)`, m.
    pub origin: Point2,
    /// Side of a cell, m.
    pub resolution: f64,
    /// Cells along x.
    pub width: usize,
    /// Cells along y.
    pub height: usize,
    /// Log-odds per cell, row by row from `y = origin.y` up; NaN where unknown.
    pub log_odds: Vec<f32>,
}

/// A grid larger than [`OccupancyParams::max_side_cells`] was asked for.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("the map would be {width} x {height} cells of {resolution} m, more than {max} on a side")]
pub struct GridTooLarge {
    /// cells along x
    pub width: usize,
    /// cells along y
    pub height: usize,
    /// m
    pub resolution: f64,
    /// the limit
    pub max: usize,
}

impl GridTooLarge {
    /// The smallest cell side, m, at which the same extent fits (two significant digits,
    /// rounded up).
    #[must_use]
    pub fn fitting_resolution(&self) -> f64 {
        let side = self.width.max(self.height) as f64;
        let needed = self.resolution * side / self.max.max(1) as f64;
        let per_unit = 10f64.powf(1.0 - needed.log10().floor());
        (needed * per_unit).ceil() / per_unit
    }
}

impl OccupancyGrid {
    /// Traces every scan (`points` in the sensor frame, seen from `map_from_sensor`).
    ///
    /// # Errors
    /// [`GridTooLarge`] when the points span more cells than allowed.
    pub fn build<'a>(
        scans: impl Iterator<Item = (Se2, &'a [Point2])> + Clone,
        params: &OccupancyParams,
    ) -> Result<Self, GridTooLarge> {
        let res = params.resolution_m.max(1e-3);
        let (mut lo, mut hi) = (
            Point2::new(f64::MAX, f64::MAX),
            Point2::new(f64::MIN, f64::MIN),
        );
        for (pose, pts) in scans.clone() {
            for p in std::iter::once(&Point2::origin()).chain(pts) {
                let q = pose.transform(*p);
                if q.x.is_finite() && q.y.is_finite() {
                    lo = Point2::new(lo.x.min(q.x), lo.y.min(q.y));
                    hi = Point2::new(hi.x.max(q.x), hi.y.max(q.y));
                }
            }
        }
        if lo.x > hi.x {
            lo = Point2::origin();
            hi = Point2::origin();
        }
        let origin = Point2::new(
            (lo.x / res).floor() * res - res,
            (lo.y / res).floor() * res - res,
        );
        let width = ((hi.x - origin.x) / res).ceil() as usize + 2;
        let height = ((hi.y - origin.y) / res).ceil() as usize + 2;
        if width > params.max_side_cells || height > params.max_side_cells {
            return Err(GridTooLarge {
                width,
                height,
                resolution: res,
                max: params.max_side_cells,
            });
        }
        let mut grid = Self {
            origin,
            resolution: res,
            width,
            height,
            log_odds: vec![f32::NAN; width * height],
        };
        for (pose, pts) in scans {
            let from = grid.cell_of(Point2::new(pose.x, pose.y));
            for p in pts {
                let to = grid.cell_of(pose.transform(*p));
                grid.trace(from, to, params);
            }
        }
        Ok(grid)
    }

    /// The cell holding `p` (may lie outside the grid).
    fn cell_of(&self, p: Point2) -> (i64, i64) {
        (
            floor_i64((p.x - self.origin.x) / self.resolution),
            floor_i64((p.y - self.origin.y) / self.resolution),
        )
    }

    /// Marks the cells from `a` to `b` (Bresenham) free, and `b` occupied.
    fn trace(&mut self, a: (i64, i64), b: (i64, i64), params: &OccupancyParams) {
        let (dx, dy) = ((b.0 - a.0).abs(), -(b.1 - a.1).abs());
        let (sx, sy) = (
            if a.0 < b.0 { 1 } else { -1 },
            if a.1 < b.1 { 1 } else { -1 },
        );
        let (mut x, mut y, mut err) = (a.0, a.1, dx + dy);
        while (x, y) != b {
            self.add(x, y, params.miss, params.clamp);
            let e2 = 2 * err;
            if e2 >= dy {
                err += dy;
                x += sx;
            }
            if e2 <= dx {
                err += dx;
                y += sy;
            }
        }
        self.add(b.0, b.1, params.hit, params.clamp);
    }

    fn add(&mut self, x: i64, y: i64, v: f32, clamp: f32) {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
            return;
        }
        let c = &mut self.log_odds[y as usize * self.width + x as usize];
        let old = if c.is_nan() { 0.0 } else { *c };
        *c = (old + v).clamp(-clamp, clamp);
    }

    /// The state of cell `(i, j)` (`Unknown` outside the grid).
    #[must_use]
    pub fn cell(&self, i: usize, j: usize) -> Cell {
        if i >= self.width || j >= self.height {
            return Cell::Unknown;
        }
        let v = self.log_odds[j * self.width + i];
        if v.is_nan() {
            Cell::Unknown
        } else if v > 0.0 {
            Cell::Occupied
        } else {
            Cell::Free
        }
    }

    /// Probability of occupancy of cell `(i, j)`, `None` when unknown.
    #[must_use]
    pub fn probability(&self, i: usize, j: usize) -> Option<f64> {
        let v = *self
            .log_odds
            .get(j.checked_mul(self.width)?.checked_add(i)?)?;
        (!v.is_nan() && i < self.width).then(|| 1.0 / (1.0 + (-f64::from(v)).exp()))
    }

    /// The grid as ROS `nav_msgs/OccupancyGrid` values, row by row from the bottom (`y =
    /// origin.y`) up: -1 unknown, else the probability of occupancy in percent.
    #[must_use]
    pub fn to_occupancy_percent(&self) -> Vec<i8> {
        self.log_odds
            .iter()
            .map(|&v| {
                if v.is_nan() {
                    -1
                } else {
                    (100.0 / (1.0 + (-f64::from(v)).exp())).round() as i8
                }
            })
            .collect()
    }

    /// The grid as an 8-bit grey image in ROS `map_server` shades, top row first (the row of
    /// largest y): occupied 0 (black), free 254 (white), unknown 205 (grey).
    #[must_use]
    pub fn to_pixels(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.width * self.height);
        for j in (0..self.height).rev() {
            for i in 0..self.width {
                out.push(match self.cell(i, j) {
                    Cell::Unknown => 205,
                    Cell::Free => 254,
                    Cell::Occupied => 0,
                });
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_beam_frees_its_path_and_occupies_its_end() {
        let pts = [Point2::new(1.0, 0.0)];
        let g = OccupancyGrid::build(
            [(Se2::new(0.0, 0.0, 0.0), &pts[..])].into_iter(),
            &OccupancyParams::default(),
        )
        .unwrap();
        let cell = |x: f64, y: f64| {
            let (i, j) = g.cell_of(Point2::new(x, y));
            g.cell(i as usize, j as usize)
        };
        assert_eq!(cell(1.0, 0.0), Cell::Occupied);
        assert_eq!(cell(0.5, 0.0), Cell::Free);
        assert_eq!(cell(0.02, 0.0), Cell::Free);
        assert_eq!(cell(0.5, 0.3), Cell::Unknown);
        // Seen from a pose turned a quarter: the point lands at (0, 1).
        let g2 = OccupancyGrid::build(
            [(Se2::new(0.0, 0.0, std::f64::consts::FRAC_PI_2), &pts[..])].into_iter(),
            &OccupancyParams::default(),
        )
        .unwrap();
        let (i, j) = g2.cell_of(Point2::new(0.0, 1.0));
        assert_eq!(g2.cell(i as usize, j as usize), Cell::Occupied);
        let px = g2.to_pixels();
        assert_eq!(px.len(), g2.width * g2.height);
        assert_eq!(px.iter().filter(|&&v| v == 0).count(), 1);
        let pc = g2.to_occupancy_percent();
        assert_eq!(pc[(j as usize) * g2.width + i as usize], 70); // 1 / (1 + e^-0.85)
        assert_eq!(
            pc.iter().filter(|&&v| v == -1).count(),
            g2.width * g2.height - 21
        );
    }

    #[test]
    fn a_huge_map_is_refused() {
        let pts = [Point2::new(1e6, 0.0)];
        let e = OccupancyGrid::build(
            [(Se2::IDENTITY, &pts[..])].into_iter(),
            &OccupancyParams::default(),
        )
        .unwrap_err();
        assert!(e.width > e.max);
        // A cell of that side fits the same extent, and is at most 10 % coarser than needed.
        let fit = e.fitting_resolution();
        let needed = e.width.max(e.height) as f64 * e.resolution / e.max as f64;
        assert!(fit >= needed && fit <= 1.1 * needed, "{fit} {needed}");
        let g = GridTooLarge {
            width: 28563,
            height: 32052,
            resolution: 0.05,
            max: 20000,
        };
        assert_eq!(g.fitting_resolution(), 0.081);
    }
}
