//! The two tables: lines (one row per line, [`lines_schema`]) and scans (one row per scan,
//! [`scans_schema`]). Column names are constants, so that writers, readers and other
//! languages' bindings name them once.
//!
//! Lines, one row per extracted line, in input order (SI units, the laser's frame):
//!
//! | column | type | null | meaning |
//! |---|---|---|---|
//! | `scan` | int64 | no | 0-based index of the scan in the input |
//! | `stamp` | float64 | yes | the scan's time stamp, s |
//! | `pose_x`, `pose_y` | float64 | yes | the robot's position (`world_from_robot`), m |
//! | `pose_theta` | float64 | yes | the robot's heading, rad |
//! | `start_x`, `start_y` | float64 | no | start point (the end at beam `first`), m |
//! | `end_x`, `end_y` | float64 | no | end point (the end at beam `last`), m |
//! | `r` | float64 | no | distance of the line from the laser, m |
//! | `alpha` | float64 | no | direction of the line's normal, rad, in `(-pi, pi]` |
//! | `first`, `last` | int64 | no | first and last supporting beam (inclusive; `first > last` across the seam of a 360 deg scan) |
//! | `points` | int64 | no | number of supporting points |
//! | `rms` | float64 | no | RMS orthogonal residual, m |
//! | `cov_rr`, `cov_ralpha`, `cov_alphaalpha` | float64 | no | covariance of `(r, alpha)`: m², m rad, rad² |
//!
//! Scans, one row per scan, in input order (`sensor_msgs/LaserScan`'s fields):
//!
//! | column | type | null | meaning |
//! |---|---|---|---|
//! | `scan` | int64 | no | 0-based index of the scan in the input |
//! | `stamp` | float64 | yes | time stamp, s |
//! | `pose_x`, `pose_y`, `pose_theta` | float64 | yes | the robot's pose, m, m, rad |
//! | `odometry_x`, `odometry_y`, `odometry_theta` | float64 | yes | the wheel odometry's pose at the scan, m, m, rad |
//! | `angle_min` | float64 | no | angle of the first beam, rad |
//! | `angle_increment` | float64 | no | angle between beams, rad (negative: clockwise) |
//! | `range_min`, `range_max` | float64 | no | valid ranges, m (`range_max` = inf: no limit) |
//! | `ranges` | list\<float64\> | no | ranges, m; NaN, inf or a null item = no return |
//! | `intensities` | list\<float64\> | yes | intensities, one per range, when the source has them |
//!
//! A pose, or the odometry, is present when all three of its columns are (`ScanRecord::pose`
//! and `ScanRecord::odometry`). The reader also takes `float32` for any `float64` column,
//! `list<float64>` (and large or fixed-size lists) for the lists, nullable columns without
//! nulls where this schema has none, and tables without the optional columns (`scan`,
//! `stamp`, the pose, the odometry, `intensities`); other columns are ignored.

use std::sync::Arc;

use arrow_schema::{DataType, Field, Schema, SchemaRef};

/// 0-based index of the scan in the input.
pub const SCAN: &str = "scan";
/// Time stamp, s.
pub const STAMP: &str = "stamp";
/// The robot's x, m.
pub const POSE_X: &str = "pose_x";
/// The robot's y, m.
pub const POSE_Y: &str = "pose_y";
/// The robot's heading, rad.
pub const POSE_THETA: &str = "pose_theta";
/// The wheel odometry's x at the scan, m (scans table).
pub const ODOMETRY_X: &str = "odometry_x";
/// The wheel odometry's y at the scan, m (scans table).
pub const ODOMETRY_Y: &str = "odometry_y";
/// The wheel odometry's heading at the scan, rad (scans table).
pub const ODOMETRY_THETA: &str = "odometry_theta";
/// Angle of the first beam, rad.
pub const ANGLE_MIN: &str = "angle_min";
/// Angle between beams, rad.
pub const ANGLE_INCREMENT: &str = "angle_increment";
/// Smallest valid range, m.
pub const RANGE_MIN: &str = "range_min";
/// Largest valid range, m.
pub const RANGE_MAX: &str = "range_max";
/// The ranges, m.
pub const RANGES: &str = "ranges";
/// The intensities.
pub const INTENSITIES: &str = "intensities";

/// The columns of the lines table that hold one `float64` per line, in order after the
/// pose: start and end point, `r`, `alpha`.
pub const LINE_GEOMETRY: [&str; 6] = ["start_x", "start_y", "end_x", "end_y", "r", "alpha"];
/// The `int64` columns of a line: supporting beams and point count.
pub const LINE_BEAMS: [&str; 3] = ["first", "last", "points"];
/// The `float64` columns after the beams: residual and covariance.
pub const LINE_FIT: [&str; 4] = ["rms", "cov_rr", "cov_ralpha", "cov_alphaalpha"];

/// The item of a list column: `float64`, nullable, named `item` as pyarrow names it.
fn f64_list() -> DataType {
    DataType::List(Arc::new(Field::new("item", DataType::Float64, true)))
}

/// The scan's index, stamp and pose: the first columns of both tables.
fn scan_columns() -> Vec<Field> {
    vec![
        Field::new(SCAN, DataType::Int64, false),
        Field::new(STAMP, DataType::Float64, true),
        Field::new(POSE_X, DataType::Float64, true),
        Field::new(POSE_Y, DataType::Float64, true),
        Field::new(POSE_THETA, DataType::Float64, true),
    ]
}

/// The schema of the lines table (see the [module docs](self)).
#[must_use]
pub fn lines_schema() -> SchemaRef {
    let mut fields = scan_columns();
    let f64s = |names: &[&str]| -> Vec<Field> {
        names
            .iter()
            .map(|n| Field::new(*n, DataType::Float64, false))
            .collect()
    };
    fields.extend(f64s(&LINE_GEOMETRY));
    fields.extend(
        LINE_BEAMS
            .iter()
            .map(|n| Field::new(*n, DataType::Int64, false)),
    );
    fields.extend(f64s(&LINE_FIT));
    Arc::new(Schema::new(fields))
}

/// The schema of the scans table (see the [module docs](self)).
#[must_use]
pub fn scans_schema() -> SchemaRef {
    let mut fields = scan_columns();
    for name in [ODOMETRY_X, ODOMETRY_Y, ODOMETRY_THETA] {
        fields.push(Field::new(name, DataType::Float64, true));
    }
    for name in [ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX] {
        fields.push(Field::new(name, DataType::Float64, false));
    }
    fields.push(Field::new(RANGES, f64_list(), false));
    fields.push(Field::new(INTENSITIES, f64_list(), true));
    Arc::new(Schema::new(fields))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tables_have_the_documented_columns() {
        let names =
            |s: SchemaRef| -> Vec<String> { s.fields().iter().map(|f| f.name().clone()).collect() };
        assert_eq!(
            names(lines_schema()).join(","),
            "scan,stamp,pose_x,pose_y,pose_theta,start_x,start_y,end_x,end_y,r,alpha,first,\
             last,points,rms,cov_rr,cov_ralpha,cov_alphaalpha"
        );
        assert_eq!(
            names(scans_schema()).join(","),
            "scan,stamp,pose_x,pose_y,pose_theta,odometry_x,odometry_y,odometry_theta,\
             angle_min,angle_increment,range_min,range_max,ranges,intensities"
        );
    }
}
