//! Ground-truth coverage: how much of the reachable free area the laser has seen.
//!
//! The world is laid on a grid of [`COVERAGE_CELL`] = 0.1 m cells (its bounding box and 1 m
//! around it). A cell is *free for the robot* when its centre is at least the footprint's
//! circumradius (0.32 m for NAJI V) from every wall and disc: there the robot fits in any
//! heading. The *reachable free area* is the set of free cells connected to the start cell
//! by a 4-neighbour flood fill. A cell is *seen* when its centre lies in the area one scan's
//! beams swept: the fan from the laser through the end points of consecutive beams
//! (noise-free ranges; the maximum range where a beam hit nothing). With the URG-04LX's
//! 0.35 deg between beams, neighbouring beams end at most 3.4 cm apart at its 5.6 m range,
//! so this is the area the beams crossed, filled by scan lines instead of walked beam by
//! beam. Coverage is the fraction of the reachable cells that are seen.
//!
//! This is the evaluation's ground truth: the explorer never reads it.

use laserlines::math::{Isometry2, Point2, Vector2};
use laserlines_sim::index::WorldIndex;
use laserlines_sim::world::Target;

use laserlines_nav::raster::{BeamTable, FanRaster};

/// Side of a coverage cell, m.
pub const COVERAGE_CELL: f64 = 0.1;

/// Margin of the grid around the world's bounding box, m.
const GRID_MARGIN: f64 = 1.0;

/// The coverage grid of one run (see the [module docs](self)).
#[derive(Debug, Clone)]
pub struct CoverageGrid {
    origin: Point2,
    cols: usize,
    rows: usize,
    reachable: Vec<bool>,
    seen: Vec<bool>,
    reachable_count: usize,
    seen_count: usize,
    /// Scratch: the fan polygon of the last scan, cell units.
    polygon: Vec<(f64, f64)>,
    /// Scratch of the fan filling.
    raster: FanRaster,
    /// The beam directions, laser frame.
    beams: BeamTable,
}

impl CoverageGrid {
    /// The grid of `index`'s world with the reachable area flood-filled from `start` for a
    /// robot of circumradius `radius` (m). When the start cell itself is not free, nothing
    /// is reachable (and coverage stays 0).
    #[must_use]
    pub fn new(index: &WorldIndex, start: Point2, radius: f64) -> Self {
        let world = index.world();
        let mut lo = Point2::new(f64::INFINITY, f64::INFINITY);
        let mut hi = Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
        let mut grow = |p: Point2| {
            if p.x.is_finite() && p.y.is_finite() {
                lo = Point2::new(lo.x.min(p.x), lo.y.min(p.y));
                hi = Point2::new(hi.x.max(p.x), hi.y.max(p.y));
            }
        };
        for w in &world.walls {
            grow(w.a);
            grow(w.b);
        }
        for d in &world.discs {
            grow(d.centre);
        }
        grow(start);
        if !(lo.x.is_finite() && hi.x.is_finite()) {
            lo = Point2::origin();
            hi = Point2::origin();
        }
        let origin = Point2::new(lo.x - GRID_MARGIN, lo.y - GRID_MARGIN);
        // At most 2000 x 2000 cells (200 m): larger worlds are clipped.
        let cols =
            (((hi.x - origin.x + GRID_MARGIN) / COVERAGE_CELL).ceil() as usize).clamp(1, 2000);
        let rows =
            (((hi.y - origin.y + GRID_MARGIN) / COVERAGE_CELL).ceil() as usize).clamp(1, 2000);
        let mut grid = Self {
            origin,
            cols,
            rows,
            reachable: vec![false; cols * rows],
            seen: vec![false; cols * rows],
            reachable_count: 0,
            seen_count: 0,
            polygon: Vec::new(),
            raster: FanRaster::default(),
            beams: BeamTable::default(),
        };
        let radius = if radius.is_finite() {
            radius.max(0.0)
        } else {
            0.0
        };
        let reachable = grid.flood_fill(index, start, radius);
        grid.reachable_count = reachable.iter().filter(|r| **r).count();
        grid.reachable = reachable;
        grid
    }

    /// The free cells (centre at least `radius` from every obstacle) connected to the cell
    /// of `start` by a 4-neighbour flood fill; none when that cell is not free.
    fn flood_fill(&self, index: &WorldIndex, start: Point2, radius: f64) -> Vec<bool> {
        let (cols, rows) = (self.cols, self.rows);
        let grid = self;
        let free = |c: usize| {
            let p = grid.centre(c);
            clearance_at_least(index, p, radius)
        };
        let mut reachable = vec![false; cols * rows];
        let Some(s) = grid.cell_of(start) else {
            return reachable;
        };
        if !free(s) {
            return reachable;
        }
        let mut stack = vec![s];
        let mut visited = vec![false; cols * rows];
        visited[s] = true;
        while let Some(c) = stack.pop() {
            reachable[c] = true;
            let (x, y) = (c % cols, c / cols);
            let mut push = |n: usize| {
                if !visited[n] {
                    visited[n] = true;
                    if free(n) {
                        stack.push(n);
                    }
                }
            };
            if x > 0 {
                push(c - 1);
            }
            if x + 1 < cols {
                push(c + 1);
            }
            if y > 0 {
                push(c - cols);
            }
            if y + 1 < rows {
                push(c + cols);
            }
        }
        reachable
    }

