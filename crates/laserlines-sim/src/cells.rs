//! Small pieces of work on grids of cells over a world, shared by the arena's outline and
//! start (here) and the ground-truth coverage (in the harness): flooding connected cells,
//! the extent of a set of points, whether a spot is clear of every obstacle.

use laserlines::geometry::distance_to_segment;
use laserlines::math::{Point2, Vector2};

use crate::index::WorldIndex;
use crate::world::Target;

/// Marks in `reached` every cell for which `ok` holds that is connected to one of `seeds`
/// through such cells (4-neighbours) on a grid of `cols` columns stored row by row; the seeds
/// themselves are marked whatever `ok` says of them.
pub fn flood4(cols: usize, ok: &[bool], seeds: &[usize], reached: &mut [bool]) {
    let rows = ok.len().checked_div(cols).unwrap_or(0);
    let mut stack: Vec<usize> = seeds.to_vec();
    for &s in seeds {
        reached[s] = true;
    }
    while let Some(c) = stack.pop() {
        for_each_neighbour4(c, cols, rows, |m| {
            if ok[m] && !reached[m] {
                reached[m] = true;
                stack.push(m);
            }
        });
    }
}

/// Calls `f` with each of the (up to four) edge neighbours of cell `c` on a grid of `cols`
/// columns and `rows` rows stored row by row: left, right, below, above.
#[inline]
pub fn for_each_neighbour4(c: usize, cols: usize, rows: usize, mut f: impl FnMut(usize)) {
    let (x, y) = (c % cols, c / cols);
    if x > 0 {
        f(c - 1);
    }
    if x + 1 < cols {
        f(c + 1);
    }
    if y > 0 {
        f(c - cols);
    }
    if y + 1 < rows {
        f(c + cols);
    }
}

/// The bounding box of the finite points, if any.
pub fn extent(points: impl Iterator<Item = Point2>) -> Option<(Point2, Point2)> {
    points
        .filter(|p| p.x.is_finite() && p.y.is_finite())
        .fold(None, |acc, p| match acc {
            None => Some((p, p)),
            Some((lo, hi)) => Some((
                Point2::new(lo.x.min(p.x), lo.y.min(p.y)),
                Point2::new(hi.x.max(p.x), hi.y.max(p.y)),
            )),
        })
}

/// True when `p` is at least `need` from every wall and disc of the index's world.
pub fn clear_of(index: &WorldIndex, p: Point2, need: f64) -> bool {
    let world = index.world();
    let r = Vector2::new(need, need);
    let mut clear = true;
    index.near_box(p - r, p + r, |t| {
        if clear {
            let d = match t {
                Target::Wall(i) => distance_to_segment(p, world.walls[i].a, world.walls[i].b),
                Target::Disc(i) => (p - world.discs[i].centre).norm() - world.discs[i].radius,
            };
            clear = d >= need;
        }
    });
    clear
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flood_reaches_the_connected_cells_only() {
        // 4 x 3, a wall of closed cells in column 2 except the bottom row.
        #[rustfmt::skip]
        let ok = [
            true, true, false, true,
            true, true, false, true,
            true, true, true,  true,
        ];
        let mut reached = [false; 12];
        flood4(4, &ok, &[0], &mut reached);
        assert!(reached.iter().zip(ok).all(|(&r, o)| r == o));
        // Without the bottom row's opening, the right column stays unreached.
        let mut ok2 = ok;
        ok2[10] = false;
        let mut reached = [false; 12];
        flood4(4, &ok2, &[0], &mut reached);
        assert_eq!(reached.iter().filter(|&&r| r).count(), 6);
        assert!(!reached[3] && !reached[7] && !reached[11]);
    }

    #[test]
    fn extent_skips_non_finite_points() {
        let pts = [
            Point2::new(1.0, -2.0),
            Point2::new(f64::NAN, 0.0),
            Point2::new(-3.0, 4.0),
        ];
        let (lo, hi) = extent(pts.into_iter()).unwrap();
        assert_eq!((lo, hi), (Point2::new(-3.0, -2.0), Point2::new(1.0, 4.0)));
        assert_eq!(extent(std::iter::empty()), None);
    }
}
