//! Bad MCAP input never panics: a truncated file or a corrupt record gives an error naming
//! the file and the byte offset, and where the rest of the file is good, reading goes on.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::io::Cursor;

use laserlines::Scan;
use laserlines_foxglove::{McapReadOptions, McapSceneWriter, read};
use laserlines_io::{At, ReadError, ScanRecord};

#[cfg(unix)]
#[path = "../../../tests/named_pipe.rs"]
mod named_pipe;

fn records(n: usize) -> Vec<ScanRecord> {
    (0..n)
        .map(|k| {
            let ranges = (0..50).map(|i| 1.0 + 0.01 * (i + k) as f64).collect();
            let mut r = ScanRecord::new(Scan::new(-1.0, 0.04, 0.1, 10.0, ranges).unwrap());
            r.scan.stamp = Some(10.0 + k as f64);
            r
        })
        .collect()
}

/// An MCAP of `n` scans, with the given compression, one chunk per scan or so.
fn mcap_bytes(n: usize, compression: Option<mcap::Compression>) -> Vec<u8> {
    let options = mcap::WriteOptions::new()
        .compression(compression)
        .chunk_size(Some(300));
    let mut w = McapSceneWriter::with_options(Cursor::new(Vec::new()), "t", options).unwrap();
    for r in records(n) {
        w.write_scan(&r).unwrap();
    }
    w.finish().unwrap().into_inner()
}

fn read_all(name: &str, data: Vec<u8>) -> Vec<Result<ScanRecord, ReadError>> {
    read::from_reader(name, Cursor::new(data), &McapReadOptions::default())
        .unwrap()
        .collect()
}

fn byte_of(e: &ReadError) -> u64 {
    match e.pos().map(|p| p.at) {
        Some(At::Byte(b)) => b,
        other => panic!("{e}: no byte offset ({other:?})"),
    }
}

/// The top-level records up to the footer: (opcode, offset, end).
fn top_records(data: &[u8]) -> Vec<(u8, usize, usize)> {
    let mut out = Vec::new();
    let mut at = 8;
    while at + 9 <= data.len() - 8 {
        let len = u64::from_le_bytes(data[at + 1..at + 9].try_into().unwrap()) as usize;
        out.push((data[at], at, at + 9 + len));
        at += 9 + len;
    }
    out
}

#[test]
fn a_good_file_reads_back_every_scan() {
    for c in [
        None,
        Some(mcap::Compression::Zstd),
        Some(mcap::Compression::Lz4),
    ] {
        let mut reader = read::from_reader(
            "good.mcap",
            Cursor::new(mcap_bytes(6, c)),
            &McapReadOptions::default(),
        )
        .unwrap();
        let scans: Vec<_> = reader.by_ref().map(|r| r.unwrap()).collect();
        assert!(reader.skipped().is_empty(), "{}", reader.skipped());
        assert_eq!(scans.len(), 6, "{c:?}");
        for (g, w) in scans.iter().zip(records(6)) {
            assert_eq!(g.scan.ranges, w.scan.ranges);
            assert_eq!(g.scan.stamp, w.scan.stamp);
            assert_eq!((g.scan.range_min, g.scan.range_max), (0.1, 10.0));
        }
    }
}

#[test]
fn a_recording_cut_off_in_an_open_chunk_says_so() {
    // What a recorder stopped in the middle of a chunk leaves: the chunk's length still the
    // placeholder of all ones, and the file ending inside the chunk.
    let data = mcap_bytes(6, None);
    let chunks: Vec<_> = top_records(&data)
        .into_iter()
        .filter(|(op, _, _)| *op == mcap::records::op::CHUNK)
        .collect();
    let (_, at, end) = *chunks.last().unwrap();
    let mut cut = data[..(at + end) / 2].to_vec();
    cut[at + 1..at + 9].copy_from_slice(&u64::MAX.to_le_bytes());
    let items = read_all("cut.mcap", cut);
    let (good, bad): (Vec<_>, Vec<_>) = items.into_iter().partition(Result::is_ok);
    assert!(!good.is_empty() && good.len() < 6, "{} scans", good.len());
    let e = bad.last().unwrap().as_ref().unwrap_err();
    assert_eq!(byte_of(e), at as u64);
    let text = e.to_string();
    assert!(
        text.contains("whose length was never written")
            && text.contains("the recording was cut off while it was being written"),
        "{text}"
    );
}

