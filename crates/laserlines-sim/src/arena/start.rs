//! Where a run starts in an arena: the grid cell centre nearest the origin in the largest
//! free region within the arena's outline.

use laserlines::math::{Isometry2, Point2, Vector2};

use super::outline::ArenaOutline;
use super::{ARENA_GRID, cell_centre};
use crate::cells::{extent, for_each_neighbour4};
use crate::index::WorldIndex;
use crate::world::{Target, World};

/// Side of the cells of [`interior_start`]'s search, m.
pub const START_SEARCH_CELL: f64 = 0.1;

/// A start pose inside the arena: the centre of the grid cell (a point `(1.2 i, 1.2 j)`)
/// nearest to the origin within the largest free region of the arena, facing +x (yaw 0).
///
/// Free means at least `clearance` m (e.g. a robot's circumradius) from every wall and
/// disc, on a [`START_SEARCH_CELL`] grid over the world's bounding box and 1 m around it;
/// regions are 4-connected and made of free cells within the arena's [`ArenaOutline`] (its
/// walls with gaps up to 1.3 m closed), or, when the outline encloses no free cell, within
/// the bounding box of its largest group of walls. Real arena files put their origin
/// anywhere: inside the arena, in a small pocket closed by barrels, or outside the outer
/// wall. `None` when no such region holds a grid cell's centre with that clearance.
///
/// ```
/// use laserlines_sim::World;
/// use laserlines_sim::arena::interior_start;
/// use laserlines::math::Point2;
/// // A 6 m x 4 m room around (10, 10), and a 1 m pocket at the origin.
/// let mut world = World::new();
/// world.add_box(Point2::new(10.8, 10.8), 6.0, 4.0, 0.0);
/// world.add_box(Point2::new(0.0, 0.0), 1.0, 1.0, 0.0);
/// let start = interior_start(&world, 0.32).unwrap();
/// let p = start.translation.vector;
/// assert!((p.x - 8.4).abs() < 1e-9 && (p.y - 9.6).abs() < 1e-9, "{p:?}");
/// ```
#[must_use]
pub fn interior_start(world: &World, clearance: f64) -> Option<Isometry2> {
    let (lo, hi) = bounds(world)?;
    if !clearance.is_finite() {
        return None;
    }
    let grid = SearchGrid::new(world, lo, hi);
    let outline = ArenaOutline::of_index(&grid.index);
    let clear: Vec<bool> = (0..grid.cols * grid.rows)
        .map(|c| grid.clear_at(grid.centre(c), clearance))
        .collect();
    let within = |test: &dyn Fn(Point2) -> bool| -> Vec<bool> {
        (0..grid.cols * grid.rows)
            .map(|c| clear[c] && test(grid.centre(c)))
            .collect()
    };
    let enclosed = within(&|p| outline.encloses(p));
    let free = if enclosed.iter().any(|f| *f) {
        enclosed
    } else {
        within(&|p| outline.within_bounds(p))
    };
    let (region, regions) = grid.regions(&free);
    let (best, _) = regions
        .iter()
        .enumerate()
        .max_by_key(|(id, size)| (**size, std::cmp::Reverse(*id)))?;
    // The grid cell centre in that region nearest to the origin.
    let (i0, i1) = (
        (lo.x / ARENA_GRID).floor() as i64,
        (hi.x / ARENA_GRID).ceil() as i64,
    );
    let (j0, j1) = (
        (lo.y / ARENA_GRID).floor() as i64,
        (hi.y / ARENA_GRID).ceil() as i64,
    );
    let mut pick: Option<Point2> = None;
    for j in j0..=j1 {
        for i in i0..=i1 {
            let p = cell_centre(i, j);
            if grid.cell_of(p).is_some_and(|c| region[c] == best)
                && grid.clear_at(p, clearance)
                && pick.is_none_or(|q| p.coords.norm() < q.coords.norm())
            {
                pick = Some(p);
            }
        }
    }
    pick.map(|p| Isometry2::new(p.coords, 0.0))
}

/// The bounding box of the world's walls and disc centres; `None` for an empty world.
fn bounds(world: &World) -> Option<(Point2, Point2)> {
    let ends = world.walls.iter().flat_map(|w| [w.a, w.b]);
    extent(ends.chain(world.discs.iter().map(|d| d.centre)))
}

/// The search grid: [`START_SEARCH_CELL`] cells over the world's bounding box and 1 m
/// around it.
struct SearchGrid<'a> {
    world: &'a World,
    index: WorldIndex,
    origin: Point2,
    cols: usize,
    rows: usize,
}

impl<'a> SearchGrid<'a> {
    fn new(world: &'a World, lo: Point2, hi: Point2) -> Self {
        let cell = START_SEARCH_CELL;
        Self {
            world,
            index: WorldIndex::new(world, 0.6),
            origin: Point2::new(lo.x - 1.0, lo.y - 1.0),
            cols: (((hi.x - lo.x + 2.0) / cell).ceil() as usize).clamp(1, 4000),
            rows: (((hi.y - lo.y + 2.0) / cell).ceil() as usize).clamp(1, 4000),
        }
    }

    fn centre(&self, c: usize) -> Point2 {
        let cell = START_SEARCH_CELL;
        Point2::new(
            self.origin.x + ((c % self.cols) as f64 + 0.5) * cell,
            self.origin.y + ((c / self.cols) as f64 + 0.5) * cell,
        )
    }

    /// The cell holding `p`, if any.
    fn cell_of(&self, p: Point2) -> Option<usize> {
        let cell = START_SEARCH_CELL;
        let fx = ((p.x - self.origin.x) / cell).floor();
        let fy = ((p.y - self.origin.y) / cell).floor();
        if !(fx >= 0.0 && fy >= 0.0 && (fx as usize) < self.cols && (fy as usize) < self.rows) {
            return None;
        }
        Some(fy as usize * self.cols + fx as usize)
    }

    /// True when `p` is at least `need` from every wall and disc.
    fn clear_at(&self, p: Point2, need: f64) -> bool {
        let r = Vector2::new(need, need);
        let mut ok = true;
        self.index.near_box(p - r, p + r, |t| {
            let d = match t {
                Target::Wall(i) => {
                    let w = &self.world.walls[i];
                    laserlines::geometry::distance_to_segment(p, w.a, w.b)
                }
                Target::Disc(i) => {
                    let d = &self.world.discs[i];
                    (p - d.centre).norm() - d.radius
                }
            };
            if d < need {
                ok = false;
            }
        });
        ok
    }

    /// The 4-connected regions of the `free` cells by flood fill: each cell's region
    /// (`usize::MAX` for none), and each region's size.
    fn regions(&self, free: &[bool]) -> (Vec<usize>, Vec<usize>) {
        let (cols, rows) = (self.cols, self.rows);
        let mut region = vec![usize::MAX; cols * rows];
        let mut regions: Vec<usize> = Vec::new();
        let mut stack = Vec::new();
        for seed in 0..cols * rows {
            if !free[seed] || region[seed] != usize::MAX {
                continue;
            }
            let id = regions.len();
            let mut size = 0;
            region[seed] = id;
            stack.push(seed);
            while let Some(c) = stack.pop() {
                size += 1;
                for_each_neighbour4(c, cols, rows, |n| {
                    if free[n] && region[n] == usize::MAX {
                        region[n] = id;
                        stack.push(n);
                    }
                });
            }
            regions.push(size);
        }
        (region, regions)
    }
}
