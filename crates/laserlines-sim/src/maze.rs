//! Seeded procedural mazes on the 1.2 m RoboCup Rescue grid.
//!
//! A maze of `cols x rows` cells of [`ARENA_GRID`] = 1.2 m occupies `[0, 1.2 cols] x
//! [0, 1.2 rows]` metres, closed by an outer wall. The generator carves a perfect maze
//! (every cell reachable by exactly one path; every wall connected to the outer wall) by a
//! randomised depth-first search, then, when islands are asked for, removes interior walls
//! one by one, in random order, until at least that many *islands* exist: groups of walls
//! connected to each other but not to the outer wall, which a robot that only follows walls
//! would circle forever. Finally it drops small round obstacles (posts of 5-10 cm radius)
//! off-centre in random cells other than the start cell, always leaving a gap of at least
//! 0.7 m in the cell beside them.
//!
//! ```
//! use laserlines_sim::maze::{MazeParams, generate};
//! let maze = generate(&MazeParams { islands: 2, ..MazeParams::default() }, 42);
//! assert!(maze.islands >= 2);
//! assert_eq!(maze, generate(&MazeParams { islands: 2, ..MazeParams::default() }, 42));
//! ```

use laserlines::math::{Isometry2, Point2, Vector2};

use crate::arena::ARENA_GRID;
use crate::rng::Rng;
use crate::world::World;

/// Parameters of a maze.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MazeParams {
    /// Cells along x. Default 10 (12 m). Clamped to 2..=64.
    pub cols: usize,
    /// Cells along y. Default 12 (14.4 m). Clamped to 2..=64.
    pub rows: usize,
    /// Least number of islands (wall groups not connected to the outer wall); 0 gives a
    /// perfect maze without islands. Default 0. A maze too small for the number asked
    /// gets as many as removing interior walls gives.
    pub islands: usize,
    /// Number of small round obstacles. Default 4.
    pub obstacles: usize,
    /// Smallest and largest obstacle radius, m. Default 0.05..0.10.
    pub obstacle_radius: (f64, f64),
}

impl Default for MazeParams {
    fn default() -> Self {
        Self {
            cols: 10,
            rows: 12,
            islands: 0,
            obstacles: 4,
            obstacle_radius: (0.05, 0.10),
        }
    }
}

/// A generated maze.
#[derive(Debug, Clone, PartialEq)]
pub struct Maze {
    /// Walls (one per cell edge, 1.2 m) and obstacles.
    pub world: World,
    /// Where a robot starts: the centre of cell (0, 0), facing +x.
    pub start: Isometry2,
    /// Cells along x.
    pub cols: usize,
    /// Cells along y.
    pub rows: usize,
    /// Number of islands in the maze.
    pub islands: usize,
}

/// The walls of a grid maze: `h[j][i]` is the edge along x at `y = 1.2 j` over column `i`,
/// `v[j][i]` the edge along y at `x = 1.2 i` over row `j`.
struct Edges {
    cols: usize,
    rows: usize,
    h: Vec<Vec<bool>>,
    v: Vec<Vec<bool>>,
}

impl Edges {
    /// The walls: one 1.2 m segment per closed edge, horizontal edges first, row by row.
    fn walls(&self) -> World {
        let g = ARENA_GRID;
        let mut world = World::new();
        for j in 0..=self.rows {
            for i in 0..self.cols {
                if self.h[j][i] {
                    let y = g * j as f64;
                    world.add_segment(
                        Point2::new(g * i as f64, y),
                        Point2::new(g * (i + 1) as f64, y),
                    );
                }
            }
        }
        for j in 0..self.rows {
            for i in 0..=self.cols {
                if self.v[j][i] {
                    let x = g * i as f64;
                    world.add_segment(
                        Point2::new(x, g * j as f64),
                        Point2::new(x, g * (j + 1) as f64),
                    );
                }
            }
        }
        world
    }

    fn full(cols: usize, rows: usize) -> Self {
        Self {
            cols,
            rows,
            h: vec![vec![true; cols]; rows + 1],
            v: vec![vec![true; cols + 1]; rows],
        }
    }

