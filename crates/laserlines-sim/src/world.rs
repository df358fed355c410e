//! The simulated world: wall segments and small round obstacles, and exact ray casting.
//!
//! Walls have no thickness and are seen from both sides. A ray that runs exactly along a
//! wall meets it at the wall's nearer end (the beam hits the wall end-on). A ray that starts
//! on a wall, or inside a disc, hits at range 0.

use std::ops::Range;

use laserlines::geometry::{circle_ray_hit, distance_to_segment, segment_ray_hit_prepared};
use laserlines::math::{Isometry2, Point2, Vector2};

/// Hits closer to each other than this (m) are a tie, won by the earlier obstacle.
const TIE_TOLERANCE: f64 = 1e-12;

/// A wall: a straight segment from `a` to `b`, metres, world frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wall {
    /// One end, m.
    pub a: Point2,
    /// The other end, m.
    pub b: Point2,
}

impl Wall {
    /// A wall from `a` to `b`.
    #[must_use]
    pub const fn new(a: Point2, b: Point2) -> Self {
        Self { a, b }
    }

    /// Length of the wall, m.
    #[must_use]
    pub fn length(&self) -> f64 {
        (self.b - self.a).norm()
    }

    /// The wall's infinite line in normal form `x cos(alpha) + y sin(alpha) = r` in the frame
    /// `frame_from_world` maps into (e.g. `laser_from_world`): `(r, alpha)` with `r >= 0` (m)
    /// and `alpha` in `(-pi, pi]` (rad). `None` for a wall of zero length or with
    /// non-finite ends.
    ///
    /// When the line passes exactly through the frame's origin (`r = 0`), `alpha` is one of
    /// the two opposite normals.
    #[must_use]
    pub fn polar_in(&self, frame_from_world: &Isometry2) -> Option<(f64, f64)> {
        let a = frame_from_world * self.a;
        let b = frame_from_world * self.b;
        polar_line(a, b)
    }

    /// Distance of the ray parameter `t` (m along the unit direction `dir` from `origin`) at
    /// which the ray meets this wall, if it does.
    fn ray_hit(&self, origin: Point2, dir: Vector2) -> Option<f64> {
        let e = self.b - self.a;
        let len = e.norm();
        if !(len > 0.0 && len.is_finite()) {
            return None;
        }
        segment_ray_hit_prepared(self.a, self.b, e, len, origin, dir)
    }
}

/// The normal form of the line through two points (the core's, where the simulator's
/// callers have always found it).
pub use laserlines::geometry::polar_line;

/// A small round obstacle (a table or chair leg, a person's leg, a barrel): a circle,
/// metres, world frame. Discs with a radius that is not positive and finite are never hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Disc {
    /// Centre, m.
    pub centre: Point2,
    /// Radius, m.
    pub radius: f64,
}

impl Disc {
    /// A disc of `radius` (m) around `centre`.
    #[must_use]
    pub const fn new(centre: Point2, radius: f64) -> Self {
        Self { centre, radius }
    }

    fn ray_hit(&self, origin: Point2, dir: Vector2) -> Option<f64> {
        circle_ray_hit(self.centre, self.radius, origin, dir)
    }
}

/// What a ray hit: an index into [`World::walls`] or [`World::discs`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Target {
    /// The wall with this index.
    Wall(usize),
    /// The disc with this index.
    Disc(usize),
}

/// The nearest intersection of a ray with the world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// Distance from the ray's origin, m (`>= 0`).
    pub range: f64,
    /// The hit point, m, world frame.
    pub point: Point2,
    /// What was hit.
    pub target: Target,
}

/// A 2D world of walls (segments) and discs (round obstacles), metres, world frame.
///
/// ```
/// use laserlines_sim::{Target, World};
/// use laserlines::math::Point2;
/// let mut world = World::new();
/// world.add_segment(Point2::new(2.0, -1.0), Point2::new(2.0, 1.0));
/// let hit = world.cast(Point2::origin(), 0.0, 10.0).unwrap();
/// assert!((hit.range - 2.0).abs() < 1e-12);
/// assert_eq!(hit.target, Target::Wall(0));
/// ```
#[derive(Debug, Clone, PartialEq, Default)]
pub struct World {
    /// The walls.
    pub walls: Vec<Wall>,
    /// The round obstacles.
    pub discs: Vec<Disc>,
}

