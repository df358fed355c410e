//! Seeded procedural mazes on the 1.2 m RoboCup Rescue grid.
//!
//! A maze of `cols x rows` cells of [`ARENA_GRID`] = 1.2 m occupies `[0, 1.2 cols] x
//! [0, 1.2 rows]` metres, closed by an outer wall. The generator carves a perfect maze
//! (every cell reachable by exactly one path; every wall connected to the outer wall) by a
//! randomised depth-first search, then, when islands are asked for, removes interior walls
//! one by one, in random order, until at least that many *islands* exist: groups of walls
//! connected to each other but not to the outer wall, which a robot that only follows walls
//! would circle forever. When asked for, it then cuts the corners of turning cells at 45
//! degrees: a cell whose two closed walls meet in a corner gets a wall from the middle of
//! one to the middle of the other (0.85 m long), so that the way through it turns by two
//! 45-degree bends. Finally it drops small round obstacles (posts of 5-10 cm radius)
//! off-centre in random cells other than the start cell and the cut ones, always leaving a
//! gap of at least 0.7 m in the cell beside them.
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
    /// Number of turning cells (two closed walls meeting in a corner) whose corner is cut
    /// by a 45-degree wall between the middles of the two walls, never the start cell;
    /// fewer when the maze has fewer such cells. Default 0.
    pub diagonals: usize,
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
            diagonals: 0,
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
    /// Number of turning cells whose corner is cut by a 45-degree wall.
    pub diagonals: usize,
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
    let mut used = vec![false; cols * rows];
    used[0] = true;
    let diagonals = add_diagonals(&e, &mut world, &mut rng, params.diagonals, &mut used);
    add_obstacles(&mut world, &mut rng, params, cols, &mut used);
    let g = ARENA_GRID;
    Maze {
        world,
        start: Isometry2::new(Vector2::new(0.5 * g, 0.5 * g), 0.0),
        cols,
        rows,
        islands,
        diagonals,
    }
}

/// Cuts the corner of up to `wanted` turning cells, chosen at random (never a `used` one,
/// which they then are), by a wall between the middles of its two closed walls; the number
/// cut. Draws nothing when none is wanted.
fn add_diagonals(
    e: &Edges,
    world: &mut World,
    rng: &mut Rng,
    wanted: usize,
    used: &mut [bool],
) -> usize {
    if wanted == 0 {
        return 0;
    }
    // Turning cells with the corner their two closed walls meet in: 0 = (i, j), 1 =
    // (i + 1, j), 2 = (i + 1, j + 1), 3 = (i, j + 1).
    let mut turns: Vec<(usize, usize, usize)> = Vec::new();
    for j in 0..e.rows {
        for i in 0..e.cols {
            let (south, north) = (e.h[j][i], e.h[j + 1][i]);
            let (west, east) = (e.v[j][i], e.v[j][i + 1]);
            if usize::from(south) + usize::from(north) + usize::from(west) + usize::from(east) != 2
                || used[j * e.cols + i]
            {
                continue;
            }
            let corner = match (south, east, north, west) {
                (true, _, _, true) => 0,
                (true, true, _, _) => 1,
                (_, true, true, _) => 2,
                (_, _, true, true) => 3,
                _ => continue,
            };
            turns.push((i, j, corner));
        }
    }
    for k in (1..turns.len()).rev() {
        turns.swap(k, rng.below(k + 1));
    }
    let g = ARENA_GRID;
    let laid = wanted.min(turns.len());
    for &(i, j, corner) in &turns[..laid] {
        // The corner, and the directions of its two walls into the cell's edges.
        let (ci, cj, dx, dy) = match corner {
            0 => (i, j, 1.0, 1.0),
            1 => (i + 1, j, -1.0, 1.0),
            2 => (i + 1, j + 1, -1.0, -1.0),
            _ => (i, j + 1, 1.0, -1.0),
        };
        let c = Point2::new(g * ci as f64, g * cj as f64);
        world.add_segment(
            c + Vector2::new(0.5 * g * dx, 0.0),
            c + Vector2::new(0.0, 0.5 * g * dy),
        );
        used[j * e.cols + i] = true;
    }
    laid
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

/// Round obstacles off-centre in random cells (never a `used` one: the start cell and the
/// diagonal ones), at most one per cell.
fn add_obstacles(
    world: &mut World,
    rng: &mut Rng,
    params: &MazeParams,
    cols: usize,
    used: &mut [bool],
) {
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
    let n = used.len();
    let free_cells = used.iter().filter(|u| !**u).count();
    for _ in 0..params.obstacles.min(free_cells) {
        let mut c = rng.below(n);
        while used[c] {
            c = (c + 1) % n;
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
    fn diagonals_cross_turning_cells_and_keep_the_maze_as_it_was() {
        let plain = generate(&MazeParams::default(), 5);
        let diag = generate(
            &MazeParams {
                diagonals: 6,
                ..MazeParams::default()
            },
            5,
        );
        assert_eq!(diag.diagonals, 6);
        assert_eq!(plain.diagonals, 0);
        // The same grid walls, then six cuts of 0.6 sqrt(2) m at 45 degrees.
        let n = plain.world.walls.len();
        assert_eq!(plain.world.walls[..], diag.world.walls[..n]);
        assert_eq!(diag.world.walls.len(), n + 6);
        for w in &diag.world.walls[n..] {
            let d = w.b - w.a;
            assert!((d.norm() - 0.6 * std::f64::consts::SQRT_2).abs() < 1e-9);
            assert!((d.x.abs() - d.y.abs()).abs() < 1e-9);
            // Both ends are the middles of grid walls.
            for end in [w.a, w.b] {
                let on_middle = plain.world.walls[..n]
                    .iter()
                    .any(|g| (Point2::from(0.5 * (g.a.coords + g.b.coords)) - end).norm() < 1e-9);
                assert!(on_middle, "{w:?}");
            }
        }
        // No post touches a diagonal.
        for disc in &diag.world.discs {
            for w in &diag.world.walls[n..] {
                let d = laserlines::line::distance_to_segment(disc.centre, w.a, w.b);
                assert!(d > disc.radius + 0.2, "{disc:?} {w:?}");
            }
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
