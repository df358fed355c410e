//! A uniform-grid index over a [`World`] for fast ray casting and proximity queries.
//!
//! [`World::cast`] tests every wall and disc; a robot simulation casts hundreds of thousands
//! of rays per simulated minute in arenas of a hundred walls and more. [`WorldIndex`] files
//! each wall and disc under the grid cells it touches and walks a ray through the cells in
//! order (Amanatides-Woo traversal), so that a ray tests only the few obstacles along it.
//! It gives the same ranges as [`World::cast`] (the same intersection formulas); where two
//! obstacles tie exactly, the target reported may differ.

use laserlines::geometry::{circle_ray_hit, clip_ray_to_box, segment_ray_hit, segment_touches_box};
use laserlines::math::{Point2, Vector2, floor_i64};

use crate::world::{Hit, Target, World};

/// Hits closer to each other than this (m) are a tie, won by the earlier obstacle.
pub(crate) const TIE_TOLERANCE: f64 = 1e-12;
/// Margin added around every obstacle when filing it under cells, m.
const FILE_MARGIN: f64 = 1e-6;

/// A uniform-grid index of a world's walls and discs (see the [module docs](self)).
///
/// ```
/// use laserlines_sim::{World, index::WorldIndex};
/// use laserlines::math::Point2;
/// let mut world = World::new();
/// world.add_box(Point2::new(0.0, 0.0), 4.0, 3.0, 0.3);
/// let index = WorldIndex::new(&world, 0.5);
/// for k in 0..100 {
///     let angle = k as f64 * 0.0628;
///     let fast = index.cast(Point2::new(0.3, -0.2), angle, 10.0).unwrap();
///     let slow = world.cast(Point2::new(0.3, -0.2), angle, 10.0).unwrap();
///     assert!((fast.range - slow.range).abs() < 1e-12);
/// }
/// ```
#[derive(Debug, Clone)]
pub struct WorldIndex {
    world: World,
    origin: Point2,
    cell: f64,
    cols: usize,
    rows: usize,
    /// Per cell, the range of `items` holding its obstacles.
    spans: Vec<(u32, u32)>,
    items: Vec<Target>,
}

impl WorldIndex {
    /// Indexes `world` with square cells of `cell_size` metres (clamped to at least 0.05 m;
    /// about half the typical wall length is a good choice). Obstacles with non-finite
    /// coordinates are left out of the index (the world's own cast ignores them too).
    #[must_use]
    pub fn new(world: &World, cell_size: f64) -> Self {
        let cell = if cell_size.is_finite() {
            cell_size.max(0.05)
        } else {
            0.5
        };
        let mut min = Point2::new(f64::INFINITY, f64::INFINITY);
        let mut max = Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
        let mut grow = |p: Point2, r: f64| {
            if p.x.is_finite() && p.y.is_finite() && r.is_finite() {
                min = Point2::new(min.x.min(p.x - r), min.y.min(p.y - r));
                max = Point2::new(max.x.max(p.x + r), max.y.max(p.y + r));
            }
        };
        for w in &world.walls {
            if finite(w.a) && finite(w.b) {
                grow(w.a, 0.0);
                grow(w.b, 0.0);
            }
        }
        for d in &world.discs {
            if d.radius > 0.0 {
                grow(d.centre, d.radius);
            }
        }
        if !(min.x.is_finite() && max.x.is_finite()) {
            min = Point2::origin();
            max = Point2::origin();
        }
        let origin = Point2::new(min.x - cell, min.y - cell);
        // At most 4096 x 4096 cells: a larger world gets larger cells.
        let span = (max.x - min.x).max(max.y - min.y) + 2.0 * cell;
        let cell = cell.max(span / 4096.0);
        let cols = (((max.x - origin.x) / cell).ceil() as usize + 1).max(1);
        let rows = (((max.y - origin.y) / cell).ceil() as usize + 1).max(1);

        let mut buckets: Vec<Vec<Target>> = vec![Vec::new(); cols * rows];
        let mut index = Self {
            world: world.clone(),
            origin,
            cell,
            cols,
            rows,
            spans: Vec::new(),
            items: Vec::new(),
        };
        for (i, w) in world.walls.iter().enumerate() {
            if !(finite(w.a) && finite(w.b)) {
                continue;
            }
            index.for_cells_near_segment(w.a, w.b, |c| buckets[c].push(Target::Wall(i)));
        }
        for (i, d) in world.discs.iter().enumerate() {
            if !(d.radius > 0.0 && d.radius.is_finite() && finite(d.centre)) {
                continue;
            }
            let r = Vector2::new(d.radius, d.radius);
            index.for_cells_in_box(d.centre - r, d.centre + r, |c| {
                buckets[c].push(Target::Disc(i));
            });
        }
        for b in &buckets {
            let from = index.items.len() as u32;
            index.items.extend_from_slice(b);
            index.spans.push((from, index.items.len() as u32));
        }
        index
    }

