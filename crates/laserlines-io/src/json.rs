//! JSON and JSONL scans: LaserScan-like objects.
//!
//! One object per scan:
//!
//! ```json
//! {"angle_min": -1.5, "angle_increment": 0.01, "range_min": 0.02, "range_max": 5.6,
//!  "ranges": [1.0, null, 1.2], "stamp": 12.5}
//! ```
//!
//! - Required: `angle_min`, `angle_increment` (rad), `range_min`, `range_max` (m), `ranges`
//!   (m; an array of numbers or `null`, where `null` is "no return" and is kept as NaN).
//! - Optional (absent or `null` = not given): `angle_max` (rad; when present and `ranges` is
//!   not empty it must equal `angle_min + (n - 1) * angle_increment` within half an
//!   increment), `intensities` (numbers or `null`, one per range), `stamp` (s), `pose`
//!   (`{"x": m, "y": m, "theta": rad}`, the robot's pose).
//! - Other fields (e.g. a ROS `header`, `scan_time`) are ignored.
//! - `NaN` and `Infinity` are not JSON: write `null`. Writers write every non-finite number
//!   as `null`.
//!
//! A `.json` file holds one object, or a top-level array of objects that is read one
//! element at a time. A `.jsonl` file holds one object per line; blank lines are skipped.
//! After a bad element or line the reader goes on with the next one.

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

use laserlines::{Scan, ScanError};

use crate::error::{ReadError, SourcePos, json_kind};
use crate::reader::{Input, LineItem, Lines, MAX_LINE_BYTES, ScanSource};
use crate::record::{Pose2, ScanRecord};
use crate::skip::SkipCounts;

