//! ROS 1 bags (`.bag`, format version 2.0, gzipped or not): `sensor_msgs/LaserScan`
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
//! **Streaming, without the index.** The reader walks the records front to back, one chunk in
//! memory at a time (at most [`BagOptions::max_chunk_bytes`], by default [`MAX_CHUNK_BYTES`],
//! compressed and decompressed), so memory stays
//! flat on long bags, and it reads from any stream (standard input, gzip). It never uses the
//! index section or the `index_pos` of the bag header, which are wrong in some real bags: the
//! `demo.bag` of the CCNY `scan_tools` declares index data records of `20 * count` bytes while
//! `12 * count` were written, so the reader skips an index data record by its `count`
//! (12 bytes per entry), falling back to `data_len` when that is smaller.
//!
//! **Which topic.** Messages of every connection whose `type` is `sensor_msgs/LaserScan` on the
//! chosen topic become records, in file order: the topic given
//! ([`crate::ReadOptions::topic`], with or without its leading `/`), or else the topic of the
//! first LaserScan connection in the file. Messages of other types and LaserScans on other
//! topics are counted as skipped ([`SKIP_OTHER_TYPE`], [`SKIP_OTHER_TOPIC`]). A bag without a
//! LaserScan connection on the chosen topic ends with an error listing its connections.
//!
//! **LaserScan.** The ROS 1 serialization of `sensor_msgs/LaserScan`: `header` (`seq: u32`,
//! `stamp: u32 secs, u32 nsecs`, `frame_id: string`), `angle_min`, `angle_max`,
//! `angle_increment`, `time_increment`, `scan_time`, `range_min`, `range_max` (`f32`),
//! `ranges: f32[]`, `intensities: f32[]` (arrays and strings are a `u32` length and the items),
//! decoded by [`crate::ros::decode_ros1_whole`] (the decoder of the MCAP reader too).
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
//! truncated bag), a top-level record header that does not parse, a missing or wrong
//! `#ROSBAG V2.0` line and a read failure end the reader with an error, after every scan
//! before them.

use std::collections::HashMap;
use std::io::{self, Read};

use laserlines::Scan;

use crate::error::{ReadError, SourcePos};
use crate::format::Format;
use crate::reader::{Input, ScanReader, ScanSource, open_input};
use crate::record::ScanRecord;
use crate::ros::{LaserScanMsg, decode_ros1_whole};
use crate::skip::SkipCounts;

/// The first line of every bag of format version 2.0.
pub const MAGIC: &[u8; 13] = b"#ROSBAG V2.0\n";
/// The connection `type` of the messages read.
pub const LASER_SCAN_TYPE: &str = "sensor_msgs/LaserScan";
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

/// Record op codes.
mod op {
    pub const MESSAGE_DATA: u8 = 0x02;
    pub const BAG_HEADER: u8 = 0x03;
    pub const INDEX_DATA: u8 = 0x04;
    pub const CHUNK: u8 = 0x05;
    pub const CHUNK_INFO: u8 = 0x06;
    pub const CONNECTION: u8 = 0x07;
}

/// What was expected and what was found, for an error message.
struct Bad {
    expected: String,
    found: String,
}

impl Bad {
    fn new(expected: impl Into<String>, found: impl Into<String>) -> Self {
        Self {
            expected: expected.into(),
            found: found.into(),
        }
    }
}

/// Calls `f` with the name and value of every `field_len: u32, name=value` field of `raw`.
fn for_each_field<'a>(
    raw: &'a [u8],
    mut f: impl FnMut(&'a [u8], &'a [u8]) -> Result<(), Bad>,
) -> Result<(), Bad> {
    let mut at = 0usize;
    while at < raw.len() {
        let rest = &raw[at..];
        let Some(len) = read_u32(rest, 0) else {
            return Err(Bad::new(
                format!("a field length (4 bytes) at header byte {at}"),
                format!("{} bytes", rest.len()),
            ));
        };
        let len = len as usize;
        let Some(field) = 4usize.checked_add(len).and_then(|end| rest.get(4..end)) else {
            return Err(Bad::new(
                format!("a field of {len} bytes at header byte {at}"),
                format!("{} bytes left in the header", rest.len() - 4),
            ));
        };
        let Some(eq) = field.iter().position(|b| *b == b'=') else {
            return Err(Bad::new(
                format!("a `name=value` field at header byte {at}"),
                "no `=`",
            ));
        };
        f(&field[..eq], &field[eq + 1..])?;
        at += 4 + len;
    }
    Ok(())
}