impl World {
    /// An empty world.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a wall from `a` to `b`; returns its index in [`World::walls`].
    pub fn add_segment(&mut self, a: Point2, b: Point2) -> usize {
        self.walls.push(Wall::new(a, b));
        self.walls.len() - 1
    }

    /// Adds a closed polygon: one wall per edge, including the edge from the last corner back
    /// to the first. Two corners give a single wall, fewer give none. Returns the indices of
    /// the walls added; wall `k` of the polygon runs from corner `k` to corner `k + 1`.
    pub fn add_polygon(&mut self, corners: &[Point2]) -> Range<usize> {
        let start = self.walls.len();
        match corners.len() {
            0 | 1 => {}
            2 => {
                self.add_segment(corners[0], corners[1]);
            }
            n => {
                for k in 0..n {
                    self.add_segment(corners[k], corners[(k + 1) % n]);
                }
            }
        }
        start..self.walls.len()
    }

    /// Adds a rectangular box (four walls, counter-clockwise) centred at `centre`, `size_x`
    /// by `size_y` metres along its own axes, rotated by `yaw` (rad). Returns the indices of
    /// the four walls.
    pub fn add_box(&mut self, centre: Point2, size_x: f64, size_y: f64, yaw: f64) -> Range<usize> {
        self.add_polygon(&box_corners(centre, size_x, size_y, yaw))
    }

    /// Adds a disc of `radius` (m) at `centre`; returns its index in [`World::discs`].
    pub fn add_disc(&mut self, centre: Point2, radius: f64) -> usize {
        self.discs.push(Disc::new(centre, radius));
        self.discs.len() - 1
    }

    /// Casts a ray from `origin` (world frame) at `angle` (rad, world frame) and returns the
    /// nearest wall or disc within `max_range` (m, inclusive), if any.
    ///
    /// Intersections are exact (ray-segment, ray-circle). Ties within 1e-12 m (e.g. a corner
    /// where two walls meet) go to the wall, or disc, with the lower index, walls before
    /// discs. A ray along a
    /// wall's own line hits the wall's nearer end; an origin on a wall or inside a disc gives
    /// range 0. Non-finite inputs or a negative or NaN `max_range` give `None`; the result
    /// never holds NaN.
    #[must_use]
    pub fn cast(&self, origin: Point2, angle: f64, max_range: f64) -> Option<Hit> {
        let finite = origin.x.is_finite() && origin.y.is_finite() && angle.is_finite();
        if !finite || max_range.is_nan() || max_range < 0.0 {
            return None;
        }
        let (s, c) = angle.sin_cos();
        let dir = Vector2::new(c, s);
        let mut best: Option<(f64, Target)> = None;
        let mut consider = |t: Option<f64>, target: Target| {
            if let Some(t) = t
                && t.is_finite()
                && t <= max_range
                && best.is_none_or(|(bt, _)| t < bt - TIE_TOLERANCE)
            {
                best = Some((t, target));
            }
        };
        for (i, w) in self.walls.iter().enumerate() {
            consider(w.ray_hit(origin, dir), Target::Wall(i));
        }
        for (i, d) in self.discs.iter().enumerate() {
            consider(d.ray_hit(origin, dir), Target::Disc(i));
        }
        let (range, target) = best?;
        let point = origin + dir * range;
        if !(point.x.is_finite() && point.y.is_finite()) {
            return None;
        }
        Some(Hit {
            range,
            point,
            target,
        })
    }

    /// Distance from `p` to the nearest obstacle, m: the nearest wall, or the rim of the
    /// nearest disc (negative inside a disc). `+inf` in an empty world.
    #[must_use]
    pub fn clearance(&self, p: Point2) -> f64 {
        let walls = self
            .walls
            .iter()
            .map(|w| distance_to_segment(p, w.a, w.b))
            .filter(|d| !d.is_nan());
        let discs = self
            .discs
            .iter()
            .filter(|d| d.radius > 0.0)
            .map(|d| (p - d.centre).norm() - d.radius)
            .filter(|d| !d.is_nan());
        walls.chain(discs).fold(f64::INFINITY, f64::min)
    }