    fn centre(&self, c: usize) -> Point2 {
        let (x, y) = (c % self.cols, c / self.cols);
        Point2::new(
            self.origin.x + (x as f64 + 0.5) * COVERAGE_CELL,
            self.origin.y + (y as f64 + 0.5) * COVERAGE_CELL,
        )
    }

    fn cell_of(&self, p: Point2) -> Option<usize> {
        let fx = ((p.x - self.origin.x) / COVERAGE_CELL).floor();
        let fy = ((p.y - self.origin.y) / COVERAGE_CELL).floor();
        if !(fx >= 0.0 && fy >= 0.0 && fx < self.cols as f64 && fy < self.rows as f64) {
            return None;
        }
        Some(fy as usize * self.cols + fx as usize)
    }

    /// Number of reachable cells.
    #[must_use]
    pub fn reachable_cells(&self) -> usize {
        self.reachable_count
    }

    /// Reachable free area, m^2.
    #[must_use]
    pub fn reachable_area_m2(&self) -> f64 {
        self.reachable_count as f64 * COVERAGE_CELL * COVERAGE_CELL
    }

    /// Number of reachable cells seen so far.
    #[must_use]
    pub fn seen_cells(&self) -> usize {
        self.seen_count
    }

    /// The fraction of the reachable cells seen so far, 0..1 (0 when nothing is reachable).
    #[must_use]
    pub fn coverage(&self) -> f64 {
        if self.reachable_count == 0 {
            0.0
        } else {
            self.seen_count as f64 / self.reachable_count as f64
        }
    }

    /// The centres of the reachable cells not seen so far.
    #[must_use]
    pub fn unseen(&self) -> Vec<Point2> {
        (0..self.cols * self.rows)
            .filter(|&c| self.reachable[c] && !self.seen[c])
            .map(|c| self.centre(c))
            .collect()
    }

    /// True when the cell holding `p` is reachable.
    #[must_use]
    pub fn is_reachable(&self, p: Point2) -> bool {
        self.cell_of(p).is_some_and(|c| self.reachable[c])
    }

    /// True when the cell holding `p` has been seen.
    #[must_use]
    pub fn is_seen(&self, p: Point2) -> bool {
        self.cell_of(p).is_some_and(|c| self.seen[c])
    }

    /// Marks the cells of one scan's swept area (see the [module docs](self)): beam `i`
    /// leaves the laser at `world_from_laser` at `angle_min + i * angle_increment` and runs
    /// to `true_ranges[i]`, or to `range_max` where that is not finite. Fewer than two
    /// beams sweep no area.
    pub fn mark_scan(
        &mut self,
        world_from_laser: &Isometry2,
        angle_min: f64,
        angle_increment: f64,
        true_ranges: &[f64],
        range_max: f64,
    ) {
        let o = Point2::from(world_from_laser.translation.vector);
        let yaw = world_from_laser.rotation.angle();
        if !(o.x.is_finite() && o.y.is_finite() && yaw.is_finite() && angle_increment.is_finite()) {
            return;
        }
        // The fan polygon in cell units: the laser, then every beam's end.
        let to_cells = |p: Point2| {
            (
                (p.x - self.origin.x) / COVERAGE_CELL,
                (p.y - self.origin.y) / COVERAGE_CELL,
            )
        };
        let mut poly = std::mem::take(&mut self.polygon);
        poly.clear();
        poly.push(to_cells(o));
        let (s_yaw, c_yaw) = yaw.sin_cos();
        let dirs = self
            .beams
            .get(angle_min, angle_increment, true_ranges.len());
        for (&r, d) in true_ranges.iter().zip(dirs) {
            let dir = Vector2::new(c_yaw * d.x - s_yaw * d.y, s_yaw * d.x + c_yaw * d.y);
            let len = if r.is_finite() { r } else { range_max };
            let len = if len.is_finite() { len.max(0.0) } else { 0.0 };
            poly.push(to_cells(o + dir * len));
        }
        let mut raster = std::mem::take(&mut self.raster);
        let (seen, reachable, count) = (&mut self.seen, &self.reachable, &mut self.seen_count);
        let cols = self.cols;
        raster.fill(&poly, cols, self.rows, |row, first, last| {
            let (from, to) = (row * cols + first, row * cols + last);
            for (s, r) in seen[from..=to].iter_mut().zip(&reachable[from..=to]) {
                if !*s {
                    *s = true;
                    *count += usize::from(*r);
                }
            }
        });
        self.raster = raster;
        self.polygon = poly;
    }
}