#[test]
fn a_truncated_file_gives_its_scans_then_an_error_at_the_cut() {
    for c in [None, Some(mcap::Compression::Zstd)] {
        let data = mcap_bytes(6, c);
        let want = records(6);
        let (_, _, data_end) = top_records(&data)
            .into_iter()
            .find(|(op, _, _)| *op == mcap::records::op::DATA_END)
            .unwrap();
        for cut in 0..data.len() {
            let items = read_all("cut.mcap", data[..cut].to_vec());
            let (good, bad): (Vec<_>, Vec<_>) = items.into_iter().partition(Result::is_ok);
            // Whatever comes out is a prefix of the scans, in order.
            for (g, w) in good.iter().zip(&want) {
                assert_eq!(g.as_ref().unwrap().scan.ranges, w.scan.ranges, "cut {cut}");
            }
            assert!(good.len() <= want.len());
            if cut >= data_end {
                // Only the summary (indexes, which the reader does not use), the footer or
                // the magic is missing: every scan, and the cut counted.
                assert_eq!((good.len(), bad.len()), (want.len(), 0), "cut {cut}");
                let mut reader = read::from_reader(
                    "cut.mcap",
                    Cursor::new(data[..cut].to_vec()),
                    &McapReadOptions::default(),
                )
                .unwrap();
                assert_eq!(reader.by_ref().count(), want.len());
                assert_eq!(reader.skipped().get(read::SKIP_CUT_SUMMARY), 1, "cut {cut}");
                continue;
            }
            // Never silently short: a cut file always ends with an error naming it.
            let e = bad
                .last()
                .unwrap_or_else(|| panic!("cut at {cut}: no error"));
            let e = e.as_ref().unwrap_err();
            assert_eq!(e.file(), "cut.mcap");
            assert!(byte_of(e) <= cut as u64, "cut {cut}: {e}");
            let text = e.to_string();
            assert!(
                text.contains("truncated")
                    || text.contains("magic")
                    || text.contains("LaserScan channel"),
                "cut {cut}: {text}"
            );
        }
    }
}

/// The chunks among the top-level records: (offset, end).
fn chunks_of(data: &[u8]) -> Vec<(usize, usize)> {
    top_records(data)
        .into_iter()
        .filter(|(op, _, _)| *op == mcap::records::op::CHUNK)
        .map(|(_, at, end)| (at, end))
        .collect()
}

/// `data` with the last bytes of the records of the chunk ending at `end` damaged.
fn damaged(data: &[u8], end: usize) -> Vec<u8> {
    let mut bad = data.to_vec();
    for b in &mut bad[end - 12..end - 4] {
        *b ^= 0x5a;
    }
    bad
}

#[test]
fn a_corrupt_chunk_is_a_counted_error_and_the_next_chunks_still_read() {
    for c in [
        None,
        Some(mcap::Compression::Zstd),
        Some(mcap::Compression::Lz4),
    ] {
        let data = mcap_bytes(6, c);
        let chunks = chunks_of(&data);
        assert!(chunks.len() >= 3, "{c:?}: {} chunks", chunks.len());
        // Damage the last bytes of the second chunk's records.
        let (second, next) = chunks[1];
        let bad = damaged(&data, next);
        let mut reader =
            read::from_reader("bad.mcap", Cursor::new(bad), &McapReadOptions::default()).unwrap();
        let items: Vec<_> = reader.by_ref().collect();
        let errors: Vec<_> = items.iter().filter_map(|r| r.as_ref().err()).collect();
        assert_eq!(errors.len(), 1, "{c:?}: {errors:?}");
        let e = errors[0];
        assert_eq!(e.file(), "bad.mcap");
        let at = byte_of(e);
        assert!(
            at >= second as u64 && at < next as u64,
            "{c:?}: error at {at}, chunk at {second}..{next}: {e}"
        );
        let scans = items.iter().filter(|r| r.is_ok()).count();
        assert!((4..6).contains(&scans), "{c:?}: {scans} scans");
        // The scans the bad chunk held are counted from the file's statistics.
        let lost = reader.skipped().get(read::SKIP_LOST_SCAN);
        assert_eq!(lost, 6 - scans as u64, "{c:?}: {:?}", reader.skipped());
        assert_eq!(reader.skipped().total(), 1 + lost);
    }
}

