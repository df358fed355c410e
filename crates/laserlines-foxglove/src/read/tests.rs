//! Unit tests of the MCAP reader on files laid out here.

use std::io::Cursor;

use super::*;
use crate::ros::{LaserScanMsg, encode};

fn msg(k: u32) -> LaserScanMsg {
    LaserScanMsg {
        stamp_sec: 100 + i64::from(k),
        stamp_nanosec: 5,
        frame_id: "laser".to_owned(),
        angle_min: -1.0,
        angle_max: 1.0,
        angle_increment: 0.5,
        range_min: 0.1,
        range_max: 10.0,
        ranges: vec![1.0, 2.0, 3.0, 4.0, 5.0],
        ..LaserScanMsg::default()
    }
}

/// An unchunked MCAP of ROS 2 scans; returns the bytes and each message record's offset.
fn ros2_file(payloads: &[Vec<u8>]) -> (Vec<u8>, Vec<u64>) {
    let options = mcap::WriteOptions::new().use_chunks(false);
    let mut w = options.create(Cursor::new(Vec::new())).unwrap();
    let s = w
        .add_schema("sensor_msgs/msg/LaserScan", "ros2msg", b"")
        .unwrap();
    let c = w
        .add_channel(s, "/scan", "cdr", &Default::default())
        .unwrap();
    for (i, p) in payloads.iter().enumerate() {
        let header = mcap::records::MessageHeader {
            channel_id: c,
            sequence: i as u32,
            log_time: 0,
            publish_time: 0,
        };
        w.write_to_known_channel(&header, p).unwrap();
    }
    w.finish().unwrap();
    let data = w.into_inner().into_inner();
    let mut offsets = Vec::new();
    let mut at = 8;
    while at + 9 <= data.len() - 8 {
        let len = u64::from_le_bytes(data[at + 1..at + 9].try_into().unwrap()) as usize;
        if data[at] == op::MESSAGE {
            offsets.push(at as u64);
        }
        at += 9 + len;
    }
    (data, offsets)
}

#[test]
fn a_corrupt_message_names_its_record_offset_and_field_and_reading_goes_on() {
    let good = encode::cdr(&msg(0), false);
    let mut bad = encode::cdr(&msg(1), false);
    // The ranges count sits after the header (4 + 8 + 4 + 6 bytes, padded to 24) and the
    // seven floats: byte 52 of the message.
    bad[52..56].copy_from_slice(&1000u32.to_le_bytes());
    let (data, offsets) = ros2_file(&[good.clone(), bad, good]);
    let reader = from_reader("x.mcap", Cursor::new(data), &McapReadOptions::default()).unwrap();
    let items: Vec<_> = reader.collect();
    assert_eq!(items.len(), 3);
    assert!(items[0].is_ok() && items[2].is_ok());
    let e = items[1].as_ref().unwrap_err().to_string();
    let want = format!(
        "x.mcap: byte {}: /scan message: ranges (byte 52 of the message): expected 1000 \
         float32 values (4000 bytes), found the message ends after",
        offsets[1]
    );
    assert!(e.starts_with(&want), "{e}\n{want}");
}

#[test]
fn zero_header_stamps_fall_back_to_the_log_time() {
    let mut m = msg(0);
    m.stamp_sec = 0;
    m.stamp_nanosec = 0;
    let options = mcap::WriteOptions::new().use_chunks(false);
    let mut w = options.create(Cursor::new(Vec::new())).unwrap();
    let s = w
        .add_schema("sensor_msgs/LaserScan", "ros1msg", b"")
        .unwrap();
    let c = w
        .add_channel(s, "/scan", "ros1", &Default::default())
        .unwrap();
    let header = mcap::records::MessageHeader {
        channel_id: c,
        sequence: 0,
        log_time: 42_500_000_000,
        publish_time: 0,
    };
    w.write_to_known_channel(&header, &encode::ros1(&m))
        .unwrap();
    w.finish().unwrap();
    let data = w.into_inner().into_inner();
    let mut reader = from_reader("y.mcap", Cursor::new(data), &McapReadOptions::default()).unwrap();
    let r = reader.next().unwrap().unwrap();
    assert_eq!(r.scan.stamp, Some(42.5));
    assert!(reader.next().is_none());
}

/// Chunk 1 defines `/a` (channel 1) and holds a scan of it; chunk 2 defines `/b` (channel 2)
/// before any later `/a` message. With chunk 1 damaged, the summary's `/a` comes before the
/// data's `/b`, so the topic read is `/a`, as in the whole file, and its later scans are read.
#[test]
fn a_lost_first_topic_is_chosen_before_one_a_later_chunk_defines() {
    let mut w = mcap::WriteOptions::new()
        .compression(None)
        .create(Cursor::new(Vec::new()))
        .unwrap();
    let s = w
        .add_schema("sensor_msgs/msg/LaserScan", "ros2msg", b"")
        .unwrap();
    let a = w.add_channel(s, "/a", "cdr", &Default::default()).unwrap();
    let mut k = 0u32;
    let mut write = |w: &mut mcap::Writer<Cursor<Vec<u8>>>, channel_id: u16| {
        let header = mcap::records::MessageHeader {
            channel_id,
            sequence: k,
            log_time: u64::from(k),
            publish_time: u64::from(k),
        };
        w.write_to_known_channel(&header, &encode::cdr(&msg(k), false))
            .unwrap();
        k += 1;
    };
    write(&mut w, a);
    w.flush().unwrap();
    let b = w.add_channel(s, "/b", "cdr", &Default::default()).unwrap();
    assert!(b > a);
    write(&mut w, b);
    write(&mut w, a);
    w.flush().unwrap();
    write(&mut w, a);
    w.finish().unwrap();
    let mut data = w.into_inner().into_inner();
    // Damage the first chunk's records (its CRC fails).
    let mut at = 8;
    while data[at] != op::CHUNK {
        at += 9 + u64::from_le_bytes(data[at + 1..at + 9].try_into().unwrap()) as usize;
    }
    let end = at + 9 + u64::from_le_bytes(data[at + 1..at + 9].try_into().unwrap()) as usize;
    for byte in &mut data[end - 12..end - 4] {
        *byte ^= 0x5a;
    }
    let dir = std::env::temp_dir().join(format!("laserlines-topics-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("topics.mcap");
    std::fs::write(&path, &data).unwrap();
    let mut reader = open(&path, &McapReadOptions::default()).unwrap();
    let items: Vec<_> = reader.by_ref().collect();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(items.iter().filter(|i| i.is_err()).count(), 1, "{items:?}");
    // The scans of /a after the damaged chunk: messages 2 and 3.
    let stamps: Vec<_> = items
        .iter()
        .filter_map(|i| i.as_ref().ok()?.scan.stamp)
        .collect();
    assert_eq!(stamps, [102.000_000_005, 103.000_000_005]);
    assert_eq!(reader.skipped().get(SKIP_OTHER_TOPIC), 1);
}
