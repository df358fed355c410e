//! Schemas and channels: what each channel carries, and the decoding of its messages
//! (LaserScans in three encodings, transforms for poses).

use foxglove::messages::{FrameTransform, FrameTransforms};
use laserlines_io::{DecodeError, Pose2, ReadError, ScanRecord, SkipCounts};
use prost::Message as _;

use super::records::{Body, Loc};
use super::{
    McapScanSource, SKIP_BAD_TRANSFORM, SKIP_LATER_ECHOES, SKIP_OTHER_TOPIC, SKIP_UNKNOWN_CHANNEL,
    ScanEncoding,
};
use crate::json;
use crate::message::{self, MessageError, SCAN_ENCODINGS};
use crate::proto::{self, RangeLimits};
use crate::{ODOM_FRAME, ROBOT_FRAME};

/// How a channel's transforms come.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum TransformKind {
    /// One `foxglove.FrameTransform` in protobuf.
    Protobuf,
    /// One `foxglove.FrameTransform` in JSON.
    Json,
    /// `foxglove.FrameTransforms` (a list) in protobuf.
    ProtobufList,
    /// `foxglove.FrameTransforms` in JSON.
    JsonList,
}

/// What a channel carries, as far as this reader cares.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Role {
    /// LaserScans this reader decodes.
    Scan(ScanEncoding, RangeLimits),
    /// LaserScans in an encoding this reader does not decode.
    UnsupportedScan,
    /// `foxglove.FrameTransform` or `foxglove.FrameTransforms`, for poses.
    Transform(TransformKind),
    /// Anything else.
    Other,
}

/// The transforms of a message of `kind`, in their order; `Err` when it does not decode.
fn decode_transforms(kind: TransformKind, data: &[u8]) -> Result<Vec<FrameTransform>, ()> {
    match kind {
        TransformKind::Protobuf => FrameTransform::decode(data).map(|t| vec![t]).map_err(drop),
        TransformKind::Json => json::frame_transform(data).map(|t| vec![t]).map_err(drop),
        TransformKind::ProtobufList => FrameTransforms::decode(data)
            .map(|l| l.transforms)
            .map_err(drop),
        TransformKind::JsonList => json::frame_transforms(data)
            .map(|l| l.transforms)
            .map_err(drop),
    }
}

pub(super) fn is_scan_schema(name: &str) -> bool {
    matches!(
        name,
        "sensor_msgs/msg/LaserScan"
            | "sensor_msgs/LaserScan"
            | "sensor_msgs/msg/MultiEchoLaserScan"
            | "sensor_msgs/MultiEchoLaserScan"
            | "foxglove.LaserScan"
    )
}

pub(super) fn role_of(schema: &str, encoding: &str, limits: RangeLimits) -> Role {
    if let Some(e) = ScanEncoding::of_channel(schema, encoding) {
        return Role::Scan(e, limits);
    }
    match (schema, encoding) {
        ("foxglove.FrameTransform", "protobuf") => Role::Transform(TransformKind::Protobuf),
        ("foxglove.FrameTransform", "json") => Role::Transform(TransformKind::Json),
        ("foxglove.FrameTransforms", "protobuf") => Role::Transform(TransformKind::ProtobufList),
        ("foxglove.FrameTransforms", "json") => Role::Transform(TransformKind::JsonList),
        (s, _) if is_scan_schema(s) => Role::UnsupportedScan,
        _ => Role::Other,
    }
}

#[derive(Debug)]
pub(super) struct ChannelInfo {
    pub(super) topic: String,
    pub(super) schema: String,
    pub(super) encoding: String,
    pub(super) role: Role,
}

impl McapScanSource {
    pub(super) fn handle_schema(&mut self, body: &[u8]) -> Result<(), String> {
        let mut b = Body::new(body);
        let id = b.u16("schema id")?;
        let name = b.string("schema name")?;
        let encoding = b.string("schema encoding")?;
        let data_len = b.u32("schema data")?;
        b.bytes(u64::from(data_len), "schema data")?;
        self.schemas.insert(id, (name, encoding));
        Ok(())
    }

