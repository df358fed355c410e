//! Ground-truth coverage: how much of the reachable free area the laser has seen.
//!
//! The world is laid on a grid of [`COVERAGE_CELL`] = 0.1 m cells (its bounding box and 1 m
//! around it). A cell is *free for the robot* when its centre is at least the footprint's
//! circumradius (0.32 m for NAJI V) from every wall and disc: there the robot fits in any
//! heading. The *reachable free area* is the set of free cells connected to the start cell
//! by a 4-neighbour flood fill. A cell is *seen* when a laser beam crossed it on its way to
//! its hit (noise-free range; up to the maximum range when the beam hit nothing). Coverage
//! is the fraction of the reachable cells that are seen.
//!
//! This is the evaluation's ground truth: the explorer never reads it.

use laserlines::math::{Isometry2, Point2, Vector2};
use laserlines_sim::index::WorldIndex;
use laserlines_sim::world::Target;

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
        };
        let radius = if radius.is_finite() {
            radius.max(0.0)
        } else {
            0.0
        };
        let free = |c: usize| {
            let p = grid.centre(c);
            clearance_at_least(index, p, radius)
        };
        let Some(s) = grid.cell_of(start) else {
            return grid;
        };
        if !free(s) {
            return grid;
        }
        let mut stack = vec![s];
        let mut visited = vec![false; cols * rows];
        visited[s] = true;
        let mut reachable = vec![false; cols * rows];
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
        grid.reachable_count = reachable.iter().filter(|r| **r).count();
        grid.reachable = reachable;
        grid
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

    /// Marks the cells crossed by the beams of one scan: beam `i` leaves the laser at
    /// `world_from_laser` at `angle_min + i * angle_increment` and runs to
    /// `true_ranges[i]`, or to `range_max` where that is not finite.
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
        let (s0, c0) = (yaw + angle_min).sin_cos();
        let (s_inc, c_inc) = angle_increment.sin_cos();
        let mut dir = Vector2::new(c0, s0);
        for (i, &r) in true_ranges.iter().enumerate() {
            if i > 0 {
                dir = Vector2::new(c_inc * dir.x - s_inc * dir.y, s_inc * dir.x + c_inc * dir.y);
            }
            let len = if r.is_finite() { r } else { range_max };
            if !(len.is_finite() && len > 0.0) {
                continue;
            }
            self.mark_ray(o, dir, len);
        }
    }

    /// Marks the cells the ray from `o` along unit `dir` crosses up to `len` metres.
    fn mark_ray(&mut self, o: Point2, dir: Vector2, len: f64) {
        let fx = (o.x - self.origin.x) / COVERAGE_CELL;
        let fy = (o.y - self.origin.y) / COVERAGE_CELL;
        if !(fx.is_finite() && fy.is_finite()) {
            return;
        }
        let (mut x, mut y) = (fx.floor() as i64, fy.floor() as i64);
        let step_x: i64 = if dir.x > 0.0 { 1 } else { -1 };
        let step_y: i64 = if dir.y > 0.0 { 1 } else { -1 };
        let inv = |d: f64| {
            if d != 0.0 {
                COVERAGE_CELL / d.abs()
            } else {
                f64::INFINITY
            }
        };
        let (dt_x, dt_y) = (inv(dir.x), inv(dir.y));
        let first = |f: f64, i: i64, step: i64, dt: f64| {
            if dt.is_infinite() {
                f64::INFINITY
            } else if step > 0 {
                (i as f64 + 1.0 - f) * dt
            } else {
                (f - i as f64) * dt
            }
        };
        let mut t_x = first(fx, x, step_x, dt_x);
        let mut t_y = first(fy, y, step_y, dt_y);
        let (cols, rows) = (self.cols as i64, self.rows as i64);
        loop {
            if x >= 0 && y >= 0 && x < cols && y < rows {
                let c = (y * cols + x) as usize;
                if !self.seen[c] {
                    self.seen[c] = true;
                    if self.reachable[c] {
                        self.seen_count += 1;
                    }
                }
            }
            let t = t_x.min(t_y);
            if t >= len {
                break;
            }
            if t_x < t_y {
                x += step_x;
                t_x += dt_x;
            } else {
                y += step_y;
                t_y += dt_y;
            }
        }
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
                laserlines::line::distance_to_segment(p, w.a, w.b)
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
    fn beams_mark_the_cells_they_cross() {
        let index = room();
        let mut g = CoverageGrid::new(&index, Point2::new(2.0, 1.0), 0.3);
        let pose = Isometry2::new(Vector2::new(0.55, 1.05), 0.0);
        // One beam straight ahead to the far wall 3.45 m away.
        g.mark_scan(&pose, 0.0, 0.1, &[3.45], 5.6);
        assert!(g.is_seen(Point2::new(2.0, 1.05)));
        assert!(g.is_seen(Point2::new(3.95, 1.05)));
        assert!(!g.is_seen(Point2::new(2.0, 1.25)));
        // Along the free band x in [0.3, 3.7] at that row: 34 reachable cells, of which the
        // beam crossed those from x = 0.5.
        assert_eq!(g.seen_cells(), 32);
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
