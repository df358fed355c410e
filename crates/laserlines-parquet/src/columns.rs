//! The columns of a scans table as the reader finds them: numbers as `float64` or `float32`,
//! lists as `list`, `large_list` or `fixed_size_list` of either; checked once against what
//! the reader needs, each giving its value at a row.

use arrow_array::cast::AsArray;
use arrow_array::types::{Float32Type, Float64Type, Int64Type};
use arrow_array::{Array, ArrayRef, Int64Array, RecordBatch};
use arrow_schema::{DataType, Schema};
use laserlines::Scan;
use laserlines_io::{Pose2, ReadError, ScanRecord, SourcePos};

use crate::schema::{
    ANGLE_INCREMENT, ANGLE_MIN, INTENSITIES, LINE_GEOMETRY, ODOMETRY_THETA, ODOMETRY_X, ODOMETRY_Y,
    POSE_THETA, POSE_X, POSE_Y, RANGE_MAX, RANGE_MIN, RANGES, SCAN, STAMP,
};

/// A column that does not hold what the reader needs.
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnError {
    /// The column's name.
    pub column: &'static str,
    /// What it must hold.
    pub expected: &'static str,
    /// What it holds.
    pub found: String,
}

const NUMBER: &str = "a column of float64 (or float32)";
const INDEX: &str = "a column of int64";
const LIST: &str =
    "a column of list<float64> (or list, large_list or fixed_size_list of float64 or float32)";

fn is_float(t: &DataType) -> bool {
    matches!(t, DataType::Float64 | DataType::Float32)
}

fn is_float_list(t: &DataType) -> bool {
    match t {
        DataType::List(item) | DataType::LargeList(item) | DataType::FixedSizeList(item, _) => {
            is_float(item.data_type())
        }
        _ => false,
    }
}

/// Checks that `schema` has the required columns and that every column the reader uses has
/// a type it reads.
///
/// # Errors
/// The first column missing or of another type.
pub fn check_schema(schema: &Schema) -> Result<(), ColumnError> {
    let required = [ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX, RANGES];
    let optional = [
        SCAN,
        STAMP,
        POSE_X,
        POSE_Y,
        POSE_THETA,
        ODOMETRY_X,
        ODOMETRY_Y,
        ODOMETRY_THETA,
        INTENSITIES,
    ];
    for (names, needed) in [(&required[..], true), (&optional[..], false)] {
        for &name in names {
            let list = name == RANGES || name == INTENSITIES;
            let expected = match name {
                SCAN => INDEX,
                _ if list => LIST,
                _ => NUMBER,
            };
            let Ok(field) = schema.field_with_name(name) else {
                if needed {
                    let columns: Vec<&str> =
                        schema.fields().iter().map(|f| f.name().as_str()).collect();
                    let lines_file = LINE_GEOMETRY.iter().all(|c| columns.contains(c));
                    let what = if lines_file {
                        "; this is a lines file, as `laserlines extract` writes, not a file of scans"
                    } else {
                        ""
                    };
                    return Err(ColumnError {
                        column: name,
                        expected,
                        found: format!("no such column (columns: {}){what}", columns.join(", ")),
                    });
                }
                continue;
            };
            let t = field.data_type();
            let ok = match name {
                SCAN => *t == DataType::Int64,
                _ if list => is_float_list(t),
                _ => is_float(t),
            };
            if !ok {
                return Err(ColumnError {
                    column: name,
                    expected,
                    found: format!("a column of {t}"),
                });
            }
        }
    }
    Ok(())
}

/// A column of numbers, `None` at a null.
#[derive(Debug, Clone)]
pub enum Numbers {
    /// float64
    F64(arrow_array::Float64Array),
    /// float32, widened
    F32(arrow_array::Float32Array),
}

impl Numbers {
    fn of(array: &ArrayRef) -> Option<Self> {
        match array.data_type() {
            DataType::Float64 => Some(Self::F64(array.as_primitive::<Float64Type>().clone())),
            DataType::Float32 => Some(Self::F32(array.as_primitive::<Float32Type>().clone())),
            _ => None,
        }
    }

    /// The value at `row`, `None` when null.
    #[must_use]
    pub fn get(&self, row: usize) -> Option<f64> {
        match self {
            Self::F64(a) => a.is_valid(row).then(|| a.value(row)),
            Self::F32(a) => a.is_valid(row).then(|| f64::from(a.value(row))),
        }
    }

    /// Values `start..end` appended to `out`, a null as NaN.
    fn extend(&self, start: usize, end: usize, out: &mut Vec<f64>) {
        out.extend((start..end).map(|i| self.get(i).unwrap_or(f64::NAN)));
    }
}

/// A column of lists of numbers.
#[derive(Debug, Clone)]
pub struct Lists {
    /// Where each row's values start and end in `values`.
    bounds: Bounds,
    nulls: Option<arrow_buffer::NullBuffer>,
    values: Numbers,
}

#[derive(Debug, Clone)]
enum Bounds {
    Offsets32(arrow_buffer::OffsetBuffer<i32>),
    Offsets64(arrow_buffer::OffsetBuffer<i64>),
    Fixed(usize),
}

impl Lists {
    fn of(array: &ArrayRef) -> Option<Self> {
        let (bounds, values) = match array.data_type() {
            DataType::List(_) => {
                let a = array.as_list::<i32>();
                (Bounds::Offsets32(a.offsets().clone()), a.values())
            }
            DataType::LargeList(_) => {
                let a = array.as_list::<i64>();
                (Bounds::Offsets64(a.offsets().clone()), a.values())
            }
            DataType::FixedSizeList(_, n) => {
                let a = array.as_fixed_size_list();
                let n = usize::try_from(*n).ok()?;
                // A fixed-size list array may start part way into its values.
                let sliced = a.values().slice(array.offset() * n, array.len() * n);
                return Some(Self {
                    bounds: Bounds::Fixed(n),
                    nulls: array.logical_nulls(),
                    values: Numbers::of(&sliced)?,
                });
            }
            _ => return None,
        };
        Some(Self {
            bounds,
            nulls: array.logical_nulls(),
            values: Numbers::of(values)?,
        })
    }

