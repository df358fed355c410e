//! A minimal SVG writer: elements always balanced, text always escaped, numbers always
//! formatted the same way, so that the output is well-formed and byte-for-byte reproducible.

use crate::style::Style;

/// Formats a pixel coordinate: three decimals, trailing zeros trimmed, never `-0`.
///
/// Non-finite values (which the drawing code never passes) are written as `0`, so that the
/// document stays valid whatever happens.
///
/// ```
/// use laserlines_render::svg::fmt_px;
/// assert_eq!(fmt_px(12.5), "12.5");
/// assert_eq!(fmt_px(1.0 / 3.0), "0.333");
/// assert_eq!(fmt_px(-0.0001), "0");
/// assert_eq!(fmt_px(f64::NAN), "0");
/// ```
#[must_use]
pub fn fmt_px(v: f64) -> String {
    fmt_trimmed(v, 3)
}

/// Formats `v` with `decimals` decimals, then trims trailing zeros (and a bare `.`); never
/// `-0`; non-finite values give `0`.
#[must_use]
pub fn fmt_trimmed(v: f64, decimals: usize) -> String {
    let mut s = fmt_fixed(v, decimals);
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
    }
    if s == "-0" { "0".to_owned() } else { s }
}

/// Formats `v` with exactly `decimals` decimals (for tick labels: `0.5`, `1.0`, `1.5`); never
/// `-0.0`; non-finite values give `0`.
#[must_use]
pub fn fmt_fixed(v: f64, decimals: usize) -> String {
    if !v.is_finite() {
        return "0".to_owned();
    }
    let s = format!("{v:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_owned()
    } else {
        s
    }
}

/// Escapes text for XML content and attribute values.
///
/// `& < > " '` become entities; characters that XML 1.0 forbids (control characters other
/// than tab, newline and carriage return, U+FFFE, U+FFFF) become U+FFFD.
///
/// ```
/// use laserlines_render::svg::escape;
/// assert_eq!(escape(r#"a<b & "c"'"#), "a&lt;b &amp; &quot;c&quot;&apos;");
/// ```
#[must_use]
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => out.push(c),
            c if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
    out
}

/// Attributes of one element, in the order they are set (which is the order written).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Attrs(Vec<(&'static str, String)>);

impl Attrs {
    /// No attributes.
    #[must_use]
    pub fn new() -> Self {
        Self(Vec::new())
    }

    /// Sets a text attribute (escaped when written).
    #[must_use]
    pub fn str(mut self, name: &'static str, value: impl Into<String>) -> Self {
        self.0.push((name, value.into()));
        self
    }

    /// Sets a numeric attribute formatted by [`fmt_px`].
    #[must_use]
    pub fn px(mut self, name: &'static str, value: f64) -> Self {
        self.0.push((name, fmt_px(value)));
        self
    }

    /// Adds the presentation attributes of `style` (stroke, fill, width, opacity, dash,
    /// class).
    #[must_use]
    pub fn style(mut self, style: &Style) -> Self {
        style.write_attrs(&mut self.0);
        self
    }

    /// The attributes as name-value pairs.
    #[must_use]
    pub fn pairs(&self) -> &[(&'static str, String)] {
        &self.0
    }
}

/// Writes SVG elements into a string, one element per line.
///
/// Every element opened is closed by [`SvgWriter::close`] or at the latest by
/// [`SvgWriter::finish`], so that the output is always balanced.
#[derive(Debug, Clone, Default)]
pub struct SvgWriter {
    out: String,
    open: Vec<&'static str>,
}

impl SvgWriter {
    /// An empty writer.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// True when nothing was written.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.out.is_empty()
    }

    fn start_tag(&mut self, name: &'static str, attrs: &Attrs) {
        self.out.push('<');
        self.out.push_str(name);
        for (k, v) in attrs.pairs() {
            self.out.push(' ');
            self.out.push_str(k);
            self.out.push_str("=\"");
            self.out.push_str(&escape(v));
            self.out.push('"');
        }
    }

    /// Opens an element that will hold children.
    pub fn open(&mut self, name: &'static str, attrs: Attrs) {
        self.start_tag(name, &attrs);
        self.out.push_str(">\n");
        self.open.push(name);
    }

    /// Closes the most recently opened element (no-op when none is open).
    pub fn close(&mut self) {
        if let Some(name) = self.open.pop() {
            self.out.push_str("</");
            self.out.push_str(name);
            self.out.push_str(">\n");
        }
    }

    /// Writes an element without children.
    pub fn leaf(&mut self, name: &'static str, attrs: Attrs) {
        self.start_tag(name, &attrs);
        self.out.push_str("/>\n");
    }

    /// Writes an element holding only `text` (escaped).
    pub fn text(&mut self, name: &'static str, attrs: Attrs, text: &str) {
        self.start_tag(name, &attrs);
        self.out.push('>');
        self.out.push_str(&escape(text));
        self.out.push_str("</");
        self.out.push_str(name);
        self.out.push_str(">\n");
    }

    /// Appends everything `other` wrote, closing its open elements first.
    pub fn append(&mut self, other: &SvgWriter) {
        self.out.push_str(&other.out);
        for name in other.open.iter().rev() {
            self.out.push_str("</");
            self.out.push_str(name);
            self.out.push_str(">\n");
        }
    }

    /// Closes every open element and returns the text.
    #[must_use]
    pub fn finish(mut self) -> String {
        while !self.open.is_empty() {
            self.close();
        }
        self.out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_fixed_and_trimmed() {
        assert_eq!(fmt_px(0.0), "0");
        assert_eq!(fmt_px(-0.0), "0");
        assert_eq!(fmt_px(1.23456), "1.235");
        assert_eq!(fmt_px(-2.5), "-2.5");
        assert_eq!(fmt_px(100.0), "100");
        assert_eq!(fmt_px(f64::INFINITY), "0");
        assert_eq!(fmt_fixed(-0.01, 1), "0.0");
        assert_eq!(fmt_fixed(1.0, 1), "1.0");
        assert_eq!(fmt_fixed(-1.5, 1), "-1.5");
        assert_eq!(fmt_trimmed(2.0, 2), "2");
    }

    #[test]
    fn escape_replaces_forbidden_characters() {
        assert_eq!(escape("\u{1}x\u{FFFF}"), "\u{FFFD}x\u{FFFD}");
        assert_eq!(escape("tab\tok"), "tab\tok");
    }

    #[test]
    fn writer_balances_and_escapes() {
        let mut w = SvgWriter::new();
        w.open("g", Attrs::new().str("class", "a\"b"));
        w.leaf("circle", Attrs::new().px("r", 1.5));
        w.open("g", Attrs::new());
        w.text("text", Attrs::new(), "x < y");
        let s = w.finish();
        assert_eq!(
            s,
            "<g class=\"a&quot;b\">\n<circle r=\"1.5\"/>\n<g>\n<text>x &lt; y</text>\n</g>\n</g>\n"
        );
    }
}
