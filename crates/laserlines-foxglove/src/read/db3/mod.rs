//! ROS 2 bags in sqlite3 storage (`.db3`, the default storage before ROS 2 Iron): the
//! `sensor_msgs/msg/LaserScan` messages (CDR) of one topic (or `sensor_msgs/msg/MultiEchoLaserScan`,
//! each beam's first echo, the echoes after it counted), read from the `topics` and
//! `messages` tables that every version of the storage has (`topics`: `id`, `name`, `type`,
//! `serialization_format`; `messages`: `id`, `topic_id`, `timestamp`, `data`).
//!
//! The database is opened read-only through SQLite itself (the `rusqlite` crate with its
//! bundled SQLite). Messages come out in the order they were written (their `id`), in one pass
//! over the rows of every topic, [`PAGE`] at a time, so memory stays flat on long bags (the
//! other topics' data is not read). The topic read is the one asked for (with or without its
//! leading `/`), or else the first LaserScan topic of the file; the other LaserScan topics'
//! messages are counted as skipped as the pass meets them. The stamp is the
//! header's, or the message's `timestamp` (receive time) when the header stamp is zero. A
//! message that does not decode (or whose row holds no integer `timestamp` or no BLOB
//! `data`) is an error naming the file and the message id, and reading goes on. Messages on
//! a `topic_id` that no topic declares are counted as skipped. Where SQLite cannot read on
//! (a corrupt page), the messages read before it come out, then a bad record naming the last
//! message read, and the reading goes on at the first id past the damage ([`resume`]), the ids
//! passed over counted under [`SKIP_UNREADABLE_IDS`]; when nothing past it reads (damage to
//! the end of the file, or to the table's root), the reading ends there with a failed read.

use std::cmp::Ordering;
use std::collections::VecDeque;
use std::io::Read;
use std::path::{Path, PathBuf};

use laserlines_io::{ReadError, ScanRecord, ScanSource, SkipCounts, SourcePos};
use rusqlite::{Connection, OpenFlags, params};

use super::{SKIP_LATER_ECHOES, SKIP_OTHER_TOPIC};
use laserlines_io::ros::ScanMsgType;

mod resume;

/// The first 16 bytes of every SQLite 3 database.
pub const SQLITE_MAGIC: &[u8; 16] = b"SQLite format 3\0";
/// The message type read.
pub const LASER_SCAN_TYPE: &str = "sensor_msgs/msg/LaserScan";
/// The multi-echo message type read (each beam's first echo).
pub const MULTI_ECHO_TYPE: &str = "sensor_msgs/msg/MultiEchoLaserScan";
/// Messages read from the database at a time.
pub const PAGE: i64 = 64;

/// What the file at `path` starts with instead of [`SQLITE_MAGIC`], for a message; `None`
/// when it starts with it.
fn sqlite_head(path: &Path) -> Option<String> {
    let mut head = Vec::with_capacity(16);
    let read = std::fs::File::open(path)
        .and_then(|f| f.take(16).read_to_end(&mut head))
        .map_err(|e| format!("a file that cannot be read ({e})"));
    match read {
        Err(e) => Some(e),
        Ok(_) if head.as_slice() == SQLITE_MAGIC => None,
        Ok(0) => Some("an empty file".to_owned()),
        Ok(_) if head.starts_with(&[0x1f, 0x8b]) => {
            Some("gzip data (SQLite reads plain files only: gunzip it first)".to_owned())
        }
        Ok(_) => Some(format!(
            "other bytes ({})",
            head.iter()
                .map(|b| format!("{b:02x}"))
                .collect::<Vec<_>>()
                .join(" ")
        )),
    }
}

/// A topic of the bag: id, name, type, serialization format.
struct Topic {
    id: i64,
    name: String,
    kind: String,
    format: String,
}

/// One `.db3` file being read.
struct Db3File {
    name: String,
    db: Connection,
    topic_id: i64,
    topic: String,
    kind: ScanMsgType,
    /// The ids of the other LaserScan topics, whose messages are counted as skipped.
    other_scans: Vec<i64>,
    /// The ids of every topic, for the messages on a `topic_id` no topic declares.
    declared: Vec<i64>,
    /// The id of the last message read (of any topic).
    after: i64,
    /// Messages read and not yet returned: id, and timestamp and data (or what the row
    /// holds instead).
    page: VecDeque<(i64, RowValues)>,
    done: bool,
    /// The error that ended the reading, returned once the page before it is.
    failed: Option<rusqlite::Error>,
    /// The error of damage the reading goes on past, and the id it goes on at, returned once
    /// the page before it is.
    passed: Option<(rusqlite::Error, i64)>,
}