fn read_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let b = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// The fields of a record header this reader uses.
#[derive(Default)]
struct RecordHeader<'a> {
    op: Option<u8>,
    conn: Option<u32>,
    time: Option<(u32, u32)>,
    topic: Option<&'a [u8]>,
    compression: Option<&'a [u8]>,
    size: Option<u32>,
    ver: Option<u32>,
    count: Option<u32>,
}

impl<'a> RecordHeader<'a> {
    fn parse(raw: &'a [u8]) -> Result<Self, Bad> {
        let mut h = Self::default();
        for_each_field(raw, |name, value| {
            let u32_field = |v: &[u8]| -> Result<u32, Bad> {
                read_u32(v, 0).filter(|_| v.len() == 4).ok_or_else(|| {
                    Bad::new(
                        format!("a 4-byte `{}` field", String::from_utf8_lossy(name)),
                        format!("{} bytes", v.len()),
                    )
                })
            };
            match name {
                b"op" => match value {
                    [op] => h.op = Some(*op),
                    _ => {
                        return Err(Bad::new(
                            "a 1-byte `op` field",
                            format!("{} bytes", value.len()),
                        ));
                    }
                },
                b"conn" => h.conn = Some(u32_field(value)?),
                b"time" => {
                    if value.len() != 8 {
                        return Err(Bad::new(
                            "an 8-byte `time` field",
                            format!("{} bytes", value.len()),
                        ));
                    }
                    let secs = read_u32(value, 0).unwrap_or(0);
                    let nsecs = read_u32(value, 4).unwrap_or(0);
                    h.time = Some((secs, nsecs));
                }
                b"topic" => h.topic = Some(value),
                b"compression" => h.compression = Some(value),
                b"size" => h.size = Some(u32_field(value)?),
                b"ver" => h.ver = Some(u32_field(value)?),
                b"count" => h.count = Some(u32_field(value)?),
                _ => {}
            }
            Ok(())
        })?;
        Ok(h)
    }

    fn op(&self) -> Result<u8, Bad> {
        self.op
            .ok_or_else(|| Bad::new("an `op` field in the record header", "none"))
    }

    fn conn(&self) -> Result<u32, Bad> {
        self.conn
            .ok_or_else(|| Bad::new("a `conn` field in the record header", "none"))
    }
}

/// What a connection carries.
#[derive(Debug, Clone)]
struct Connection {
    topic: String,
    kind: String,
}

impl Connection {
    fn is_laser_scan(&self) -> bool {
        self.kind == LASER_SCAN_TYPE
    }
}

/// Where a record sits, for errors.
#[derive(Debug, Clone, Copy)]
enum Loc {
    /// At this byte of the file.
    File(u64),
    /// Inside a compressed chunk: the chunk record's byte in the file, the compression and
    /// the offset in the decompressed data.
    Compressed {
        chunk: u64,
        compression: &'static str,
        offset: usize,
    },
}

impl Loc {
    fn pos(self, file: &str) -> SourcePos {
        match self {
            Self::File(at) | Self::Compressed { chunk: at, .. } => SourcePos::byte(file, at),
        }
    }

    /// `""`, or ` (at offset N of the decompressed bz2 chunk)`.
    fn context(self) -> String {
        match self {
            Self::File(_) => String::new(),
            Self::Compressed {
                compression,
                offset,
                ..
            } => format!(" (at offset {offset} of the decompressed {compression} chunk)"),
        }
    }

    fn error(self, file: &str, bad: Bad) -> ReadError {
        ReadError::Syntax {
            pos: self.pos(file),
            expected: format!("{}{}", bad.expected, self.context()),
            found: bad.found,
        }
    }
}

/// One decompressed chunk being read.
struct Chunk {
    data: Vec<u8>,
    /// Offset of the next record in `data`.
    at: usize,
    /// Byte of the chunk record in the file.
    record: u64,
    /// Byte of `data[0]` in the file, for uncompressed chunks.
    data_in_file: Option<u64>,
    compression: &'static str,
}

impl Chunk {
    fn loc(&self, offset: usize) -> Loc {
        match self.data_in_file {
            Some(start) => Loc::File(start + offset as u64),
            None => Loc::Compressed {
                chunk: self.record,
                compression: self.compression,
                offset,
            },
        }
    }
}

