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
//! | `ODOM` | `x y theta tv rv accel ipc_timestamp ipc_hostname logger_timestamp` | not a scan: its pose is the odometry of the `RAWLASER` lines after it (the other laser lines carry their own) |
//! | `PARAM` | `name value ...` | the laser settings below; other parameters are ignored |
//! | anything else (`NEFF`, `TRUEPOS`, `SYNC`, ...) | | not a scan: counted as skipped under `NAME message (not a scan)`, so that the summary shows what the log held besides scans |
//!
//! A log that ends inside an `ODOM` line (its last line without a line end, and short of
//! fields) is counted as skipped under [`SKIP_CUT_LAST_LINE`]; a cut scan line is an error of
//! its own, and a whole last line without its line end is read as any other.
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
//! message was sent; the Freiburg benchmark's relations refer to it; a NaN or infinite one is
//! an error, as in a pose). Several published logs
//! have broken time stamps (all 0, or printed with six significant digits so that hundreds of
//! scans share one value): the reader keeps them as written and never reorders, so records
//! come in file order. `pose` is the line's first pose triple `x y theta` (CARMEN's
//! `laser_pose`, in the log's world frame: metres, radians; in published logs often corrected
//! by SLAM); `RAWLASER` lines have none. `odometry` is the robot's odometry: the second
//! triple `odom_x odom_y odom_theta` of `FLASER`/`RLASER`, `robot_x robot_y robot_theta` of
//! `ROBOTLASER`, and for `RAWLASER` the pose of the last `ODOM` line before it (none before
//! the first). Mapping with odometry (`laserlines map --odometry on`) reads `odometry`
//! only, never the laser pose.
//!
//! **Bad lines.** A line with the wrong number of fields (e.g. fewer than `n + 11` tokens in
//! an `FLASER` line), a field that is not a number, or a line that does not start with a
//! message name is an error naming the file, the line and what was expected; the reader then
//! goes on with the next line. So a caller stops at the first bad line, or counts it and goes
//! on (`laserlines extract --skip-bad`).

use std::f64::consts::{PI, TAU};
use std::sync::Arc;

use crate::error::{ReadError, SourcePos, shown};
use crate::reader::{Input, LineItem, Lines, Pending, ScanSource};
use crate::record::{Pose2, ScanRecord};
use crate::skip::SkipCounts;

mod fields;
mod laser;

use laser::{Laser, LaserParams, Selection, parse_laser};

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

pub(super) fn default_increment(beams: usize) -> f64 {
    match beams {
        180 | 181 => PI / 180.0,
        360 | 361 => PI / 360.0,
        n if n >= 2 => PI / (n - 1) as f64,
        _ => PI / 180.0,
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
    /// The pose of the last `ODOM` line (read only when the chosen laser is a `RAWLASER`,
    /// whose lines carry no odometry).
    odom: Option<Pose2>,
    /// A line of the chosen laser was seen (parsed or not).
    seen_selected: bool,
    /// Other lasers seen, for the message when none of the chosen one is found.
    others: Vec<Laser>,
    unknown_names: Vec<String>,
    /// A fatal read error ended the input.
    failed: bool,
    ended: bool,
    /// The last line read was an `ODOM` line with fewer fields than `ODOM` has.
    short_odom: bool,
}

/// The skip reason of a log that ends inside an `ODOM` line: its last line has no line end
/// and fewer fields than `ODOM` has, so the file was cut there (a cut scan line is an error
/// of its own).
pub const SKIP_CUT_LAST_LINE: &str = "last line cut short (the log ends inside an ODOM line)";

/// Tokens of a whole `ODOM` line, its name with them.
const ODOM_TOKENS: usize = 10;

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
                odom: None,
                seen_selected: false,
                others: Vec::new(),
                unknown_names: Vec::new(),
                failed: false,
                ended: false,
                short_odom: false,
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
            skipped.add(&format!("{name} message (not a scan)"));
        } else {
            skipped.add("other messages (not scans)");
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

    /// The parameters that give the angles of `laser`'s lines, and the last `ODOM` pose.
    fn params(&self, laser: Laser) -> (LaserParams, Option<Pose2>) {
        let params = if laser == Laser::Rear {
            self.rear
        } else {
            self.front
        };
        (params, self.odom)
    }

    /// Reads the pose of an `ODOM` line (`ODOM x y theta tv rv accel ...`) when the chosen
    /// laser's lines need it.
    fn odom(&mut self, line: usize, text: &str) -> Result<(), ReadError> {
        if !matches!(self.selection, Selection::One(Laser::Raw(_))) {
            return Ok(());
        }
        let mut tokens = text.split_ascii_whitespace();
        tokens.next();
        let mut parts = [0.0; 3];
        for (part, field) in parts.iter_mut().zip(["x", "y", "theta"]) {
            let token = tokens.next();
            *part = token
                .and_then(fields::parse_number)
                .filter(|v| v.is_finite())
                .ok_or_else(|| ReadError::Field {
                    pos: SourcePos::line(&self.name, line),
                    field: format!("ODOM {field}"),
                    expected: "a finite number".to_owned(),
                    found: token.map_or_else(|| "the end of the line".to_owned(), shown),
                })?;
        }
        self.odom = Some(Pose2::new(parts[0], parts[1], parts[2]));
        Ok(())
    }
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
                    if !state.ended && state.short_odom && self.lines.last_unterminated() {
                        skipped.add(SKIP_CUT_LAST_LINE);
                    }
                    if state.ended || state.failed || state.seen_selected {
                        state.ended = true;
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
            state.short_odom = false;
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
                "ODOM" => {
                    state.short_odom = text.split_ascii_whitespace().count() < ODOM_TOKENS;
                    if let Err(e) = state.odom(line, text) {
                        return Some(Pending::Ready(Err(e)));
                    }
                }
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
mod tests;
