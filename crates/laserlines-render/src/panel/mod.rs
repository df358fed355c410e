//! A panel: one plot area with its axes, drawn in world (or data) coordinates.
//!
//! Maps use metres with equal scales on both axes, y up: the sensor frame of REP 103 lies
//! with x (forward) pointing right on the page and y (left) pointing up, as the axis labels
//! say. Charts use independent, optionally logarithmic axes.

use laserlines::math::Point2;

mod marks;
mod write;

use marks::{arc_points, push_cmd};
pub(crate) use marks::{marker_style, sane_px, wrap, write_marker, write_text};

use crate::geometry::{Extent, PxRect, Scale};
use crate::style::{Marker, Style, TextStyle};
use crate::svg::{Attrs, SvgWriter, fmt_px};

/// Font size of tick labels, px.
const TICK_FONT: f64 = 11.0;
/// Font size of axis labels, px.
const LABEL_FONT: f64 = 12.0;
/// Font size of panel titles, px.
const TITLE_FONT: f64 = 13.5;
/// Line height of panel titles, px.
const TITLE_LINE: f64 = 17.0;
/// Length of tick marks, px.
const TICK_LEN: f64 = 4.0;
/// Geometry is clipped to the plot area grown by this much, px (the SVG clip path does the
/// exact cut; this only keeps coordinates small).
const CLIP_MARGIN: f64 = 12.0;
/// Target spacing of major ticks, px.
const TICK_SPACING: f64 = 60.0;

/// One axis of a chart panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// Smallest value shown.
    pub min: f64,
    /// Largest value shown.
    pub max: f64,
    /// Base-10 logarithmic scale (then `0 < min < max`).
    pub log: bool,
    /// Axis label, with its unit, e.g. `time per scan [us]`.
    pub label: String,
}

impl Axis {
    /// A linear axis over `[min, max]`.
    #[must_use]
    pub fn linear(min: f64, max: f64, label: impl Into<String>) -> Self {
        Self {
            min,
            max,
            log: false,
            label: label.into(),
        }
    }

    /// A logarithmic axis over `[min, max]`, `0 < min < max`.
    #[must_use]
    pub fn log(min: f64, max: f64, label: impl Into<String>) -> Self {
        Self {
            min,
            max,
            log: true,
            label: label.into(),
        }
    }

    /// The axis with its bounds repaired: finite, ordered, non-degenerate, positive on a log
    /// scale.
    fn sanitized(&self) -> Self {
        let mut a = self.clone();
        if a.log {
            if !(a.min.is_finite() && a.min > 0.0) {
                a.min = 1.0;
            }
            if !(a.max.is_finite() && a.max > a.min * 1.0001) {
                a.max = a.min * 10.0;
            }
        } else {
            if !a.min.is_finite() || a.min.abs() > 1e12 {
                a.min = 0.0;
            }
            if !(a.max.is_finite() && a.max.abs() <= 1e12 && a.max - a.min > 1e-12) {
                a.max = a.min + 1.0;
            }
        }
        a
    }
}

/// What kind of plot a panel is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// Equal scales, metres, scale bar.
    Map,
    /// Independent axes.
    Chart,
}

/// One plot area with axes, ticks, grid, an optional scale bar, a title and notes.
///
/// Drawing calls take world coordinates (metres on maps, data units on charts); sizes of
/// markers, strokes and text are in pixels. Geometry that falls outside the plot is clipped;
/// anything non-finite is silently left out, so no input can break the document.
#[derive(Debug, Clone)]
pub struct Panel {
    kind: Kind,
    width: f64,
    height: f64,
    x: Scale,
    y: Scale,
    title: Option<String>,
    x_label: String,
    y_label: String,
    grid: bool,
    scale_bar: bool,
    body: SvgWriter,
    notes: Vec<String>,
    /// Pixels covered by drawn data (samples), to keep the scale bar off the data.
    ink: Vec<[f64; 2]>,
}