/// Skip reason for messages whose `topic_id` no topic of the bag declares.
pub const SKIP_UNDECLARED_TOPIC: &str = "message on an undeclared topic";

/// Skip reason for the message ids passed over where SQLite cannot read (a damaged page):
/// every id between the last message read and the first one read past the damage, of any
/// topic (what they held cannot be read).
pub const SKIP_UNREADABLE_IDS: &str = "message id passed over on a damaged page (any topic)";

/// A `messages` row's column that does not hold what it must: its name, what it must hold
/// and what it holds.
type BadRow = (&'static str, &'static str, &'static str);

/// A `messages` row's `timestamp` and `data`, or the column that does not hold them.
type RowValues = Result<(i64, Vec<u8>), BadRow>;

/// Every row of `messages` from id `?2` on, in id order, at most `?3`: its id and `topic_id`,
/// and for topic `?1` its `timestamp` and `data` (read only for that topic, so that other
/// topics' large messages stay unread).
const ROWS: &str = "SELECT id, topic_id, CASE WHEN topic_id = ?1 THEN timestamp END, \
                    CASE WHEN topic_id = ?1 THEN data END FROM messages WHERE id >= ?2 \
                    ORDER BY id LIMIT ?3";

/// A row of [`ROWS`]: its id, its `topic_id` (`None` when that is no integer), and for topic
/// `topic_id` its timestamp and data or the column that holds no integer or no BLOB.
type Row = (i64, Option<i64>, Option<RowValues>);

/// The error of a row whose id is not above the last one read: the pages SQLite found it
/// by are damaged.
fn out_of_order(id: i64) -> rusqlite::Error {
    rusqlite::Error::SqliteFailure(
        rusqlite::ffi::Error::new(rusqlite::ffi::SQLITE_CORRUPT),
        Some(format!("message ids out of order: {id} after a later one")),
    )
}

/// Reads a row of [`ROWS`] for topic `topic_id`.
fn read_row(row: &rusqlite::Row<'_>, topic_id: i64) -> rusqlite::Result<Row> {
    use rusqlite::types::ValueRef;
    let kind = |v: ValueRef<'_>| match v {
        ValueRef::Null => "NULL",
        ValueRef::Integer(_) => "an integer",
        ValueRef::Real(_) => "a real",
        ValueRef::Text(_) => "TEXT",
        ValueRef::Blob(_) => "a BLOB",
    };
    let id = row.get::<_, i64>(0)?;
    let topic = match row.get_ref(1)? {
        ValueRef::Integer(t) => Some(t),
        _ => None,
    };
    if topic != Some(topic_id) {
        return Ok((id, topic, None));
    }
    let values = match (row.get_ref(2)?, row.get_ref(3)?) {
        (ValueRef::Integer(t), ValueRef::Blob(d)) => Ok((t, d.to_vec())),
        (ValueRef::Integer(_), d) => Err(("data", "a BLOB (the CDR message)", kind(d))),
        (t, _) => Err(("timestamp", "an integer (nanoseconds)", kind(t))),
    };
    Ok((id, topic, Some(values)))
}

fn db_error(name: &str, e: &rusqlite::Error) -> ReadError {
    ReadError::Syntax {
        pos: SourcePos::byte(name, 0),
        expected: "a ROS 2 bag in sqlite3 storage (tables topics and messages)".to_owned(),
        found: format!("a database SQLite cannot read that way ({e})"),
    }
}

fn same_topic(given: &str, topic: &str) -> bool {
    given.trim_start_matches('/') == topic.trim_start_matches('/')
}

impl Db3File {
    /// Opens a file and chooses its topic: `topic`, or the first LaserScan topic.
    fn open(path: &Path, topic: Option<&str>) -> Result<Self, ReadError> {
        let name = path.display().to_string();
        if let Some(found) = sqlite_head(path) {
            return Err(ReadError::Syntax {
                pos: SourcePos::byte(&name, 0),
                expected: "an SQLite 3 database (`SQLite format 3`), as ROS 2 bags in sqlite3 \
                           storage are"
                    .to_owned(),
                found,
            });
        }
        let flags = OpenFlags::SQLITE_OPEN_READ_ONLY | OpenFlags::SQLITE_OPEN_NO_MUTEX;
        let db = Connection::open_with_flags(path, flags).map_err(|e| db_error(&name, &e))?;
        let topics = read_topics(&db).map_err(|e| db_error(&name, &e))?;
        let chosen = topics.iter().find_map(|t| {
            let kind = ScanMsgType::ros2(&t.kind)?;
            topic
                .is_none_or(|given| same_topic(given, &t.name))
                .then_some((t, kind))
        });
        let Some((chosen, kind)) = chosen else {
            return Err(no_topic(&name, topic, &topics));
        };
        if chosen.format != "cdr" {
            return Err(ReadError::Syntax {
                pos: SourcePos::byte(&name, 0),
                expected: format!("topic {} serialized as cdr", chosen.name),
                found: format!("serialization format {:?}", chosen.format),
            });
        }
        let other_scans = topics
            .iter()
            .filter(|t| ScanMsgType::ros2(&t.kind).is_some() && t.id != chosen.id)
            .map(|t| t.id)
            .collect();
        Ok(Self {
            topic_id: chosen.id,
            topic: chosen.name.clone(),
            kind,
            other_scans,
            declared: topics.iter().map(|t| t.id).collect(),
            name,
            db,
            after: i64::MIN,
            page: VecDeque::new(),
            done: false,
            failed: None,
            passed: None,
        })
    }

