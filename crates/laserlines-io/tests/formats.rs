//! Reading hand-written fixtures of every format, with values checked by hand.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::path::Path;

use laserlines::RangeWindow;
use laserlines_io::{Format, Pose2, ScanRecord, breezy, open};

fn read_all(path: &str) -> Vec<ScanRecord> {
    let reader = open(Path::new(path), None).unwrap();
    let records: Result<Vec<_>, _> = reader.collect();
    records.unwrap()
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn json_single_object_with_every_field() {
    let records = read_all("tests/fixtures/three_beams.json");
    assert_eq!(records.len(), 1);
    let r = &records[0];
    let s = &r.scan;
    assert_eq!(r.line, Some(1));
    assert_eq!(s.angle_min, -0.5);
    assert_eq!(s.angle_increment, 0.5);
    assert_eq!((s.range_min, s.range_max), (0.1, 10.0));
    assert_eq!(s.ranges[0], 1.0);
    assert!(s.ranges[1].is_nan(), "null is kept as NaN");
    assert_eq!(s.ranges[2], 2.5);
    assert_eq!(s.intensities.as_deref(), Some(&[100.0, 0.0, 50.5][..]));
    assert_eq!(s.stamp, Some(12.25));
    assert_eq!(r.pose, Some(Pose2::new(1.0, -2.0, 0.5)));
    // Beam 0 at -0.5 rad, 1 m; beam 2 at +0.5 rad, 2.5 m.
    let pts = s.points(s.range_window(None));
    assert_eq!(pts.len(), 2);
    assert!(close(pts[0].point.x, 0.877_582_561_890_372_8, 1e-15));
    assert!(close(pts[0].point.y, -0.479_425_538_604_203, 1e-15));
    assert_eq!(pts[1].index, 2);
    assert!(close(pts[1].point.x, 2.193_956_404_725_932, 1e-15));
    assert!(close(pts[1].point.y, 1.198_563_846_510_507_5, 1e-15));
}

/// A ROS message written as JSON keeps its time in `header.stamp`: ROS 2's `sec`/`nanosec`,
/// ROS 1's `secs`/`nsecs`; a top-level `stamp` comes first; a `header.stamp` of another form
/// is an error naming it.
#[test]
fn json_reads_a_ros_header_stamp() {
    let read = |text: &str| {
        let dir = std::env::temp_dir().join(format!("laserlines-io-header-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("scan.jsonl");
        std::fs::write(&path, text).unwrap();
        open(&path, None).unwrap().collect::<Result<Vec<_>, _>>()
    };
    let scan = r#""angle_min": -0.5, "angle_increment": 0.5, "range_min": 0.1, "range_max": 10.0, "ranges": [1.0, 2.0]"#;
    let text = [
        format!(r#"{{"header": {{"stamp": {{"sec": 1700000000, "nanosec": 250000000}}, "frame_id": "laser"}}, {scan}}}"#),
        format!(r#"{{"header": {{"seq": 7, "stamp": {{"secs": 12, "nsecs": 500000000}}}}, {scan}}}"#),
        format!(r#"{{"stamp": 3.0, "header": {{"stamp": {{"sec": 9, "nanosec": 0}}}}, {scan}}}"#),
        format!(r#"{{"header": {{"frame_id": "laser"}}, {scan}}}"#),
        // Zero is no time, as the bag and MCAP readers take it.
        format!(r#"{{"header": {{"stamp": {{"sec": 0, "nanosec": 0}}}}, {scan}}}"#),
    ]
    .join("\n");
    let records = read(&text).unwrap();
    let stamps: Vec<_> = records.iter().map(|r| r.scan.stamp).collect();
    assert_eq!(
        stamps,
        [Some(1_700_000_000.25), Some(12.5), Some(3.0), None, None]
    );
    for (stamp, needle) in [
        (r#"{"secs": 1, "nsecs": 3e9}"#, "header.stamp.nsecs"),
        (r#"{"sec": 1, "nsecs": 0}"#, "(ROS 1)"),
        (r#"{"sec": Infinity, "nanosec": 0}"#, "found `Infinity`"),
    ] {
        let e = read(&format!(r#"{{"header": {{"stamp": {stamp}}}, {scan}}}"#)).unwrap_err();
        assert!(e.to_string().contains(needle), "{stamp}: {e}");
    }
    let e = read(&format!(r#"{{"header": {{"stamp": 12.5}}, {scan}}}"#)).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("header.stamp") && msg.contains("nanosec"),
        "{msg}"
    );
    let e = read(&format!(
        r#"{{"header": {{"stamp": {{"sec": -1, "nanosec": 0}}}}, {scan}}}"#
    ))
    .unwrap_err();
    assert!(e.to_string().contains("header.stamp.sec"), "{e}");
}

#[test]
fn json_top_level_array_is_read_element_by_element() {
    let records = read_all("tests/fixtures/two_scans_array.json");
    assert_eq!(records.len(), 2);
    assert_eq!(records[0].line, Some(2));
    assert_eq!(records[0].scan.ranges, vec![1.0, 2.0, 3.0, 4.0]);
    assert_eq!(records[0].scan.stamp, None);
    assert_eq!(records[1].line, Some(4));
    assert_eq!(records[1].scan.angle_min, 1.0);
    assert_eq!(
        records[1].scan.angle_increment, -0.25,
        "reversed scans are kept"
    );
    assert_eq!(records[1].scan.ranges[0], 0.5);
    assert!(records[1].scan.ranges[1].is_nan());
    assert_eq!(records[1].scan.stamp, Some(3.5));
}

#[test]
fn jsonl_from_python_keeps_nan_and_infinity() {
    // `tests/fixtures/python_nonfinite.jsonl` is Python 3.11's `json.dumps` of two scans with
    // `float('nan')`, `float('inf')` and `float('-inf')` in them, as it writes them by
    // default: `NaN`, `Infinity`, `-Infinity` (and the same words inside a string).
    let records = read_all("tests/fixtures/python_nonfinite.jsonl");
    assert_eq!(records.len(), 2);
    let s = &records[0].scan;
    assert_eq!(s.ranges[0], 1.0);
    assert!(s.ranges[1].is_nan());
    assert_eq!(
        s.ranges[2],
        f64::INFINITY,
        "a beam that saw nothing within range"
    );
    assert_eq!(s.ranges[3], 2.5);
    assert_eq!(s.ranges[4], f64::INFINITY);
    let intensities = s.intensities.as_deref().unwrap();
    assert_eq!(intensities[..4], [10.0, 0.0, f64::NEG_INFINITY, 5.0]);
    assert!(intensities[4].is_nan());
    assert_eq!((s.stamp, s.range_max), (Some(3.5), 5.6));
    let t = &records[1];
    assert_eq!(t.scan.ranges, vec![f64::INFINITY, 1.5]);
    assert_eq!(t.pose, Some(Pose2::new(1.0, 2.0, 0.5)));
    assert_eq!(t.line, Some(2));
    // The largest numbers stay what they are beside a Python token.
    let text = r#"{"angle_min": 0, "angle_increment": 0.1, "range_min": 0, "range_max": 1, "ranges": [NaN, 1.79e308, 179e306, -Infinity]}"#;
    let reader = laserlines_io::from_reader("big.json", std::io::Cursor::new(text), Format::Json);
    let ranges = &reader.unwrap().next().unwrap().unwrap().scan.ranges;
    assert!(ranges[0].is_nan());
    assert_eq!(ranges[1..], [1.79e308, 1.79e308, f64::NEG_INFINITY]);
}

#[test]
fn jsonl_one_scan_per_line_blank_lines_skipped() {
    let reader = open(Path::new("tests/fixtures/scans.jsonl"), None).unwrap();
    assert_eq!(reader.format(), Format::Jsonl);
    let records: Vec<_> = reader.map(Result::unwrap).collect();
    assert_eq!(records.len(), 3);
    assert_eq!(
        records.iter().map(|r| r.line).collect::<Vec<_>>(),
        vec![Some(1), Some(3), Some(4)]
    );
    let valid: Vec<usize> = records
        .iter()
        .map(|r| r.scan.count_valid(r.scan.range_window(None)))
        .collect();
    // [1.5, 2.0, 0.01 < range_min]; [null, 6.0 > range_max, 5.6 the limit itself: no
    // return, as a clamping driver writes it]; no beams.
    assert_eq!(valid, vec![2, 0, 0]);
    assert_eq!(records[1].scan.stamp, Some(100.1));
    assert!(records[2].scan.is_empty());
}

#[test]
fn csv_with_comments_empty_and_nan_ranges() {
    let records = read_all("tests/fixtures/scan.csv");
    assert_eq!(records.len(), 1);
    let s = &records[0].scan;
    assert_eq!(records[0].line, Some(6));
    assert_eq!(s.angle_min, -0.15);
    assert!(close(s.angle_increment, 0.1, 1e-15));
    assert_eq!(s.ranges[0], 1.25);
    assert!(s.ranges[1].is_nan() && s.ranges[2].is_nan());
    assert_eq!(s.ranges[3], 3.5);
    assert_eq!((s.range_min, s.range_max), (0.05, 8.0));
    assert_eq!(s.stamp, Some(7.5));
    assert_eq!(records[0].pose, None);
    assert!(close(s.angle(3), 0.15, 1e-15));
}

#[test]
fn csv_without_limits_accepts_every_positive_range_and_decreasing_angles() {
    let records = read_all("tests/fixtures/scan_no_meta.csv");
    let s = &records[0].scan;
    assert_eq!(s.angle_min, 0.3);
    assert!(close(s.angle_increment, -0.1, 1e-15));
    assert_eq!(s.range_min, laserlines_io::csv::DEFAULT_RANGE_MIN);
    assert_eq!(s.range_max, laserlines_io::csv::DEFAULT_RANGE_MAX);
    assert_eq!(s.ranges, vec![2.0, 2.5, 0.0]);
    // 0 is never a measurement.
    assert_eq!(s.count_valid(s.range_window(None)), 2);
}

#[test]
fn breezy_dat_tokens_geometry_and_odometry() {
    let records = read_all("tests/fixtures/two_scans.dat");
    assert_eq!(records.len(), 2);
    let (a, b) = (&records[0], &records[1]);
    assert_eq!(a.line, Some(1));
    assert_eq!(b.line, Some(2));
    assert_eq!(a.scan.len(), 682, "the trailing token is not a beam");
    assert_eq!(a.scan.stamp, Some(1.0));
    assert_eq!(b.scan.stamp, Some(1.1));
    assert_eq!(a.scan.angle_min, breezy::ANGLE_MIN);
    assert!(close(a.scan.angle_min.to_degrees(), -119.53125, 1e-9));
    assert!(close(a.scan.angle_increment.to_degrees(), 0.3515625, 1e-12));
    assert_eq!((a.scan.range_min, a.scan.range_max), (0.02, 5.6));
    assert_eq!(a.scan.ranges[0], 1.0);
    assert_eq!(a.scan.ranges[340], 2.5);
    assert_eq!(a.scan.ranges[681], 0.019);
    assert_eq!(a.scan.ranges[1], 0.0);
    // 0 (no echo) and 19 mm (an URG error code) are not measurements.
    let pts = a.scan.points(a.scan.range_window(None));
    assert_eq!(
        pts.iter().map(|p| p.index).collect::<Vec<_>>(),
        vec![0, 340]
    );
    // Beam 340 is SCIP step 384: straight ahead.
    assert!(close(pts[1].point.x, 2.5, 1e-12) && pts[1].point.y.abs() < 1e-12);
    // Beam 0 is 119.53 deg to the right.
    assert!(close(pts[0].angle, -119.53125_f64.to_radians(), 1e-12));
    // Odometry: the first scan is the origin; both wheels one turn forward = one
    // circumference (2 pi 77 mm) straight ahead.
    assert_eq!(a.pose, Some(Pose2::new(0.0, 0.0, 0.0)));
    let p = b.pose.unwrap();
    assert!(
        close(p.x, 2.0 * std::f64::consts::PI * 0.077, 1e-12),
        "{p:?}"
    );
    assert!(p.y.abs() < 1e-12 && p.theta.abs() < 1e-12);
}

#[test]
fn bundled_excerpt_reads_forty_scans_with_poses() {
    let records = laserlines_io::demo::urg04lx_excerpt().unwrap();
    assert_eq!(records.len(), laserlines_io::demo::URG04LX_EXCERPT_SCANS);
    assert_eq!(records[0].scan.stamp, Some(212.387282));
    assert_eq!(records[39].scan.stamp, Some(216.200669));
    for w in records.windows(2) {
        assert!(w[1].scan.stamp > w[0].scan.stamp);
    }
    for r in &records {
        assert_eq!(r.scan.len(), 682);
        assert!(r.pose.unwrap().is_finite());
        assert!(
            r.scan
                .count_valid(r.scan.range_window(Some(RangeWindow::PAPER)))
                > 50
        );
    }
    assert_eq!(records[0].pose, Some(Pose2::default()));
}

#[test]
fn gzip_is_transparent_by_name_and_by_magic() {
    use std::io::Write;
    let dir = std::env::temp_dir().join(format!("laserlines-io-gz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read("tests/fixtures/scans.jsonl").unwrap();
    let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    enc.write_all(&text).unwrap();
    let gz = enc.finish().unwrap();
    let named = dir.join("scans.jsonl.gz");
    std::fs::write(&named, &gz).unwrap();
    assert_eq!(open(&named, None).unwrap().count(), 3);
    // Gzip content under a plain name is recognised by its magic bytes.
    let unnamed = dir.join("scans.jsonl");
    std::fs::write(&unnamed, &gz).unwrap();
    assert_eq!(open(&unnamed, None).unwrap().count(), 3);
    // And so is gzip on a stream (standard input).
    let reader =
        laserlines_io::from_reader("-", std::io::Cursor::new(gz.clone()), Format::Jsonl).unwrap();
    assert_eq!(reader.count(), 3);
    // Two members (`cat a.gz b.gz`) read as one text; bytes after them that start no member
    // end the reading after the scans, with an error that says so.
    let two = [gz.clone(), gz].concat();
    std::fs::write(&named, &two).unwrap();
    assert!(open(&named, None).unwrap().all(|r| r.is_ok()));
    assert_eq!(open(&named, None).unwrap().count(), 6);
    std::fs::write(&named, [two, b"JUNK".to_vec()].concat()).unwrap();
    let items: Vec<_> = open(&named, None).unwrap().collect();
    assert_eq!(items.len(), 7);
    assert!(items[..6].iter().all(Result::is_ok));
    let e = items[6].as_ref().unwrap_err();
    assert!(!e.is_bad_record(), "{e}");
    assert!(
        e.to_string()
            .contains(laserlines_io::gzip::TRAILING_GARBAGE),
        "{e}"
    );
    // A last line without its line end, then garbage: the line is read, then the error.
    let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    enc.write_all(text.trim_ascii_end()).unwrap();
    let unended = [enc.finish().unwrap(), b"JUNK".to_vec()].concat();
    std::fs::write(&named, unended).unwrap();
    let items: Vec<_> = open(&named, None).unwrap().collect();
    assert_eq!(items.len(), 4, "{items:?}");
    assert!(items[..3].iter().all(Result::is_ok), "{items:?}");
    let e = items[3].as_ref().unwrap_err();
    assert!(
        e.to_string()
            .contains(laserlines_io::gzip::TRAILING_GARBAGE),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn readers_and_errors_can_cross_threads() {
    fn send<T: Send>() {}
    fn send_sync<T: Send + Sync + 'static>() {}
    send::<laserlines_io::ScanReader>();
    send::<laserlines_io::LinesReader>();
    send::<ScanRecord>();
    send_sync::<laserlines_io::ReadError>();
    send_sync::<laserlines_io::WriteError>();
}

#[test]
fn csv_geometry_stamp_pose_and_intensity_from_comments() {
    let records = read_all("tests/fixtures/one_beam_with_geometry.csv");
    let r = &records[0];
    assert_eq!(r.line, Some(10));
    assert_eq!((r.scan.angle_min, r.scan.angle_increment), (0.75, -0.125));
    assert_eq!((r.scan.range_min, r.scan.range_max), (0.02, 5.6));
    assert_eq!(r.scan.ranges, vec![4.5]);
    assert_eq!(r.scan.intensities, Some(vec![1200.0]));
    assert_eq!(r.scan.stamp, Some(212.387282));
    assert_eq!(r.pose, Some(Pose2::new(1.5, -0.25, 3.0)));
}
