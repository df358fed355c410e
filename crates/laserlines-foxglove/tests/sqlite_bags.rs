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

/// Copies the fixture to `path` with its `/scan` messages replaced by `n` copies of the
/// first (ids after the fixture's, timestamps [`STAMP0`] plus 1 to `n`), and opens it.
fn with_scans(path: &Path, n: u32) -> rusqlite::Connection {
    std::fs::copy(db3(), path).unwrap();
    let db = rusqlite::Connection::open(path).unwrap();
    db.execute_batch(&format!(
        "CREATE TEMP TABLE first AS SELECT messages.topic_id AS t, data AS d FROM messages \
         JOIN topics ON topics.id = topic_id WHERE name = '/scan' ORDER BY messages.id LIMIT 1; \
         DELETE FROM messages WHERE topic_id = (SELECT t FROM first); \
         WITH RECURSIVE c(x) AS (SELECT 1 UNION ALL SELECT x + 1 FROM c WHERE x < {n}) \
         INSERT INTO messages(topic_id, timestamp, data) \
         SELECT (SELECT t FROM first), {STAMP0} + x, (SELECT d FROM first) FROM c;"
    ))
    .unwrap();
    db
}

/// The timestamps of [`with_scans`] count from this, ns.
const STAMP0: i64 = 1_700_000_000_000_000_000;

