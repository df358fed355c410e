//! ROS 1 bags (`.bag`, format versions 2.0 and 1.2, gzipped or not): `sensor_msgs/LaserScan`
//! messages.
//!
//! A bag is `#ROSBAG V2.0\n` and then records, each `header_len: u32, header, data_len: u32,
//! data` (little-endian), the header being `field_len: u32, name=value` fields with an `op`
//! byte:
//!
//! | op | record | what the reader does |
//! |---|---|---|
//! | `0x03` | bag header | skipped |
//! | `0x05` | chunk (`compression` = `none`, `bz2` or `lz4`, `size`) | decompressed, its records read in order |
//! | `0x07` | connection (`conn`, `topic`; data: `type`, `md5sum`, ...) | remembered |
//! | `0x02` | message data (`conn`, `time`) | decoded when its connection is the chosen LaserScan topic |
//! | `0x04` | index data (`ver`, `conn`, `count`) | skipped: `min(12 * count, data_len)` bytes |
//! | `0x06` | chunk info | skipped |
//!
//! Bags of the older version 1.2 (`#ROSRECORD V1.2`, ROS 0.5 to 1.0, 2009-2010) have the same
//! framing without chunks or connection records; the reader takes their records: `0x01`
//! message definition (`topic`, `type`, `md5`, `def`; no data), `0x02` message data (`topic`,
//! `type`, `md5`, `sec`, `nsec`: the record time), `0x03` file header and `0x04` index data
//! (skipped).
//!
//! **Streaming, without the index.** The reader walks the records front to back, one chunk in
//! memory at a time (at most [`BagOptions::max_chunk_bytes`], by default [`MAX_CHUNK_BYTES`],
//! compressed and decompressed), so memory stays
//! flat on long bags, and it reads from any stream (standard input, gzip). It does not walk by
//! the index section or the `index_pos` of the bag header, which are wrong in some real bags:
//! the `demo.bag` of the CCNY `scan_tools` declares index data records of `20 * count` bytes
//! while `12 * count` were written, so the reader skips an index data record by its `count`
//! (12 bytes per entry), falling back to `data_len` when that is smaller. Of the index
//! section, a bag that is a regular file (not gzipped; not a pipe) gives only its connection
//! records, read first, for the connections whose own record was in a chunk that could not be
//! read (`index.rs`): so a damaged first chunk loses its own messages, not every later
//! chunk's. From a stream, the messages of such connections are counted
//! ([`SKIP_UNKNOWN_CONNECTION`]).
//!
//! **Which topic.** Messages of every connection whose `type` is `sensor_msgs/LaserScan` or
//! `sensor_msgs/MultiEchoLaserScan` on the chosen topic become records, in file order: the
//! topic given ([`crate::ReadOptions::topic`], with or without its leading `/`), or else the
//! topic of the first connection of either type in the file. Messages of other types and LaserScans on other
//! topics are counted as skipped ([`SKIP_OTHER_TYPE`], [`SKIP_OTHER_TOPIC`]). A bag without a
//! LaserScan connection on the chosen topic ends with an error listing its connections.
//!
//! **LaserScan.** The ROS 1 serialization of `sensor_msgs/LaserScan`: `header` (`seq: u32`,
//! `stamp: u32 secs, u32 nsecs`, `frame_id: string`), `angle_min`, `angle_max`,
//! `angle_increment`, `time_increment`, `scan_time`, `range_min`, `range_max` (`f32`),
//! `ranges: f32[]`, `intensities: f32[]` (arrays and strings are a `u32` length and the items),
//! decoded by [`crate::ros::decode_ros1_whole`] (the decoder of the MCAP reader too). A
//! `MultiEchoLaserScan` gives each beam's first echo (NaN for a beam without one), the
//! echoes after it counted ([`SKIP_LATER_ECHOES`]; the scan is kept).
//! The scan keeps `angle_min`, `angle_increment`, `range_min`, `range_max` and the ranges
//! (widened to `f64`; NaN and infinities kept, they are no returns); `angle_max` is not
//! checked (drivers disagree on it by a beam). Intensities are kept when there is one per
//! range; a non-empty array of another length is dropped and counted
//! ([`SKIP_BAD_INTENSITIES`]). `scan.stamp` is the header stamp in seconds, or the message
//! record's `time` when the header stamp is zero. Bags carry no pose for a scan: `pose` is
//! `None`.
//!
//! **Bad input.** Errors name the file and the byte offset: of the record in the file, or for
//! a record inside a compressed chunk the chunk's offset and the record's offset in the
//! decompressed chunk. A message that does not decode is an error and the reader goes on with
//! the next message; a chunk that does not decompress, or whose records are broken, is an error
//! and the reader goes on with the next chunk. A record that runs past the end of the file (a
//! truncated bag; an uncompressed chunk cut short gives its complete records first), a top-level record header that does not parse, a missing or wrong
//! `#ROSBAG V2.0` (or `#ROSRECORD V1.2`) line and a read failure end the reader with an
//! error, after every scan before them.

