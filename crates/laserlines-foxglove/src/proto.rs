//! `foxglove.LaserScan` and `foxglove.FrameTransform` (protobuf) to and from laserlines' types.
//!
//! Decoding uses `prost` on the message types of the `foxglove` crate, generated from the
//! published Foxglove schemas: the same definitions the writer encodes with, and a decoder
//! that checks every length against the bytes left.
//!
//! `foxglove.LaserScan` has no range limits and gives the angles of the first and last beam
//! rather than an increment:
//! - `angle_increment = (end_angle - start_angle) / (n - 1)`; for fewer than two beams it is
//!   `end_angle - start_angle`, or 1 degree when that is zero (any non-zero value describes
//!   a single beam);
//! - `range_min`/`range_max` come from the channel metadata keys `range_min` and `range_max`
//!   (which laserlines writes), widened to take in every finite positive range of the
//!   message, so that no range the writer kept becomes invalid (`range_max` then lies just
//!   above the largest, a reading of the limit itself being no return; one equal to the
//!   metadata's `range_max` stays no return); without them they are 0 and just above the
//!   largest finite range (1 m when there is none);
//! - the message's own `pose` (the scan's origin in its frame) is not used: laserlines scans
//!   are in the sensor frame.

use foxglove::messages::{FrameTransform, LaserScan, Pose, Quaternion, Timestamp, Vector3};
use laserlines::Scan;
use laserlines_io::Pose2;

/// Range limits a channel declares in its metadata, in metres.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RangeLimits {
    /// `range_min`, when the channel gives it.
    pub min: Option<f64>,
    /// `range_max`, when the channel gives it.
    pub max: Option<f64>,
}

impl RangeLimits {
    /// Reads `range_min` and `range_max` from channel metadata; unparsable or non-finite
    /// values are ignored.
    #[must_use]
    pub fn from_metadata<'a>(mut get: impl FnMut(&str) -> Option<&'a str>) -> Self {
        let mut read = |key: &str| {
            get(key)
                .and_then(|v| v.trim().parse::<f64>().ok())
                .filter(|v| v.is_finite())
        };
        Self {
            min: read("range_min"),
            max: read("range_max"),
        }
    }
}

/// Seconds as a `foxglove` timestamp; negative or non-finite stamps become zero, stamps past
/// the `u32` seconds range saturate.
#[must_use]
pub fn timestamp(seconds: f64) -> Timestamp {
    if !(seconds.is_finite() && seconds > 0.0) {
        return Timestamp::new(0, 0);
    }
    let whole = seconds.floor();
    if whole >= f64::from(u32::MAX) {
        return Timestamp::new(u32::MAX, 999_999_999);
    }
    let nanos = ((seconds - whole) * 1e9).round().min(999_999_999.0) as u32;
    Timestamp::new(whole as u32, nanos)
}

/// A `foxglove` timestamp in seconds.
#[must_use]
pub fn seconds(t: &Timestamp) -> f64 {
    f64::from(t.sec()) + f64::from(t.nsec()) * 1e-9
}

/// The identity pose.
#[must_use]
pub fn identity_pose() -> Pose {
    Pose {
        position: Some(Vector3 {
            x: 0.0,
            y: 0.0,
            z: 0.0,
        }),
        orientation: Some(yaw_quaternion(0.0)),
    }
}

/// A rotation by `yaw` rad about z.
#[must_use]
pub fn yaw_quaternion(yaw: f64) -> Quaternion {
    let (s, c) = (yaw / 2.0).sin_cos();
    Quaternion {
        x: 0.0,
        y: 0.0,
        z: s,
        w: c,
    }
}

/// The yaw of a rotation, rad (REP 103: counter-clockwise about z).
#[must_use]
pub fn quaternion_yaw(q: &Quaternion) -> f64 {
    (2.0 * (q.w * q.z + q.x * q.y)).atan2(1.0 - 2.0 * (q.y * q.y + q.z * q.z))
}

