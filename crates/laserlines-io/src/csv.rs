//! CSV scans: `index,angle_rad,range_m`, one scan per file.
//!
//! ```text
//! # range_min: 0.02
//! # range_max: 5.6
//! index,angle_rad,range_m
//! 0,-0.5,1.25
//! 1,0,
//! 2,0.5,nan
//! ```
//!
//! - The header is `index,angle_rad,range_m`, or `index,angle_rad,range_m,intensity` with a
//!   fourth column of intensities. Spaces around fields are ignored; blank lines are skipped.
//! - `index` counts the rows from 0 and must do so without gaps.
//! - `angle_rad` must be uniform: `angle_min` is the first row's angle and
//!   `angle_increment = (last - first) / (n - 1)`, unless the comments give them; every row
//!   must lie within 1 % of an increment of `angle_min + index * angle_increment`. So without
//!   those comments at least 2 rows are needed.
//! - `range_m` in metres; empty or `nan` is "no return" (kept as NaN).
//! - A CSV carries no range limits: unless given in the comments, the scan gets
//!   `range_min = 0` and `range_max = f64::MAX`, so that every finite positive range counts
//!   as a measurement (narrow it with the extractor's range limits).
//! - Comment lines start with `#`. Comments of the form `# key: value` with the keys
//!   `angle_min`, `angle_increment` (rad), `range_min`, `range_max` (m), `stamp` (s),
//!   `pose_x`, `pose_y` (m), `pose_theta` (rad), and the same for the wheel odometry
//!   `odometry_x`, `odometry_y`, `odometry_theta`, set those values (a pose needs all
//!   three); other comments are ignored. The CSV writer writes them all, so that a scan
//!   (even one of 0 or 1 beams) survives a round trip exactly.
//!
//! **Readings at their own bearings.** A spinning scanner's raw output (an RPLIDAR's or a
//! YDLIDAR's: bearings that are not evenly spaced) has the header `angle_rad,range_m`, without
//! `index`; `angle_deg` and `range_mm` name those units instead. Its rows are put on a grid
//! of evenly spaced beams by [`laserlines::bearings::grid`] (the median spacing, or `#
//! angle_increment:`; a full turn, or a sector starting after its widest gap; a beam without
//! a reading is NaN). A row may come in any order. `# clockwise: 1` says the bearings turn
//! clockwise (as the RPLIDAR SDK's do); they are then negated. Two readings on one beam keep
//! a measurement (above 0, inside the range limits), then the nearer; each reading left out
//! is counted as
//! skipped under [`SKIP_SHARED_BEAM`]. `# angle_min:` does not apply to such a file.
//!
//! Any error (a missing column, a bad number, non-uniform angles) ends the reader: the file
//! holds only one scan.

use laserlines::Scan;

use crate::error::{ReadError, SourcePos, shown};
use crate::reader::{Input, LineItem, Lines, ScanSource};
use crate::record::{Pose2, ScanRecord};
use crate::skip::SkipCounts;

/// The header of a CSV scan.
pub const HEADER: &str = "index,angle_rad,range_m";
/// The header of a CSV scan with intensities.
pub const HEADER_WITH_INTENSITY: &str = "index,angle_rad,range_m,intensity";
/// The header of readings at their own bearings (radians, metres; `angle_deg` and
/// `range_mm` name those units instead).
pub const READINGS_HEADER: &str = "angle_rad,range_m";
/// Skip reason of a reading at its own bearing left out because its beam kept a better one.
pub const SKIP_SHARED_BEAM: &str =
    "reading on a beam that kept a better one (readings put on a grid of beams)";
/// Non-uniform angles are accepted up to this fraction of the increment.
pub const ANGLE_TOLERANCE: f64 = 0.01;
/// The `range_min` given to a CSV scan without a `# range_min:` comment, m.
pub const DEFAULT_RANGE_MIN: f64 = 0.0;
/// The `range_max` given to a CSV scan without a `# range_max:` comment, m.
pub const DEFAULT_RANGE_MAX: f64 = f64::MAX;