mod chunk;
mod index;
mod records;
mod state;
mod v12;

use std::collections::{BTreeMap, HashMap};
use std::io;

use crate::error::{ReadError, SourcePos};
use crate::format::Format;
use crate::reader::{Input, ScanReader, ScanSource, open_input};
use crate::record::ScanRecord;
use crate::skip::SkipCounts;
use chunk::Chunk;
use records::{Bad, Counted, Loc, RecordHeader, op};
use state::State;

/// The first line of every bag of format version 2.0.
pub const MAGIC: &[u8; 13] = b"#ROSBAG V2.0\n";
/// The first line of every bag of format version 1.2.
pub const MAGIC_V12: &[u8; 16] = b"#ROSRECORD V1.2\n";
/// The connection `type` of the messages read.
pub const LASER_SCAN_TYPE: &str = "sensor_msgs/LaserScan";
/// The connection `type` of the multi-echo messages read (each beam's first echo).
pub const MULTI_ECHO_TYPE: &str = "sensor_msgs/MultiEchoLaserScan";
/// Default largest chunk read, compressed or decompressed, bytes (also the largest message
/// outside a chunk). ROS writes chunks of 768 KiB by default.
pub const MAX_CHUNK_BYTES: u64 = 256 << 20;
/// Largest record header or connection record data read, bytes.
pub const MAX_HEADER_BYTES: u64 = 16 << 20;

/// Skip reason for LaserScans on topics other than the one read.
pub const SKIP_OTHER_TOPIC: &str = "LaserScan on another topic";
/// Skip reason for messages whose connection is not a LaserScan.
pub const SKIP_OTHER_TYPE: &str = "message of another type";
/// Skip reason for messages on a connection never declared.
pub const SKIP_UNKNOWN_CONNECTION: &str = "message on an undeclared connection";
/// Skip reason for records of an op code the format does not define (or that do not belong
/// where they are, e.g. a chunk inside a chunk).
pub const SKIP_UNKNOWN_RECORD: &str = "record of an unknown or misplaced op";
/// Counted (the scan itself is kept) per echo after a beam's first in a
/// `MultiEchoLaserScan`'s ranges and intensities: the first echo is read.
pub const SKIP_LATER_ECHOES: &str = "later echoes left out (first echo read)";
/// Counted (the scan itself is kept) when a LaserScan's intensities are not one per range.
pub const SKIP_BAD_INTENSITIES: &str = "intensities dropped (not one per range)";

/// How to read a bag.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BagOptions {
    /// The topic to read; `None` reads the topic of the first LaserScan connection.
    pub topic: Option<String>,
    /// Largest chunk (compressed or decompressed) or message read, bytes; a larger one is an
    /// error and is skipped. Default [`MAX_CHUNK_BYTES`].
    pub max_chunk_bytes: u64,
}

impl Default for BagOptions {
    fn default() -> Self {
        Self {
            topic: None,
            max_chunk_bytes: MAX_CHUNK_BYTES,
        }
    }
}

/// Reads the LaserScans of a bag from any buffered reader (gzip recognised by its magic
/// bytes), with these options. [`crate::from_reader_with`] does the same with the default
/// chunk limit.
///
/// # Errors
/// [`ReadError::Open`] when the first bytes cannot be read; everything else comes out of
/// the reader as error items.
pub fn from_reader(
    name: &str,
    reader: impl std::io::BufRead + Send + 'static,
    options: &BagOptions,
) -> Result<ScanReader, ReadError> {
    let input = open_input(name, Box::new(reader), false)?;
    let source = BagSource::with_options(name, input, options);
    Ok(ScanReader::from_source(name, Format::Bag, Box::new(source)))
}

/// Reads a ROS 1 bag.
pub(crate) struct BagSource {
    max_chunk_bytes: u64,
    name: String,
    input: Counted,
    chunk: Option<Chunk>,
    state: State,
    started: bool,
    /// No more records: the input ended or an error ended the reader.
    done: bool,
    /// An error ended the reader (no end-of-file checks then).
    failed: bool,
    /// A version 1.2 bag: the connection number given to each topic (version 2.0 bags
    /// number their connections themselves).
    v12: Option<HashMap<Vec<u8>, u32>>,
    finished: bool,
    /// The end of the input inside an uncompressed chunk: the error that ends the reader once
    /// the chunk's complete records are read.
    cut: Option<ReadError>,
    /// Buffers kept between records: a record header, record data (compressed chunks,
    /// connection data, messages outside chunks), and decompressed chunk data.
    header: Vec<u8>,
    raw: Vec<u8>,
    spare: Vec<u8>,
}

