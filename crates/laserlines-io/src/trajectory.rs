//! Trajectories and what mapping writes: TUM trajectory text (read and write), the Freiburg
//! benchmark's relations (read), and occupancy maps in ROS `map_server` form (PGM + YAML).
//!
//! | format | line |
//! |---|---|
//! | TUM | `t x y z qx qy qz qw`: time (s), position (m), orientation as a unit quaternion; `#` comments |
//! | relations | `t1 t2 x y z roll pitch yaw`: the pose at `t2` seen from the pose at `t1` (m, rad) |
//!
//! Planar poses are written with `z = 0` and a rotation about z; read back, the heading is
//! the quaternion's yaw.

use std::io::{BufRead, Write};

use laserlines::scan::Short;

use crate::error::{ReadError, SourcePos, shown};
use crate::record::Pose2;

/// One pose of a trajectory with its time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StampedPose {
    /// Time, s.
    pub t: f64,
    /// `world_from_robot`.
    pub pose: Pose2,
}

/// One relation of the benchmark: the pose at `t2` seen from the pose at `t1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RelationRecord {
    /// Its line in the file (from 1).
    pub line: usize,
    /// First time, s.
    pub t1: f64,
    /// Second time, s.
    pub t2: f64,
    /// `x(t1)^-1 * x(t2)` in the plane (its `z`, roll and pitch are checked to be 0 within
    /// 1e-6 and dropped).
    pub delta: Pose2,
}

/// Writes poses as TUM lines (`t x y 0 0 0 qz qw`), every number in its shortest exact form
/// (in e-notation when it is below 1e-5 or from 1e16 in size, so that `2.7e-27` is not
/// written with 26 zeros).
///
/// # Errors
/// The writer's error.
pub fn write_tum(out: &mut impl Write, poses: &[StampedPose]) -> std::io::Result<()> {
    writeln!(out, "# t x y z qx qy qz qw")?;
    for p in poses {
        let half = p.pose.theta / 2.0;
        writeln!(
            out,
            "{} {} {} 0 0 0 {} {}",
            Short(p.t),
            Short(p.pose.x),
            Short(p.pose.y),
            Short(half.sin()),
            Short(half.cos())
        )?;
    }
    Ok(())
}

/// Reads a TUM trajectory. `name` is used in messages.
///
/// # Errors
/// [`ReadError`] naming the line: a line without 8 numbers, a non-finite value, a quaternion
/// that is not of unit length (within 1e-3).
pub fn read_tum(name: &str, input: impl BufRead) -> Result<Vec<StampedPose>, ReadError> {
    let mut out = Vec::new();
    for_each_row(name, input, "8 numbers: t x y z qx qy qz qw", |pos, v| {
        let [t, x, y, _z, qx, qy, qz, qw] = v;
        let norm = (qx * qx + qy * qy + qz * qz + qw * qw).sqrt();
        if (norm - 1.0).abs() > 1e-3 {
            return Err(ReadError::Field {
                pos,
                field: "qx qy qz qw".into(),
                expected: "a unit quaternion".into(),
                found: format!("length {norm}"),
            });
        }
        let yaw = (2.0 * (qw * qz + qx * qy)).atan2(1.0 - 2.0 * (qy * qy + qz * qz));
        out.push(StampedPose {
            t,
            pose: Pose2::new(x, y, yaw),
        });
        Ok(())
    })?;
    Ok(out)
}