/// The input with a count of the bytes consumed.
struct Counted {
    input: Input,
    pos: u64,
}

impl Counted {
    /// Fills `buf` unless the input ends; returns how many bytes were read.
    fn read_full(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let mut got = 0;
        while got < buf.len() {
            match self.input.read(&mut buf[got..]) {
                Ok(0) => break,
                Ok(n) => got += n,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => {
                    self.pos += got as u64;
                    return Err(e);
                }
            }
        }
        self.pos += got as u64;
        Ok(got)
    }

    /// Reads up to `len` bytes into `out` (cleared first), growing it as bytes arrive.
    fn read_vec(&mut self, len: u64, out: &mut Vec<u8>) -> io::Result<u64> {
        out.clear();
        let got = (&mut self.input).take(len).read_to_end(out)? as u64;
        self.pos += got;
        Ok(got)
    }

    /// Skips up to `len` bytes; returns how many were skipped.
    fn skip(&mut self, len: u64) -> io::Result<u64> {
        let got = io::copy(&mut (&mut self.input).take(len), &mut io::sink())?;
        self.pos += got;
        Ok(got)
    }
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
    finished: bool,
    /// Buffers kept between records: a record header, record data (compressed chunks,
    /// connection data, messages outside chunks), and decompressed chunk data.
    header: Vec<u8>,
    raw: Vec<u8>,
    spare: Vec<u8>,
}

/// Connections and the topic choice.
struct State {
    name: String,
    connections: HashMap<u32, Connection>,
    requested: Option<String>,
    chosen: Option<String>,
}

impl BagSource {
    pub(crate) fn new(name: &str, input: Input, topic: Option<&str>) -> Self {
        let options = BagOptions {
            topic: topic.map(str::to_owned),
            ..BagOptions::default()
        };
        Self::with_options(name, input, &options)
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
            },
            started: false,
            done: false,
            failed: false,
            finished: false,
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

    fn truncated(&self, start: u64, what: &str, wanted: u64, got: u64) -> ReadError {
        ReadError::Syntax {
            pos: SourcePos::byte(&self.name, start),
            expected: format!("{what} ({wanted} bytes)"),
            found: format!("{got} bytes before the end of the input (a truncated bag)"),
        }
    }

