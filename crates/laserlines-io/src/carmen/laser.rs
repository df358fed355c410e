//! The lasers of a CARMEN log (`FLASER`, `RLASER`, `ROBOTLASERk`, `RAWLASERk`), which of
//! them are read, their `PARAM` settings, and the parsing of one laser line.

use std::f64::consts::PI;
use std::fmt;

use laserlines::Scan;

use crate::error::{ReadError, SourcePos};
use crate::record::{Pose2, ScanRecord};

use super::fields::Fields;
use super::{RANGE_MAX, default_increment};

/// A laser message of a CARMEN log.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Laser {
    /// `FLASER`.
    Front,
    /// `RLASER`.
    Rear,
    /// `ROBOTLASERk`.
    Robot(u8),
    /// `RAWLASERk`.
    Raw(u8),
}

impl Laser {
    /// The laser of a message name (exact, upper case), if it is one.
    pub(super) fn from_name(name: &str) -> Option<Self> {
        let digit = |rest: &str| match rest.as_bytes() {
            [d @ b'0'..=b'9'] => Some(d - b'0'),
            _ => None,
        };
        match name {
            "FLASER" => Some(Self::Front),
            "RLASER" => Some(Self::Rear),
            _ => {
                if let Some(rest) = name.strip_prefix("ROBOTLASER") {
                    digit(rest).map(Self::Robot)
                } else if let Some(rest) = name.strip_prefix("RAWLASER") {
                    digit(rest).map(Self::Raw)
                } else {
                    None
                }
            }
        }
    }
}

impl fmt::Display for Laser {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Front => f.write_str("FLASER"),
            Self::Rear => f.write_str("RLASER"),
            Self::Robot(k) => write!(f, "ROBOTLASER{k}"),
            Self::Raw(k) => write!(f, "RAWLASER{k}"),
        }
    }
}

/// Which laser lines become records.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Selection {
    /// `FLASER` and `ROBOTLASER1`.
    Front,
    /// One message.
    One(Laser),
}

impl Selection {
    pub(super) fn contains(self, laser: Laser) -> bool {
        match self {
            Self::Front => matches!(laser, Laser::Front | Laser::Robot(1)),
            Self::One(one) => one == laser,
        }
    }
}

impl fmt::Display for Selection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Front => f.write_str("FLASER or ROBOTLASER1"),
            Self::One(laser) => laser.fmt(f),
        }
    }
}

/// Field of view and resolution of one laser from `PARAM` lines, radians.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct LaserParams {
    pub(super) fov: Option<f64>,
    pub(super) resolution: Option<f64>,
}

impl LaserParams {
    /// First beam angle and increment for `beams` readings.
    pub(super) fn geometry(self, beams: usize) -> (f64, f64) {
        let fov = self.fov.unwrap_or(PI);
        let increment = match (self.resolution, self.fov) {
            (Some(resolution), _) => resolution,
            (None, Some(fov)) if beams >= 2 => fov / (beams - 1) as f64,
            _ => default_increment(beams),
        };
        (-fov / 2.0, increment)
    }
}

/// Validates a parsed scan into a record.
pub(super) fn record(
    name: &str,
    scan: Scan,
    (pose, odometry): (Option<Pose2>, Option<Pose2>),
    line: usize,
) -> Result<ScanRecord, ReadError> {
    scan.validate().map_err(|source| ReadError::InvalidScan {
        pos: SourcePos::line(name, line),
        source,
    })?;
    Ok(ScanRecord {
        scan,
        pose,
        odometry,
        line: Some(line),
    })
}

/// Parses one laser line into a record; `params` give the angles of `FLASER` / `RLASER`
/// lines, `odom` the last `ODOM` message's pose (the odometry of `RAWLASER` lines, which
/// carry none). A pure function of its arguments, so that it may run on any thread.
pub(super) fn parse_laser(
    name: &str,
    (params, odom): (LaserParams, Option<Pose2>),
    laser: Laser,
    line: usize,
    text: &str,
) -> Result<ScanRecord, ReadError> {
    let mut fields = Fields::new(name, line, laser, text);
    fields.skip(); // the name
    match laser {
        Laser::Front | Laser::Rear => parse_flaser(name, params, line, text, fields),
        Laser::Robot(_) | Laser::Raw(_) => {
            parse_robotlaser(name, laser, line, text, fields).map(|mut r| {
                if matches!(laser, Laser::Raw(_)) {
                    r.odometry = odom;
                }
                r
            })
        }
    }
}