    /// Reads the next [`PAGE`] messages: the topic's go to the page, the other LaserScan
    /// topics' and those on an undeclared topic are counted in `skipped`. The rows read
    /// before an error stay read.
    fn fetch(&mut self, skipped: &mut SkipCounts) -> Result<(), rusqlite::Error> {
        let Some(from) = self.after.checked_add(1) else {
            // The last id there can be was read.
            self.done = true;
            return Ok(());
        };
        let mut stmt = self.db.prepare(ROWS)?;
        let mut rows = stmt.query(params![self.topic_id, from, PAGE])?;
        let mut read = 0;
        while let Some(row) = rows.next()? {
            let (id, topic, values) = read_row(row, self.topic_id)?;
            // A damaged interior page can lead back to rows read before: damage, as the
            // reading only goes forward.
            if id < from || (read > 0 && id <= self.after) {
                return Err(out_of_order(id));
            }
            self.after = id;
            read += 1;
            match (values, topic) {
                (Some(values), _) => self.page.push_back((id, values)),
                (None, Some(t)) if self.other_scans.contains(&t) => {
                    skipped.add(SKIP_OTHER_TOPIC);
                }
                (None, Some(t)) if self.declared.contains(&t) => {}
                (None, _) => skipped.add(SKIP_UNDECLARED_TOPIC),
            }
        }
        if read < PAGE {
            self.done = true;
        }
        Ok(())
    }

    /// The next record and the echoes left out of it; the ids passed over past damage are
    /// counted in `skipped`.
    fn next(&mut self, skipped: &mut SkipCounts) -> Option<Result<(ScanRecord, usize), ReadError>> {
        while self.page.is_empty() && !self.done && self.passed.is_none() {
            let before = self.after;
            if let Err(e) = self.fetch(skipped) {
                // Whether the failure came at the first row the reading asked for.
                let at_once = self.after == before;
                match resume::resume_point(&self.db, self.topic_id, self.after, at_once) {
                    Some(at) => self.passed = Some((e, at)),
                    None => {
                        self.done = true;
                        self.failed = Some(e);
                    }
                }
            }
        }
        let Some((id, values)) = self.page.pop_front() else {
            if let Some((e, at)) = self.passed.take() {
                skipped.add_n(SKIP_UNREADABLE_IDS, resume::passed_over(self.after, at));
                let error = self.damage_passed(&e, at);
                self.after = at - 1;
                return Some(Err(error));
            }
            return self.failed.take().map(|e| Err(self.read_failed(&e)));
        };
        Some(match values {
            Ok((timestamp, data)) => self.decode(id, timestamp, &data),
            Err((column, expected, found)) => Err(ReadError::Field {
                pos: SourcePos::message(&self.name, id),
                field: format!("{} message's {column}", self.topic),
                expected: expected.to_owned(),
                found: found.to_owned(),
            }),
        })
    }

    /// Where the last message read is: the message, or byte 0 before the first.
    fn last_read(&self) -> SourcePos {
        if self.after == i64::MIN {
            SourcePos::byte(&self.name, 0)
        } else {
            SourcePos::message(&self.name, self.after)
        }
    }

    /// The bad record of damage that the reading goes on past, at id `at`.
    fn damage_passed(&self, e: &rusqlite::Error, at: i64) -> ReadError {
        let from = resume::first_passed(self.after);
        let ids = match (at - 1).cmp(&from) {
            Ordering::Greater => format!("message ids {from} to {} cannot be read", at - 1),
            Ordering::Equal => format!("message id {from} cannot be read"),
            // Found from `at` itself, which the scan through the pages did not reach.
            Ordering::Less if at == self.after.saturating_add(1) => {
                "no message id is passed over".to_owned()
            }
            // Damage to rows numbered below 1, which rosbag2 does not write.
            Ordering::Less => format!("the message ids below {at} cannot be read"),
        };
        ReadError::Syntax {
            pos: self.last_read(),
            expected: "the messages after it on pages SQLite can read".to_owned(),
            found: format!("a damaged page ({e}); {ids}, those from {at} on can"),
        }
    }