/// Reads a relations file. `name` is used in messages.
///
/// # Errors
/// [`ReadError`] naming the line: a line without 8 numbers, a non-finite value, a relation
/// out of the plane (`z`, roll or pitch not 0).
pub fn read_relations(name: &str, input: impl BufRead) -> Result<Vec<RelationRecord>, ReadError> {
    let mut out = Vec::new();
    for_each_row(
        name,
        input,
        "8 numbers: t1 t2 x y z roll pitch yaw",
        |pos, v| {
            let [t1, t2, x, y, z, roll, pitch, yaw] = v;
            if z.abs() > 1e-6 || roll.abs() > 1e-6 || pitch.abs() > 1e-6 {
                return Err(ReadError::Field {
                    pos,
                    field: "z roll pitch".into(),
                    expected: "0 0 0 (a planar relation)".into(),
                    found: format!("{z} {roll} {pitch}"),
                });
            }
            out.push(RelationRecord {
                line: pos.at.line().unwrap_or(0),
                t1,
                t2,
                delta: Pose2::new(x, y, yaw),
            });
            Ok(())
        },
    )?;
    Ok(out)
}

/// Calls `f` with the 8 finite numbers of every line that is neither blank nor a `#`
/// comment.
fn for_each_row(
    name: &str,
    input: impl BufRead,
    expected: &str,
    mut f: impl FnMut(SourcePos, [f64; 8]) -> Result<(), ReadError>,
) -> Result<(), ReadError> {
    for (k, line) in input.lines().enumerate() {
        let pos = SourcePos::line(name, k + 1);
        let line = line.map_err(|source| ReadError::Io {
            pos: pos.clone(),
            source,
        })?;
        let text = line.trim();
        if text.is_empty() || text.starts_with('#') {
            continue;
        }
        let mut v = [0.0; 8];
        let mut n = 0;
        for tok in text.split_whitespace() {
            let value = tok.parse::<f64>().ok().filter(|x| x.is_finite());
            match (value, v.get_mut(n)) {
                (Some(x), Some(slot)) => *slot = x,
                (None, _) => {
                    return Err(ReadError::Field {
                        pos,
                        field: format!("value {}", n + 1),
                        expected: "a finite number".into(),
                        found: shown(tok),
                    });
                }
                (Some(_), None) => {}
            }
            n += 1;
        }
        if n != 8 {
            return Err(ReadError::Syntax {
                pos,
                expected: expected.into(),
                found: format!("{n} values"),
            });
        }
        f(pos, v)?;
    }
    Ok(())
}

/// An occupancy map as an 8-bit grey image placed in the map frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapImage<'a> {
    /// `width * height` grey values, rows from the top (largest y) down.
    pub pixels: &'a [u8],
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Side of a pixel, m.
    pub resolution_m: f64,
    /// The map-frame position of the image's lower-left corner, m.
    pub origin: (f64, f64),
}

