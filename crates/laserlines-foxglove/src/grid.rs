//! Occupancy maps as `foxglove.Grid` (`laserlines map --mcap`).
//!
//! Each cell carries `red`, `green`, `blue`, `alpha` (so that the 3D panel shows the map as
//! ROS `map_server` shades it: occupied black, free white, unknown translucent grey) and
//! `occupancy` (INT8: -1 unknown, else the probability of occupancy in percent, as ROS
//! `nav_msgs/OccupancyGrid`).

use foxglove::messages::packed_element_field::NumericType;
use foxglove::messages::{Grid, PackedElementField, Pose, Vector2, Vector3};

use crate::proto::{timestamp, yaw_quaternion};

/// Bytes per cell: red, green, blue, alpha, occupancy.
const CELL_BYTES: u32 = 5;

/// A grid of `width x height` cells of side `resolution_m` whose first row lies at
/// `origin` (the corner of cell (0, 0), in `frame_id`) and rows go up in y;
/// `occupancy[j * width + i]` is -1 for unknown, else 0..=100. `None` when the sizes do not
/// agree.
#[must_use]
pub fn occupancy_grid(
    occupancy: &[i8],
    width: usize,
    height: usize,
    resolution_m: f64,
    origin: (f64, f64),
    frame_id: &str,
    time: f64,
) -> Option<Grid> {
    if occupancy.len() != width.checked_mul(height)? {
        return None;
    }
    let columns = u32::try_from(width).ok()?;
    let mut data = Vec::with_capacity(occupancy.len() * CELL_BYTES as usize);
    for &o in occupancy {
        let (grey, alpha) = match o {
            o if o < 0 => (128, 60),
            o => (255 - (i32::from(o.min(100)) * 255 / 100) as u8, 255),
        };
        data.extend_from_slice(&[grey, grey, grey, alpha, o as u8]);
    }
    let field = |name: &str, offset: u32, ty: NumericType| PackedElementField {
        name: name.to_owned(),
        offset,
        r#type: ty as i32,
    };
    Some(Grid {
        timestamp: Some(timestamp(time)),
        frame_id: frame_id.to_owned(),
        pose: Some(Pose {
            position: Some(Vector3 {
                x: origin.0,
                y: origin.1,
                z: 0.0,
            }),
            orientation: Some(yaw_quaternion(0.0)),
        }),
        column_count: columns,
        cell_size: Some(Vector2 {
            x: resolution_m,
            y: resolution_m,
        }),
        row_stride: columns.checked_mul(CELL_BYTES)?,
        cell_stride: CELL_BYTES,
        fields: vec![
            field("red", 0, NumericType::Uint8),
            field("green", 1, NumericType::Uint8),
            field("blue", 2, NumericType::Uint8),
            field("alpha", 3, NumericType::Uint8),
            field("occupancy", 4, NumericType::Int8),
        ],
        data: data.into(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_are_laid_out_row_by_row_with_their_colours() {
        let g = occupancy_grid(&[-1, 0, 100, 50], 2, 2, 0.05, (1.0, -2.0), "world", 3.0).unwrap();
        assert_eq!(g.column_count, 2);
        assert_eq!(g.row_stride, 10);
        assert_eq!(
            &g.data[..],
            &[
                128, 128, 128, 60, 255, 255, 255, 255, 255, 0, 0, 0, 0, 255, 100, 128, 128, 128,
                255, 50
            ]
        );
        assert_eq!(g.pose.unwrap().position.unwrap().y, -2.0);
        assert!(occupancy_grid(&[0; 3], 2, 2, 0.05, (0.0, 0.0), "world", 0.0).is_none());
    }
}