impl Panel {
    /// A map of `view` (metres) whose plot area is about `plot_width` px wide, with equal
    /// scales on both axes (y up).
    ///
    /// The plot's height follows the view's aspect ratio within 0.5..1.25 times the width;
    /// beyond that the view is widened on the short side, centred. An invalid view (not
    /// finite, empty) falls back to 2 m x 2 m around the origin.
    #[must_use]
    pub fn map(view: Extent, plot_width: f64) -> Self {
        let view = if view.is_valid() {
            view
        } else {
            Extent::new(-1.0, -1.0, 1.0, 1.0)
        };
        let width = sane_px(plot_width, 400.0);
        let mut height = width * view.height() / view.width();
        let mut v = view;
        if !(height.is_finite() && height <= 1.25 * width) {
            height = 1.25 * width;
            let half = 0.5 * view.height() * width / height;
            let c = view.center().x;
            v.min_x = c - half;
            v.max_x = c + half;
        } else if height < 0.5 * width {
            height = 0.5 * width;
            let half = 0.5 * view.width() * height / width;
            let c = view.center().y;
            v.min_y = c - half;
            v.max_y = c + half;
        }
        Self {
            kind: Kind::Map,
            width,
            height,
            x: Scale {
                min: v.min_x,
                max: v.max_x,
                log: false,
                px0: 0.0,
                px1: width,
            },
            y: Scale {
                min: v.min_y,
                max: v.max_y,
                log: false,
                px0: height,
                px1: 0.0,
            },
            title: None,
            x_label: "x [m], forward".to_owned(),
            y_label: "y [m], left".to_owned(),
            grid: true,
            scale_bar: true,
            body: SvgWriter::new(),
            notes: Vec::new(),
            ink: Vec::new(),
        }
    }

    /// A chart with independent axes and a plot area of `plot_width` x `plot_height` px.
    #[must_use]
    pub fn chart(x: &Axis, y: &Axis, plot_width: f64, plot_height: f64) -> Self {
        let (x, y) = (x.sanitized(), y.sanitized());
        let width = sane_px(plot_width, 480.0);
        let height = sane_px(plot_height, 320.0);
        Self {
            kind: Kind::Chart,
            width,
            height,
            x: Scale {
                min: x.min,
                max: x.max,
                log: x.log,
                px0: 0.0,
                px1: width,
            },
            y: Scale {
                min: y.min,
                max: y.max,
                log: y.log,
                px0: height,
                px1: 0.0,
            },
            title: None,
            x_label: x.label,
            y_label: y.label,
            grid: true,
            scale_bar: false,
            body: SvgWriter::new(),
            notes: Vec::new(),
            ink: Vec::new(),
        }
    }

    /// Sets the title written above the plot (wrapped to the panel's width).
    pub fn set_title(&mut self, title: impl Into<String>) {
        self.title = Some(title.into());
    }

    /// Sets the axis labels.
    pub fn set_labels(&mut self, x: impl Into<String>, y: impl Into<String>) {
        self.x_label = x.into();
        self.y_label = y.into();
    }

    /// Shows or hides the grid lines at the major ticks (shown by default).
    pub fn show_grid(&mut self, on: bool) {
        self.grid = on;
    }

    /// Shows or hides the scale bar (maps show one by default; charts never do).
    pub fn show_scale_bar(&mut self, on: bool) {
        self.scale_bar = on && self.kind == Kind::Map;
    }

    /// Size of the plot area, px.
    #[must_use]
    pub fn plot_size(&self) -> [f64; 2] {
        [self.width, self.height]
    }

    /// The world rectangle the plot area shows (for log axes, the data bounds).
    #[must_use]
    pub fn view(&self) -> Extent {
        Extent::new(self.x.min, self.y.min, self.x.max, self.y.max)
    }

    /// Pixels per metre on a map (per data unit on a linear chart's x axis).
    #[must_use]
    pub fn px_per_unit(&self) -> f64 {
        self.x.px_per_unit()
    }

    /// The pixel of a world point, relative to the plot's top-left corner, or `None` when it
    /// has none (non-finite, or `<= 0` on a log axis).
    #[must_use]
    pub fn to_px(&self, p: Point2) -> Option<[f64; 2]> {
        Some([self.x.map(p.x)?, self.y.map(p.y)?])
    }

    fn clip_rect(&self) -> PxRect {
        PxRect {
            x0: -CLIP_MARGIN,
            y0: -CLIP_MARGIN,
            x1: self.width + CLIP_MARGIN,
            y1: self.height + CLIP_MARGIN,
        }
    }

    fn plot_rect(&self) -> PxRect {
        PxRect {
            x0: 0.0,
            y0: 0.0,
            x1: self.width,
            y1: self.height,
        }
    }

