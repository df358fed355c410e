//! Foxglove's schemas in the `json` message encoding (schema encoding `jsonschema`), as the
//! `mcap` libraries and the Foxglove SDKs write them: `foxglove.LaserScan`,
//! `foxglove.FrameTransform` and `foxglove.FrameTransforms`, decoded into the same message
//! types as their protobuf form, so that the rest of the reader treats both alike.
//!
//! - A time is `{"sec": s, "nsec": ns}` (integers; nanoseconds past a second carry into it).
//! - `ranges` and `intensities` are arrays of numbers; `null` is a beam without a reading
//!   (NaN), as `JSON.stringify` writes NaN and infinities. Python's `NaN`, `Infinity` and
//!   `-Infinity` (what `json.dumps` writes by default) are read as such.
//! - `start_angle`, `end_angle` and `ranges` are required; a missing `timestamp`,
//!   `intensities`, `translation` or `rotation` is left unset, as in protobuf; a missing
//!   coordinate is 0 (a quaternion's `w`, 1). A scan's `pose` (its origin in its frame) is
//!   not read, in JSON as in protobuf.

use foxglove::messages::{
    FrameTransform, FrameTransforms, LaserScan, Quaternion, Timestamp, Vector3,
};
use laserlines_io::error::json_kind;
use laserlines_io::json::{python_infinity, rewrite_python_tokens};
use serde_json::{Map, Value};

/// Why a JSON message does not decode: the field, what it should hold and what it holds.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field}: expected {expected}, found {found}")]
pub struct JsonMessageError {
    /// The field (dotted path; `message` for the whole text).
    pub field: String,
    /// What the field should hold.
    pub expected: String,
    /// What it holds.
    pub found: String,
}

type Result<T> = std::result::Result<T, JsonMessageError>;

fn error(field: &str, expected: &str, found: String) -> JsonMessageError {
    JsonMessageError {
        field: field.to_owned(),
        expected: expected.to_owned(),
        found,
    }
}

/// The message's top-level object.
fn object(data: &[u8], schema: &str) -> Result<Map<String, Value>> {
    let text = std::str::from_utf8(data).map_err(|e| {
        error(
            "message",
            "UTF-8 JSON text",
            format!("a byte that is not UTF-8 at byte {}", e.valid_up_to()),
        )
    })?;
    let value = match serde_json::from_str::<Value>(text) {
        Ok(v) => v,
        Err(first) => rewrite_python_tokens(text)
            .and_then(|t| serde_json::from_str::<Value>(&t).ok())
            .ok_or_else(|| {
                error(
                    "message",
                    &format!("a JSON {schema} object"),
                    format!("text that is not JSON ({first})"),
                )
            })?,
    };
    match value {
        Value::Object(map) => Ok(map),
        other => Err(error(
            "message",
            &format!("a JSON {schema} object"),
            json_kind(&other),
        )),
    }
}

/// A number, or one of the stand-ins of Python's infinities.
fn number_of(v: &Value) -> Option<f64> {
    match v {
        Value::Number(n) => n.as_f64(),
        Value::String(s) => python_infinity(s),
        _ => None,
    }
}

/// The number at `key` of `obj` (`path` names it in errors); `None` when absent or `null`.
fn number(obj: &Map<String, Value>, key: &str, path: &str) -> Result<Option<f64>> {
    match obj.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => number_of(v)
            .map(Some)
            .ok_or_else(|| error(path, "a number", json_kind(v))),
    }
}

fn required(obj: &Map<String, Value>, key: &str) -> Result<f64> {
    number(obj, key, key)?.ok_or_else(|| error(key, "a number", "nothing".to_owned()))
}

/// The array of numbers at `key` (`null` items as NaN); empty when absent or `null`.
fn numbers(obj: &Map<String, Value>, key: &str) -> Result<Vec<f64>> {
    match obj.get(key) {
        None | Some(Value::Null) => Ok(Vec::new()),
        Some(Value::Array(items)) => items
            .iter()
            .enumerate()
            .map(|(i, v)| match v {
                Value::Null => Ok(f64::NAN),
                v => number_of(v)
                    .ok_or_else(|| error(&format!("{key}[{i}]"), "a number or null", json_kind(v))),
            })
            .collect(),
        Some(v) => Err(error(key, "an array of numbers", json_kind(v))),
    }
}

/// The object at `key`; `None` when absent or `null`.
fn child<'a>(obj: &'a Map<String, Value>, key: &str) -> Result<Option<&'a Map<String, Value>>> {
    match obj.get(key) {
        None | Some(Value::Null) => Ok(None),
        Some(Value::Object(m)) => Ok(Some(m)),
        Some(v) => Err(error(key, "an object", json_kind(v))),
    }
}