/// True when `p` is at least `radius` from every wall and disc of the index's world.
fn clearance_at_least(index: &WorldIndex, p: Point2, radius: f64) -> bool {
    let world = index.world();
    let r = Vector2::new(radius, radius);
    let mut ok = true;
    index.near_box(p - r, p + r, |t| {
        if !ok {
            return;
        }
        let d = match t {
            Target::Wall(i) => {
                let w = &world.walls[i];
                laserlines::geometry::distance_to_segment(p, w.a, w.b)
            }
            Target::Disc(i) => {
                let d = &world.discs[i];
                (p - d.centre).norm() - d.radius
            }
        };
        if d < radius {
            ok = false;
        }
    });
    ok
}

#[cfg(test)]
mod tests {
    use super::*;
    use laserlines_sim::World;

    fn room() -> WorldIndex {
        let mut w = World::new();
        w.add_box(Point2::new(2.0, 1.0), 4.0, 2.0, 0.0);
        WorldIndex::new(&w, 0.5)
    }

    #[test]
    fn reachable_area_of_a_room() {
        let index = room();
        let g = CoverageGrid::new(&index, Point2::new(2.0, 1.0), 0.3);
        // Free centres: x in [0.3, 3.7], y in [0.3, 1.7]: 34 x 14 cells of 0.1 m.
        assert!((g.reachable_cells() as i64 - 34 * 14).abs() <= 2 * (34 + 14));
        assert!(!g.is_reachable(Point2::new(5.0, 1.0)));
        assert!(!g.is_reachable(Point2::new(0.1, 1.0)));
        assert_eq!(g.coverage(), 0.0);
        // From outside the room the inside is not reachable.
        let out = CoverageGrid::new(&index, Point2::new(-0.5, 1.0), 0.3);
        assert!(!out.is_reachable(Point2::new(2.0, 1.0)));
        // A start on a wall reaches nothing.
        let none = CoverageGrid::new(&index, Point2::new(0.0, 1.0), 0.3);
        assert_eq!(none.reachable_cells(), 0);
        assert_eq!(none.coverage(), 0.0);
    }

    #[test]
    fn scans_mark_the_cells_they_sweep() {
        let index = room();
        let mut g = CoverageGrid::new(&index, Point2::new(2.0, 1.0), 0.3);
        // Three beams 0.05 rad apart, 3.45 m long, from 1.3 cm above the centre line of the
        // row y in [1.0, 1.1].
        let pose = Isometry2::new(Vector2::new(0.55, 1.063), 0.0);
        g.mark_scan(&pose, -0.05, 0.05, &[3.45, 3.45, 3.45], 5.6);
        assert!(g.is_seen(Point2::new(2.0, 1.05)));
        assert!(g.is_seen(Point2::new(3.95, 1.05)));
        assert!(!g.is_seen(Point2::new(2.0, 1.25)));
        assert!(!g.is_seen(Point2::new(0.65, 1.05)));
        // The fan's half-width is 0.05 d at d from the laser. Reachable centres (x = 0.35
        // .. 3.65) inside it: on the row y = 1.05 (1.3 cm off the axis) from d > 0.26,
        // x = 0.85 .. 3.65 (29 cells); on y = 1.15 (8.7 cm off) from d > 1.74, x = 2.35 ..
        // 3.65 (14); on y = 0.95 (11.3 cm off) from d > 2.26, x = 2.85 .. 3.65 (9).
        assert_eq!(g.seen_cells(), 29 + 14 + 9);
        // One beam sweeps nothing.
        let mut one = CoverageGrid::new(&index, Point2::new(2.0, 1.0), 0.3);
        one.mark_scan(&pose, 0.0, 0.1, &[3.45], 5.6);
        assert_eq!(one.seen_cells(), 0);
        // A full turn of beams to the walls sees the whole room.
        let n = 3600;
        let ranges: Vec<f64> = (0..n)
            .map(|i| {
                let a = -std::f64::consts::PI + i as f64 * std::f64::consts::TAU / n as f64;
                index
                    .cast(Point2::new(2.0, 1.0), a, 10.0)
                    .map_or(f64::NAN, |h| h.range)
            })
            .collect();
        let centre = Isometry2::new(Vector2::new(2.0, 1.0), 0.0);
        g.mark_scan(
            &centre,
            -std::f64::consts::PI,
            std::f64::consts::TAU / n as f64,
            &ranges,
            5.6,
        );
        assert!((g.coverage() - 1.0).abs() < 1e-12, "{}", g.coverage());
    }
}