    /// The indexed world.
    #[must_use]
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The cell size, m.
    #[must_use]
    pub fn cell_size(&self) -> f64 {
        self.cell
    }

    fn cell_of(&self, p: Point2) -> (i64, i64) {
        (
            floor_i64((p.x - self.origin.x) / self.cell),
            floor_i64((p.y - self.origin.y) / self.cell),
        )
    }

    fn clamp_cell(&self, (cx, cy): (i64, i64)) -> (usize, usize) {
        (
            cx.clamp(0, self.cols as i64 - 1) as usize,
            cy.clamp(0, self.rows as i64 - 1) as usize,
        )
    }

    fn for_cells_in_box(&self, lo: Point2, hi: Point2, mut f: impl FnMut(usize)) {
        let m = Vector2::new(FILE_MARGIN, FILE_MARGIN);
        let (x0, y0) = self.clamp_cell(self.cell_of(lo - m));
        let (x1, y1) = self.clamp_cell(self.cell_of(hi + m));
        for y in y0..=y1 {
            for x in x0..=x1 {
                f(y * self.cols + x);
            }
        }
    }

    /// Every cell within `FILE_MARGIN` of the segment (a conservative supercover).
    fn for_cells_near_segment(&self, a: Point2, b: Point2, mut f: impl FnMut(usize)) {
        let lo = Point2::new(a.x.min(b.x), a.y.min(b.y));
        let hi = Point2::new(a.x.max(b.x), a.y.max(b.y));
        let m = Vector2::new(FILE_MARGIN, FILE_MARGIN);
        let (x0, y0) = self.clamp_cell(self.cell_of(lo - m));
        let (x1, y1) = self.clamp_cell(self.cell_of(hi + m));
        for y in y0..=y1 {
            for x in x0..=x1 {
                let c0 = Point2::new(
                    self.origin.x + x as f64 * self.cell - FILE_MARGIN,
                    self.origin.y + y as f64 * self.cell - FILE_MARGIN,
                );
                let c1 = Point2::new(
                    c0.x + self.cell + 2.0 * FILE_MARGIN,
                    c0.y + self.cell + 2.0 * FILE_MARGIN,
                );
                if segment_touches_box(a, b, c0, c1) {
                    f(y * self.cols + x);
                }
            }
        }
    }

    fn cell_items(&self, c: usize) -> &[Target] {
        let (from, to) = self.spans[c];
        &self.items[from as usize..to as usize]
    }

    /// Every wall and disc filed under a cell that meets the box `lo..hi` (world frame, m);
    /// an obstacle may be listed more than once. Walls and discs farther away are never
    /// listed, so a caller can test exact distances on this short list.
    pub fn near_box(&self, lo: Point2, hi: Point2, mut f: impl FnMut(Target)) {
        if !(finite(lo) && finite(hi)) {
            return;
        }
        self.for_cells_in_box(lo, hi, |c| {
            for &t in self.cell_items(c) {
                f(t);
            }
        });
    }

    /// Casts a ray like [`World::cast`]: from `origin` at `angle` (rad, world frame), the
    /// nearest wall or disc within `max_range` (m, inclusive). Never panics; non-finite
    /// inputs give `None`.
    #[must_use]
    pub fn cast(&self, origin: Point2, angle: f64, max_range: f64) -> Option<Hit> {
        if !(finite(origin) && angle.is_finite()) || max_range.is_nan() || max_range < 0.0 {
            return None;
        }
        let (s, c) = angle.sin_cos();
        self.cast_dir(origin, Vector2::new(c, s), max_range)
    }