    /// An image (`href`, e.g. a `data:` URI) stretched over the world rectangle `area`,
    /// drawn without smoothing so that map cells stay sharp.
    pub fn image(&mut self, area: Extent, href: &str) {
        let (Some(a), Some(b)) = (
            self.to_px(Point2::new(area.min_x, area.max_y)),
            self.to_px(Point2::new(area.max_x, area.min_y)),
        ) else {
            return;
        };
        self.body.leaf(
            "image",
            Attrs::new()
                .px("x", a[0])
                .px("y", a[1])
                .px("width", b[0] - a[0])
                .px("height", b[1] - a[1])
                .str("preserveAspectRatio", "none")
                .str("style", "image-rendering:pixelated")
                .str("href", href),
        );
    }

    /// A straight segment from `a` to `b`.
    pub fn line(&mut self, a: Point2, b: Point2, style: &Style) {
        let (Some(pa), Some(pb)) = (self.to_px(a), self.to_px(b)) else {
            return;
        };
        let Some((pa, pb)) = self.clip_rect().clip_segment(pa, pb) else {
            return;
        };
        self.add_ink(pa, pb);
        self.body.leaf(
            "line",
            Attrs::new()
                .px("x1", pa[0])
                .px("y1", pa[1])
                .px("x2", pb[0])
                .px("y2", pb[1])
                .style(&Style {
                    fill: None,
                    ..style.clone()
                }),
        );
    }

    /// A polyline through `points`; pieces outside the plot and around non-finite points are
    /// left out (the line breaks there).
    pub fn polyline(&mut self, points: &[Point2], style: &Style) {
        let d = self.path_data(points);
        if !d.is_empty() {
            self.body.leaf(
                "path",
                Attrs::new().str("d", d).style(&Style {
                    fill: None,
                    ..style.clone()
                }),
            );
        }
    }

    /// Records samples along a drawn segment (every 6 px, at most 400).
    fn add_ink(&mut self, a: [f64; 2], b: [f64; 2]) {
        let len = (b[0] - a[0]).hypot(b[1] - a[1]);
        let n = ((len / 6.0).ceil() as usize).clamp(1, 400);
        for k in 0..=n {
            let t = k as f64 / n as f64;
            self.ink
                .push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
        }
    }

    fn path_data(&mut self, points: &[Point2]) -> String {
        let rect = self.clip_rect();
        let mut d = String::new();
        let mut pen: Option<[f64; 2]> = None;
        let px: Vec<Option<[f64; 2]>> = points.iter().map(|&p| self.to_px(p)).collect();
        for w in px.windows(2) {
            let (Some(a), Some(b)) = (w[0], w[1]) else {
                pen = None;
                continue;
            };
            let Some((ca, cb)) = rect.clip_segment(a, b) else {
                pen = None;
                continue;
            };
            if pen != Some(ca) {
                push_cmd(&mut d, 'M', ca);
            }
            self.add_ink(ca, cb);
            push_cmd(&mut d, 'L', cb);
            pen = Some(cb);
        }
        d
    }

    /// A closed polygon (filled by the style's fill), clipped to the plot.
    pub fn polygon(&mut self, points: &[Point2], style: &Style) {
        let px: Vec<[f64; 2]> = points.iter().filter_map(|&p| self.to_px(p)).collect();
        self.polygon_px(&px, style);
    }

    fn polygon_px(&mut self, px: &[[f64; 2]], style: &Style) {
        let clipped = self.clip_rect().clip_polygon(px);
        if clipped.len() < 3 {
            return;
        }
        let mut pts = String::new();
        for (i, p) in clipped.iter().enumerate() {
            if i > 0 {
                pts.push(' ');
            }
            pts.push_str(&fmt_px(p[0]));
            pts.push(',');
            pts.push_str(&fmt_px(p[1]));
        }
        self.body
            .leaf("polygon", Attrs::new().str("points", pts).style(style));
    }

