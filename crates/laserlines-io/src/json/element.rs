//! One JSON scan object (a line of JSONL, an element of a `.json` file) into a record, with
//! errors at the line and column of the offending key.

use serde::Deserialize;
use serde_json::{Map, Value};

use laserlines::scan::Short;
use laserlines::{Scan, ScanError};

use crate::error::{ReadError, SourcePos, json_kind};
use crate::record::{Pose2, ScanRecord};

use super::tokens::{self, Rewritten};

/// A JSON text (one line of JSONL, or one element of a `.json` file) and where it starts.
pub(crate) struct Element<'a> {
    pub(crate) file: &'a str,
    pub(crate) text: &'a str,
    /// 1-based line of the text's first byte.
    pub(crate) line: usize,
    /// 1-based column of the text's first byte.
    pub(crate) column: usize,
    /// The text is parsed in its rewritten form ([`super::tokens`]): the stand-ins of
    /// `Infinity` and `-Infinity` are read as infinities.
    pub(crate) python: bool,
}

impl Element<'_> {
    /// Position of a byte offset into `text`.
    fn pos_of_offset(&self, offset: usize) -> SourcePos {
        let before = &self.text.as_bytes()[..offset.min(self.text.len())];
        let newlines = before.iter().filter(|b| **b == b'\n').count();
        let column = match before.iter().rposition(|b| *b == b'\n') {
            Some(nl) => offset - nl,
            None => self.column + offset,
        };
        SourcePos::line_column(self.file, self.line + newlines, column)
    }

    /// The position of the object key `"key"` (its opening quote), or the element's start.
    fn pos_of_key(&self, key: &str) -> SourcePos {
        self.pos_of_offset(self.key_at(key).map_or(0, |(at, _)| at))
    }

    /// The offset of the object key `"key"` in the text, and the text of its value on.
    fn key_at(&self, key: &str) -> Option<(usize, &str)> {
        let pattern = format!("\"{key}\"");
        let mut from = 0;
        while let Some(i) = self.text[from..].find(&pattern) {
            let at = from + i;
            let rest = self.text[at + pattern.len()..].trim_start();
            if let Some(value) = rest.strip_prefix(':') {
                return Some((at, value.trim_start()));
            }
            from = at + pattern.len();
        }
        None
    }

    /// What the value of `key` is, as [`json_kind`] says, or `NaN` when it was written so
    /// (and read as `null`, [`super::tokens`]).
    fn kind_of(&self, key: &str, value: &Value) -> String {
        let nan = matches!(value, Value::Null)
            && self.key_at(key).is_some_and(|(_, v)| v.starts_with("NaN"));
        if nan {
            "`NaN`".to_owned()
        } else {
            json_kind(value)
        }
    }

    /// Parses the text as one scan record; a text that is not JSON only by Python's `NaN`,
    /// `Infinity` and `-Infinity` ([`super::tokens`]) is read with them.
    pub(crate) fn parse_scan(&self) -> Result<ScanRecord, ReadError> {
        let first = self.parse_text(self.text, None);
        if first.is_err()
            && let Some(python) = tokens::rewrite(self.text)
        {
            let rewritten = Element {
                python: true,
                ..*self
            };
            return rewritten.parse_text(&python.text, Some(&python));
        }
        first
    }

    /// [`Element::parse_scan`] of `text`: the element's own text, or its rewritten form
    /// `python`.
    fn parse_text(&self, text: &str, python: Option<&Rewritten>) -> Result<ScanRecord, ReadError> {
        // Fast path: straight into typed fields. Anything it rejects goes through the slow
        // path, which accepts the same documents and explains what is wrong (and alone reads
        // the stand-ins of a rewritten text).
        if let Some(fast) = (!self.python)
            .then(|| serde_json::from_str::<FastScan>(text).ok())
            .flatten()
            // A ROS header's stamp is read by the slow path.
            .filter(|f| f.stamp.is_some() || f.header.is_none())
        {
            let scan = Scan {
                angle_min: fast.angle_min,
                angle_increment: fast.angle_increment,
                range_min: fast.range_min,
                range_max: fast.range_max,
                ranges: fast.ranges.0,
                intensities: fast.intensities.map(|i| i.0),
                stamp: fast.stamp,
            };
            return self.checked(scan, (fast.pose, fast.odometry), fast.angle_max);
        }
        let value: Value = serde_json::from_str(text).map_err(|e| self.json_error(&e, python))?;
        let Value::Object(obj) = value else {
            return Err(ReadError::Syntax {
                pos: self.pos_of_offset(0),
                expected: "a scan object `{...}`".to_owned(),
                found: json_kind(&value),
            });
        };
        self.scan_from_object(&obj)
    }

    /// The parser's error `e`, at its place in the text as written (`python`: the text it
    /// parsed, when rewritten).
    fn json_error(&self, e: &serde_json::Error, python: Option<&Rewritten>) -> ReadError {
        let full = e.to_string();
        let mut message = match full.rfind(" at line ") {
            Some(i) => full[..i].to_owned(),
            None => full,
        };
        let offset = match python {
            None => offset_of_line_column(self.text, e.line(), e.column()),
            Some(r) => r.original_offset(offset_of_line_column(&r.text, e.line(), e.column())),
        };
        // Bytes, not str: the parser's column need not fall on a character boundary.
        let bytes = self.text.as_bytes();
        let here = &bytes[offset.saturating_sub(1).min(bytes.len())..];
        for word in ["nan", "inf", "-inf"] {
            let w = word.as_bytes();
            let at_word = here.starts_with(w) || here.get(1..).is_some_and(|h| h.starts_with(w));
            if at_word {
                let hint = if in_beam_list(&bytes[..offset.min(bytes.len())]) {
                    "write null for a beam without return, or Infinity for one that saw \
                     nothing within range"
                } else {
                    "this field needs a finite number"
                };
                message.push_str(&format!(" (`{word}` is not JSON; {hint})"));
                break;
            }
        }
        ReadError::Json {
            pos: self.pos_of_offset(offset),
            message,
        }
    }

    fn field_error(&self, field: &str, key: &str, expected: &str, found: String) -> ReadError {
        ReadError::Field {
            pos: self.pos_of_key(key),
            field: field.to_owned(),
            expected: expected.to_owned(),
            found,
        }
    }

    /// The infinity `value` stands for, in a rewritten text ([`super::tokens`]).
    fn infinity(&self, value: &Value) -> Option<f64> {
        match value {
            Value::String(s) if self.python => tokens::standin(s),
            _ => None,
        }
    }

    /// A required number (in a rewritten text also `Infinity`, `-Infinity`: the scan's check
    /// judges them).
    fn number(&self, obj: &Map<String, Value>, key: &str) -> Result<f64, ReadError> {
        let value = obj.get(key);
        if let Some(inf) = value.and_then(|v| self.infinity(v)) {
            return Ok(inf);
        }
        match value {
            Some(Value::Number(n)) => n
                .as_f64()
                .ok_or_else(|| self.field_error(key, key, "a number", format!("`{n}`"))),
            Some(other) => Err(self.field_error(key, key, "a number", self.kind_of(key, other))),
            None => Err(ReadError::Field {
                pos: self.pos_of_offset(0),
                field: key.to_owned(),
                expected: "a number".to_owned(),
                found: "nothing (the field is missing)".to_owned(),
            }),
        }
    }

    /// An optional number (absent or `null` = `None`).
    fn opt_number(&self, obj: &Map<String, Value>, key: &str) -> Result<Option<f64>, ReadError> {
        match obj.get(key) {
            None | Some(Value::Null) => Ok(None),
            Some(_) => self.number(obj, key).map(Some),
        }
    }

    /// An array of numbers or `null` (kept as NaN).
    fn number_array(&self, value: &Value, key: &str) -> Result<Vec<f64>, ReadError> {
        let expected = "an array of numbers or null";
        let Value::Array(items) = value else {
            return Err(self.field_error(key, key, expected, json_kind(value)));
        };
        let mut out = Vec::with_capacity(items.len());
        for (i, item) in items.iter().enumerate() {
            if let Some(inf) = self.infinity(item) {
                out.push(inf);
                continue;
            }
            match item {
                Value::Null => out.push(f64::NAN),
                Value::Number(n) => match n.as_f64() {
                    Some(x) => out.push(x),
                    None => {
                        return Err(self.field_error(
                            &format!("{key}[{i}]"),
                            key,
                            "a number or null",
                            format!("`{n}`"),
                        ));
                    }
                },
                other => {
                    return Err(self.field_error(
                        &format!("{key}[{i}]"),
                        key,
                        "a number or null",
                        json_kind(other),
                    ));
                }
            }
        }
        Ok(out)
    }

    /// The pose under `key` (`pose`, `odometry`).
    fn pose(&self, obj: &Map<String, Value>, key: &str) -> Result<Option<Pose2>, ReadError> {
        let expected = "an object {\"x\": m, \"y\": m, \"theta\": rad} or null";
        match obj.get(key) {
            None | Some(Value::Null) => Ok(None),
            Some(Value::Object(p)) => {
                let mut parts = [0.0; 3];
                for (part, name) in parts.iter_mut().zip(["x", "y", "theta"]) {
                    *part = self.pose_part(p, key, name)?;
                }
                Ok(Some(Pose2::new(parts[0], parts[1], parts[2])))
            }
            Some(other) => Err(self.field_error(key, key, expected, json_kind(other))),
        }
    }

    /// The part `name` (`x`, `y`, `theta`) of the pose under `key`: a finite number.
    fn pose_part(&self, p: &Map<String, Value>, key: &str, name: &str) -> Result<f64, ReadError> {
        let value = p.get(name);
        if let Some(v) = value.and_then(Value::as_f64) {
            return Ok(v);
        }
        let found = match value {
            Some(v) => match self.infinity(v) {
                Some(inf) => tokens::written(inf).to_owned(),
                None if self.python && v.is_null() => "null (`NaN` is read as null)".to_owned(),
                None => json_kind(v),
            },
            None => "nothing (the field is missing)".to_owned(),
        };
        Err(self.field_error(&format!("{key}.{name}"), key, "a finite number", found))
    }

    /// The optional `stamp`: a finite number; without one, a ROS message's `header.stamp`.
    fn stamp(&self, obj: &Map<String, Value>) -> Result<Option<f64>, ReadError> {
        match self.opt_number(obj, "stamp")? {
            Some(t) if !t.is_finite() => Err(self.field_error(
                "stamp",
                "stamp",
                "a finite number or null",
                tokens::written(t).to_owned(),
            )),
            Some(t) => Ok(Some(t)),
            None => self.header_stamp(obj),
        }
    }

    /// `header.stamp` as a ROS message written as JSON holds it (rosbridge, `ros2 topic
    /// echo`, a bag exported by a script): `{"sec", "nanosec"}` (ROS 2) or `{"secs",
    /// "nsecs"}` (ROS 1), in seconds; `None` without one, and for a zero stamp (no time, as
    /// the bag and MCAP readers take it). A `header.stamp` of another form, a negative or
    /// non-finite part, or nanoseconds of a whole second or more, is an error naming it.
    fn header_stamp(&self, obj: &Map<String, Value>) -> Result<Option<f64>, ReadError> {
        let Some(stamp) = obj.get("header").and_then(|h| h.get("stamp")) else {
            return Ok(None);
        };
        let found = |v: &Value| match self.infinity(v) {
            Some(x) => tokens::written(x).to_owned(),
            None => json_kind(v),
        };
        let pair = [("sec", "nanosec"), ("secs", "nsecs")]
            .into_iter()
            .find_map(|(s, n)| Some(((s, stamp.get(s)?), (n, stamp.get(n)?))));
        let Some(((sec_name, sec), (nsec_name, nsec))) = pair else {
            return Err(self.field_error(
                "header.stamp",
                "header",
                "{\"sec\", \"nanosec\"} (ROS 2) or {\"secs\", \"nsecs\"} (ROS 1)",
                found(stamp),
            ));
        };
        let part = |name: &str, v: &Value, below: f64| {
            v.as_f64()
                .filter(|x| (0.0..below).contains(x))
                .ok_or_else(|| {
                    let expected = if below.is_finite() {
                        "a number from 0 up to 999999999"
                    } else {
                        "a finite number from 0 up"
                    };
                    self.field_error(
                        &format!("header.stamp.{name}"),
                        "header",
                        expected,
                        found(v),
                    )
                })
        };
        let t = part(sec_name, sec, f64::INFINITY)? + part(nsec_name, nsec, 1e9)? * 1e-9;
        Ok((t > 0.0).then_some(t))
    }

    fn scan_from_object(&self, obj: &Map<String, Value>) -> Result<ScanRecord, ReadError> {
        // The output of `laserlines extract` (crate::lines) given where scans are expected.
        if !obj.contains_key("angle_min") && obj.contains_key("lines") && obj.contains_key("scan") {
            return Err(ReadError::Syntax {
                pos: self.pos_of_offset(0),
                expected: "a scan (angle_min, angle_increment, range_min, range_max, ranges)"
                    .to_owned(),
                found: "a lines record (scan, lines): this is a lines file, as `laserlines \
                        extract` writes, not a file of scans"
                    .to_owned(),
            });
        }
        let angle_min = self.number(obj, "angle_min")?;
        let angle_increment = self.number(obj, "angle_increment")?;
        let range_min = self.number(obj, "range_min")?;
        let range_max = self.number(obj, "range_max")?;
        let ranges = match obj.get("ranges") {
            Some(v) => self.number_array(v, "ranges")?,
            None => {
                return Err(ReadError::Field {
                    pos: self.pos_of_offset(0),
                    field: "ranges".to_owned(),
                    expected: "an array of numbers or null".to_owned(),
                    found: "nothing (the field is missing)".to_owned(),
                });
            }
        };
        let intensities = match obj.get("intensities") {
            None | Some(Value::Null) => None,
            Some(v) => Some(self.number_array(v, "intensities")?),
        };
        let stamp = self.stamp(obj)?;
        let poses = (self.pose(obj, "pose")?, self.pose(obj, "odometry")?);
        let angle_max = self.opt_number(obj, "angle_max")?;
        let scan = Scan {
            angle_min,
            angle_increment,
            range_min,
            range_max,
            ranges,
            intensities,
            stamp,
        };
        self.checked(scan, poses, angle_max)
    }

    /// Validates a parsed scan and checks `angle_max` against its beams.
    fn checked(
        &self,
        scan: Scan,
        (pose, odometry): (Option<Pose2>, Option<Pose2>),
        angle_max: Option<f64>,
    ) -> Result<ScanRecord, ReadError> {
        let angle_increment = scan.angle_increment;
        if let Err(source) = scan.validate() {
            let key = match source {
                ScanError::AngleMinNotFinite(_) => "angle_min",
                ScanError::BadAngleIncrement(_) | ScanError::SpanTooLarge { .. } => {
                    "angle_increment"
                }
                ScanError::BadRangeLimits { .. } => "range_min",
                ScanError::IntensityLength { .. } => "intensities",
            };
            return Err(ReadError::InvalidScan {
                pos: self.pos_of_key(key),
                source,
            });
        }
        if let Some(angle_max) = angle_max
            && !scan.ranges.is_empty()
        {
            let want = scan.angle_max();
            let tolerance = 0.5 * angle_increment.abs();
            let off = (angle_max - want).abs();
            if off.is_nan() || off > tolerance {
                return Err(self.field_error(
                    "angle_max",
                    "angle_max",
                    &format!(
                        "angle_min + (n - 1) * angle_increment = {} rad for n = {} \
                         ranges (within {} rad)",
                        Short(want),
                        scan.ranges.len(),
                        Short(tolerance)
                    ),
                    Short(angle_max).to_string(),
                ));
            }
        }
        Ok(ScanRecord {
            scan,
            pose,
            odometry,
            line: Some(self.line),
        })
    }
}