    /// The values of `row` appended to `out` (a null item as NaN); false when the list
    /// itself is null.
    pub fn extend_row(&self, row: usize, out: &mut Vec<f64>) -> bool {
        if self.nulls.as_ref().is_some_and(|n| n.is_null(row)) {
            return false;
        }
        let (start, end) = match &self.bounds {
            Bounds::Offsets32(o) => (o[row] as usize, o[row + 1] as usize),
            Bounds::Offsets64(o) => (o[row] as usize, o[row + 1] as usize),
            Bounds::Fixed(n) => (row * n, (row + 1) * n),
        };
        self.values.extend(start, end, out);
        true
    }
}

/// The columns of one batch the reader uses.
#[derive(Debug, Clone)]
pub struct ScanColumns {
    /// The scan indices, when the table has them.
    pub index: Option<Int64Array>,
    /// angle_min, angle_increment, range_min, range_max.
    pub geometry: [Numbers; 4],
    /// The ranges.
    pub ranges: Lists,
    /// The stamps, when the table has them.
    pub stamp: Option<Numbers>,
    /// x, y, theta, when the table has all three.
    pub pose: Option<[Numbers; 3]>,
    /// The wheel odometry's x, y, theta, when the table has all three.
    pub odometry: Option<[Numbers; 3]>,
    /// The intensities, when the table has them.
    pub intensities: Option<Lists>,
}

impl ScanColumns {
    /// The columns of `batch`, whose schema passed [`check_schema`]; `None` otherwise.
    #[must_use]
    pub fn of(batch: &RecordBatch) -> Option<Self> {
        let numbers = |name: &str| batch.column_by_name(name).and_then(Numbers::of);
        let lists = |name: &str| batch.column_by_name(name).and_then(Lists::of);
        let geometry = [
            numbers(ANGLE_MIN)?,
            numbers(ANGLE_INCREMENT)?,
            numbers(RANGE_MIN)?,
            numbers(RANGE_MAX)?,
        ];
        let triple = |names: [&str; 3]| match names.map(numbers) {
            [Some(x), Some(y), Some(theta)] => Some([x, y, theta]),
            _ => None,
        };
        let pose = triple([POSE_X, POSE_Y, POSE_THETA]);
        let odometry = triple([ODOMETRY_X, ODOMETRY_Y, ODOMETRY_THETA]);
        let index = batch
            .column_by_name(SCAN)
            .filter(|c| *c.data_type() == DataType::Int64)
            .map(|c| c.as_primitive::<Int64Type>().clone());
        Some(Self {
            index,
            geometry,
            ranges: lists(RANGES)?,
            stamp: numbers(STAMP),
            pose,
            odometry,
            intensities: lists(INTENSITIES),
        })
    }
}

/// The names of the geometry columns, in the order of [`ScanColumns::geometry`].
pub const GEOMETRY: [&str; 4] = [ANGLE_MIN, ANGLE_INCREMENT, RANGE_MIN, RANGE_MAX];

impl ScanColumns {
    /// The scan index of `row` (the `scan` column), when the table has one and it is not null.
    #[must_use]
    pub fn scan_index(&self, row: usize) -> Option<i64> {
        self.index
            .as_ref()
            .and_then(|c| c.is_valid(row).then(|| c.value(row)))
    }

    /// The record at `row` of the batch, validated; errors name `pos` (the file and the
    /// row of the table).
    ///
    /// # Errors
    /// [`ReadError::Field`] for a null where a number or the ranges are required,
    /// [`ReadError::InvalidScan`] for a scan [`Scan::validate`] rejects.
    pub fn record(&self, row: usize, pos: &SourcePos) -> Result<ScanRecord, ReadError> {
        let null = |column: &str, expected: &str| ReadError::Field {
            pos: pos.clone(),
            field: column.to_owned(),
            expected: expected.to_owned(),
            found: "null".to_owned(),
        };
        let mut geometry = [0.0; 4];
        for ((value, column), name) in geometry.iter_mut().zip(&self.geometry).zip(GEOMETRY) {
            *value = column.get(row).ok_or_else(|| null(name, "a number"))?;
        }
        let [angle_min, angle_increment, range_min, range_max] = geometry;
        let mut ranges = Vec::new();
        if !self.ranges.extend_row(row, &mut ranges) {
            return Err(null(RANGES, "a list of ranges"));
        }
        let intensities = self.intensities.as_ref().and_then(|lists| {
            let mut values = Vec::new();
            lists.extend_row(row, &mut values).then_some(values)
        });
        let scan = Scan {
            angle_min,
            angle_increment,
            range_min,
            // `inf` is no limit, which a scan writes as the largest finite number.
            range_max: if range_max == f64::INFINITY {
                f64::MAX
            } else {
                range_max
            },
            ranges,
            intensities,
            stamp: self.stamp.as_ref().and_then(|s| s.get(row)),
        };
        scan.validate().map_err(|source| ReadError::InvalidScan {
            pos: pos.clone(),
            source,
        })?;
        let at = |columns: &Option<[Numbers; 3]>| {
            columns.as_ref().and_then(|[x, y, theta]| {
                Some(Pose2::new(x.get(row)?, y.get(row)?, theta.get(row)?))
            })
        };
        Ok(ScanRecord {
            scan,
            pose: at(&self.pose),
            odometry: at(&self.odometry),
            line: None,
        })
    }
}
