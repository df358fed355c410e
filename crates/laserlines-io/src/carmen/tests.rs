//! Unit tests of the CARMEN reader.

use super::fields::parse_number;
use super::*;
use crate::reader::{ReadOptions, from_reader_with};
use crate::{Format, Pose2, ScanReader};

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
    assert_eq!(pending_reader.skipped().get("NEFF message (not a scan)"), 1);
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
    assert_eq!(r.odometry, Some(Pose2::new(1.5, -2.0, 0.25)));
    assert_eq!(r.line, Some(1));
    assert_eq!(r.scan.angle_min, -PI / 2.0);
    assert!((r.scan.angle_max() - PI / 2.0).abs() < 1e-12);
    assert!(reader.skipped().is_empty());
    // A time stamp that is not a finite number is an error naming the field, as in the pose.
    let (items, _) = read(&flaser(181, 2.0, &TAIL.replacen("12.5", "nan", 1)), None);
    let e = items[0].as_ref().unwrap_err().to_string();
    assert!(
        e.contains("ipc_timestamp: expected a finite number, found `nan`"),
        "{e}"
    );
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
        e.contains("FLASER range 1: expected a number >= 0 (m) or inf, found `x`"),
        "{e}"
    );
    // No distance is NaN, -inf, beyond a double or negative; 0 is read (as no return), and
    // so is inf, as logs converted from ROS write no return.
    for bad in ["nan", "-inf", "1e400", "-1.5", "-0.001"] {
        let e = read(&format!("FLASER 2 1 {bad} 0 0 0 0 0 0 0 h 0\n"), None).0[0]
            .clone()
            .unwrap_err();
        let want = format!("FLASER range 1: expected a number >= 0 (m) or inf, found `{bad}`");
        assert!(e.contains(&want), "{bad}: {e}");
    }
    assert!(read("FLASER 2 1 0 0 0 0 0 0 0 0 h 0\n", None).0[0].is_ok());
    for inf in ["inf", "+inf", "Infinity"] {
        let (items, _) = read(&format!("FLASER 2 1 {inf} 0 0 0 0 0 0 0 h 0\n"), None);
        let scan = &items[0].as_ref().unwrap().scan;
        assert_eq!(scan.ranges[1], f64::INFINITY, "{inf}");
    }
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
    assert_eq!(s.get("NEFF message (not a scan)"), 2);
    assert_eq!(s.get("TRUEPOS message (not a scan)"), 1);
    assert_eq!(s.get("RLASER scan (another laser)"), 1);
    // The rear laser as the topic.
    let (items, reader) = read(&text, Some("rlaser"));
    assert_eq!(items.len(), 1);
    assert_eq!(items[0].as_ref().unwrap().line, Some(9));
    assert_eq!(reader.skipped().get("FLASER scan (another laser)"), 1);
}

#[test]
fn a_log_cut_inside_its_last_line_says_so() {
    let scan = flaser(2, 1.0, TAIL);
    // Cut inside an ODOM line: its scans are read, and the cut is counted.
    let cut = format!("{scan}ODOM 0.685387 0.112968 1.84");
    let (items, reader) = read(&cut, None);
    assert_eq!(items.len(), 1);
    assert!(items[0].is_ok());
    assert_eq!(reader.skipped().get(SKIP_CUT_LAST_LINE), 1);
    // Every line ended, or a last line without its line end but whole (as the Freiburg 101
    // log ends): nothing cut.
    for whole in [
        format!("{scan}ODOM 0 0 0 0 0 0 1 h 1\n"),
        format!("{scan}ODOM 0 0 0 0 0 0 1 h 1"),
        format!("{scan}NEFF 12"),
        scan.trim_end().to_owned(),
    ] {
        let (items, reader) = read(&whole, None);
        assert_eq!(items.len(), 1, "{whole}");
        assert!(items[0].is_ok(), "{whole}");
        assert_eq!(reader.skipped().get(SKIP_CUT_LAST_LINE), 0, "{whole}");
    }
}

