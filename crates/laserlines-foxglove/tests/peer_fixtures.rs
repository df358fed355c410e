//! MCAP files, ROS 2 bags in sqlite3 storage and a ROS 1 bag written by other tools (rosbags'
//! rosbag1 and rosbag2 writers, rosbags' ROS 1 serializer with the Python mcap writer,
//! mcap-protobuf-support, the Python mcap writer with JSON messages from `json.dumps`), read
//! by our reader and compared value by value with what the script that wrote them put in
//! (`expected.json`). The files and the
//! values come from `scripts/peer_check.py fixtures crates/laserlines-foxglove/tests/fixtures`.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::path::{Path, PathBuf};

use laserlines_foxglove::McapReadOptions;
use laserlines_foxglove::read;
use laserlines_io::ReadOptions;
use serde_json::Value;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
}

/// A number of expected.json: a float, or "nan" / "inf" / "-inf".
fn num(v: &Value) -> f64 {
    match v {
        Value::String(s) if s == "nan" => f64::NAN,
        Value::String(s) if s == "inf" => f64::INFINITY,
        Value::String(s) if s == "-inf" => f64::NEG_INFINITY,
        other => other.as_f64().unwrap(),
    }
}

fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

fn check_file(name: &str, topics: &serde_json::Map<String, Value>) -> usize {
    let mut compared = 0;
    for (topic, records) in topics {
        let path = fixtures().join(name);
        let options = ReadOptions::format(None).with_topic(Some(topic));
        let reader = laserlines_foxglove::open_scans(&path, &options).unwrap();
        let got: Vec<_> = reader.collect::<Result<_, _>>().unwrap();
        let want = records.as_array().unwrap();
        assert_eq!(got.len(), want.len(), "{name} {topic}");
        for (k, (g, w)) in got.iter().zip(want).enumerate() {
            let at = format!("{name} {topic} scan {k}");
            let s = &g.scan;
            let stamp =
                w["stamp_sec"].as_f64().unwrap() + w["stamp_nanosec"].as_f64().unwrap() * 1e-9;
            assert_eq!(s.stamp, Some(stamp), "{at} stamp");
            for (field, value) in [
                ("angle_min", s.angle_min),
                ("angle_increment", s.angle_increment),
                ("range_min", s.range_min),
                ("range_max", s.range_max),
            ] {
                assert!(
                    same(value, num(&w[field])),
                    "{at} {field}: {value} vs {}",
                    w[field]
                );
                compared += 1;
            }
            let ranges = w["ranges"].as_array().unwrap();
            assert_eq!(s.ranges.len(), ranges.len(), "{at} beams");
            for (i, (a, b)) in s.ranges.iter().zip(ranges).enumerate() {
                assert!(same(*a, num(b)), "{at} ranges[{i}]: {a} vs {b}");
                compared += 1;
            }
            match (&s.intensities, w["intensities"].as_array()) {
                (None, None) => {}
                (Some(got), Some(want)) => {
                    assert_eq!(got.len(), want.len(), "{at} intensities");
                    for (a, b) in got.iter().zip(want) {
                        assert!(same(*a, num(b)), "{at} intensities");
                        compared += 1;
                    }
                }
                (a, b) => panic!("{at} intensities: {a:?} vs {b:?}"),
            }
            for (key, got) in [("pose", g.pose), ("odometry", g.odometry)] {
                match w.get(key).and_then(Value::as_array) {
                    None => assert_eq!(got, None, "{at} {key}"),
                    Some(want) => {
                        let got = got.unwrap_or_else(|| panic!("{at}: no {key}"));
                        assert!(same(got.x, num(&want[0])), "{at} {key}.x");
                        assert!(same(got.y, num(&want[1])), "{at} {key}.y");
                        let dtheta = got.theta - num(&want[2]);
                        assert!(dtheta.abs() < 1e-12, "{at} {key}.theta {}", got.theta);
                        compared += 3;
                    }
                }
            }
        }
    }
    compared
}

#[test]
fn files_written_by_rosbags_and_the_python_mcap_writers_read_value_for_value() {
    let text = std::fs::read_to_string(fixtures().join("expected.json")).unwrap();
    let expected: Value = serde_json::from_str(&text).unwrap();
    let files = expected.as_object().unwrap();
    assert_eq!(files.len(), 8);
    let mut compared = 0;
    for (name, topics) in files {
        compared += check_file(name, topics.as_object().unwrap());
    }
    assert!(compared > 100, "{compared}");
}