/// The yaw of a rotation about z alone, as the writer wrote it: of the angles whose
/// [`yaw_quaternion`] is this very quaternion, the one with the fewest decimal digits (so a
/// pose written with theta 0.3 reads back 0.3, not 0.30000000000000004); [`quaternion_yaw`]
/// for any other rotation, or when no nearby angle gives the same quaternion.
#[must_use]
pub fn yaw_of_written_quaternion(q: &Quaternion) -> f64 {
    let yaw = quaternion_yaw(q);
    if q.x != 0.0 || q.y != 0.0 || !yaw.is_finite() {
        return yaw;
    }
    let same = |candidate: f64| {
        let r = yaw_quaternion(candidate);
        r.z.to_bits() == q.z.to_bits() && r.w.to_bits() == q.w.to_bits()
    };
    let shortest = (1..=17).find_map(|digits| {
        let candidate: f64 = format!("{:.*e}", digits - 1, yaw).parse().ok()?;
        same(candidate).then_some(candidate)
    });
    if let Some(y) = shortest {
        return y;
    }
    // A few units in the last place either way.
    let mut up = yaw;
    let mut down = yaw;
    for _ in 0..4 {
        up = up.next_up();
        down = down.next_down();
        for candidate in [up, down] {
            if same(candidate) {
                return candidate;
            }
        }
    }
    yaw
}

/// A laserlines scan from a `foxglove.LaserScan` (see the module docs for the conversions).
/// `fallback_stamp` (s) is used when the message has no timestamp. Not validated here.
#[must_use]
pub fn scan_from_foxglove(msg: &LaserScan, limits: RangeLimits, fallback_stamp: f64) -> Scan {
    let n = msg.ranges.len();
    let span = msg.end_angle - msg.start_angle;
    let angle_increment = if n >= 2 {
        span / (n - 1) as f64
    } else if span != 0.0 {
        span
    } else {
        1f64.to_radians()
    };
    let largest = msg
        .ranges
        .iter()
        .copied()
        .filter(|r| r.is_finite() && *r > 0.0)
        .fold(None, |m: Option<f64>, r| Some(m.map_or(r, |m| m.max(r))));
    let smallest = msg
        .ranges
        .iter()
        .copied()
        .filter(|r| r.is_finite() && *r > 0.0)
        .fold(None, |m: Option<f64>, r| Some(m.map_or(r, |m| m.min(r))));
    let range_min = match (limits.min, smallest) {
        (Some(min), Some(s)) => min.min(s).max(0.0),
        (Some(min), None) => min.max(0.0),
        (None, _) => 0.0,
    };
    // A reading of the limit itself is no return (`laserlines::scan::saturated_below`): a
    // limit taken from the data lies just above its largest range.
    let range_max = match (limits.max, largest) {
        (Some(max), Some(l)) if l > max => l.next_up(),
        (Some(max), _) => max,
        (None, Some(l)) => l.next_up(),
        (None, None) => 1.0,
    };
    Scan {
        angle_min: msg.start_angle,
        angle_increment,
        range_min,
        range_max,
        ranges: msg.ranges.clone(),
        intensities: if msg.intensities.is_empty() {
            None
        } else {
            Some(msg.intensities.clone())
        },
        stamp: Some(msg.timestamp.as_ref().map_or(fallback_stamp, seconds)),
    }
}

/// A `foxglove.LaserScan` in frame `frame_id` from a laserlines scan. Ranges that are not
/// valid for the scan ([`laserlines::RangeWindow::contains`]) are written as NaN, so that
/// viewers draw no point for them and readers, which cannot know the scan's limits, never
/// take them for measurements.
#[must_use]
pub fn foxglove_from_scan(scan: &Scan, frame_id: &str, stamp: f64) -> LaserScan {
    let window = scan.range_window(None);
    LaserScan {
        timestamp: Some(timestamp(stamp)),
        frame_id: frame_id.to_owned(),
        pose: Some(identity_pose()),
        start_angle: scan.angle_min,
        end_angle: scan.angle_max(),
        ranges: scan
            .ranges
            .iter()
            .map(|r| if window.contains(*r) { *r } else { f64::NAN })
            .collect(),
        intensities: scan.intensities.clone().unwrap_or_default(),
    }
}

/// A planar pose from a transform (x, y and the yaw of its rotation); `None` when a part is
/// missing or not finite.
#[must_use]
pub fn pose_from_transform(t: &FrameTransform) -> Option<Pose2> {
    let tr = t.translation.as_ref()?;
    let q = t.rotation.as_ref()?;
    let pose = Pose2::new(tr.x, tr.y, yaw_of_written_quaternion(q));
    pose.is_finite().then_some(pose)
}

