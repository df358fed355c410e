//! BreezySLAM `.dat` logs: a Hokuyo URG-04LX on the Paris Mines Tech robot (CoreSLAM).
//!
//! One scan per line, 707 whitespace-separated tokens:
//!
//! | tokens | meaning | what the reader does |
//! |---|---|---|
//! | 0 | time stamp, integer microseconds | `scan.stamp` in seconds |
//! | 1 | not used by BreezySLAM | not interpreted |
//! | 2, 3 | left and right wheel encoder counts, cumulative | wheel odometry: `odometry` and `pose` |
//! | 4..=23 | 20 more fields BreezySLAM skips | not interpreted |
//! | 24..=705 | the 682 ranges, integer millimetres | `scan.ranges` in metres |
//! | 706 | one trailing value BreezySLAM's loaders drop | not interpreted (not a 683rd beam) |
//!
//! **Geometry.** The file does not store angles. The URG-04LX measures SCIP steps 44..=725
//! of a 1024-step turn, step 384 facing forward; these are the 682 beams. So
//! `angle_increment = 2 pi / 1024` (0.3515625 deg), `angle_min = -340 * angle_increment`
//! (-119.53 deg) and the last beam is at `+341 * angle_increment` (+119.88 deg),
//! counter-clockwise as in ROS. `range_min = 0.02` m and `range_max = 5.6` m: the value 0
//! (no echo) and the URG error codes 1..=19 mm are never measurements.
//!
//! **Pose.** Wheel odometry (the record's `odometry`, and its `pose` too) from the encoder
//! counts with the robot's constants as the BreezySLAM repository's `Rover` class states
//! them (wheel radius 77 mm, half axle 165 mm, 2000 ticks per wheel revolution): see
//! [`WheelOdometry`]. The pose is the robot's (the
//! middle of the wheel axle) in the odometry frame that starts at `(0, 0, 0)` at the first
//! scan of the input. The laser sits [`LASER_OFFSET_X`] ahead of it (BreezySLAM's
//! `MinesLaser`); the pose does not include that offset.
//!
//! A line with another number of tokens, or a token that is not an integer where one is
//! needed, is an error naming the line; the reader then goes on with the next line. Blank
//! lines are skipped.

use laserlines::Scan;
use laserlines::math::wrap_angle;

use crate::error::{ReadError, SourcePos, shown};
use crate::reader::{Input, LineItem, Lines, ScanSource};
use crate::record::{Pose2, ScanRecord};
use crate::skip::SkipCounts;

/// Tokens per line.
pub const TOKENS: usize = 707;
/// Beams per scan.
pub const BEAMS: usize = 682;
/// Index of the token holding the first range.
pub const FIRST_RANGE_TOKEN: usize = 24;
/// Angle between beams, rad (360 deg / 1024 SCIP steps).
pub const ANGLE_INCREMENT: f64 = std::f64::consts::TAU / 1024.0;
/// Angle of the first beam, rad: SCIP step 44, 340 steps right of the front step 384.
pub const ANGLE_MIN: f64 = -340.0 * ANGLE_INCREMENT;
/// Smallest valid range, m (0 and 1..=19 mm are URG "no echo" and error codes).
pub const RANGE_MIN: f64 = 0.02;
/// Largest valid range, m.
pub const RANGE_MAX: f64 = 5.6;
/// Wheel radius of the Paris Mines Tech robot, m.
pub const WHEEL_RADIUS: f64 = 0.077;
/// Half the distance between the wheels, m.
pub const HALF_AXLE: f64 = 0.165;
/// Encoder ticks per wheel revolution.
pub const TICKS_PER_REVOLUTION: f64 = 2000.0;
/// How far ahead of the wheel axle the laser sits, m (x in the robot frame).
pub const LASER_OFFSET_X: f64 = 0.145;

const TOKENS_EXPECTED: &str = "707 tokens (timestamp, 23 fields, 682 ranges, 1 trailing)";

