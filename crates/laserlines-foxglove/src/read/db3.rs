//! ROS 2 bags in sqlite3 storage (`.db3`, the default storage before ROS 2 Iron): the
//! `sensor_msgs/msg/LaserScan` messages (CDR) of one topic (or `sensor_msgs/msg/MultiEchoLaserScan`,
//! each beam's first echo, the echoes after it counted), read from the `topics` and
//! `messages` tables that every version of the storage has (`topics`: `id`, `name`, `type`,
//! `serialization_format`; `messages`: `id`, `topic_id`, `timestamp`, `data`).
//!
//! The database is opened read-only through SQLite itself (the `rusqlite` crate with its
//! bundled SQLite). Messages come out in the order they were written (their `id`), a page of
//! [`PAGE`] messages at a time, so memory stays flat on long bags. The topic read is the one
//! asked for (with or without its leading `/`), or else the first LaserScan topic of the
//! file; the other LaserScan topics' messages are counted as skipped. The stamp is the
//! header's, or the message's `timestamp` (receive time) when the header stamp is zero. A
//! message that does not decode (or whose row holds no integer `timestamp` or no BLOB
//! `data`) is an error naming the file and the message id, and reading goes on. Messages on
//! a `topic_id` that no topic declares are counted as skipped. A database SQLite cannot read
//! further (a corrupt page) ends the reading after the messages read before it, as a failed
//! read, not a bad record.

use std::collections::VecDeque;
use std::io::Read;
use std::path::{Path, PathBuf};

use laserlines_io::{ReadError, ScanRecord, ScanSource, SkipCounts, SourcePos};
use rusqlite::{Connection, OpenFlags, params};

use super::{SKIP_LATER_ECHOES, SKIP_OTHER_TOPIC};
use laserlines_io::ros::ScanMsgType;

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
    /// The id of the last message read.
    after: i64,
    /// Messages read and not yet returned: id, and timestamp and data (or what the row
    /// holds instead).
    page: VecDeque<(i64, RowValues)>,
    done: bool,
    /// The error that ended the reading, returned once the page before it is.
    failed: Option<rusqlite::Error>,
}

/// Skip reason for messages whose `topic_id` no topic of the bag declares.
pub const SKIP_UNDECLARED_TOPIC: &str = "message on an undeclared topic";

/// A `messages` row's column that does not hold what it must: its name, what it must hold
/// and what it holds.
type BadRow = (&'static str, &'static str, &'static str);

/// A `messages` row's `timestamp` and `data`, or the column that does not hold them.
type RowValues = Result<(i64, Vec<u8>), BadRow>;

/// A `messages` row's `timestamp` and `data`, or the column that holds no integer or no BLOB.
fn row_values(row: &rusqlite::Row<'_>) -> rusqlite::Result<RowValues> {
    use rusqlite::types::ValueRef;
    let kind = |v: ValueRef<'_>| match v {
        ValueRef::Null => "NULL",
        ValueRef::Integer(_) => "an integer",
        ValueRef::Real(_) => "a real",
        ValueRef::Text(_) => "TEXT",
        ValueRef::Blob(_) => "a BLOB",
    };
    Ok(match (row.get_ref(1)?, row.get_ref(2)?) {
        (ValueRef::Integer(t), ValueRef::Blob(d)) => Ok((t, d.to_vec())),
        (ValueRef::Integer(_), d) => Err(("data", "a BLOB (the CDR message)", kind(d))),
        (t, _) => Err(("timestamp", "an integer (nanoseconds)", kind(t))),
    })
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
    /// Opens a file and chooses its topic: `topic`, or the first LaserScan topic. Counts the
    /// messages of the other LaserScan topics in `skipped`.
    fn open(path: &Path, topic: Option<&str>, skipped: &mut SkipCounts) -> Result<Self, ReadError> {
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
        let others: Vec<i64> = topics
            .iter()
            .filter(|t| ScanMsgType::ros2(&t.kind).is_some() && t.id != chosen.id)
            .map(|t| t.id)
            .collect();
        for id in others {
            let n: i64 = db
                .query_row(
                    "SELECT COUNT(*) FROM messages WHERE topic_id = ?1",
                    params![id],
                    |row| row.get(0),
                )
                .map_err(|e| db_error(&name, &e))?;
            skipped.add_n(SKIP_OTHER_TOPIC, u64::try_from(n).unwrap_or(0));
        }
        Ok(Self {
            topic_id: chosen.id,
            topic: chosen.name.clone(),
            kind,
            name,
            db,
            after: i64::MIN,
            page: VecDeque::new(),
            done: false,
            failed: None,
        })
    }

    /// Reads the next page of messages of the topic; the rows read before an error stay in
    /// the page.
    fn fetch(&mut self) -> Result<(), rusqlite::Error> {
        let mut stmt = self.db.prepare(
            "SELECT id, timestamp, data FROM messages WHERE topic_id = ?1 AND id > ?2 \
             ORDER BY id LIMIT ?3",
        )?;
        let rows = stmt.query_map(params![self.topic_id, self.after, PAGE], |row| {
            Ok((row.get::<_, i64>(0)?, row_values(row)?))
        })?;
        let mut read = 0;
        for row in rows {
            let (id, values) = row?;
            self.after = id;
            self.page.push_back((id, values));
            read += 1;
        }
        if read < PAGE {
            self.done = true;
        }
        Ok(())
    }

    /// The next record and the echoes left out of it.
    fn next(&mut self) -> Option<Result<(ScanRecord, usize), ReadError>> {
        if self.page.is_empty()
            && !self.done
            && let Err(e) = self.fetch()
        {
            self.done = true;
            self.failed = Some(e);
        }
        let Some((id, values)) = self.page.pop_front() else {
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

    /// Counts the messages on a `topic_id` no topic declares, once the file is read through
    /// (a database that failed part way is not asked again).
    fn count_undeclared(&self, skipped: &mut SkipCounts) {
        let n: rusqlite::Result<i64> = self.db.query_row(
            "SELECT COUNT(*) FROM messages WHERE topic_id NOT IN (SELECT id FROM topics)",
            [],
            |row| row.get(0),
        );
        if let Ok(n) = n {
            skipped.add_n(SKIP_UNDECLARED_TOPIC, u64::try_from(n).unwrap_or(0));
        }
    }

    /// The error of a database SQLite cannot read past the last message read: not a bad
    /// record, as nothing after it can be read.
    fn read_failed(&self, e: &rusqlite::Error) -> ReadError {
        let (pos, what) = if self.after == i64::MIN {
            (SourcePos::byte(&self.name, 0), "the bag's messages")
        } else {
            (
                SourcePos::message(&self.name, self.after),
                "the messages after this one",
            )
        };
        ReadError::Io {
            pos,
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
                match Db3File::open(&path, self.topic.as_deref(), skipped) {
                    Ok(file) => {
                        // Later files read the topic this one settled.
                        self.topic = Some(file.topic.clone());
                        self.current = Some(file);
                    }
                    Err(e) => return Some(Err(e)),
                }
            }
            let current = self.current.as_mut()?;
            match current.next() {
                Some(item) => {
                    return Some(item.map(|(record, left_out)| {
                        skipped.add_n(SKIP_LATER_ECHOES, left_out as u64);
                        record
                    }));
                }
                None => {
                    if current.failed.is_none() {
                        current.count_undeclared(skipped);
                    }
                    self.current = None;
                }
            }
        }
    }
}
