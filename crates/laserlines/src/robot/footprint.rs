//! The robot's outline and its exact distances to segments, discs and points.

use crate::geometry::{distance_to_box, distance_to_segment, segment_touches_box};
use crate::math::{Isometry2, Point2, Vector2};

/// The robot's outline: a rectangle centred on the robot frame's origin, axis-aligned in
/// that frame.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct Footprint {
    /// Extent along x (forward), m. Default 0.50.
    pub length: f64,
    /// Extent along y (left), m. Default 0.40.
    pub width: f64,
}

impl Footprint {
    /// About the NAJI V rescue robot: 0.50 m long, 0.40 m wide.
    #[must_use]
    pub const fn naji_v() -> Self {
        Self {
            length: 0.5,
            width: 0.4,
        }
    }

    /// Radius of the circle around the origin that holds the whole footprint, m: the room
    /// the robot needs to turn on the spot (0.32 m for NAJI V).
    #[must_use]
    pub fn circumradius(&self) -> f64 {
        (0.5 * self.length).hypot(0.5 * self.width)
    }

    /// Half extents `(length / 2, width / 2)`, m.
    #[must_use]
    pub fn half(&self) -> Vector2 {
        Vector2::new(0.5 * self.length, 0.5 * self.width)
    }

    /// The corners in the world frame, counter-clockwise starting at the front right.
    #[must_use]
    pub fn corners(&self, world_from_robot: &Isometry2) -> [Point2; 4] {
        let h = self.half();
        [
            world_from_robot * Point2::new(h.x, -h.y),
            world_from_robot * Point2::new(h.x, h.y),
            world_from_robot * Point2::new(-h.x, h.y),
            world_from_robot * Point2::new(-h.x, -h.y),
        ]
    }

    /// Distance from the footprint at `world_from_robot` to the segment `a`-`b` (world
    /// frame), m; 0 when they touch or overlap. Exact.
    #[must_use]
    pub fn distance_to_segment(&self, world_from_robot: &Isometry2, a: Point2, b: Point2) -> f64 {
        let robot_from_world = world_from_robot.inverse();
        self.distance_to_segment_local(robot_from_world * a, robot_from_world * b)
    }

    /// Like [`Footprint::distance_to_segment`] with the segment in the robot frame.
    #[must_use]
    pub fn distance_to_segment_local(&self, a: Point2, b: Point2) -> f64 {
        let h = self.half();
        let lo = Point2::new(-h.x, -h.y);
        let hi = Point2::new(h.x, h.y);
        if segment_touches_box(a, b, lo, hi) {
            return 0.0;
        }
        // Disjoint convex shapes: the least distance is between a vertex of one and the
        // other shape.
        let corners = [lo, Point2::new(h.x, -h.y), hi, Point2::new(-h.x, h.y)];
        corners
            .iter()
            .map(|&c| distance_to_segment(c, a, b))
            .fold(distance_to_box(a, h).min(distance_to_box(b, h)), f64::min)
    }

    /// Distance from the footprint at `world_from_robot` to a disc (world frame), m; 0 when
    /// they touch or overlap. Exact.
    #[must_use]
    pub fn distance_to_disc(
        &self,
        world_from_robot: &Isometry2,
        centre: Point2,
        radius: f64,
    ) -> f64 {
        let c = world_from_robot.inverse() * centre;
        (self.distance_to_point_local(c) - radius.max(0.0)).max(0.0)
    }

    /// Distance from the footprint to a point in the robot frame, m (0 inside).
    #[inline]
    #[must_use]
    pub fn distance_to_point_local(&self, p: Point2) -> f64 {
        distance_to_box(p, self.half())
    }
}

impl Default for Footprint {
    fn default() -> Self {
        Self::naji_v()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point2 {
        Point2::new(x, y)
    }

    #[test]
    fn footprint_distances_by_hand() {
        let fp = Footprint::naji_v();
        let id = Isometry2::identity();
        // A wall 0.1 m beyond the front face.
        assert!((fp.distance_to_segment(&id, p(0.35, -1.0), p(0.35, 1.0)) - 0.1).abs() < 1e-12);
        // A wall crossing the body.
        assert_eq!(fp.distance_to_segment(&id, p(0.0, -1.0), p(0.0, 1.0)), 0.0);
        // A wall wholly inside the body.
        assert_eq!(fp.distance_to_segment(&id, p(0.0, 0.0), p(0.1, 0.1)), 0.0);
        // A wall end pointing at the front-left corner (0.25, 0.2) from (0.55, 0.6): 0.5 m.
        assert!((fp.distance_to_segment(&id, p(0.55, 0.6), p(2.0, 2.0)) - 0.5).abs() < 1e-12);
        // A diagonal wall passing a corner: the line x + y = 1 is (1 - 0.45)/sqrt(2) from
        // the corner (0.25, 0.2).
        let d = fp.distance_to_segment(&id, p(1.0, 0.0), p(0.0, 1.0));
        assert!((d - 0.55 / 2f64.sqrt()).abs() < 1e-12);
        // Turned by 90 deg, the body spans 0.4 m along x.
        let turned = Isometry2::new(Vector2::zeros(), std::f64::consts::FRAC_PI_2);
        assert!((fp.distance_to_segment(&turned, p(0.3, -1.0), p(0.3, 1.0)) - 0.1).abs() < 1e-12);
        // Discs.
        assert!((fp.distance_to_disc(&id, p(0.0, 0.5), 0.1) - 0.2).abs() < 1e-12);
        assert_eq!(fp.distance_to_disc(&id, p(0.3, 0.0), 0.1), 0.0);
        assert!((fp.distance_to_disc(&id, p(0.55, 0.6), 0.1) - 0.4).abs() < 1e-12);
        assert!((fp.circumradius() - 0.32015621187164245).abs() < 1e-12);
    }
}