/// Values set by `# key: value` comments.
#[derive(Default)]
struct Meta {
    range_min: Option<f64>,
    range_max: Option<f64>,
    stamp: Option<f64>,
    angle_min: Option<f64>,
    angle_increment: Option<f64>,
    clockwise: Option<f64>,
    angle_min_line: usize,
    pose: [Option<f64>; 3],
    pose_line: usize,
    odometry: [Option<f64>; 3],
    odometry_line: usize,
}

/// Reads a CSV scan.
pub(crate) struct CsvSource {
    name: String,
    lines: Lines,
    done: bool,
    /// Readings left out by the grid of a file of readings, to count as skipped.
    shared: u64,
}

impl CsvSource {
    pub(crate) fn new(name: &str, input: Input) -> Self {
        Self {
            name: name.to_owned(),
            lines: Lines::new(name, input),
            done: false,
            shared: 0,
        }
    }

    fn read_scan(&mut self) -> Result<ScanRecord, ReadError> {
        let name = self.name.clone();
        let mut meta = Meta::default();
        let rows = self.read_rows(&mut meta)?;
        let Some((header_line, columns)) = rows.header else {
            return Err(ReadError::Syntax {
                pos: SourcePos::line(&name, self.lines.line_number() + 1),
                expected: format!("the header `{HEADER}`"),
                found: "the end of the input".to_owned(),
            });
        };
        let end_line = self.lines.line_number() + 1;
        if let Columns::Readings { .. } = columns {
            return self.read_readings(&meta, rows, header_line, end_line);
        }
        let (angle_min, increment) = geometry(&name, &meta, &rows, end_line)?;
        let pose = triple(&name, "pose", meta.pose, meta.pose_line)?;
        let odometry = triple(&name, "odometry", meta.odometry, meta.odometry_line)?;
        let first_line = rows.lines.first().copied().unwrap_or(header_line);
        let scan = Scan {
            angle_min,
            angle_increment: increment,
            range_min: meta.range_min.unwrap_or(DEFAULT_RANGE_MIN),
            range_max: meta.range_max.unwrap_or(DEFAULT_RANGE_MAX),
            ranges: rows.ranges,
            intensities: (columns == Columns::Indexed { intensity: true })
                .then_some(rows.intensities),
            stamp: meta.stamp,
        };
        scan.validate().map_err(|source| ReadError::InvalidScan {
            pos: SourcePos::line(&name, header_line),
            source,
        })?;
        Ok(ScanRecord {
            scan,
            pose,
            odometry,
            line: Some(first_line),
        })
    }

    /// The scan of a file of readings at their own bearings (`rows`), on a grid of beams.
    fn read_readings(
        &mut self,
        meta: &Meta,
        rows: Rows,
        header_line: usize,
        end_line: usize,
    ) -> Result<ScanRecord, ReadError> {
        let name = self.name.clone();
        if meta.angle_min.is_some() {
            return Err(ReadError::Field {
                pos: SourcePos::line(&name, meta.angle_min_line),
                field: "# angle_min".to_owned(),
                expected: "no `# angle_min:` in a file of readings at their own bearings (the \
                           grid starts at a reading)"
                    .to_owned(),
                found: "one".to_owned(),
            });
        }
        let clockwise = meta.clockwise.is_some_and(|c| c != 0.0);
        let mut bearings = rows.angles;
        if clockwise {
            bearings.iter_mut().for_each(|b| *b = -*b);
        }
        let gridded = laserlines::bearings::grid(
            &bearings,
            &rows.ranges,
            meta.angle_increment,
            meta.range_min.unwrap_or(DEFAULT_RANGE_MIN),
            meta.range_max.unwrap_or(DEFAULT_RANGE_MAX),
        )
        .map_err(|e| match e {
            laserlines::bearings::GridError::Scan(source) => ReadError::InvalidScan {
                pos: SourcePos::line(&name, header_line),
                source,
            },
            laserlines::bearings::GridError::Empty => ReadError::Syntax {
                pos: SourcePos::line(&name, end_line),
                expected: "at least one row of readings".to_owned(),
                found: "the end of the input".to_owned(),
            },
            other => ReadError::Syntax {
                pos: SourcePos::line(&name, header_line),
                expected: "readings that make a grid of beams".to_owned(),
                found: other.to_string(),
            },
        })?;
        self.shared = gridded.shared as u64;
        let mut scan = gridded.scan;
        scan.stamp = meta.stamp;
        Ok(ScanRecord {
            scan,
            pose: triple(&name, "pose", meta.pose, meta.pose_line)?,
            odometry: triple(&name, "odometry", meta.odometry, meta.odometry_line)?,
            line: rows.lines.first().copied(),
        })
    }

