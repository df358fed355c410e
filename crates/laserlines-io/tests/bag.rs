//! ROS 1 bags: fixtures written by the Python `rosbags` library (plain, bz2 and lz4 chunks)
//! compared with what `rosbags` reads back from them (`tests/fixtures/bags/expected.json`,
//! made by `make_bags.py`), bad input cut or corrupted from them, and the real CCNY
//! `demo.bag` whose index records declare wrong lengths (skipped, with a notice, when
//! `../shared/data/real` is absent).

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::io::{Cursor, Write};
use std::path::{Path, PathBuf};

use laserlines_io::bag::{MAGIC, SKIP_OTHER_TOPIC, SKIP_OTHER_TYPE, SKIP_UNKNOWN_CONNECTION};
use laserlines_io::{Format, ReadError, ReadOptions, ScanRecord, from_reader_with, open_with};
use serde_json::Value;

#[path = "../../../tests/shared_data.rs"]
mod shared_data;

#[cfg(unix)]
#[path = "../../../tests/named_pipe.rs"]
mod named_pipe;

const BAGS: &str = "tests/fixtures/bags";

fn expected() -> Value {
    let text = std::fs::read_to_string(Path::new(BAGS).join("expected.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// Every item of a bag, read from memory under the name `t.bag`; and the skip summary.
fn read_bytes(bytes: &[u8], topic: Option<&str>) -> (Vec<Result<ScanRecord, ReadError>>, String) {
    let mut reader =
        from_reader_with("t.bag", Cursor::new(bytes.to_vec()), Format::Bag, topic).unwrap();
    let items = reader.by_ref().collect();
    (items, reader.skipped().to_string())
}

fn fixture(name: &str) -> Vec<u8> {
    std::fs::read(Path::new(BAGS).join(name)).unwrap()
}

fn f32_bits(x: f64) -> u64 {
    u64::from((x as f32).to_bits())
}

/// The record matches what rosbags read for the same message.
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
    let ranges = want["ranges"].as_array().unwrap();
    assert_eq!(s.ranges.len(), ranges.len(), "{what}");
    for (got, bits) in s.ranges.iter().zip(ranges) {
        let want = f32::from_bits(bits.as_u64().unwrap() as u32);
        if want.is_nan() {
            assert!(got.is_nan(), "{what}");
        } else {
            assert_eq!(*got, f64::from(want), "{what}");
        }
    }
    let intensities = want["intensities"].as_array().unwrap();
    match &s.intensities {
        None => assert!(intensities.is_empty(), "{what}"),
        Some(got) => {
            let want: Vec<f64> = intensities
                .iter()
                .map(|b| f64::from(f32::from_bits(b.as_u64().unwrap() as u32)))
                .collect();
            assert_eq!(got, &want, "{what}");
        }
    }
    let (sec, nanosec) = (
        want["stamp_sec"].as_u64().unwrap(),
        want["stamp_nanosec"].as_u64().unwrap(),
    );
    let stamp = if (sec, nanosec) == (0, 0) {
        // A zero header stamp: the record time.
        let ns = want["time_ns"].as_u64().unwrap();
        (ns / 1_000_000_000) as f64 + (ns % 1_000_000_000) as f64 * 1e-9
    } else {
        sec as f64 + nanosec as f64 * 1e-9
    };
    assert_eq!(s.stamp, Some(stamp), "{what}");
    assert_eq!(record.pose, None);
}

#[test]
fn plain_bz2_and_lz4_bags_read_as_rosbags_reads_them() {
    let expected = expected();
    for name in ["laserscans.bag", "laserscans_bz2.bag", "laserscans_lz4.bag"] {
        let messages = expected[name].as_array().unwrap();
        for (topic, given) in [
            ("/scan", None),
            ("/scan", Some("/scan")),
            ("/scan_rear", Some("/scan_rear")),
            ("/scan_rear", Some("scan_rear")),
        ] {
            let path = Path::new(BAGS).join(name);
            let mut reader =
                open_with(&path, &ReadOptions::format(None).with_topic(given)).unwrap();
            assert_eq!(reader.format(), Format::Bag);
            let records: Vec<ScanRecord> = reader.by_ref().map(|r| r.unwrap()).collect();
            let want: Vec<&Value> = messages.iter().filter(|m| m["topic"] == topic).collect();
            assert_eq!(records.len(), want.len(), "{name} {topic}");
            assert_eq!(records.len(), if topic == "/scan" { 6 } else { 3 });
            for (i, (r, w)) in records.iter().zip(&want).enumerate() {
                assert_same(r, w, &format!("{name} {topic} message {i}"));
            }
            let other_scans = messages
                .iter()
                .filter(|m| m["type"] == "sensor_msgs/msg/LaserScan" && m["topic"] != topic)
                .count();
            let skipped = reader.skipped();
            assert_eq!(skipped.get(SKIP_OTHER_TYPE), 4, "{name}");
            assert_eq!(skipped.get(SKIP_OTHER_TOPIC), other_scans as u64, "{name}");
            assert_eq!(skipped.total(), 4 + other_scans as u64, "{name}: {skipped}");
        }
    }
}

#[test]
fn a_bag_without_laserscan_ends_with_an_error_naming_its_connections() {
    let bytes = fixture("no_laserscan.bag");
    let (items, skipped) = read_bytes(&bytes, None);
    assert_eq!(items.len(), 1);
    let e = items[0].as_ref().unwrap_err().to_string();
    assert_eq!(
        e,
        format!(
            "t.bag: byte {}: expected a sensor_msgs/LaserScan or sensor_msgs/MultiEchoLaserScan connection, found connections \
             /chatter (std_msgs/String)",
            bytes.len()
        )
    );
    assert_eq!(skipped, "4 × message of another type, 1 × malformed record");
    // A topic the bag does not have.
    let (items, _) = read_bytes(&fixture("laserscans.bag"), Some("/nope"));
    assert_eq!(items.len(), 1);
    let e = items[0].as_ref().unwrap_err().to_string();
    assert!(
        e.contains("expected a sensor_msgs/LaserScan or sensor_msgs/MultiEchoLaserScan connection on topic /nope, found connections"),
        "{e}"
    );
    // A topic that is not a LaserScan.
    let (items, _) = read_bytes(&fixture("laserscans.bag"), Some("/chatter"));
    assert_eq!(items.len(), 1);
    assert!(items[0].is_err());
}

/// Top-level records of a bag: (offset, op, header length, data offset, data length).
fn records(bytes: &[u8]) -> Vec<(usize, u8, usize, usize, usize)> {
    let u32_at = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    let mut out = Vec::new();
    let mut at = 13;
    while at < bytes.len() {
        let header_len = u32_at(at);
        let header = &bytes[at + 4..at + 4 + header_len];
        let op_at = header.windows(3).position(|w| w == b"op=").unwrap();
        let op = header[op_at + 3];
        let data_len = u32_at(at + 4 + header_len);
        let data = at + 8 + header_len;
        out.push((at, op, header_len, data, data_len));
        // Index data: 12 bytes per entry (these fixtures are consistent).
        at = data + data_len;
    }
    out
}

fn chunks(bytes: &[u8]) -> Vec<(usize, usize, usize)> {
    records(bytes)
        .into_iter()
        .filter(|r| r.1 == 0x05)
        .map(|(at, _, _, data, len)| (at, data, len))
        .collect()
}

fn scans_and_errors(items: &[Result<ScanRecord, ReadError>]) -> (usize, Vec<String>) {
    let scans = items.iter().filter(|i| i.is_ok()).count();
    let errors = items
        .iter()
        .filter_map(|i| i.as_ref().err().map(ToString::to_string))
        .collect();
    (scans, errors)
}

#[test]
fn a_truncated_chunk_ends_with_an_error_naming_its_offset_after_the_scans_before_it() {
    for name in ["laserscans.bag", "laserscans_bz2.bag", "laserscans_lz4.bag"] {
        let bytes = fixture(name);
        let chunks = chunks(&bytes);
        assert_eq!(chunks.len(), 4);
        let (third, data, len) = chunks[2];
        let cut = &bytes[..data + len / 2];
        let (items, _) = read_bytes(cut, None);
        let (scans, errors) = scans_and_errors(&items);
        // The first two chunks hold three /scan messages.
        assert_eq!(scans, 3, "{name}");
        assert_eq!(
            errors,
            vec![format!(
                "t.bag: byte {third}: expected chunk data ({len} bytes), found {} bytes \
                 before the end of the input (a truncated bag or a corrupt length field)",
                len / 2
            )],
            "{name}"
        );
        assert!(
            items.last().unwrap().is_err(),
            "{name}: the error comes last"
        );
        // Cut one byte before the end of the third chunk: an uncompressed chunk gives every
        // complete message before the cut (all but its last record); a compressed one none.
        let (whole, _) = read_bytes(&bytes[..data + len], None);
        let (through_third, errors) = scans_and_errors(&whole);
        assert!(
            errors.is_empty() && through_third > 3,
            "{name}: {through_third} {errors:?}"
        );
        let (items, _) = read_bytes(&bytes[..data + len - 1], None);
        let (scans, errors) = scans_and_errors(&items);
        let expected = if name == "laserscans.bag" {
            through_third - 1
        } else {
            3
        };
        assert_eq!(scans, expected, "{name}");
        assert_eq!(errors.len(), 1, "{name}: {errors:?}");
        assert!(
            errors[0].contains(&format!("byte {third}: expected chunk data")),
            "{errors:?}"
        );
        assert!(items.last().unwrap().is_err(), "{name}");
        // Cut inside a record header, and inside the magic.
        let (items, _) = read_bytes(&bytes[..third + 6], None);
        let (_, errors) = scans_and_errors(&items);
        assert_eq!(errors.len(), 1);
        assert!(
            errors[0].starts_with(&format!("t.bag: byte {third}: expected a record header")),
            "{}",
            errors[0]
        );
        let (items, _) = read_bytes(&bytes[..7], None);
        assert_eq!(
            items[0].as_ref().unwrap_err().to_string(),
            "t.bag: byte 0: expected `#ROSBAG V2.0` or `#ROSRECORD V1.2` (a ROS 1 bag), found \
             `#ROSBAG`"
        );
    }
}

#[test]
fn not_a_bag_is_an_error_at_byte_zero() {
    for (bytes, found) in [
        (&b""[..], "an empty input"),
        (b"hello, world\n", "`hello, world\\n`"),
        (
            b"#ROSBAG V1.2\nxx",
            "`#ROSBAG V1.2` (versions 2.0 and 1.2 are read)",
        ),
    ] {
        let (items, skipped) = read_bytes(bytes, None);
        assert_eq!(items.len(), 1);
        assert_eq!(
            items[0].as_ref().unwrap_err().to_string(),
            format!(
                "t.bag: byte 0: expected `#ROSBAG V2.0` or `#ROSRECORD V1.2` (a ROS 1 bag), \
                 found {found}"
            )
        );
        assert_eq!(skipped, "1 × malformed record");
    }
}

#[test]
fn a_corrupt_compressed_chunk_is_an_error_and_reading_goes_on() {
    // bz2 checks a CRC of its blocks: flipped bytes anywhere are found. The LZ4 frames ROS
    // writes carry no checksum, so flipped literal bytes decode to other numbers unseen;
    // a broken frame header or block length is found.
    for (name, flip) in [
        ("laserscans_bz2.bag", 1.0 / 3.0),
        ("laserscans_lz4.bag", 0.0),
    ] {
        let mut bytes = fixture(name);
        let chunks = chunks(&bytes);
        let (second, data, len) = chunks[1];
        let from = data + (len as f64 * flip) as usize;
        for b in &mut bytes[from..from + 40] {
            *b ^= 0x5a;
        }
        let (items, _) = read_bytes(&bytes, None);
        let (scans, errors) = scans_and_errors(&items);
        assert!(!errors.is_empty(), "{name}");
        for e in &errors {
            assert!(
                e.starts_with(&format!("t.bag: byte {second}")),
                "{name}: {e}"
            );
        }
        // The chunks after it are read: at least the last three /scan messages.
        assert!((3..6).contains(&scans), "{name}: {scans} scans, {errors:?}");
    }
}

/// A bag on disk whose first chunk (where the connections are first declared) is damaged:
/// the index section's connection records stand in for the lost ones, so the scans of the
/// later chunks are read. From a stream (no end to read first) they are on an undeclared
/// connection, as documented.
#[test]
fn a_corrupt_first_chunk_on_disk_loses_only_its_own_scans() {
    let dir = std::env::temp_dir().join(format!("laserlines-io-first-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut bytes = fixture("laserscans_bz2.bag");
    let (good, _) = read_bytes(&bytes, None);
    let good: Vec<_> = good.into_iter().map(Result::unwrap).collect();
    let (first, data, len) = chunks(&bytes)[0];
    // bz2 checks a CRC of its blocks: the chunk does not decompress.
    for b in &mut bytes[data + len / 3..data + len / 3 + 40] {
        *b ^= 0x5a;
    }
    let path = dir.join("first.bag");
    std::fs::write(&path, &bytes).unwrap();
    let mut reader = open_with(&path, &ReadOptions::default()).unwrap();
    let items: Vec<_> = reader.by_ref().collect();
    let (scans, errors) = scans_and_errors(&items);
    assert_eq!(errors.len(), 1, "{errors:?}");
    assert!(
        errors[0].contains(&format!("byte {first}")),
        "{}",
        errors[0]
    );
    // The first chunk held one of the six /scan messages; the other five are read as they
    // were, the topic is /scan as in the whole bag, and no message is left on an undeclared
    // connection.
    assert_eq!(good.len(), 6);
    assert_eq!(scans, 5, "{:?}", reader.skipped());
    let read: Vec<_> = items.into_iter().filter_map(Result::ok).collect();
    // (Compared as text: the scans hold NaN ranges.)
    assert_eq!(format!("{read:?}"), format!("{:?}", &good[1..]));
    assert_eq!(reader.skipped().get(SKIP_UNKNOWN_CONNECTION), 0);
    let (streamed, _) = read_bytes(&bytes, None);
    let (streamed, _) = scans_and_errors(&streamed);
    assert_eq!(streamed, 0);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A `len: u32, name=value` field of a bag record header.
fn field(name: &str, value: &[u8]) -> Vec<u8> {
    let mut out = ((name.len() + 1 + value.len()) as u32)
        .to_le_bytes()
        .to_vec();
    out.extend_from_slice(name.as_bytes());
    out.push(b'=');
    out.extend_from_slice(value);
    out
}

/// A bag record: its header of `fields` and its `data`.
fn bag_record(fields: &[Vec<u8>], data: &[u8]) -> Vec<u8> {
    let header = fields.concat();
    let mut out = (header.len() as u32).to_le_bytes().to_vec();
    out.extend_from_slice(&header);
    out.extend_from_slice(&(data.len() as u32).to_le_bytes());
    out.extend_from_slice(data);
    out
}

/// A connection record of LaserScans on `topic`.
fn connection_record(conn: u32, topic: &str) -> Vec<u8> {
    let data = [
        field("topic", topic.as_bytes()),
        field("type", b"sensor_msgs/LaserScan"),
        field("md5sum", b"90c7ef2dc6895d81024acba2ac42f369"),
    ]
    .concat();
    let header = [
        field("op", &[0x07]),
        field("conn", &conn.to_le_bytes()),
        field("topic", topic.as_bytes()),
    ];
    bag_record(&header, &data)
}

/// A message record of a LaserScan of three beams stamped `secs` on connection `conn`.
fn scan_record(conn: u32, secs: u32) -> Vec<u8> {
    let mut data = Vec::new();
    for v in [0u32, secs, 0, 5] {
        // seq, stamp, and the length of frame_id "laser"
        data.extend_from_slice(&v.to_le_bytes());
    }
    data.extend_from_slice(b"laser");
    for v in [-0.5f32, 0.5, 0.5, 0.0, 0.1, 0.02, 5.6] {
        data.extend_from_slice(&v.to_le_bytes());
    }
    data.extend_from_slice(&3u32.to_le_bytes());
    for v in [1.0f32, 2.0, 3.0] {
        data.extend_from_slice(&v.to_le_bytes());
    }
    data.extend_from_slice(&0u32.to_le_bytes());
    let mut time = secs.to_le_bytes().to_vec();
    time.extend_from_slice(&0u32.to_le_bytes());
    let header = [
        field("op", &[0x02]),
        field("conn", &conn.to_le_bytes()),
        field("time", &time),
    ];
    bag_record(&header, &data)
}

/// An uncompressed chunk record of `records`.
fn chunk_record(records: &[Vec<u8>]) -> Vec<u8> {
    let inner = records.concat();
    let header = [
        field("op", &[0x05]),
        field("compression", b"none"),
        field("size", &(inner.len() as u32).to_le_bytes()),
    ];
    bag_record(&header, &inner)
}

/// Chunk 1 declares `/a` (connection 0) and holds a scan of it; chunk 2 declares `/b`
/// (connection 1) before any later `/a` message. With chunk 1 damaged, the index section's
/// `/a` comes before the chunk's `/b`, so the topic read is `/a`, as in the whole bag, and
/// its later scans are read.
#[test]
fn a_lost_first_topic_is_chosen_before_one_a_later_chunk_declares() {
    let chunks = [
        chunk_record(&[connection_record(0, "/a"), scan_record(0, 10)]),
        chunk_record(&[
            connection_record(1, "/b"),
            scan_record(1, 11),
            scan_record(0, 12),
        ]),
        chunk_record(&[scan_record(0, 13)]),
    ];
    let index = [connection_record(0, "/a"), connection_record(1, "/b")].concat();
    let bag_header = |index_pos: u64| {
        let header = [
            field("op", &[0x03]),
            field("index_pos", &index_pos.to_le_bytes()),
            field("conn_count", &2u32.to_le_bytes()),
            field("chunk_count", &3u32.to_le_bytes()),
        ];
        bag_record(&header, &[b' '; 64])
    };
    let head = MAGIC.len() + bag_header(0).len();
    let index_pos = (head + chunks.iter().map(Vec::len).sum::<usize>()) as u64;
    let mut bytes = [
        MAGIC.to_vec(),
        bag_header(index_pos),
        chunks.concat(),
        index,
    ]
    .concat();
    let read = |bytes: &[u8]| {
        let dir = std::env::temp_dir().join(format!("laserlines-io-topics-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("topics.bag");
        std::fs::write(&path, bytes).unwrap();
        let mut reader = open_with(&path, &ReadOptions::default()).unwrap();
        let items: Vec<_> = reader.by_ref().collect();
        std::fs::remove_dir_all(&dir).unwrap();
        let stamps: Vec<_> = items
            .iter()
            .filter_map(|i| i.as_ref().ok()?.scan.stamp)
            .collect();
        let errors = items.iter().filter(|i| i.is_err()).count();
        (stamps, errors, reader.skipped().get(SKIP_OTHER_TOPIC))
    };
    assert_eq!(read(&bytes), (vec![10.0, 12.0, 13.0], 0, 1));
    // The first record of chunk 1 claims a header of 2^31 bytes: the chunk's rest is lost.
    let data = head + 4 + u32::from_le_bytes(chunks[0][..4].try_into().unwrap()) as usize + 4;
    bytes[data..data + 4].copy_from_slice(&(1u32 << 31).to_le_bytes());
    assert_eq!(read(&bytes), (vec![12.0, 13.0], 1, 1));
}

/// A bag read through a named pipe: the index section is not read first (that would take the
/// reader's bytes), and every scan comes out as from the file.
#[cfg(unix)]
#[test]
fn a_bag_through_a_named_pipe_reads_whole() {
    let bytes = fixture("laserscans.bag");
    let (good, _) = read_bytes(&bytes, None);
    let read =
        |fifo: &Path| -> Vec<_> { open_with(fifo, &ReadOptions::default()).unwrap().collect() };
    let Some(items) = named_pipe::through_named_pipe("scans.bag", bytes, read) else {
        return;
    };
    assert_eq!(format!("{items:?}"), format!("{good:?}"));
}

/// Damage to the index section (after the last chunk: what the reader of a bag on disk
/// reads first) never panics and never changes a scan: every chunk is whole.
#[test]
fn random_damage_to_the_index_section_of_a_bag_on_disk_changes_no_scan() {
    let dir = std::env::temp_dir().join(format!("laserlines-io-index-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("index.bag");
    let bytes = fixture("laserscans_bz2.bag");
    let (good, _) = read_bytes(&bytes, None);
    let good = format!("{good:?}");
    // The index section: from the first connection record after the last chunk.
    let (last_chunk, _, _) = *chunks(&bytes).last().unwrap();
    let from = records(&bytes)
        .into_iter()
        .find(|r| r.0 > last_chunk && r.1 == 0x07)
        .unwrap()
        .0;
    let mut state = 13u64;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 33) as usize
    };
    for _ in 0..300 {
        let mut bad = bytes.clone();
        for _ in 0..1 + next() % 4 {
            let i = from + next() % (bad.len() - from);
            bad[i] = next() as u8;
        }
        std::fs::write(&path, &bad).unwrap();
        let items: Vec<_> = open_with(&path, &ReadOptions::default()).unwrap().collect();
        for e in items.iter().filter_map(|i| i.as_ref().err()) {
            assert!(e.pos().is_some(), "{e}");
        }
        let scans: Vec<_> = items.into_iter().filter(Result::is_ok).collect();
        assert_eq!(format!("{scans:?}"), good);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_corrupt_record_length_in_a_chunk_drops_the_rest_of_that_chunk_only() {
    let mut bytes = fixture("laserscans.bag");
    let chunks = chunks(&bytes);
    let (_, data, _) = chunks[1];
    // The first record of the second chunk claims a header of 2^31 bytes.
    bytes[data..data + 4].copy_from_slice(&0x8000_0000u32.to_le_bytes());
    let (items, skipped) = read_bytes(&bytes, None);
    let (scans, errors) = scans_and_errors(&items);
    assert_eq!(errors.len(), 1);
    assert!(
        errors[0].starts_with(&format!(
            "t.bag: byte {data}: expected a record header of 2147483648 bytes, found"
        )),
        "{}",
        errors[0]
    );
    assert!((3..6).contains(&scans), "{scans}");
    assert!(skipped.contains("1 × malformed record"), "{skipped}");
}

#[test]
fn a_corrupt_top_level_header_length_ends_the_reader() {
    let mut bytes = fixture("laserscans.bag");
    let (second, _, _) = chunks(&bytes)[1];
    bytes[second..second + 4].copy_from_slice(&u32::MAX.to_le_bytes());
    let (items, _) = read_bytes(&bytes, None);
    let (scans, errors) = scans_and_errors(&items);
    assert_eq!(scans, 1);
    assert_eq!(
        errors,
        vec![format!(
            "t.bag: byte {second}: read failed: expected a record header of at most 16777216 \
             bytes, found a header length of 4294967295 bytes (a corrupt record); the records \
             after it cannot be found, so the rest of the input is not read"
        )]
    );
    // The chunks after it are never found: a failed read, which no skip passes over.
    let e = items.iter().find_map(|r| r.as_ref().err()).unwrap();
    assert!(!e.is_bad_record());
}

#[test]
fn a_data_length_past_the_end_names_a_corrupt_length_field_as_a_cause() {
    let mut bytes = fixture("laserscans.bag");
    let (second, data, len) = chunks(&bytes)[1];
    // The second chunk claims 100 kB more data than the whole bag holds after it.
    let claimed = (bytes.len() - data + 100_000) as u32;
    bytes[data - 4..data].copy_from_slice(&claimed.to_le_bytes());
    let (items, _) = read_bytes(&bytes, None);
    let (_, errors) = scans_and_errors(&items);
    let rest = bytes.len() - data;
    assert!(rest > len, "{rest} {len}");
    assert_eq!(
        errors,
        vec![format!(
            "t.bag: byte {second}: expected chunk data ({claimed} bytes), found {rest} bytes \
             before the end of the input (a truncated bag or a corrupt length field)"
        )]
    );
}

#[test]
fn a_message_that_does_not_decode_is_an_error_and_the_next_one_is_read() {
    let mut bytes = fixture("laserscans.bag");
    // The first /scan message: frame_id "laser", then angle_min = -1.0 (f32).
    let mut pattern = b"\x05\x00\x00\x00laser".to_vec();
    pattern.extend_from_slice(&(-1.0f32).to_le_bytes());
    let at = bytes
        .windows(pattern.len())
        .position(|w| w == pattern)
        .unwrap();
    // After frame_id: 7 float32 fields, then the ranges count.
    let count_at = at + 9 + 7 * 4;
    assert_eq!(&bytes[count_at..count_at + 4], &101u32.to_le_bytes());
    bytes[count_at..count_at + 4].copy_from_slice(&1000u32.to_le_bytes());
    let (items, _) = read_bytes(&bytes, None);
    let (scans, errors) = scans_and_errors(&items);
    assert_eq!(scans, 5);
    assert_eq!(errors.len(), 1);
    assert!(items[0].is_err());
    let e = &errors[0];
    // The count sits at message byte 12 + 4 + 5 + 7 * 4 = 49 (seq, stamp, frame_id, floats).
    assert!(
        e.contains("/scan message: expected ranges at message byte 49: 1000 float32 values (4000 bytes), found the message ends after"),
        "{e}"
    );
    // The offset is the message's, in the file (an uncompressed chunk).
    let message_start = at - 12;
    assert!(
        e.starts_with(&format!("t.bag: byte {message_start}:")),
        "{e}"
    );
}

// ---- the real demo.bag ----

fn demo_bag() -> Option<PathBuf> {
    shared_data::available(
        shared_data::path("real/ccny-scan-tools-urg-bag/demo.bag"),
        "the demo.bag test",
    )
}

fn check_demo(records: &[ScanRecord]) {
    assert_eq!(records.len(), 360);
    let (mut zeros, mut below_min, mut total) = (0, 0, 0);
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for r in records {
        let s = &r.scan;
        assert_eq!(s.len(), 681);
        assert!((s.angle_min - -2.0862138).abs() < 1e-7);
        assert!((s.angle_increment - 0.0061359233).abs() < 1e-9);
        assert!((s.angle_max() - 2.0862138).abs() < 1e-6);
        assert!((s.range_min - 0.02).abs() < 1e-7 && (s.range_max - 5.6).abs() < 1e-6);
        assert_eq!(s.intensities, None);
        assert_eq!(r.pose, None);
        let w = s.range_window(None);
        for &x in &s.ranges {
            total += 1;
            if x == 0.0 {
                zeros += 1;
            } else if x < s.range_min {
                below_min += 1;
            } else {
                assert!(w.contains(x));
                lo = lo.min(x);
                hi = hi.max(x);
            }
        }
    }
    // PROVENANCE.md: 245,160 values, 12,699 zeros, 643 more below range_min, the rest
    // 0.286 .. 5.468 m.
    assert_eq!((total, zeros, below_min), (245_160, 12_699, 643));
    assert!(
        (lo - 0.286).abs() < 5e-4 && (hi - 5.468).abs() < 5e-4,
        "{lo} {hi}"
    );
    let stamps: Vec<f64> = records.iter().map(|r| r.scan.stamp.unwrap()).collect();
    assert!((stamps[0] - 1282836370.97).abs() < 0.01);
    assert!((stamps[359] - 1282836406.79).abs() < 0.01);
    for w in stamps.windows(2) {
        let dt = w[1] - w[0];
        assert!((0.094..0.105).contains(&dt), "dt {dt}");
    }
}

#[test]
fn demo_bag_gives_all_360_scans_despite_its_wrong_index_lengths() {
    let Some(path) = demo_bag() else { return };
    let mut reader = open_with(&path, &ReadOptions::default()).unwrap();
    let records: Vec<ScanRecord> = reader.by_ref().map(|r| r.unwrap()).collect();
    assert!(reader.skipped().is_empty(), "{}", reader.skipped());
    check_demo(&records);
    // The same from a gzip stream (no seeking), with the topic named.
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    gz.write_all(&std::fs::read(&path).unwrap()).unwrap();
    let (items, skipped) = read_bytes(&gz.finish().unwrap(), Some("/scan"));
    let records: Vec<ScanRecord> = items.into_iter().map(|r| r.unwrap()).collect();
    assert_eq!(skipped, "none");
    check_demo(&records);
}

#[test]
fn chunks_over_the_limit_are_errors_and_skipped() {
    use laserlines_io::bag::{BagOptions, from_reader};
    let bytes = fixture("laserscans_bz2.bag");
    let options = BagOptions {
        max_chunk_bytes: 1000,
        ..BagOptions::default()
    };
    let reader = from_reader("t.bag", Cursor::new(bytes.clone()), &options).unwrap();
    let items: Vec<_> = reader.collect();
    let (scans, errors) = scans_and_errors(&items);
    assert_eq!(scans, 0);
    // Four chunks over the limit (1103 .. 2133 bytes decompressed); the connection records
    // of the index section still name the LaserScan topic, so no error at the end.
    assert_eq!(errors.len(), 4, "{errors:?}");
    for (e, (at, _, _)) in errors.iter().zip(chunks(&bytes)) {
        assert!(
            e.starts_with(&format!(
                "t.bag: byte {at}: expected a chunk of at most 1000 bytes"
            )),
            "{e}"
        );
    }
}
