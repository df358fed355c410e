//! ROS bags of format version 1.2 (`#ROSRECORD V1.2`): a bag written from the format
//! description by `tests/fixtures/bags/make_v12_bag.py`, compared with what ROS's own
//! `rosbag` library reads back from it (`expected_v12.json`); the same bag without its index,
//! cut short, and with a bad record.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::io::Cursor;
use std::path::Path;

use laserlines_io::bag::{SKIP_OTHER_TOPIC, SKIP_OTHER_TYPE};
use laserlines_io::{Format, ReadError, ReadOptions, ScanRecord, from_reader_with, open_with};
use serde_json::Value;

const BAGS: &str = "tests/fixtures/bags";
const BAG: &str = "laserscans_v12.bag";

fn expected() -> Vec<Value> {
    let text = std::fs::read_to_string(Path::new(BAGS).join("expected_v12.json")).unwrap();
    let all: Value = serde_json::from_str(&text).unwrap();
    all[BAG].as_array().unwrap().clone()
}

fn bytes() -> Vec<u8> {
    std::fs::read(Path::new(BAGS).join(BAG)).unwrap()
}

fn read_bytes(bytes: &[u8], topic: Option<&str>) -> Vec<Result<ScanRecord, ReadError>> {
    from_reader_with("t.bag", Cursor::new(bytes.to_vec()), Format::Bag, topic)
        .unwrap()
        .collect()
}

fn f32_bits(x: f64) -> u64 {
    u64::from((x as f32).to_bits())
}

/// The record matches what `rosbag` read for the same message.
fn assert_same(record: &ScanRecord, want: &Value, what: &str) {
    let s = &record.scan;
    assert_eq!(f32_bits(s.angle_min), want["angle_min"], "{what}");
    assert_eq!(
        f32_bits(s.angle_increment),
        want["angle_increment"],
        "{what}"
    );
    assert_eq!(f32_bits(s.range_min), want["range_min"], "{what}");
    assert_eq!(f32_bits(s.range_max), want["range_max"], "{what}");
    let ranges: Vec<u64> = want["ranges"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_u64().unwrap())
        .collect();
    let got: Vec<u64> = s.ranges.iter().map(|r| f32_bits(*r)).collect();
    assert_eq!(got, ranges, "{what}: ranges, bit for bit");
    let intensities = want["intensities"].as_array().unwrap();
    match &s.intensities {
        None => assert!(intensities.is_empty(), "{what}"),
        Some(got) => {
            let got: Vec<u64> = got.iter().map(|r| f32_bits(*r)).collect();
            let want: Vec<u64> = intensities.iter().map(|v| v.as_u64().unwrap()).collect();
            assert_eq!(got, want, "{what}");
        }
    }
    let (sec, nanosec) = (
        want["stamp_sec"].as_u64().unwrap(),
        want["stamp_nanosec"].as_u64().unwrap(),
    );
    let stamp = if (sec, nanosec) == (0, 0) {
        let ns = want["time_ns"].as_u64().unwrap();
        (ns / 1_000_000_000) as f64 + (ns % 1_000_000_000) as f64 * 1e-9
    } else {
        sec as f64 + nanosec as f64 * 1e-9
    };
    assert_eq!(s.stamp, Some(stamp), "{what}");
    assert_eq!(record.pose, None);
}

#[test]
fn a_version_1_2_bag_reads_as_ros_rosbag_reads_it() {
    let messages = expected();
    assert_eq!(messages.len(), 13);
    for (topic, given) in [
        ("/base_scan", None),
        ("/base_scan", Some("base_scan")),
        ("/tilt_scan", Some("/tilt_scan")),
    ] {
        let path = Path::new(BAGS).join(BAG);
        let mut reader = open_with(&path, &ReadOptions::format(None).with_topic(given)).unwrap();
        let records: Vec<ScanRecord> = reader.by_ref().map(|r| r.unwrap()).collect();
        let want: Vec<&Value> = messages.iter().filter(|m| m["topic"] == topic).collect();
        assert_eq!(records.len(), want.len(), "{topic}");
        assert_eq!(records.len(), if topic == "/base_scan" { 6 } else { 3 });
        for (i, (r, w)) in records.iter().zip(&want).enumerate() {
            assert_same(r, w, &format!("{topic} message {i}"));
        }
        let skipped = reader.skipped();
        assert_eq!(skipped.get(SKIP_OTHER_TYPE), 4, "the four /chatter strings");
        assert_eq!(skipped.get(SKIP_OTHER_TOPIC), 9 - want.len() as u64);
        assert_eq!(skipped.total(), 4 + 9 - want.len() as u64, "{skipped}");
    }
}

