//! A small reader of the XML subset `.raf` files use: opening and empty-element tags with
//! their attributes, in order, with the line each starts on.

/// An opening or empty-element tag with its attributes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Tag<'a> {
    pub(crate) name: &'a str,
    pub(crate) attributes: Vec<(&'a str, String)>,
    pub(crate) line: usize,
}

impl Tag<'_> {
    pub(crate) fn attribute(&self, name: &str) -> Option<String> {
        self.attributes
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, v)| v.clone())
    }
}

/// The opening tags of an XML text, in order; a small reader for the subset `.raf` files
/// use: declarations, comments, CDATA and closing tags are skipped, attribute values are
/// quoted with `"` or `'`, the five predefined entities and numeric references are decoded.
pub(crate) struct Tags<'a> {
    pub(crate) text: &'a str,
    pub(crate) pos: usize,
}

impl<'a> Tags<'a> {
    pub(crate) fn new(text: &'a str) -> Self {
        Self { text, pos: 0 }
    }

    pub(crate) fn line_at(&self, pos: usize) -> usize {
        1 + self.text.as_bytes()[..pos.min(self.text.len())]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
    }

    pub(crate) fn skip_past(
        &mut self,
        start: usize,
        end: &str,
        what: &str,
    ) -> Result<(), (usize, String)> {
        match self.text[start..].find(end) {
            Some(k) => {
                self.pos = start + k + end.len();
                Ok(())
            }
            None => {
                self.pos = self.text.len();
                Err((self.line_at(start), format!("unclosed {what}")))
            }
        }
    }
}

impl<'a> Iterator for Tags<'a> {
    type Item = Result<Tag<'a>, (usize, String)>;

    fn next(&mut self) -> Option<Self::Item> {
        loop {
            let start = self.pos + self.text.get(self.pos..)?.find('<')?;
            let rest = &self.text[start..];
            let skipped = if rest.starts_with("<!--") {
                Some(self.skip_past(start, "-->", "comment"))
            } else if rest.starts_with("<![CDATA[") {
                Some(self.skip_past(start, "]]>", "CDATA section"))
            } else if rest.starts_with("<?") {
                Some(self.skip_past(start, "?>", "declaration"))
            } else if rest.starts_with("<!") || rest.starts_with("</") {
                Some(self.skip_past(start, ">", "tag"))
            } else {
                None
            };
            match skipped {
                Some(Ok(())) => continue,
                Some(Err(e)) => return Some(Err(e)),
                None => {}
            }
            let line = self.line_at(start);
            let Some(len) = tag_end(rest) else {
                self.pos = self.text.len();
                return Some(Err((line, "unclosed tag".to_owned())));
            };
            self.pos = start + len + 1;
            let inner = rest[1..len].trim_end_matches('/');
            return Some(parse_tag(inner, line));
        }
    }
}

/// The offset of the `>` closing the tag at the start of `s`, outside quoted values.
pub(crate) fn tag_end(s: &str) -> Option<usize> {
    let mut quote: Option<char> = None;
    for (i, ch) in s.char_indices().skip(1) {
        match (quote, ch) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), _) => {}
            (None, '"' | '\'') => quote = Some(ch),
            (None, '>') => return Some(i),
            (None, '<') => return None,
            _ => {}
        }
    }
    None
}

pub(crate) fn parse_tag(inner: &str, line: usize) -> Result<Tag<'_>, (usize, String)> {
    let inner = inner.trim();
    let name_end = inner
        .find(|c: char| c.is_whitespace())
        .unwrap_or(inner.len());
    let name = &inner[..name_end];
    if name.is_empty() {
        return Err((line, "a tag without a name".to_owned()));
    }
    let mut attributes = Vec::new();
    let mut rest = inner[name_end..].trim_start();
    while !rest.is_empty() {
        let Some(eq) = rest.find('=') else {
            return Err((line, format!("attribute {rest:?} has no value")));
        };
        let key = rest[..eq].trim();
        if key.is_empty() || key.contains(char::is_whitespace) {
            return Err((line, format!("bad attribute name {key:?}")));
        }
        let after = rest[eq + 1..].trim_start();
        let Some(q) = after.chars().next().filter(|c| *c == '"' || *c == '\'') else {
            return Err((line, format!("the value of {key:?} is not quoted")));
        };
        let Some(close) = after[1..].find(q) else {
            return Err((line, format!("the value of {key:?} is not closed")));
        };
        let raw = &after[1..1 + close];
        let value = decode_entities(raw)
            .ok_or_else(|| (line, format!("bad entity in the value of {key:?}")))?;
        attributes.push((key, value));
        rest = after[close + 2..].trim_start();
    }
    Ok(Tag {
        name,
        attributes,
        line,
    })
}

pub(crate) fn decode_entities(raw: &str) -> Option<String> {
    if !raw.contains('&') {
        return Some(raw.to_owned());
    }
    let mut out = String::with_capacity(raw.len());
    let mut rest = raw;
    while let Some(amp) = rest.find('&') {
        out.push_str(&rest[..amp]);
        let semi = rest[amp..].find(';')? + amp;
        let entity = &rest[amp + 1..semi];
        let ch = match entity {
            "lt" => '<',
            "gt" => '>',
            "amp" => '&',
            "quot" => '"',
            "apos" => '\'',
            e if e.starts_with("#x") => char::from_u32(u32::from_str_radix(&e[2..], 16).ok()?)?,
            e if e.starts_with('#') => char::from_u32(e[1..].parse().ok()?)?,
            _ => return None,
        };
        out.push(ch);
        rest = &rest[semi + 1..];
    }
    out.push_str(rest);
    Some(out)
}