/// A file of one chunk whose chunk is damaged lost its channels' definitions with it: the
/// summary's `Channel` records stand in for them, so the scans it held are counted from the
/// statistics, and no "topic not found" error is added to the chunk's own.
#[test]
fn a_corrupt_only_chunk_counts_its_scans_from_the_summary() {
    for c in [None, Some(mcap::Compression::Zstd)] {
        let options = mcap::WriteOptions::new()
            .compression(c)
            .chunk_size(Some(1 << 20));
        let mut w = McapSceneWriter::with_options(Cursor::new(Vec::new()), "t", options).unwrap();
        for r in records(5) {
            w.write_scan(&r).unwrap();
        }
        let data = w.finish().unwrap().into_inner();
        let chunks = chunks_of(&data);
        assert_eq!(chunks.len(), 1, "{c:?}");
        let (at, end) = chunks[0];
        let bad = damaged(&data, end);
        let mut reader =
            read::from_reader("one.mcap", Cursor::new(bad), &McapReadOptions::default()).unwrap();
        let items: Vec<_> = reader.by_ref().collect();
        let errors: Vec<_> = items.iter().filter_map(|r| r.as_ref().err()).collect();
        assert_eq!(errors.len(), 1, "{c:?}: {errors:?}");
        let e = byte_of(errors[0]);
        assert!(e >= at as u64 && e < end as u64, "{c:?}: {}", errors[0]);
        assert!(items.iter().all(Result::is_err), "{c:?}");
        assert_eq!(reader.skipped().get(read::SKIP_LOST_SCAN), 5, "{c:?}");
    }
}