impl BagSource {
    pub(crate) fn new(name: &str, input: Input, topic: Option<&str>) -> Self {
        let options = BagOptions {
            topic: topic.map(str::to_owned),
            ..BagOptions::default()
        };
        Self::with_options(name, input, &options)
    }

    /// The source with the connection records of the index section of the bag at `path`
    /// (the file `input` reads) at hand, for connections whose own record was in a chunk
    /// that could not be read.
    pub(crate) fn with_index(mut self, path: &std::path::Path) -> Self {
        self.state.indexed = index::indexed_connections(path);
        self
    }

    fn with_options(name: &str, input: Input, options: &BagOptions) -> Self {
        Self {
            max_chunk_bytes: options.max_chunk_bytes,
            name: name.to_owned(),
            input: Counted { input, pos: 0 },
            chunk: None,
            state: State {
                name: name.to_owned(),
                connections: HashMap::new(),
                requested: options.topic.clone(),
                chosen: None,
                indexed: BTreeMap::new(),
                lost: false,
            },
            started: false,
            done: false,
            failed: false,
            v12: None,
            finished: false,
            cut: None,
            header: Vec::new(),
            raw: Vec::new(),
            spare: Vec::new(),
        }
    }

    fn fail(&mut self, e: ReadError) -> Option<Result<ScanRecord, ReadError>> {
        self.done = true;
        self.failed = true;
        self.chunk = None;
        Some(Err(e))
    }

    fn io_error(&self, source: io::Error) -> ReadError {
        ReadError::Io {
            pos: SourcePos::byte(&self.name, self.input.pos),
            source,
        }
    }

    /// The error of `what` (`wanted` bytes, a size read from a length field, which may be
    /// corrupt) cut short by the end of the input after `got` bytes.
    fn truncated(&self, start: u64, what: &str, wanted: u64, got: u64) -> ReadError {
        self.cut_short(
            start,
            what,
            (wanted, got),
            "a truncated bag or a corrupt length field",
        )
    }

    /// The error of the 4-byte length field `what` cut short by the end of the input after
    /// `got` bytes: surely a truncated bag.
    fn truncated_length(&self, start: u64, what: &str, got: usize) -> ReadError {
        self.cut_short(start, what, (4, got as u64), "a truncated bag")
    }

    /// The error of `what`, `wanted` bytes of which `got` came before the end, for `why`.
    fn cut_short(&self, start: u64, what: &str, (wanted, got): (u64, u64), why: &str) -> ReadError {
        ReadError::Syntax {
            pos: SourcePos::byte(&self.name, start),
            expected: format!("{what} ({wanted} bytes)"),
            found: format!("{got} bytes before the end of the input ({why})"),
        }
    }

    /// Checks the `#ROSBAG V2.0` (or `#ROSRECORD V1.2`) line.
    fn start(&mut self) -> Result<(), ReadError> {
        let mut magic = [0u8; MAGIC_V12.len()];
        let got = self
            .input
            .read_full(&mut magic[..MAGIC.len()])
            .map_err(|e| self.io_error(e))?;
        if got == MAGIC.len() && magic[..got] == MAGIC[..] {
            return Ok(());
        }
        let mut got = got;
        if magic[..got] == MAGIC_V12[..MAGIC.len()] {
            got += self
                .input
                .read_full(&mut magic[MAGIC.len()..])
                .map_err(|e| self.io_error(e))?;
            if magic[..got] == MAGIC_V12[..] {
                self.v12 = Some(HashMap::new());
                return Ok(());
            }
        }
        let head = &magic[..got];
        let found = if got == 0 {
            "an empty input".to_owned()
        } else if head.starts_with(b"#ROSBAG V") || head.starts_with(b"#ROSRECORD V") {
            let line = head.split(|b| *b == b'\n').next().unwrap_or(head);
            format!(
                "`{}` (versions 2.0 and 1.2 are read)",
                String::from_utf8_lossy(line)
            )
        } else {
            format!("`{}`", String::from_utf8_lossy(head).escape_debug())
        };
        Err(ReadError::Syntax {
            pos: SourcePos::byte(&self.name, 0),
            expected: "`#ROSBAG V2.0` or `#ROSRECORD V1.2` (a ROS 1 bag)".to_owned(),
            found,
        })
    }

