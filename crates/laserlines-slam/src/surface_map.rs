//! A map of surface points that keeps growing, with nearest-neighbour queries in constant
//! time: the reference of a robot matching every scan onto everything it has seen
//! ([`crate::tracker::Tracker`]).
//!
//! Points are kept one per square voxel of side `cell_m` and *facing* (the quarter of the
//! circle its normal points into, so that the two faces of a thin wall stay apart), each the
//! weighted mean of the points that fell into it until their weights add up to
//! `max_weight`. A dense grid of the same cells, grown on demand, holds for every cell and
//! facing the point nearest to the cell's centre within `reach_m`: a query reads one cell.

use std::collections::HashMap;

use laserlines::math::{Point2, Vector2, floor_i64};

use crate::cloud::{FastHash, NearestSurface, SurfacePoint};

/// The grid grows in whole steps of this many cells along each axis.
const GROW_CELLS: usize = 64;
/// No point: an empty slot of the grid.
const NONE: u32 = u32::MAX;

/// What a voxel has summed.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Sums {
    weight: f64,
    x: f64,
    y: f64,
    nx: f64,
    ny: f64,
}

/// Surface points, one per voxel and facing, on a grid that answers "nearest point" in
/// constant time (see the [module docs](self)).
#[derive(Debug, Clone)]
pub struct SurfaceMap {
    cell: f64,
    reach: f64,
    max_weight: f64,
    max_cells: usize,
    points: Vec<SurfacePoint>,
    sums: Vec<Sums>,
    /// The point of each voxel and facing: `(i, j, facing)` on the lattice of `cell`
    /// through the origin.
    voxels: HashMap<(i32, i32, u8), u32, FastHash>,
    /// The lattice cell of the grid's first column and row.
    origin: (i64, i64),
    cols: usize,
    rows: usize,
    /// Per cell, per facing, the point nearest to the cell's centre within `reach`.
    near: Vec<[u32; 4]>,
}

impl SurfaceMap {
    /// An empty map of voxels of side `cell_m` (m), whose grid finds points within
    /// `reach_m` (m) of a cell's centre and grows to at most `max_extent_m` (m) along
    /// either axis (points beyond are not kept).
    #[must_use]
    pub fn new(cell_m: f64, reach_m: f64, max_weight: f64, max_extent_m: f64) -> Self {
        let cell = if cell_m.is_finite() {
            cell_m.max(1e-3)
        } else {
            0.05
        };
        let reach = if reach_m.is_finite() {
            reach_m.clamp(0.0, 100.0 * cell)
        } else {
            cell
        };
        let max_cells = if max_extent_m.is_finite() {
            (max_extent_m.max(0.0) / cell).min(1e5) as usize
        } else {
            GROW_CELLS
        };
        Self {
            cell,
            reach,
            max_weight: if max_weight > 0.0 { max_weight } else { 1.0 },
            max_cells,
            points: Vec::new(),
            sums: Vec::new(),
            voxels: HashMap::default(),
            origin: (0, 0),
            cols: 0,
            rows: 0,
            near: Vec::new(),
        }
    }

    /// Number of points (voxels and facings holding one).
    #[must_use]
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// True when the map holds no point.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The points, each the mean of its voxel's.
    #[must_use]
    pub fn points(&self) -> &[SurfacePoint] {
        &self.points
    }

    /// Side of a voxel and of a grid cell, m.
    #[must_use]
    pub fn cell_m(&self) -> f64 {
        self.cell
    }

    /// Adds a point of weight `weight` (> 0; e.g. the inverse variance of its range noise):
    /// it starts a voxel or moves that voxel's mean toward it, unless the voxel's weights
    /// already reach `max_weight`. Returns true when it started a voxel. Points with
    /// non-finite coordinates, normals or weights, and points the grid cannot grow to, are
    /// ignored.
    pub fn insert(&mut self, p: SurfacePoint, weight: f64) -> bool {
        let finite = p.point.x.is_finite()
            && p.point.y.is_finite()
            && p.normal.x.is_finite()
            && p.normal.y.is_finite();
        if !(finite && weight.is_finite() && weight > 0.0) {
            return false;
        }
        let (i, j) = self.lattice(p.point);
        let Some(key) = i32::try_from(i).ok().zip(i32::try_from(j).ok()) else {
            return false;
        };
        let facing = facing(p.normal);
        if let Some(&id) = self.voxels.get(&(key.0, key.1, facing)) {
            self.accumulate(id as usize, p, weight);
            return false;
        }
        if !self.ensure(i, j) {
            return false;
        }
        let Ok(id) = u32::try_from(self.points.len()) else {
            return false;
        };
        if id == NONE {
            return false;
        }
        self.voxels.insert((key.0, key.1, facing), id);
        self.points.push(p);
        self.sums.push(Sums {
            weight,
            x: weight * p.point.x,
            y: weight * p.point.y,
            nx: weight * p.normal.x,
            ny: weight * p.normal.y,
        });
        self.spread(id, i, j, facing);
        true
    }

