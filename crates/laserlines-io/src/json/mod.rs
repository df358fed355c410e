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
//!   (`{"x": m, "y": m, "theta": rad}`, the robot's pose), `odometry` (the same form: the
//!   wheel odometry's pose, the one `laserlines map` uses).
//! - Without a `stamp`, a ROS message's `header.stamp` (`{"sec", "nanosec"}` of ROS 2 or
//!   `{"secs", "nsecs"}` of ROS 1; zero is no stamp, as in bags) gives it; the rest of a
//!   `header` and other fields (e.g. `scan_time`) are ignored.
//! - `NaN`, `Infinity` and `-Infinity` are not JSON, but Python's `json.dump` writes them
//!   for non-finite floats by default: outside strings they are read as NaN, `+inf` and
//!   `-inf` in `ranges` and `intensities` (`+inf`: a beam that saw nothing within range, REP
//!   117, which `null` cannot say); elsewhere `NaN` reads as `null`, and a `stamp` or a pose
//!   must be finite (an error names the field), as the scan's own check holds its limits and
//!   angles. Writers write every non-finite number as `null` but for an infinite beam
//!   (range or intensity), which they write as `Infinity` or `-Infinity` so that it reads
//!   back as it was ([`write_scan`]): a scan without one is strict JSON.
//!
//! A `.json` file holds one object, or a top-level array of objects that is read one
//! element at a time. A `.jsonl` file holds one object per line; blank lines are skipped.
//! After a bad element or line the reader goes on with the next one.

use std::ops::ControlFlow::{self, Break, Continue};

use serde::Serialize;

use crate::error::{ReadError, SourcePos};
use crate::reader::{Input, LineItem, Lines, MAX_LINE_BYTES, ScanSource};
use crate::record::{Pose2, ScanRecord};
use crate::skip::SkipCounts;

mod element;
mod tokens;

/// Whether the bytes of a JSON text, fed one at a time, lie in a string.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Strings {
    inside: bool,
    escaped: bool,
}

impl Strings {
    /// Takes the next byte; true when it belongs to a string (its quotes included).
    pub(crate) fn step(&mut self, b: u8) -> bool {
        if self.inside {
            if self.escaped {
                self.escaped = false;
            } else if b == b'\\' {
                self.escaped = true;
            } else if b == b'"' {
                self.inside = false;
            }
            true
        } else {
            self.inside = b == b'"';
            self.inside
        }
    }

    /// True inside a string.
    pub(crate) fn inside(self) -> bool {
        self.inside
    }
}

pub(crate) use element::Element;

/// JSON text as Python's `json.dump` writes it by default, for other readers of JSON: `text`
/// with every `NaN` outside strings rewritten as `null` and every `Infinity` and `-Infinity`
/// as a string that [`python_infinity`] reads back (see the module docs); `None` when the
/// text has none of them.
#[must_use]
pub fn rewrite_python_tokens(text: &str) -> Option<String> {
    tokens::rewrite(text).map(|r| r.text)
}

