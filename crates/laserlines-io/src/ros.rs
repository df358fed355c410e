//! `sensor_msgs/LaserScan` as ROS 1 serializes it and as ROS 2 serializes it in CDR: the one
//! decoder of the ROS bag reader ([`crate::bag`]) and the MCAP reader of
//! `laserlines-foxglove`.
//!
//! Both carry the same fields:
//!
//! ```text
//! std_msgs/Header header      # ROS 1: uint32 seq, time stamp (uint32 sec, uint32 nsec), string frame_id
//!                             # ROS 2: builtin_interfaces/Time stamp (int32 sec, uint32 nanosec), string frame_id
//! float32 angle_min           # rad
//! float32 angle_max           # rad
//! float32 angle_increment     # rad
//! float32 time_increment      # s
//! float32 scan_time           # s
//! float32 range_min           # m
//! float32 range_max           # m
//! float32[] ranges            # m
//! float32[] intensities
//! ```
//!
//! `sensor_msgs/MultiEchoLaserScan` (a multi-echo driver's output, such as `urg_node`'s
//! `echoes` topic or the 2D lasers of Cartographer's public bags) has the same fields but
//! for `ranges` and `intensities`, which are `sensor_msgs/LaserEcho[]`, each a `float32[]
//! echoes` list per beam. Its decoders keep each beam's first echo, as Cartographer reads
//! these messages (NaN, no return, for a beam with none), and count the echoes left out
//! ([`LaserScanMsg::echoes_left_out`]).
//!
//! ROS 1 writes little-endian numbers back to back; a string or array is a `uint32` count and
//! its elements. ROS 2 writes CDR: a 4-byte encapsulation header (`00 01` little-endian or
//! `00 00` big-endian, then two option bytes), then every number aligned to its size counted from
//! the end of that header, and strings that count and carry a terminating NUL. Each decoder
//! checks every count against the bytes left before allocating, so a corrupt message is an
//! error naming the field and its byte offset in the message, never a panic or a huge
//! allocation.

use crate::wire::{DecodeError, Endian, Wire};

/// A decoded `sensor_msgs/LaserScan`, with its values as the message holds them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LaserScanMsg {
    /// Header stamp, whole seconds (ROS 2 allows negative seconds; ROS 1 does not).
    pub stamp_sec: i64,
    /// Header stamp, nanoseconds.
    pub stamp_nanosec: u32,
    /// Header frame id.
    pub frame_id: String,
    /// Angle of the first beam, rad.
    pub angle_min: f32,
    /// Angle of the last beam, rad (as the driver wrote it; not used for beam angles).
    pub angle_max: f32,
    /// Angle between beams, rad.
    pub angle_increment: f32,
    /// Time between beams, s.
    pub time_increment: f32,
    /// Time between scans, s.
    pub scan_time: f32,
    /// Smallest valid range, m.
    pub range_min: f32,
    /// Largest valid range, m.
    pub range_max: f32,
    /// Ranges, m.
    pub ranges: Vec<f32>,
    /// Intensities (empty when the driver gives none).
    pub intensities: Vec<f32>,
    /// Echoes after the first left out of a `MultiEchoLaserScan`'s ranges and intensities
    /// (0 for a `LaserScan`).
    pub echoes_left_out: usize,
}

/// The scan message types read, by their ROS 1 and ROS 2 names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScanMsgType {
    /// `sensor_msgs/LaserScan`, `sensor_msgs/msg/LaserScan`.
    LaserScan,
    /// `sensor_msgs/MultiEchoLaserScan`, `sensor_msgs/msg/MultiEchoLaserScan`: each beam's
    /// first echo.
    MultiEcho,
}

impl ScanMsgType {
    /// The type of the ROS 1 name `name` (`sensor_msgs/LaserScan`), `None` for any other.
    #[must_use]
    pub fn ros1(name: &str) -> Option<Self> {
        match name {
            "sensor_msgs/LaserScan" => Some(Self::LaserScan),
            "sensor_msgs/MultiEchoLaserScan" => Some(Self::MultiEcho),
            _ => None,
        }
    }

    /// The type of the ROS 2 name `name` (`sensor_msgs/msg/LaserScan`), `None` for any other.
    #[must_use]
    pub fn ros2(name: &str) -> Option<Self> {
        match name {
            "sensor_msgs/msg/LaserScan" => Some(Self::LaserScan),
            "sensor_msgs/msg/MultiEchoLaserScan" => Some(Self::MultiEcho),
            _ => None,
        }
    }
}