    /// Moves the mean of voxel `id` toward `p`.
    fn accumulate(&mut self, id: usize, p: SurfacePoint, weight: f64) {
        let s = &mut self.sums[id];
        if s.weight >= self.max_weight {
            return;
        }
        s.weight += weight;
        s.x += weight * p.point.x;
        s.y += weight * p.point.y;
        s.nx += weight * p.normal.x;
        s.ny += weight * p.normal.y;
        let n = Vector2::new(s.nx, s.ny);
        let len = n.norm();
        let point = Point2::new(s.x / s.weight, s.y / s.weight);
        let q = &mut self.points[id];
        q.point = point;
        if len > 1e-9 {
            q.normal = n / len;
        }
    }

    /// Makes point `id` (in lattice cell `(i, j)`, `facing`) the nearest of the cells whose
    /// centres lie within the reach and hold no nearer point of that facing.
    fn spread(&mut self, id: u32, i: i64, j: i64, facing: u8) {
        let k = (self.reach / self.cell).ceil() as i64;
        let p = self.points[id as usize].point;
        let r2 = self.reach * self.reach;
        for dj in -k..=k {
            for di in -k..=k {
                let Some(c) = self.index(i + di, j + dj) else {
                    continue;
                };
                let centre = self.centre(i + di, j + dj);
                let d2 = (p - centre).norm_squared();
                if d2 > r2 {
                    continue;
                }
                let slot = &mut self.near[c][usize::from(facing)];
                if *slot == NONE || (self.points[*slot as usize].point - centre).norm_squared() > d2
                {
                    *slot = id;
                }
            }
        }
    }

    /// The lattice cell of `p`.
    fn lattice(&self, p: Point2) -> (i64, i64) {
        (floor_i64(p.x / self.cell), floor_i64(p.y / self.cell))
    }

    /// The centre of lattice cell `(i, j)`.
    fn centre(&self, i: i64, j: i64) -> Point2 {
        Point2::new((i as f64 + 0.5) * self.cell, (j as f64 + 0.5) * self.cell)
    }

    /// The grid index of lattice cell `(i, j)`, if the grid holds it.
    fn index(&self, i: i64, j: i64) -> Option<usize> {
        let (u, v) = (i.checked_sub(self.origin.0)?, j.checked_sub(self.origin.1)?);
        (u >= 0 && v >= 0 && (u as usize) < self.cols && (v as usize) < self.rows)
            .then(|| v as usize * self.cols + u as usize)
    }

    /// Grows the grid to hold lattice cell `(i, j)` and its reach; false when that would
    /// make it larger than its largest extent.
    fn ensure(&mut self, i: i64, j: i64) -> bool {
        let k = (self.reach / self.cell).ceil() as i64 + 1;
        let (lo_i, lo_j, hi_i, hi_j) = (
            i.saturating_sub(k),
            j.saturating_sub(k),
            i.saturating_add(k),
            j.saturating_add(k),
        );
        let empty = self.cols == 0;
        let (have_lo, have_hi) = (
            self.origin,
            (
                self.origin.0 + self.cols as i64 - 1,
                self.origin.1 + self.rows as i64 - 1,
            ),
        );
        if !empty
            && lo_i >= have_lo.0
            && lo_j >= have_lo.1
            && hi_i <= have_hi.0
            && hi_j <= have_hi.1
        {
            return true;
        }
        let step = GROW_CELLS as i64;
        let snap_lo = |v: i64| v.div_euclid(step).saturating_mul(step);
        let snap_hi = |v: i64| v.div_euclid(step).saturating_add(1).saturating_mul(step) - 1;
        let (mut lo, mut hi) = (
            (snap_lo(lo_i), snap_lo(lo_j)),
            (snap_hi(hi_i), snap_hi(hi_j)),
        );
        if !empty {
            lo = (lo.0.min(have_lo.0), lo.1.min(have_lo.1));
            hi = (hi.0.max(have_hi.0), hi.1.max(have_hi.1));
        }
        let (cols, rows) = (hi.0 - lo.0 + 1, hi.1 - lo.1 + 1);
        let too_big =
            |n: i64| usize::try_from(n).map_or(true, |n| n > self.max_cells.max(step as usize));
        if too_big(cols) || too_big(rows) {
            return false;
        }
        let (cols, rows) = (cols as usize, rows as usize);
        let mut near = vec![[NONE; 4]; cols * rows];
        if !empty {
            let di = (have_lo.0 - lo.0) as usize;
            let dj = (have_lo.1 - lo.1) as usize;
            for r in 0..self.rows {
                let from = r * self.cols;
                let to = (r + dj) * cols + di;
                near[to..to + self.cols].copy_from_slice(&self.near[from..from + self.cols]);
            }
        }
        self.origin = lo;
        self.cols = cols;
        self.rows = rows;
        self.near = near;
        true
    }
}