    /// The error of a database SQLite cannot read past the last message read: not a bad
    /// record, as nothing after it can be read.
    fn read_failed(&self, e: &rusqlite::Error) -> ReadError {
        let what = if self.after == i64::MIN {
            "the bag's messages"
        } else {
            "the messages after this one"
        };
        ReadError::Io {
            pos: self.last_read(),
            source: std::io::Error::other(format!("SQLite cannot read {what} ({e})")),
        }
    }

    fn decode(
        &self,
        id: i64,
        timestamp: i64,
        data: &[u8],
    ) -> Result<(ScanRecord, usize), ReadError> {
        let pos = || SourcePos::message(&self.name, id);
        let msg =
            laserlines_io::ros::decode_cdr_as(data, self.kind).map_err(|e| ReadError::Field {
                pos: pos(),
                field: format!(
                    "{} message: {} (byte {} of the message)",
                    self.topic, e.field, e.offset
                ),
                expected: e.expected,
                found: e.found,
            })?;
        let mut scan = msg.to_scan();
        if scan.stamp.is_none() && timestamp > 0 {
            scan.stamp = Some(
                (timestamp / 1_000_000_000) as f64 + (timestamp % 1_000_000_000) as f64 * 1e-9,
            );
        }
        scan.validate()
            .map_err(|source| ReadError::InvalidScan { pos: pos(), source })?;
        let record = ScanRecord {
            scan,
            pose: None,
            odometry: None,
            line: None,
        };
        Ok((record, msg.echoes_left_out))
    }
}

fn read_topics(db: &Connection) -> Result<Vec<Topic>, rusqlite::Error> {
    let mut stmt =
        db.prepare("SELECT id, name, type, serialization_format FROM topics ORDER BY id")?;
    let rows = stmt.query_map([], |row| {
        Ok(Topic {
            id: row.get(0)?,
            name: row.get(1)?,
            kind: row.get(2)?,
            format: row.get(3)?,
        })
    })?;
    rows.collect()
}

/// The error of a bag without the topic asked for (or without any scan topic).
fn no_topic(name: &str, topic: Option<&str>, topics: &[Topic]) -> ReadError {
    let mut seen: Vec<String> = topics
        .iter()
        .map(|t| format!("{} ({})", t.name, t.kind))
        .collect();
    let total = seen.len();
    seen.truncate(10);
    let mut found = if seen.is_empty() {
        "no topics".to_owned()
    } else {
        format!("topics {}", seen.join(", "))
    };
    if total > seen.len() {
        found.push_str(&format!(" ({total} in all)"));
    }
    let expected = match topic {
        Some(t) => format!("a {LASER_SCAN_TYPE} or {MULTI_ECHO_TYPE} topic {t}"),
        None => format!("a {LASER_SCAN_TYPE} or {MULTI_ECHO_TYPE} topic"),
    };
    ReadError::Syntax {
        pos: SourcePos::byte(name, 0),
        expected,
        found,
    }
}

/// The `.db3` files of a ROS 2 bag, read one after the other on the topic the first one
/// settles.
pub(super) struct Db3FilesSource {
    pub(super) files: VecDeque<PathBuf>,
    current: Option<Db3File>,
    topic: Option<String>,
}

impl Db3FilesSource {
    pub(super) fn new(files: Vec<PathBuf>, topic: Option<&str>) -> Self {
        Self {
            files: files.into(),
            current: None,
            topic: topic.map(str::to_owned),
        }
    }
}

impl ScanSource for Db3FilesSource {
    fn next_record(&mut self, skipped: &mut SkipCounts) -> Option<Result<ScanRecord, ReadError>> {
        loop {
            if self.current.is_none() {
                let path = self.files.pop_front()?;
                match Db3File::open(&path, self.topic.as_deref()) {
                    Ok(file) => {
                        // Later files read the topic this one settled.
                        self.topic = Some(file.topic.clone());
                        self.current = Some(file);
                    }
                    Err(e) => return Some(Err(e)),
                }
            }
            let current = self.current.as_mut()?;
            match current.next(skipped) {
                Some(item) => {
                    return Some(item.map(|(record, left_out)| {
                        skipped.add_n(SKIP_LATER_ECHOES, left_out as u64);
                        record
                    }));
                }
                None => self.current = None,
            }
        }
    }
}
