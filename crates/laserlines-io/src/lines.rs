//! The lines JSONL schema: one object per scan with the lines extracted from it.
//!
//! ```json
//! {"scan":0,"stamp":212.387282,"pose":{"x":0.0,"y":0.0,"theta":0.0},
//!  "lines":[{"start":[1.0,-0.5],"end":[1.0,0.5],"r":1.0,"alpha":0.0,"first":10,"last":40,
//!            "points":31,"rms":0.004,"covariance":[[1e-6,0.0],[0.0,1e-5]]}]}
//! ```
//!
//! (one line per scan in the file). `scan` is the 0-based number of the scan in its input;
//! `stamp` (s), `pose` (the robot's, m and rad) and `odometry` (its wheel odometry, m and
//! rad, as [`crate::ScanRecord::odometry`]) appear when the input has them. Each line
//! carries its end points (m, sensor frame), the normal form `x cos(alpha) + y sin(alpha) = r`
//! (`r` in m, `alpha` in rad), the first and last beam index, the number of supporting
//! points, the RMS residual (m) and the 2x2 covariance of `(r, alpha)`. Numbers are written
//! so that they read back bit for bit; a non-finite number is written as `null` and read back
//! as NaN.

use std::io::BufRead;
use std::path::Path;

use laserlines::Line;
use laserlines::math::{Matrix2, Point2};
use serde::{Deserialize, Deserializer, Serialize};

use crate::error::{ReadError, SourcePos};
use crate::reader::{Input, LineItem, Lines, open_input};
use crate::record::Pose2;

/// The lines of one scan, as one object of a lines JSONL file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScanLines {
    /// 0-based number of the scan in its input.
    pub scan: u64,
    /// Time stamp of the scan, s, when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stamp: Option<f64>,
    /// The robot's pose when the scan was taken, when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pose: Option<Pose2>,
    /// The robot's wheel odometry when the scan was taken, when the input has it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub odometry: Option<Pose2>,
    /// The lines, ordered by first beam.
    pub lines: Vec<LineRecord>,
}

/// One extracted line in the lines JSONL schema (the fields of [`laserlines::Line`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LineRecord {
    /// Start point `[x, y]`, m, sensor frame (the end at beam `first`).
    #[serde(deserialize_with = "pair")]
    pub start: [f64; 2],
    /// End point `[x, y]`, m, sensor frame (the end at beam `last`).
    #[serde(deserialize_with = "pair")]
    pub end: [f64; 2],
    /// Distance of the line from the sensor, m.
    #[serde(deserialize_with = "number")]
    pub r: f64,
    /// Direction of the line's normal, rad.
    #[serde(deserialize_with = "number")]
    pub alpha: f64,
    /// First supporting beam index.
    pub first: usize,
    /// Last supporting beam index (inclusive).
    pub last: usize,
    /// Number of supporting points.
    pub points: usize,
    /// RMS orthogonal residual, m.
    #[serde(deserialize_with = "number")]
    pub rms: f64,
    /// Covariance of `(r, alpha)`, row-major: `[[m^2, m rad], [m rad, rad^2]]`.
    #[serde(deserialize_with = "matrix")]
    pub covariance: [[f64; 2]; 2],
}

impl From<&Line> for LineRecord {
    fn from(l: &Line) -> Self {
        let c = &l.covariance;
        Self {
            start: [l.start.x, l.start.y],
            end: [l.end.x, l.end.y],
            r: l.r,
            alpha: l.alpha,
            first: l.first,
            last: l.last,
            points: l.points,
            rms: l.rms,
            covariance: [[c[(0, 0)], c[(0, 1)]], [c[(1, 0)], c[(1, 1)]]],
        }
    }
}

impl LineRecord {
    /// The record as a [`laserlines::Line`].
    #[must_use]
    pub fn to_line(&self) -> Line {
        let c = &self.covariance;
        Line {
            start: Point2::new(self.start[0], self.start[1]),
            end: Point2::new(self.end[0], self.end[1]),
            r: self.r,
            alpha: self.alpha,
            first: self.first,
            last: self.last,
            points: self.points,
            rms: self.rms,
            covariance: Matrix2::new(c[0][0], c[0][1], c[1][0], c[1][1]),
        }
    }
}

fn number<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

fn pair<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
    let [a, b] = <[Option<f64>; 2]>::deserialize(d)?;
    Ok([a.unwrap_or(f64::NAN), b.unwrap_or(f64::NAN)])
}

fn matrix<'de, D: Deserializer<'de>>(d: D) -> Result<[[f64; 2]; 2], D::Error> {
    let rows = <[[Option<f64>; 2]; 2]>::deserialize(d)?;
    Ok(rows.map(|row| row.map(|v| v.unwrap_or(f64::NAN))))
}

/// Reads a lines JSONL file one scan at a time (blank lines are skipped). After a bad line
/// it goes on with the next one.
pub struct LinesReader {
    name: String,
    lines: Lines,
}

impl std::fmt::Debug for LinesReader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LinesReader")
            .field("name", &self.name)
            .finish_non_exhaustive()
    }
}

impl LinesReader {
    /// Opens a lines JSONL file, gzipped or not.
    ///
    /// # Errors
    /// [`ReadError::Open`] when the file cannot be opened.
    pub fn open(path: &Path) -> Result<Self, ReadError> {
        let name = path.display().to_string();
        let file = std::fs::File::open(path).map_err(|source| ReadError::Open {
            file: name.clone(),
            source,
        })?;
        let input = open_input(
            &name,
            Box::new(std::io::BufReader::new(file)),
            crate::format::has_gz_extension(path),
        )?;
        Ok(Self::from_input(&name, input))
    }

    /// Reads lines JSONL from any buffered reader; `name` is used in messages.
    ///
    /// # Errors
    /// [`ReadError::Open`] when the first bytes cannot be read.
    pub fn from_reader(
        name: &str,
        reader: impl BufRead + Send + 'static,
    ) -> Result<Self, ReadError> {
        Ok(Self::from_input(
            name,
            open_input(name, Box::new(reader), false)?,
        ))
    }

    fn from_input(name: &str, input: Input) -> Self {
        Self {
            name: name.to_owned(),
            lines: Lines::new(name, input),
        }
    }
}

impl Iterator for LinesReader {
    type Item = Result<ScanLines, ReadError>;

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            let item = match self.lines.next_line()? {
                Ok(item) => item,
                Err(e) => return Some(Err(e)),
            };
            let (line, text) = match item {
                LineItem::NotUtf8(e) => return Some(Err(e)),
                LineItem::Text(line, text) => (line, text),
            };
            if text.trim().is_empty() {
                continue;
            }
            return Some(serde_json::from_str(text).map_err(|e| {
                let full = e.to_string();
                let message = match full.rfind(" at line ") {
                    Some(i) => full[..i].to_owned(),
                    None => full,
                };
                ReadError::Json {
                    pos: SourcePos::line_column(&self.name, line, e.column().max(1)),
                    message,
                }
            }));
        }
    }
}
