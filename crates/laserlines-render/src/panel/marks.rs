//! SVG pieces shared by panels and the canvas: path commands, arcs, wrapped text, text and
//! markers, and sane pixel sizes.

use laserlines::math::Point2;

use crate::style::{Anchor, Color, Marker, Style, TextStyle, text_width};
use crate::svg::{Attrs, SvgWriter, fmt_px};

/// Replaces a non-finite, tiny or huge pixel size by `fallback` or clamps it.
pub(crate) fn sane_px(v: f64, fallback: f64) -> f64 {
    if v.is_finite() && v > 0.0 {
        v.clamp(1.0, 20_000.0)
    } else {
        fallback
    }
}

pub(crate) fn push_cmd(d: &mut String, cmd: char, p: [f64; 2]) {
    if !d.is_empty() {
        d.push(' ');
    }
    d.push(cmd);
    d.push_str(&fmt_px(p[0]));
    d.push(' ');
    d.push_str(&fmt_px(p[1]));
}

/// Points along an arc, at most 1 deg apart (at most 3600 of them).
pub(crate) fn arc_points(center: Point2, radius: f64, from: f64, to: f64) -> Vec<Point2> {
    let sweep = to - from;
    if !(sweep.is_finite() && from.is_finite() && radius.is_finite()) {
        return Vec::new();
    }
    let n = ((sweep.abs().to_degrees()).ceil() as usize).clamp(1, 3600);
    (0..=n)
        .map(|i| {
            let a = from + sweep * i as f64 / n as f64;
            Point2::new(center.x + radius * a.cos(), center.y + radius * a.sin())
        })
        .collect()
}

/// Greedy word wrap to `max_px` (a single word longer than that stays on its own line).
pub(crate) fn wrap(text: &str, size: f64, bold: bool, max_px: f64) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut cur = String::new();
    let words = text
        .split_whitespace()
        .flat_map(|word| split_long(word, size, bold, max_px));
    for word in words {
        let candidate = if cur.is_empty() {
            word.to_owned()
        } else {
            format!("{cur} {word}")
        };
        if !cur.is_empty() && text_width(&candidate, size, bold) > max_px {
            lines.push(std::mem::take(&mut cur));
            cur = word.to_owned();
        } else {
            cur = candidate;
        }
    }
    if !cur.is_empty() {
        lines.push(cur);
    }
    lines
}

/// A word wider than `max_px` (a long file path) cut into pieces that fit, each ending after
/// a `/`, `\\`, `_`, `-` or `.` where there is one; any other word as it is.
fn split_long(word: &str, size: f64, bold: bool, max_px: f64) -> Vec<String> {
    if text_width(word, size, bold) <= max_px {
        return vec![word.to_owned()];
    }
    let mut pieces = Vec::new();
    let mut cur = String::new();
    // The length of `cur` up to its last break character.
    let mut last_break = None;
    for c in word.chars() {
        cur.push(c);
        if text_width(&cur, size, bold) > max_px && cur.chars().count() > 1 {
            let cut = last_break.unwrap_or(cur.len() - c.len_utf8());
            let rest = cur.split_off(cut);
            pieces.push(std::mem::replace(&mut cur, rest));
            last_break = None;
        }
        if matches!(c, '/' | '\\' | '_' | '-' | '.') {
            last_break = Some(cur.len());
        }
    }
    if !cur.is_empty() {
        pieces.push(cur);
    }
    pieces
}

/// Writes a `<text>` element at pixel `p`.
pub(crate) fn write_text(w: &mut SvgWriter, p: [f64; 2], text: &str, style: &TextStyle) {
    if !(p[0].is_finite() && p[1].is_finite()) {
        return;
    }
    let mut a = Attrs::new();
    if let Some(c) = &style.class {
        a = a.str("class", c.clone());
    }
    a = a
        .px("x", p[0] + style.offset[0])
        .px("y", p[1] + style.offset[1])
        .str("font-size", fmt_px(style.size));
    if style.anchor != Anchor::Start {
        a = a.str("text-anchor", style.anchor.svg());
    }
    if style.bold {
        a = a.str("font-weight", "bold");
    }
    if style.italic {
        a = a.str("font-style", "italic");
    }
    a = a.str("fill", style.color.hex());
    if style.halo {
        a = a
            .str("stroke", "#ffffff")
            .str("stroke-width", "3")
            .str("stroke-opacity", "0.85")
            .str("paint-order", "stroke");
    }
    w.text("text", a, text);
}

/// The style a marker is painted with: filled shapes take the fill (or else the stroke
/// colour), line shapes take the stroke (or else the fill colour).
pub(crate) fn marker_style(marker: Marker, style: &Style) -> Style {
    let color = style.stroke.or(style.fill).unwrap_or(Color::INK);
    match marker {
        Marker::Dot => Style {
            fill: Some(style.fill.unwrap_or(color)),
            stroke: None,
            ..style.clone()
        },
        Marker::Cross | Marker::Plus => Style {
            stroke: Some(style.stroke.unwrap_or(color)),
            fill: None,
            ..style.clone()
        },
        Marker::Circle
        | Marker::Square
        | Marker::Diamond
        | Marker::Triangle
        | Marker::TriangleRight => style.clone(),
    }
}

/// Writes one marker of `size` px centred on `p` (no style: the caller's group has it).
pub(crate) fn write_marker(w: &mut SvgWriter, p: [f64; 2], marker: Marker, size: f64) {
    let h = 0.5 * size;
    match marker {
        Marker::Dot | Marker::Circle => w.leaf(
            "circle",
            Attrs::new().px("cx", p[0]).px("cy", p[1]).px("r", h),
        ),
        Marker::Square => w.leaf(
            "rect",
            Attrs::new()
                .px("x", p[0] - h)
                .px("y", p[1] - h)
                .px("width", size)
                .px("height", size),
        ),
        Marker::Cross | Marker::Plus => {
            let mut d = String::new();
            let (a, b) = if marker == Marker::Cross {
                ([-h, -h, h, h], [-h, h, h, -h])
            } else {
                ([-h, 0.0, h, 0.0], [0.0, -h, 0.0, h])
            };
            push_cmd(&mut d, 'M', [p[0] + a[0], p[1] + a[1]]);
            push_cmd(&mut d, 'L', [p[0] + a[2], p[1] + a[3]]);
            push_cmd(&mut d, 'M', [p[0] + b[0], p[1] + b[1]]);
            push_cmd(&mut d, 'L', [p[0] + b[2], p[1] + b[3]]);
            w.leaf("path", Attrs::new().str("d", d));
        }
        Marker::Diamond | Marker::Triangle | Marker::TriangleRight => {
            let pts: Vec<[f64; 2]> = match marker {
                Marker::Diamond => vec![
                    [p[0], p[1] - h],
                    [p[0] + h, p[1]],
                    [p[0], p[1] + h],
                    [p[0] - h, p[1]],
                ],
                Marker::Triangle => vec![
                    [p[0], p[1] - h],
                    [p[0] + h, p[1] + 0.8 * h],
                    [p[0] - h, p[1] + 0.8 * h],
                ],
                _ => vec![
                    [p[0] + h, p[1]],
                    [p[0] - 0.8 * h, p[1] - 0.6 * h],
                    [p[0] - 0.8 * h, p[1] + 0.6 * h],
                ],
            };
            let s: Vec<String> = pts
                .iter()
                .map(|q| format!("{},{}", fmt_px(q[0]), fmt_px(q[1])))
                .collect();
            w.leaf("polygon", Attrs::new().str("points", s.join(" ")));
        }
    }
}
