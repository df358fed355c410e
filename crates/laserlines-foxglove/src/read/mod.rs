//! Streaming reader of LaserScans out of MCAP files.
//!
//! The reader walks the file's records front to back (magic, then `opcode: u8, length: u64,
//! body` records), reading one record, or one chunk, at a time: memory is bounded by the
//! largest chunk, not by the file. It does not walk by the summary section or the indexes; it
//! stops at the `DataEnd` record (or the footer), and reads of the summary only the
//! `Statistics` record, to count the scans of a skipped chunk ([`SKIP_LOST_SCAN`]), and the
//! `Schema` and `Channel` records: at the end, for the channels the data section never
//! defined, to count what a skipped chunk held; and of a regular file (not gzipped; not a
//! pipe) also first, for the channels whose own definition was in a chunk that could not be
//! read (`definitions.rs`), so that a damaged first chunk loses its own messages, not every
//! later chunk's.
//!
//! Messages come out in file order. Six LaserScan encodings are read:
//!
//! | schema name | message encoding | decoder |
//! |---|---|---|
//! | `sensor_msgs/msg/LaserScan` | `cdr` | [`crate::ros::decode_cdr`] (ROS 2) |
//! | `sensor_msgs/LaserScan` | `ros1` | [`crate::ros::decode_ros1`] (ROS 1) |
//! | `sensor_msgs/msg/MultiEchoLaserScan` | `cdr` | [`crate::ros::decode_cdr_as`]: each beam's first echo |
//! | `sensor_msgs/MultiEchoLaserScan` | `ros1` | [`crate::ros::decode_ros1_as`]: each beam's first echo |
//! | `foxglove.LaserScan` | `protobuf` | `prost` ([`crate::proto`]) |
//! | `foxglove.LaserScan` | `json` | [`crate::json`] |
//!
//! One topic is read: [`McapReadOptions::topic`], or else the first topic whose channel
//! carries a LaserScan. LaserScans on other topics are counted as skipped. The stamp is the
//! message header's (`foxglove.LaserScan`: its `timestamp`), or the record's log time when the
//! header stamp is zero. Poses: `foxglove.FrameTransform` messages (and each transform of a
//! `foxglove.FrameTransforms`, in protobuf or JSON) give the pose and the odometry of the
//! scans that follow (REP 105 frames): `odom -> base_link` is the odometry; any other
//! `X -> base_link` is the pose, and so is `X -> odom` followed by the odometry (as
//! laserlines writes them on `/tf`).
//!
//! Bad input gives errors naming the file and the byte offset of the record (for a record
//! inside a compressed chunk: the chunk's offset, and the record's offset in the decompressed
//! chunk). After a bad message, a bad record or a bad chunk (wrong CRC, failed decompression,
//! unknown compression) the reader goes on with the next one; a record that runs past the end
//! of the file, a length over [`McapReadOptions::max_record_bytes`] or a bad magic ends it. A
//! file that ends without its `DataEnd` or footer record (a truncated file) ends with an error
//! after every scan it holds.

use std::collections::{HashMap, VecDeque};
use std::io::{self, BufRead, BufReader, Read};
use std::path::Path;

use laserlines_io::{
    Format, Input, Pose2, ReadError, ScanReader, ScanRecord, ScanSource, SkipCounts, SourcePos,
};
use mcap::records::op;

mod channels;
mod chunk;
pub mod db3;
mod definitions;
mod dir;
mod records;
mod tail;

pub use tail::{SKIP_CUT_SUMMARY, SKIP_LOST_SCAN};

use channels::ChannelInfo;
use db3::Db3FilesSource;
use definitions::SummaryDefinitions;
use dir::{McapFilesSource, Storage, bag_files, open_file};
use records::{Loc, hex, opcode_name, read_full};

/// The eight bytes every MCAP file starts (and ends) with.
pub const MAGIC: [u8; 8] = [0x89, b'M', b'C', b'A', b'P', 0x30, b'\r', b'\n'];