    /// Reads and handles one top-level record. `Ok(None)` at the end of the input.
    fn top_record(
        &mut self,
        skipped: &mut SkipCounts,
    ) -> Result<Option<Result<ScanRecord, ReadError>>, ReadError> {
        let start = self.input.pos;
        let mut len = [0u8; 4];
        let got = self
            .input
            .read_full(&mut len)
            .map_err(|e| self.io_error(e))?;
        if got == 0 {
            self.done = true;
            return Ok(None);
        }
        if got < 4 {
            return Err(self.truncated_length(start, "a record header length", got));
        }
        let header_len = u64::from(u32::from_le_bytes(len));
        if header_len > MAX_HEADER_BYTES {
            return Err(ReadError::corrupt_length(
                SourcePos::byte(&self.name, start),
                &format!("a record header of at most {MAX_HEADER_BYTES} bytes"),
                &format!("a header length of {header_len} bytes (a corrupt record)"),
            ));
        }
        let mut header = std::mem::take(&mut self.header);
        let got = self
            .input
            .read_vec(header_len, &mut header)
            .map_err(|e| self.io_error(e))?;
        if got < header_len {
            self.header = header;
            return Err(self.truncated(start, "a record header", header_len, got));
        }
        let result = self.handle_top(start, &header, skipped);
        self.header = header;
        result
    }

    fn handle_top(
        &mut self,
        start: u64,
        raw: &[u8],
        skipped: &mut SkipCounts,
    ) -> Result<Option<Result<ScanRecord, ReadError>>, ReadError> {
        let header_len = raw.len() as u64;
        let mut len = [0u8; 4];
        let got = self
            .input
            .read_full(&mut len)
            .map_err(|e| self.io_error(e))?;
        if got < 4 {
            return Err(self.truncated_length(start, "a record data length", got));
        }
        let data_len = u64::from(u32::from_le_bytes(len));
        let data_start = start + 4 + header_len + 4;
        let loc = Loc::File(start);
        let parsed = RecordHeader::parse(raw).and_then(|h| h.op().map(|op| (h, op)));
        let (header, op) = match parsed {
            Ok(parsed) => parsed,
            Err(bad) => {
                // The lengths still frame the record: skip it and go on.
                self.skip_data(start, data_len, "record data")?;
                return Ok(Some(Err(loc.error(&self.name, bad))));
            }
        };
        if self.v12.is_some() {
            return self.handle_v12(start, &header, op, (data_start, data_len), skipped);
        }
        match op {
            op::CHUNK => {
                let compression = header.compression.map(<[u8]>::to_vec);
                let size = header.size;
                self.read_chunk(start, data_start, data_len, compression, size)
            }
            op::INDEX_DATA => {
                let by_count = match (header.ver, header.count) {
                    (Some(1), Some(count)) => u64::from(count) * 12,
                    _ => data_len,
                };
                self.skip_data(start, by_count.min(data_len), "index data")?;
                Ok(None)
            }
            op::CONNECTION => self.top_connection(start, &header, data_len),
            op::MESSAGE_DATA => {
                let conn = header.conn();
                let time = header.time;
                self.top_message(start, (conn, time), (data_start, data_len), skipped)
            }
            op::BAG_HEADER | op::CHUNK_INFO => {
                self.skip_data(start, data_len, "record data")?;
                Ok(None)
            }
            _ => {
                self.skip_data(start, data_len, "record data")?;
                skipped.add(SKIP_UNKNOWN_RECORD);
                Ok(None)
            }
        }
    }

    /// A connection record outside a chunk: its data read and the connection kept.
    fn top_connection(
        &mut self,
        start: u64,
        header: &RecordHeader<'_>,
        data_len: u64,
    ) -> Result<Option<Result<ScanRecord, ReadError>>, ReadError> {
        let loc = Loc::File(start);
        let conn = header.conn().map_err(|bad| loc.error(&self.name, bad));
        let topic = header.topic.map(<[u8]>::to_vec);
        if data_len > MAX_HEADER_BYTES {
            return self.too_large(
                start,
                data_len,
                MAX_HEADER_BYTES,
                ("connection data", "connection data"),
            );
        }
        let mut data = std::mem::take(&mut self.raw);
        self.read_data(start, data_len, "connection data", &mut data)?;
        let result = conn.and_then(|conn| {
            self.state
                .connection(conn, topic.as_deref(), &data)
                .map_err(|bad| loc.error(&self.name, bad))
        });
        self.raw = data;
        Ok(result.err().map(Err))
    }