    /// [`WorldIndex::cast`] along a unit direction vector `dir` instead of an angle.
    #[must_use]
    pub fn cast_dir(&self, origin: Point2, dir: Vector2, max_range: f64) -> Option<Hit> {
        if !(finite(origin) && dir.x.is_finite() && dir.y.is_finite())
            || max_range.is_nan()
            || max_range < 0.0
        {
            return None;
        }
        // Clip the ray to the grid's box; walk the cells it crosses in order.
        let lo = self.origin;
        let hi = Point2::new(
            lo.x + self.cols as f64 * self.cell,
            lo.y + self.rows as f64 * self.cell,
        );
        let (t_in, t_out) = clip_ray_to_box(origin, dir, lo, hi)?;
        let t_end = t_out.min(if max_range.is_finite() {
            max_range
        } else {
            f64::INFINITY
        });
        if t_in > t_end {
            return None;
        }
        let mut walk = CellWalk::new(self, origin, dir, t_in);
        let mut best: Option<(f64, Target)> = None;
        loop {
            for &target in self.cell_items(walk.cy * self.cols + walk.cx) {
                let t = match target {
                    Target::Wall(i) => {
                        let w = &self.world.walls[i];
                        segment_ray_hit(w.a, w.b, origin, dir)
                    }
                    Target::Disc(i) => {
                        let d = &self.world.discs[i];
                        circle_ray_hit(d.centre, d.radius, origin, dir)
                    }
                };
                consider(&mut best, t, target, max_range);
            }
            let t_exit = walk.t_max_x.min(walk.t_max_y);
            if let Some((bt, _)) = best
                && bt <= t_exit - 1e-9
            {
                break;
            }
            if t_exit > t_end || !walk.advance(self.cols, self.rows) {
                break;
            }
        }
        let (range, target) = best?;
        let point = origin + dir * range;
        if !finite(point) {
            return None;
        }
        Some(Hit {
            range,
            point,
            target,
        })
    }
}

/// Keeps the hit at `t` of `target` in `best` when it is within `max_range` and nearer
/// (ties within [`TIE_TOLERANCE`] to the earlier obstacle).
fn consider(best: &mut Option<(f64, Target)>, t: Option<f64>, target: Target, max_range: f64) {
    if let Some(t) = t
        && t.is_finite()
        && t <= max_range
        && best.is_none_or(|(bt, tb)| {
            t < bt - TIE_TOLERANCE || (t <= bt + TIE_TOLERANCE && target_order(target, tb))
        })
    {
        *best = Some((t, target));
    }
}

/// The cells a ray crosses, in order (Amanatides and Woo): the present cell and the ray
/// parameters at which it next crosses a column and a row boundary.
struct CellWalk {
    cx: usize,
    cy: usize,
    step_x: i64,
    step_y: i64,
    t_max_x: f64,
    t_max_y: f64,
    t_delta_x: f64,
    t_delta_y: f64,
}

impl CellWalk {
    /// The walk of the ray from `origin` along `dir` through `index`'s grid, entering it at
    /// the parameter `t_in`.
    fn new(index: &WorldIndex, origin: Point2, dir: Vector2, t_in: f64) -> Self {
        let (lo, cell) = (index.origin, index.cell);
        let start = origin + dir * t_in;
        let (cx, cy) = index.clamp_cell(index.cell_of(start));
        let step_x: i64 = if dir.x > 0.0 { 1 } else { -1 };
        let step_y: i64 = if dir.y > 0.0 { 1 } else { -1 };
        let next_boundary =
            |c: usize, step: i64, o: f64| o + (c as f64 + if step > 0 { 1.0 } else { 0.0 }) * cell;
        let t_max = |d: f64, c: usize, step: i64, o: f64, from: f64| {
            if d != 0.0 {
                (next_boundary(c, step, o) - from) / d
            } else {
                f64::INFINITY
            }
        };
        let t_delta = |d: f64| {
            if d != 0.0 {
                cell / d.abs()
            } else {
                f64::INFINITY
            }
        };
        Self {
            cx,
            cy,
            step_x,
            step_y,
            t_max_x: t_max(dir.x, cx, step_x, lo.x, origin.x),
            t_max_y: t_max(dir.y, cy, step_y, lo.y, origin.y),
            t_delta_x: t_delta(dir.x),
            t_delta_y: t_delta(dir.y),
        }
    }