/// A file on disk whose first chunk (where the channels are defined) is damaged: the
/// summary's definitions stand in for the lost ones, so every scan of the later chunks is
/// read, and only the damaged chunk's scans are counted lost. From a stream (no end to read
/// first) the later chunks' scans are on an undeclared channel, as documented.
#[test]
fn a_corrupt_first_chunk_on_disk_loses_only_its_own_scans() {
    let dir = std::env::temp_dir().join(format!("laserlines-first-chunk-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for c in [None, Some(mcap::Compression::Zstd)] {
        let data = mcap_bytes(8, c);
        let chunks = chunks_of(&data);
        assert!(chunks.len() >= 3, "{c:?}: {} chunks", chunks.len());
        let (first, end) = chunks[0];
        let bad = damaged(&data, end);
        let good = read_all("good.mcap", data.clone());
        let path = dir.join("first.mcap");
        std::fs::write(&path, &bad).unwrap();
        let mut reader = read::open(&path, &McapReadOptions::default()).unwrap();
        let items: Vec<_> = reader.by_ref().collect();
        let errors: Vec<_> = items.iter().filter_map(|r| r.as_ref().err()).collect();
        assert_eq!(errors.len(), 1, "{c:?}: {errors:?}");
        let at = byte_of(errors[0]);
        assert!(
            at >= first as u64 && at < end as u64,
            "{c:?}: {}",
            errors[0]
        );
        let scans: Vec<_> = items.iter().filter_map(|r| r.as_ref().ok()).collect();
        let lost = reader.skipped().get(read::SKIP_LOST_SCAN);
        // The first chunk holds the definitions and at most a scan or two.
        assert!(scans.len() >= 6, "{c:?}: {} scans", scans.len());
        assert_eq!(
            scans.len() as u64 + lost,
            8,
            "{c:?}: {:?}",
            reader.skipped()
        );
        assert_eq!(reader.skipped().get(read::SKIP_UNKNOWN_CHANNEL), 0, "{c:?}");
        // The scans read are the good file's last ones, as they were.
        let tail = &good[8 - scans.len()..];
        for (got, want) in scans.iter().zip(tail) {
            assert_eq!(*got, want.as_ref().unwrap(), "{c:?}");
        }
        // From a stream, the later chunks' messages are on an undeclared channel.
        let mut stream =
            read::from_reader("first.mcap", Cursor::new(bad), &McapReadOptions::default()).unwrap();
        let streamed = stream.by_ref().filter(Result::is_ok).count();
        assert_eq!(streamed, 0, "{c:?}");
        assert!(
            stream.skipped().get(read::SKIP_UNKNOWN_CHANNEL) > 0,
            "{c:?}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An MCAP read through a named pipe: its summary is not read first (that would take the
/// reader's bytes), and every scan comes out as from the file.
#[cfg(unix)]
#[test]
fn an_mcap_through_a_named_pipe_reads_whole() {
    let data = mcap_bytes(6, Some(mcap::Compression::Zstd));
    let good = format!("{:?}", read_all("good.mcap", data.clone()));
    let read = |fifo: &std::path::Path| -> Vec<_> {
        read::open(fifo, &McapReadOptions::default())
            .unwrap()
            .collect()
    };
    let Some(items) = named_pipe::through_named_pipe("scans.mcap", data, read) else {
        return;
    };
    assert_eq!(format!("{items:?}"), good);
}

#[test]
fn a_record_over_the_size_limit_is_passed_over_and_counted() {
    let mut data = mcap_bytes(4, None);
    let records = top_records(&data);
    let largest = records.iter().map(|r| r.2 - r.1 - 9).max().unwrap();
    // An attachment (opcode 0x09) larger than any other record, after the first chunk, and a
    // limit between the two: it is passed over unread, every scan read.
    let len = largest + 100;
    let mut attachment = vec![0x09];
    attachment.extend_from_slice(&(len as u64).to_le_bytes());
    attachment.resize(9 + len, 0);
    let after_first = records[1].2;
    data.splice(after_first..after_first, attachment);
    let options = McapReadOptions {
        max_record_bytes: (largest + 50) as u64,
        ..McapReadOptions::default()
    };
    let mut reader = read::from_reader("big.mcap", Cursor::new(data), &options).unwrap();
    let items: Vec<_> = reader.by_ref().collect();
    assert_eq!(items.len(), 4, "{items:?}");
    assert!(items.iter().all(Result::is_ok), "{items:?}");
    assert_eq!(reader.skipped().get(read::SKIP_OVERSIZED), 1);
}

#[test]
fn a_huge_record_length_ends_the_reader_without_allocating_it() {
    let mut data = mcap_bytes(2, None);
    let (_, at, _) = top_records(&data)[1];
    data[at + 1..at + 9].copy_from_slice(&(u64::MAX - 3).to_le_bytes());
    let items = read_all("huge.mcap", data);
    let e = items.last().unwrap().as_ref().unwrap_err();
    // The records after it cannot be found: a failed read, not a bad record to skip.
    assert!(!e.is_bad_record());
    let e = e.to_string();
    assert!(
        e.contains(&format!("huge.mcap: byte {at}: read failed")),
        "{e}"
    );
    assert!(e.contains("a record of at most"), "{e}");
    assert!(e.ends_with("so the rest of the input is not read"), "{e}");
}

#[test]
fn not_an_mcap_file() {
    for (data, found) in [
        (&b""[..], "an empty file"),
        (b"\x89MCA", "89 4d 43 41"),
        (b"{\"ranges\": []}", "7b 22 72 61 6e 67 65 73"),
    ] {
        let items = read_all("x.mcap", data.to_vec());
        assert_eq!(items.len(), 1);
        let e = items[0].as_ref().unwrap_err().to_string();
        assert!(
            e.starts_with("x.mcap: byte 0: expected the MCAP magic"),
            "{e}"
        );
        assert!(e.contains(found), "{e}");
    }
}

#[test]
fn a_file_without_laserscans_says_which_channels_it_has() {
    let mut w = mcap::Writer::new(Cursor::new(Vec::new())).unwrap();
    let s = w
        .add_schema("std_msgs/msg/String", "ros2msg", b"string data")
        .unwrap();
    let c = w
        .add_channel(s, "/chatter", "cdr", &Default::default())
        .unwrap();
    let header = mcap::records::MessageHeader {
        channel_id: c,
        sequence: 1,
        log_time: 1,
        publish_time: 1,
    };
    w.write_to_known_channel(&header, &[0, 1, 0, 0, 3, 0, 0, 0, b'h', b'i', 0])
        .unwrap();
    w.finish().unwrap();
    let data = w.into_inner().into_inner();
    let items = read_all("chatter.mcap", data);
    assert_eq!(items.len(), 1);
    let e = items[0].as_ref().unwrap_err().to_string();
    assert!(e.contains("expected a LaserScan channel"), "{e}");
    assert!(e.contains("/chatter (std_msgs/msg/String)"), "{e}");
}

#[test]
fn a_json_laserscan_with_a_bad_field_is_an_error_naming_topic_field_and_byte() {
    let mut w = mcap::Writer::new(Cursor::new(Vec::new())).unwrap();
    let s = w
        .add_schema("foxglove.LaserScan", "jsonschema", b"{}")
        .unwrap();
    let c = w
        .add_channel(s, "/laser", "json", &Default::default())
        .unwrap();
    let messages: [&[u8]; 3] = [
        br#"{"start_angle": -1.0, "end_angle": 1.0, "ranges": [1.0, null, 2.0]}"#,
        br#"{"start_angle": -1.0, "end_angle": 1.0, "ranges": [1.0, "far", 2.0]}"#,
        br#"{"start_angle": -1.0, "end_angle": 1.0, "ranges": [1.0, 1.5, 2.0]}"#,
    ];
    for (k, data) in messages.iter().enumerate() {
        let header = mcap::records::MessageHeader {
            channel_id: c,
            sequence: k as u32,
            log_time: 1_000_000_000 * (k as u64 + 1),
            publish_time: 0,
        };
        w.write_to_known_channel(&header, data).unwrap();
    }
    w.finish().unwrap();
    let items = read_all("json.mcap", w.into_inner().into_inner());
    assert_eq!(items.len(), 3);
    let first = items[0].as_ref().unwrap();
    assert_eq!(first.scan.angle_increment, 1.0);
    assert!(first.scan.ranges[1].is_nan());
    assert_eq!(
        first.scan.stamp,
        Some(1.0),
        "the log time, without a timestamp"
    );
    let e = items[1].as_ref().unwrap_err();
    let text = e.to_string();
    assert!(text.starts_with("json.mcap: byte "), "{text}");
    assert!(text.contains("/laser message"), "{text}");
    assert!(text.contains("ranges[1]"), "{text}");
    assert!(text.contains("expected a number or null"), "{text}");
    assert!(text.contains("a string (\"far\")"), "{text}");
    byte_of(e);
    assert_eq!(items[2].as_ref().unwrap().scan.ranges, vec![1.0, 1.5, 2.0]);
}

/// A tiny deterministic generator for byte mutations.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        self.0 >> 33
    }
}

#[test]
fn random_damage_never_panics_and_errors_always_name_file_and_byte() {
    let mut rng = Lcg(7);
    for c in [
        None,
        Some(mcap::Compression::Zstd),
        Some(mcap::Compression::Lz4),
    ] {
        let data = mcap_bytes(4, c);
        for _ in 0..400 {
            let mut bad = data.clone();
            for _ in 0..1 + rng.next() % 4 {
                let i = (rng.next() as usize) % bad.len();
                bad[i] = rng.next() as u8;
            }
            for item in read_all("fuzz.mcap", bad) {
                match item {
                    Ok(r) => r.scan.validate().unwrap(),
                    Err(e) => {
                        assert_eq!(e.file(), "fuzz.mcap");
                        byte_of(&e);
                    }
                }
            }
        }
    }
}

/// Damage after `DataEnd` (the summary the reader of a file on disk reads first) never
/// panics and never changes a scan: the data section is whole, so every scan reads as in the
/// undamaged file.
#[test]
fn random_damage_to_the_summary_of_a_file_on_disk_changes_no_scan() {
    let dir = std::env::temp_dir().join(format!("laserlines-summary-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("summary.mcap");
    let mut rng = Lcg(11);
    let data = mcap_bytes(4, Some(mcap::Compression::Zstd));
    let good = format!("{:?}", read_all("good.mcap", data.clone()));
    let data_end = top_records(&data)
        .iter()
        .find(|(op, _, _)| *op == mcap::records::op::DATA_END)
        .map(|&(_, at, _)| at)
        .unwrap();
    // Past the DataEnd record (13 bytes with its CRC).
    let from = data_end + 13;
    for _ in 0..300 {
        let mut bad = data.clone();
        for _ in 0..1 + rng.next() % 4 {
            let i = from + (rng.next() as usize) % (bad.len() - from);
            bad[i] = rng.next() as u8;
        }
        std::fs::write(&path, &bad).unwrap();
        let items: Vec<_> = read::open(&path, &McapReadOptions::default())
            .unwrap()
            .collect();
        for e in items.iter().filter_map(|i| i.as_ref().err()) {
            byte_of(e);
        }
        let scans: Vec<_> = items.into_iter().filter(Result::is_ok).collect();
        assert_eq!(format!("{scans:?}"), good);
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
