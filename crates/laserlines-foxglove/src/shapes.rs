//! Small pieces of Foxglove scenes shared by the navigation and sector scenes: colours,
//! points, poses in the plane and line lists.

use foxglove::messages::{Color, LinePrimitive, Point3, Pose, Vector3, line_primitive};
use laserlines::math::Point2;

use crate::proto::yaw_quaternion;

/// An RGBA colour, each channel 0..1.
pub(crate) fn color(r: f64, g: f64, b: f64, a: f64) -> Color {
    Color { r, g, b, a }
}

/// A point of the plane at z = 0.
pub(crate) fn point3(p: Point2) -> Point3 {
    Point3 {
        x: p.x,
        y: p.y,
        z: 0.0,
    }
}

/// A pose in the plane: position (m) and yaw (rad).
pub(crate) fn pose_at(x: f64, y: f64, yaw: f64) -> Pose {
    Pose {
        position: Some(Vector3 { x, y, z: 0.0 }),
        orientation: Some(yaw_quaternion(yaw)),
    }
}

/// A `LINE_LIST` of point pairs in one colour, `thickness_px` wide on screen.
pub(crate) fn line_list(points: Vec<Point3>, c: Color, thickness_px: f64) -> LinePrimitive {
    LinePrimitive {
        r#type: line_primitive::Type::LineList as i32,
        pose: Some(pose_at(0.0, 0.0, 0.0)),
        thickness: thickness_px,
        scale_invariant: true,
        points,
        color: Some(c),
        colors: Vec::new(),
        indices: Vec::new(),
    }
}