    /// A message record outside a chunk, on connection `conn` at record time `time`: its
    /// data read and decoded when it is a scan of the chosen topic.
    fn top_message(
        &mut self,
        start: u64,
        (conn, time): (Result<u32, Bad>, Option<(u32, u32)>),
        (data_start, data_len): (u64, u64),
        skipped: &mut SkipCounts,
    ) -> Result<Option<Result<ScanRecord, ReadError>>, ReadError> {
        let loc = Loc::File(start);
        let max = self.max_chunk_bytes;
        if data_len > max {
            return self.too_large(start, data_len, max, ("message data", "a message"));
        }
        let mut data = std::mem::take(&mut self.raw);
        self.read_data(start, data_len, "message data", &mut data)?;
        let result = conn
            .map_err(|bad| loc.error(&self.name, bad))
            .and_then(|conn| {
                self.state
                    .message(conn, time, &data, Loc::File(data_start), skipped)
            })
            .transpose();
        self.raw = data;
        Ok(result)
    }

    /// Reads `len` bytes of record data into `out`; a short read is an error naming `what`.
    fn read_data(
        &mut self,
        start: u64,
        len: u64,
        what: &str,
        out: &mut Vec<u8>,
    ) -> Result<(), ReadError> {
        let got = self
            .input
            .read_vec(len, out)
            .map_err(|e| self.io_error(e))?;
        if got < len {
            return Err(self.truncated(start, what, len, got));
        }
        Ok(())
    }

    /// Skips `what` (record data) of `len` bytes, more than the `max` allowed for one
    /// `item`: the record is reported as an error and reading goes on after it.
    fn too_large(
        &mut self,
        start: u64,
        len: u64,
        max: u64,
        (what, item): (&str, &str),
    ) -> Result<Option<Result<ScanRecord, ReadError>>, ReadError> {
        self.skip_data(start, len, what)?;
        Ok(Some(Err(Loc::File(start).error(
            &self.name,
            Bad::new(
                format!("{item} of at most {max} bytes"),
                format!("{len} bytes"),
            ),
        ))))
    }

    fn skip_data(&mut self, start: u64, len: u64, what: &str) -> Result<(), ReadError> {
        let got = self.input.skip(len).map_err(|e| self.io_error(e))?;
        if got < len {
            return Err(self.truncated(start, what, len, got));
        }
        Ok(())
    }

    /// At the end of the input: the error of a bag without the chosen LaserScans.
    fn finish(&mut self) -> Option<Result<ScanRecord, ReadError>> {
        if self.finished || self.failed {
            return None;
        }
        self.finished = true;
        if self.state.chosen.is_some() {
            return None;
        }
        let mut seen: Vec<String> = self
            .state
            .connections
            .values()
            .map(|c| format!("{} ({})", c.topic, c.kind))
            .collect();
        seen.sort();
        seen.dedup();
        let total = seen.len();
        seen.truncate(8);
        let mut found = if seen.is_empty() {
            "no connection".to_owned()
        } else {
            format!("connections {}", seen.join(", "))
        };
        if total > seen.len() {
            found.push_str(&format!(" and {} more", total - seen.len()));
        }
        let expected = match &self.state.requested {
            Some(topic) => {
                format!("a {LASER_SCAN_TYPE} or {MULTI_ECHO_TYPE} connection on topic {topic}")
            }
            None => format!("a {LASER_SCAN_TYPE} or {MULTI_ECHO_TYPE} connection"),
        };
        Some(Err(ReadError::Syntax {
            pos: SourcePos::byte(&self.name, self.input.pos),
            expected,
            found,
        }))
    }
}

impl ScanSource for BagSource {
    fn next_record(&mut self, skipped: &mut SkipCounts) -> Option<Result<ScanRecord, ReadError>> {
        let item = self.next_item(skipped);
        if let Some(Err(_)) = &item {
            self.state.lost = true;
        }
        item
    }
}

impl BagSource {
    fn next_item(&mut self, skipped: &mut SkipCounts) -> Option<Result<ScanRecord, ReadError>> {
        if !self.started {
            self.started = true;
            if let Err(e) = self.start() {
                return self.fail(e);
            }
        }
        loop {
            if self.chunk.is_some() {
                if let Some(item) = self.chunk_record(skipped) {
                    return Some(item);
                }
                continue;
            }
            if let Some(cut) = self.cut.take() {
                return self.fail(cut);
            }
            if self.done {
                return self.finish();
            }
            match self.top_record(skipped) {
                Ok(Some(item)) => return Some(item),
                Ok(None) => {}
                Err(e) => return self.fail(e),
            }
        }
    }
}