/// Echoes after each beam's first over the two scans of one topic of the multi-echo
/// fixtures (`multi_echo_scans` of `peer_check.py`): beams with 0, 1, 2, 0, 1, 2 echoes and
/// then 1, 2, 0, 1, 2, 0, 1 on the first topic, their intensities alike in the first scan only:
/// 2 + 2 in the first scan, 2 in the second.
const FIRST_TOPIC_ECHOES_LEFT_OUT: u64 = 6;

#[test]
fn multi_echo_scans_count_the_echoes_after_the_first_and_the_other_topic() {
    for name in [
        "ros1_multiecho.bag",
        "ros2_multiecho.mcap",
        "ros2_multiecho_sqlite3",
    ] {
        let path = fixtures().join(name);
        let mut reader =
            laserlines_foxglove::open_scans(&path, &ReadOptions::format(None)).unwrap();
        let scans: Vec<_> = reader.by_ref().collect::<Result<_, _>>().unwrap();
        // The default topic is the first: its scans have 6 and 7 beams.
        let beams: Vec<usize> = scans.iter().map(|r| r.scan.ranges.len()).collect();
        assert_eq!(beams, [6, 7], "{name}");
        let skipped = reader.skipped();
        assert_eq!(
            skipped.get(read::SKIP_LATER_ECHOES),
            FIRST_TOPIC_ECHOES_LEFT_OUT,
            "{name}"
        );
        assert_eq!(skipped.get(read::SKIP_OTHER_TOPIC), 2, "{name}");
    }
}

#[test]
fn the_default_topic_is_the_first_laserscan_topic_and_others_are_counted() {
    let path = fixtures().join("ros2_laserscan.mcap");
    let mut reader = read::open(&path, &McapReadOptions::default()).unwrap();
    let n = reader.by_ref().filter(|r| r.is_ok()).count();
    assert_eq!(n, 3);
    // /scan_rear's three scans; the std_msgs/String topic is not a scan and not counted.
    assert_eq!(reader.skipped().get(read::SKIP_OTHER_TOPIC), 3);
    assert_eq!(reader.skipped().total(), 3);
    let first = read::open(&path, &McapReadOptions::default())
        .unwrap()
        .next()
        .unwrap()
        .unwrap();
    assert_eq!(
        first.scan.ranges.len(),
        7,
        "the /scan series has 7, 10, 13 beams"
    );
}

#[test]
fn a_missing_topic_is_an_error_naming_the_topics_there() {
    let path = fixtures().join("ros2_laserscan.mcap");
    let reader = read::open(&path, &McapReadOptions::topic(Some("/nope"))).unwrap();
    let items: Vec<_> = reader.collect();
    assert_eq!(items.len(), 1);
    let e = items[0].as_ref().unwrap_err().to_string();
    assert!(e.contains("ros2_laserscan.mcap: byte "), "{e}");
    assert!(e.contains("a channel on topic /nope"), "{e}");
    assert!(e.contains("/scan_rear (sensor_msgs/msg/LaserScan)"), "{e}");
    assert!(e.contains("/note (std_msgs/msg/String)"), "{e}");
}

#[test]
fn a_topic_that_is_not_a_laserscan_is_an_error() {
    let path = fixtures().join("ros2_laserscan.mcap");
    let reader = read::open(&path, &McapReadOptions::topic(Some("/note"))).unwrap();
    let items: Vec<_> = reader.collect();
    let e = items[0].as_ref().unwrap_err().to_string();
    assert!(e.contains("topic /note"), "{e}");
    assert!(e.contains("std_msgs/msg/String messages"), "{e}");
}

#[test]
fn a_ros2_bag_directory_reads_its_mcap_files_in_name_order() {
    let dir = std::env::temp_dir().join(format!("laserlines-bag-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let src = fixtures().join("ros2_laserscan.mcap");
    std::fs::copy(&src, dir.join("bag_0.mcap")).unwrap();
    std::fs::copy(&src, dir.join("bag_1.mcap")).unwrap();
    std::fs::write(
        dir.join("metadata.yaml"),
        "rosbag2_bagfile_information: {}\n",
    )
    .unwrap();
    let mut reader = read::open(&dir, &McapReadOptions::default()).unwrap();
    let scans: Vec<_> = reader.by_ref().collect::<Result<_, _>>().unwrap();
    assert_eq!(scans.len(), 6);
    assert_eq!(scans[0].scan.ranges.len(), 7);
    assert_eq!(scans[3].scan.ranges.len(), 7);
    assert_eq!(reader.skipped().get(read::SKIP_OTHER_TOPIC), 6);
    std::fs::remove_file(dir.join("bag_0.mcap")).unwrap();
    std::fs::remove_file(dir.join("bag_1.mcap")).unwrap();
    let e = read::open(&dir, &McapReadOptions::default()).unwrap_err();
    assert!(e.to_string().contains("holds no .mcap or .db3 file"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
