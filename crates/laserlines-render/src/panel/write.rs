//! Writing a panel as SVG: the frame, grid, ticks, labels, title, the clipped drawing and
//! the scale bar.

use super::marks::{push_cmd, wrap, write_text};
use super::{LABEL_FONT, Panel, TICK_FONT, TICK_LEN, TICK_SPACING, TITLE_FONT, TITLE_LINE};
use crate::geometry::{Scale, decimals_for, nice_floor, nice_step, ticks};
use crate::style::{Anchor, Color, Style, TextStyle, text_width};
use crate::svg::{Attrs, SvgWriter, fmt_fixed, fmt_px, fmt_trimmed};

impl Panel {
    pub(super) fn title_lines(&self) -> Vec<String> {
        match &self.title {
            Some(t) => wrap(t, TITLE_FONT, true, self.width.max(120.0)),
            None => Vec::new(),
        }
    }

    /// Ticks of the x axis: (value, label, major).
    pub(super) fn x_ticks(&self) -> Vec<(f64, String, bool)> {
        axis_ticks(&self.x, self.width)
    }

    pub(super) fn y_ticks(&self) -> Vec<(f64, String, bool)> {
        axis_ticks(&self.y, self.height)
    }

    /// Space around the plot area for ticks, labels and title: `[left, right, top, bottom]`,
    /// px.
    #[must_use]
    pub fn margins(&self) -> [f64; 4] {
        let label_w = self
            .y_ticks()
            .iter()
            .map(|(_, l, _)| text_width(l, TICK_FONT, false))
            .fold(0.0, f64::max);
        let left = TICK_LEN + 4.0 + label_w + 8.0 + LABEL_FONT + 2.0;
        // The last x tick label may stick out to the right.
        let right = 14.0;
        let top = 8.0 + TITLE_LINE * self.title_lines().len() as f64;
        let bottom = TICK_LEN + 4.0 + TICK_FONT + 8.0 + LABEL_FONT + 4.0;
        [left, right, top, bottom]
    }

    /// Writes the panel with its plot area's top-left corner at `origin` (px in the
    /// document); `id` must be unique in the document.
    pub(crate) fn write(&self, w: &mut SvgWriter, origin: [f64; 2], id: usize) {
        let clip_id = format!("clip-{id}");
        w.open(
            "g",
            Attrs::new().str("class", "panel").str(
                "transform",
                format!("translate({},{})", fmt_px(origin[0]), fmt_px(origin[1])),
            ),
        );
        w.open("defs", Attrs::new());
        w.open("clipPath", Attrs::new().str("id", clip_id.clone()));
        w.leaf(
            "rect",
            Attrs::new()
                .px("x", 0.0)
                .px("y", 0.0)
                .px("width", self.width)
                .px("height", self.height),
        );
        w.close();
        w.close();
        let (xt, yt) = (self.x_ticks(), self.y_ticks());
        if self.grid {
            self.write_grid(w, &xt, &yt);
        }
        w.open(
            "g",
            Attrs::new()
                .str("class", "plot")
                .str("clip-path", format!("url(#{clip_id})")),
        );
        w.append(&self.body);
        w.close();
        // Frame.
        w.leaf(
            "rect",
            Attrs::new()
                .px("x", 0.0)
                .px("y", 0.0)
                .px("width", self.width)
                .px("height", self.height)
                .style(&Style::stroke(Color::INK, 1.0).with_class("frame")),
        );
        self.write_axes(w, &xt, &yt);
        if self.scale_bar {
            self.write_scale_bar(w);
        }
        self.write_notes_and_title(w);
        w.close();
    }

    /// The grid lines at the major ticks.
    fn write_grid(
        &self,
        w: &mut SvgWriter,
        xt: &[(f64, String, bool)],
        yt: &[(f64, String, bool)],
    ) {
        let major = Style::stroke(Color::GRID, 1.0).with_class("grid");
        let mut d = String::new();
        for (v, _, is_major) in xt {
            if let (true, Some(px)) = (*is_major, self.x.map(*v)) {
                push_cmd(&mut d, 'M', [px, 0.0]);
                push_cmd(&mut d, 'L', [px, self.height]);
            }
        }
        for (v, _, is_major) in yt {
            if let (true, Some(py)) = (*is_major, self.y.map(*v)) {
                push_cmd(&mut d, 'M', [0.0, py]);
                push_cmd(&mut d, 'L', [self.width, py]);
            }
        }
        if !d.is_empty() {
            w.leaf("path", Attrs::new().str("d", d).style(&major));
        }
    }

