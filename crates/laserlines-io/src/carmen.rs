//! CARMEN logs (`.clf`, `.log`, gzipped or not): the text logs of the CARMEN robot navigation
//! toolkit, as in the Radish data sets and the Freiburg SLAM benchmark.
//!
//! One message per line, its name first, fields separated by white space; lines starting with
//! `#` are comments and blank lines are ignored. The reader understands:
//!
//! | message | fields after the name | what the reader does |
//! |---|---|---|
//! | `FLASER`, `RLASER` | `n r_1 .. r_n x y theta odom_x odom_y odom_theta ipc_timestamp ipc_hostname logger_timestamp` | a scan of the front / rear laser; angles from `PARAM` (below) |
//! | `ROBOTLASERk` | `laser_type start_angle fov angular_resolution maximum_range accuracy remission_mode n r_1 .. r_n m e_1 .. e_m laser_x laser_y laser_theta robot_x robot_y robot_theta tv rv forward_safety_dist side_safety_dist turn_axis ipc_timestamp ipc_hostname logger_timestamp` | a scan of laser `k` (0..=9); angles and `range_max` from the line, remissions as intensities |
//! | `RAWLASERk` | `laser_type start_angle fov angular_resolution maximum_range accuracy remission_mode n r_1 .. r_n m e_1 .. e_m ipc_timestamp ipc_hostname logger_timestamp` | a scan of laser `k` without a pose |
//! | `ODOM` | `x y theta tv rv accel ipc_timestamp ipc_hostname logger_timestamp` | recognised, not a scan: the laser lines carry their own pose |
//! | `PARAM` | `name value ...` | the laser settings below; other parameters are ignored |
//! | anything else (`NEFF`, `TRUEPOS`, `SYNC`, ...) | | counted as skipped under `unknown message NAME` |
//!
//! **Which laser.** A log may hold several lasers, and the same laser twice (`ROBOTLASER1`
//! and `RAWLASER1`). By default the reader yields the front laser: every `FLASER` and
//! `ROBOTLASER1` line. A topic ([`crate::ReadOptions::topic`]) names one message instead
//! (`RLASER`, `RAWLASER2`, ..., case-insensitive). Scans of the other lasers are counted as
//! skipped (`RLASER scan (another laser)`). A log with no line of the chosen laser ends with
//! an error saying which lasers it has.
//!
//! **Angles of `FLASER` and `RLASER`.** These lines do not store angles. The reader takes them
//! from the last `PARAM laser_front_laser_fov` / `laser_front_laser_resolution` before the
//! line (`laser_rear_laser_*` for `RLASER`; the older spellings `laser_frontlaser_*` too),
//! and otherwise follows CARMEN's own log reader (`carmen_laser_guess_angle_increment`):
//!
//! - the first beam is at `-fov / 2`, with `fov = pi` (180 deg, to the robot's right) unless
//!   `laser_*_fov` says otherwise; beams go counter-clockwise (REP 103);
//! - the angle between beams is `laser_*_resolution` when given; else `fov / (n - 1)` when the
//!   fov is given; else 1 deg for 180 or 181 beams, 0.5 deg for 360 or 361 beams (the SICK
//!   LMS modes; with 180 or 360 beams the logger dropped the last one, so the scan ends one
//!   step short of +90 deg), and `pi / (n - 1)` (n beams spanning 180 deg) for any other count.
//!
//! `laser_*_resolution` is in degrees, as CARMEN writes it. `laser_*_fov` appears in degrees
//! (`180`) and in radians (`3.14159`) in real logs; a value above `2 pi` is read as degrees.
//! See [`default_geometry`].
//!
//! **No return.** A SICK LMS reports "no echo" as a reading at the top of its scale, and the
//! value depends on the logger: 81.91 m (8191 cm, the 13-bit full scale) and the error codes
//! just below it (81.83 .. 81.90 m), a 50.0 m clamp, about 51.1 m in some older logs (51.01 ..
//! 51.25 m, spread by the log's correction), and 32.767 m (32767 mm, the 16-bit full scale,
//! with 32.759 .. 32.765 m just below it). These are never measurements: a reading in one of
//! the [`NO_RETURN_BANDS`] becomes `+inf` ("no return", as REP 117 writes it), so that no
//! extractor ever sees it as a wall. The bands are narrow on purpose: outdoor logs (Freiburg
//! campus) hold genuine readings from 51.3 m up to 81.82 m, which stay valid. A band rather
//! than "everything above the log's largest reading" keeps the reader streaming (it never
//! needs to see the whole log first) and works on standard input.
//!
//! **Range limits.** `range_min` is 0 (CARMEN has none; 0 itself is never valid). `range_max`
//! is [`RANGE_MAX`] for `FLASER` / `RLASER`, and the line's `maximum_range` for
//! `ROBOTLASER` / `RAWLASER` (or [`RANGE_MAX`] when that is not a positive number).
//!
//! **Time and pose.** `scan.stamp` is the line's `ipc_timestamp` in seconds (the time the
//! message was sent; the Freiburg benchmark's relations refer to it). Several published logs
//! have broken time stamps (all 0, or printed with six significant digits so that hundreds of
//! scans share one value): the reader keeps them as written and never reorders, so records
//! come in file order. `pose` is the line's first pose triple `x y theta` (CARMEN's
//! `laser_pose`, in the log's world frame: metres, radians); `RAWLASER` lines have none.
//!
//! **Bad lines.** A line with the wrong number of fields (e.g. fewer than `n + 11` tokens in
//! an `FLASER` line), a field that is not a number, or a line that does not start with a
//! message name is an error naming the file, the line and what was expected; the reader then
//! goes on with the next line. So a caller stops at the first bad line, or counts it and goes
//! on (`laserlines extract --skip-bad`).

