//! Geometry primitives of the plane, shared by the simulator, the navigation and the
//! pictures, one concern per file (metres, REP 103 frames):
//!
//! - [`clip`]: Liang-Barsky clipping of a segment or a ray against half-planes, boxes and
//!   wedges;
//! - [`ray`]: where a ray meets a segment or a circle;
//! - [`distance`]: distances and nearest points between points, segments and boxes;
//! - [`polar`]: the normal form `(r, alpha)` of the line through two points.
//!
//! Degenerate input (zero-length segments, non-finite coordinates) gives `None` or a
//! documented value, never a panic.

pub mod clip;
pub mod distance;
pub mod polar;
pub mod ray;

pub use clip::{clip_ray_to_box, clip_segment, clip_to_wedge, segment_touches_box};
pub use distance::{distance_to_box, distance_to_segment, nearest_on_segment};
pub use polar::polar_line;
pub use ray::{circle_ray_hit, segment_ray_hit, segment_ray_hit_prepared};
