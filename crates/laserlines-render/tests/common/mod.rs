//! Test support: a deterministic synthetic scan and a small XML well-formedness checker.

#![allow(dead_code, clippy::unwrap_used, clippy::expect_used)] // test support fails loudly

use laserlines::Scan;

/// xorshift64*: a tiny deterministic generator, so that the scan is the same everywhere.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed.max(1))
    }

    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Standard normal (Box-Muller).
    pub fn gauss(&mut self) -> f64 {
        let u1 = self.uniform().max(1e-300);
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
}

/// Distance along the ray `o + t (cos a, sin a)` to the segment `p`-`q`, if it hits.
fn ray_segment(o: [f64; 2], a: f64, p: [f64; 2], q: [f64; 2]) -> Option<f64> {
    let d = [a.cos(), a.sin()];
    let e = [q[0] - p[0], q[1] - p[1]];
    let den = d[0] * e[1] - d[1] * e[0];
    if den.abs() < 1e-12 {
        return None;
    }
    let w = [p[0] - o[0], p[1] - o[1]];
    let t = (w[0] * e[1] - w[1] * e[0]) / den;
    let s = (w[0] * d[1] - w[1] * d[0]) / den;
    (t > 1e-9 && (0.0..=1.0).contains(&s)).then_some(t)
}

/// Distance along the ray to a circle of radius `r` around `c`, if it hits.
fn ray_circle(o: [f64; 2], a: f64, c: [f64; 2], r: f64) -> Option<f64> {
    let d = [a.cos(), a.sin()];
    let w = [o[0] - c[0], o[1] - c[1]];
    let b = w[0] * d[0] + w[1] * d[1];
    let disc = b * b - (w[0] * w[0] + w[1] * w[1] - r * r);
    if disc < 0.0 {
        return None;
    }
    let t = -b - disc.sqrt();
    (t > 1e-9).then_some(t)
}

/// The test scene: a 4 m x 6 m room [0,4]x[0,6], a 1.0 m x 0.6 m box centred at (1.8, 4.5)
/// rotated 30 deg, and a pole of 5 cm radius at (3.2, 2.6). The URG-04LX sees it from
/// (1.3, 1.8) facing yaw 100 deg: 682 beams from -120 deg, 360/1024 deg apart, gaussian
/// range noise of 10 mm rounded to 1 mm, 1 % dropouts (no return) and 1 % spurious short
/// returns (clutter), all from a fixed seed.
pub fn room_scan() -> Scan {
    let mut walls: Vec<([f64; 2], [f64; 2])> = vec![
        ([0.0, 0.0], [4.0, 0.0]),
        ([4.0, 0.0], [4.0, 6.0]),
        ([4.0, 6.0], [0.0, 6.0]),
        ([0.0, 6.0], [0.0, 0.0]),
    ];
    let (c, th) = ([1.8, 4.5], 30.0_f64.to_radians());
    let corner = |u: f64, v: f64| {
        [
            c[0] + u * th.cos() - v * th.sin(),
            c[1] + u * th.sin() + v * th.cos(),
        ]
    };
    let box_corners = [
        corner(-0.5, -0.3),
        corner(0.5, -0.3),
        corner(0.5, 0.3),
        corner(-0.5, 0.3),
    ];
    for k in 0..4 {
        walls.push((box_corners[k], box_corners[(k + 1) % 4]));
    }
    let sensor = [1.3, 1.8];
    let yaw = 100.0_f64.to_radians();
    let angle_min = -120.0_f64.to_radians();
    let inc = (360.0_f64 / 1024.0).to_radians();
    let mut rng = Rng::new(0x5EED_2008);
    let ranges = (0..682)
        .map(|i| {
            let a = yaw + angle_min + i as f64 * inc;
            let mut t = walls
                .iter()
                .filter_map(|&(p, q)| ray_segment(sensor, a, p, q))
                .fold(f64::INFINITY, f64::min);
            if let Some(tp) = ray_circle(sensor, a, [3.2, 2.6], 0.05) {
                t = t.min(tp);
            }
            let noise = 0.01 * rng.gauss();
            let u = rng.uniform();
            if u < 0.01 {
                0.0
            } else if u < 0.02 {
                ((0.3 + 0.7 * rng.uniform()) * t * 1000.0).round() / 1000.0
            } else {
                ((t + noise) * 1000.0).round() / 1000.0
            }
        })
        .collect();
    Scan::new(angle_min, inc, 0.02, 5.6, ranges).expect("valid scan")
}