    /// The comments (into `meta`), the header and the data rows, to the end of the input.
    fn read_rows(&mut self, meta: &mut Meta) -> Result<Rows, ReadError> {
        let name = self.name.clone();
        let mut rows = Rows::default();
        while let Some(item) = self.lines.next_line() {
            let (line, text) = match item? {
                LineItem::Text(line, text) => (line, text),
                LineItem::NotUtf8(e) => return Err(e),
            };
            let trimmed = text.trim();
            if trimmed.is_empty() {
                continue;
            }
            if let Some(comment) = trimmed.strip_prefix('#') {
                parse_comment(&name, line, comment, meta)?;
                continue;
            }
            let fields: Vec<&str> = trimmed.split(',').map(str::trim).collect();
            let Some((_, columns)) = rows.header else {
                rows.header = Some((line, header_columns(&name, line, trimmed, &fields)?));
                continue;
            };
            if fields.len() != columns.count() {
                return Err(ReadError::Syntax {
                    pos: SourcePos::line(&name, line),
                    expected: format!("{} columns ({})", columns.count(), columns.names()),
                    found: format!("{} columns: {}", fields.len(), shown(trimmed)),
                });
            }
            let (angle, range, intensity) = match columns {
                Columns::Indexed { .. } => parse_row(&name, line, &fields, rows.angles.len())?,
                Columns::Readings {
                    degrees,
                    millimetres,
                } => parse_reading(&name, line, &fields, degrees, millimetres)?,
            };
            if let Some(intensity) = intensity {
                rows.intensities.push(intensity);
            }
            rows.angles.push(angle);
            rows.ranges.push(range);
            rows.lines.push(line);
        }
        Ok(rows)
    }
}

/// The columns a header names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Columns {
    /// `index,angle_rad,range_m[,intensity]`: evenly spaced beams.
    Indexed { intensity: bool },
    /// `angle_rad|angle_deg,range_m|range_mm`: readings at their own bearings.
    Readings { degrees: bool, millimetres: bool },
}

impl Columns {
    fn count(self) -> usize {
        match self {
            Self::Indexed { intensity } => 3 + usize::from(intensity),
            Self::Readings { .. } => 2,
        }
    }

    fn names(self) -> String {
        match self {
            Self::Indexed { intensity: false } => HEADER.to_owned(),
            Self::Indexed { intensity: true } => HEADER_WITH_INTENSITY.to_owned(),
            Self::Readings {
                degrees,
                millimetres,
            } => format!(
                "{},{}",
                if degrees { "angle_deg" } else { "angle_rad" },
                if millimetres { "range_mm" } else { "range_m" }
            ),
        }
    }
}

/// What the rows of a CSV scan hold.
#[derive(Debug, Default)]
struct Rows {
    /// The header's line and its columns.
    header: Option<(usize, Columns)>,
    angles: Vec<f64>,
    ranges: Vec<f64>,
    intensities: Vec<f64>,
    /// The line of each row.
    lines: Vec<usize>,
}