/// Skip reason for LaserScans on topics other than the one read.
pub const SKIP_OTHER_TOPIC: &str = "LaserScan on another topic";
/// Counted (the scan is kept) per echo after a beam's first in a `MultiEchoLaserScan`.
pub const SKIP_LATER_ECHOES: &str = laserlines_io::bag::SKIP_LATER_ECHOES;
/// Skip reason for `foxglove.FrameTransform(s)` messages that do not decode.
pub const SKIP_BAD_TRANSFORM: &str = "malformed FrameTransform";
/// Skip reason for messages on a channel that was never declared.
pub const SKIP_UNKNOWN_CHANNEL: &str = "message on an undeclared channel";
/// Skip reason for a whole record longer than [`McapReadOptions::max_record_bytes`], passed
/// over unread.
pub const SKIP_OVERSIZED: &str = "record over the reader's size limit (passed over unread)";

/// How to read an MCAP file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct McapReadOptions {
    /// The topic to read; `None` reads the first topic that carries LaserScans.
    pub topic: Option<String>,
    /// Largest record, and largest decompressed chunk, accepted, in bytes (default 1 GiB). A
    /// larger declared length is an error, so a corrupt length cannot exhaust memory.
    pub max_record_bytes: u64,
    /// Read a file (not a directory) as a ROS 2 bag in sqlite3 storage whatever its name
    /// (`--format db3`); otherwise only a `.db3` file is.
    pub db3: bool,
}

impl Default for McapReadOptions {
    fn default() -> Self {
        Self {
            topic: None,
            max_record_bytes: 1 << 30,
            db3: false,
        }
    }
}

impl McapReadOptions {
    /// Options reading `topic` (or the first LaserScan topic when `None`).
    #[must_use]
    pub fn topic(topic: Option<&str>) -> Self {
        Self {
            topic: topic.map(str::to_owned),
            ..Self::default()
        }
    }
}

/// How a channel's LaserScans are encoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScanEncoding {
    /// ROS 2 `sensor_msgs/msg/LaserScan` in CDR.
    Ros2Cdr,
    /// ROS 1 `sensor_msgs/LaserScan` (ROS serialization).
    Ros1,
    /// ROS 2 `sensor_msgs/msg/MultiEchoLaserScan` in CDR: each beam's first echo.
    Ros2CdrMultiEcho,
    /// ROS 1 `sensor_msgs/MultiEchoLaserScan`: each beam's first echo.
    Ros1MultiEcho,
    /// `foxglove.LaserScan` in protobuf.
    FoxgloveProtobuf,
    /// `foxglove.LaserScan` in JSON ([`crate::json`]).
    FoxgloveJson,
}

/// The [`ScanSource`] of MCAP files: yields the LaserScans of one topic, in file order.
pub struct McapScanSource {
    name: String,
    input: Input,
    options: McapReadOptions,
    /// Offset of the next top-level record.
    pos: u64,
    started: bool,
    done: bool,
    /// Saw `DataEnd` or the footer.
    ended_properly: bool,
    schemas: HashMap<u16, (String, String)>,
    channels: HashMap<u16, ChannelInfo>,
    /// The topic being read, once known.
    topic: Option<String>,
    /// Latest pose from `/tf` (`X -> base_link`, or `X -> odom -> base_link`).
    pose: Option<Pose2>,
    /// Latest odometry from `/tf` (`odom -> base_link`).
    odometry: Option<Pose2>,
    /// Latest `X -> odom` from `/tf`.
    world_from_odom: Option<Pose2>,
    pending: VecDeque<Result<ScanRecord, ReadError>>,
    /// Messages met per channel id, to compare with the file's `Statistics` record.
    seen: HashMap<u16, u64>,
    /// The summary's definitions, for channels whose own were in a chunk that could not be
    /// read (a file on disk only).
    summary: SummaryDefinitions,
    /// A record or chunk could not be read (an error was handed out): definitions may have
    /// been lost.
    lost: bool,
    body: Vec<u8>,
    chunk: Vec<u8>,
}

