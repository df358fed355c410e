//! Writing scans, lines and poses to an MCAP file that Foxglove plays (channels and frames in
//! [`crate::scene`]).
//!
//! Messages are encoded with the `foxglove` crate's protobuf types and schemas and written with
//! `mcap::Writer` (zstd chunks of 1 MiB, indexes and summary), so that every write error comes
//! back to the caller.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{self, BufWriter, Seek, Write};
use std::path::Path;

use foxglove::Encode;
use laserlines::Line;
use laserlines_io::{ScanRecord, WriteError};
use mcap::records::MessageHeader;

use crate::scene::{SceneClock, SceneMessages, log_time_ns, scene_messages};
use crate::{LINES_TOPIC, SCAN_TOPIC, TF_TOPIC};

/// A channel of the output, added on its first message.
#[derive(Debug, Clone, Copy, Default)]
struct Slot {
    id: Option<u16>,
    sequence: u32,
}

/// Writes scans (and their lines and poses) as Foxglove messages into an MCAP file.
///
/// Channels are added on first use: `/scan` with the first scan, `/lines` with the first
/// lines, `/tf` with the first pose. `/scan` carries the first scan's `range_min` and
/// `range_max` in its metadata, which [`crate::read`] uses to restore them. Call
/// [`McapSceneWriter::finish`] to write the summary and see any error.
pub struct McapSceneWriter<W: Write + Seek> {
    name: String,
    writer: mcap::Writer<W>,
    scan: Slot,
    lines: Slot,
    tf: Slot,
    /// Channels of [`McapSceneWriter::write_message`], by topic, with their schema's name.
    other: BTreeMap<String, (Slot, String)>,
    clock: SceneClock,
    buf: Vec<u8>,
    scans: u64,
}

impl<W: Write + Seek> std::fmt::Debug for McapSceneWriter<W> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("McapSceneWriter")
            .field("name", &self.name)
            .field("scans", &self.scans)
            .finish_non_exhaustive()
    }
}

fn mcap_error(name: &str, e: mcap::McapError) -> WriteError {
    let source = match e {
        mcap::McapError::Io(e) => e,
        other => io::Error::other(other),
    };
    WriteError::Io {
        file: name.to_owned(),
        source,
    }
}

/// What an MCAP output must be named instead of `.mcap.gz`.
pub(crate) const NOT_GZIPPED: &str = "a name ending in .mcap: MCAP compresses its own chunks (zstd), so .mcap.gz is read but not \
     written";

impl McapSceneWriter<BufWriter<File>> {
    /// Creates an MCAP file at `path` (replacing any file there). A name ending in `.gz` is
    /// refused: MCAP compresses its own chunks (zstd), and a gzipped MCAP (`.mcap.gz`, which
    /// [`crate::read`] reads) would only be larger to seek in.
    ///
    /// # Errors
    /// [`WriteError::Io`] when the file cannot be created or the header written;
    /// [`WriteError::Name`] for a `.gz` name.
    pub fn create(path: &Path) -> Result<Self, WriteError> {
        let name = path.display().to_string();
        let gz = path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("gz"));
        if gz {
            return Err(WriteError::Name {
                file: name,
                expected: NOT_GZIPPED,
            });
        }
        if path == Path::new("-") {
            return Err(WriteError::Io {
                file: name,
                source: io::Error::other("MCAP output must be a file, not standard output"),
            });
        }
        let file = File::create(path).map_err(|source| WriteError::Io {
            file: name.clone(),
            source,
        })?;
        Self::new(BufWriter::with_capacity(1 << 16, file), &name)
    }
}

impl<W: Write + Seek> McapSceneWriter<W> {
    /// A writer into `out`, named `name` in messages, with zstd chunks of 1 MiB.
    ///
    /// # Errors
    /// [`WriteError::Io`] when the MCAP header cannot be written.
    pub fn new(out: W, name: &str) -> Result<Self, WriteError> {
        let options = mcap::WriteOptions::new().compression(Some(mcap::Compression::Zstd));
        Self::with_options(out, name, options)
    }

    /// A writer with the given MCAP options (chunk size, compression, ...; the library
    /// field is set to laserlines').
    ///
    /// # Errors
    /// [`WriteError::Io`] when the MCAP header cannot be written.
    pub fn with_options(
        out: W,
        name: &str,
        options: mcap::WriteOptions,
    ) -> Result<Self, WriteError> {
        let options = options.library(format!(
            "laserlines {} ({})",
            env!("CARGO_PKG_VERSION"),
            mcap::LIBRARY_IDENTIFIER
        ));
        let writer = options.create(out).map_err(|e| mcap_error(name, e))?;
        Ok(Self {
            name: name.to_owned(),
            writer,
            scan: Slot::default(),
            lines: Slot::default(),
            tf: Slot::default(),
            other: BTreeMap::new(),
            clock: SceneClock::new(),
            buf: Vec::new(),
            scans: 0,
        })
    }