/// Differential-drive wheel odometry from cumulative encoder counts.
///
/// Between two readings, with the wheels turned by `dl` and `dr` radians
/// (`ticks * 2 pi / TICKS_PER_REVOLUTION`), the robot moves `ds = R (dl + dr) / 2` along its
/// heading and turns `dtheta = R (dr - dl) / (2 h)` (R wheel radius, h half axle); these are
/// BreezySLAM's `WheeledVehicle.computePoseChange` once its `Rover` tick conversion is
/// applied. The step is integrated at the mid-heading,
/// `x += ds cos(theta + dtheta / 2)`, `y += ds sin(theta + dtheta / 2)`, and `theta` is kept
/// in `(-pi, pi]`.
#[derive(Debug, Clone, PartialEq)]
pub struct WheelOdometry {
    /// Wheel radius, m.
    pub wheel_radius: f64,
    /// Half the distance between the wheels, m.
    pub half_axle: f64,
    /// Encoder ticks per wheel revolution.
    pub ticks_per_revolution: f64,
    last: Option<(i64, i64)>,
    pose: Pose2,
}

impl Default for WheelOdometry {
    /// The Paris Mines Tech robot: 77 mm wheels, 165 mm half axle, 2000 ticks per turn.
    fn default() -> Self {
        Self::new(WHEEL_RADIUS, HALF_AXLE, TICKS_PER_REVOLUTION)
    }
}

impl WheelOdometry {
    /// Odometry for a robot with these constants (m, m, ticks), starting at `(0, 0, 0)`.
    #[must_use]
    pub fn new(wheel_radius: f64, half_axle: f64, ticks_per_revolution: f64) -> Self {
        Self {
            wheel_radius,
            half_axle,
            ticks_per_revolution,
            last: None,
            pose: Pose2::default(),
        }
    }

    /// Takes the next cumulative encoder counts and returns the pose. The first call
    /// returns `(0, 0, 0)`.
    pub fn update(&mut self, left_ticks: i64, right_ticks: i64) -> Pose2 {
        if let Some((l0, r0)) = self.last {
            let to_rad = std::f64::consts::TAU / self.ticks_per_revolution;
            let dl = (i128::from(left_ticks) - i128::from(l0)) as f64 * to_rad;
            let dr = (i128::from(right_ticks) - i128::from(r0)) as f64 * to_rad;
            let ds = self.wheel_radius * (dl + dr) / 2.0;
            let dtheta = self.wheel_radius * (dr - dl) / (2.0 * self.half_axle);
            let mid = self.pose.theta + dtheta / 2.0;
            self.pose.x += ds * mid.cos();
            self.pose.y += ds * mid.sin();
            self.pose.theta = wrap_angle(self.pose.theta + dtheta);
        }
        self.last = Some((left_ticks, right_ticks));
        self.pose
    }

    /// The current pose.
    #[must_use]
    pub fn pose(&self) -> Pose2 {
        self.pose
    }
}

/// Reads a BreezySLAM `.dat` log.
pub(crate) struct DatSource {
    name: String,
    lines: Lines,
    odometry: WheelOdometry,
}

impl DatSource {
    pub(crate) fn new(name: &str, input: Input) -> Self {
        Self {
            name: name.to_owned(),
            lines: Lines::new(name, input),
            odometry: WheelOdometry::default(),
        }
    }
}

/// The largest range a Hokuyo reports, mm: the 18 bits of SCIP's three-character encoding.
/// A reading outside `0..=MAX_READING_MM` is no reading but a corrupt token.
pub(crate) const MAX_READING_MM: i64 = (1 << 18) - 1;

/// Parses one `.dat` line into a scan and the encoder counts.
fn parse_line(name: &str, line: usize, text: &str) -> Result<(Scan, i64, i64), ReadError> {
    let count = text.split_ascii_whitespace().count();
    if count != TOKENS {
        return Err(ReadError::Syntax {
            pos: SourcePos::line(name, line),
            expected: TOKENS_EXPECTED.to_owned(),
            found: count.to_string(),
        });
    }
    let bad = |index: usize, token: &str, what: String, unit: &str| ReadError::Field {
        pos: SourcePos::line(name, line),
        field: format!("token {index} ({what})"),
        expected: format!("an integer ({unit})"),
        found: shown(token),
    };
    let mut ranges = Vec::with_capacity(BEAMS);
    let (mut stamp_us, mut left, mut right) = (0, 0, 0);
    for (index, token) in text.split_ascii_whitespace().enumerate() {
        let value = || token.parse::<i64>();
        match index {
            0 => {
                stamp_us =
                    value().map_err(|_| bad(index, token, "timestamp".into(), "microseconds"))?;
            }
            2 => {
                left =
                    value().map_err(|_| bad(index, token, "left wheel encoder".into(), "ticks"))?;
            }
            3 => {
                right = value()
                    .map_err(|_| bad(index, token, "right wheel encoder".into(), "ticks"))?;
            }
            i if (FIRST_RANGE_TOKEN..FIRST_RANGE_TOKEN + BEAMS).contains(&i) => {
                let beam = i - FIRST_RANGE_TOKEN;
                let mm = value()
                    .ok()
                    .filter(|mm| (0..=MAX_READING_MM).contains(mm))
                    .ok_or_else(|| ReadError::Field {
                        pos: SourcePos::line(name, line),
                        field: format!("token {index} (range of beam {beam})"),
                        expected: format!(
                            "an integer from 0 to {MAX_READING_MM} (millimetres, the most a \
                             SCIP reading carries)"
                        ),
                        found: shown(token),
                    })?;
                ranges.push(mm as f64 / 1000.0);
            }
            _ => {}
        }
    }
    let scan = Scan {
        angle_min: ANGLE_MIN,
        angle_increment: ANGLE_INCREMENT,
        range_min: RANGE_MIN,
        range_max: RANGE_MAX,
        ranges,
        intensities: None,
        stamp: Some(stamp_us as f64 / 1e6),
    };
    Ok((scan, left, right))
}