#[test]
fn a_row_of_the_wrong_type_loses_no_other_message_and_orphans_are_counted() {
    let dir = temp_dir("bad-rows");
    let path = dir.join("bag_0.db3");
    std::fs::copy(db3(), &path).unwrap();
    let db = with_scans(&path, 200);
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

/// Overwrites the type byte of the table leaf page (of `messages`) that holds the row whose
/// timestamp is `stamp` ([`leaf_of`]), so that SQLite cannot read that page. Returns the
/// page's number (from 1).
fn damage_page_of(path: &Path, stamp: i64) -> usize {
    let mut bytes = std::fs::read(path).unwrap();
    let page = page_size(&bytes);
    let n = leaf_of(&bytes, page, stamp);
    bytes[n * page] = 0x42;
    std::fs::write(path, bytes).unwrap();
    n + 1
}

/// The page size of the database `bytes` (its header's bytes 16-17).
fn page_size(bytes: &[u8]) -> usize {
    let page = usize::from(u16::from_be_bytes([bytes[16], bytes[17]]));
    assert!(page >= 512, "page size {page}");
    page
}

/// The number (from 0) of the table leaf page of `messages` in `bytes` that holds the row
/// whose timestamp is `stamp` (found by its 8 big-endian bytes in the record; the timestamp
/// index holds them too, on an index page; page 1, the schema's, is never a leaf of it).
fn leaf_of(bytes: &[u8], page: usize, stamp: i64) -> usize {
    let key = stamp.to_be_bytes();
    (0..bytes.len() / page)
        .find(|&n| {
            let p = &bytes[n * page..(n + 1) * page];
            p[0] == 0x0d && p.windows(8).any(|w| w == key)
        })
        .expect("the row's table leaf page")
}

/// The id of the message of timestamp `stamp` in the database at `path` (read before it is
/// damaged).
fn db_id(path: &Path, stamp: i64) -> i64 {
    let db = rusqlite::Connection::open(path).unwrap();
    db.query_row(
        "SELECT id FROM messages WHERE timestamp = ?1",
        [stamp],
        |row| row.get(0),
    )
    .unwrap()
}

/// The scans read from the bag at `path`, its errors with their place among the items, and
/// the ids it passed over.
fn read_damaged(path: &Path) -> (usize, Vec<(usize, laserlines_io::ReadError)>, u64) {
    let mut reader = read::open(path, &McapReadOptions::default()).unwrap();
    let (mut scans, mut errors) = (0, Vec::new());
    for (k, item) in reader.by_ref().enumerate() {
        match item {
            Ok(_) => scans += 1,
            Err(e) => errors.push((k, e)),
        }
    }
    let passed = reader.skipped().get(read::db3::SKIP_UNREADABLE_IDS);
    (scans, errors, passed)
}

/// The first and last id passed over, and the id the reading goes on at, as the error of a
/// damaged page names them.
fn passed_ids(e: &str) -> (i64, i64, i64) {
    let ids = e.split("; message id").nth(1).expect(e);
    let n: Vec<i64> = ids
        .split(|c: char| !c.is_ascii_digit())
        .filter_map(|w| w.parse().ok())
        .collect();
    match n[..] {
        [from, to, resume] => (from, to, resume),
        [from, resume] => (from, from, resume),
        _ => panic!("{e}"),
    }
}

#[test]
fn damaged_pages_lose_only_their_own_messages_and_name_the_last_one_read() {
    let dir = temp_dir("damaged-page");
    let path = dir.join("bag_0.db3");
    // The /scan messages are the 1st to the 400th from id `first` on; others come before.
    for damage in [&[200][..], &[1], &[100, 300]] {
        drop(with_scans(&path, 400));
        let first = db_id(&path, STAMP0 + 1);
        for &k in damage {
            damage_page_of(&path, STAMP0 + k);
        }
        let (scans, errors, passed) = read_damaged(&path);
        assert_eq!(errors.len(), damage.len(), "{damage:?}: {errors:?}");
        let (mut ids, mut lost) = (0, 0);
        for (j, ((at, e), &k)) in errors.iter().zip(damage).enumerate() {
            assert!(e.is_bad_record(), "{e}");
            let (from, to, resume) = passed_ids(&e.to_string());
            assert_eq!(resume, to + 1, "{e}");
            // The damaged message was passed over, and the messages before the damage (and
            // the errors before) came before the error.
            assert!((from..=to).contains(&(first + k - 1)), "{damage:?}: {e}");
            assert_eq!(
                *at as i64,
                (from - first).max(0) - lost + j as i64,
                "{damage:?}: {e}"
            );
            let pos = if from <= 1 {
                "byte 0".to_owned()
            } else {
                format!("message {}", from - 1)
            };
            assert_eq!(
                e.to_string(),
                format!(
                    "{}: {pos}: expected the messages after it on pages SQLite can read, found \
                     a damaged page (database disk image is malformed); message ids {from} to \
                     {to} cannot be read, those from {resume} on can",
                    path.display()
                )
            );
            ids += to - from + 1;
            lost += to + 1 - from.max(first);
        }
        assert_eq!(passed, ids as u64, "{damage:?}");
        assert_eq!(scans as i64, 400 - lost, "{damage:?}");
        assert!(lost < 40 * damage.len() as i64, "{damage:?}: {lost} lost");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn damage_to_the_last_page_ends_the_reading_after_the_messages_before_it() {
    let dir = temp_dir("damaged-end");
    let path = dir.join("bag_0.db3");
    drop(with_scans(&path, 400));
    let first = db_id(&path, STAMP0 + 1);
    damage_page_of(&path, STAMP0 + 400);
    let (scans, errors, passed) = read_damaged(&path);
    assert_eq!(errors.len(), 1, "{errors:?}");
    let (at, e) = &errors[0];
    assert!((360..400).contains(&scans), "{scans}");
    assert_eq!((*at, passed), (scans, 0));
    assert!(!e.is_bad_record(), "{e}");
    assert_eq!(
        e.to_string(),
        format!(
            "{}: message {}: read failed: SQLite cannot read the messages after this one (database disk \
             image is malformed)",
            path.display(),
            first + scans as i64 - 1
        )
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_damaged_overflow_page_loses_only_its_message() {
    let dir = temp_dir("damaged-overflow");
    let path = dir.join("bag_0.db3");
    let db = with_scans(&path, 100);
    // The 50th message made 20 kB long: most of it on overflow pages, each starting with the
    // number of the next (4 bytes), then `Q`s.
    db.execute(
        "UPDATE messages SET data = CAST(printf('%.*c', 20000, 'Q') AS BLOB) \
         WHERE timestamp = ?1",
        [STAMP0 + 50],
    )
    .unwrap();
    drop(db);
    let id = db_id(&path, STAMP0 + 50);
    let mut bytes = std::fs::read(&path).unwrap();
    let page = page_size(&bytes);
    let full = vec![b'Q'; page - 4];
    let overflow = (0..bytes.len() / page)
        .find(|&n| bytes[n * page + 4..(n + 1) * page] == full[..])
        .expect("an overflow page of Qs");
    // A next page far past the end of the file.
    bytes[overflow * page..overflow * page + 4].copy_from_slice(&[0x7f, 0xff, 0xff, 0xff]);
    std::fs::write(&path, bytes).unwrap();
    let (scans, errors, passed) = read_damaged(&path);
    assert_eq!((scans, passed, errors.len()), (99, 1, 1), "{errors:?}");
    let (at, e) = &errors[0];
    assert_eq!(*at, 49);
    assert!(
        e.to_string().ends_with(&format!(
            "message {}: expected the messages after it on pages SQLite can read, found a \
             damaged page (database disk image is malformed); message id {id} cannot be read, \
             those from {} on can",
            id - 1,
            id + 1
        )),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Random damage to a bag's pages (bytes overwritten anywhere past the file header):
/// reading ends, every error names the file, and no more scans come out than the bag holds
/// (a reading that went back over messages would give more).
#[test]
fn random_damage_ends_the_reading_and_gives_no_message_twice() {
    let dir = temp_dir("random-damage");
    let path = dir.join("bag_0.db3");
    drop(with_scans(&path, 400));
    let clean = std::fs::read(&path).unwrap();
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for round in 0..60 {
        let mut bytes = clean.clone();
        for _ in 0..1 + next() % 8 {
            let at = 100 + (next() as usize) % (bytes.len() - 100);
            bytes[at] = next() as u8;
        }
        std::fs::write(&path, &bytes).unwrap();
        let Ok(reader) = read::open(&path, &McapReadOptions::default()) else {
            continue;
        };
        let (mut scans, mut items) = (0, 0);
        for item in reader.take(2000) {
            items += 1;
            match item {
                Ok(r) => {
                    assert!(r.scan.validate().is_ok());
                    scans += 1;
                }
                Err(e) => assert_eq!(e.file(), path.display().to_string(), "{round}: {e}"),
            }
        }
        assert!(scans <= 400, "round {round}: {scans} scans");
        // The reading ended by itself: at most one item per row and a few errors.
        assert!(items < 2000, "round {round}: {items} items");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_message_at_the_largest_id_is_read_once() {
    let dir = temp_dir("largest-id");
    let path = dir.join("bag_0.db3");
    // With the fixture's 6 other messages, 64 rows: one whole page of the reading, whose
    // last row has the largest id there can be, so that the reading asks for more after it.
    let db = with_scans(&path, 58);
    let rows: i64 = db
        .query_row("SELECT COUNT(*) FROM messages", [], |row| row.get(0))
        .unwrap();
    assert_eq!(rows, read::db3::PAGE);
    db.execute(
        "UPDATE messages SET id = 9223372036854775807 WHERE timestamp = ?1",
        [STAMP0 + 58],
    )
    .unwrap();
    drop(db);
    let (scans, errors, passed) = read_damaged(&path);
    assert_eq!((scans, errors.len(), passed), (58, 0, 0), "{errors:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Two leaf pages swapped: the pages read whole, but the interior pages lead to rows out of
/// order, or past rows they hold. The reading goes forward only: it ends, gives no message
/// twice, and says where the order broke.
#[test]
fn swapped_pages_end_the_reading_without_going_back() {
    let dir = temp_dir("swapped");
    let path = dir.join("bag_0.db3");
    drop(with_scans(&path, 400));
    let clean = std::fs::read(&path).unwrap();
    let page = page_size(&clean);
    let (a, b) = (
        leaf_of(&clean, page, STAMP0 + 50),
        leaf_of(&clean, page, STAMP0 + 200),
    );
    assert_ne!(a, b);
    let mut bytes = clean.clone();
    bytes[a * page..(a + 1) * page].copy_from_slice(&clean[b * page..(b + 1) * page]);
    bytes[b * page..(b + 1) * page].copy_from_slice(&clean[a * page..(a + 1) * page]);
    std::fs::write(&path, bytes).unwrap();
    let (scans, errors, _) = read_damaged(&path);
    assert!((1..400).contains(&scans), "{scans}");
    assert!(!errors.is_empty());
    assert!(
        errors
            .iter()
            .any(|(_, e)| e.to_string().contains("message ids out of order")),
        "{errors:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