/// A 360 deg scan of the room [0,4]x[0,6] without the box and pole, from (1.3, 1.8) facing
/// +x: 360 beams 1 deg apart from -180 deg, so that the wall x = 0 lies across the scan's
/// seam; gaussian range noise of 10 mm from a fixed seed.
pub fn turn_scan() -> Scan {
    let walls: [([f64; 2], [f64; 2]); 4] = [
        ([0.0, 0.0], [4.0, 0.0]),
        ([4.0, 0.0], [4.0, 6.0]),
        ([4.0, 6.0], [0.0, 6.0]),
        ([0.0, 6.0], [0.0, 0.0]),
    ];
    let (sensor, inc) = ([1.3, 1.8], 1.0_f64.to_radians());
    let mut rng = Rng::new(0x5EED_2009);
    let ranges = (0..360)
        .map(|i| {
            let a = -std::f64::consts::PI + i as f64 * inc;
            let t = walls
                .iter()
                .filter_map(|&(p, q)| ray_segment(sensor, a, p, q))
                .fold(f64::INFINITY, f64::min);
            t + 0.01 * rng.gauss()
        })
        .collect();
    Scan::new(-std::f64::consts::PI, inc, 0.02, 8.0, ranges).expect("valid scan")
}

/// An XML element: name, attributes, children and the text directly inside it.
#[derive(Debug, Clone, Default)]
pub struct Element {
    pub name: String,
    pub attrs: Vec<(String, String)>,
    pub children: Vec<Element>,
    pub text: String,
}

impl Element {
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    pub fn has_class(&self, class: &str) -> bool {
        self.attr("class")
            .is_some_and(|c| c.split_whitespace().any(|x| x == class))
    }

    /// All descendants (depth first, self included) matching `pred`.
    pub fn find_all<'a>(&'a self, pred: &dyn Fn(&Element) -> bool) -> Vec<&'a Element> {
        let mut out = Vec::new();
        let mut stack = vec![self];
        while let Some(e) = stack.pop() {
            if pred(e) {
                out.push(e);
            }
            stack.extend(e.children.iter().rev());
        }
        out
    }

    /// Elements named `name` with class `class`.
    pub fn count(&self, name: &str, class: &str) -> usize {
        self.find_all(&|e| e.name == name && e.has_class(class))
            .len()
    }

    /// Number of `child` elements inside groups of class `class`.
    pub fn count_in_group(&self, class: &str, child: &str) -> usize {
        self.find_all(&|e| e.name == "g" && e.has_class(class))
            .iter()
            .map(|g| g.children.iter().filter(|c| c.name == child).count())
            .sum()
    }

    /// All text inside, concatenated.
    pub fn all_text(&self) -> String {
        let mut s = self.text.clone();
        for c in &self.children {
            s.push_str(&c.all_text());
        }
        s
    }
}

fn is_name_start(c: char) -> bool {
    c.is_ascii_alphabetic() || c == '_' || c == ':'
}

fn is_name_char(c: char) -> bool {
    is_name_start(c) || c.is_ascii_digit() || c == '-' || c == '.'
}

fn unescape(s: &str, at: usize) -> Result<String, String> {
    let mut out = String::new();
    let mut rest = s;
    while let Some(k) = rest.find('&') {
        out.push_str(&rest[..k]);
        let end = rest[k..]
            .find(';')
            .ok_or_else(|| format!("unterminated entity near byte {at}"))?;
        let ent = &rest[k + 1..k + end];
        match ent {
            "amp" => out.push('&'),
            "lt" => out.push('<'),
            "gt" => out.push('>'),
            "quot" => out.push('"'),
            "apos" => out.push('\''),
            e if e.starts_with("#x") => out.push(
                u32::from_str_radix(&e[2..], 16)
                    .ok()
                    .and_then(char::from_u32)
                    .ok_or_else(|| format!("bad character reference &{e}; near byte {at}"))?,
            ),
            e if e.starts_with('#') => out.push(
                e[1..]
                    .parse::<u32>()
                    .ok()
                    .and_then(char::from_u32)
                    .ok_or_else(|| format!("bad character reference &{e}; near byte {at}"))?,
            ),
            e => return Err(format!("unknown entity &{e}; near byte {at}")),
        }
        rest = &rest[k + end + 1..];
    }
    out.push_str(rest);
    Ok(out)
}