    pub(super) fn handle_channel(&mut self, body: &[u8], loc: Loc) -> Result<(), String> {
        let mut b = Body::new(body);
        let id = b.u16("channel id")?;
        let schema_id = b.u16("schema id")?;
        let topic = b.string("topic")?;
        let encoding = b.string("message encoding")?;
        let metadata = b.map("metadata")?;
        let schema = self
            .schemas
            .get(&schema_id)
            .map(|(name, _)| name.clone())
            .unwrap_or_default();
        let limits = RangeLimits::from_metadata(|k| {
            metadata
                .iter()
                .find(|(key, _)| key == k)
                .map(|(_, v)| v.as_str())
        });
        let role = role_of(&schema, &encoding, limits);
        let scan_like = matches!(role, Role::Scan(..) | Role::UnsupportedScan);
        if self.topic.is_none() && scan_like {
            self.topic = Some(topic.clone());
        }
        if self.topic.as_deref() == Some(topic.as_str()) && !matches!(role, Role::Scan(..)) {
            let what = if schema.is_empty() {
                "no schema".to_owned()
            } else {
                format!("{schema} messages")
            };
            let e = self.syntax(
                loc.byte(),
                format!(
                    "topic {topic}{} to carry LaserScans ({SCAN_ENCODINGS})",
                    loc.context()
                ),
                format!("{what} in the {encoding:?} encoding"),
            );
            self.fail(e);
        }
        self.channels.insert(
            id,
            ChannelInfo {
                topic,
                schema,
                encoding,
                role,
            },
        );
        Ok(())
    }

    pub(super) fn handle_message(
        &mut self,
        body: &[u8],
        loc: Loc,
        skipped: &mut SkipCounts,
    ) -> Result<(), String> {
        let mut b = Body::new(body);
        let channel_id = b.u16("channel id")?;
        let _sequence = b.u32("sequence")?;
        let log_time = b.u64("log time")?;
        let _publish_time = b.u64("publish time")?;
        let data = b.rest();
        *self.seen.entry(channel_id).or_default() += 1;
        if !self.channels.contains_key(&channel_id) {
            self.define_from_summary(channel_id, true);
            if self.done {
                // The summary's definition ended the reader (a topic that is not a scan's).
                return Ok(());
            }
        }
        let Some(channel) = self.channels.get(&channel_id) else {
            skipped.add(SKIP_UNKNOWN_CHANNEL);
            return Ok(());
        };
        match &channel.role {
            Role::Transform(kind) => {
                match decode_transforms(*kind, data) {
                    Ok(list) => list.iter().for_each(|t| self.take_transform(t)),
                    Err(()) => skipped.add(SKIP_BAD_TRANSFORM),
                }
                Ok(())
            }
            Role::Scan(encoding, limits) => {
                if self.topic.as_deref() != Some(channel.topic.as_str()) {
                    skipped.add(SKIP_OTHER_TOPIC);
                    return Ok(());
                }
                let log_seconds =
                    (log_time / 1_000_000_000) as f64 + (log_time % 1_000_000_000) as f64 * 1e-9;
                let item = self
                    .decode_scan(*encoding, *limits, data, log_seconds, loc, channel)
                    .map(|(record, left_out)| {
                        skipped.add_n(SKIP_LATER_ECHOES, left_out as u64);
                        record
                    });
                self.pending.push_back(item);
                Ok(())
            }
            Role::UnsupportedScan => {
                skipped.add(SKIP_OTHER_TOPIC);
                Ok(())
            }
            Role::Other => Ok(()),
        }
    }