    /// Steps to the next cell; false when that leaves the `cols` x `rows` grid.
    fn advance(&mut self, cols: usize, rows: usize) -> bool {
        if self.t_max_x < self.t_max_y {
            let nx = self.cx as i64 + self.step_x;
            if nx < 0 || nx >= cols as i64 {
                return false;
            }
            self.cx = nx as usize;
            self.t_max_x += self.t_delta_x;
        } else {
            let ny = self.cy as i64 + self.step_y;
            if ny < 0 || ny >= rows as i64 {
                return false;
            }
            self.cy = ny as usize;
            self.t_max_y += self.t_delta_y;
        }
        true
    }
}

impl WorldIndex {}

/// True when `a` should win a tie against `b` (the world's order: walls by index, then discs).
pub(crate) fn target_order(a: Target, b: Target) -> bool {
    match (a, b) {
        (Target::Wall(i), Target::Wall(j)) | (Target::Disc(i), Target::Disc(j)) => i < j,
        (Target::Wall(_), Target::Disc(_)) => true,
        (Target::Disc(_), Target::Wall(_)) => false,
    }
}

/// True when both coordinates are finite.
pub(crate) fn finite(p: Point2) -> bool {
    p.x.is_finite() && p.y.is_finite()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    #[test]
    fn same_ranges_as_the_world_on_random_rays() {
        let mut rng = Rng::new(3);
        let mut world = World::new();
        for _ in 0..60 {
            let a = Point2::new(rng.range(-6.0, 6.0), rng.range(-6.0, 6.0));
            let b = a + Vector2::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
            world.add_segment(a, b);
        }
        // Grid-aligned walls, as in arenas: rays along them and through their ends.
        for k in -4..4 {
            let x = 1.2 * f64::from(k) + 0.6;
            world.add_segment(Point2::new(x, -0.6), Point2::new(x, 0.6));
            world.add_segment(Point2::new(-0.6, x), Point2::new(0.6, x));
        }
        for _ in 0..10 {
            world.add_disc(
                Point2::new(rng.range(-6.0, 6.0), rng.range(-6.0, 6.0)),
                rng.range(0.05, 0.5),
            );
        }
        for cell in [0.3, 0.5, 1.2, 5.0] {
            let index = WorldIndex::new(&world, cell);
            for _ in 0..3000 {
                let o = Point2::new(rng.range(-8.0, 8.0), rng.range(-8.0, 8.0));
                let angle = if rng.chance(0.2) {
                    f64::from(rng.below(8) as u32) * std::f64::consts::FRAC_PI_4
                } else {
                    rng.range(-4.0, 4.0)
                };
                let max = rng.range(0.0, 12.0);
                let fast = index.cast(o, angle, max).map(|h| h.range);
                let slow = world.cast(o, angle, max).map(|h| h.range);
                match (fast, slow) {
                    (Some(f), Some(s)) => assert!((f - s).abs() < 1e-9, "{f} vs {s}"),
                    (None, None) => {}
                    other => panic!("{other:?} at {o} angle {angle} max {max}"),
                }
            }
        }
    }

    /// The sweep of `scan_into` gives, beam by beam, what `cast_dir` gives along the same
    /// direction: random worlds, poses on and off walls, both senses of rotation, full turns.

    #[test]
    fn degenerate_inputs_give_none() {
        let mut world = World::new();
        world.add_segment(Point2::new(1.0, -1.0), Point2::new(1.0, 1.0));
        let index = WorldIndex::new(&world, 0.5);
        assert!(index.cast(Point2::new(f64::NAN, 0.0), 0.0, 5.0).is_none());
        assert!(index.cast(Point2::origin(), f64::INFINITY, 5.0).is_none());
        assert!(index.cast(Point2::origin(), 0.0, -1.0).is_none());
        assert!(index.cast(Point2::origin(), 0.0, 0.5).is_none());
        assert!(index.cast(Point2::new(50.0, 50.0), 0.0, 5.0).is_none());
        let empty = WorldIndex::new(&World::new(), 0.5);
        assert!(empty.cast(Point2::origin(), 0.0, 5.0).is_none());
        assert!((index.cast(Point2::origin(), 0.0, 5.0).unwrap().range - 1.0).abs() < 1e-12);
    }
}
