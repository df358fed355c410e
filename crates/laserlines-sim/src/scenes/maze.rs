//! Mazes on the RoboCup Rescue grid.

use std::f64::consts::PI;

use super::{ROBOCUP_GRID, Scene, p, pose, scene};
use crate::rng::Rng;
use crate::world::World;

/// A maze on the 1.2 m RoboCup Rescue grid ([`ROBOCUP_GRID`]): 4..5 by 4..5 cells, a
/// random spanning tree of passages with about one interior wall in eight removed as well
/// (loops, open spaces), so corners, T-junctions and free wall ends abound. Collinear
/// neighbouring grid edges are merged into one wall, so one straight wall is one [`Wall`].
/// The sensor stands in a random cell within 0.25 m of its centre, facing any way.
///
/// [`Wall`]: crate::Wall
pub fn maze(rng: &mut Rng) -> Scene {
    let g = ROBOCUP_GRID;
    let nx = 4 + rng.below(2);
    let ny = 4 + rng.below(2);
    // horizontal[j][i]: the edge at y = j g, x in [i g, (i + 1) g]; j in 0..=ny.
    let mut horizontal = vec![vec![true; nx]; ny + 1];
    // vertical[i][j]: the edge at x = i g, y in [j g, (j + 1) g]; i in 0..=nx.
    let mut vertical = vec![vec![true; ny]; nx + 1];

    carve_spanning_tree(rng, &mut horizontal, &mut vertical);
    // Open some more interior walls.
    for (j, row) in horizontal.iter_mut().enumerate() {
        if j == 0 || j == ny {
            continue;
        }
        for e in row.iter_mut() {
            if *e && rng.chance(0.12) {
                *e = false;
            }
        }
    }
    for (i, col) in vertical.iter_mut().enumerate() {
        if i == 0 || i == nx {
            continue;
        }
        for e in col.iter_mut() {
            if *e && rng.chance(0.12) {
                *e = false;
            }
        }
    }
    // Merge runs of collinear edges into walls.
    let mut world = World::new();
    for (j, row) in horizontal.iter().enumerate() {
        let y = j as f64 * g;
        for (from, to) in runs(row) {
            world.add_segment(p(from as f64 * g, y), p(to as f64 * g, y));
        }
    }
    for (i, col) in vertical.iter().enumerate() {
        let x = i as f64 * g;
        for (from, to) in runs(col) {
            world.add_segment(p(x, from as f64 * g), p(x, to as f64 * g));
        }
    }
    let (ci, cj) = (rng.below(nx), rng.below(ny));
    let x = (ci as f64 + 0.5) * g + rng.range(-0.25, 0.25);
    let y = (cj as f64 + 0.5) * g + rng.range(-0.25, 0.25);
    let yaw = rng.range(-PI, PI);
    scene("maze", world, pose(x, y, yaw))
}

/// Removes the edges of a random spanning tree of the `nx` by `ny` cells (depth-first search
/// with an explicit stack) from `horizontal[j][i]` (the edge at `y = j g`) and
/// `vertical[i][j]` (the edge at `x = i g`).
fn carve_spanning_tree(rng: &mut Rng, horizontal: &mut [Vec<bool>], vertical: &mut [Vec<bool>]) {
    let nx = vertical.len() - 1;
    let ny = horizontal.len() - 1;
    let mut visited = vec![vec![false; ny]; nx];
    let start = (rng.below(nx), rng.below(ny));
    visited[start.0][start.1] = true;
    let mut stack = vec![start];
    while let Some(&(i, j)) = stack.last() {
        let mut next: Vec<(usize, usize)> = Vec::with_capacity(4);
        if i > 0 && !visited[i - 1][j] {
            next.push((i - 1, j));
        }
        if i + 1 < nx && !visited[i + 1][j] {
            next.push((i + 1, j));
        }
        if j > 0 && !visited[i][j - 1] {
            next.push((i, j - 1));
        }
        if j + 1 < ny && !visited[i][j + 1] {
            next.push((i, j + 1));
        }
        if next.is_empty() {
            stack.pop();
            continue;
        }
        let (a, b) = next[rng.below(next.len())];
        if a != i {
            vertical[i.max(a)][j] = false;
        } else {
            horizontal[j.max(b)][i] = false;
        }
        visited[a][b] = true;
        stack.push((a, b));
    }
}

/// Maximal runs of `true` in `edges` as half-open index ranges `(from, to)`.
fn runs(edges: &[bool]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut from = None;
    for (k, &e) in edges.iter().enumerate() {
        match (e, from) {
            (true, None) => from = Some(k),
            (false, Some(f)) => {
                out.push((f, k));
                from = None;
            }
            _ => {}
        }
    }
    if let Some(f) = from {
        out.push((f, edges.len()));
    }
    out
}
