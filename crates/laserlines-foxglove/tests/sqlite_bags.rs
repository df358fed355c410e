//! ROS 2 bags in sqlite3 storage: the bag directory rosbags wrote
//! (`tests/fixtures/ros2_laserscan_sqlite3`, compared value by value in `peer_fixtures.rs`),
//! its topics, split bags, a `.db3` file given alone, and bad input.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::path::{Path, PathBuf};

use laserlines_foxglove::{McapReadOptions, read};
use laserlines_io::{Format, ReadOptions};

fn bag() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/ros2_laserscan_sqlite3")
}

fn db3() -> PathBuf {
    bag().join("ros2_laserscan_sqlite3.db3")
}

fn temp_dir(what: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("laserlines-db3-{what}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn the_default_topic_is_the_first_laserscan_topic_and_the_other_is_counted() {
    let mut reader = read::open(&bag(), &McapReadOptions::default()).unwrap();
    assert_eq!(reader.format(), Format::Db3);
    let scans: Vec<_> = reader.by_ref().collect::<Result<_, _>>().unwrap();
    // The /scan series has 7, 10 and 13 beams; /scan_rear 8, 11, 14.
    let beams: Vec<usize> = scans.iter().map(|r| r.scan.ranges.len()).collect();
    assert_eq!(beams, [7, 10, 13]);
    assert_eq!(reader.skipped().get(read::SKIP_OTHER_TOPIC), 3);
    assert_eq!(reader.skipped().total(), 3);
    for name in ["/scan_rear", "scan_rear"] {
        let reader = read::open(&bag(), &McapReadOptions::topic(Some(name))).unwrap();
        let beams: Vec<usize> = reader.map(|r| r.unwrap().scan.ranges.len()).collect();
        assert_eq!(beams, [8, 11, 14], "{name}");
    }
}

#[test]
fn a_db3_file_alone_and_through_open_scans_reads_the_same() {
    let alone: Vec<_> = read::open(&db3(), &McapReadOptions::default())
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    let options = ReadOptions::format(None);
    let chosen: Vec<_> = laserlines_foxglove::open_scans(&db3(), &options)
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    let dir: Vec<_> = laserlines_foxglove::open_scans(&bag(), &options)
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    assert_eq!(alone.len(), 3);
    // NaN ranges: compared as printed.
    assert_eq!(format!("{alone:?}"), format!("{chosen:?}"));
    assert_eq!(format!("{alone:?}"), format!("{dir:?}"));
}

#[test]
fn a_missing_topic_is_an_error_naming_the_topics_there() {
    let items: Vec<_> = read::open(&bag(), &McapReadOptions::topic(Some("/nope")))
        .unwrap()
        .collect();
    assert_eq!(items.len(), 1);
    let e = items[0].as_ref().unwrap_err().to_string();
    assert!(
        e.ends_with(
            "ros2_laserscan_sqlite3.db3: byte 0: expected a sensor_msgs/msg/LaserScan or \
             sensor_msgs/msg/MultiEchoLaserScan topic /nope, found topics /scan (sensor_msgs/msg/LaserScan), /scan_rear \
             (sensor_msgs/msg/LaserScan), /note (std_msgs/msg/String)"
        ),
        "{e}"
    );
    // A topic that is there but holds no LaserScans.
    let items: Vec<_> = read::open(&bag(), &McapReadOptions::topic(Some("/note")))
        .unwrap()
        .collect();
    assert!(
        items[0]
            .as_ref()
            .unwrap_err()
            .to_string()
            .contains("topic /note")
    );
}

#[test]
fn a_split_bag_reads_its_files_in_numeric_order() {
    let dir = temp_dir("split");
    // bag_10 must come after bag_2: give each file a different first scan count.
    for (k, name) in ["bag_0.db3", "bag_2.db3", "bag_10.db3"].iter().enumerate() {
        let path = dir.join(name);
        std::fs::copy(db3(), &path).unwrap();
        let db = rusqlite::Connection::open(&path).unwrap();
        // Keep k + 1 of the three /scan messages in file k.
        db.execute(
            "DELETE FROM messages WHERE topic_id = (SELECT id FROM topics WHERE name = '/scan') \
             AND id NOT IN (SELECT id FROM messages WHERE topic_id = (SELECT id FROM topics \
             WHERE name = '/scan') ORDER BY id LIMIT ?1)",
            [k as i64 + 1],
        )
        .unwrap();
    }
    let reader = read::open(&dir, &McapReadOptions::default()).unwrap();
    let beams: Vec<usize> = reader.map(|r| r.unwrap().scan.ranges.len()).collect();
    assert_eq!(beams, [7, 7, 10, 7, 10, 13]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_message_that_does_not_decode_names_its_id_and_reading_goes_on() {
    let dir = temp_dir("bad-message");
    let path = dir.join("bag_0.db3");
    std::fs::copy(db3(), &path).unwrap();
    let db = rusqlite::Connection::open(&path).unwrap();
    let id: i64 = db
        .query_row(
            "SELECT messages.id FROM messages JOIN topics ON topics.id = topic_id \
             WHERE name = '/scan' ORDER BY messages.id LIMIT 1 OFFSET 1",
            [],
            |row| row.get(0),
        )
        .unwrap();
    db.execute(
        "UPDATE messages SET data = substr(data, 1, 30) WHERE id = ?1",
        [id],
    )
    .unwrap();
    drop(db);
    let items: Vec<_> = read::open(&dir, &McapReadOptions::default())
        .unwrap()
        .collect();
    assert_eq!(items.len(), 3);
    assert!(items[0].is_ok() && items[2].is_ok());
    let e = items[1].as_ref().unwrap_err().to_string();
    assert!(
        e.starts_with(&format!(
            "{}: message {id}: /scan message: ",
            path.display()
        )),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_row_of_the_wrong_type_loses_no_other_message_and_orphans_are_counted() {
    let dir = temp_dir("bad-rows");
    let path = dir.join("bag_0.db3");
    std::fs::copy(db3(), &path).unwrap();
    let db = rusqlite::Connection::open(&path).unwrap();
    // 200 /scan messages, more than three pages: copies of the first, each stamped apart.
    db.execute_batch(
        "CREATE TEMP TABLE first AS SELECT messages.topic_id AS t, data AS d FROM messages \
         JOIN topics ON topics.id = topic_id WHERE name = '/scan' ORDER BY messages.id LIMIT 1; \
         DELETE FROM messages WHERE topic_id = (SELECT t FROM first); \
         WITH RECURSIVE c(x) AS (SELECT 1 UNION ALL SELECT x + 1 FROM c WHERE x < 200) \
         INSERT INTO messages(topic_id, timestamp, data) \
         SELECT (SELECT t FROM first), 1700000000000000000 + x, (SELECT d FROM first) FROM c;",
    )
    .unwrap();
    let nth = |k: i64| -> i64 {
        db.query_row(
            "SELECT messages.id FROM messages JOIN topics ON topics.id = topic_id \
             WHERE name = '/scan' ORDER BY messages.id LIMIT 1 OFFSET ?1",
            [k],
            |row| row.get(0),
        )
        .unwrap()
    };
    let (text, noon, orphan) = (nth(100), nth(150), nth(3));
    db.execute(
        "UPDATE messages SET data = CAST(data AS TEXT) WHERE id = ?1",
        [text],
    )
    .unwrap();
    // The column is NOT NULL, and text that is no number stays text in it.
    db.execute(
        "UPDATE messages SET timestamp = 'noon' WHERE id = ?1",
        [noon],
    )
    .unwrap();
    db.execute("UPDATE messages SET topic_id = 99 WHERE id = ?1", [orphan])
        .unwrap();
    drop(db);
    let mut reader = read::open(&path, &McapReadOptions::default()).unwrap();
    let items: Vec<_> = reader.by_ref().collect();
    // Every message but the orphan comes out, the two bad rows as errors in their place.
    assert_eq!(items.len(), 199);
    let errors: Vec<(usize, String)> = items
        .iter()
        .enumerate()
        .filter_map(|(k, r)| r.as_ref().err().map(|e| (k, e.to_string())))
        .collect();
    let at = |id: i64| format!("{}: message {id}: /scan message's ", path.display());
    assert_eq!(errors.len(), 2, "{errors:?}");
    assert_eq!(errors[0].0, 99);
    assert!(errors[0].1.starts_with(&at(text)), "{}", errors[0].1);
    assert!(
        errors[0]
            .1
            .ends_with("data: expected a BLOB (the CDR message), found TEXT")
    );
    assert_eq!(errors[1].0, 149);
    assert!(errors[1].1.starts_with(&at(noon)), "{}", errors[1].1);
    assert!(
        errors[1]
            .1
            .ends_with("timestamp: expected an integer (nanoseconds), found TEXT")
    );
    assert!(
        errors
            .iter()
            .all(|(_, e)| !e.contains("-9223372036854775808"))
    );
    assert_eq!(reader.skipped().get(read::db3::SKIP_UNDECLARED_TOPIC), 1);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_file_that_is_no_database_is_an_error_at_byte_zero() {
    let dir = temp_dir("not-sqlite");
    std::fs::write(dir.join("bag_0.db3"), b"not a database at all").unwrap();
    let items: Vec<_> = read::open(&dir, &McapReadOptions::default())
        .unwrap()
        .collect();
    assert_eq!(items.len(), 1);
    let e = items[0].as_ref().unwrap_err().to_string();
    assert_eq!(
        e,
        format!(
            "{}: byte 0: expected an SQLite 3 database (`SQLite format 3`), as ROS 2 bags in \
             sqlite3 storage are, found other bytes (6e 6f 74 20 61 20 64 61 74 61 62 61 73 \
             65 20 61)",
            dir.join("bag_0.db3").display()
        )
    );
    // An empty file and a gzipped database say so.
    for (bytes, found) in [
        (&b""[..], "found an empty file"),
        (
            &[0x1f, 0x8b, 8, 0][..],
            "found gzip data (SQLite reads plain files only",
        ),
    ] {
        std::fs::write(dir.join("bag_0.db3"), bytes).unwrap();
        let items: Vec<_> = read::open(&dir, &McapReadOptions::default())
            .unwrap()
            .collect();
        let e = items[0].as_ref().unwrap_err().to_string();
        assert!(e.contains(found), "{e}");
    }
    // Compressed bag files are named in the error.
    std::fs::remove_file(dir.join("bag_0.db3")).unwrap();
    std::fs::write(dir.join("bag_0.db3.zstd"), b"(zstd)").unwrap();
    let e = read::open(&dir, &McapReadOptions::default()).unwrap_err();
    assert!(e.to_string().contains("compressed (.zstd)"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_db3_format_reads_a_database_of_any_name() {
    let dir = temp_dir("any-name");
    let renamed = dir.join("scans.bin");
    std::fs::copy(db3(), &renamed).unwrap();
    let options = ReadOptions::format(Some(Format::Db3));
    let scans: Vec<_> = laserlines_foxglove::open_scans(&renamed, &options)
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    let alone: Vec<_> = read::open(&db3(), &McapReadOptions::default())
        .unwrap()
        .collect::<Result<_, _>>()
        .unwrap();
    assert_eq!(format!("{scans:?}"), format!("{alone:?}"));
    // Without the format, the name decides (an MCAP is expected, and named).
    let e = laserlines_foxglove::open_scans(&renamed, &ReadOptions::format(None)).unwrap_err();
    assert!(e.to_string().contains("scans.bin"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn standard_input_is_refused_for_sqlite3_storage() {
    let options = ReadOptions::format(Some(Format::Db3));
    let e = laserlines_foxglove::open_scans(Path::new("-"), &options).unwrap_err();
    assert!(
        e.to_string()
            .contains("SQLite cannot read a database from standard input"),
        "{e}"
    );
}