impl LaserScanMsg {
    /// The header stamp in seconds, or `None` when it is zero (unset).
    #[must_use]
    pub fn stamp(&self) -> Option<f64> {
        if self.stamp_sec == 0 && self.stamp_nanosec == 0 {
            None
        } else {
            Some(self.stamp_sec as f64 + f64::from(self.stamp_nanosec) * 1e-9)
        }
    }

    /// The scan in laserlines' model: beam `i` at `angle_min + i * angle_increment`; empty
    /// intensities become `None`. Not validated here.
    #[must_use]
    pub fn to_scan(&self) -> laserlines::Scan {
        let widen = |v: &[f32]| v.iter().map(|x| f64::from(*x)).collect::<Vec<f64>>();
        laserlines::Scan {
            angle_min: f64::from(self.angle_min),
            angle_increment: f64::from(self.angle_increment),
            range_min: f64::from(self.range_min),
            range_max: f64::from(self.range_max),
            ranges: widen(&self.ranges),
            intensities: if self.intensities.is_empty() {
                None
            } else {
                Some(widen(&self.intensities))
            },
            stamp: self.stamp(),
        }
    }
}

/// The fields after the header, identical in both serializations but for alignment.
fn body(w: &mut Wire<'_>, msg: &mut LaserScanMsg, kind: ScanMsgType) -> Result<(), DecodeError> {
    msg.angle_min = w.f32("angle_min")?;
    msg.angle_max = w.f32("angle_max")?;
    msg.angle_increment = w.f32("angle_increment")?;
    msg.time_increment = w.f32("time_increment")?;
    msg.scan_time = w.f32("scan_time")?;
    msg.range_min = w.f32("range_min")?;
    msg.range_max = w.f32("range_max")?;
    match kind {
        ScanMsgType::LaserScan => {
            msg.ranges = w.f32_seq("ranges")?;
            msg.intensities = w.f32_seq("intensities")?;
        }
        ScanMsgType::MultiEcho => {
            let (ranges, a) = w.first_echoes("ranges")?;
            let (intensities, b) = w.first_echoes("intensities")?;
            (msg.ranges, msg.intensities, msg.echoes_left_out) = (ranges, intensities, a + b);
        }
    }
    Ok(())
}

/// Decodes a ROS 1 `sensor_msgs/LaserScan` (little-endian ROS serialization); bytes after
/// the intensities are left alone (see [`decode_ros1_whole`]).
///
/// # Errors
/// A [`DecodeError`] naming the field that runs past the end of `data`.
pub fn decode_ros1(data: &[u8]) -> Result<LaserScanMsg, DecodeError> {
    decode_ros1_as(data, ScanMsgType::LaserScan)
}

/// [`decode_ros1`] of a message of type `kind`.
///
/// # Errors
/// As [`decode_ros1`].
pub fn decode_ros1_as(data: &[u8], kind: ScanMsgType) -> Result<LaserScanMsg, DecodeError> {
    decode_ros1_at(data, kind).map(|(msg, _)| msg)
}

/// [`decode_ros1`] of a message that must end right after its intensities, as a ROS bag's
/// message data does.
///
/// # Errors
/// As [`decode_ros1`], and a [`DecodeError`] on `intensities` for bytes left after them.
pub fn decode_ros1_whole(data: &[u8]) -> Result<LaserScanMsg, DecodeError> {
    decode_ros1_whole_as(data, ScanMsgType::LaserScan)
}

/// [`decode_ros1_whole`] of a message of type `kind`.
///
/// # Errors
/// As [`decode_ros1_whole`].
pub fn decode_ros1_whole_as(data: &[u8], kind: ScanMsgType) -> Result<LaserScanMsg, DecodeError> {
    let (msg, end) = decode_ros1_at(data, kind)?;
    if end != data.len() {
        return Err(DecodeError {
            offset: end,
            field: "intensities",
            expected: "the end of the message".to_owned(),
            found: format!("{} more bytes", data.len() - end),
        });
    }
    Ok(msg)
}

