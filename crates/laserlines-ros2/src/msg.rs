//! The ROS 2 messages the node reads and writes, field for field as their `.msg` files
//! define them, so that their CDR encoding (by `ros2-client`, fields in order) is what any
//! ROS 2 node sends and expects.
//!
//! | type | `.msg` | DDS type name |
//! |---|---|---|
//! | [`LaserScan`] | `sensor_msgs/msg/LaserScan` | `sensor_msgs::msg::dds_::LaserScan_` |
//! | [`LineSegmentList`] | `laser_line_extraction/msg/LineSegmentList` | `laser_line_extraction::msg::dds_::LineSegmentList_` |
//! | [`Marker`] | `visualization_msgs/msg/Marker` (Humble and later) | `visualization_msgs::msg::dds_::Marker_` |
//! | [`MarkerArray`] | `visualization_msgs/msg/MarkerArray` | `visualization_msgs::msg::dds_::MarkerArray_` |

use ros2_client::{Message, MessageTypeName};
use serde::{Deserialize, Serialize};

/// The package of `LineSegmentList` in laser_line_extraction (ROS 1 and the ROS 2 node with
/// the same message names).
pub const LINE_PACKAGE: &str = "laser_line_extraction";

/// `builtin_interfaces/msg/Time`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Time {
    /// Seconds.
    pub sec: i32,
    /// Nanoseconds, `0..1e9`.
    pub nanosec: u32,
}

impl Time {
    /// The time in seconds.
    #[must_use]
    pub fn seconds(self) -> f64 {
        f64::from(self.sec) + f64::from(self.nanosec) * 1e-9
    }
}

/// `builtin_interfaces/msg/Duration` (same layout as [`Time`]).
pub type Duration = Time;

/// `std_msgs/msg/Header`.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct Header {
    /// Time of the data.
    pub stamp: Time,
    /// Frame of the data.
    pub frame_id: String,
}

/// `sensor_msgs/msg/LaserScan`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct LaserScan {
    /// Stamp of the first beam and the laser's frame.
    pub header: Header,
    /// Angle of the first beam, rad.
    pub angle_min: f32,
    /// Angle of the last beam, rad.
    pub angle_max: f32,
    /// Angle between beams, rad.
    pub angle_increment: f32,
    /// Time between beams, s.
    pub time_increment: f32,
    /// Time between scans, s.
    pub scan_time: f32,
    /// Smallest valid range, m.
    pub range_min: f32,
    /// Largest valid range, m.
    pub range_max: f32,
    /// Ranges, m (outside the limits, NaN or inf: no return).
    pub ranges: Vec<f32>,
    /// Intensities (may be empty).
    pub intensities: Vec<f32>,
}

impl Message for LaserScan {}

/// `laser_line_extraction/msg/LineSegment`: the line `x cos(angle) + y sin(angle) = radius`
/// in the header's frame.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct LineSegment {
    /// Distance of the line from the origin, m (`>= 0`).
    pub radius: f32,
    /// Direction of the line's normal, rad.
    pub angle: f32,
    /// Covariance of `(radius, angle)`, row-major: `[var r, cov r-a, cov a-r, var a]`.
    pub covariance: [f32; 4],
    /// Start point `[x, y]`, m (the end at the first beam).
    pub start: [f32; 2],
    /// End point `[x, y]`, m (the end at the last beam).
    pub end: [f32; 2],
}

/// `laser_line_extraction/msg/LineSegmentList`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct LineSegmentList {
    /// The scan's header (frame replaced by `--frame-id` when given).
    pub header: Header,
    /// The lines, in beam order.
    pub line_segments: Vec<LineSegment>,
}

impl Message for LineSegmentList {}

/// `geometry_msgs/msg/Point`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Point {
    /// x, m.
    pub x: f64,
    /// y, m.
    pub y: f64,
    /// z, m.
    pub z: f64,
}

/// `geometry_msgs/msg/Vector3`.
pub type Vector3 = Point;

/// `geometry_msgs/msg/Quaternion`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Quaternion {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
    /// w.
    pub w: f64,
}

impl Default for Quaternion {
    /// The identity rotation.
    fn default() -> Self {
        Self {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 1.0,
        }
    }
}