impl NearestSurface for SurfaceMap {
    /// The nearer of the points the query's cell holds for the query's facing and for the
    /// neighbouring facing its normal leans toward (every normal within 45 deg of the
    /// query's lies in one of the two), within `max_distance` of `q`.
    fn nearest_surface(
        &self,
        q: Point2,
        normal: Vector2,
        max_distance: f64,
    ) -> Option<SurfacePoint> {
        if !(q.x.is_finite() && q.y.is_finite()) {
            return None;
        }
        let (i, j) = self.lattice(q);
        let cell = &self.near[self.index(i, j)?];
        let (f, lean) = facings(normal);
        let r2 = max_distance * max_distance;
        let mut best = NONE;
        let mut best_d2 = f64::INFINITY;
        for slot in [cell[f], cell[lean]] {
            if slot == NONE {
                continue;
            }
            let d2 = (self.points[slot as usize].point - q).norm_squared();
            if d2 <= r2 && (best == NONE || d2 < best_d2) {
                best = slot;
                best_d2 = d2;
            }
        }
        (best != NONE).then(|| self.points[best as usize])
    }
}

/// The quarter of the circle a normal points into: 0 within 45 deg of +x, 1 of +y, 2 of -x,
/// 3 of -y.
fn facing(n: Vector2) -> u8 {
    // (u, v): the normal turned by -45 deg (and scaled by sqrt 2).
    let (u, v) = (n.x + n.y, n.y - n.x);
    match (u >= 0.0, v >= 0.0) {
        (true, false) => 0,
        (true, true) => 1,
        (false, true) => 2,
        (false, false) => 3,
    }
}