/// The message and the byte where it ends.
fn decode_ros1_at(data: &[u8], kind: ScanMsgType) -> Result<(LaserScanMsg, usize), DecodeError> {
    let mut w = Wire::new(data, 0, Endian::Little, false);
    let _seq = w.u32("header.seq")?;
    let mut msg = LaserScanMsg {
        stamp_sec: i64::from(w.u32("header.stamp.secs")?),
        stamp_nanosec: w.u32("header.stamp.nsecs")?,
        frame_id: w.string("header.frame_id", false)?,
        ..LaserScanMsg::default()
    };
    body(&mut w, &mut msg, kind)?;
    Ok((msg, w.position()))
}

/// Decodes a ROS 2 `sensor_msgs/msg/LaserScan` in CDR (XCDR1, either byte order).
///
/// # Errors
/// A [`DecodeError`] for an unknown encapsulation or a field that runs past the end of `data`.
pub fn decode_cdr(data: &[u8]) -> Result<LaserScanMsg, DecodeError> {
    decode_cdr_as(data, ScanMsgType::LaserScan)
}

/// [`decode_cdr`] of a message of type `kind`.
///
/// # Errors
/// As [`decode_cdr`].
pub fn decode_cdr_as(data: &[u8], kind: ScanMsgType) -> Result<LaserScanMsg, DecodeError> {
    let Some(head) = data.get(..4) else {
        return Err(DecodeError {
            offset: 0,
            field: "encapsulation header",
            expected: "4 bytes".to_owned(),
            found: format!("a message of {} bytes", data.len()),
        });
    };
    let endian = match (head[0], head[1]) {
        (0, 0) => Endian::Big,
        (0, 1) => Endian::Little,
        (a, b) => {
            return Err(DecodeError {
                offset: 0,
                field: "encapsulation header",
                expected: "plain CDR (00 00 big-endian or 00 01 little-endian)".to_owned(),
                found: format!("{a:02x} {b:02x}"),
            });
        }
    };
    let mut w = Wire::new(data, 4, endian, true);
    let mut msg = LaserScanMsg {
        stamp_sec: i64::from(w.i32("header.stamp.sec")?),
        stamp_nanosec: w.u32("header.stamp.nanosec")?,
        frame_id: w.string("header.frame_id", true)?,
        ..LaserScanMsg::default()
    };
    body(&mut w, &mut msg, kind)?;
    Ok(msg)
}

/// Serializes a message the way ROS does: for tests and tools that write LaserScans.
pub mod encode {
    use super::LaserScanMsg;

    /// The ROS 1 serialization (header `seq` 7).
    #[must_use]
    pub fn ros1(m: &LaserScanMsg) -> Vec<u8> {
        let flat = [m.ranges.as_slice(), m.intensities.as_slice()];
        ros1_with(m, |o| {
            for seq in flat {
                put_seq_le(o, seq);
            }
        })
    }

    /// The ROS 1 serialization of a `sensor_msgs/MultiEchoLaserScan` with `m`'s header and
    /// scalars, `ranges` and `intensities` one echo list per beam (`m`'s own are not used).
    #[must_use]
    pub fn ros1_multi_echo(
        m: &LaserScanMsg,
        ranges: &[Vec<f32>],
        intensities: &[Vec<f32>],
    ) -> Vec<u8> {
        ros1_with(m, |o| {
            for lists in [ranges, intensities] {
                o.extend_from_slice(&(lists.len() as u32).to_le_bytes());
                for seq in lists {
                    put_seq_le(o, seq);
                }
            }
        })
    }

    fn put_seq_le(o: &mut Vec<u8>, seq: &[f32]) {
        o.extend_from_slice(&(seq.len() as u32).to_le_bytes());
        for v in seq {
            o.extend_from_slice(&v.to_le_bytes());
        }
    }

    fn ros1_with(m: &LaserScanMsg, sequences: impl FnOnce(&mut Vec<u8>)) -> Vec<u8> {
        let mut o = Vec::new();
        o.extend_from_slice(&7u32.to_le_bytes());
        o.extend_from_slice(&(m.stamp_sec as u32).to_le_bytes());
        o.extend_from_slice(&m.stamp_nanosec.to_le_bytes());
        o.extend_from_slice(&(m.frame_id.len() as u32).to_le_bytes());
        o.extend_from_slice(m.frame_id.as_bytes());
        for v in scalars(m) {
            o.extend_from_slice(&v.to_le_bytes());
        }
        sequences(&mut o);
        o
    }

    fn scalars(m: &LaserScanMsg) -> [f32; 7] {
        [
            m.angle_min,
            m.angle_max,
            m.angle_increment,
            m.time_increment,
            m.scan_time,
            m.range_min,
            m.range_max,
        ]
    }