    /// Grid vertex id of corner `(i, j)`.
    fn vertex(&self, i: usize, j: usize) -> usize {
        j * (self.cols + 1) + i
    }

    /// Number of wall groups that do not touch the outer wall.
    fn islands(&self) -> usize {
        let n = (self.cols + 1) * (self.rows + 1);
        let mut parent: Vec<usize> = (0..n).collect();
        fn find(p: &mut [usize], mut x: usize) -> usize {
            while p[x] != x {
                p[x] = p[p[x]];
                x = p[x];
            }
            x
        }
        let mut has_edge = vec![false; n];
        let mut join = |p: &mut Vec<usize>, a: usize, b: usize| {
            has_edge[a] = true;
            has_edge[b] = true;
            let (ra, rb) = (find(p, a), find(p, b));
            if ra != rb {
                p[ra] = rb;
            }
        };
        for j in 0..=self.rows {
            for i in 0..self.cols {
                if self.h[j][i] {
                    join(&mut parent, self.vertex(i, j), self.vertex(i + 1, j));
                }
            }
        }
        for j in 0..self.rows {
            for i in 0..=self.cols {
                if self.v[j][i] {
                    join(&mut parent, self.vertex(i, j), self.vertex(i, j + 1));
                }
            }
        }
        let outer = find(&mut parent, 0);
        let mut roots: Vec<usize> = (0..n)
            .filter(|&x| has_edge[x])
            .map(|x| find(&mut parent, x))
            .filter(|&r| r != outer)
            .collect();
        roots.sort_unstable();
        roots.dedup();
        roots.len()
    }
}

/// Generates a maze for `seed`, see the [module docs](self). The same parameters and seed
/// give the same maze.
#[must_use]
pub fn generate(params: &MazeParams, seed: u64) -> Maze {
    let cols = params.cols.clamp(2, 64);
    let rows = params.rows.clamp(2, 64);
    let mut rng = Rng::new(seed);
    let mut e = Edges::full(cols, rows);
    carve_perfect(&mut e, &mut rng);
    let islands = if params.islands > 0 {
        open_islands(&mut e, &mut rng, params.islands)
    } else {
        0
    };
    let mut world = e.walls();
    add_obstacles(&mut world, &mut rng, params, cols, rows);
    let g = ARENA_GRID;
    Maze {
        world,
        start: Isometry2::new(Vector2::new(0.5 * g, 0.5 * g), 0.0),
        cols,
        rows,
        islands,
    }
}

/// A perfect maze: randomised depth-first search from cell (0, 0), opening the wall to each
/// new cell.
fn carve_perfect(e: &mut Edges, rng: &mut Rng) {
    let (cols, rows) = (e.cols, e.rows);
    let mut visited = vec![false; cols * rows];
    let mut stack = vec![(0usize, 0usize)];
    visited[0] = true;
    while let Some(&(i, j)) = stack.last() {
        let mut next = Vec::with_capacity(4);
        if i > 0 && !visited[j * cols + i - 1] {
            next.push((i - 1, j));
        }
        if i + 1 < cols && !visited[j * cols + i + 1] {
            next.push((i + 1, j));
        }
        if j > 0 && !visited[(j - 1) * cols + i] {
            next.push((i, j - 1));
        }
        if j + 1 < rows && !visited[(j + 1) * cols + i] {
            next.push((i, j + 1));
        }
        if next.is_empty() {
            stack.pop();
            continue;
        }
        let (ni, nj) = next[rng.below(next.len())];
        if ni != i {
            e.v[j][i.max(ni)] = false;
        } else {
            e.h[j.max(nj)][i] = false;
        }
        visited[nj * cols + ni] = true;
        stack.push((ni, nj));
    }
}