    /// The notes over the plot and the title above it.
    fn write_notes_and_title(&self, w: &mut SvgWriter) {
        for (i, note) in self.notes.iter().enumerate() {
            let y = 28.0 + 18.0 * i as f64;
            write_text(
                w,
                [0.5 * self.width, y],
                note,
                &TextStyle::size(13.0)
                    .italic()
                    .colored(Color::GREY)
                    .anchored(Anchor::Middle)
                    .with_halo()
                    .with_class("note"),
            );
        }
        let lines = self.title_lines();
        let n = lines.len() as f64;
        for (i, line) in lines.iter().enumerate() {
            write_text(
                w,
                [0.0, -6.0 - TITLE_LINE * (n - 1.0 - i as f64) - 3.0],
                line,
                &TextStyle::size(TITLE_FONT).bold().with_class("panel-title"),
            );
        }
    }

    pub(super) fn write_axes(
        &self,
        w: &mut SvgWriter,
        xt: &[(f64, String, bool)],
        yt: &[(f64, String, bool)],
    ) {
        let mut d = String::new();
        let tick_style = TextStyle::size(TICK_FONT).with_class("tick-label");
        w.open("g", Attrs::new().str("class", "axes"));
        for (v, label, major) in xt {
            let Some(px) = self.x.map(*v) else { continue };
            let len = if *major { TICK_LEN } else { 0.6 * TICK_LEN };
            push_cmd(&mut d, 'M', [px, self.height]);
            push_cmd(&mut d, 'L', [px, self.height + len]);
            if !label.is_empty() {
                write_text(
                    w,
                    [px, self.height + TICK_LEN + 3.0 + TICK_FONT * 0.8],
                    label,
                    &tick_style.clone().anchored(Anchor::Middle),
                );
            }
        }
        for (v, label, major) in yt {
            let Some(py) = self.y.map(*v) else { continue };
            let len = if *major { TICK_LEN } else { 0.6 * TICK_LEN };
            push_cmd(&mut d, 'M', [0.0, py]);
            push_cmd(&mut d, 'L', [-len, py]);
            if !label.is_empty() {
                write_text(
                    w,
                    [-TICK_LEN - 3.0, py + 0.35 * TICK_FONT],
                    label,
                    &tick_style.clone().anchored(Anchor::End),
                );
            }
        }
        if !d.is_empty() {
            w.leaf(
                "path",
                Attrs::new()
                    .str("d", d)
                    .style(&Style::stroke(Color::INK, 1.0)),
            );
        }
        let [left, _, _, bottom] = self.margins();
        write_text(
            w,
            [0.5 * self.width, self.height + bottom - 5.0],
            &self.x_label,
            &TextStyle::size(LABEL_FONT)
                .anchored(Anchor::Middle)
                .with_class("axis-label"),
        );
        let (x, y) = (-left + LABEL_FONT, 0.5 * self.height);
        w.text(
            "text",
            Attrs::new()
                .str("class", "axis-label")
                .px("x", x)
                .px("y", y)
                .str("font-size", fmt_px(LABEL_FONT))
                .str("text-anchor", "middle")
                .str("fill", Color::INK.hex())
                .str(
                    "transform",
                    format!("rotate(-90 {} {})", fmt_px(x), fmt_px(y)),
                ),
            &self.y_label,
        );
        w.close();
    }

    pub(super) fn write_scale_bar(&self, w: &mut SvgWriter) {
        let ppm = self.px_per_unit();
        let len_m = nice_floor(0.2 * self.width / ppm);
        let len_px = len_m * ppm;
        if !(len_px.is_finite() && len_px > 4.0) {
            return;
        }
        let label = format!("{} m", fmt_trimmed(len_m, 6));
        let label_w = text_width(&label, TICK_FONT, false);
        let bar = Style::stroke(Color::INK, 1.6);
        // Preferably in the bottom margin, right of the x axis label, off the data.
        let bottom = self.margins()[3];
        let x_label_w = text_width(&self.x_label, LABEL_FONT, false);
        let bx = self.width - 1.0 - len_px;
        if bx - 6.0 - label_w >= 0.5 * (self.width + x_label_w) + 16.0 {
            let base = self.height + bottom - 5.0;
            w.open("g", Attrs::new().str("class", "scale-bar"));
            w.leaf(
                "path",
                Attrs::new()
                    .str("d", bar_path(bx, base - 3.0, len_px))
                    .style(&bar),
            );
            write_text(
                w,
                [bx - 6.0, base],
                &label,
                &TextStyle::size(TICK_FONT).anchored(Anchor::End),
            );
            w.close();
            return;
        }
        self.write_scale_bar_in_plot(w, len_px, &label, label_w);
    }

