//! Where an arena is: the area its walls enclose once gaps a wall element wide are closed,
//! and the bounding box of its largest group of walls.
//!
//! Arena files leave gaps in their outer walls (entrances, a missing element) and sometimes
//! hold a stray element far from the rest. The *outline* closes every gap up to
//! [`SEAL_GAP`] = 1.3 m (one 1.2 m wall element and a little): on a grid of
//! [`OUTLINE_CELL`] = 0.1 m cells over the world and 1 m around it, the outside is what a
//! disc of diameter [`SEAL_GAP`] reaches from the grid's edge without touching a wall or
//! disc; the arena is everything else. It cannot enter the arenas' 1.2 m corridors either,
//! so an arena whose outline is broken by a wider gap keeps its corridors and small rooms
//! and loses only the open floor the gap leads into. The *bounds* are the bounding box of
//! the largest group of walls and discs, obstacles less than [`SEAL_GAP`] apart joined in
//! one group, so that a stray wall (`rc_2015_arena_big.raf` has one 19 m east of the rest)
//! does not stretch them.

use laserlines::geometry::distance_to_segment;
use laserlines::math::{Point2, Vector2};

use crate::cells::{clear_of, extent, flood4, for_each_neighbour4};
use crate::index::WorldIndex;
use crate::world::World;

/// Widest gap the outline closes, m.
pub const SEAL_GAP: f64 = 1.3;

/// Side of the outline's grid cells, m.
pub const OUTLINE_CELL: f64 = 0.1;

/// Margin of the outline's grid around the world, m.
const MARGIN: f64 = 1.0;

/// The outline of an arena (see the [module docs](self)).
///
/// ```
/// use laserlines_sim::World;
/// use laserlines_sim::arena::ArenaOutline;
/// use laserlines::math::Point2;
/// // A 6 m x 4 m room with a 1 m door in one wall, and a stray wall far off.
/// let mut world = World::new();
/// world.add_segment(Point2::new(0.0, 0.0), Point2::new(6.0, 0.0));
/// world.add_segment(Point2::new(6.0, 0.0), Point2::new(6.0, 4.0));
/// world.add_segment(Point2::new(6.0, 4.0), Point2::new(0.0, 4.0));
/// world.add_segment(Point2::new(0.0, 4.0), Point2::new(0.0, 2.5));
/// world.add_segment(Point2::new(0.0, 1.5), Point2::new(0.0, 0.0));
/// world.add_segment(Point2::new(30.0, 0.0), Point2::new(30.0, 1.2));
/// let outline = ArenaOutline::new(&world);
/// assert!(outline.encloses(Point2::new(0.5, 2.0)));
/// assert!(!outline.encloses(Point2::new(-0.5, 2.0)));
/// let (lo, hi) = outline.bounds().unwrap();
/// assert_eq!((lo.x, hi.x), (0.0, 6.0));
/// ```
#[derive(Debug, Clone)]
pub struct ArenaOutline {
    origin: Point2,
    cols: usize,
    rows: usize,
    inside: Vec<bool>,
    bounds: Option<(Point2, Point2)>,
}

impl ArenaOutline {
    /// The outline of `world`.
    #[must_use]
    pub fn new(world: &World) -> Self {
        Self::of_index(&WorldIndex::new(world, 0.6))
    }

    /// The outline of the index's world.
    #[must_use]
    pub fn of_index(index: &WorldIndex) -> Self {
        let world = index.world();
        let all = extent(obstacle_points(world));
        let (lo, hi) = all.unwrap_or((Point2::origin(), Point2::origin()));
        let origin = Point2::new(lo.x - MARGIN, lo.y - MARGIN);
        let cols = (((hi.x - lo.x + 2.0 * MARGIN) / OUTLINE_CELL).ceil() as usize).clamp(1, 4000);
        let rows = (((hi.y - lo.y + 2.0 * MARGIN) / OUTLINE_CELL).ceil() as usize).clamp(1, 4000);
        let mut outline = Self {
            origin,
            cols,
            rows,
            inside: Vec::new(),
            bounds: largest_group_bounds(world),
        };
        let open: Vec<bool> = (0..cols * rows)
            .map(|c| clear_of(index, outline.centre(c), 0.5 * SEAL_GAP))
            .collect();
        outline.inside = outline.not_reached_from_edge(&open);
        outline
    }