/// A JSON text (one line of JSONL, or one element of a `.json` file) and where it starts.
pub(crate) struct Element<'a> {
    pub(crate) file: &'a str,
    pub(crate) text: &'a str,
    /// 1-based line of the text's first byte.
    pub(crate) line: usize,
    /// 1-based column of the text's first byte.
    pub(crate) column: usize,
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

    /// Position of a (parser's 1-based) line and column inside `text`.
    fn pos_of_line_column(&self, line: usize, column: usize) -> SourcePos {
        let column = column.max(1);
        if line <= 1 {
            SourcePos::line_column(self.file, self.line, self.column + column - 1)
        } else {
            SourcePos::line_column(self.file, self.line + line - 1, column)
        }
    }

    /// Byte offset of a (parser's 1-based) line and column inside `text`.
    fn offset_of_line_column(&self, line: usize, column: usize) -> usize {
        let mut start = 0;
        for _ in 1..line {
            match self.text[start..].find('\n') {
                Some(i) => start += i + 1,
                None => return self.text.len(),
            }
        }
        (start + column.saturating_sub(1)).min(self.text.len())
    }

    /// The position of the object key `"key"` (its opening quote), or the element's start.
    fn pos_of_key(&self, key: &str) -> SourcePos {
        let pattern = format!("\"{key}\"");
        let mut from = 0;
        while let Some(i) = self.text[from..].find(&pattern) {
            let at = from + i;
            let rest = self.text[at + pattern.len()..].trim_start();
            if rest.starts_with(':') {
                return self.pos_of_offset(at);
            }
            from = at + pattern.len();
        }
        self.pos_of_offset(0)
    }

    /// Parses the text as one scan record.
    pub(crate) fn parse_scan(&self) -> Result<ScanRecord, ReadError> {
        // Fast path: straight into typed fields. Anything it rejects goes through the slow
        // path, which accepts the same documents and explains what is wrong.
        if let Ok(fast) = serde_json::from_str::<FastScan>(self.text) {
            let scan = Scan {
                angle_min: fast.angle_min,
                angle_increment: fast.angle_increment,
                range_min: fast.range_min,
                range_max: fast.range_max,
                ranges: fast.ranges.0,
                intensities: fast.intensities.map(|i| i.0),
                stamp: fast.stamp,
            };
            return self.checked(scan, fast.pose, fast.angle_max);
        }
        let value: Value = serde_json::from_str(self.text).map_err(|e| self.json_error(&e))?;
        let Value::Object(obj) = value else {
            return Err(ReadError::Syntax {
                pos: self.pos_of_offset(0),
                expected: "a scan object `{...}`".to_owned(),
                found: json_kind(&value),
            });
        };
        self.scan_from_object(&obj)
    }

    fn json_error(&self, e: &serde_json::Error) -> ReadError {
        let full = e.to_string();
        let mut message = match full.rfind(" at line ") {
            Some(i) => full[..i].to_owned(),
            None => full,
        };
        let offset = self.offset_of_line_column(e.line(), e.column());
        // Bytes, not str: the parser's column need not fall on a character boundary.
        let bytes = self.text.as_bytes();
        let here = &bytes[offset.saturating_sub(1).min(bytes.len())..];
        for word in ["NaN", "-Infinity", "Infinity", "nan", "inf"] {
            let w = word.as_bytes();
            let at_word = here.starts_with(w) || here.get(1..).is_some_and(|h| h.starts_with(w));
            if at_word {
                message.push_str(&format!(
                    " (`{word}` is not JSON; write null for a beam without return)"
                ));
                break;
            }
        }
        ReadError::Json {
            pos: self.pos_of_line_column(e.line(), e.column()),
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

    /// A required number.
    fn number(&self, obj: &Map<String, Value>, key: &str) -> Result<f64, ReadError> {
        match obj.get(key) {
            Some(Value::Number(n)) => n
                .as_f64()
                .ok_or_else(|| self.field_error(key, key, "a number", format!("`{n}`"))),
            Some(other) => Err(self.field_error(key, key, "a number", json_kind(other))),
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

    fn pose(&self, obj: &Map<String, Value>) -> Result<Option<Pose2>, ReadError> {
        let expected = "an object {\"x\": m, \"y\": m, \"theta\": rad} or null";
        match obj.get("pose") {
            None | Some(Value::Null) => Ok(None),
            Some(Value::Object(p)) => {
                let mut parts = [0.0; 3];
                for (part, name) in parts.iter_mut().zip(["x", "y", "theta"]) {
                    match p.get(name).and_then(Value::as_f64) {
                        Some(v) => *part = v,
                        None => {
                            let found = match p.get(name) {
                                Some(v) => json_kind(v),
                                None => "nothing (the field is missing)".to_owned(),
                            };
                            return Err(self.field_error(
                                &format!("pose.{name}"),
                                "pose",
                                "a number",
                                found,
                            ));
                        }
                    }
                }
                Ok(Some(Pose2::new(parts[0], parts[1], parts[2])))
            }
            Some(other) => Err(self.field_error("pose", "pose", expected, json_kind(other))),
        }
    }

    fn scan_from_object(&self, obj: &Map<String, Value>) -> Result<ScanRecord, ReadError> {
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
        let stamp = self.opt_number(obj, "stamp")?;
        let pose = self.pose(obj)?;
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
        self.checked(scan, pose, angle_max)
    }

    /// Validates a parsed scan and checks `angle_max` against its beams.
    fn checked(
        &self,
        scan: Scan,
        pose: Option<Pose2>,
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
                        "angle_min + (n - 1) * angle_increment = {want} rad for n = {} \
                         ranges (within {tolerance} rad)",
                        scan.ranges.len()
                    ),
                    format!("{angle_max}"),
                ));
            }
        }
        Ok(ScanRecord {
            scan,
            pose,
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
    angle_max: Option<f64>,
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

/// Reads JSONL: one scan object per line.
pub(crate) struct JsonlSource {
    name: String,
    lines: Lines,
}

impl JsonlSource {
    pub(crate) fn new(name: &str, input: Input) -> Self {
        Self {
            name: name.to_owned(),
            lines: Lines::new(name, input),
        }
    }
}

impl ScanSource for JsonlSource {
    fn next_record(&mut self, _skipped: &mut SkipCounts) -> Option<Result<ScanRecord, ReadError>> {
        loop {
            let item = match self.lines.next_line()? {
                Ok(item) => item,
                Err(e) => return Some(Err(e)),
            };
            match item {
                LineItem::NotUtf8(e) => return Some(Err(e)),
                LineItem::Text(line, text) => {
                    if text.trim().is_empty() {
                        continue;
                    }
                    let element = Element {
                        file: &self.name,
                        text,
                        line,
                        column: 1,
                    };
                    return Some(element.parse_scan());
                }
            }
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum JsonState {
    Start,
    AfterSingle,
    ArrayFirst,
    ArraySeparator,
    AfterArray,
    Done,
}

/// Reads a `.json` file: one scan object, or a top-level array of them, one element at a time.
pub(crate) struct JsonSource {
    name: String,
    input: Input,
    state: JsonState,
    /// 1-based line and column of the next byte; offset of the next byte.
    line: usize,
    column: usize,
    offset: u64,
    buf: Vec<u8>,
}

/// How reading one element ended.
enum Framed {
    /// A complete element is in `buf`, starting at (line, column).
    Element(usize, usize),
    /// The input ended inside an element starting at (line, column); `buf` holds what came.
    Truncated(usize, usize),
}

impl JsonSource {
    pub(crate) fn new(name: &str, input: Input) -> Self {
        Self {
            name: name.to_owned(),
            input,
            state: JsonState::Start,
            line: 1,
            column: 1,
            offset: 0,
            buf: Vec::new(),
        }
    }

    fn here(&self) -> SourcePos {
        SourcePos::line_column(&self.name, self.line, self.column)
    }

    fn io_error(&self, source: std::io::Error) -> ReadError {
        ReadError::Io {
            pos: self.here(),
            source,
        }
    }

    fn peek(&mut self) -> Result<Option<u8>, ReadError> {
        loop {
            match self.input.fill_buf() {
                Ok(buf) => return Ok(buf.first().copied()),
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(self.io_error(e)),
            }
        }
    }

    fn bump(&mut self, b: u8) {
        self.input.consume(1);
        self.offset += 1;
        if b == b'\n' {
            self.line += 1;
            self.column = 1;
        } else {
            self.column += 1;
        }
    }

    /// Skips JSON whitespace (and a UTF-8 byte order mark at the very start); returns the
    /// next byte without consuming it.
    fn skip_ws(&mut self) -> Result<Option<u8>, ReadError> {
        loop {
            let Some(b) = self.peek()? else {
                return Ok(None);
            };
            if matches!(b, b' ' | b'\t' | b'\n' | b'\r') {
                self.bump(b);
            } else if self.offset == 0 && b == 0xEF {
                // A byte order mark is EF BB BF; anything else starting with EF is not JSON.
                self.bump(b);
                for want in [0xBB, 0xBF] {
                    match self.peek()? {
                        Some(x) if x == want => self.bump(x),
                        other => {
                            return Err(ReadError::Syntax {
                                pos: self.here(),
                                expected: "a JSON object `{` or array `[`".to_owned(),
                                found: describe_byte(other),
                            });
                        }
                    }
                }
                self.column = 1;
            } else {
                return Ok(Some(b));
            }
        }
    }

    /// Reads one element (object, array or scalar) into `buf`, tracking nesting and strings.
    fn read_element(&mut self) -> Result<Framed, ReadError> {
        self.buf.clear();
        let (line, column) = (self.line, self.column);
        let mut depth = 0usize;
        let mut in_string = false;
        let mut escaped = false;
        loop {
            let Some(b) = self.peek()? else {
                return Ok(if depth == 0 && !in_string && !self.buf.is_empty() {
                    Framed::Element(line, column)
                } else {
                    Framed::Truncated(line, column)
                });
            };
            if !in_string && depth == 0 && !self.buf.is_empty() {
                // A scalar ends at a separator; a container ended when depth came back to 0.
                let scalar = !matches!(self.buf[0], b'{' | b'[');
                if !scalar || matches!(b, b',' | b']' | b'}' | b' ' | b'\t' | b'\n' | b'\r') {
                    return Ok(Framed::Element(line, column));
                }
            }
            if self.buf.len() >= MAX_LINE_BYTES {
                return Err(ReadError::Io {
                    pos: SourcePos::line_column(&self.name, line, column),
                    source: std::io::Error::new(
                        std::io::ErrorKind::InvalidData,
                        format!("JSON element longer than {MAX_LINE_BYTES} bytes"),
                    ),
                });
            }
            self.bump(b);
            self.buf.push(b);
            if in_string {
                if escaped {
                    escaped = false;
                } else if b == b'\\' {
                    escaped = true;
                } else if b == b'"' {
                    in_string = false;
                }
            } else {
                match b {
                    b'"' => in_string = true,
                    b'{' | b'[' => depth += 1,
                    b'}' | b']' => depth = depth.saturating_sub(1),
                    _ => {}
                }
            }
        }
    }

    /// Reads the next element and parses it as a scan; truncation ends the reader.
    fn element(&mut self) -> Result<ScanRecord, ReadError> {
        let framed = self.read_element()?;
        let (line, column, truncated) = match framed {
            Framed::Element(l, c) => (l, c, false),
            Framed::Truncated(l, c) => (l, c, true),
        };
        if truncated {
            self.state = JsonState::Done;
        }
        let text = match std::str::from_utf8(&self.buf) {
            Ok(t) => t,
            Err(e) => {
                let valid = &self.buf[..e.valid_up_to()];
                let newlines = valid.iter().filter(|b| **b == b'\n').count();
                let col = match valid.iter().rposition(|b| *b == b'\n') {
                    Some(nl) => valid.len() - nl,
                    None => column + valid.len(),
                };
                return Err(ReadError::Syntax {
                    pos: SourcePos::line_column(&self.name, line + newlines, col),
                    expected: "UTF-8 text".to_owned(),
                    found: format!("the byte 0x{:02x}", self.buf[e.valid_up_to()]),
                });
            }
        };
        let element = Element {
            file: &self.name,
            text,
            line,
            column,
        };
        let result = element.parse_scan();
        if truncated {
            // The parser usually explains the truncation; if it somehow accepts the text,
            // the framing still says the input ended inside an element.
            return match result {
                Err(e) => Err(e),
                Ok(_) => Err(ReadError::Syntax {
                    pos: self.here(),
                    expected: "the rest of the JSON element".to_owned(),
                    found: "the end of the input".to_owned(),
                }),
            };
        }
        result
    }

    fn structure_error(&mut self, expected: &str, found: Option<u8>) -> ReadError {
        self.state = JsonState::Done;
        ReadError::Syntax {
            pos: self.here(),
            expected: expected.to_owned(),
            found: describe_byte(found),
        }
    }

    fn step(&mut self) -> Option<Result<ScanRecord, ReadError>> {
        loop {
            if self.state == JsonState::Done {
                return None;
            }
            let next = match self.skip_ws() {
                Ok(b) => b,
                Err(e) => {
                    self.state = JsonState::Done;
                    return Some(Err(e));
                }
            };
            match self.state {
                JsonState::Done => return None,
                JsonState::Start => match next {
                    Some(b'{') => {
                        self.state = JsonState::AfterSingle;
                        return Some(self.element());
                    }
                    Some(b'[') => {
                        self.bump(b'[');
                        self.state = JsonState::ArrayFirst;
                    }
                    None => {
                        self.state = JsonState::Done;
                        return Some(Err(ReadError::Syntax {
                            pos: self.here(),
                            expected: "a JSON scan object `{` or an array `[` of them".to_owned(),
                            found: "an empty input".to_owned(),
                        }));
                    }
                    other => {
                        return Some(Err(self.structure_error(
                            "a JSON scan object `{` or an array `[` of them",
                            other,
                        )));
                    }
                },
                JsonState::AfterSingle => {
                    self.state = JsonState::Done;
                    return next.map(|b| {
                        Err(self.structure_error(
                            "the end of the input after the scan object (for several scans \
                             use a top-level array, or JSONL with one object per line)",
                            Some(b),
                        ))
                    });
                }
                JsonState::ArrayFirst => match next {
                    Some(b']') => {
                        self.bump(b']');
                        self.state = JsonState::AfterArray;
                    }
                    None => {
                        return Some(Err(self.structure_error("a scan object or `]`", None)));
                    }
                    Some(_) => {
                        self.state = JsonState::ArraySeparator;
                        return Some(self.element());
                    }
                },
                JsonState::ArraySeparator => match next {
                    Some(b',') => {
                        self.bump(b',');
                        match self.skip_ws() {
                            Err(e) => {
                                self.state = JsonState::Done;
                                return Some(Err(e));
                            }
                            Ok(Some(b']')) | Ok(None) => {
                                let found = self.peek().ok().flatten();
                                return Some(Err(
                                    self.structure_error("a scan object after `,`", found)
                                ));
                            }
                            Ok(Some(_)) => return Some(self.element()),
                        }
                    }
                    Some(b']') => {
                        self.bump(b']');
                        self.state = JsonState::AfterArray;
                    }
                    other => {
                        return Some(Err(
                            self.structure_error("`,` or `]` after an array element", other)
                        ));
                    }
                },
                JsonState::AfterArray => {
                    self.state = JsonState::Done;
                    return next.map(|b| {
                        Err(self.structure_error("the end of the input after the array", Some(b)))
                    });
                }
            }
        }
    }
}

impl ScanSource for JsonSource {
    fn next_record(&mut self, _skipped: &mut SkipCounts) -> Option<Result<ScanRecord, ReadError>> {
        self.step()
    }
}

/// Describes a byte (or the end of input) for "found ..." messages.
fn describe_byte(b: Option<u8>) -> String {
    match b {
        None => "the end of the input".to_owned(),
        Some(b) if b.is_ascii_graphic() => format!("`{}`", b as char),
        Some(b) => format!("the byte 0x{b:02x}"),
    }
}

/// The JSON form of a scan, as the writers write it.
#[derive(Serialize)]
pub(crate) struct ScanJson<'a> {
    pub(crate) angle_min: f64,
    pub(crate) angle_max: f64,
    pub(crate) angle_increment: f64,
    pub(crate) range_min: f64,
    pub(crate) range_max: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) stamp: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) pose: Option<Pose2>,
    pub(crate) ranges: &'a [f64],
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(crate) intensities: Option<&'a [f64]>,
}

impl<'a> ScanJson<'a> {
    pub(crate) fn new(record: &'a ScanRecord) -> Self {
        let s = &record.scan;
        Self {
            angle_min: s.angle_min,
            angle_max: s.angle_max(),
            angle_increment: s.angle_increment,
            range_min: s.range_min,
            range_max: s.range_max,
            stamp: s.stamp,
            pose: record.pose,
            ranges: &s.ranges,
            intensities: s.intensities.as_deref(),
        }
    }
}