    /// Number of scans written.
    #[must_use]
    pub fn scans(&self) -> u64 {
        self.scans
    }

    /// Writes a scan and, when it has one, the robot's pose (`laserlines convert`).
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn write_scan(&mut self, record: &ScanRecord) -> Result<(), WriteError> {
        let time = self.clock.time_of(record.scan.stamp);
        self.write_messages(&scene_messages(record, None, time), &record.scan)
    }

    /// Writes a scan, the lines extracted from it and, when it has one, the robot's pose
    /// (`laserlines extract -o out.mcap`).
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn write_lines(&mut self, record: &ScanRecord, lines: &[Line]) -> Result<(), WriteError> {
        let time = self.clock.time_of(record.scan.stamp);
        self.write_messages(&scene_messages(record, Some(lines), time), &record.scan)
    }

    /// Writes any Foxglove message on `topic` at `time` (s): the channel is added on the
    /// topic's first message, with the message type's schema. For scenes beyond a scan and its
    /// lines (`laserlines simulate --mcap`: arena walls, sector objects, estimated poses).
    /// `/scan`, `/lines` and `/tf` keep their own channels: use [`Self::write_lines`] or
    /// [`Self::write_transform`] for those.
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails; a topic of the writer's own channels or one
    /// already used with another message type is refused the same way.
    pub fn write_message<T: Encode>(
        &mut self,
        topic: &str,
        msg: &T,
        time: f64,
    ) -> Result<(), WriteError> {
        if [SCAN_TOPIC, LINES_TOPIC, TF_TOPIC].contains(&topic) {
            return Err(WriteError::Io {
                file: self.name.clone(),
                source: io::Error::other(format!(
                    "topic {topic} is written by write_scan/write_lines/write_transform"
                )),
            });
        }
        let schema = T::get_schema().map(|s| s.name).unwrap_or_default();
        let mut slot = match self.other.get(topic) {
            Some((slot, name)) if *name == schema => *slot,
            Some((_, name)) => {
                return Err(WriteError::Io {
                    file: self.name.clone(),
                    source: io::Error::other(format!(
                        "topic {topic} carries {name}, not {schema}: one message type per topic"
                    )),
                });
            }
            None => Slot::default(),
        };
        self.log(&mut slot, topic, BTreeMap::new(), msg, log_time_ns(time))?;
        self.other.insert(topic.to_owned(), (slot, schema));
        Ok(())
    }

    /// Writes a transform on `/tf` at its own timestamp.
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn write_transform(
        &mut self,
        transform: &foxglove::messages::FrameTransform,
    ) -> Result<(), WriteError> {
        let time = transform
            .timestamp
            .as_ref()
            .map_or(0.0, crate::proto::seconds);
        let mut slot = self.tf;
        self.log(
            &mut slot,
            TF_TOPIC,
            BTreeMap::new(),
            transform,
            log_time_ns(time),
        )?;
        self.tf = slot;
        Ok(())
    }

    /// Writes a scan with its lines at `time` (s) without transforms; the caller places the
    /// frames with [`Self::write_transform`] (a laser away from the robot's origin).
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn write_scan_lines_at(
        &mut self,
        scan: &laserlines::Scan,
        lines: &[Line],
        time: f64,
    ) -> Result<(), WriteError> {
        let messages = SceneMessages {
            time,
            scan: crate::proto::foxglove_from_scan(scan, crate::LASER_FRAME, time),
            lines: Some(crate::scene::lines_update(lines, time)),
            transforms: Vec::new(),
        };
        self.write_messages(&messages, scan)
    }

    /// Writes the messages of one scan: poses first, so that a reader meets the pose before
    /// the scan it belongs to.
    fn write_messages(
        &mut self,
        m: &SceneMessages,
        scan: &laserlines::Scan,
    ) -> Result<(), WriteError> {
        let log_time = log_time_ns(m.time);
        for t in &m.transforms {
            let mut slot = self.tf;
            self.log(&mut slot, TF_TOPIC, BTreeMap::new(), t, log_time)?;
            self.tf = slot;
        }
        let mut slot = self.scan;
        let limits = BTreeMap::from([
            ("range_min".to_owned(), scan.range_min.to_string()),
            ("range_max".to_owned(), scan.range_max.to_string()),
        ]);
        self.log(&mut slot, SCAN_TOPIC, limits, &m.scan, log_time)?;
        self.scan = slot;
        if let Some(lines) = &m.lines {
            let mut slot = self.lines;
            self.log(&mut slot, LINES_TOPIC, BTreeMap::new(), lines, log_time)?;
            self.lines = slot;
        }
        self.scans += 1;
        Ok(())
    }