impl ScanSource for DatSource {
    fn next_record(&mut self, _skipped: &mut SkipCounts) -> Option<Result<ScanRecord, ReadError>> {
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
            return Some(
                parse_line(&self.name, line, text).map(|(scan, left, right)| {
                    let pose = self.odometry.update(left, right);
                    ScanRecord {
                        scan,
                        pose: Some(pose),
                        odometry: Some(pose),
                        line: Some(line),
                    }
                }),
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn geometry_matches_the_urg04lx_steps() {
        assert!((ANGLE_INCREMENT.to_degrees() - 0.3515625).abs() < 1e-12);
        assert!((ANGLE_MIN.to_degrees() - (-119.53125)).abs() < 1e-9);
        let last = ANGLE_MIN + (BEAMS - 1) as f64 * ANGLE_INCREMENT;
        assert!((last.to_degrees() - 119.8828125).abs() < 1e-9);
        // Beam 340 is step 384: straight ahead.
        assert!((ANGLE_MIN + 340.0 * ANGLE_INCREMENT).abs() < 1e-12);
    }

    #[test]
    fn straight_run_one_wheel_turn_moves_one_circumference() {
        let mut odo = WheelOdometry::default();
        assert_eq!(odo.update(100, 200), Pose2::new(0.0, 0.0, 0.0));
        let p = odo.update(2100, 2200);
        assert!((p.x - 2.0 * PI * 0.077).abs() < 1e-12, "{p:?}");
        assert!(p.y.abs() < 1e-12 && p.theta.abs() < 1e-12);
    }

    #[test]
    fn spin_in_place_turns_by_wheel_arc_over_half_axle() {
        let mut odo = WheelOdometry::default();
        odo.update(0, 0);
        // Each wheel half a turn, in opposite directions: arc pi * R each, turn = arc / h.
        let p = odo.update(-1000, 1000);
        let want = PI * 0.077 / 0.165;
        assert!((p.theta - want).abs() < 1e-12, "{p:?}");
        assert!(p.x.abs() < 1e-12 && p.y.abs() < 1e-12);
    }

    #[test]
    fn constant_curvature_follows_the_exact_circle() {
        // Left wheel 1 tick, right wheel 2 ticks per step: a circle to the left.
        let mut odo = WheelOdometry::default();
        let steps = 3000i64;
        let mut p = odo.update(0, 0);
        for k in 1..=steps {
            p = odo.update(k, 2 * k);
        }
        let to_rad = 2.0 * PI / 2000.0;
        let (pl, pr) = (steps as f64 * to_rad, 2.0 * steps as f64 * to_rad);
        let theta = 0.077 * (pr - pl) / (2.0 * 0.165);
        let rho = 0.165 * (pr + pl) / (pr - pl);
        let (x, y) = (rho * theta.sin(), rho * (1.0 - theta.cos()));
        assert!(
            (p.x - x).abs() < 1e-6 && (p.y - y).abs() < 1e-6,
            "{p:?} vs {x} {y}"
        );
        assert!((p.theta - wrap_angle(theta)).abs() < 1e-9);
    }

    #[test]
    fn encoder_extremes_do_not_overflow() {
        let mut odo = WheelOdometry::default();
        odo.update(i64::MIN, i64::MAX);
        let p = odo.update(i64::MAX, i64::MIN);
        assert!(p.is_finite(), "{p:?}");
    }
}