    /// True when `p` lies within the outline: the walls, gaps up to [`SEAL_GAP`] closed,
    /// enclose it.
    #[must_use]
    pub fn encloses(&self, p: Point2) -> bool {
        self.cell_of(p).is_some_and(|c| self.inside[c])
    }

    /// The bounding box of the largest group of walls and discs (see the
    /// [module docs](self)); `None` for an empty world.
    #[must_use]
    pub fn bounds(&self) -> Option<(Point2, Point2)> {
        self.bounds
    }

    /// True when `p` lies in [`ArenaOutline::bounds`].
    #[must_use]
    pub fn within_bounds(&self, p: Point2) -> bool {
        self.bounds
            .is_some_and(|(lo, hi)| p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y)
    }

    fn centre(&self, c: usize) -> Point2 {
        Point2::new(
            self.origin.x + ((c % self.cols) as f64 + 0.5) * OUTLINE_CELL,
            self.origin.y + ((c / self.cols) as f64 + 0.5) * OUTLINE_CELL,
        )
    }

    fn cell_of(&self, p: Point2) -> Option<usize> {
        let fx = ((p.x - self.origin.x) / OUTLINE_CELL).floor();
        let fy = ((p.y - self.origin.y) / OUTLINE_CELL).floor();
        if !(fx >= 0.0 && fy >= 0.0 && fx < self.cols as f64 && fy < self.rows as f64) {
            return None;
        }
        Some(fy as usize * self.cols + fx as usize)
    }

    /// The cells outside no disc of diameter [`SEAL_GAP`] reaches from the grid's edge: the
    /// `open` cells (centres at least its radius from every obstacle) reached from the edge
    /// (4-neighbours), each grown by that radius.
    fn not_reached_from_edge(&self, open: &[bool]) -> Vec<bool> {
        let (cols, rows) = (self.cols, self.rows);
        let mut reached = vec![false; cols * rows];
        let edge: Vec<usize> = (0..cols * rows)
            .filter(|&c| {
                let (x, y) = (c % cols, c / cols);
                open[c] && (x == 0 || y == 0 || x + 1 == cols || y + 1 == rows)
            })
            .collect();
        flood4(cols, open, &edge, &mut reached);
        // Grow the reached centres by the disc's radius: stamp the disc around every reached
        // cell on the edge of the reached area.
        let r = 0.5 * SEAL_GAP / OUTLINE_CELL;
        let k = r.floor() as i64;
        let stencil: Vec<(i64, i64)> = (-k..=k)
            .flat_map(|dy| (-k..=k).map(move |dx| (dx, dy)))
            .filter(|&(dx, dy)| ((dx * dx + dy * dy) as f64) <= r * r)
            .collect();
        let mut outside = reached.clone();
        for c in 0..cols * rows {
            let mut edge = false;
            if reached[c] {
                for_each_neighbour4(c, cols, rows, |n| edge |= !reached[n]);
            }
            if !edge {
                continue;
            }
            let (x, y) = ((c % cols) as i64, (c / cols) as i64);
            for &(dx, dy) in &stencil {
                let (nx, ny) = (x + dx, y + dy);
                if nx >= 0 && ny >= 0 && nx < cols as i64 && ny < rows as i64 {
                    outside[ny as usize * cols + nx as usize] = true;
                }
            }
        }
        outside.iter().map(|o| !o).collect()
    }
}

/// The end points of the walls and the centres of the discs.
fn obstacle_points(world: &World) -> impl Iterator<Item = Point2> + '_ {
    world
        .walls
        .iter()
        .flat_map(|w| [w.a, w.b])
        .chain(world.discs.iter().map(|d| d.centre))
}

/// One obstacle as the grouping sees it: a segment (a disc is a point with a radius).
#[derive(Clone, Copy)]
struct Piece {
    a: Point2,
    b: Point2,
    radius: f64,
}

impl Piece {
    /// The distance between two pieces, from the ends of each to the other (exact for
    /// segments that do not cross; crossing ones are near anyway in an arena of 1.2 m
    /// elements).
    fn gap(&self, o: &Piece) -> f64 {
        let d = distance_to_segment(self.a, o.a, o.b)
            .min(distance_to_segment(self.b, o.a, o.b))
            .min(distance_to_segment(o.a, self.a, self.b))
            .min(distance_to_segment(o.b, self.a, self.b));
        (d - self.radius - o.radius).max(0.0)
    }
}