/// Removes interior walls in random order (a wall whose removal dissolves an island is put
/// back) until `wanted` islands exist; the islands made.
fn open_islands(e: &mut Edges, rng: &mut Rng, wanted: usize) -> usize {
    let (cols, rows) = (e.cols, e.rows);
    let mut interior: Vec<(bool, usize, usize)> = Vec::new();
    for j in 1..rows {
        for i in 0..cols {
            if e.h[j][i] {
                interior.push((true, i, j));
            }
        }
    }
    for j in 0..rows {
        for i in 1..cols {
            if e.v[j][i] {
                interior.push((false, i, j));
            }
        }
    }
    // Fisher-Yates.
    for k in (1..interior.len()).rev() {
        interior.swap(k, rng.below(k + 1));
    }
    let mut islands = 0;
    for (horizontal, i, j) in interior {
        if horizontal {
            e.h[j][i] = false;
        } else {
            e.v[j][i] = false;
        }
        let now = e.islands();
        if now < islands {
            // Removing this wall dissolved an island: put it back.
            if horizontal {
                e.h[j][i] = true;
            } else {
                e.v[j][i] = true;
            }
            continue;
        }
        islands = now;
        if islands >= wanted {
            break;
        }
    }
    islands
}

/// Round obstacles off-centre in random cells (never the start cell), at most one per cell.
fn add_obstacles(world: &mut World, rng: &mut Rng, params: &MazeParams, cols: usize, rows: usize) {
    let g = ARENA_GRID;
    let (r_lo, r_hi) = params.obstacle_radius;
    let r_lo = if r_lo.is_finite() {
        r_lo.clamp(0.01, 0.15)
    } else {
        0.05
    };
    let r_hi = if r_hi.is_finite() {
        r_hi.clamp(r_lo, 0.15)
    } else {
        r_lo
    };
    let mut used = vec![false; cols * rows];
    used[0] = true;
    let free_cells = cols * rows - 1;
    for _ in 0..params.obstacles.min(free_cells) {
        let mut c = rng.below(cols * rows);
        while used[c] {
            c = (c + 1) % (cols * rows);
        }
        used[c] = true;
        let (i, j) = (c % cols, c / cols);
        let centre = Point2::new(g * (i as f64 + 0.5), g * (j as f64 + 0.5));
        let radius = rng.range(r_lo, r_hi);
        // 0.25..0.3 m off the centre along each axis: the far gap is at least
        // 0.6 + 0.25 - 0.15 = 0.7 m wide.
        let sign = |rng: &mut Rng| if rng.chance(0.5) { 1.0 } else { -1.0 };
        let ox = sign(rng) * rng.range(0.25, 0.3);
        let oy = sign(rng) * rng.range(0.25, 0.3);
        world.add_disc(centre + Vector2::new(ox, oy), radius);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_perfect_maze_has_no_islands_and_the_right_wall_count() {
        for seed in 0..10 {
            let m = generate(&MazeParams::default(), seed);
            assert_eq!(m.islands, 0);
            // A spanning tree of 120 cells opens 119 interior edges: walls = all edges - 119.
            let all = 11 * 12 + 13 * 10;
            assert_eq!(m.world.walls.len(), all - 119);
            assert_eq!(m.world.discs.len(), 4);
        }
    }

    #[test]
    fn islands_are_made_when_asked_for() {
        for seed in 0..10 {
            let m = generate(
                &MazeParams {
                    islands: 3,
                    ..MazeParams::default()
                },
                seed,
            );
            assert!(m.islands >= 3, "seed {seed}: {}", m.islands);
        }
    }

    #[test]
    fn obstacles_keep_a_passage_and_avoid_the_start_cell() {
        let m = generate(
            &MazeParams {
                obstacles: 40,
                ..MazeParams::default()
            },
            3,
        );
        assert_eq!(m.world.discs.len(), 40);
        for d in &m.world.discs {
            assert!((d.centre - Point2::new(0.6, 0.6)).norm() > 0.8);
            let to_walls = m
                .world
                .walls
                .iter()
                .map(|w| laserlines::line::distance_to_segment(d.centre, w.a, w.b))
                .fold(f64::INFINITY, f64::min);
            assert!(to_walls >= d.radius + 0.15 - 1e-9);
        }
    }

    #[test]
    fn sizes_are_clamped() {
        let m = generate(
            &MazeParams {
                cols: 0,
                rows: 1000,
                obstacles: 10_000,
                ..MazeParams::default()
            },
            1,
        );
        assert_eq!((m.cols, m.rows), (2, 64));
        assert_eq!(m.world.discs.len(), 2 * 64 - 1);
    }
}
