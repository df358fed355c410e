//! A figure: a title, panels in a grid and a legend, written as one SVG document.

use crate::panel::{Panel, marker_style, wrap, write_marker, write_text};
use crate::style::{Anchor, Color, Marker, Style, TextStyle, text_width};
use crate::svg::{Attrs, SvgWriter, fmt_px};

/// Outer padding of the figure, px.
const PAD: f64 = 14.0;
/// Space between grid cells, px.
const GAP: f64 = 18.0;
/// Font size of the figure title, px.
const TITLE_FONT: f64 = 17.0;
/// Font size of legend labels, px.
const LEGEND_FONT: f64 = 12.0;
/// Height of one legend row, px.
const LEGEND_ROW: f64 = 20.0;
/// Font family of the whole figure.
const FONT_FAMILY: &str = "DejaVu Sans, Helvetica, Arial, sans-serif";

/// How a legend entry is pictured.
#[derive(Debug, Clone, PartialEq)]
pub enum Swatch {
    /// A short line in a style.
    Line(Style),
    /// A marker of a size (px) in a style.
    Marker(Marker, f64, Style),
    /// A small filled rectangle in a style.
    Patch(Style),
    /// A colour ramp, low values first.
    Ramp(Vec<Color>),
    /// A row of markers, one per colour (categories coloured one each).
    Palette(Marker, Vec<Color>),
}

impl Swatch {
    fn width(&self) -> f64 {
        match self {
            Self::Ramp(_) => 48.0,
            Self::Palette(_, c) => 9.0 * c.len().clamp(1, 6) as f64,
            _ => 24.0,
        }
    }
}

/// One entry of a figure's legend.
#[derive(Debug, Clone, PartialEq)]
pub struct LegendEntry {
    /// What the entry looks like.
    pub swatch: Swatch,
    /// What it means.
    pub label: String,
}

impl LegendEntry {
    /// An entry.
    #[must_use]
    pub fn new(swatch: Swatch, label: impl Into<String>) -> Self {
        Self {
            swatch,
            label: label.into(),
        }
    }
}

/// A figure: an optional title, panels laid out in a grid (row by row), and a legend below.
///
/// ```
/// use laserlines::math::Point2;
/// use laserlines_render::{Canvas, Extent, LegendEntry, Panel, Style, Swatch, Color};
/// let mut panel = Panel::map(Extent::new(-1.0, -1.0, 1.0, 1.0), 300.0);
/// let wall = Style::stroke(Color::NAVY, 2.0);
/// panel.line(Point2::new(0.5, -0.5), Point2::new(0.5, 0.5), &wall);
/// let mut canvas = Canvas::new(1);
/// canvas.set_title("A wall");
/// canvas.add_panel(panel);
/// canvas.add_legend(LegendEntry::new(Swatch::Line(wall), "wall"));
/// let svg = canvas.to_svg();
/// assert!(svg.starts_with("<?xml") && svg.trim_end().ends_with("</svg>"));
/// ```
#[derive(Debug, Clone)]
pub struct Canvas {
    columns: usize,
    title: Option<String>,
    panels: Vec<Panel>,
    legend: Vec<LegendEntry>,
}

impl Canvas {
    /// An empty figure whose panels fill `columns` columns (at least one).
    #[must_use]
    pub fn new(columns: usize) -> Self {
        Self {
            columns: columns.max(1),
            title: None,
            panels: Vec::new(),
            legend: Vec::new(),
        }
    }

    /// Sets the figure title.
    pub fn set_title(&mut self, title: impl Into<String>) {
        self.title = Some(title.into());
    }

    /// Adds a panel at the next grid position and returns its index.
    pub fn add_panel(&mut self, panel: Panel) -> usize {
        self.panels.push(panel);
        self.panels.len() - 1
    }

    /// The panel at `index`, to draw more on it.
    pub fn panel_mut(&mut self, index: usize) -> Option<&mut Panel> {
        self.panels.get_mut(index)
    }

    /// Number of panels.
    #[must_use]
    pub fn panel_count(&self) -> usize {
        self.panels.len()
    }

    /// Adds a legend entry (entries appear in the order added).
    pub fn add_legend(&mut self, entry: LegendEntry) {
        self.legend.push(entry);
    }