/// The normal's [`facing`] and the neighbouring facing it leans toward: the next one
/// counter-clockwise when the normal lies on or counter-clockwise of its facing's centre
/// direction, else the previous one.
#[inline]
fn facings(n: Vector2) -> (usize, usize) {
    let f = usize::from(facing(n));
    // The cross product of the facing's centre direction (+x, +y, -x, -y) with the normal.
    let ccw = match f {
        0 => n.y >= 0.0,
        1 => n.x <= 0.0,
        2 => n.y <= 0.0,
        _ => n.x >= 0.0,
    };
    (f, if ccw { (f + 1) % 4 } else { (f + 3) % 4 })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sp(x: f64, y: f64, nx: f64, ny: f64) -> SurfacePoint {
        SurfacePoint {
            point: Point2::new(x, y),
            normal: Vector2::new(nx, ny).normalize(),
        }
    }

    #[test]
    fn the_lean_is_the_side_of_the_facings_centre_the_normal_lies_on() {
        // Every degree, and the axes' signed zeros.
        let mut normals: Vec<Vector2> = (0..360)
            .map(|d| {
                let a = f64::from(d).to_radians();
                Vector2::new(a.cos(), a.sin())
            })
            .collect();
        normals.extend([
            Vector2::new(1.0, 0.0),
            Vector2::new(1.0, -0.0),
            Vector2::new(0.0, 1.0),
            Vector2::new(-0.0, 1.0),
            Vector2::new(-1.0, 0.0),
            Vector2::new(-1.0, -0.0),
            Vector2::new(0.0, -1.0),
            Vector2::new(-0.0, -1.0),
        ]);
        for n in normals {
            let (f, lean) = facings(n);
            let (cx, cy): (f64, f64) = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][f];
            let expected = if cx * n.y - cy * n.x >= 0.0 {
                (f + 1) % 4
            } else {
                (f + 3) % 4
            };
            assert_eq!(lean, expected, "{n:?}");
            assert_eq!(f, usize::from(facing(n)));
        }
    }

    #[test]
    fn facings_split_the_circle_in_quarters() {
        for (deg, f) in [
            (0.0, 0),
            (44.0, 0),
            (46.0, 1),
            (134.0, 1),
            (136.0, 2),
            (-136.0, 2),
            (-134.0, 3),
            (-46.0, 3),
            (-44.0, 0),
        ] {
            let a: f64 = f64::to_radians(deg);
            assert_eq!(facing(Vector2::new(a.cos(), a.sin())), f, "{deg}");
        }
    }

    /// The grid's answer is the exhaustive search's wherever the nearest point of a facing
    /// lies well within the reach of the cell's centre.
    #[test]
    fn nearest_matches_an_exhaustive_search_along_walls() {
        let mut map = SurfaceMap::new(0.05, 0.15, 40.0, 100.0);
        // Two walls of a corner and the two faces of a thin wall.
        let mut all = Vec::new();
        for k in 0..60 {
            let t = f64::from(k) * 0.037;
            all.push(sp(t, 0.0, 0.0, 1.0));
            all.push(sp(0.0, t, 1.0, 0.0));
            all.push(sp(1.0 + t, 1.5, 0.0, 1.0));
            all.push(sp(1.0 + t, 1.5, 0.0, -1.0));
        }
        for &p in &all {
            map.insert(p, 1.0);
        }
        // Two faces in one voxel stay two points.
        assert!(map.len() > 4 * 40, "{}", map.len());
        for (q, n) in [
            (Point2::new(0.5, 0.03), Vector2::new(0.0, 1.0)),
            (Point2::new(0.04, 1.0), Vector2::new(1.0, 0.0)),
            (Point2::new(2.0, 1.53), Vector2::new(0.0, 1.0)),
            (Point2::new(2.0, 1.47), Vector2::new(0.0, -1.0)),
            (Point2::new(2.0, 1.47), Vector2::new(0.3, -1.0).normalize()),
        ] {
            let got = map.nearest_surface(q, n, 0.1).unwrap();
            assert!(got.normal.dot(&n) > 0.7, "{q:?}: {got:?}");
            // The wall it belongs to is the query's: within 3 cm of its line, and no
            // point of that face is more than a cell nearer.
            let best = map
                .points()
                .iter()
                .filter(|p| p.normal.dot(&n) > 0.7)
                .map(|p| (p.point - q).norm())
                .fold(f64::INFINITY, f64::min);
            assert!((got.point - q).norm() <= best + 0.05, "{q:?}: {got:?}");
        }
        // Far from everything: nothing.
        assert!(
            map.nearest_surface(Point2::new(5.0, 5.0), Vector2::new(1.0, 0.0), 0.1)
                .is_none()
        );
        assert!(
            map.nearest_surface(Point2::new(0.5, 0.3), Vector2::new(0.0, 1.0), 0.1)
                .is_none()
        );
    }

    #[test]
    fn a_voxel_averages_its_points_up_to_its_weight() {
        let mut map = SurfaceMap::new(0.05, 0.1, 3.0, 100.0);
        assert!(map.insert(sp(0.01, 0.02, 0.0, 1.0), 1.0));
        assert!(!map.insert(sp(0.03, 0.02, 0.0, 1.0), 1.0));
        assert!(!map.insert(sp(0.02, 0.04, 0.0, 1.0), 2.0));
        // Full: the next one changes nothing.
        assert!(!map.insert(sp(0.04, 0.04, 0.0, 1.0), 1.0));
        assert_eq!(map.len(), 1);
        let p = map.points()[0].point;
        assert!(
            (p.x - 0.02).abs() < 1e-12 && (p.y - 0.03).abs() < 1e-12,
            "{p:?}"
        );
    }

    #[test]
    fn growing_keeps_what_the_grid_held_and_refuses_beyond_its_extent() {
        let mut map = SurfaceMap::new(0.05, 0.1, 10.0, 20.0);
        assert!(map.insert(sp(0.0, 0.0, 1.0, 0.0), 1.0));
        assert!(map.insert(sp(-9.0, 9.0, 1.0, 0.0), 1.0));
        let q = map.nearest_surface(Point2::new(0.02, 0.0), Vector2::new(1.0, 0.0), 0.1);
        assert_eq!(q.map(|p| p.point), Some(Point2::new(0.0, 0.0)));
        assert!(!map.insert(sp(30.0, 0.0, 1.0, 0.0), 1.0));
        assert!(!map.insert(sp(f64::NAN, 0.0, 1.0, 0.0), 1.0));
        assert!(!map.insert(sp(1e300, 0.0, 1.0, 0.0), 1.0));
        assert!(!map.insert(sp(1.0, 0.0, 1.0, 0.0), f64::NAN));
        assert_eq!(map.len(), 2);
        assert!(
            map.nearest_surface(Point2::new(1e300, 0.0), Vector2::new(1.0, 0.0), 0.1)
                .is_none()
        );
    }
}
