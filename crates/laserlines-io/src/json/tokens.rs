//! Python's `NaN`, `Infinity` and `-Infinity`: not JSON, but what Python's `json.dump`
//! writes for non-finite floats unless told otherwise (`allow_nan=True` is its default), so
//! they are common in scans written from Python. A scan whose beams saw nothing within
//! range holds `inf` (REP 117), and that tells `hough-split` a beam saw through a gap; the
//! `null` JSON would need for it tells nothing.
//!
//! The tokens outside strings are rewritten for the JSON parser: `Infinity` and `-Infinity`
//! as the strings `"+infin"` and `"-infini"`, of the same length, which [`standin`] reads
//! as `+inf` and `-inf` where a number may be infinite (a beam, an intensity, a scan's limits
//! and angles, which the scan's check then judges) and which no number the text holds can be
//! taken for; and `NaN` as `null` (one byte longer; positions of errors are mapped back to
//! the text as written).

use super::Strings;

/// What `Infinity` becomes: a JSON string of its length (8 bytes).
const INFINITY_STANDIN: &str = "\"+infin\"";

/// What `-Infinity` becomes: a JSON string of its length (9 bytes).
const NEG_INFINITY_STANDIN: &str = "\"-infini\"";

/// A text with Python's tokens rewritten ([`rewrite`]).
#[derive(Debug)]
pub(crate) struct Rewritten {
    /// The text for the JSON parser.
    pub(crate) text: String,
    /// Offsets in `text` of the `null`s written for `NaN`, in order.
    nulls: Vec<usize>,
}

impl Rewritten {
    /// The offset in the text as written of the byte at `offset` in the rewritten text.
    pub(crate) fn original_offset(&self, offset: usize) -> usize {
        let mut shift = 0;
        for &n in &self.nulls {
            if offset >= n + 4 {
                shift += 1;
            } else if offset > n + 2 {
                // Inside the `null` past its third byte: the end of its `NaN`.
                return n + 2 - shift;
            } else {
                break;
            }
        }
        offset - shift
    }
}

/// The infinity a string of a rewritten text stands for, if it is one of the stand-ins.
pub(crate) fn standin(s: &str) -> Option<f64> {
    match s {
        "+infin" => Some(f64::INFINITY),
        "-infini" => Some(f64::NEG_INFINITY),
        _ => None,
    }
}

/// How `value` of a rewritten text was written: `Infinity` or `-Infinity` for a stand-in.
pub(crate) fn written(value: f64) -> &'static str {
    if value > 0.0 {
        "`Infinity`"
    } else {
        "`-Infinity`"
    }
}

/// The Python tokens and what each becomes.
const TOKENS: [(&[u8], &str); 3] = [
    (b"-Infinity", NEG_INFINITY_STANDIN),
    (b"Infinity", INFINITY_STANDIN),
    (b"NaN", "null"),
];

/// `text` with every `NaN`, `Infinity` and `-Infinity` outside strings (between a `[`, `,`,
/// `:` or white space and a `,`, `]`, `}` or white space) rewritten; `None` when it has
/// none.
pub(crate) fn rewrite(text: &str) -> Option<Rewritten> {
    let bytes = text.as_bytes();
    let mut out: Option<Rewritten> = None;
    // Bytes of `text` copied to `out` so far.
    let mut copied = 0;
    let (mut i, mut strings) = (0, Strings::default());
    while i < bytes.len() {
        if strings.step(bytes[i]) {
            i += 1;
            continue;
        }
        let opens = i == 0 || matches!(bytes[i - 1], b'[' | b',' | b':') || is_space(bytes[i - 1]);
        let found = opens
            .then(|| {
                TOKENS.iter().find(|(token, _)| {
                    bytes[i..].starts_with(token)
                        && bytes
                            .get(i + token.len())
                            .is_none_or(|&c| matches!(c, b',' | b']' | b'}') || is_space(c))
                })
            })
            .flatten();
        let Some(&(token, with)) = found else {
            i += 1;
            continue;
        };
        let r = out.get_or_insert_with(|| Rewritten {
            text: String::with_capacity(text.len() + 16),
            nulls: Vec::new(),
        });
        r.text.push_str(&text[copied..i]);
        if with == "null" {
            r.nulls.push(r.text.len());
        }
        r.text.push_str(with);
        i += token.len();
        copied = i;
    }
    let mut r = out?;
    r.text.push_str(&text[copied..]);
    Some(r)
}

/// JSON's white space.
fn is_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\n' | b'\r')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_outside_strings_are_rewritten() {
        let text = r#"{"ranges": [1.5, NaN, Infinity,-Infinity], "frame": "NaN Infinity"}"#;
        let r = rewrite(text).unwrap();
        assert_eq!(
            r.text,
            r#"{"ranges": [1.5, null, "+infin","-infini"], "frame": "NaN Infinity"}"#
        );
        // Offsets after the `null` are one byte further on than in the text as written.
        let at = |s: &str, needle: &str| s.find(needle).unwrap();
        assert_eq!(
            r.original_offset(at(&r.text, "\"-infini")),
            at(text, "-Infinity")
        );
        assert_eq!(r.original_offset(at(&r.text, "null")), at(text, "NaN"));
        assert_eq!(
            r.original_offset(at(&r.text, "null") + 3),
            at(text, "NaN") + 2
        );
        assert_eq!(r.original_offset(5), 5);
        assert_eq!(standin("+infin"), Some(f64::INFINITY));
        assert_eq!(standin("-infini"), Some(f64::NEG_INFINITY));
        assert_eq!(standin("inf"), None);
    }

    #[test]
    fn words_that_only_begin_with_a_token_stay() {
        for text in [
            r#"{"a": NaNa}"#,
            r#"{"a": Infinityx}"#,
            r#"{"a": xNaN}"#,
            r#"{"a": "\"NaN"}"#,
            r#"{"a": 1}"#,
        ] {
            assert!(rewrite(text).is_none(), "{text}");
        }
        let escaped = r#"{"a": "\\", "b": NaN}"#;
        assert_eq!(rewrite(escaped).unwrap().text, r#"{"a": "\\", "b": null}"#);
    }
}