/// Parses a well-formed XML document (no DTD): balanced tags, quoted unique attributes,
/// known entities only, no `<` in attribute values, one root element, XML 1.0 characters.
pub fn parse(doc: &str) -> Result<Element, String> {
    for (i, c) in doc.char_indices() {
        let ok =
            matches!(c, '\t' | '\n' | '\r') || (c >= ' ' && c != '\u{FFFE}' && c != '\u{FFFF}');
        if !ok {
            return Err(format!("character {c:?} not allowed in XML at byte {i}"));
        }
    }
    let mut stack: Vec<Element> = vec![Element::default()];
    let mut i = 0;
    let b = doc.as_bytes();
    let mut roots = 0;
    while i < b.len() {
        if b[i] != b'<' {
            let end = doc[i..].find('<').map_or(doc.len(), |k| i + k);
            let text = &doc[i..end];
            if text.contains('>') && text.contains("]]>") {
                return Err(format!("']]>' in text at byte {i}"));
            }
            let t = unescape(text, i)?;
            if stack.len() == 1 && !t.trim().is_empty() {
                return Err(format!("text outside the root element at byte {i}"));
            }
            if let Some(top) = stack.last_mut() {
                top.text.push_str(&t);
            }
            i = end;
            continue;
        }
        if doc[i..].starts_with("<?") {
            let end = doc[i..]
                .find("?>")
                .ok_or_else(|| format!("unterminated processing instruction at byte {i}"))?;
            i += end + 2;
            continue;
        }
        if doc[i..].starts_with("<!--") {
            let end = doc[i + 4..]
                .find("-->")
                .ok_or_else(|| format!("unterminated comment at byte {i}"))?;
            i += 4 + end + 3;
            continue;
        }
        if doc[i..].starts_with("<!") {
            return Err(format!("DTD or CDATA not supported at byte {i}"));
        }
        let close = doc[i..].starts_with("</");
        let start = if close { i + 2 } else { i + 1 };
        let mut j = start;
        let chars: Vec<char> = doc[start..].chars().take(1).collect();
        if chars.first().is_none_or(|c| !is_name_start(*c)) {
            return Err(format!("bad tag name at byte {i}"));
        }
        while j < b.len() && is_name_char(b[j] as char) {
            j += 1;
        }
        let name = doc[start..j].to_owned();
        if close {
            while j < b.len() && (b[j] as char).is_ascii_whitespace() {
                j += 1;
            }
            if j >= b.len() || b[j] != b'>' {
                return Err(format!("bad closing tag </{name} at byte {i}"));
            }
            let el = stack.pop().filter(|_| !stack.is_empty());
            match el {
                Some(el) if el.name == name && !stack.is_empty() => {
                    if let Some(parent) = stack.last_mut() {
                        parent.children.push(el);
                    }
                }
                Some(el) => {
                    return Err(format!("</{name}> at byte {i} closes <{}>", el.name));
                }
                None => return Err(format!("</{name}> at byte {i} closes nothing")),
            }
            if stack.len() == 1 {
                roots += 1;
            }
            i = j + 1;
            continue;
        }
        let mut el = Element {
            name,
            ..Element::default()
        };
        loop {
            let ws = j;
            while j < b.len() && (b[j] as char).is_ascii_whitespace() {
                j += 1;
            }
            if j >= b.len() {
                return Err(format!("unterminated tag <{}> at byte {i}", el.name));
            }
            if b[j] == b'>' || doc[j..].starts_with("/>") {
                break;
            }
            if ws == j {
                return Err(format!("missing space before attribute at byte {j}"));
            }
            let k0 = j;
            if !is_name_start(b[j] as char) {
                return Err(format!("bad attribute name at byte {j}"));
            }
            while j < b.len() && is_name_char(b[j] as char) {
                j += 1;
            }
            let key = doc[k0..j].to_owned();
            if j >= b.len() || b[j] != b'=' {
                return Err(format!("attribute {key} without '=' at byte {j}"));
            }
            j += 1;
            let q = *b.get(j).ok_or("unterminated attribute")?;
            if q != b'"' && q != b'\'' {
                return Err(format!("unquoted attribute {key} at byte {j}"));
            }
            let vend = doc[j + 1..]
                .find(q as char)
                .ok_or_else(|| format!("unterminated attribute {key} at byte {j}"))?;
            let raw = &doc[j + 1..j + 1 + vend];
            if raw.contains('<') {
                return Err(format!("'<' in attribute {key} at byte {j}"));
            }
            if el.attrs.iter().any(|(k, _)| *k == key) {
                return Err(format!("duplicate attribute {key} at byte {j}"));
            }
            el.attrs.push((key, unescape(raw, j)?));
            j += vend + 2;
        }
        if stack.len() == 1 && roots > 0 {
            return Err(format!("second root element <{}> at byte {i}", el.name));
        }
        if b[j] == b'>' {
            stack.push(el);
            i = j + 1;
        } else {
            if let Some(parent) = stack.last_mut() {
                parent.children.push(el);
            }
            if stack.len() == 1 {
                roots += 1;
            }
            i = j + 2;
        }
    }
    if stack.len() != 1 {
        let open: Vec<&str> = stack[1..].iter().map(|e| e.name.as_str()).collect();
        return Err(format!("unclosed elements at the end: {open:?}"));
    }
    let mut top = stack.pop().unwrap_or_default();
    if top.children.len() != 1 {
        return Err(format!("{} root elements", top.children.len()));
    }
    Ok(top.children.remove(0))
}

#[test]
fn checker_rejects_broken_documents() {
    assert!(parse("<a><b/></a>").is_ok());
    assert!(parse("<?xml version=\"1.0\"?>\n<a x=\"1&amp;2\">t &lt; u</a>\n").is_ok());
    for bad in [
        "<a><b></a>",
        "<a>",
        "<a></a><b/>",
        "<a x=1/>",
        "<a x=\"1\" x=\"2\"/>",
        "<a>x & y</a>",
        "<a x=\"<\"/>",
        "<a>\u{1}</a>",
        "text",
        "<a></b>",
        "<a x=\"1\"y=\"2\"/>",
        "<a>&bogus;</a>",
    ] {
        assert!(parse(bad).is_err(), "accepted {bad:?}");
    }
    let e = parse("<a><g class=\"p q\"><c/><c/></g><g class=\"p\"/></a>").unwrap();
    assert_eq!(e.count("g", "p"), 2);
    assert_eq!(e.count_in_group("q", "c"), 2);
}