    fn log<T: Encode>(
        &mut self,
        slot: &mut Slot,
        topic: &str,
        metadata: BTreeMap<String, String>,
        msg: &T,
        log_time: u64,
    ) -> Result<(), WriteError> {
        let id = match slot.id {
            Some(id) => id,
            None => {
                let schema_id = match T::get_schema() {
                    Some(s) => self
                        .writer
                        .add_schema(&s.name, &s.encoding, &s.data)
                        .map_err(|e| mcap_error(&self.name, e))?,
                    None => 0,
                };
                let id = self
                    .writer
                    .add_channel(schema_id, topic, &T::get_message_encoding(), &metadata)
                    .map_err(|e| mcap_error(&self.name, e))?;
                slot.id = Some(id);
                id
            }
        };
        self.buf.clear();
        msg.encode(&mut self.buf).map_err(|e| WriteError::Io {
            file: self.name.clone(),
            source: io::Error::other(e.to_string()),
        })?;
        slot.sequence = slot.sequence.wrapping_add(1);
        let header = MessageHeader {
            channel_id: id,
            sequence: slot.sequence,
            log_time,
            publish_time: log_time,
        };
        self.writer
            .write_to_known_channel(&header, &self.buf)
            .map_err(|e| mcap_error(&self.name, e))
    }

    /// Writes the summary and the footer, flushes, and returns the output.
    ///
    /// # Errors
    /// [`WriteError::Io`] when writing fails.
    pub fn finish(mut self) -> Result<W, WriteError> {
        self.writer
            .finish()
            .map_err(|e| mcap_error(&self.name, e))?;
        let name = self.name;
        let mut out = self.writer.into_inner();
        out.flush()
            .map_err(|source| WriteError::Io { file: name, source })?;
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use foxglove::messages::{FrameTransform, SceneUpdate};
    use laserlines::Scan;
    use laserlines_io::Pose2;
    use prost::Message as _;
    use std::io::Cursor;

    fn by_topic(bytes: &[u8]) -> BTreeMap<String, Vec<(String, u64, Vec<u8>)>> {
        let mut out: BTreeMap<String, Vec<(String, u64, Vec<u8>)>> = BTreeMap::new();
        for m in mcap::MessageStream::new(bytes).unwrap() {
            let m = m.unwrap();
            let schema = m.channel.schema.as_ref().map(|s| s.name.clone()).unwrap();
            out.entry(m.channel.topic.clone()).or_default().push((
                schema,
                m.log_time,
                m.data.into_owned(),
            ));
        }
        out
    }

    #[test]
    fn own_topics_transforms_and_scans_at_a_time() {
        let mut w = McapSceneWriter::new(Cursor::new(Vec::new()), "mem.mcap").unwrap();
        let update = crate::scene::lines_update(&[], 0.5);
        w.write_message("/arena", &update, 0.0).unwrap();
        w.write_message("/arena", &update, 2.0).unwrap();
        // The writer's own topics are refused (their channels carry metadata and order).
        let e = w.write_message("/scan", &update, 1.0).unwrap_err();
        assert!(e.to_string().contains("/scan"), "{e}");
        // One message type per topic.
        let tf0 = crate::proto::transform_from_pose("world", "a", Pose2::new(0.0, 0.0, 0.0), 0.5);
        let e = w.write_message("/arena", &tf0, 1.0).unwrap_err();
        assert!(
            e.to_string().contains("foxglove.SceneUpdate")
                && e.to_string().contains("foxglove.FrameTransform"),
            "{e}"
        );
        let tf =
            crate::proto::transform_from_pose("world", "base_link", Pose2::new(1.0, 2.0, 0.3), 1.5);
        w.write_transform(&tf).unwrap();
        let scan = Scan::new(-1.0, 0.01, 0.02, 4.0, vec![1.0; 201]).unwrap();
        w.write_scan_lines_at(&scan, &[], 1.5).unwrap();
        assert_eq!(w.scans(), 1);
        let bytes = w.finish().unwrap().into_inner();
        let topics = by_topic(&bytes);
        let arena = &topics["/arena"];
        assert_eq!(arena.len(), 2);
        assert_eq!(arena[0].0, "foxglove.SceneUpdate");
        assert_eq!((arena[0].1, arena[1].1), (0, 2_000_000_000));
        assert_eq!(SceneUpdate::decode(arena[1].2.as_slice()).unwrap(), update);
        let tfs = &topics["/tf"];
        assert_eq!(tfs.len(), 1);
        assert_eq!(tfs[0].1, 1_500_000_000);
        assert_eq!(FrameTransform::decode(tfs[0].2.as_slice()).unwrap(), tf);
        assert_eq!(topics["/scan"][0].1, 1_500_000_000);
        assert_eq!(topics["/lines"].len(), 1);
    }
}