    /// The CDR serialization of ROS 2, big-endian when `big`.
    #[must_use]
    pub fn cdr(m: &LaserScanMsg, big: bool) -> Vec<u8> {
        let flat = [m.ranges.as_slice(), m.intensities.as_slice()];
        cdr_with(m, big, |c| {
            for seq in flat {
                c.seq(seq);
            }
        })
    }

    /// The CDR serialization of a `sensor_msgs/msg/MultiEchoLaserScan`, as
    /// [`ros1_multi_echo`].
    #[must_use]
    pub fn cdr_multi_echo(
        m: &LaserScanMsg,
        big: bool,
        ranges: &[Vec<f32>],
        intensities: &[Vec<f32>],
    ) -> Vec<u8> {
        cdr_with(m, big, |c| {
            for lists in [ranges, intensities] {
                c.u32(lists.len() as u32);
                for seq in lists {
                    c.seq(seq);
                }
            }
        })
    }

    /// A CDR writer: numbers aligned to 4 from the end of the encapsulation header.
    struct Cdr {
        o: Vec<u8>,
        big: bool,
    }

    impl Cdr {
        fn u32(&mut self, v: u32) {
            while !(self.o.len() - 4).is_multiple_of(4) {
                self.o.push(0);
            }
            let b = if self.big {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            };
            self.o.extend_from_slice(&b);
        }

        fn seq(&mut self, seq: &[f32]) {
            self.u32(seq.len() as u32);
            for v in seq {
                self.u32(v.to_bits());
            }
        }
    }