/// The infinity that a string of a text from [`rewrite_python_tokens`] stands for, if it is
/// one of its stand-ins.
#[must_use]
pub fn python_infinity(s: &str) -> Option<f64> {
    tokens::standin(s)
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
                        python: false,
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
        let mut strings = Strings::default();
        loop {
            let Some(b) = self.peek()? else {
                return Ok(if depth == 0 && !strings.inside() && !self.buf.is_empty() {
                    Framed::Element(line, column)
                } else {
                    Framed::Truncated(line, column)
                });
            };
            if !strings.inside() && depth == 0 && !self.buf.is_empty() {
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
            if !strings.step(b) {
                match b {
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
            python: false,
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
            let flow = match self.state {
                JsonState::Done => return None,
                JsonState::Start => self.at_start(next),
                JsonState::AfterSingle => {
                    self.state = JsonState::Done;
                    Break(next.map(|b| {
                        Err(self.structure_error(
                            "the end of the input after the scan object (for several scans \
                             use a top-level array, or JSONL with one object per line)",
                            Some(b),
                        ))
                    }))
                }
                JsonState::ArrayFirst => self.at_array_first(next),
                JsonState::ArraySeparator => self.at_array_separator(next),
                JsonState::AfterArray => {
                    self.state = JsonState::Done;
                    Break(next.map(|b| {
                        Err(self.structure_error("the end of the input after the array", Some(b)))
                    }))
                }
            };
            if let Break(item) = flow {
                return item;
            }
        }
    }

    /// At the start: one object, or the opening of an array.
    fn at_start(&mut self, next: Option<u8>) -> Flow {
        match next {
            Some(b'{') => {
                self.state = JsonState::AfterSingle;
                Break(Some(self.element()))
            }
            Some(b'[') => {
                self.bump(b'[');
                self.state = JsonState::ArrayFirst;
                Continue(())
            }
            None => {
                self.state = JsonState::Done;
                Break(Some(Err(ReadError::Syntax {
                    pos: self.here(),
                    expected: "a JSON scan object `{` or an array `[` of them".to_owned(),
                    found: "an empty input".to_owned(),
                })))
            }
            other => Break(Some(Err(self.structure_error(
                "a JSON scan object `{` or an array `[` of them",
                other,
            )))),
        }
    }

    /// After `[`: the first element or `]`.
    fn at_array_first(&mut self, next: Option<u8>) -> Flow {
        match next {
            Some(b']') => {
                self.bump(b']');
                self.state = JsonState::AfterArray;
                Continue(())
            }
            None => Break(Some(
                Err(self.structure_error("a scan object or `]`", None)),
            )),
            Some(_) => {
                self.state = JsonState::ArraySeparator;
                Break(Some(self.element()))
            }
        }
    }

    /// After an element: `,` and the next element, or `]`.
    fn at_array_separator(&mut self, next: Option<u8>) -> Flow {
        match next {
            Some(b',') => {
                self.bump(b',');
                match self.skip_ws() {
                    Err(e) => {
                        self.state = JsonState::Done;
                        Break(Some(Err(e)))
                    }
                    Ok(Some(b']')) | Ok(None) => {
                        let found = self.peek().ok().flatten();
                        Break(Some(Err(
                            self.structure_error("a scan object after `,`", found)
                        )))
                    }
                    Ok(Some(_)) => Break(Some(self.element())),
                }
            }
            Some(b']') => {
                self.bump(b']');
                self.state = JsonState::AfterArray;
                Continue(())
            }
            other => Break(Some(Err(
                self.structure_error("`,` or `]` after an array element", other)
            ))),
        }
    }
}

/// What a state of the JSON reader does with the next byte: read on, or give an item (or
/// the end).
type Flow = ControlFlow<Option<Result<ScanRecord, ReadError>>>;

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

/// The JSON form of a scan, as the writers write it, but for its beams ([`write_scan`]).
#[derive(Serialize)]
struct ScanHead {
    angle_min: f64,
    angle_max: f64,
    angle_increment: f64,
    range_min: f64,
    range_max: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    stamp: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pose: Option<Pose2>,
    #[serde(skip_serializing_if = "Option::is_none")]
    odometry: Option<Pose2>,
}

/// Writes `record` as one JSON object (no newline). Every number is written so that it
/// reads back exactly, every non-finite one as `null` but for the beams: an infinite range
/// or intensity as `Infinity` or `-Infinity`, as Python's `json.dump` writes it and this
/// module reads it (REP 117's "nothing within range" and "too near", which `null`, a beam
/// without any return, cannot say; `hough-split` reads the first as a beam that saw through
/// a gap), a NaN one as `null`. A scan without infinite beams is strict JSON. A pose or an
/// odometry with a non-finite number is no pose and is left out, as the reader would refuse
/// it.
///
/// # Errors
/// Those of the JSON encoder (none are expected on a `Vec`).
pub(crate) fn write_scan(out: &mut Vec<u8>, record: &ScanRecord) -> std::io::Result<()> {
    let s = &record.scan;
    let head = ScanHead {
        angle_min: s.angle_min,
        angle_max: s.angle_max(),
        angle_increment: s.angle_increment,
        range_min: s.range_min,
        range_max: s.range_max,
        stamp: s.stamp,
        pose: record.pose.filter(|p| p.is_finite()),
        odometry: record.odometry.filter(|p| p.is_finite()),
    };
    serde_json::to_writer(&mut *out, &head).map_err(std::io::Error::other)?;
    // The object's closing brace, reopened for the beams.
    out.pop();
    out.extend_from_slice(b",\"ranges\":");
    beams(out, &s.ranges)?;
    if let Some(intensities) = s.intensities.as_deref() {
        out.extend_from_slice(b",\"intensities\":");
        beams(out, intensities)?;
    }
    out.push(b'}');
    Ok(())
}

/// Writes `values` as a JSON array: `Infinity` and `-Infinity` for the infinite ones,
/// `null` for NaN ([`write_scan`]).
fn beams(out: &mut Vec<u8>, values: &[f64]) -> std::io::Result<()> {
    out.push(b'[');
    for (k, &v) in values.iter().enumerate() {
        if k > 0 {
            out.push(b',');
        }
        if v == f64::INFINITY {
            out.extend_from_slice(b"Infinity");
        } else if v == f64::NEG_INFINITY {
            out.extend_from_slice(b"-Infinity");
        } else {
            serde_json::to_writer(&mut *out, &v).map_err(std::io::Error::other)?;
        }
    }
    out.push(b']');
    Ok(())
}
