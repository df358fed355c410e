//! One LaserScan message on its own: its encoding told from an MCAP channel's schema name and
//! message encoding, and its scan decoded. The MCAP reader decodes every message through
//! here; so do tools that get messages one by one from elsewhere (the rows of Ray Data's
//! `read_mcap`, through the Python package).

use foxglove::messages::LaserScan;
use laserlines::Scan;
use laserlines_io::DecodeError;
use prost::Message as _;

use crate::json::{self, JsonMessageError};
use crate::proto::{self, RangeLimits};
use crate::read::ScanEncoding;
use crate::ros;

impl ScanEncoding {
    /// The encoding of a channel with schema `schema` and message encoding `encoding`
    /// ([`SCAN_ENCODINGS`]); `None` for anything else.
    #[must_use]
    pub fn of_channel(schema: &str, encoding: &str) -> Option<Self> {
        match (schema, encoding) {
            ("sensor_msgs/msg/LaserScan", "cdr") => Some(Self::Ros2Cdr),
            ("sensor_msgs/LaserScan", "ros1") => Some(Self::Ros1),
            ("foxglove.LaserScan", "protobuf") => Some(Self::FoxgloveProtobuf),
            ("foxglove.LaserScan", "json") => Some(Self::FoxgloveJson),
            _ => None,
        }
    }
}

/// The LaserScans this crate decodes, for messages that name them.
pub const SCAN_ENCODINGS: &str = "sensor_msgs/msg/LaserScan in cdr, sensor_msgs/LaserScan in ros1, \
                                  or foxglove.LaserScan in protobuf or json";

/// Why a message is not a LaserScan of its encoding.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MessageError {
    /// A ROS message (CDR or ROS 1) that does not decode: the field and byte.
    #[error("{} (byte {} of the message): expected {}, found {}", .0.field, .0.offset, .0.expected, .0.found)]
    Ros(DecodeError),
    /// A protobuf message that does not decode.
    #[error("expected a protobuf foxglove.LaserScan, found bytes that do not decode ({0})")]
    Protobuf(String),
    /// A JSON message that does not decode: the field and what was wrong.
    #[error(transparent)]
    Json(#[from] JsonMessageError),
}

/// The scan of one message of `encoding`. `limits` are the channel's range limits (for
/// `foxglove.LaserScan`, which has none of its own); `log_seconds` is the message's log
/// time, the stamp of a message whose own is zero (when positive). Not validated.
///
/// # Errors
/// [`MessageError`] when the bytes do not decode.
pub fn decode_scan(
    encoding: ScanEncoding,
    limits: RangeLimits,
    data: &[u8],
    log_seconds: f64,
) -> Result<Scan, MessageError> {
    let mut scan = match encoding {
        ScanEncoding::Ros2Cdr => ros::decode_cdr(data).map_err(MessageError::Ros)?.to_scan(),
        ScanEncoding::Ros1 => ros::decode_ros1(data).map_err(MessageError::Ros)?.to_scan(),
        ScanEncoding::FoxgloveProtobuf => {
            let msg = LaserScan::decode(data).map_err(|e| MessageError::Protobuf(e.to_string()))?;
            proto::scan_from_foxglove(&msg, limits, log_seconds)
        }
        ScanEncoding::FoxgloveJson => {
            proto::scan_from_foxglove(&json::laser_scan(data)?, limits, log_seconds)
        }
    };
    if scan.stamp.is_none() && log_seconds > 0.0 {
        scan.stamp = Some(log_seconds);
    }
    Ok(scan)
}