/// Top-level records of a 1.2 bag: (offset, op, data offset, data length).
fn records(bytes: &[u8]) -> Vec<(usize, u8, usize, usize)> {
    let u32_at = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    let mut out = Vec::new();
    let mut at = 16;
    while at < bytes.len() {
        let header_len = u32_at(at);
        let header = &bytes[at + 4..at + 4 + header_len];
        let op_at = header.windows(3).position(|w| w == b"op=").unwrap();
        let data_len = u32_at(at + 4 + header_len);
        let data = at + 8 + header_len;
        out.push((at, header[op_at + 3], data, data_len));
        at = data + data_len;
    }
    out
}

#[test]
fn the_fixture_has_every_record_kind_of_the_format() {
    let ops: Vec<u8> = records(&bytes()).iter().map(|r| r.1).collect();
    assert!(bytes().starts_with(b"#ROSRECORD V1.2\n"));
    assert_eq!(ops[0], 0x03, "file header first");
    assert_eq!(
        ops.iter().filter(|o| **o == 0x01).count(),
        3,
        "a definition per topic"
    );
    assert_eq!(ops.iter().filter(|o| **o == 0x02).count(), 13);
    assert_eq!(
        ops.iter().filter(|o| **o == 0x04).count(),
        3,
        "an index per topic"
    );
}

#[test]
fn without_its_index_a_recording_cut_short_still_gives_its_scans() {
    let bytes = bytes();
    let recs = records(&bytes);
    let first_index = recs.iter().find(|r| r.1 == 0x04).unwrap().0;
    let items = read_bytes(&bytes[..first_index], None);
    assert_eq!(items.len(), 6);
    assert!(items.iter().all(Result::is_ok));
    // Cut inside the third /base_scan message: two scans, then an error at its offset.
    let third = recs
        .iter()
        .filter(|r| r.1 == 0x02)
        .nth(6) // chatter, base, tilt, chatter, base, chatter, base
        .unwrap();
    let items = read_bytes(&bytes[..third.2 + 10], None);
    assert_eq!(items.iter().filter(|i| i.is_ok()).count(), 2);
    let e = items.last().unwrap().as_ref().unwrap_err().to_string();
    assert_eq!(
        e,
        format!(
            "t.bag: byte {}: expected message data ({} bytes), found 10 bytes before the end \
             of the input (a truncated bag or a corrupt length field)",
            third.0, third.3
        )
    );
}

#[test]
fn a_message_that_does_not_decode_is_an_error_and_reading_goes_on() {
    let mut bytes = bytes();
    let recs = records(&bytes);
    // The first /base_scan message: its ranges length made huge.
    let first = recs.iter().filter(|r| r.1 == 0x02).nth(1).unwrap();
    let frame_len = u32::from_le_bytes(bytes[first.2 + 12..first.2 + 16].try_into().unwrap());
    let ranges_at = first.2 + 16 + frame_len as usize + 28;
    bytes[ranges_at..ranges_at + 4].copy_from_slice(&u32::MAX.to_le_bytes());
    let items = read_bytes(&bytes, None);
    assert_eq!(items.len(), 6);
    let e = items[0].as_ref().unwrap_err().to_string();
    assert!(
        e.starts_with(&format!("t.bag: byte {}: /base_scan message: ", first.2)),
        "{e}"
    );
    assert!(items[1..].iter().all(Result::is_ok));
}

#[test]
fn other_versions_are_named_in_the_error() {
    for (head, version) in [
        (&b"#ROSRECORD V1.1\n/scan\n"[..], "#ROSRECORD V1.1"),
        (&b"#ROSBAG V1.3\n"[..], "#ROSBAG V1.3"),
    ] {
        let items = read_bytes(head, None);
        assert_eq!(items.len(), 1);
        let e = items[0].as_ref().unwrap_err().to_string();
        assert_eq!(
            e,
            format!(
                "t.bag: byte 0: expected `#ROSBAG V2.0` or `#ROSRECORD V1.2` (a ROS 1 bag), \
                 found `{version}` (versions 2.0 and 1.2 are read)"
            )
        );
    }
}