/// The columns the header names.
fn header_columns(
    name: &str,
    line: usize,
    trimmed: &str,
    fields: &[&str],
) -> Result<Columns, ReadError> {
    match fields {
        ["index", "angle_rad", "range_m"] => Ok(Columns::Indexed { intensity: false }),
        ["index", "angle_rad", "range_m", "intensity"] => Ok(Columns::Indexed { intensity: true }),
        [
            angle @ ("angle_rad" | "angle_deg"),
            range @ ("range_m" | "range_mm"),
        ] => Ok(Columns::Readings {
            degrees: *angle == "angle_deg",
            millimetres: *range == "range_mm",
        }),
        _ => Err(ReadError::Syntax {
            pos: SourcePos::line(name, line),
            expected: format!(
                "the header `{HEADER}` (or `{HEADER_WITH_INTENSITY}`), or `{READINGS_HEADER}` \
                 for readings at their own bearings (`angle_deg`, `range_mm` in those units)"
            ),
            found: shown(trimmed),
        }),
    }
}

/// The bearing (rad) and range (m) of a row of readings.
fn parse_reading(
    name: &str,
    line: usize,
    fields: &[&str],
    degrees: bool,
    millimetres: bool,
) -> Result<(f64, f64, Option<f64>), ReadError> {
    let (angle_field, angle_expected) = if degrees {
        ("angle_deg", "a finite bearing in degrees")
    } else {
        ("angle_rad", "a finite bearing in radians")
    };
    let angle = match fields[0].parse::<f64>() {
        Ok(a) if a.is_finite() => a,
        _ => {
            return Err(ReadError::Field {
                pos: SourcePos::line(name, line),
                field: angle_field.to_owned(),
                expected: angle_expected.to_owned(),
                found: shown(fields[0]),
            });
        }
    };
    let range = if fields[1].is_empty() {
        f64::NAN
    } else {
        let what = if millimetres { "range_mm" } else { "range_m" };
        fields[1].parse::<f64>().map_err(|_| ReadError::Field {
            pos: SourcePos::line(name, line),
            field: what.to_owned(),
            expected: format!(
                "a range in {}, or empty or `nan` for no return",
                if millimetres { "millimetres" } else { "metres" }
            ),
            found: shown(fields[1]),
        })?
    };
    let angle = if degrees { angle.to_radians() } else { angle };
    let range = if millimetres { range * 1e-3 } else { range };
    Ok((angle, range, None))
}

/// The angle, range and (with 4 columns) intensity of data row number `row`.
fn parse_row(
    name: &str,
    line: usize,
    fields: &[&str],
    row: usize,
) -> Result<(f64, f64, Option<f64>), ReadError> {
    let field = |field: &str, expected: String, found: &str| ReadError::Field {
        pos: SourcePos::line(name, line),
        field: field.to_owned(),
        expected,
        found: shown(found),
    };
    match fields[0].parse::<usize>() {
        Ok(i) if i == row => {}
        _ => {
            return Err(field(
                "index",
                format!("{row} (rows are numbered from 0 without gaps)"),
                fields[0],
            ));
        }
    }
    let angle = match fields[1].parse::<f64>() {
        Ok(a) if a.is_finite() => a,
        _ => {
            return Err(field(
                "angle_rad",
                "a finite angle in radians".to_owned(),
                fields[1],
            ));
        }
    };
    let number = |i: usize, what: &str, expected: &str| {
        if fields[i].is_empty() {
            Ok(f64::NAN)
        } else {
            fields[i]
                .parse::<f64>()
                .map_err(|_| field(what, expected.to_owned(), fields[i]))
        }
    };
    let range = number(
        2,
        "range_m",
        "a range in metres, or empty or `nan` for no return",
    )?;
    let intensity = if fields.len() == 4 {
        Some(number(3, "intensity", "a number, or empty or `nan`")?)
    } else {
        None
    };
    Ok((angle, range, intensity))
}