#[test]
fn many_unknown_names_share_one_reason() {
    let text: String =
        (0..40).map(|i| format!("MSG{i} 1\n")).collect::<String>() + &flaser(2, 1.0, TAIL);
    let (_, reader) = read(&text, None);
    let s = reader.skipped();
    assert_eq!(s.total(), 40);
    assert_eq!(
        s.get("other messages (not scans)"),
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
        e.contains(
            "expected laser scans (FLASER or ROBOTLASER1 lines), found no laser message in 1 lines"
        ),
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
    assert_eq!(r.odometry, Some(Pose2::new(0.9, 1.9, 0.5)));
    assert_eq!(r.scan.stamp, Some(100.25));
    let raw = "RAWLASER2 0 -1.0 2.0 1.0 0 0.01 0 3 1 2 3 0 7.5 host 7.6\n";
    let (items, _) = read(raw, Some("RAWLASER2"));
    let r = items[0].as_ref().unwrap();
    assert_eq!(r.pose, None);
    assert_eq!(r.odometry, None);
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

/// The two pose triples of a laser line are kept apart: `pose` is the first (the laser pose,
/// corrected in some published logs), `odometry` the robot's odometry, and a `RAWLASER`,
/// which carries no pose, takes the last `ODOM` before it.
#[test]
fn odometry_is_the_odometry_triple_never_the_laser_pose() {
    let text = format!(
        "{}{}ODOM 5.0 6.0 0.7 0 0 0 1 h 1\n{}",
        flaser(3, 2.0, "10.0 20.0 1.0 0.1 0.2 0.3 1.0 host 1.0"),
        "ROBOTLASER1 0 -1.0 1.0 1.0 8.0 0.01 0 3 1 2 3 0 11.0 21.0 1.1 0.4 0.5 0.6 0 0 0 0 0 2.0 host 2.0\n",
        flaser(3, 2.0, "12.0 22.0 1.2 0.7 0.8 0.9 3.0 host 3.0"),
    );
    let (items, _) = read(&text, None);
    let got: Vec<(Option<Pose2>, Option<Pose2>)> = items
        .iter()
        .map(|r| {
            let r = r.as_ref().unwrap();
            (r.pose, r.odometry)
        })
        .collect();
    assert_eq!(
        got,
        [
            (
                Some(Pose2::new(10.0, 20.0, 1.0)),
                Some(Pose2::new(0.1, 0.2, 0.3))
            ),
            (
                Some(Pose2::new(11.0, 21.0, 1.1)),
                Some(Pose2::new(0.4, 0.5, 0.6))
            ),
            (
                Some(Pose2::new(12.0, 22.0, 1.2)),
                Some(Pose2::new(0.7, 0.8, 0.9))
            ),
        ]
    );
    // RAWLASER: the last ODOM before the line (none before the first ODOM).
    let raw = |t: f64| format!("RAWLASER1 0 -1.0 1.0 1.0 8.0 0.01 0 3 1 2 3 0 {t} host {t}\n");
    let text = format!(
        "{}ODOM 1.0 2.0 0.5 0 0 0 1 h 1\nODOM 1.5 2.5 0.6 0 0 0 1.1 h 1.1\n{}{}ODOM 2.0 3.0 0.7 0 0 0 1.3 h 1.3\n{}",
        raw(0.9),
        raw(1.15),
        raw(1.2),
        raw(1.35)
    );
    let (items, _) = read(&text, Some("RAWLASER1"));
    let odometry: Vec<Option<Pose2>> = items.iter().map(|r| r.as_ref().unwrap().odometry).collect();
    assert_eq!(
        odometry,
        [
            None,
            Some(Pose2::new(1.5, 2.5, 0.6)),
            Some(Pose2::new(1.5, 2.5, 0.6)),
            Some(Pose2::new(2.0, 3.0, 0.7)),
        ]
    );
    // The same on the deferred path `extract` takes.
    let mut reader = from_reader_with(
        "t.clf",
        std::io::Cursor::new(text.clone()),
        Format::Carmen,
        Some("RAWLASER1"),
    )
    .unwrap();
    let mut deferred = Vec::new();
    while let Some(p) = reader.next_pending() {
        deferred.push(p.parse().unwrap().odometry);
    }
    assert_eq!(deferred, odometry);
    // A bad ODOM line is an error naming it, when the chosen laser needs it; reading goes
    // on. The front laser does not read ODOM lines.
    let text = format!("ODOM 1.0 nan 0.5 0 0 0 1 h 1\n{}", raw(1.0));
    let (items, _) = read(&text, Some("RAWLASER1"));
    let e = items[0].clone().unwrap_err();
    assert!(
        e.contains("t.clf:1: ODOM y: expected a finite number, found `nan`"),
        "{e}"
    );
    assert!(items[1].is_ok());
    let text = format!("ODOM 1.0 nan 0.5 0 0 0 1 h 1\n{}", flaser(3, 2.0, TAIL));
    assert!(read(&text, None).0.iter().all(Result::is_ok));
}