/// `geometry_msgs/msg/Pose`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Pose {
    /// Position, m.
    pub position: Point,
    /// Orientation.
    pub orientation: Quaternion,
}

/// `std_msgs/msg/ColorRGBA`, components in `0..1`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ColorRgba {
    /// Red.
    pub r: f32,
    /// Green.
    pub g: f32,
    /// Blue.
    pub b: f32,
    /// Opacity.
    pub a: f32,
}

/// `sensor_msgs/msg/CompressedImage` (a marker's texture; always empty here).
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct CompressedImage {
    /// Header.
    pub header: Header,
    /// Image format.
    pub format: String,
    /// Image bytes.
    pub data: Vec<u8>,
}

/// `visualization_msgs/msg/UVCoordinate`.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct UvCoordinate {
    /// u.
    pub u: f32,
    /// v.
    pub v: f32,
}

/// `visualization_msgs/msg/MeshFile` (always empty here).
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct MeshFile {
    /// File name.
    pub filename: String,
    /// File bytes.
    pub data: Vec<u8>,
}

/// `visualization_msgs/msg/Marker` as of ROS 2 Humble (with texture and mesh fields).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Marker {
    /// Stamp and frame.
    pub header: Header,
    /// Namespace; with `id` names the marker.
    pub ns: String,
    /// Id within the namespace.
    pub id: i32,
    /// Kind of marker ([`Marker::LINE_LIST`], ...).
    pub r#type: i32,
    /// [`Marker::ADD`] or [`Marker::DELETE`].
    pub action: i32,
    /// Pose in the header's frame.
    pub pose: Pose,
    /// Scale (`x`: line width for lines, m; `z`: text height).
    pub scale: Vector3,
    /// Colour.
    pub color: ColorRgba,
    /// Lifetime (zero: until replaced).
    pub lifetime: Duration,
    /// Retransformed every frame.
    pub frame_locked: bool,
    /// Points (pairs of end points for `LINE_LIST`).
    pub points: Vec<Point>,
    /// Per-point colours (empty: `color`).
    pub colors: Vec<ColorRgba>,
    /// Texture resource (unused).
    pub texture_resource: String,
    /// Texture (unused).
    pub texture: CompressedImage,
    /// Texture coordinates (unused).
    pub uv_coordinates: Vec<UvCoordinate>,
    /// Text of a `TEXT_VIEW_FACING` marker.
    pub text: String,
    /// Mesh resource (unused).
    pub mesh_resource: String,
    /// Mesh file (unused).
    pub mesh_file: MeshFile,
    /// Mesh materials (unused).
    pub mesh_use_embedded_materials: bool,
}

impl Marker {
    /// `type`: a list of line segments, two points each.
    pub const LINE_LIST: i32 = 5;
    /// `type`: text facing the viewer.
    pub const TEXT_VIEW_FACING: i32 = 9;
    /// `action`: add or modify.
    pub const ADD: i32 = 0;
    /// `action`: delete the marker of this `ns` and `id`.
    pub const DELETE: i32 = 2;
}

impl Message for Marker {}

/// `visualization_msgs/msg/MarkerArray`.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct MarkerArray {
    /// The markers.
    pub markers: Vec<Marker>,
}

impl Message for MarkerArray {}

/// `sensor_msgs/msg/LaserScan`.
#[must_use]
pub fn laser_scan_type() -> MessageTypeName {
    MessageTypeName::new("sensor_msgs", "LaserScan")
}

/// `<package>/msg/LineSegmentList` ([`LINE_PACKAGE`] unless told otherwise).
#[must_use]
pub fn line_segment_list_type(package: &str) -> MessageTypeName {
    MessageTypeName::new(package, "LineSegmentList")
}

/// `visualization_msgs/msg/Marker`.
#[must_use]
pub fn marker_type() -> MessageTypeName {
    MessageTypeName::new("visualization_msgs", "Marker")
}

/// `visualization_msgs/msg/MarkerArray`.
#[must_use]
pub fn marker_array_type() -> MessageTypeName {
    MessageTypeName::new("visualization_msgs", "MarkerArray")
}