/// The transform `parent -> child` placing `child` at `pose` in `parent`.
#[must_use]
pub fn transform_from_pose(parent: &str, child: &str, pose: Pose2, stamp: f64) -> FrameTransform {
    FrameTransform {
        timestamp: Some(timestamp(stamp)),
        parent_frame_id: parent.to_owned(),
        child_frame_id: child.to_owned(),
        translation: Some(Vector3 {
            x: pose.x,
            y: pose.y,
            z: 0.0,
        }),
        rotation: Some(yaw_quaternion(pose.theta)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn timestamps_round_trip_to_the_nanosecond() {
        for s in [0.0, 1.5, 212.387282, 1_700_000_000.123_457] {
            let t = timestamp(s);
            assert!((seconds(&t) - s).abs() < 1e-6, "{s}");
        }
        assert_eq!(seconds(&timestamp(-3.0)), 0.0);
        assert_eq!(seconds(&timestamp(f64::NAN)), 0.0);
        assert_eq!(timestamp(1e12).sec(), u32::MAX);
    }

    #[test]
    fn poses_read_back_the_theta_written() {
        for k in 0..200 {
            // Values as users write them, and sums that carry float noise of their own.
            let decimal: f64 = format!("{:.2}", -3.1 + 0.031 * f64::from(k))
                .parse()
                .unwrap();
            let noisy = 0.3 * f64::from(k % 11) - 0.5;
            for theta in [decimal, noisy] {
                let t = transform_from_pose("world", "base_link", Pose2::new(1.0, 2.0, theta), 0.0);
                let back = pose_from_transform(&t).unwrap().theta;
                assert!((back - theta).abs() <= 4.0 * f64::EPSILON * theta.abs().max(1.0));
                // The same quaternion, so nothing a reader can tell apart.
                let again = yaw_quaternion(back);
                let q = t.rotation.as_ref().unwrap();
                assert_eq!((again.z, again.w), (q.z, q.w), "{theta}");
                if theta == decimal {
                    assert_eq!(back, theta, "a decimal theta reads back exactly");
                }
            }
        }
        assert_eq!(
            pose_from_transform(&transform_from_pose(
                "w",
                "b",
                Pose2::new(0.0, 0.0, 0.3),
                0.0
            ))
            .unwrap()
            .theta,
            0.3
        );
    }

    #[test]
    fn yaw_round_trips() {
        for yaw in [-3.0, -1.0, 0.0, 0.5, 3.1] {
            assert!((quaternion_yaw(&yaw_quaternion(yaw)) - yaw).abs() < 1e-12);
        }
    }

    #[test]
    fn invalid_ranges_become_nan_and_limits_widen() {
        let mut scan = Scan::new(
            -1.0,
            0.5,
            0.1,
            4.0,
            vec![1.0, 5.0, 0.05, f64::INFINITY, 4.0, 3.9],
        )
        .unwrap();
        scan.stamp = Some(3.25);
        let m = foxglove_from_scan(&scan, "laser", 3.25);
        assert_eq!((m.ranges[0], m.ranges[5]), (1.0, 3.9));
        // Beyond the limits, and the limit itself (no return).
        assert!(m.ranges[1..5].iter().all(|r| r.is_nan()));
        assert_eq!(m.end_angle, 1.5);
        let limits = RangeLimits {
            min: Some(0.1),
            max: Some(4.0),
        };
        let back = scan_from_foxglove(&m, limits, 0.0);
        assert_eq!(back.angle_increment, 0.5);
        assert_eq!((back.range_min, back.range_max), (0.1, 4.0));
        assert_eq!(back.stamp, Some(3.25));
        back.validate().unwrap();
        // Without metadata: every finite positive range is valid.
        let bare = scan_from_foxglove(&m, RangeLimits::default(), 0.0);
        assert_eq!((bare.range_min, bare.range_max), (0.0, 3.9f64.next_up()));
        // Metadata narrower than the data is widened.
        let narrow = RangeLimits {
            min: Some(2.0),
            max: Some(3.0),
        };
        let wide = scan_from_foxglove(&m, narrow, 0.0);
        assert_eq!((wide.range_min, wide.range_max), (1.0, 3.9f64.next_up()));
    }

    #[test]
    fn single_beams_get_a_nonzero_increment() {
        let m = LaserScan {
            start_angle: 0.3,
            end_angle: 0.3,
            ranges: vec![2.0],
            ..LaserScan::default()
        };
        let s = scan_from_foxglove(&m, RangeLimits::default(), 7.0);
        assert!(s.angle_increment != 0.0);
        assert_eq!(s.stamp, Some(7.0));
        s.validate().unwrap();
    }

    #[test]
    fn metadata_limits_parse_leniently() {
        let meta = [("range_min", " 0.02"), ("range_max", "nan")];
        let l = RangeLimits::from_metadata(|k| meta.iter().find(|(m, _)| *m == k).map(|p| p.1));
        assert_eq!(l.min, Some(0.02));
        assert_eq!(l.max, None);
    }
}