use std::f64::consts::{PI, TAU};
use std::fmt;
use std::str::SplitAsciiWhitespace;
use std::sync::Arc;

use laserlines::Scan;

use crate::error::{ReadError, SourcePos, shown};
use crate::reader::{Input, LineItem, Lines, Pending, ScanSource};
use crate::record::{Pose2, ScanRecord};
use crate::skip::SkipCounts;

/// `range_max` of `FLASER` / `RLASER` scans, m: every SICK LMS reading below the error codes
/// 81.83 .. 81.91 m can be a measurement.
pub const RANGE_MAX: f64 = 81.83;

/// Closed intervals of readings that mean "no return", m (see the module docs):
/// the 16-bit millimetre full scale 32.767 m and the codes just below it, the 50 m clamp and
/// the ~51.1 m marker of older logs, and the 13-bit centimetre full scale 81.91 m with the
/// SICK error codes from 81.83 m up. Each band reaches half a unit of the printed precision
/// beyond the values seen, so that rounding in the text never lets a marker through.
pub const NO_RETURN_BANDS: [(f64, f64); 3] =
    [(32.7585, 32.7675), (49.995, 51.3), (81.825, f64::INFINITY)];

/// True when a reading is one of the "no return" markers ([`NO_RETURN_BANDS`]).
#[must_use]
pub fn is_no_return(range: f64) -> bool {
    NO_RETURN_BANDS
        .iter()
        .any(|&(low, high)| range >= low && range <= high)
}

/// Angle of the first beam and angle between beams (rad) of an `FLASER` / `RLASER` line of
/// `beams` readings when the log gives no laser `PARAM`: first beam at -90 deg, 1 deg apart
/// for 180 and 181 beams, 0.5 deg apart for 360 and 361, else `beams` spanning 180 deg.
#[must_use]
pub fn default_geometry(beams: usize) -> (f64, f64) {
    (-PI / 2.0, default_increment(beams))
}

fn default_increment(beams: usize) -> f64 {
    match beams {
        180 | 181 => PI / 180.0,
        360 | 361 => PI / 360.0,
        n if n >= 2 => PI / (n - 1) as f64,
        _ => PI / 180.0,
    }
}

/// Exact powers of ten as `f64` (every one up to 1e22 is representable).
const POW10: [f64; 16] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
];

/// Parses a number exactly as `str::parse::<f64>` does, faster for the plain decimals CARMEN
/// writes (`-12.345`): with at most 15 digits the digits form an exact integer `m` and
/// `m / 10^k` is one correctly rounded division, the same value the standard parser gives.
/// Anything else (exponents, `inf`, long numbers) goes to the standard parser.
fn parse_number(token: &str) -> Option<f64> {
    let bytes = token.as_bytes();
    let (negative, digits) = match bytes.first() {
        Some(b'-') => (true, &bytes[1..]),
        Some(b'+') => (false, &bytes[1..]),
        _ => (false, bytes),
    };
    let mut mantissa: u64 = 0;
    let mut count = 0usize;
    let mut fraction = 0usize;
    let mut dot = false;
    for &b in digits {
        match b {
            b'0'..=b'9' => {
                count += 1;
                if count > 15 {
                    return token.parse().ok();
                }
                mantissa = mantissa * 10 + u64::from(b - b'0');
                if dot {
                    fraction += 1;
                }
            }
            b'.' if !dot => dot = true,
            _ => return token.parse().ok(),
        }
    }
    if count == 0 {
        return token.parse().ok();
    }
    let value = mantissa as f64 / POW10[fraction];
    Some(if negative { -value } else { value })
}