    /// The SVG document.
    #[must_use]
    pub fn to_svg(&self) -> String {
        let grid = self.grid();
        let width = (2.0 * PAD + grid.width).max(360.0);
        let title_lines = match &self.title {
            Some(t) => wrap(t, TITLE_FONT, true, width - 2.0 * PAD),
            None => Vec::new(),
        };
        let title_h = if title_lines.is_empty() {
            0.0
        } else {
            title_lines.len() as f64 * (TITLE_FONT + 5.0) + 6.0
        };
        let grid_top = PAD + title_h;
        let legend = self.layout_legend(width - 2.0 * PAD - 20.0);
        let legend_top = grid_top + grid.height + if self.panels.is_empty() { 0.0 } else { 8.0 };
        let legend_h = if legend.is_empty() {
            0.0
        } else {
            legend.len() as f64 * LEGEND_ROW + 12.0
        };
        let height = (legend_top + legend_h + PAD).max(2.0 * PAD + title_h + 40.0);
        let mut w = SvgWriter::new();
        self.write_head(&mut w, [width, height], &title_lines);
        let x0 = PAD + 0.5 * (width - 2.0 * PAD - grid.width);
        for (i, p) in self.panels.iter().enumerate() {
            p.write(&mut w, grid.origin(i, [x0, grid_top]), i);
        }
        if !legend.is_empty() {
            self.write_legend(&mut w, &legend, [PAD, legend_top], width - 2.0 * PAD);
        }
        let mut out = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
        out.push_str(&w.finish());
        out
    }

    /// The grid of panels: per column the largest left margin, plot width and right
    /// margin, per row the largest top margin, plot height and bottom margin.
    fn grid(&self) -> Grid {
        let cols = self.columns.min(self.panels.len()).max(1);
        let rows = self.panels.len().div_ceil(cols);
        let mut col = vec![[0.0_f64; 3]; cols];
        let mut row = vec![[0.0_f64; 3]; rows];
        for (i, p) in self.panels.iter().enumerate() {
            let [l, r, t, b] = p.margins();
            let [w, h] = p.plot_size();
            let c = &mut col[i % cols];
            *c = [c[0].max(l), c[1].max(w), c[2].max(r)];
            let rr = &mut row[i / cols];
            *rr = [rr[0].max(t), rr[1].max(h), rr[2].max(b)];
        }
        let width: f64 =
            col.iter().map(|c| c[0] + c[1] + c[2]).sum::<f64>() + GAP * (cols as f64 - 1.0);
        let height: f64 =
            row.iter().map(|r| r[0] + r[1] + r[2]).sum::<f64>() + GAP * (rows as f64 - 1.0);
        let height = if self.panels.is_empty() { 0.0 } else { height };
        Grid {
            col,
            row,
            width,
            height,
        }
    }

    /// The `<svg>` element, the background and the figure's title.
    fn write_head(&self, w: &mut SvgWriter, [width, height]: [f64; 2], title_lines: &[String]) {
        w.open(
            "svg",
            Attrs::new()
                .str("xmlns", "http://www.w3.org/2000/svg")
                .px("width", width)
                .px("height", height)
                .str(
                    "viewBox",
                    format!("0 0 {} {}", fmt_px(width), fmt_px(height)),
                )
                .str("font-family", FONT_FAMILY)
                .str("stroke-linecap", "round")
                .str("stroke-linejoin", "round"),
        );
        if let Some(t) = &self.title {
            w.text("title", Attrs::new(), t);
        }
        w.leaf(
            "rect",
            Attrs::new()
                .str("class", "background")
                .px("width", width)
                .px("height", height)
                .str("fill", "#ffffff"),
        );
        for (i, line) in title_lines.iter().enumerate() {
            write_text(
                w,
                [
                    0.5 * width,
                    PAD + TITLE_FONT + i as f64 * (TITLE_FONT + 5.0),
                ],
                line,
                &TextStyle::size(TITLE_FONT)
                    .bold()
                    .anchored(Anchor::Middle)
                    .with_class("figure-title"),
            );
        }
    }

    /// Flows the legend entries into rows no wider than `max_w`: row -> [(entry, x offset)].
    fn layout_legend(&self, max_w: f64) -> Vec<Vec<(usize, f64)>> {
        let mut rows: Vec<Vec<(usize, f64)>> = Vec::new();
        let mut x = 0.0;
        for (i, e) in self.legend.iter().enumerate() {
            let w = e.swatch.width() + 6.0 + text_width(&e.label, LEGEND_FONT, false);
            if rows.is_empty() || (x > 0.0 && x + w > max_w) {
                rows.push(Vec::new());
                x = 0.0;
            }
            if let Some(r) = rows.last_mut() {
                r.push((i, x));
            }
            x += w + 22.0;
        }
        rows
    }