/// The bounding box of the largest group of walls and discs (most obstacles; pieces less
/// than [`SEAL_GAP`] apart in one group).
fn largest_group_bounds(world: &World) -> Option<(Point2, Point2)> {
    let finite = |p: Point2| p.x.is_finite() && p.y.is_finite();
    let pieces: Vec<Piece> = world
        .walls
        .iter()
        .filter(|w| finite(w.a) && finite(w.b))
        .map(|w| Piece {
            a: w.a,
            b: w.b,
            radius: 0.0,
        })
        .chain(
            world
                .discs
                .iter()
                .filter(|d| finite(d.centre) && d.radius.is_finite())
                .map(|d| Piece {
                    a: d.centre,
                    b: d.centre,
                    radius: d.radius.max(0.0),
                }),
        )
        .collect();
    let n = pieces.len();
    let mut parent: Vec<usize> = (0..n).collect();
    fn find(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    let boxes: Vec<(Point2, Point2)> = pieces
        .iter()
        .map(|q| {
            let r = q.radius + SEAL_GAP;
            (
                Point2::new(q.a.x.min(q.b.x) - r, q.a.y.min(q.b.y) - r),
                Point2::new(q.a.x.max(q.b.x) + r, q.a.y.max(q.b.y) + r),
            )
        })
        .collect();
    for i in 0..n {
        for j in i + 1..n {
            let (bi, bj) = (boxes[i], boxes[j]);
            let overlap =
                bi.0.x <= bj.1.x && bj.0.x <= bi.1.x && bi.0.y <= bj.1.y && bj.0.y <= bi.1.y;
            if overlap && pieces[i].gap(&pieces[j]) < SEAL_GAP {
                let (ri, rj) = (find(&mut parent, i), find(&mut parent, j));
                if ri != rj {
                    parent[ri] = rj;
                }
            }
        }
    }
    let mut size = vec![0usize; n];
    for i in 0..n {
        let r = find(&mut parent, i);
        size[r] += 1;
    }
    let best = (0..n).max_by_key(|&r| (size[r], std::cmp::Reverse(r)))?;
    let members = (0..n)
        .filter(|&i| find(&mut parent, i) == best)
        .collect::<Vec<_>>();
    extent(members.iter().flat_map(|&i| {
        let q = pieces[i];
        let r = Vector2::new(q.radius, q.radius);
        [q.a - r, q.a + r, q.b - r, q.b + r]
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn corridors_stay_inside_when_the_outline_is_broken() {
        // A 1.2 m corridor leading from a room with a 3 m gap in its far wall: the open
        // room floods from outside, the corridor does not.
        let mut w = World::new();
        // Corridor from x = 0 to 6 between y = 0 and 1.2, closed at x = 0.
        w.add_segment(Point2::new(0.0, 0.0), Point2::new(6.0, 0.0));
        w.add_segment(Point2::new(0.0, 1.2), Point2::new(6.0, 1.2));
        w.add_segment(Point2::new(0.0, 0.0), Point2::new(0.0, 1.2));
        // Room from x = 6 to 12, y from -2 to 3.2, its east wall with a 3 m gap.
        w.add_segment(Point2::new(6.0, 1.2), Point2::new(6.0, 3.2));
        w.add_segment(Point2::new(6.0, 0.0), Point2::new(6.0, -2.0));
        w.add_segment(Point2::new(6.0, 3.2), Point2::new(12.0, 3.2));
        w.add_segment(Point2::new(6.0, -2.0), Point2::new(12.0, -2.0));
        w.add_segment(Point2::new(12.0, 3.2), Point2::new(12.0, 2.1));
        w.add_segment(Point2::new(12.0, -2.0), Point2::new(12.0, -0.9));
        let o = ArenaOutline::new(&w);
        assert!(o.encloses(Point2::new(3.0, 0.6)));
        assert!(!o.encloses(Point2::new(9.0, 0.6)));
        assert!(o.within_bounds(Point2::new(9.0, 0.6)));
        assert!(!o.within_bounds(Point2::new(13.0, 0.6)));
    }

    #[test]
    fn empty_worlds_have_no_bounds_and_enclose_nothing() {
        let o = ArenaOutline::new(&World::new());
        assert!(o.bounds().is_none());
        assert!(!o.encloses(Point2::origin()));
        assert!(!o.within_bounds(Point2::origin()));
    }
}