    fn cdr_with(m: &LaserScanMsg, big: bool, sequences: impl FnOnce(&mut Cdr)) -> Vec<u8> {
        let mut c = Cdr {
            o: vec![0, u8::from(!big), 0, 0],
            big,
        };
        c.u32(m.stamp_sec as i32 as u32);
        c.u32(m.stamp_nanosec);
        c.u32(m.frame_id.len() as u32 + 1);
        c.o.extend_from_slice(m.frame_id.as_bytes());
        c.o.push(0);
        for v in scalars(m) {
            c.u32(v.to_bits());
        }
        sequences(&mut c);
        c.o
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> LaserScanMsg {
        LaserScanMsg {
            stamp_sec: 1_700_000_000,
            stamp_nanosec: 250_000_000,
            frame_id: "laser".to_owned(),
            angle_min: -1.5,
            angle_max: 1.5,
            angle_increment: 0.75,
            time_increment: 1e-4,
            scan_time: 0.1,
            range_min: 0.02,
            range_max: 30.0,
            ranges: vec![1.0, f32::INFINITY, f32::NAN, 0.0, 31.5],
            intensities: vec![10.0, 0.0, 0.0, 0.0, 3.5],
            echoes_left_out: 0,
        }
    }

    fn same(a: &LaserScanMsg, b: &LaserScanMsg) {
        let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&a.ranges), bits(&b.ranges));
        assert_eq!(bits(&a.intensities), bits(&b.intensities));
        let strip = |m: &LaserScanMsg| LaserScanMsg {
            ranges: vec![],
            intensities: vec![],
            ..m.clone()
        };
        assert_eq!(strip(a), strip(b));
    }

    #[test]
    fn ros1_and_cdr_round_trip_every_field() {
        let m = sample();
        same(&decode_ros1(&encode::ros1(&m)).unwrap(), &m);
        same(&decode_cdr(&encode::cdr(&m, false)).unwrap(), &m);
        same(&decode_cdr(&encode::cdr(&m, true)).unwrap(), &m);
        // A frame id whose length is not a multiple of 4 moves the alignment.
        for id in ["", "a", "ab", "abc", "abcd"] {
            let m = LaserScanMsg {
                frame_id: id.to_owned(),
                ..sample()
            };
            same(&decode_cdr(&encode::cdr(&m, false)).unwrap(), &m);
        }
    }

    #[test]
    fn truncation_anywhere_is_an_error_naming_a_field() {
        let m = sample();
        for data in [encode::ros1(&m), encode::cdr(&m, false)] {
            for cut in 0..data.len() {
                let r = if data[..4] == [0, 1, 0, 0] {
                    decode_cdr(&data[..cut])
                } else {
                    decode_ros1(&data[..cut])
                };
                let e = r.unwrap_err();
                assert!(e.offset <= cut, "{e}");
            }
        }
    }

    #[test]
    fn a_whole_message_ends_after_its_intensities() {
        let mut data = encode::ros1(&sample());
        same(&decode_ros1_whole(&data).unwrap(), &sample());
        data.extend_from_slice(&[1, 2, 3]);
        // The lenient decoder reads the message; the whole-message one names the extra bytes.
        same(&decode_ros1(&data).unwrap(), &sample());
        let e = decode_ros1_whole(&data).unwrap_err();
        assert_eq!((e.field, e.offset), ("intensities", data.len() - 3));
        assert_eq!(e.found, "3 more bytes");
    }

    /// Three beams: two echoes, none, one; intensities likewise.
    fn echoes() -> (Vec<Vec<f32>>, Vec<Vec<f32>>) {
        (
            vec![vec![1.5, 4.0], vec![], vec![2.25]],
            vec![vec![100.0, 7.0], vec![], vec![50.0]],
        )
    }

    #[test]
    fn multi_echo_scans_keep_each_beams_first_echo() {
        let head = LaserScanMsg {
            ranges: vec![],
            intensities: vec![],
            ..sample()
        };
        let (ranges, intensities) = echoes();
        let kind = ScanMsgType::MultiEcho;
        for (data, decoded) in [
            (
                encode::ros1_multi_echo(&head, &ranges, &intensities),
                decode_ros1_whole_as as fn(&[u8], ScanMsgType) -> _,
            ),
            (
                encode::cdr_multi_echo(&head, false, &ranges, &intensities),
                decode_cdr_as,
            ),
            (
                encode::cdr_multi_echo(&head, true, &ranges, &intensities),
                decode_cdr_as,
            ),
        ] {
            let m = decoded(&data, kind).unwrap();
            let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&m.ranges), bits(&[1.5, f32::NAN, 2.25]));
            assert_eq!(bits(&m.intensities), bits(&[100.0, f32::NAN, 50.0]));
            assert_eq!(m.echoes_left_out, 2);
            assert_eq!((m.frame_id.as_str(), m.angle_increment), ("laser", 0.75));
            // Every cut is an error naming the field, never a panic.
            for cut in 0..data.len() {
                let e = decoded(&data[..cut], kind).unwrap_err();
                assert!(e.offset <= cut, "{e}");
            }
        }
        assert_eq!(
            ScanMsgType::ros1("sensor_msgs/MultiEchoLaserScan"),
            Some(kind)
        );
        assert_eq!(
            ScanMsgType::ros2("sensor_msgs/msg/MultiEchoLaserScan"),
            Some(kind)
        );
        assert_eq!(ScanMsgType::ros2("sensor_msgs/MultiEchoLaserScan"), None);
    }

    #[test]
    fn a_huge_echo_count_is_an_error_naming_the_list() {
        let head = LaserScanMsg {
            ranges: vec![],
            intensities: vec![],
            ..sample()
        };
        let mut data = encode::ros1_multi_echo(&head, &[vec![1.0]], &[]);
        // The first beam's echo list claims 2^30 values.
        let at = data.len() - 4 - 4 - 4;
        data[at..at + 4].copy_from_slice(&(1u32 << 30).to_le_bytes());
        let e = decode_ros1_as(&data, ScanMsgType::MultiEcho).unwrap_err();
        assert_eq!((e.field, e.offset), ("ranges", at));
        assert!(
            e.expected
                .starts_with("echo list 0 of 1: 1073741824 float32"),
            "{e}"
        );
        // Decoded as a plain LaserScan, the same bytes do not fit either.
        assert!(decode_ros1_whole(&data).is_err());
    }

    #[test]
    fn unknown_encapsulation_is_named() {
        let mut d = encode::cdr(&sample(), false);
        d[1] = 7;
        let e = decode_cdr(&d).unwrap_err();
        assert_eq!(e.field, "encapsulation header");
        assert_eq!(e.found, "00 07");
    }

    #[test]
    fn stamps_and_scan_conversion() {
        let m = sample();
        let s = m.to_scan();
        assert_eq!(s.stamp, Some(1_700_000_000.25));
        assert_eq!(s.angle_increment, 0.75);
        assert_eq!(s.ranges[4], 31.5);
        assert!(s.intensities.is_some());
        let unset = LaserScanMsg::default();
        assert_eq!(unset.stamp(), None);
        assert_eq!(unset.to_scan().intensities, None);
    }
}