    /// Checks the `#ROSBAG V2.0` line.
    fn start(&mut self) -> Result<(), ReadError> {
        let mut magic = [0u8; MAGIC.len()];
        let got = self
            .input
            .read_full(&mut magic)
            .map_err(|e| self.io_error(e))?;
        if got == MAGIC.len() && &magic == MAGIC {
            return Ok(());
        }
        let head = &magic[..got];
        let found = if got == 0 {
            "an empty input".to_owned()
        } else if head.starts_with(b"#ROSBAG V") {
            let line = head.split(|b| *b == b'\n').next().unwrap_or(head);
            format!(
                "`{}` (only version 2.0 is read)",
                String::from_utf8_lossy(line)
            )
        } else {
            format!("`{}`", String::from_utf8_lossy(head).escape_debug())
        };
        Err(ReadError::Syntax {
            pos: SourcePos::byte(&self.name, 0),
            expected: "`#ROSBAG V2.0` (a ROS 1 bag)".to_owned(),
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
            return Err(self.truncated(start, "a record header length", 4, got as u64));
        }
        let header_len = u64::from(u32::from_le_bytes(len));
        if header_len > MAX_HEADER_BYTES {
            return Err(ReadError::Syntax {
                pos: SourcePos::byte(&self.name, start),
                expected: format!("a record header of at most {MAX_HEADER_BYTES} bytes"),
                found: format!("a header length of {header_len} bytes (a corrupt record)"),
            });
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
            return Err(self.truncated(start, "a record data length", 4, got as u64));
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
            op::CONNECTION => {
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
            op::MESSAGE_DATA => {
                let max = self.max_chunk_bytes;
                if data_len > max {
                    return self.too_large(start, data_len, max, ("message data", "a message"));
                }
                let mut data = std::mem::take(&mut self.raw);
                self.read_data(start, data_len, "message data", &mut data)?;
                let result = header
                    .conn()
                    .map_err(|bad| loc.error(&self.name, bad))
                    .and_then(|conn| {
                        self.state
                            .message(conn, header.time, &data, Loc::File(data_start), skipped)
                    })
                    .transpose();
                self.raw = data;
                Ok(result)
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

    /// Reads a chunk record's data and decompresses it.
    fn read_chunk(
        &mut self,
        start: u64,
        data_start: u64,
        data_len: u64,
        compression: Option<Vec<u8>>,
        size: Option<u32>,
    ) -> Result<Option<Result<ScanRecord, ReadError>>, ReadError> {
        let loc = Loc::File(start);
        let max = self.max_chunk_bytes;
        let too_big = |what: &str, len: u64| {
            Bad::new(
                format!("a chunk of at most {max} bytes"),
                format!("{len} bytes {what}"),
            )
        };
        let checked = match (compression.as_deref(), size) {
            (None, _) => Err(Bad::new(
                "a `compression` field in the chunk header",
                "none",
            )),
            (_, None) => Err(Bad::new("a `size` field in the chunk header", "none")),
            (_, Some(size)) if u64::from(size) > max => {
                Err(too_big("decompressed", u64::from(size)))
            }
            _ if data_len > max => Err(too_big("compressed", data_len)),
            (Some(b"none"), Some(size)) => Ok(("none", size)),
            (Some(b"bz2"), Some(size)) => Ok(("bz2", size)),
            (Some(b"lz4"), Some(size)) => Ok(("lz4", size)),
            (Some(other), _) => Err(Bad::new(
                "chunk compression `none`, `bz2` or `lz4`",
                format!("`{}`", String::from_utf8_lossy(other).escape_debug()),
            )),
        };
        let (compression, size) = match checked {
            Ok(c) => c,
            Err(bad) => {
                self.skip_data(start, data_len, "chunk data")?;
                return Ok(Some(Err(loc.error(&self.name, bad))));
            }
        };
        let mut raw = std::mem::take(&mut self.raw);
        self.read_data(start, data_len, "chunk data", &mut raw)?;
        let data = match compression {
            "none" => {
                self.chunk = Some(Chunk {
                    data: raw,
                    at: 0,
                    record: start,
                    data_in_file: Some(data_start),
                    compression,
                });
                return Ok(None);
            }
            _ => {
                let mut out = std::mem::take(&mut self.spare);
                out.clear();
                let result = if compression == "bz2" {
                    bzip2::read::BzDecoder::new(&raw[..])
                        .take(u64::from(size) + 1)
                        .read_to_end(&mut out)
                } else {
                    lz4_flex::frame::FrameDecoder::new(&raw[..])
                        .take(u64::from(size) + 1)
                        .read_to_end(&mut out)
                };
                self.raw = raw;
                match result {
                    Ok(n) if n as u64 == u64::from(size) => out,
                    Ok(n) => {
                        return Ok(Some(Err(loc.error(
                            &self.name,
                            Bad::new(
                                format!("{size} bytes out of the {compression} chunk, as its `size` says"),
                                if n as u64 > u64::from(size) { "more".to_owned() } else { format!("{n} bytes") },
                            ),
                        ))));
                    }
                    Err(e) => {
                        return Ok(Some(Err(loc.error(
                            &self.name,
                            Bad::new(
                                format!("{compression}-compressed chunk data"),
                                format!("data that does not decompress: {e}"),
                            ),
                        ))));
                    }
                }
            }
        };
        self.chunk = Some(Chunk {
            data,
            at: 0,
            record: start,
            data_in_file: None,
            compression,
        });
        Ok(None)
    }

    /// Reads the next record of the current chunk. `None` when the chunk is done.
    fn chunk_record(&mut self, skipped: &mut SkipCounts) -> Option<Result<ScanRecord, ReadError>> {
        loop {
            let chunk = self.chunk.as_mut()?;
            let at = chunk.at;
            if at >= chunk.data.len() {
                let done = self.chunk.take();
                if let Some(done) = done {
                    self.spare = done.data;
                }
                return None;
            }
            let loc = chunk.loc(at);
            let data = &chunk.data;
            let framed = frame(data, at);
            let (header, body, next) = match framed {
                Ok(f) => f,
                Err(bad) => {
                    // The chunk's framing is lost: drop its rest, go on with the next record.
                    chunk.at = data.len();
                    return Some(Err(loc.error(&self.name, bad)));
                }
            };
            chunk.at = next;
            let body_loc = chunk.loc(next - body.len());
            let parsed = RecordHeader::parse(header).and_then(|h| h.op().map(|op| (h, op)));
            let result = match parsed {
                Err(bad) => Some(Err(loc.error(&self.name, bad))),
                Ok((h, op::CONNECTION)) => h
                    .conn()
                    .and_then(|conn| self.state.connection(conn, h.topic, body))
                    .err()
                    .map(|bad| Err(loc.error(&self.name, bad))),
                Ok((h, op::MESSAGE_DATA)) => match h.conn() {
                    Err(bad) => Some(Err(loc.error(&self.name, bad))),
                    Ok(conn) => self
                        .state
                        .message(conn, h.time, body, body_loc, skipped)
                        .transpose(),
                },
                Ok(_) => {
                    skipped.add(SKIP_UNKNOWN_RECORD);
                    None
                }
            };
            if result.is_some() {
                return result;
            }
        }
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
            Some(topic) => format!("a {LASER_SCAN_TYPE} connection on topic {topic}"),
            None => format!("a {LASER_SCAN_TYPE} connection"),
        };
        Some(Err(ReadError::Syntax {
            pos: SourcePos::byte(&self.name, self.input.pos),
            expected,
            found,
        }))
    }
}

/// Splits the record at `at` of a chunk: its header, its data and the offset after it.
fn frame(data: &[u8], at: usize) -> Result<(&[u8], &[u8], usize), Bad> {
    let left = data.len() - at;
    let header_len = read_u32(data, at).ok_or_else(|| {
        Bad::new(
            "a record header length (4 bytes)",
            format!("{left} bytes left in the chunk"),
        )
    })? as usize;
    let header_start = at + 4;
    let header = header_start
        .checked_add(header_len)
        .and_then(|end| data.get(header_start..end))
        .ok_or_else(|| {
            Bad::new(
                format!("a record header of {header_len} bytes"),
                format!("{} bytes left in the chunk", left.saturating_sub(4)),
            )
        })?;
    let data_len_at = header_start + header_len;
    let data_len = read_u32(data, data_len_at).ok_or_else(|| {
        Bad::new(
            "a record data length (4 bytes)",
            format!("{} bytes left in the chunk", data.len() - data_len_at),
        )
    })? as usize;
    let body_start = data_len_at + 4;
    let body = body_start
        .checked_add(data_len)
        .and_then(|end| data.get(body_start..end))
        .ok_or_else(|| {
            Bad::new(
                format!("record data of {data_len} bytes"),
                format!("{} bytes left in the chunk", data.len() - body_start),
            )
        })?;
    Ok((header, body, body_start + data_len))
}

/// True when a topic given by the user names `topic` (a leading `/` is optional).
fn same_topic(given: &str, topic: &str) -> bool {
    given.trim_start_matches('/') == topic.trim_start_matches('/')
}

impl State {
    /// Remembers a connection record (`data` is the connection header: `type`, ...).
    fn connection(&mut self, conn: u32, topic: Option<&[u8]>, data: &[u8]) -> Result<(), Bad> {
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
        if connection.is_laser_scan()
            && self.chosen.is_none()
            && self
                .requested
                .as_deref()
                .is_none_or(|given| same_topic(given, &connection.topic))
        {
            self.chosen = Some(connection.topic.clone());
        }
        self.connections.insert(conn, connection);
        Ok(())
    }

    /// Handles a message record: a scan record, a counted skip (`None`), or an error.
    fn message(
        &self,
        conn: u32,
        time: Option<(u32, u32)>,
        data: &[u8],
        loc: Loc,
        skipped: &mut SkipCounts,
    ) -> Result<Option<ScanRecord>, ReadError> {
        let Some(connection) = self.connections.get(&conn) else {
            skipped.add(SKIP_UNKNOWN_CONNECTION);
            return Ok(None);
        };
        if !connection.is_laser_scan() {
            skipped.add(SKIP_OTHER_TYPE);
            return Ok(None);
        }
        if self.chosen.as_deref() != Some(connection.topic.as_str()) {
            skipped.add(SKIP_OTHER_TOPIC);
            return Ok(None);
        }
        let message = decode_ros1_whole(data).map_err(|bad| ReadError::Field {
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
            ..
        } = message;
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
            line: None,
        }))
    }
}

impl ScanSource for BagSource {
    fn next_record(&mut self, skipped: &mut SkipCounts) -> Option<Result<ScanRecord, ReadError>> {
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