/// The scan object as typed fields, for the fast path of [`Element::parse_scan`].
#[derive(Deserialize)]
struct FastScan {
    angle_min: f64,
    angle_increment: f64,
    range_min: f64,
    range_max: f64,
    ranges: NanVec,
    #[serde(default)]
    intensities: Option<NanVec>,
    #[serde(default)]
    stamp: Option<f64>,
    #[serde(default)]
    pose: Option<Pose2>,
    #[serde(default)]
    odometry: Option<Pose2>,
    #[serde(default)]
    angle_max: Option<f64>,
    /// A ROS message's header, looked at only for its stamp ([`Element::header_stamp`]).
    #[serde(default)]
    header: Option<serde::de::IgnoredAny>,
}

/// An array of numbers or `null`, with `null` read as NaN.
struct NanVec(Vec<f64>);

impl<'de> Deserialize<'de> for NanVec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visit;
        impl<'de> serde::de::Visitor<'de> for Visit {
            type Value = NanVec;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("an array of numbers or null")
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<NanVec, A::Error> {
                let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1 << 16));
                while let Some(x) = seq.next_element::<Option<f64>>()? {
                    out.push(x.unwrap_or(f64::NAN));
                }
                Ok(NanVec(out))
            }
        }
        d.deserialize_seq(Visit)
    }
}

/// Byte offset of a (parser's 1-based) line and column inside `text`.
fn offset_of_line_column(text: &str, line: usize, column: usize) -> usize {
    let mut start = 0;
    for _ in 1..line {
        match text[start..].find('\n') {
            Some(i) => start += i + 1,
            None => return text.len(),
        }
    }
    (start + column.saturating_sub(1)).min(text.len())
}

/// Whether the end of `before` lies inside the list of `ranges` or `intensities`: the last
/// of those keys is followed by its `[` and no `]` since.
fn in_beam_list(before: &[u8]) -> bool {
    let key_at = |key: &[u8]| before.windows(key.len()).rposition(|w| w == key);
    let Some(at) = key_at(b"\"ranges\"").max(key_at(b"\"intensities\"")) else {
        return false;
    };
    let after = &before[at..];
    after.contains(&b'[') && !after.contains(&b']')
}