/// The scan's first angle and increment: from the comments (as the writer writes them),
/// else from the first and last rows; every row's angle checked against them.
fn geometry(
    name: &str,
    meta: &Meta,
    rows: &Rows,
    end_line: usize,
) -> Result<(f64, f64), ReadError> {
    let angles = &rows.angles;
    let n = angles.len();
    let angle_min = meta.angle_min.or_else(|| angles.first().copied());
    let increment = meta
        .angle_increment
        .or_else(|| (n >= 2).then(|| (angles[n - 1] - angles[0]) / (n - 1) as f64));
    let (Some(angle_min), Some(increment)) = (angle_min, increment) else {
        return Err(ReadError::Syntax {
            pos: SourcePos::line(name, end_line),
            expected: "at least 2 data rows (to derive angle_increment), or the comments \
                       `# angle_min:` and `# angle_increment:`"
                .to_owned(),
            found: format!(
                "{n} row{} and then the end of the input",
                if n == 1 { "" } else { "s" }
            ),
        });
    };
    if !increment.is_finite() || increment == 0.0 {
        let line = rows.lines.last().copied().unwrap_or(end_line);
        return Err(ReadError::Field {
            pos: SourcePos::line(name, line),
            field: "angle_rad".to_owned(),
            expected: "angles that change from row to row".to_owned(),
            found: format!("an angle increment of {increment} rad"),
        });
    }
    let tolerance = ANGLE_TOLERANCE * increment.abs();
    for (i, (&a, &line)) in angles.iter().zip(&rows.lines).enumerate() {
        let want = angle_min + i as f64 * increment;
        if (a - want).abs().is_nan() || (a - want).abs() > tolerance {
            return Err(ReadError::Field {
                pos: SourcePos::line(name, line),
                field: "angle_rad".to_owned(),
                expected: format!(
                    "uniform angles: {want} (= {angle_min} + {i} * {increment}) within \
                     {tolerance} (readings at their own bearings: the header \
                     `{READINGS_HEADER}`, without `index`)"
                ),
                found: format!("{a}"),
            });
        }
    }
    Ok((angle_min, increment))
}

fn parse_comment(name: &str, line: usize, comment: &str, meta: &mut Meta) -> Result<(), ReadError> {
    let Some((key, value)) = comment.split_once(':') else {
        return Ok(());
    };
    let key = key.trim();
    let slot = match key {
        "range_min" => &mut meta.range_min,
        "range_max" => &mut meta.range_max,
        "stamp" => &mut meta.stamp,
        "angle_min" => {
            meta.angle_min_line = line;
            &mut meta.angle_min
        }
        "clockwise" => &mut meta.clockwise,
        "angle_increment" => &mut meta.angle_increment,
        "pose_x" => &mut meta.pose[0],
        "pose_y" => &mut meta.pose[1],
        "pose_theta" => &mut meta.pose[2],
        "odometry_x" => &mut meta.odometry[0],
        "odometry_y" => &mut meta.odometry[1],
        "odometry_theta" => &mut meta.odometry[2],
        _ => return Ok(()),
    };
    let value = value.trim();
    match value.parse::<f64>() {
        Ok(v) if v.is_finite() => *slot = Some(v),
        _ => {
            return Err(ReadError::Field {
                pos: SourcePos::line(name, line),
                field: format!("# {key}"),
                expected: "a finite number".to_owned(),
                found: shown(value),
            });
        }
    }
    if key.starts_with("pose_") {
        meta.pose_line = line;
    }
    if key.starts_with("odometry_") {
        meta.odometry_line = line;
    }
    Ok(())
}

/// The pose `{what}_x`, `{what}_y`, `{what}_theta` of the comments: all three or none.
fn triple(
    name: &str,
    what: &str,
    parts: [Option<f64>; 3],
    line: usize,
) -> Result<Option<Pose2>, ReadError> {
    match parts {
        [None, None, None] => Ok(None),
        [Some(x), Some(y), Some(theta)] => Ok(Some(Pose2::new(x, y, theta))),
        _ => Err(ReadError::Syntax {
            pos: SourcePos::line(name, line),
            expected: format!("all of `# {what}_x:`, `# {what}_y:` and `# {what}_theta:`"),
            found: "only some of them".to_owned(),
        }),
    }
}

impl ScanSource for CsvSource {
    fn next_record(&mut self, skipped: &mut SkipCounts) -> Option<Result<ScanRecord, ReadError>> {
        if self.done {
            return None;
        }
        self.done = true;
        let record = self.read_scan();
        if self.shared > 0 {
            skipped.add_n(SKIP_SHARED_BEAM, self.shared);
        }
        Some(record)
    }
}