impl std::fmt::Debug for McapScanSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("McapScanSource")
            .field("name", &self.name)
            .field("pos", &self.pos)
            .field("topic", &self.topic)
            .finish_non_exhaustive()
    }
}

impl McapScanSource {
    /// A source reading `input`, named `name` in messages.
    #[must_use]
    pub fn new(name: &str, input: Input, options: McapReadOptions) -> Self {
        Self {
            name: name.to_owned(),
            input,
            topic: options.topic.clone(),
            options,
            pos: 0,
            started: false,
            done: false,
            ended_properly: false,
            schemas: HashMap::new(),
            channels: HashMap::new(),
            pose: None,
            odometry: None,
            world_from_odom: None,
            pending: VecDeque::new(),
            seen: HashMap::new(),
            summary: SummaryDefinitions::default(),
            lost: false,
            body: Vec::new(),
            chunk: Vec::new(),
        }
    }

    fn at(&self, byte: u64) -> SourcePos {
        SourcePos::byte(&self.name, byte)
    }

    fn syntax(
        &self,
        byte: u64,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> ReadError {
        ReadError::Syntax {
            pos: self.at(byte),
            expected: expected.into(),
            found: found.into(),
        }
    }

    /// Stops reading after a fatal error.
    fn fail(&mut self, e: ReadError) {
        self.pending.push_back(Err(e));
        self.done = true;
    }

    fn io_error(&mut self, byte: u64, source: io::Error) {
        let e = ReadError::Io {
            pos: self.at(byte),
            source,
        };
        self.fail(e);
    }

    /// Reads the magic; false (with the error queued) when it is wrong.
    fn start(&mut self) -> bool {
        self.started = true;
        let mut magic = [0u8; 8];
        let got = match read_full(&mut self.input, &mut magic) {
            Ok(n) => n,
            Err(e) => {
                self.io_error(0, e);
                return false;
            }
        };
        self.pos = got as u64;
        if got < magic.len() || magic != MAGIC {
            let found = if got == 0 {
                "an empty file".to_owned()
            } else {
                hex(&magic[..got])
            };
            let e = self.syntax(0, format!("the MCAP magic {}", hex(&MAGIC)), found);
            self.fail(e);
            return false;
        }
        true
    }

    /// Reads and handles one top-level record.
    fn advance(&mut self, skipped: &mut SkipCounts) {
        if !self.started && !self.start() {
            return;
        }
        let at = self.pos;
        let mut head = [0u8; 9];
        let got = match read_full(&mut self.input, &mut head) {
            Ok(n) => n,
            Err(e) => return self.io_error(at, e),
        };
        if got == 0 {
            self.finish_input(at);
            return;
        }
        if got < head.len() {
            let e = self.syntax(
                at,
                "a record header (opcode and length, 9 bytes)",
                format!("the end of the file after {got} bytes: the file is truncated"),
            );
            return self.fail(e);
        }
        let opcode = head[0];
        let mut len_bytes = [0u8; 8];
        len_bytes.copy_from_slice(&head[1..]);
        let len = u64::from_le_bytes(len_bytes);
        if len > self.options.max_record_bytes {
            let unfinished = opcode == op::CHUNK && len == u64::MAX;
            let expected = format!(
                "a record of at most {} bytes",
                self.options.max_record_bytes
            );
            let found = if unfinished {
                // What a writer leaves in the header of a chunk it has not closed.
                format!(
                    "a {} record (opcode 0x{opcode:02x}) whose length was never written \
                         (0xffffffffffffffff): the recording was cut off while it was being \
                         written, before it was finished",
                    opcode_name(opcode)
                )
            } else {
                format!(
                    "a {} record (opcode 0x{opcode:02x}) of {len} bytes",
                    opcode_name(opcode)
                )
            };
            // An unfinished chunk ends a recording that was cut off: nothing follows it.
            if unfinished {
                let e = self.syntax(at, expected, found);
                return self.fail(e);
            }
            return self.pass_over(at, len, (&expected, &found), skipped);
        }
        let mut body = std::mem::take(&mut self.body);
        body.clear();
        let read = (&mut self.input).take(len).read_to_end(&mut body);
        match read {
            Err(e) => {
                self.body = body;
                return self.io_error(at, e);
            }
            Ok(n) if (n as u64) < len => {
                self.body = body;
                let e = self.syntax(
                    at,
                    format!(
                        "a {} record (opcode 0x{opcode:02x}) of {len} bytes",
                        opcode_name(opcode)
                    ),
                    format!("the end of the file after {n} bytes: the file is truncated"),
                );
                return self.fail(e);
            }
            Ok(_) => {}
        }
        self.pos = at + 9 + len;
        match opcode {
            op::CHUNK => self.handle_chunk(at, &body, skipped),
            op::DATA_END => {
                self.ended_properly = true;
                self.skim_summary(skipped);
            }
            op::FOOTER => {
                self.ended_properly = true;
                self.finish_input(self.pos);
            }
            _ => self.handle_record(opcode, &body, Loc::File(at), skipped),
        }
        self.body = body;
    }

    /// A record at `at` longer than the reader takes (`what`: what it may be, what it is):
    /// passed over unread and counted ([`SKIP_OVERSIZED`]) when the file holds it; when the
    /// file ends first its length is corrupt, which hides where the next record starts: a
    /// failed read, which no skip may pass over in silence.
    fn pass_over(&mut self, at: u64, len: u64, what: (&str, &str), skipped: &mut SkipCounts) {
        let mut rest = (&mut self.input).take(len);
        match io::copy(&mut rest, &mut io::sink()) {
            Err(e) => self.io_error(at, e),
            Ok(n) if n < len => {
                let found = format!("{}, and the file ends {n} bytes after its header", what.1);
                let e = ReadError::corrupt_length(self.at(at), what.0, &found);
                self.fail(e);
            }
            Ok(_) => {
                skipped.add(SKIP_OVERSIZED);
                self.pos = at + 9 + len;
            }
        }
    }

    /// Handles a schema, channel or message record (top-level or inside a chunk); other
    /// records are of no interest.
    fn handle_record(&mut self, opcode: u8, body: &[u8], loc: Loc, skipped: &mut SkipCounts) {
        let result = match opcode {
            op::SCHEMA => self.handle_schema(body),
            op::CHANNEL => {
                if self.lost
                    && let Some(id) = records::u16_at(body, 0)
                {
                    self.define_from_summary(id, false);
                }
                self.handle_channel(body, loc)
            }
            op::MESSAGE => self.handle_message(body, loc, skipped),
            _ => Ok(()),
        };
        if let Err(found) = result {
            let e = self.syntax(
                loc.byte(),
                format!(
                    "a well-formed {} record{}",
                    opcode_name(opcode),
                    loc.context()
                ),
                found,
            );
            self.pending.push_back(Err(e));
        }
    }

    /// End of the records: queue the errors of a truncated file and of a topic never found.
    fn finish_input(&mut self, at: u64) {
        if !self.ended_properly {
            let e = self.syntax(
                at,
                "a record, or the DataEnd and Footer records that end an MCAP file",
                "the end of the file: the file is truncated",
            );
            self.pending.push_back(Err(e));
        }
        let found_topic = self
            .topic
            .as_ref()
            .is_some_and(|t| self.channels.values().any(|c| &c.topic == t));
        if !found_topic {
            let mut seen: Vec<String> = self
                .channels
                .values()
                .map(|c| {
                    if c.schema.is_empty() {
                        format!("{} ({})", c.topic, c.encoding)
                    } else {
                        format!("{} ({})", c.topic, c.schema)
                    }
                })
                .collect();
            seen.sort();
            seen.dedup();
            let shown = if seen.is_empty() {
                "no channels".to_owned()
            } else if seen.len() > 10 {
                format!(
                    "channels {}, ... ({} in all)",
                    seen[..10].join(", "),
                    seen.len()
                )
            } else {
                format!("channels {}", seen.join(", "))
            };
            let expected = match &self.options.topic {
                Some(t) => format!("a channel on topic {t}"),
                None => format!("a LaserScan channel ({})", crate::message::SCAN_ENCODINGS),
            };
            let e = self.syntax(at, expected, shown);
            self.pending.push_back(Err(e));
        }
        self.done = true;
    }
}

impl ScanSource for McapScanSource {
    fn next_record(&mut self, skipped: &mut SkipCounts) -> Option<Result<ScanRecord, ReadError>> {
        loop {
            if let Some(item) = self.pending.pop_front() {
                self.lost |= item.is_err();
                return Some(item);
            }
            if self.done {
                return None;
            }
            self.advance(skipped);
        }
    }
}

/// Opens an MCAP file (gzipped or not; `-` reads standard input) or a ROS 2 bag as a
/// streaming [`ScanReader`] of the LaserScans of one topic.
///
/// A directory is read as a ROS 2 bag: its `.mcap` files (MCAP storage) or its `.db3` files
/// (sqlite3 storage, [`db3`]) one after the other, in name order (`bag_0`, `bag_1`, ...,
/// `bag_10`), on the topic the first file settles. A file whose name ends in `.db3` is read
/// as one file of a bag in sqlite3 storage.
///
/// # Errors
/// [`ReadError::Open`] when the file cannot be opened, or the directory cannot be listed or
/// holds no `.mcap` or `.db3` file. Everything else (a bad magic, a missing topic, corrupt
/// records) comes out of the reader as error items.
pub fn open(path: &Path, options: &McapReadOptions) -> Result<ScanReader, ReadError> {
    let name = path.display().to_string();
    if path == Path::new("-") {
        return from_reader(&name, BufReader::new(io::stdin()), options);
    }
    let db3 = options.db3 || Format::from_path(path) == Some(Format::Db3);
    let (storage, files) = if path.is_dir() {
        bag_files(path)?
    } else if db3 {
        std::fs::metadata(path).map_err(|source| ReadError::Open {
            file: name.clone(),
            source,
        })?;
        (Storage::Sqlite, vec![path.to_path_buf()])
    } else {
        let source = open_file(path, options)?;
        return Ok(ScanReader::from_source(
            &name,
            Format::Mcap,
            Box::new(source),
        ));
    };
    let (format, source): (Format, Box<dyn ScanSource>) = match storage {
        Storage::Mcap => (
            Format::Mcap,
            Box::new(McapFilesSource {
                files: files.into(),
                current: None,
                options: options.clone(),
            }),
        ),
        Storage::Sqlite => (
            Format::Db3,
            Box::new(Db3FilesSource::new(files, options.topic.as_deref())),
        ),
    };
    Ok(ScanReader::from_source(&name, format, source))
}

/// Reads MCAP from any buffered reader; `name` is used in messages. Gzip input is
/// recognised by its magic bytes and decompressed.
///
/// # Errors
/// [`ReadError::Open`] when the first bytes cannot be read.
pub fn from_reader(
    name: &str,
    reader: impl BufRead + Send + 'static,
    options: &McapReadOptions,
) -> Result<ScanReader, ReadError> {
    let input = laserlines_io::open_input(name, Box::new(reader), false)?;
    Ok(reader_for(name, input, options))
}

fn reader_for(name: &str, input: Input, options: &McapReadOptions) -> ScanReader {
    let source = McapScanSource::new(name, input, options.clone());
    ScanReader::from_source(name, Format::Mcap, Box::new(source))
}

#[cfg(test)]
mod tests;