    /// True when `p` is at least `min_clearance` metres from every wall and disc.
    #[must_use]
    pub fn is_free(&self, p: Point2, min_clearance: f64) -> bool {
        p.x.is_finite() && p.y.is_finite() && self.clearance(p) >= min_clearance
    }

    /// True when every one of `rays` rays cast from `p` over the full turn hits something
    /// within `max_range` (m): `p` is enclosed (a point inside a closed room, not in the
    /// open). `false` for zero rays.
    #[must_use]
    pub fn encloses(&self, p: Point2, rays: usize, max_range: f64) -> bool {
        rays > 0
            && (0..rays).all(|k| {
                let angle = -std::f64::consts::PI + std::f64::consts::TAU * k as f64 / rays as f64;
                self.cast(p, angle, max_range).is_some()
            })
    }
}

/// The corners of a box, counter-clockwise, `size_x` by `size_y` metres centred at `centre`
/// and rotated by `yaw` (rad).
#[must_use]
pub fn box_corners(centre: Point2, size_x: f64, size_y: f64, yaw: f64) -> [Point2; 4] {
    let (s, c) = yaw.sin_cos();
    let ux = Vector2::new(c, s) * (size_x / 2.0);
    let uy = Vector2::new(-s, c) * (size_y / 2.0);
    [
        centre - ux - uy,
        centre + ux - uy,
        centre + ux + uy,
        centre - ux + uy,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI, SQRT_2};

    fn p(x: f64, y: f64) -> Point2 {
        Point2::new(x, y)
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn perpendicular_wall_is_hit_at_its_distance() {
        let mut w = World::new();
        w.add_segment(p(2.0, -1.0), p(2.0, 1.0));
        let h = w.cast(p(0.0, 0.0), 0.0, 10.0).unwrap();
        assert!(close(h.range, 2.0));
        assert!(close(h.point.x, 2.0) && close(h.point.y, 0.0));
        assert_eq!(h.target, Target::Wall(0));
        // Seen from the other side too (walls are two-sided).
        let h = w.cast(p(5.0, 0.5), PI, 10.0).unwrap();
        assert!(close(h.range, 3.0) && close(h.point.y, 0.5));
    }

    #[test]
    fn oblique_wall_is_hit_where_the_lines_cross() {
        // The wall lies on y = x - 2.
        let mut w = World::new();
        w.add_segment(p(1.0, -1.0), p(3.0, 1.0));
        let h = w.cast(p(0.0, 0.0), 0.0, 10.0).unwrap();
        assert!(close(h.range, 2.0) && close(h.point.x, 2.0) && close(h.point.y, 0.0));
        // Straight up from (2.5, -3): meets y = 0.5 at range 3.5.
        let h = w.cast(p(2.5, -3.0), FRAC_PI_2, 10.0).unwrap();
        assert!(close(h.range, 3.5) && close(h.point.y, 0.5));
        // At -45 deg from the origin the ray ends exactly on the wall's end (1, -1).
        let h = w.cast(p(0.0, 0.0), -FRAC_PI_4, 10.0).unwrap();
        assert!((h.range - SQRT_2).abs() < 1e-9);
        // Just past the end: no hit.
        assert!(w.cast(p(0.0, 0.0), -FRAC_PI_4 - 1e-6, 10.0).is_none());
    }

    #[test]
    fn disc_is_hit_on_its_near_rim() {
        let mut w = World::new();
        w.add_disc(p(3.0, 0.0), 0.5);
        let h = w.cast(p(0.0, 0.0), 0.0, 10.0).unwrap();
        assert!(close(h.range, 2.5) && h.target == Target::Disc(0));
        // A ray at offset 0.3 from the centre: range 3 - sqrt(0.25 - 0.09) = 2.6.
        let h = w.cast(p(0.0, 0.3), 0.0, 10.0).unwrap();
        assert!((h.range - 2.6).abs() < 1e-12 && close(h.point.y, 0.3));
        // Tangent ray at offset 0.5 touches at x = 3; just outside misses.
        let h = w.cast(p(0.0, 0.5), 0.0, 10.0).unwrap();
        assert!((h.range - 3.0).abs() < 1e-9);
        assert!(w.cast(p(0.0, 0.500_001), 0.0, 10.0).is_none());
        // Pointing away: no hit. From inside: range 0.
        assert!(w.cast(p(0.0, 0.0), PI, 10.0).is_none());
        let h = w.cast(p(3.1, 0.0), 1.0, 10.0).unwrap();
        assert!(close(h.range, 0.0));
    }

    #[test]
    fn corner_goes_to_the_first_wall_at_equal_range() {
        let mut w = World::new();
        w.add_segment(p(2.0, 0.0), p(2.0, 2.0));
        w.add_segment(p(2.0, 2.0), p(0.0, 2.0));
        let h = w.cast(p(0.0, 0.0), FRAC_PI_4, 10.0).unwrap();
        assert!((h.range - 2.0 * SQRT_2).abs() < 1e-9);
        assert!((h.point.x - 2.0).abs() < 1e-9 && (h.point.y - 2.0).abs() < 1e-9);
        assert_eq!(h.target, Target::Wall(0));
        // Either side of the corner goes to the wall on that side.
        assert_eq!(
            w.cast(p(0.0, 0.0), FRAC_PI_4 - 0.01, 10.0).unwrap().target,
            Target::Wall(0)
        );
        assert_eq!(
            w.cast(p(0.0, 0.0), FRAC_PI_4 + 0.01, 10.0).unwrap().target,
            Target::Wall(1)
        );
    }

    #[test]
    fn parallel_rays_hit_only_along_the_wall_line() {
        let mut w = World::new();
        w.add_segment(p(1.0, 0.0), p(3.0, 0.0));
        // Along the wall's line: meets the near end edge-on.
        let h = w.cast(p(0.0, 0.0), 0.0, 10.0).unwrap();
        assert!(close(h.range, 1.0) && h.target == Target::Wall(0));
        // From beyond the far end going back: meets the end at (3, 0).
        let h = w.cast(p(5.0, 0.0), PI, 10.0).unwrap();
        assert!((h.range - 2.0).abs() < 1e-12);
        // Parallel but offset: no hit, no NaN.
        assert!(w.cast(p(0.0, 0.5), 0.0, 10.0).is_none());
        // Along the line, pointing away from the wall: no hit.
        assert!(w.cast(p(0.0, 0.0), PI, 10.0).is_none());
    }

    #[test]
    fn origin_on_a_wall_hits_at_range_zero() {
        let mut w = World::new();
        w.add_segment(p(-1.0, 0.0), p(1.0, 0.0));
        for angle in [FRAC_PI_2, -FRAC_PI_2, 0.0, PI, 0.3] {
            let h = w.cast(p(0.0, 0.0), angle, 10.0).unwrap();
            assert!(close(h.range, 0.0), "angle {angle}: {h:?}");
            assert!(h.point.x.is_finite() && h.point.y.is_finite());
        }
    }

    #[test]
    fn no_hit_cases_return_none() {
        let mut w = World::new();
        w.add_segment(p(2.0, -1.0), p(2.0, 1.0));
        w.add_disc(p(-3.0, 0.0), 0.2);
        // Away from everything, above the wall, beyond max_range, bad inputs.
        assert!(w.cast(p(0.0, 0.0), FRAC_PI_2, 10.0).is_none());
        assert!(w.cast(p(0.0, 0.0), 0.6, 10.0).is_none());
        assert!(w.cast(p(0.0, 0.0), 0.0, 1.99).is_none());
        assert!(w.cast(p(0.0, 0.0), 0.0, 2.0).is_some());
        assert!(w.cast(p(0.0, 0.0), f64::NAN, 10.0).is_none());
        assert!(w.cast(p(f64::NAN, 0.0), 0.0, 10.0).is_none());
        assert!(w.cast(p(0.0, 0.0), 0.0, f64::NAN).is_none());
        assert!(w.cast(p(0.0, 0.0), 0.0, -1.0).is_none());
        assert!(w.cast(p(0.0, 0.0), 0.0, f64::INFINITY).is_some());
        assert!(World::new().cast(p(0.0, 0.0), 0.0, 10.0).is_none());
    }

    #[test]
    fn nearest_hit_wins_whatever_the_order() {
        let mut w = World::new();
        w.add_segment(p(3.0, -1.0), p(3.0, 1.0));
        w.add_disc(p(2.5, 0.0), 0.1);
        w.add_segment(p(2.0, -1.0), p(2.0, 1.0));
        let h = w.cast(p(0.0, 0.0), 0.0, 10.0).unwrap();
        assert_eq!(h.target, Target::Wall(1));
        assert!(close(h.range, 2.0));
        let h = w.cast(p(2.1, 0.0), 0.0, 10.0).unwrap();
        assert_eq!(h.target, Target::Disc(0));
        assert!((h.range - 0.3).abs() < 1e-12);
    }

    #[test]
    fn degenerate_and_non_finite_obstacles_are_ignored() {
        let mut w = World::new();
        w.add_segment(p(1.0, 0.0), p(1.0, 0.0));
        w.add_segment(p(f64::NAN, 0.0), p(2.0, 1.0));
        w.add_segment(p(f64::INFINITY, -1.0), p(2.0, 1.0));
        w.add_disc(p(2.0, 0.0), 0.0);
        w.add_disc(p(2.0, 0.0), f64::NAN);
        w.add_disc(p(f64::NAN, 0.0), 1.0);
        for k in 0..64 {
            assert!(w.cast(p(0.0, 0.0), k as f64 * 0.1, 10.0).is_none());
        }
        assert!(w.clearance(p(0.0, 0.0)) >= 0.0);
    }

    #[test]
    fn builders_add_the_right_walls() {
        let mut w = World::new();
        let r = w.add_polygon(&[p(0.0, 0.0), p(4.0, 0.0), p(4.0, 3.0)]);
        assert_eq!(r, 0..3);
        assert_eq!(w.walls[2], Wall::new(p(4.0, 3.0), p(0.0, 0.0)));
        assert_eq!(w.add_polygon(&[p(0.0, 0.0)]), 3..3);
        assert_eq!(w.add_polygon(&[p(0.0, 0.0), p(1.0, 0.0)]), 3..4);
        let b = w.add_box(p(1.0, 1.0), 2.0, 1.0, FRAC_PI_2);
        assert_eq!(b, 4..8);
        // Rotated by 90 deg, the box spans x in [0.5, 1.5] and y in [0, 2].
        let first = w.walls[4];
        assert!((first.a.x - 1.5).abs() < 1e-12 && first.a.y.abs() < 1e-12);
        assert!((w.walls[4].length() - 2.0).abs() < 1e-12);
        assert!((w.walls[5].length() - 1.0).abs() < 1e-12);
        assert_eq!(w.add_disc(p(9.0, 9.0), 0.3), 0);
    }

    #[test]
    fn clearance_and_enclosure() {
        let mut w = World::new();
        w.add_polygon(&[p(0.0, 0.0), p(4.0, 0.0), p(4.0, 3.0), p(0.0, 3.0)]);
        w.add_disc(p(2.0, 2.0), 0.5);
        assert!(close(w.clearance(p(0.5, 1.0)), 0.5));
        assert!((w.clearance(p(1.0, 1.0)) - (2f64.sqrt() - 0.5)).abs() < 1e-12);
        assert!((w.clearance(p(2.0, 1.2)) - 0.3).abs() < 1e-12);
        assert!(w.clearance(p(2.0, 2.0)) < 0.0);
        assert!(w.is_free(p(0.5, 1.0), 0.4) && !w.is_free(p(0.5, 1.0), 0.6));
        assert!(w.encloses(p(1.0, 1.0), 360, 10.0));
        assert!(!w.encloses(p(5.0, 1.0), 360, 10.0));
        assert!(World::new().clearance(p(0.0, 0.0)).is_infinite());
    }

    #[test]
    fn a_wall_in_a_moved_frame_has_its_polar_form_there() {
        // (The normal form itself is tested in the core's `geometry::polar`.)
        // In a frame rotated by 90 deg and moved to (0, -1), the wall y = 1 is 2 m ahead.
        let wall = Wall::new(p(-5.0, 1.0), p(5.0, 1.0));
        let frame_from_world = Isometry2::new(Vector2::new(0.0, -1.0), FRAC_PI_2).inverse();
        let (r, alpha) = wall.polar_in(&frame_from_world).unwrap();
        assert!(close(r, 2.0) && alpha.abs() < 1e-12);
    }
}