/// An `FLASER` or `RLASER` line after its name.
fn parse_flaser(
    name: &str,
    params: LaserParams,
    line: usize,
    text: &str,
    mut fields: Fields<'_>,
) -> Result<ScanRecord, ReadError> {
    let n = fields.count("number of readings")?;
    // One pass over the fields; only on an error are the tokens counted, so that a line of
    // the wrong length is reported as such, whatever else is wrong.
    let parsed = fields.ranges(n).and_then(|ranges| {
        let pose = fields.pose("x", "y", "theta")?;
        let odometry = fields.pose("odom_x", "odom_y", "odom_theta")?;
        let stamp = Some(fields.stamps()?);
        fields.end()?;
        Ok((ranges, (pose, odometry), stamp))
    });
    let (ranges, (pose, odometry), stamp) = match parsed {
        Ok(parsed) => parsed,
        Err(e) => {
            let count = text.split_ascii_whitespace().count();
            let layout = "the name, n, n ranges, x y theta odom_x odom_y odom_theta \
                          ipc_timestamp ipc_hostname logger_timestamp";
            fields.check_total(count, n.checked_add(11), n, None, layout)?;
            return Err(e);
        }
    };
    let (angle_min, angle_increment) = params.geometry(n);
    let scan = Scan {
        angle_min,
        angle_increment,
        range_min: 0.0,
        range_max: RANGE_MAX,
        ranges,
        intensities: None,
        stamp,
    };
    record(name, scan, (Some(pose), Some(odometry)), line)
}

/// A `ROBOTLASERk` or `RAWLASERk` line after its name: the laser's settings, ranges,
/// remissions, and (robot laser) the poses and motion.
fn parse_robotlaser(
    name: &str,
    laser: Laser,
    line: usize,
    text: &str,
    mut fields: Fields<'_>,
) -> Result<ScanRecord, ReadError> {
    let robot = matches!(laser, Laser::Robot(_));
    let count = text.split_ascii_whitespace().count();
    fields.number("laser_type")?;
    let start_angle = fields.number("start_angle")?;
    fields.number("fov")?;
    let angular_resolution = fields.number("angular_resolution")?;
    let maximum_range = fields.number("maximum_range")?;
    fields.number("accuracy")?;
    fields.number("remission_mode")?;
    let n = fields.count("number of readings")?;
    let trailing = if robot { 14 } else { 3 };
    let layout = if robot {
        "the name, 7 laser settings, n, n ranges, m, m remissions, laser x y theta, \
         robot x y theta, tv rv forward_safety_dist side_safety_dist turn_axis, \
         ipc_timestamp ipc_hostname logger_timestamp"
    } else {
        "the name, 7 laser settings, n, n ranges, m, m remissions, ipc_timestamp \
         ipc_hostname logger_timestamp"
    };
    // Enough tokens to reach m, before reading n ranges.
    fields.check_at_least(count, n.checked_add(10), n, layout)?;
    let ranges = fields.ranges(n)?;
    let m = fields.count("number of remissions")?;
    let total = n
        .checked_add(m)
        .and_then(|nm| nm.checked_add(10 + trailing));
    fields.check_total(count, total, n, Some(m), layout)?;
    let mut remissions = Vec::with_capacity(m);
    for i in 0..m {
        remissions.push(fields.number_at(|| format!("remission {i}"))?);
    }
    let poses = if robot {
        let pose = fields.pose("laser_x", "laser_y", "laser_theta")?;
        let odometry = fields.pose("robot_x", "robot_y", "robot_theta")?;
        for what in [
            "tv",
            "rv",
            "forward_safety_dist",
            "side_safety_dist",
            "turn_axis",
        ] {
            fields.number(what)?;
        }
        (Some(pose), Some(odometry))
    } else {
        (None, None)
    };
    let stamp = Some(fields.stamps()?);
    let range_max = if maximum_range.is_finite() && maximum_range > 0.0 {
        maximum_range
    } else {
        RANGE_MAX
    };
    let intensities = (m == n && m > 0).then_some(remissions);
    let scan = Scan {
        angle_min: start_angle,
        angle_increment: angular_resolution,
        range_min: 0.0,
        range_max,
        ranges,
        intensities,
        stamp,
    };
    record(name, scan, poses, line)
}