    /// The scale bar inside the plot, in the corner that covers the fewest drawn samples
    /// (bottom right on ties), on a white box.
    fn write_scale_bar_in_plot(&self, w: &mut SvgWriter, len_px: f64, label: &str, label_w: f64) {
        let bar = Style::stroke(Color::INK, 1.6);
        let box_w = len_px.max(label_w) + 12.0;
        let box_h = 28.0;
        let corners = [
            [self.width - 8.0 - box_w, self.height - 8.0 - box_h],
            [8.0, self.height - 8.0 - box_h],
            [self.width - 8.0 - box_w, 8.0],
            [8.0, 8.0],
        ];
        let covered = |c: &[f64; 2]| {
            self.ink
                .iter()
                .filter(|p| {
                    p[0] >= c[0] - 4.0
                        && p[0] <= c[0] + box_w + 4.0
                        && p[1] >= c[1] - 4.0
                        && p[1] <= c[1] + box_h + 4.0
                })
                .count()
        };
        let mut best = (usize::MAX, corners[0]);
        for c in corners {
            let n = covered(&c);
            if n < best.0 {
                best = (n, c);
            }
        }
        let [x0, y0] = best.1;
        w.open("g", Attrs::new().str("class", "scale-bar"));
        w.leaf(
            "rect",
            Attrs::new()
                .px("x", x0)
                .px("y", y0)
                .px("width", box_w)
                .px("height", box_h)
                .style(
                    &Style::stroke(Color::LIGHT_GREY, 0.8)
                        .with_fill(Color::WHITE)
                        .with_opacity(0.9),
                ),
        );
        let bx = x0 + 0.5 * (box_w - len_px);
        let by = y0 + box_h - 7.0;
        w.leaf(
            "path",
            Attrs::new().str("d", bar_path(bx, by, len_px)).style(&bar),
        );
        write_text(
            w,
            [x0 + 0.5 * box_w, by - 6.0],
            label,
            &TextStyle::size(TICK_FONT).anchored(Anchor::Middle),
        );
        w.close();
    }
}

/// Ticks of one axis: (value, label, major). Linear axes get nice steps about
/// [`TICK_SPACING`] px apart; log axes get decades (labelled) and 2..9 (unlabelled, or
/// labelled 2 and 5 when the axis spans less than two decades).
pub(super) fn axis_ticks(s: &Scale, len_px: f64) -> Vec<(f64, String, bool)> {
    if s.log {
        let lo = s.min.log10().floor();
        let hi = s.max.log10().ceil();
        if !(lo.is_finite() && hi.is_finite()) || hi - lo > 60.0 {
            return Vec::new();
        }
        let few = hi - lo <= 2.0;
        let mut out = Vec::new();
        let mut k = lo;
        while k <= hi {
            for m in 1..10 {
                let v = f64::from(m) * 10f64.powf(k);
                if v < s.min * (1.0 - 1e-9) || v > s.max * (1.0 + 1e-9) {
                    continue;
                }
                let labelled = m == 1 || (few && (m == 2 || m == 5));
                let label = if labelled {
                    fmt_log_tick(v, k)
                } else {
                    String::new()
                };
                out.push((v, label, m == 1));
            }
            k += 1.0;
        }
        out
    } else {
        let span = s.max - s.min;
        let step = nice_step(span * TICK_SPACING / len_px.max(1.0));
        let decimals = decimals_for(step);
        ticks(s.min, s.max, step)
            .into_iter()
            .map(|v| (v, fmt_fixed(v, decimals), true))
            .collect()
    }
}

pub(super) fn fmt_log_tick(v: f64, k: f64) -> String {
    if (-3.0..=5.0).contains(&k) {
        fmt_trimmed(v, 3)
    } else {
        let m = (v / 10f64.powf(k)).round();
        if m == 1.0 {
            format!("1e{k}")
        } else {
            format!("{m}e{k}")
        }
    }
}

/// The scale bar's path: a bar `len_px` long at `(x, y)` with 4 px end ticks up.
fn bar_path(x: f64, y: f64, len_px: f64) -> String {
    let mut d = String::new();
    push_cmd(&mut d, 'M', [x, y - 4.0]);
    push_cmd(&mut d, 'L', [x, y]);
    push_cmd(&mut d, 'L', [x + len_px, y]);
    push_cmd(&mut d, 'L', [x + len_px, y - 4.0]);
    d
}
