//! Messages as they travel in a DDS `DATA` submessage: a 4-byte encapsulation header (the
//! representation, `CDR_LE` or `CDR_BE`, and two option bytes), then the CDR body. Decoding
//! goes through the same adapter as the node's subscription (RustDDS's
//! `CDRDeserializerAdapter`), so that [`decode`] answers for any payload what the node
//! does with it: a message, or an error that the node counts and skips.

use ros2_client::dds::rustdds::no_key::{DeserializerAdapter as _, SerializerAdapter as _};
use ros2_client::dds::rustdds::{
    CDRDeserializerAdapter, CDRSerializerAdapter, RepresentationIdentifier,
};
use serde::Serialize;
use serde::de::DeserializeOwned;

/// A payload that is not a message of the expected type.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum WireError {
    /// Shorter than the 4-byte encapsulation header.
    #[error("payload of {0} bytes has no encapsulation header (4 bytes)")]
    NoHeader(usize),
    /// The header names a representation other than plain CDR.
    #[error("representation {0:02x?} is not CDR_LE or CDR_BE")]
    Representation([u8; 2]),
    /// The CDR body does not decode as the message.
    #[error("CDR body does not decode: {0}")]
    Body(String),
    /// The message cannot be encoded.
    #[error("cannot encode: {0}")]
    Encode(String),
}

/// Decodes a message from a serialized payload (header and CDR body).
///
/// # Errors
/// A [`WireError`] naming what is wrong; never a panic, whatever the bytes.
pub fn decode<M: DeserializeOwned>(payload: &[u8]) -> Result<M, WireError> {
    if payload.len() < 4 {
        return Err(WireError::NoHeader(payload.len()));
    }
    let rep = [payload[0], payload[1]];
    let id =
        RepresentationIdentifier::from_bytes(&rep).map_err(|_| WireError::Representation(rep))?;
    if id != RepresentationIdentifier::CDR_LE && id != RepresentationIdentifier::CDR_BE {
        return Err(WireError::Representation(rep));
    }
    CDRDeserializerAdapter::<M>::from_bytes(&payload[4..], id)
        .map_err(|e| WireError::Body(e.to_string()))
}

/// Encodes a message as the node's publishers do (little-endian CDR with its header).
///
/// # Errors
/// [`WireError::Encode`] when serialization fails.
pub fn encode<M: Serialize>(msg: &M) -> Result<Vec<u8>, WireError> {
    let body =
        CDRSerializerAdapter::<M>::to_bytes(msg).map_err(|e| WireError::Encode(e.to_string()))?;
    let mut out = Vec::with_capacity(body.len() + 4);
    out.extend_from_slice(&RepresentationIdentifier::CDR_LE.to_bytes());
    out.extend_from_slice(&[0, 0]);
    out.extend_from_slice(&body);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::msg::{Header, LaserScan, LineSegment, LineSegmentList, Time};

    /// A LaserScan by hand, as XCDR1 little endian lays it out: header (stamp 4+4, frame_id
    /// length 6 with its NUL, "laser\0", 2 bytes of padding to 4), seven float32, the ranges
    /// (count 2, values), the intensities (count 0).
    fn hand_made() -> Vec<u8> {
        let mut b = vec![0x00, 0x01, 0x00, 0x00];
        b.extend_from_slice(&7_i32.to_le_bytes());
        b.extend_from_slice(&5_u32.to_le_bytes());
        b.extend_from_slice(&6_u32.to_le_bytes());
        b.extend_from_slice(b"laser\0\0\0");
        for v in [-1.0_f32, 1.0, 2.0, 0.0, 0.1, 0.02, 5.6] {
            b.extend_from_slice(&v.to_le_bytes());
        }
        b.extend_from_slice(&2_u32.to_le_bytes());
        b.extend_from_slice(&1.5_f32.to_le_bytes());
        b.extend_from_slice(&f32::INFINITY.to_le_bytes());
        b.extend_from_slice(&0_u32.to_le_bytes());
        b
    }

    #[test]
    fn a_hand_made_scan_decodes_and_encodes_to_the_same_bytes() {
        let m: LaserScan = decode(&hand_made()).unwrap();
        assert_eq!(m.header.stamp, Time { sec: 7, nanosec: 5 });
        assert_eq!(m.header.frame_id, "laser");
        assert_eq!(
            (m.angle_min, m.angle_max, m.angle_increment),
            (-1.0, 1.0, 2.0)
        );
        assert_eq!((m.range_min, m.range_max), (0.02, 5.6));
        assert_eq!(m.ranges, vec![1.5, f32::INFINITY]);
        assert!(m.intensities.is_empty());
        assert_eq!(encode(&m).unwrap(), hand_made());
    }

    #[test]
    fn a_line_segment_is_eleven_float32_in_field_order() {
        let list = LineSegmentList {
            header: Header::default(),
            line_segments: vec![LineSegment {
                radius: 1.0,
                angle: 2.0,
                covariance: [3.0, 4.0, 5.0, 6.0],
                start: [7.0, 8.0],
                end: [9.0, 10.0],
            }],
        };
        let b = encode(&list).unwrap();
        // header: 4 + (4 + 4) stamp + 4 length + 1 NUL, padded to 16; count at 16..20.
        let body = &b[4..];
        assert_eq!(&body[16..20], &1_u32.to_le_bytes());
        let floats: Vec<f32> = body[20..]
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect();
        assert_eq!(floats, (1..=10).map(|v| v as f32).collect::<Vec<_>>());
    }

    #[test]
    fn bad_payloads_are_errors() {
        assert_eq!(decode::<LaserScan>(&[0, 1]), Err(WireError::NoHeader(2)));
        assert!(matches!(
            decode::<LaserScan>(&[0, 7, 0, 0, 1, 2, 3, 4]),
            Err(WireError::Representation([0, 7]))
        ));
        let mut cut = hand_made();
        cut.truncate(cut.len() - 6);
        assert!(matches!(decode::<LaserScan>(&cut), Err(WireError::Body(_))));
        // A ranges count far beyond the bytes there: an error, not a huge allocation.
        let mut huge = hand_made();
        let at = huge.len() - 16;
        huge[at..at + 4].copy_from_slice(&u32::MAX.to_le_bytes());
        assert!(matches!(
            decode::<LaserScan>(&huge),
            Err(WireError::Body(_))
        ));
    }
}
