//! The connections of a bag, the choice of the LaserScan topic, and the decoding of its
//! messages into scan records.

use std::collections::{BTreeMap, HashMap};

use laserlines::Scan;

use crate::error::ReadError;
use crate::record::ScanRecord;
use crate::ros::{LaserScanMsg, ScanMsgType, decode_ros1_whole_as};
use crate::skip::SkipCounts;

use super::index::IndexedConnection;
use super::records::{Bad, Loc, for_each_field};
use super::{
    SKIP_BAD_INTENSITIES, SKIP_LATER_ECHOES, SKIP_OTHER_TOPIC, SKIP_OTHER_TYPE,
    SKIP_UNKNOWN_CONNECTION,
};

/// What a connection carries.
#[derive(Debug, Clone)]
pub(super) struct Connection {
    pub(super) topic: String,
    pub(super) kind: String,
}

impl Connection {
    /// The scan message type the connection carries, `None` for any other type.
    pub(super) fn scan_type(&self) -> Option<ScanMsgType> {
        ScanMsgType::ros1(&self.kind)
    }
}

/// Connections and the topic choice.
pub(super) struct State {
    pub(super) name: String,
    pub(super) connections: HashMap<u32, Connection>,
    pub(super) requested: Option<String>,
    pub(super) chosen: Option<String>,
    /// The index section's connection records ([`super::index`]), for connections whose own
    /// record was in a chunk that could not be read.
    pub(super) indexed: BTreeMap<u32, IndexedConnection>,
    /// A record or chunk could not be read (an error was handed out): connection records may
    /// have been lost.
    pub(super) lost: bool,
}

impl State {
    /// Remembers a connection record of the bag's records (`data` is the connection header:
    /// `type`, ...). Once records were lost, the index section's connections numbered below
    /// it come first ([`State::declare_from_index`]).
    pub(super) fn connection(
        &mut self,
        conn: u32,
        topic: Option<&[u8]>,
        data: &[u8],
    ) -> Result<(), Bad> {
        if self.lost {
            self.declare_from_index(conn, false);
        }
        self.declare(conn, topic, data)
    }

    /// Remembers a connection record.
    fn declare(&mut self, conn: u32, topic: Option<&[u8]>, data: &[u8]) -> Result<(), Bad> {
        let mut kind = None;
        let mut data_topic = None;
        for_each_field(data, |name, value| {
            match name {
                b"type" => kind = Some(value),
                b"topic" => data_topic = Some(value),
                _ => {}
            }
            Ok(())
        })
        .map_err(|bad| {
            Bad::new(
                format!("{} in the connection data", bad.expected),
                bad.found,
            )
        })?;
        let Some(topic) = topic.or(data_topic) else {
            return Err(Bad::new("a `topic` field in the connection record", "none"));
        };
        let Some(kind) = kind else {
            return Err(Bad::new("a `type` field in the connection data", "none"));
        };
        let connection = Connection {
            topic: String::from_utf8_lossy(topic).into_owned(),
            kind: String::from_utf8_lossy(kind).into_owned(),
        };
        self.add(conn, connection);
        Ok(())
    }

    /// Remembers a connection, choosing its topic when it is the first LaserScan topic
    /// asked for.
    pub(super) fn add(&mut self, conn: u32, connection: Connection) {
        if connection.scan_type().is_some()
            && self.chosen.is_none()
            && self
                .requested
                .as_deref()
                .is_none_or(|given| same_topic(given, &connection.topic))
        {
            self.chosen = Some(connection.topic.clone());
        }
        self.connections.insert(conn, connection);
    }

    /// Declares from the index section the connections numbered below `conn` (and `conn`
    /// itself when `with_conn`) that no record read so far declared, in order: bags number
    /// their connections in the order they declare them, so those were declared before it, in
    /// a chunk that was lost, and the topic is chosen as in the whole bag. A record that does
    /// not parse is passed over.
    fn declare_from_index(&mut self, conn: u32, with_conn: bool) {
        let upto = if with_conn {
            self.indexed.range(..=conn)
        } else {
            self.indexed.range(..conn)
        };
        let earlier: Vec<u32> = upto.map(|(&c, _)| c).collect();
        for c in earlier {
            if let Some(indexed) = self.indexed.remove(&c)
                && !self.connections.contains_key(&c)
            {
                let _ = self.declare(c, indexed.topic.as_deref(), &indexed.data);
            }
        }
    }

    /// Handles a message record: a scan record, a counted skip (`None`), or an error.
    pub(super) fn message(
        &mut self,
        conn: u32,
        time: Option<(u32, u32)>,
        data: &[u8],
        loc: Loc,
        skipped: &mut SkipCounts,
    ) -> Result<Option<ScanRecord>, ReadError> {
        if !self.connections.contains_key(&conn) {
            self.declare_from_index(conn, true);
        }
        let Some(connection) = self.connections.get(&conn) else {
            skipped.add(SKIP_UNKNOWN_CONNECTION);
            return Ok(None);
        };
        let Some(kind) = connection.scan_type() else {
            skipped.add(SKIP_OTHER_TYPE);
            return Ok(None);
        };
        if self.chosen.as_deref() != Some(connection.topic.as_str()) {
            skipped.add(SKIP_OTHER_TOPIC);
            return Ok(None);
        }
        let message = decode_ros1_whole_as(data, kind).map_err(|bad| ReadError::Field {
            pos: loc.pos(&self.name),
            field: format!("{} message{}", connection.topic, loc.context()),
            expected: format!(
                "{} at message byte {}: {}",
                bad.field, bad.offset, bad.expected
            ),
            found: bad.found,
        })?;
        let LaserScanMsg {
            stamp_sec,
            stamp_nanosec,
            angle_min,
            angle_increment,
            range_min,
            range_max,
            ranges,
            intensities,
            echoes_left_out,
            ..
        } = message;
        skipped.add_n(SKIP_LATER_ECHOES, echoes_left_out as u64);
        let (secs, nsecs) = if (stamp_sec, stamp_nanosec) == (0, 0) {
            time.map_or((0, 0), |(s, n)| (i64::from(s), n))
        } else {
            (stamp_sec, stamp_nanosec)
        };
        let widen = |v: Vec<f32>| v.into_iter().map(f64::from).collect::<Vec<f64>>();
        let (ranges, intensities) = (widen(ranges), widen(intensities));
        let intensities = if intensities.len() == ranges.len() && !ranges.is_empty() {
            Some(intensities)
        } else {
            if !intensities.is_empty() {
                skipped.add(SKIP_BAD_INTENSITIES);
            }
            None
        };
        let scan = Scan {
            angle_min: f64::from(angle_min),
            angle_increment: f64::from(angle_increment),
            range_min: f64::from(range_min),
            range_max: f64::from(range_max),
            ranges,
            intensities,
            stamp: Some(secs as f64 + f64::from(nsecs) * 1e-9),
        };
        scan.validate().map_err(|source| ReadError::InvalidScan {
            pos: loc.pos(&self.name),
            source,
        })?;
        Ok(Some(ScanRecord {
            scan,
            pose: None,
            odometry: None,
            line: None,
        }))
    }
}

/// True when a topic given by the user names `topic` (a leading `/` is optional).
pub(super) fn same_topic(given: &str, topic: &str) -> bool {
    given.trim_start_matches('/') == topic.trim_start_matches('/')
}