/// Writes an occupancy map as ROS `map_server` does: a binary PGM (`P5`, 8 bits, rows from
/// the top) and the YAML that places it, naming the image `image_name`.
///
/// # Errors
/// The writers' errors; `InvalidInput` when the image does not have `width * height` values.
pub fn write_map_server(
    pgm: &mut impl Write,
    yaml: &mut impl Write,
    image_name: &str,
    map: &MapImage<'_>,
) -> std::io::Result<()> {
    let MapImage {
        pixels,
        width,
        height,
        resolution_m,
        origin,
    } = *map;
    if pixels.len() != width.saturating_mul(height) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!(
                "{} grey values for a {width} x {height} image",
                pixels.len()
            ),
        ));
    }
    write!(pgm, "P5\n{width} {height}\n255\n")?;
    pgm.write_all(pixels)?;
    writeln!(yaml, "image: {image_name}")?;
    writeln!(yaml, "resolution: {resolution_m}")?;
    writeln!(yaml, "origin: [{}, {}, 0.0]", origin.0, origin.1)?;
    writeln!(yaml, "negate: 0")?;
    writeln!(yaml, "occupied_thresh: 0.65")?;
    writeln!(yaml, "free_thresh: 0.196")?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tum_round_trip_keeps_every_value() {
        let poses = [
            StampedPose {
                t: 1_134_864_645.903_21,
                pose: Pose2::new(1.25, -3.5, 0.75),
            },
            StampedPose {
                t: 2.0,
                pose: Pose2::new(0.0, 0.0, -3.0),
            },
            StampedPose {
                t: 3.0,
                pose: Pose2::new(2.744_740_301_962_794_4e-27, -1e20, 1e-30),
            },
        ];
        let mut buf = Vec::new();
        write_tum(&mut buf, &poses).unwrap();
        let text = String::from_utf8(buf.clone()).unwrap();
        assert!(
            text.ends_with("\n3 2.7447403019627944e-27 -1e20 0 0 0 5e-31 1\n"),
            "{text}"
        );
        let back = read_tum("t.tum", buf.as_slice()).unwrap();
        assert_eq!(back.len(), 3);
        for (a, b) in poses.iter().zip(&back) {
            assert_eq!(a.t, b.t);
            assert_eq!((a.pose.x, a.pose.y), (b.pose.x, b.pose.y));
            assert!((a.pose.theta - b.pose.theta).abs() < 1e-12);
        }
        // A quarter turn about z: qz = qw = sqrt(1/2).
        let text = format!("0 1 2 0 0 0 {h} {h}\n", h = 0.5f64.sqrt());
        let q = read_tum("q.tum", text.as_bytes()).unwrap();
        assert!((q[0].pose.theta - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }

    #[test]
    fn bad_lines_are_named() {
        let e = read_tum("t.tum", "# c\n1 2 3 0 0 0 0 1\n1 2 3\n".as_bytes()).unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.tum:3: expected 8 numbers: t x y z qx qy qz qw, found 3 values"
        );
        let e = read_tum("t.tum", "1 2 3 0 0 0 0 2\n".as_bytes()).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("t.tum:1: qx qy qz qw: expected a unit quaternion"),
            "{e}"
        );
        let e = read_relations("r", "1 2 0.1 0.2 0 0 0 nan\n".as_bytes()).unwrap_err();
        assert_eq!(
            e.to_string(),
            "r:1: value 8: expected a finite number, found `nan`"
        );
        // A file of another kind on one line (JSON) is quoted cut short.
        let json = format!("[{}]", vec!["{\"r\":1.5}"; 40_000].join(","));
        let e = read_tum("l.json", json.as_bytes()).unwrap_err().to_string();
        assert_eq!(
            e,
            "l.json:1: value 1: expected a finite number, found `[{\\\"r\\\":1.5},{\\\"r\\\":1.5},{\\\"r\\\":1.5},{\\\"r\\\":1.5}...`"
        );
        let e = read_relations("r", "1 2 0.1 0.2 0.5 0 0 0.3\n".as_bytes()).unwrap_err();
        assert!(e.to_string().contains("a planar relation"), "{e}");
        let r = read_relations(
            "r",
            "# t1 t2\n\n1 2 0.1 0.2 0.000000 0 0 0.3\n\n".as_bytes(),
        )
        .unwrap();
        assert_eq!(
            r,
            vec![RelationRecord {
                line: 3,
                t1: 1.0,
                t2: 2.0,
                delta: Pose2::new(0.1, 0.2, 0.3)
            }]
        );
    }

    #[test]
    fn map_server_files() {
        let (mut pgm, mut yaml) = (Vec::new(), Vec::new());
        let map = MapImage {
            pixels: &[0, 254, 205, 0, 0, 0],
            width: 3,
            height: 2,
            resolution_m: 0.05,
            origin: (-1.5, 2.0),
        };
        write_map_server(&mut pgm, &mut yaml, "map.pgm", &map).unwrap();
        assert_eq!(&pgm[..11], b"P5\n3 2\n255\n");
        assert_eq!(&pgm[11..], &[0, 254, 205, 0, 0, 0]);
        let y = String::from_utf8(yaml).unwrap();
        assert!(
            y.contains("image: map.pgm\nresolution: 0.05\norigin: [-1.5, 2, 0.0]\n"),
            "{y}"
        );
        let short = MapImage {
            pixels: &[0; 5],
            ..map
        };
        assert!(write_map_server(&mut Vec::new(), &mut Vec::new(), "m", &short).is_err());
    }
}
