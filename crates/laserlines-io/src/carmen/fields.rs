//! The fields of one CARMEN line, read in order, with errors naming the line and the
//! field; and the fast exact parser of plain decimals.

use std::str::SplitAsciiWhitespace;

use crate::error::{ReadError, SourcePos, shown};
use crate::record::Pose2;

use super::{Laser, is_no_return};

/// Exact powers of ten as `f64` (every one up to 1e22 is representable).
pub(super) const POW10: [f64; 16] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
];

/// Parses a number exactly as `str::parse::<f64>` does, faster for the plain decimals CARMEN
/// writes (`-12.345`): with at most 15 digits the digits form an exact integer `m` and
/// `m / 10^k` is one correctly rounded division, the same value the standard parser gives.
/// Anything else (exponents, `inf`, long numbers) goes to the standard parser.
pub(super) fn parse_number(token: &str) -> Option<f64> {
    let bytes = token.as_bytes();
    let (negative, digits) = match bytes.first() {
        Some(b'-') => (true, &bytes[1..]),
        Some(b'+') => (false, &bytes[1..]),
        _ => (false, bytes),
    };
    let mut mantissa: u64 = 0;
    let mut count = 0usize;
    let mut fraction = 0usize;
    let mut dot = false;
    for &b in digits {
        match b {
            b'0'..=b'9' => {
                count += 1;
                if count > 15 {
                    return token.parse().ok();
                }
                mantissa = mantissa * 10 + u64::from(b - b'0');
                if dot {
                    fraction += 1;
                }
            }
            b'.' if !dot => dot = true,
            _ => return token.parse().ok(),
        }
    }
    if count == 0 {
        return token.parse().ok();
    }
    let value = mantissa as f64 / POW10[fraction];
    Some(if negative { -value } else { value })
}

/// The fields of one line, read in order, with errors naming line and field.
pub(super) struct Fields<'a> {
    file: &'a str,
    line: usize,
    laser: Laser,
    text_len: usize,
    tokens: SplitAsciiWhitespace<'a>,
}

impl<'a> Fields<'a> {
    pub(super) fn new(file: &'a str, line: usize, laser: Laser, text: &'a str) -> Self {
        Self {
            file,
            line,
            laser,
            text_len: text.len(),
            tokens: text.split_ascii_whitespace(),
        }
    }

    pub(super) fn pos(&self) -> SourcePos {
        SourcePos::line(self.file, self.line)
    }

    pub(super) fn skip(&mut self) {
        self.tokens.next();
    }

    pub(super) fn field_error(
        &self,
        field: String,
        expected: &str,
        token: Option<&str>,
    ) -> ReadError {
        ReadError::Field {
            pos: self.pos(),
            field: format!("{} {field}", self.laser),
            expected: expected.to_owned(),
            found: token.map_or_else(|| "the end of the line".to_owned(), shown),
        }
    }

    /// A count (of readings or remissions).
    pub(super) fn count(&mut self, what: &str) -> Result<usize, ReadError> {
        let token = self.tokens.next();
        token
            .and_then(|t| t.parse::<usize>().ok())
            .ok_or_else(|| self.field_error(what.to_owned(), "a non-negative integer", token))
    }

    pub(super) fn number(&mut self, what: &str) -> Result<f64, ReadError> {
        self.number_at(|| what.to_owned())
    }

    pub(super) fn number_at(&mut self, what: impl FnOnce() -> String) -> Result<f64, ReadError> {
        let token = self.tokens.next();
        token
            .and_then(parse_number)
            .ok_or_else(|| self.field_error(what(), "a number", token))
    }

    /// `n` ranges in metres, "no return" markers turned into `+inf`. A range must be a
    /// number of at least 0, or `inf` (as logs converted from ROS write no return): a NaN,
    /// `-inf`, a number beyond a double (`1e400`) or a negative reading is no distance any
    /// logger writes, and an error naming it.
    pub(super) fn ranges(&mut self, n: usize) -> Result<Vec<f64>, ReadError> {
        // `n` comes from the line: never reserve more than its tokens can fill.
        let mut ranges = Vec::with_capacity(n.min(self.text_len / 2 + 1));
        for i in 0..n {
            let token = self.tokens.next();
            let r = token
                .and_then(parse_number)
                .filter(|r| {
                    *r >= 0.0
                        && (r.is_finite()
                            || token.is_some_and(|t| {
                                let t = t.strip_prefix('+').unwrap_or(t);
                                t.eq_ignore_ascii_case("inf") || t.eq_ignore_ascii_case("infinity")
                            }))
                })
                .ok_or_else(|| {
                    self.field_error(format!("range {i}"), "a number >= 0 (m) or inf", token)
                })?;
            ranges.push(if is_no_return(r) { f64::INFINITY } else { r });
        }
        Ok(ranges)
    }

    /// A finite pose triple.
    pub(super) fn pose(&mut self, x: &str, y: &str, theta: &str) -> Result<Pose2, ReadError> {
        let mut part = |what: &str| {
            let token = self.tokens.next();
            token
                .and_then(parse_number)
                .filter(|v| v.is_finite())
                .ok_or_else(|| self.field_error(what.to_owned(), "a finite number", token))
        };
        Ok(Pose2::new(part(x)?, part(y)?, part(theta)?))
    }

    /// `ipc_timestamp ipc_hostname logger_timestamp`: the ipc time stamp, which must be a
    /// finite number (a NaN or infinite one is an error, as in the pose).
    pub(super) fn stamps(&mut self) -> Result<f64, ReadError> {
        let token = self.tokens.next();
        let ipc = token
            .and_then(parse_number)
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                self.field_error("ipc_timestamp".to_owned(), "a finite number", token)
            })?;
        self.skip(); // ipc_hostname
        self.number("logger_timestamp")?;
        Ok(ipc)
    }

    /// The line has no more tokens.
    pub(super) fn end(&mut self) -> Result<(), ReadError> {
        match self.tokens.next() {
            None => Ok(()),
            Some(token) => Err(ReadError::Syntax {
                pos: self.pos(),
                expected: "the end of the line".to_owned(),
                found: shown(token),
            }),
        }
    }

    pub(super) fn count_error(
        &self,
        total: &str,
        detail: &str,
        found: usize,
        layout: &str,
    ) -> ReadError {
        ReadError::Syntax {
            pos: self.pos(),
            expected: format!("{total} tokens for {} {detail} ({layout})", self.laser),
            found: format!("{found} tokens"),
        }
    }

    /// The line has exactly `total` tokens.
    pub(super) fn check_total(
        &self,
        count: usize,
        total: Option<usize>,
        n: usize,
        m: Option<usize>,
        layout: &str,
    ) -> Result<(), ReadError> {
        if total == Some(count) {
            return Ok(());
        }
        let detail = match m {
            Some(m) => format!("with {n} ranges and {m} remissions"),
            None => format!("with {n} ranges"),
        };
        Err(self.count_error(&show_total(total), &detail, count, layout))
    }

    /// The line has at least `total` tokens.
    pub(super) fn check_at_least(
        &self,
        count: usize,
        total: Option<usize>,
        n: usize,
        layout: &str,
    ) -> Result<(), ReadError> {
        if total.is_some_and(|t| count >= t) {
            return Ok(());
        }
        let total = format!("at least {}", show_total(total));
        Err(self.count_error(&total, &format!("with {n} ranges"), count, layout))
    }
}

pub(super) fn show_total(total: Option<usize>) -> String {
    total.map_or_else(|| "more than 2^64".to_owned(), |t| t.to_string())
}