    pub(super) fn decode_scan(
        &self,
        encoding: ScanEncoding,
        limits: RangeLimits,
        data: &[u8],
        log_seconds: f64,
        loc: Loc,
        channel: &ChannelInfo,
    ) -> Result<(ScanRecord, usize), ReadError> {
        let field_error = |e: DecodeError| ReadError::Field {
            pos: self.at(loc.byte()),
            field: format!(
                "{} message{}: {} (byte {} of the message)",
                channel.topic,
                loc.context(),
                e.field,
                e.offset
            ),
            expected: e.expected,
            found: e.found,
        };
        let (scan, left_out) = message::decode_scan_counted(encoding, limits, data, log_seconds)
            .map_err(|e| match e {
                MessageError::Ros(e) => field_error(e),
                MessageError::Json(e) => ReadError::Field {
                    pos: self.at(loc.byte()),
                    field: format!("{} message{}: {}", channel.topic, loc.context(), e.field),
                    expected: e.expected,
                    found: e.found,
                },
                MessageError::Protobuf(e) => ReadError::Field {
                    pos: self.at(loc.byte()),
                    field: format!("{} message{}", channel.topic, loc.context()),
                    expected: "a protobuf foxglove.LaserScan".to_owned(),
                    found: format!("bytes that do not decode ({e})"),
                },
            })?;
        scan.validate().map_err(|source| ReadError::InvalidScan {
            pos: self.at(loc.byte()),
            source,
        })?;
        let record = ScanRecord {
            scan,
            pose: self.pose,
            odometry: self.odometry,
            line: None,
        };
        Ok((record, left_out))
    }

    /// Takes a transform of `/tf`: the odometry (`odom -> base_link`), the pose (any other
    /// `X -> base_link`), or where the odometry frame lies (`X -> odom`).
    fn take_transform(&mut self, t: &FrameTransform) {
        let Some(p) = proto::pose_from_transform(t) else {
            return;
        };
        // The odometry frame at the world's origin (as laserlines writes it when pose and
        // odometry agree) gives the odometry back bit for bit.
        let compose = |a: Pose2, b: Pose2| {
            if a == Pose2::default() {
                return b;
            }
            let c = a.to_isometry() * b.to_isometry();
            Pose2::new(
                c.translation.vector.x,
                c.translation.vector.y,
                c.rotation.angle(),
            )
        };
        match (t.parent_frame_id.as_str(), t.child_frame_id.as_str()) {
            (ODOM_FRAME, ROBOT_FRAME) => {
                self.odometry = Some(p);
                self.pose = Some(self.world_from_odom.map_or(p, |w| compose(w, p)));
            }
            (_, ROBOT_FRAME) => self.pose = Some(p),
            (_, ODOM_FRAME) => {
                self.world_from_odom = Some(p);
                if let Some(o) = self.odometry {
                    self.pose = Some(compose(p, o));
                }
            }
            _ => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use laserlines_io::Pose2;

    #[test]
    fn transforms_decode_alone_and_as_a_list_in_both_encodings() {
        let a = proto::transform_from_pose("odom", "base_link", Pose2::new(1.0, 2.0, 0.5), 3.0);
        let b = proto::transform_from_pose("map", "odom", Pose2::new(-1.0, 0.0, 0.0), 3.0);
        let list = FrameTransforms {
            transforms: vec![a.clone(), b.clone()],
        };
        let kinds = [
            ("foxglove.FrameTransform", "protobuf"),
            ("foxglove.FrameTransforms", "protobuf"),
        ];
        let roles: Vec<_> = kinds
            .iter()
            .map(|(s, e)| role_of(s, e, RangeLimits::default()))
            .collect();
        assert_eq!(roles[0], Role::Transform(TransformKind::Protobuf));
        assert_eq!(roles[1], Role::Transform(TransformKind::ProtobufList));
        let one = decode_transforms(TransformKind::Protobuf, &a.encode_to_vec()).unwrap();
        assert_eq!(one, vec![a.clone()]);
        let both = decode_transforms(TransformKind::ProtobufList, &list.encode_to_vec()).unwrap();
        assert_eq!(both, vec![a, b]);
        let json = br#"{"transforms": [{"child_frame_id": "base_link"}]}"#;
        let from_json = decode_transforms(TransformKind::JsonList, json).unwrap();
        assert_eq!(from_json[0].child_frame_id, "base_link");
        assert!(decode_transforms(TransformKind::Json, b"[]").is_err());
        assert!(decode_transforms(TransformKind::ProtobufList, &[0xff, 0xff]).is_err());
        assert_eq!(
            role_of("foxglove.FrameTransforms", "json", RangeLimits::default()),
            Role::Transform(TransformKind::JsonList)
        );
    }
}