/// `{"sec", "nsec"}` at `key`.
fn timestamp(obj: &Map<String, Value>, key: &str) -> Result<Option<Timestamp>> {
    let Some(t) = child(obj, key)? else {
        return Ok(None);
    };
    let part = |name: &str| -> Result<u32> {
        let path = format!("{key}.{name}");
        match t.get(name) {
            None | Some(Value::Null) => Ok(0),
            Some(v) => v
                .as_u64()
                .and_then(|n| u32::try_from(n).ok())
                .ok_or_else(|| error(&path, "a whole number from 0 to 4294967295", json_kind(v))),
        }
    };
    let (sec, nsec) = (part("sec")?, part("nsec")?);
    // Nanoseconds past a second carry into the seconds; past the last second, they stop there.
    let carried = u64::from(sec) + u64::from(nsec / 1_000_000_000);
    Ok(Some(match u32::try_from(carried) {
        Ok(sec) => Timestamp::new(sec, nsec % 1_000_000_000),
        Err(_) => Timestamp::new(u32::MAX, 999_999_999),
    }))
}

fn vector3(obj: &Map<String, Value>, key: &str) -> Result<Option<Vector3>> {
    let Some(v) = child(obj, key)? else {
        return Ok(None);
    };
    let c = |name: &str| Ok(number(v, name, &format!("{key}.{name}"))?.unwrap_or(0.0));
    Ok(Some(Vector3 {
        x: c("x")?,
        y: c("y")?,
        z: c("z")?,
    }))
}

fn quaternion(obj: &Map<String, Value>, key: &str) -> Result<Option<Quaternion>> {
    let Some(q) = child(obj, key)? else {
        return Ok(None);
    };
    let c = |name: &str, default: f64| {
        Ok(number(q, name, &format!("{key}.{name}"))?.unwrap_or(default))
    };
    Ok(Some(Quaternion {
        x: c("x", 0.0)?,
        y: c("y", 0.0)?,
        z: c("z", 0.0)?,
        w: c("w", 1.0)?,
    }))
}

fn string(obj: &Map<String, Value>, key: &str) -> Result<String> {
    match obj.get(key) {
        None | Some(Value::Null) => Ok(String::new()),
        Some(Value::String(s)) => Ok(s.clone()),
        Some(v) => Err(error(key, "a string", json_kind(v))),
    }
}

/// A `foxglove.LaserScan` in JSON.
///
/// # Errors
/// [`JsonMessageError`] naming the field that is missing or of the wrong kind.
pub fn laser_scan(data: &[u8]) -> Result<LaserScan> {
    let obj = object(data, "foxglove.LaserScan")?;
    if !matches!(obj.get("ranges"), Some(Value::Array(_))) {
        let found = obj.get("ranges").map_or("nothing".to_owned(), json_kind);
        return Err(error("ranges", "an array of numbers", found));
    }
    Ok(LaserScan {
        timestamp: timestamp(&obj, "timestamp")?,
        frame_id: string(&obj, "frame_id")?,
        pose: None,
        start_angle: required(&obj, "start_angle")?,
        end_angle: required(&obj, "end_angle")?,
        ranges: numbers(&obj, "ranges")?,
        intensities: numbers(&obj, "intensities")?,
    })
}

fn transform_of(obj: &Map<String, Value>) -> Result<FrameTransform> {
    Ok(FrameTransform {
        timestamp: timestamp(obj, "timestamp")?,
        parent_frame_id: string(obj, "parent_frame_id")?,
        child_frame_id: string(obj, "child_frame_id")?,
        translation: vector3(obj, "translation")?,
        rotation: quaternion(obj, "rotation")?,
    })
}

/// A `foxglove.FrameTransform` in JSON.
///
/// # Errors
/// [`JsonMessageError`] naming the field that is of the wrong kind.
pub fn frame_transform(data: &[u8]) -> Result<FrameTransform> {
    transform_of(&object(data, "foxglove.FrameTransform")?)
}