/// A laser message of a CARMEN log.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Laser {
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
    fn from_name(name: &str) -> Option<Self> {
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
enum Selection {
    /// `FLASER` and `ROBOTLASER1`.
    Front,
    /// One message.
    One(Laser),
}

impl Selection {
    fn contains(self, laser: Laser) -> bool {
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
struct LaserParams {
    fov: Option<f64>,
    resolution: Option<f64>,
}

impl LaserParams {
    /// First beam angle and increment for `beams` readings.
    fn geometry(self, beams: usize) -> (f64, f64) {
        let fov = self.fov.unwrap_or(PI);
        let increment = match (self.resolution, self.fov) {
            (Some(resolution), _) => resolution,
            (None, Some(fov)) if beams >= 2 => fov / (beams - 1) as f64,
            _ => default_increment(beams),
        };
        (-fov / 2.0, increment)
    }
}

/// Distinct names of unknown messages counted one by one; the rest share one reason.
const MAX_UNKNOWN_NAMES: usize = 16;
/// Longest message name shown in a skip reason.
const MAX_NAME_CHARS: usize = 24;

/// Reads a CARMEN log.
pub(crate) struct CarmenSource {
    lines: Lines,
    state: State,
}

/// Everything but the lines, so that a line's text and the state borrow apart.
struct State {
    name: String,
    /// The same, shared with deferred parsers.
    shared_name: Arc<str>,
    selection: Selection,
    front: LaserParams,
    rear: LaserParams,
    /// A line of the chosen laser was seen (parsed or not).
    seen_selected: bool,
    /// Other lasers seen, for the message when none of the chosen one is found.
    others: Vec<Laser>,
    unknown_names: Vec<String>,
    /// A fatal read error ended the input.
    failed: bool,
    ended: bool,
}

impl CarmenSource {
    /// A reader of `input`; `topic` names the laser message to read (default: the front
    /// laser, `FLASER` and `ROBOTLASER1`).
    pub(crate) fn new(name: &str, input: Input, topic: Option<&str>) -> Result<Self, ReadError> {
        let selection = match topic {
            None => Selection::Front,
            Some(topic) => match Laser::from_name(&topic.trim().to_ascii_uppercase()) {
                Some(laser) => Selection::One(laser),
                None => {
                    return Err(ReadError::Topic {
                        file: name.to_owned(),
                        topic: topic.to_owned(),
                        expected: "a CARMEN laser message: FLASER, RLASER, ROBOTLASER0..9 or \
                                   RAWLASER0..9"
                            .to_owned(),
                    });
                }
            },
        };
        Ok(Self {
            lines: Lines::new(name, input),
            state: State {
                name: name.to_owned(),
                shared_name: Arc::from(name),
                selection,
                front: LaserParams::default(),
                rear: LaserParams::default(),
                seen_selected: false,
                others: Vec::new(),
                unknown_names: Vec::new(),
                failed: false,
                ended: false,
            },
        })
    }
}

impl State {
    /// The error at the end of a log without a line of the chosen laser.
    fn missing_laser(&self, lines: usize) -> ReadError {
        let found = if self.others.is_empty() {
            if lines == 0 {
                "an empty log".to_owned()
            } else {
                format!("no laser message in {lines} lines")
            }
        } else {
            let names: Vec<String> = self.others.iter().map(ToString::to_string).collect();
            format!("only {} lines (choose one as the topic)", names.join(", "))
        };
        ReadError::Syntax {
            pos: SourcePos::line(&self.name, lines.max(1)),
            expected: format!("laser scans ({} lines)", self.selection),
            found,
        }
    }

    /// Counts a message this reader does not know.
    fn count_unknown(&mut self, name: &str, skipped: &mut SkipCounts) {
        if name.len() <= MAX_NAME_CHARS
            && (self.unknown_names.iter().any(|n| n == name)
                || self.unknown_names.len() < MAX_UNKNOWN_NAMES)
        {
            if !self.unknown_names.iter().any(|n| n == name) {
                self.unknown_names.push(name.to_owned());
            }
            skipped.add(&format!("unknown message {name}"));
        } else {
            skipped.add("unknown message (other names)");
        }
    }

    /// Applies a `PARAM` line.
    fn param(&mut self, line: usize, text: &str) -> Result<(), ReadError> {
        let mut tokens = text.split_ascii_whitespace();
        tokens.next();
        let (Some(name), Some(value)) = (tokens.next(), tokens.next()) else {
            return Err(ReadError::Syntax {
                pos: SourcePos::line(&self.name, line),
                expected: "PARAM name value".to_owned(),
                found: shown(text),
            });
        };
        let (params, is_fov) = match name {
            "laser_front_laser_fov" | "laser_frontlaser_fov" => (&mut self.front, true),
            "laser_front_laser_resolution" | "laser_frontlaser_resolution" => {
                (&mut self.front, false)
            }
            "laser_rear_laser_fov" | "laser_rearlaser_fov" => (&mut self.rear, true),
            "laser_rear_laser_resolution" | "laser_rearlaser_resolution" => (&mut self.rear, false),
            _ => return Ok(()),
        };
        let parsed = value
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite() && *v > 0.0);
        let angle = match (parsed, is_fov) {
            (Some(fov), true) if fov <= TAU + 1e-6 => Some(fov),
            (Some(fov_deg), true) if fov_deg <= 360.0 => Some(fov_deg.to_radians()),
            (Some(res_deg), false) if res_deg <= 360.0 => Some(res_deg.to_radians()),
            _ => None,
        };
        let Some(angle) = angle else {
            return Err(ReadError::Field {
                pos: SourcePos::line(&self.name, line),
                field: format!("PARAM {name}"),
                expected: if is_fov {
                    "a field of view in (0, 2 pi] rad or (0, 360] deg".to_owned()
                } else {
                    "a resolution in (0, 360] deg".to_owned()
                },
                found: shown(value),
            });
        };
        if is_fov {
            params.fov = Some(angle);
        } else {
            params.resolution = Some(angle);
        }
        Ok(())
    }

    /// The parameters that give the angles of `laser`'s lines.
    fn params(&self, laser: Laser) -> LaserParams {
        if laser == Laser::Rear {
            self.rear
        } else {
            self.front
        }
    }
}

/// Parses one laser line into a record; `params` give the angles of `FLASER` / `RLASER`
/// lines. A pure function of its arguments, so that it may run on any thread.
fn parse_laser(
    name: &str,
    params: LaserParams,
    laser: Laser,
    line: usize,
    text: &str,
) -> Result<ScanRecord, ReadError> {
    let mut fields = Fields::new(name, line, laser, text);
    fields.skip(); // the name
    match laser {
        Laser::Front | Laser::Rear => {
            let n = fields.count("number of readings")?;
            // One pass over the fields; only on an error are the tokens counted, so that
            // a line of the wrong length is reported as such, whatever else is wrong.
            let parsed = fields.ranges(n).and_then(|ranges| {
                let pose = fields.pose("x", "y", "theta")?;
                fields.pose("odom_x", "odom_y", "odom_theta")?;
                let stamp = fields.stamps()?;
                fields.end()?;
                Ok((ranges, pose, stamp))
            });
            let (ranges, pose, stamp) = match parsed {
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
            record(name, scan, Some(pose), line)
        }
        Laser::Robot(_) | Laser::Raw(_) => {
            let count = text.split_ascii_whitespace().count();
            fields.number("laser_type")?;
            let start_angle = fields.number("start_angle")?;
            fields.number("fov")?;
            let angular_resolution = fields.number("angular_resolution")?;
            let maximum_range = fields.number("maximum_range")?;
            fields.number("accuracy")?;
            fields.number("remission_mode")?;
            let n = fields.count("number of readings")?;
            let trailing = if matches!(laser, Laser::Robot(_)) {
                14
            } else {
                3
            };
            let layout = if matches!(laser, Laser::Robot(_)) {
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
            let pose = if matches!(laser, Laser::Robot(_)) {
                let pose = fields.pose("laser_x", "laser_y", "laser_theta")?;
                fields.pose("robot_x", "robot_y", "robot_theta")?;
                for what in [
                    "tv",
                    "rv",
                    "forward_safety_dist",
                    "side_safety_dist",
                    "turn_axis",
                ] {
                    fields.number(what)?;
                }
                Some(pose)
            } else {
                None
            };
            let stamp = fields.stamps()?;
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
            record(name, scan, pose, line)
        }
    }
}

/// Validates a parsed scan into a record.
fn record(
    name: &str,
    scan: Scan,
    pose: Option<Pose2>,
    line: usize,
) -> Result<ScanRecord, ReadError> {
    scan.validate().map_err(|source| ReadError::InvalidScan {
        pos: SourcePos::line(name, line),
        source,
    })?;
    Ok(ScanRecord {
        scan,
        pose,
        line: Some(line),
    })
}

/// The fields of one line, read in order, with errors naming line and field.
struct Fields<'a> {
    file: &'a str,
    line: usize,
    laser: Laser,
    text_len: usize,
    tokens: SplitAsciiWhitespace<'a>,
}

impl<'a> Fields<'a> {
    fn new(file: &'a str, line: usize, laser: Laser, text: &'a str) -> Self {
        Self {
            file,
            line,
            laser,
            text_len: text.len(),
            tokens: text.split_ascii_whitespace(),
        }
    }

    fn pos(&self) -> SourcePos {
        SourcePos::line(self.file, self.line)
    }

    fn skip(&mut self) {
        self.tokens.next();
    }

    fn field_error(&self, field: String, expected: &str, token: Option<&str>) -> ReadError {
        ReadError::Field {
            pos: self.pos(),
            field: format!("{} {field}", self.laser),
            expected: expected.to_owned(),
            found: token.map_or_else(|| "the end of the line".to_owned(), shown),
        }
    }

    /// A count (of readings or remissions).
    fn count(&mut self, what: &str) -> Result<usize, ReadError> {
        let token = self.tokens.next();
        token
            .and_then(|t| t.parse::<usize>().ok())
            .ok_or_else(|| self.field_error(what.to_owned(), "a non-negative integer", token))
    }

    fn number(&mut self, what: &str) -> Result<f64, ReadError> {
        self.number_at(|| what.to_owned())
    }

    fn number_at(&mut self, what: impl FnOnce() -> String) -> Result<f64, ReadError> {
        let token = self.tokens.next();
        token
            .and_then(parse_number)
            .ok_or_else(|| self.field_error(what(), "a number", token))
    }

    /// `n` ranges in metres, "no return" markers turned into `+inf`.
    fn ranges(&mut self, n: usize) -> Result<Vec<f64>, ReadError> {
        // `n` comes from the line: never reserve more than its tokens can fill.
        let mut ranges = Vec::with_capacity(n.min(self.text_len / 2 + 1));
        for i in 0..n {
            let token = self.tokens.next();
            let r = token
                .and_then(parse_number)
                .ok_or_else(|| self.field_error(format!("range {i}"), "a number (m)", token))?;
            ranges.push(if is_no_return(r) { f64::INFINITY } else { r });
        }
        Ok(ranges)
    }

    /// A finite pose triple.
    fn pose(&mut self, x: &str, y: &str, theta: &str) -> Result<Pose2, ReadError> {
        let mut part = |what: &str| {
            let token = self.tokens.next();
            token
                .and_then(parse_number)
                .filter(|v| v.is_finite())
                .ok_or_else(|| self.field_error(what.to_owned(), "a finite number", token))
        };
        Ok(Pose2::new(part(x)?, part(y)?, part(theta)?))
    }

    /// `ipc_timestamp ipc_hostname logger_timestamp`: the ipc time stamp when finite.
    fn stamps(&mut self) -> Result<Option<f64>, ReadError> {
        let ipc = self.number("ipc_timestamp")?;
        self.skip(); // ipc_hostname
        self.number("logger_timestamp")?;
        Ok(ipc.is_finite().then_some(ipc))
    }

    /// The line has no more tokens.
    fn end(&mut self) -> Result<(), ReadError> {
        match self.tokens.next() {
            None => Ok(()),
            Some(token) => Err(ReadError::Syntax {
                pos: self.pos(),
                expected: "the end of the line".to_owned(),
                found: shown(token),
            }),
        }
    }

    fn count_error(&self, total: &str, detail: &str, found: usize, layout: &str) -> ReadError {
        ReadError::Syntax {
            pos: self.pos(),
            expected: format!("{total} tokens for {} {detail} ({layout})", self.laser),
            found: format!("{found} tokens"),
        }
    }

    /// The line has exactly `total` tokens.
    fn check_total(
        &self,
        count: usize,
        total: Option<usize>,
        n: usize,
        m: Option<usize>,
        layout: &str,
    ) -> Result<(), ReadError> {
        if total == Some(count) {
            return Ok(());
        }
        let detail = match m {
            Some(m) => format!("with {n} ranges and {m} remissions"),
            None => format!("with {n} ranges"),
        };
        Err(self.count_error(&show_total(total), &detail, count, layout))
    }

    /// The line has at least `total` tokens.
    fn check_at_least(
        &self,
        count: usize,
        total: Option<usize>,
        n: usize,
        layout: &str,
    ) -> Result<(), ReadError> {
        if total.is_some_and(|t| count >= t) {
            return Ok(());
        }
        let total = format!("at least {}", show_total(total));
        Err(self.count_error(&total, &format!("with {n} ranges"), count, layout))
    }
}

fn show_total(total: Option<usize>) -> String {
    total.map_or_else(|| "more than 2^64".to_owned(), |t| t.to_string())
}

/// True for a CARMEN message name: an upper-case letter, then upper-case letters, digits or
/// underscores.
fn is_message_name(token: &str) -> bool {
    let mut bytes = token.bytes();
    bytes.next().is_some_and(|b| b.is_ascii_uppercase())
        && bytes.all(|b| b.is_ascii_uppercase() || b.is_ascii_digit() || b == b'_')
}

impl CarmenSource {
    /// The next item; laser lines parsed at once, or left to parse when `defer`.
    fn next_item(&mut self, skipped: &mut SkipCounts, defer: bool) -> Option<Pending> {
        let state = &mut self.state;
        loop {
            let item = match self.lines.next_line() {
                Some(Ok(item)) => item,
                Some(Err(e)) => {
                    state.failed = true;
                    return Some(Pending::Ready(Err(e)));
                }
                None => {
                    if state.ended || state.failed || state.seen_selected {
                        return None;
                    }
                    state.ended = true;
                    let e = state.missing_laser(self.lines.line_number());
                    return Some(Pending::Ready(Err(e)));
                }
            };
            let (line, text) = match item {
                LineItem::NotUtf8(e) => return Some(Pending::Ready(Err(e))),
                LineItem::Text(line, text) => (line, text),
            };
            let Some(first) = text.split_ascii_whitespace().next() else {
                continue; // blank line
            };
            if first.starts_with('#') {
                continue;
            }
            if let Some(laser) = Laser::from_name(first) {
                if state.selection.contains(laser) {
                    state.seen_selected = true;
                    let params = state.params(laser);
                    if !defer {
                        let parsed = parse_laser(&state.name, params, laser, line, text);
                        return Some(Pending::Ready(parsed));
                    }
                    let name = Arc::clone(&state.shared_name);
                    let text = text.to_owned();
                    return Some(Pending::Deferred(Box::new(move || {
                        parse_laser(&name, params, laser, line, &text)
                    })));
                }
                if !state.others.contains(&laser) {
                    state.others.push(laser);
                }
                skipped.add(&format!("{laser} scan (another laser)"));
                continue;
            }
            match first {
                "ODOM" => {}
                "PARAM" => {
                    if let Err(e) = state.param(line, text) {
                        return Some(Pending::Ready(Err(e)));
                    }
                }
                name if is_message_name(name) => state.count_unknown(name, skipped),
                other => {
                    return Some(Pending::Ready(Err(ReadError::Syntax {
                        pos: SourcePos::line(&state.name, line),
                        expected: "a CARMEN message name (e.g. FLASER, ODOM, PARAM) or a `#` \
                                   comment"
                            .to_owned(),
                        found: shown(other),
                    })));
                }
            }
        }
    }
}

impl ScanSource for CarmenSource {
    fn next_record(&mut self, skipped: &mut SkipCounts) -> Option<Result<ScanRecord, ReadError>> {
        self.next_item(skipped, false).map(Pending::parse)
    }

    /// Laser lines are handed over unparsed: parsing their numbers costs more than reading.
    fn next_pending(&mut self, skipped: &mut SkipCounts) -> Option<Pending> {
        self.next_item(skipped, true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reader::{ReadOptions, from_reader_with};
    use crate::{Format, ScanReader};

    fn read(text: &str, topic: Option<&str>) -> (Vec<Result<ScanRecord, String>>, ScanReader) {
        let mut reader = from_reader_with(
            "t.clf",
            std::io::Cursor::new(text.to_owned()),
            Format::Carmen,
            topic,
        )
        .unwrap();
        let items = reader
            .by_ref()
            .map(|r| r.map_err(|e| e.to_string()))
            .collect();
        (items, reader)
    }

    fn flaser(n: usize, range: f64, tail: &str) -> String {
        let ranges: Vec<String> = (0..n).map(|_| format!("{range}")).collect();
        format!("FLASER {n} {} {tail}\n", ranges.join(" "))
    }

    const TAIL: &str = "1.5 -2.0 0.25 1.5 -2.0 0.25 12.5 host 0.3";

    #[test]
    fn fast_numbers_equal_the_standard_parser() {
        let mut cases: Vec<String> = [
            "0",
            "-0",
            "+0",
            "1.",
            ".5",
            "-.5",
            "+.5",
            ".",
            "-",
            "+",
            "",
            "81.91",
            "32.767",
            "1.01893e+09",
            "4.29497e+09",
            "-0.445999",
            "1134864629.895182",
            "576.536523",
            "123456789012345",
            "1234567890123456",
            "0.000000000000001",
            "1e5",
            "inf",
            "-inf",
            "nan",
            "NaN",
            "1..2",
            "1.2.3",
            "--1",
            "+-1",
            "0x10",
            "1_000",
            " 1",
            "9007199254740993",
            "0.1",
            "0.2",
            "0.3",
            "2.675",
            "1.005",
            "999999999999999",
            "99999999999999.9",
        ]
        .iter()
        .map(|s| (*s).to_owned())
        .collect();
        // Every decimal with up to 6 digits around the point, both signs, and leading zeros.
        let mut x: u64 = 0x2545_f491_4f6c_dd1d;
        for _ in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let digits = (x % 16) as usize + 1;
            let point = (x >> 8) as usize % (digits + 1);
            let mut s = String::new();
            if x & (1 << 40) != 0 {
                s.push('-');
            }
            let mut y = x >> 12;
            for i in 0..digits {
                if i == point {
                    s.push('.');
                }
                s.push(char::from(b'0' + (y % 10) as u8));
                y /= 10;
            }
            cases.push(s);
        }
        for case in &cases {
            let fast = parse_number(case).map(f64::to_bits);
            let std = case.parse::<f64>().ok().map(f64::to_bits);
            assert_eq!(fast, std, "{case:?}");
        }
    }

    #[test]
    fn pending_items_parse_to_what_next_gives() {
        let text = format!(
            "{}FLASER 5 1 2\nNEFF 1\nPARAM laser_front_laser_resolution 0.5\n{}3.5 x\n{}",
            flaser(181, 2.0, TAIL),
            flaser(360, 81.91, TAIL),
            flaser(2, 1.0, TAIL)
        );
        let (items, reader) = read(&text, None);
        let mut pending_reader =
            from_reader_with("t.clf", std::io::Cursor::new(text), Format::Carmen, None).unwrap();
        let mut pending = Vec::new();
        while let Some(p) = pending_reader.next_pending() {
            pending.push(p);
        }
        let deferred = pending
            .iter()
            .filter(|p| matches!(p, Pending::Deferred(_)))
            .count();
        assert_eq!(deferred, 4, "{pending:?}");
        let parsed: Vec<_> = pending
            .into_iter()
            .map(|p| p.parse().map_err(|e| e.to_string()))
            .collect();
        assert_eq!(items, parsed);
        // Deferred errors are the caller's to count; the rest is counted as usual.
        assert_eq!(reader.skipped().get("malformed record"), 2);
        assert_eq!(pending_reader.skipped().get("malformed record"), 1);
        assert_eq!(pending_reader.skipped().get("unknown message NEFF"), 1);
        assert_eq!(pending_reader.records(), 0);
    }

    #[test]
    fn laser_names_round_trip() {
        for name in [
            "FLASER",
            "RLASER",
            "ROBOTLASER1",
            "ROBOTLASER0",
            "RAWLASER4",
        ] {
            assert_eq!(Laser::from_name(name).unwrap().to_string(), name);
        }
        for name in [
            "ROBOTLASER",
            "ROBOTLASER12",
            "RAWLASERx",
            "LASER3",
            "flaser",
        ] {
            assert_eq!(Laser::from_name(name), None, "{name}");
        }
    }

    #[test]
    fn default_geometry_follows_carmen() {
        let deg = PI / 180.0;
        assert_eq!(default_geometry(180), (-PI / 2.0, deg));
        assert_eq!(default_geometry(181), (-PI / 2.0, deg));
        assert_eq!(default_geometry(360), (-PI / 2.0, deg / 2.0));
        assert_eq!(default_geometry(361), (-PI / 2.0, deg / 2.0));
        let (min, inc) = default_geometry(91);
        assert_eq!(min, -PI / 2.0);
        assert!((inc - 2.0 * deg).abs() < 1e-15);
        assert!(default_geometry(1).1 > 0.0 && default_geometry(0).1 > 0.0);
    }

    #[test]
    fn flaser_fields_pose_and_stamp() {
        let (items, reader) = read(&flaser(181, 2.0, TAIL), None);
        assert_eq!(items.len(), 1);
        let r = items[0].as_ref().unwrap();
        assert_eq!(r.scan.len(), 181);
        assert_eq!(r.scan.stamp, Some(12.5));
        assert_eq!(r.pose, Some(Pose2::new(1.5, -2.0, 0.25)));
        assert_eq!(r.line, Some(1));
        assert_eq!(r.scan.angle_min, -PI / 2.0);
        assert!((r.scan.angle_max() - PI / 2.0).abs() < 1e-12);
        assert!(reader.skipped().is_empty());
    }

    #[test]
    fn param_fov_and_resolution_set_the_angles() {
        // Resolution only: first beam at -90 deg, 0.5 deg apart.
        let text = format!(
            "PARAM laser_front_laser_resolution 0.5 nohost 0\n{}",
            flaser(360, 2.0, TAIL)
        );
        let (items, _) = read(&text, None);
        let s = &items[0].as_ref().unwrap().scan;
        assert_eq!(s.angle_min, -PI / 2.0);
        assert!((s.angle_increment - 0.5_f64.to_radians()).abs() < 1e-15);
        // Fov in radians, no resolution: n beams spanning it, centred.
        let text = format!(
            "PARAM laser_front_laser_fov 1.5 1 host 1\n{}",
            flaser(151, 2.0, TAIL)
        );
        let s = read(&text, None).0[0].as_ref().unwrap().scan.clone();
        assert!((s.angle_min + 0.75).abs() < 1e-15);
        assert!((s.angle_increment - 0.01).abs() < 1e-15);
        // Fov in degrees.
        let text = format!(
            "PARAM laser_front_laser_fov 100 1 host 1\nPARAM laser_front_laser_resolution 0.25\n{}",
            flaser(401, 2.0, TAIL)
        );
        let s = read(&text, None).0[0].as_ref().unwrap().scan.clone();
        assert!((s.angle_min + 50.0_f64.to_radians()).abs() < 1e-12);
        assert!((s.angle_max() - 50.0_f64.to_radians()).abs() < 1e-12);
        // Rear parameters do not touch the front laser, and the older spelling works.
        let text = format!(
            "PARAM laser_rear_laser_resolution 0.25\nPARAM laser_frontlaser_resolution 1 0.0 nohost 0\n{}",
            flaser(180, 2.0, TAIL)
        );
        let s = read(&text, None).0[0].as_ref().unwrap().scan.clone();
        assert_eq!(s.angle_increment, PI / 180.0);
    }

    #[test]
    fn bad_param_values_are_errors_naming_the_line() {
        for value in ["abc", "0", "-1", "nan", "400"] {
            let text = format!(
                "PARAM laser_front_laser_fov {value}\n{}",
                flaser(3, 1.0, TAIL)
            );
            let (items, _) = read(&text, None);
            assert_eq!(items.len(), 2, "{value}");
            let e = items[0].as_ref().unwrap_err();
            assert!(e.starts_with("t.clf:1: PARAM laser_front_laser_fov"), "{e}");
            assert!(items[1].is_ok());
        }
        let (items, _) = read(&format!("PARAM lonely\n{}", flaser(3, 1.0, TAIL)), None);
        assert!(items[0].as_ref().unwrap_err().contains("PARAM name value"));
    }

    #[test]
    fn no_return_markers_become_infinite() {
        for marker in [81.91, 81.83, 81.87, 50.0, 51.06, 51.25, 32.767, 32.759] {
            assert!(is_no_return(marker), "{marker}");
        }
        for real in [0.1, 32.63, 32.77, 49.91, 51.36, 79.34, 81.82] {
            assert!(!is_no_return(real), "{real}");
        }
        let text = "FLASER 4 1.0 81.91 50.0 32.767 0 0 0 0 0 0 0 h 0\n";
        let (items, _) = read(text, None);
        let s = &items[0].as_ref().unwrap().scan;
        assert_eq!(s.ranges[0], 1.0);
        assert!(s.ranges[1..].iter().all(|r| *r == f64::INFINITY));
        assert_eq!(s.count_valid(s.range_window(None)), 1);
    }

    #[test]
    fn wrong_field_counts_are_errors_and_reading_goes_on() {
        let short = "FLASER 5 1 2 3 4 5 0 0 0 0 0 0 0 h\n"; // one token short
        let long = "FLASER 2 1 2 3 0 0 0 0 0 0 0 h 0\n"; // one token too many
        let text = format!("{short}{long}{}", flaser(3, 1.0, TAIL));
        let (items, reader) = read(&text, None);
        assert_eq!(items.len(), 3);
        let e = items[0].as_ref().unwrap_err();
        assert!(
            e.starts_with("t.clf:1: expected 16 tokens for FLASER with 5 ranges")
                && e.ends_with("found 15 tokens"),
            "{e}"
        );
        assert!(
            items[1]
                .as_ref()
                .unwrap_err()
                .starts_with("t.clf:2: expected 13 tokens")
        );
        assert!(items[2].is_ok());
        assert_eq!(reader.skipped().get("malformed record"), 2);
        // No count, a bad count, a huge count.
        for bad in ["FLASER\n", "FLASER x 1 2\n", "FLASER -3 1\n"] {
            let e = read(bad, None).0[0].clone().unwrap_err();
            assert!(
                e.contains("FLASER number of readings: expected a non-negative integer"),
                "{e}"
            );
        }
        let e = read("FLASER 18446744073709551615 1\n", None).0[0]
            .clone()
            .unwrap_err();
        assert!(e.contains("more than 2^64"), "{e}");
        let e = read("FLASER 2 1 x 0 0 0 0 0 0 0 h 0\n", None).0[0]
            .clone()
            .unwrap_err();
        assert!(
            e.contains("FLASER range 1: expected a number (m), found `x`"),
            "{e}"
        );
        let e = read("FLASER 1 1 0 nan 0 0 0 0 0 h 0\n", None).0[0]
            .clone()
            .unwrap_err();
        assert!(e.contains("FLASER y: expected a finite number"), "{e}");
    }

    #[test]
    fn comments_odom_unknown_messages_and_other_lasers() {
        let text = format!(
            "# comment\n\n#PARAM x 1\nODOM 0 0 0 0 0 0 1 h 1\nNEFF 12\nNEFF 3\nTRUEPOS 1 2\n{}RLASER 1 1.0 0 0 0 0 0 0 1 h 1\n",
            flaser(2, 1.0, TAIL)
        );
        let (items, reader) = read(&text, None);
        assert_eq!(items.len(), 1);
        assert_eq!(items[0].as_ref().unwrap().line, Some(8));
        let s = reader.skipped();
        assert_eq!(s.get("unknown message NEFF"), 2);
        assert_eq!(s.get("unknown message TRUEPOS"), 1);
        assert_eq!(s.get("RLASER scan (another laser)"), 1);
        // The rear laser as the topic.
        let (items, reader) = read(&text, Some("rlaser"));
        assert_eq!(items.len(), 1);
        assert_eq!(items[0].as_ref().unwrap().line, Some(9));
        assert_eq!(reader.skipped().get("FLASER scan (another laser)"), 1);
    }

    #[test]
    fn many_unknown_names_share_one_reason() {
        let text: String =
            (0..40).map(|i| format!("MSG{i} 1\n")).collect::<String>() + &flaser(2, 1.0, TAIL);
        let (_, reader) = read(&text, None);
        let s = reader.skipped();
        assert_eq!(s.total(), 40);
        assert_eq!(
            s.get("unknown message (other names)"),
            40 - MAX_UNKNOWN_NAMES as u64
        );
        assert_eq!(s.iter().count(), MAX_UNKNOWN_NAMES + 1);
    }

    #[test]
    fn garbage_lines_are_errors() {
        let text = format!("3.5 1 2\nflaser 1 2\n{}", flaser(2, 1.0, TAIL));
        let (items, _) = read(&text, None);
        assert_eq!(items.len(), 3);
        assert!(
            items[0]
                .as_ref()
                .unwrap_err()
                .contains("expected a CARMEN message name")
        );
        assert!(items[1].is_err() && items[2].is_ok());
    }

    #[test]
    fn a_log_without_the_chosen_laser_ends_with_an_error() {
        let (items, _) = read("ODOM 0 0 0 0 0 0 1 h 1\n", None);
        assert_eq!(items.len(), 1);
        let e = items[0].as_ref().unwrap_err();
        assert!(
            e.contains("expected laser scans (FLASER or ROBOTLASER1 lines), found no laser message in 1 lines"),
            "{e}"
        );
        let (items, _) = read("", None);
        assert!(
            items[0]
                .as_ref()
                .unwrap_err()
                .contains("found an empty log")
        );
        let (items, _) = read(&flaser(2, 1.0, TAIL), Some("RAWLASER1"));
        let e = items[0].as_ref().unwrap_err();
        assert!(
            e.contains("expected laser scans (RAWLASER1 lines), found only FLASER lines"),
            "{e}"
        );
        // An unknown topic is refused when opening.
        let e = from_reader_with(
            "t.clf",
            std::io::Cursor::new(Vec::new()),
            Format::Carmen,
            Some("/scan"),
        )
        .unwrap_err();
        assert!(matches!(e, ReadError::Topic { .. }), "{e}");
        assert_eq!(
            ReadOptions::format(Some(Format::Carmen))
                .with_topic(Some("FLASER"))
                .topic
                .as_deref(),
            Some("FLASER")
        );
    }

    #[test]
    fn robotlaser_and_rawlaser_carry_their_geometry() {
        let robot = "ROBOTLASER1 0 -1.5 3.0 0.5 20.0 0.01 0 7 1 2 3 4 5 6 81.91 7 10 20 30 40 50 60 70 \
                     1.0 2.0 0.5 0.9 1.9 0.5 0.1 0.2 0.3 0.4 0.5 100.25 host 3.0\n";
        let (items, _) = read(robot, None);
        let r = items[0].as_ref().unwrap();
        assert_eq!(r.scan.angle_min, -1.5);
        assert_eq!(r.scan.angle_increment, 0.5);
        assert_eq!(r.scan.range_max, 20.0);
        assert_eq!(r.scan.ranges[6], f64::INFINITY);
        assert_eq!(r.scan.intensities.as_deref().unwrap()[6], 70.0);
        assert_eq!(r.pose, Some(Pose2::new(1.0, 2.0, 0.5)));
        assert_eq!(r.scan.stamp, Some(100.25));
        let raw = "RAWLASER2 0 -1.0 2.0 1.0 0 0.01 0 3 1 2 3 0 7.5 host 7.6\n";
        let (items, _) = read(raw, Some("RAWLASER2"));
        let r = items[0].as_ref().unwrap();
        assert_eq!(r.pose, None);
        assert_eq!(r.scan.range_max, RANGE_MAX);
        assert_eq!(r.scan.intensities, None);
        assert_eq!(r.scan.stamp, Some(7.5));
        // One remission short.
        let e = read(
            "RAWLASER2 0 -1.0 2.0 1.0 0 0.01 0 3 1 2 3 2 5 7.5 host 7.6\n",
            Some("RAWLASER2"),
        )
        .0[0]
            .clone()
            .unwrap_err();
        assert!(
            e.contains("expected 18 tokens for RAWLASER2 with 3 ranges and 2 remissions"),
            "{e}"
        );
        // Cut before m.
        let e = read("ROBOTLASER1 0 -1.0 2.0 1.0 0 0.01 0 3 1 2\n", None).0[0]
            .clone()
            .unwrap_err();
        assert!(
            e.contains("expected at least 13 tokens for ROBOTLASER1 with 3 ranges"),
            "{e}"
        );
        // Geometry that is not a scan.
        let e = read(
            "RAWLASER1 0 -1.0 2.0 0 0 0.01 0 3 1 2 3 0 7.5 host 7.6\n",
            Some("RAWLASER1"),
        )
        .0[0]
            .clone()
            .unwrap_err();
        assert!(e.contains("invalid scan"), "{e}");
    }

    #[test]
    fn bad_utf8_is_an_error_and_reading_goes_on() {
        let mut bytes = b"NEFF \xff\n".to_vec();
        bytes.extend_from_slice(flaser(2, 1.0, TAIL).as_bytes());
        let mut reader =
            crate::from_reader("t.clf", std::io::Cursor::new(bytes), Format::Carmen).unwrap();
        assert!(reader.next().unwrap().is_err());
        assert!(reader.next().unwrap().is_ok());
        assert!(reader.next().is_none());
    }
}