    /// A circle of `radius` world units around `center` (an ellipse on a chart with unequal
    /// scales).
    pub fn circle(&mut self, center: Point2, radius: f64, style: &Style) {
        if !(radius.is_finite() && radius > 0.0) {
            return;
        }
        if self.kind == Kind::Map {
            let Some(c) = self.to_px(center) else { return };
            let r = radius * self.px_per_unit();
            // Left out when it cannot touch the plot.
            let rect = self.clip_rect();
            let near = c[0] + r >= rect.x0
                && c[0] - r <= rect.x1
                && c[1] + r >= rect.y0
                && c[1] - r <= rect.y1;
            if near && r < 1e6 {
                self.body.leaf(
                    "circle",
                    Attrs::new()
                        .px("cx", c[0])
                        .px("cy", c[1])
                        .px("r", r)
                        .style(style),
                );
            }
        } else {
            let pts = arc_points(center, radius, 0.0, std::f64::consts::TAU);
            self.polygon(&pts, style);
        }
    }

    /// An arc of `radius` around `center` from angle `from` to `to` (rad, counter-clockwise
    /// from +x; `to < from` draws clockwise).
    pub fn arc(&mut self, center: Point2, radius: f64, from: f64, to: f64, style: &Style) {
        if !(radius.is_finite() && radius > 0.0) {
            return;
        }
        self.polyline(&arc_points(center, radius, from, to), style);
    }

    /// An annular sector around `center` between radii `inner` and `outer` and angles `from`
    /// to `to` (rad, counter-clockwise from +x). `inner = 0` gives a pie slice, e.g. the
    /// navigation sectors around the robot.
    pub fn wedge(
        &mut self,
        center: Point2,
        inner: f64,
        outer: f64,
        from: f64,
        to: f64,
        style: &Style,
    ) {
        if !(inner.is_finite() && outer.is_finite() && outer > 0.0 && inner >= 0.0) {
            return;
        }
        let mut pts = arc_points(center, outer, from, to);
        if inner > 0.0 {
            let mut back = arc_points(center, inner, from, to);
            back.reverse();
            pts.extend(back);
        } else {
            pts.push(center);
        }
        self.polygon(&pts, style);
    }

    /// Text anchored at a world point (left out when the point lies outside the plot).
    pub fn text(&mut self, at: Point2, text: &str, style: &TextStyle) {
        let Some(p) = self.to_px(at) else { return };
        if !self.plot_rect().contains(p) {
            return;
        }
        self.text_px(p, text, style);
    }

    fn text_px(&mut self, p: [f64; 2], text: &str, style: &TextStyle) {
        write_text(&mut self.body, p, text, style);
    }

    /// One point marker of `size` px at a world point.
    pub fn marker(&mut self, at: Point2, marker: Marker, size: f64, style: &Style) {
        self.markers(std::slice::from_ref(&at), marker, size, style);
    }

    /// Point markers of `size` px at world points, written as one group that carries the
    /// style (markers outside the plot are left out; nothing is written when none remains).
    pub fn markers(&mut self, points: &[Point2], marker: Marker, size: f64, style: &Style) {
        let size = sane_px(size, 4.0).min(100.0);
        let rect = self.clip_rect();
        let inside: Vec<[f64; 2]> = points
            .iter()
            .filter_map(|&p| self.to_px(p))
            .filter(|p| rect.contains(*p))
            .collect();
        if inside.is_empty() {
            return;
        }
        self.ink.extend(inside.iter().copied());
        self.body
            .open("g", Attrs::new().style(&marker_style(marker, style)));
        for p in inside {
            write_marker(&mut self.body, p, marker, size);
        }
        self.body.close();
    }

    /// The robot: a triangle of `size` px at `at`, pointing along `heading` (rad,
    /// counter-clockwise from +x), as in the paper's Fig. 3a.
    pub fn robot(&mut self, at: Point2, heading: f64, size: f64, style: &Style) {
        let Some(c) = self.to_px(at) else { return };
        if !heading.is_finite() || !self.clip_rect().contains(c) {
            return;
        }
        let size = sane_px(size, 12.0).min(100.0);
        // A point `forward` ahead and `left` to the left of the robot, in page pixels (page y
        // points down).
        let (sin, cos) = heading.sin_cos();
        let at = |forward: f64, left: f64| {
            [
                c[0] + size * (forward * cos - left * sin),
                c[1] - size * (forward * sin + left * cos),
            ]
        };
        self.polygon_px(&[at(0.55, 0.0), at(-0.45, 0.36), at(-0.45, -0.36)], style);
    }

    /// A note written centred near the top of the plot (e.g. "no valid points").
    pub fn note(&mut self, text: impl Into<String>) {
        self.notes.push(text.into());
    }
}

#[cfg(test)]
mod tests;