/// A `foxglove.FrameTransforms` in JSON: `{"transforms": [...]}`.
///
/// # Errors
/// [`JsonMessageError`] naming the field that is of the wrong kind (`transforms[i].field`).
pub fn frame_transforms(data: &[u8]) -> Result<FrameTransforms> {
    let obj = object(data, "foxglove.FrameTransforms")?;
    let transforms = match obj.get("transforms") {
        None | Some(Value::Null) => Vec::new(),
        Some(Value::Array(items)) => items
            .iter()
            .enumerate()
            .map(|(i, v)| match v {
                Value::Object(t) => transform_of(t).map_err(|e| JsonMessageError {
                    field: format!("transforms[{i}].{}", e.field),
                    ..e
                }),
                v => Err(error(
                    &format!("transforms[{i}]"),
                    "a FrameTransform object",
                    json_kind(v),
                )),
            })
            .collect::<Result<_>>()?,
        Some(v) => Err(error("transforms", "an array", json_kind(v)))?,
    };
    Ok(FrameTransforms { transforms })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_laserscan_reads_with_nulls_and_python_tokens() {
        let text = br#"{"timestamp": {"sec": 12, "nsec": 1500000000}, "frame_id": "laser",
            "start_angle": -0.5, "end_angle": 0.5, "ranges": [1.0, null, NaN, Infinity, 2],
            "intensities": [7, -Infinity, 9, 10, 11]}"#;
        let m = laser_scan(text).unwrap();
        let t = m.timestamp.unwrap();
        // 1.5 s of nanoseconds carry into the seconds.
        assert_eq!((t.sec(), t.nsec()), (13, 500_000_000));
        assert_eq!(m.frame_id, "laser");
        assert_eq!((m.start_angle, m.end_angle), (-0.5, 0.5));
        assert_eq!(m.ranges[0], 1.0);
        assert!(m.ranges[1].is_nan() && m.ranges[2].is_nan());
        assert_eq!(m.ranges[3], f64::INFINITY);
        assert_eq!(m.ranges[4], 2.0);
        assert_eq!(m.intensities[1], f64::NEG_INFINITY);
    }

    #[test]
    fn missing_and_mistyped_fields_are_named() {
        let cases: [(&[u8], &str, &str, &str); 7] = [
            (
                b"[1, 2]",
                "message",
                "a JSON foxglove.LaserScan object",
                "an array of 2 values",
            ),
            (
                b"{\"ranges\": [1]",
                "message",
                "a JSON foxglove.LaserScan object",
                "text that is not JSON",
            ),
            (b"\xff{}", "message", "UTF-8 JSON text", "at byte 0"),
            (
                br#"{"end_angle": 1, "ranges": [1]}"#,
                "start_angle",
                "a number",
                "nothing",
            ),
            (
                br#"{"start_angle": 0, "end_angle": 1}"#,
                "ranges",
                "an array of numbers",
                "nothing",
            ),
            (
                br#"{"start_angle": 0, "end_angle": 1, "ranges": [1], "timestamp": {"sec": -1}}"#,
                "timestamp.sec",
                "a whole number from 0 to 4294967295",
                "a number (-1)",
            ),
            (
                br#"{"start_angle": "0", "end_angle": 1, "ranges": [1]}"#,
                "start_angle",
                "a number",
                "a string (\"0\")",
            ),
        ];
        for (text, field, expected, found) in cases {
            let e = laser_scan(text).unwrap_err();
            assert_eq!(e.field, field, "{e}");
            assert_eq!(e.expected, expected, "{e}");
            assert!(e.found.contains(found), "{e}");
        }
    }

    #[test]
    fn transforms_read_alone_and_in_a_list() {
        let one = br#"{"parent_frame_id": "odom", "child_frame_id": "base_link",
            "translation": {"x": 1.5, "y": -2}, "rotation": {"z": 0.6, "w": 0.8}}"#;
        let t = frame_transform(one).unwrap();
        assert_eq!(
            (t.parent_frame_id.as_str(), t.child_frame_id.as_str()),
            ("odom", "base_link")
        );
        let tr = t.translation.unwrap();
        assert_eq!((tr.x, tr.y, tr.z), (1.5, -2.0, 0.0));
        let q = t.rotation.unwrap();
        assert_eq!((q.x, q.y, q.z, q.w), (0.0, 0.0, 0.6, 0.8));
        assert_eq!(t.timestamp, None);
        let list = format!(
            r#"{{"transforms": [{}, {{"child_frame_id": "odom"}}]}}"#,
            std::str::from_utf8(one).unwrap()
        );
        let l = frame_transforms(list.as_bytes()).unwrap();
        assert_eq!(l.transforms.len(), 2);
        assert_eq!(l.transforms[1].child_frame_id, "odom");
        assert_eq!(l.transforms[1].translation, None);
        let e = frame_transforms(br#"{"transforms": [{"translation": {"x": true}}]}"#).unwrap_err();
        assert_eq!(e.field, "transforms[0].translation.x");
        assert_eq!(e.found, "a boolean (true)");
    }
}