    fn write_legend(
        &self,
        w: &mut SvgWriter,
        rows: &[Vec<(usize, f64)>],
        origin: [f64; 2],
        width: f64,
    ) {
        w.open("g", Attrs::new().str("class", "legend"));
        w.leaf(
            "rect",
            Attrs::new()
                .px("x", origin[0])
                .px("y", origin[1])
                .px("width", width)
                .px("height", rows.len() as f64 * LEGEND_ROW + 12.0)
                .style(&Style::stroke(Color::LIGHT_GREY, 1.0).with_fill(Color::WHITE)),
        );
        for (r, row) in rows.iter().enumerate() {
            let cy = origin[1] + 6.0 + LEGEND_ROW * (r as f64 + 0.5);
            for &(i, dx) in row {
                let e = &self.legend[i];
                let x = origin[0] + 10.0 + dx;
                w.open("g", Attrs::new().str("class", "legend-entry"));
                write_swatch(w, &e.swatch, [x, cy]);
                write_text(
                    w,
                    [x + e.swatch.width() + 6.0, cy + 0.35 * LEGEND_FONT],
                    &e.label,
                    &TextStyle::size(LEGEND_FONT),
                );
                w.close();
            }
        }
        w.close();
    }
}

/// The layout of a canvas's panels (see `Canvas::grid`).
struct Grid {
    col: Vec<[f64; 3]>,
    row: Vec<[f64; 3]>,
    width: f64,
    height: f64,
}

impl Grid {
    /// Where panel `i`'s plot starts, for the grid at `[x0, top]`.
    fn origin(&self, i: usize, [x0, top]: [f64; 2]) -> [f64; 2] {
        let cols = self.col.len();
        let (c, r) = (i % cols, i / cols);
        let x = x0
            + self.col[..c]
                .iter()
                .map(|c| c[0] + c[1] + c[2] + GAP)
                .sum::<f64>()
            + self.col[c][0];
        let y = top
            + self.row[..r]
                .iter()
                .map(|r| r[0] + r[1] + r[2] + GAP)
                .sum::<f64>()
            + self.row[r][0];
        [x, y]
    }
}

/// Draws a swatch whose left edge is at `x`, vertically centred on `cy`.
fn write_swatch(w: &mut SvgWriter, swatch: &Swatch, [x, cy]: [f64; 2]) {
    let sw = swatch.width();
    match swatch {
        Swatch::Line(style) => w.leaf(
            "line",
            Attrs::new()
                .px("x1", x)
                .px("y1", cy)
                .px("x2", x + sw)
                .px("y2", cy)
                .style(&Style {
                    fill: None,
                    class: None,
                    ..style.clone()
                }),
        ),
        Swatch::Marker(m, size, style) => {
            let style = Style {
                class: None,
                ..marker_style(*m, style)
            };
            w.open("g", Attrs::new().style(&style));
            write_marker(w, [x + 0.5 * sw, cy], *m, size.clamp(1.0, 16.0));
            w.close();
        }
        Swatch::Patch(style) => w.leaf(
            "rect",
            Attrs::new()
                .px("x", x)
                .px("y", cy - 6.0)
                .px("width", sw)
                .px("height", 12.0)
                .style(&Style {
                    class: None,
                    ..style.clone()
                }),
        ),
        Swatch::Ramp(colors) => {
            let n = colors.len().max(1);
            let step = sw / n as f64;
            for (k, c) in colors.iter().enumerate() {
                w.leaf(
                    "rect",
                    Attrs::new()
                        .px("x", x + k as f64 * step)
                        .px("y", cy - 5.0)
                        .px("width", step + 0.3)
                        .px("height", 10.0)
                        .style(&Style::fill(*c)),
                );
            }
        }
        Swatch::Palette(m, colors) => {
            for (k, c) in colors.iter().take(6).enumerate() {
                let style = marker_style(*m, &Style::fill(*c));
                w.open("g", Attrs::new().style(&style));
                write_marker(w, [x + 4.5 + 9.0 * k as f64, cy], *m, 6.0);
                w.close();
            }
        }
    }
}
