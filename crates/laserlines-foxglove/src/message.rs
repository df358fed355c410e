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
            ("sensor_msgs/msg/MultiEchoLaserScan", "cdr") => Some(Self::Ros2CdrMultiEcho),
            ("sensor_msgs/MultiEchoLaserScan", "ros1") => Some(Self::Ros1MultiEcho),
            ("foxglove.LaserScan", "protobuf") => Some(Self::FoxgloveProtobuf),
            ("foxglove.LaserScan", "json") => Some(Self::FoxgloveJson),
            _ => None,
        }
    }
}

/// The LaserScans this crate decodes, for messages that name them.
pub const SCAN_ENCODINGS: &str = "sensor_msgs/msg/LaserScan or sensor_msgs/msg/MultiEchoLaserScan \
                                  in cdr, sensor_msgs/LaserScan or sensor_msgs/MultiEchoLaserScan \
                                  in ros1, or foxglove.LaserScan in protobuf or json";

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
    decode_scan_counted(encoding, limits, data, log_seconds).map(|(scan, _)| scan)
}

/// [`decode_scan`], and the echoes after each beam's first left out of a
/// `MultiEchoLaserScan` (0 for the other encodings).
///
/// # Errors
/// As [`decode_scan`].
pub fn decode_scan_counted(
    encoding: ScanEncoding,
    limits: RangeLimits,
    data: &[u8],
    log_seconds: f64,
) -> Result<(Scan, usize), MessageError> {
    use ros::ScanMsgType::{LaserScan as Single, MultiEcho};
    let ros_scan = |msg: Result<ros::LaserScanMsg, DecodeError>| {
        msg.map(|m| (m.to_scan(), m.echoes_left_out))
            .map_err(MessageError::Ros)
    };
    let (mut scan, left_out) = match encoding {
        ScanEncoding::Ros2Cdr => ros_scan(ros::decode_cdr_as(data, Single))?,
        ScanEncoding::Ros1 => ros_scan(ros::decode_ros1_as(data, Single))?,
        ScanEncoding::Ros2CdrMultiEcho => ros_scan(ros::decode_cdr_as(data, MultiEcho))?,
        ScanEncoding::Ros1MultiEcho => ros_scan(ros::decode_ros1_as(data, MultiEcho))?,
        ScanEncoding::FoxgloveProtobuf => {
            let msg = LaserScan::decode(data).map_err(|e| MessageError::Protobuf(e.to_string()))?;
            // Protobuf reads an empty payload as a message whose fields are all zero: one
            // without ranges, angles or time stamp is that, not a scan of no beams.
            if msg.ranges.is_empty()
                && msg.start_angle == 0.0
                && msg.end_angle == 0.0
                && msg.timestamp.is_none()
            {
                return Err(MessageError::Protobuf(format!(
                    "no ranges, angles or time stamp in {} bytes: an empty message",
                    data.len()
                )));
            }
            (proto::scan_from_foxglove(&msg, limits, log_seconds), 0)
        }
        ScanEncoding::FoxgloveJson => (
            proto::scan_from_foxglove(&json::laser_scan(data)?, limits, log_seconds),
            0,
        ),
    };
    if scan.stamp.is_none() && log_seconds > 0.0 {
        scan.stamp = Some(log_seconds);
    }
    Ok((scan, left_out))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_empty_protobuf_payload_is_no_scan_but_a_scan_of_no_beams_is() {
        let decode = |data: &[u8]| {
            decode_scan(
                ScanEncoding::FoxgloveProtobuf,
                RangeLimits::default(),
                data,
                5.0,
            )
        };
        let msg = LaserScan {
            start_angle: -1.0,
            end_angle: 1.0,
            ranges: vec![1.0, 2.0, 3.0],
            ..LaserScan::default()
        };
        let scan = decode(&msg.encode_to_vec()).unwrap();
        assert_eq!(scan.ranges, [1.0, 2.0, 3.0]);
        assert!((scan.angle_increment - 1.0).abs() < 1e-12);
        // An empty payload: a message of zeros.
        let e = decode(&[]).unwrap_err().to_string();
        assert!(
            e.contains("no ranges, angles or time stamp in 0 bytes: an empty message"),
            "{e}"
        );
        // A scan of no beams, as the MCAP writer writes one, reads back as one.
        let empty = LaserScan {
            ranges: Vec::new(),
            ..msg
        };
        assert!(decode(&empty.encode_to_vec()).unwrap().ranges.is_empty());
    }
}
