//! Bags of format version 1.2 (`#ROSRECORD V1.2`, ROS 0.5 to 1.0): the framing of 2.0
//! without chunks or connection records. A topic's type comes from its message definition
//! record (`0x01`: `topic`, `type`, `md5`, `def`) or from the header of a message data record
//! (`0x02`: `topic`, `type`, `md5`, `sec`, `nsec`), whichever comes first; each topic is
//! given a connection number of its own, so that the rest of the reader handles both versions
//! alike. The file header (`0x03`: `index_pos`) and index data records (`0x04`, version 0)
//! are skipped: the reader walks the records front to back, as for 2.0.

use crate::error::ReadError;
use crate::record::ScanRecord;
use crate::skip::SkipCounts;

use super::records::{Bad, Loc, RecordHeader, op};
use super::state::Connection;
use super::{BagSource, SKIP_UNKNOWN_RECORD};

impl BagSource {
    /// Handles a record of a version 1.2 bag whose header has been read.
    pub(super) fn handle_v12(
        &mut self,
        start: u64,
        header: &RecordHeader<'_>,
        op: u8,
        (data_start, data_len): (u64, u64),
        skipped: &mut SkipCounts,
    ) -> Result<Option<Result<ScanRecord, ReadError>>, ReadError> {
        match op {
            op::MESSAGE_DEFINITION => {
                let topic = self.v12_topic(header);
                self.skip_data(start, data_len, "message definition data")?;
                Ok(topic
                    .err()
                    .map(|bad| Err(Loc::File(start).error(&self.name, bad))))
            }
            op::MESSAGE_DATA => {
                let conn = self.v12_topic(header);
                let time = match (header.sec, header.nsec) {
                    (Some(sec), Some(nsec)) => Some((sec, nsec)),
                    _ => None,
                };
                self.top_message(start, (conn, time), (data_start, data_len), skipped)
            }
            op::BAG_HEADER | op::INDEX_DATA => {
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

    /// The connection number of the record's topic, declaring the topic with the record's
    /// type the first time it is seen.
    fn v12_topic(&mut self, header: &RecordHeader<'_>) -> Result<u32, Bad> {
        let topic = header
            .topic
            .ok_or_else(|| Bad::new("a `topic` field in the record header", "none"))?;
        let topics = self.v12.get_or_insert_default();
        if let Some(conn) = topics.get(topic) {
            return Ok(*conn);
        }
        let kind = header
            .kind
            .ok_or_else(|| Bad::new("a `type` field in the record header", "none"))?;
        let conn = u32::try_from(topics.len()).unwrap_or(u32::MAX);
        topics.insert(topic.to_vec(), conn);
        self.state.add(
            conn,
            Connection {
                topic: String::from_utf8_lossy(topic).into_owned(),
                kind: String::from_utf8_lossy(kind).into_owned(),
            },
        );
        Ok(conn)
    }
}
