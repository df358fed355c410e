//! An x-y chart of labelled points, e.g. accuracy against time per scan for each extractor.

use laserlines::math::Point2;

use crate::canvas::Canvas;
use crate::geometry::nice_step;
use crate::panel::{Axis, Panel};
use crate::style::{Anchor, Color, Marker, Style, TextStyle, category, text_width};

/// Font size of point labels, px.
const LABEL_FONT: f64 = 11.5;
/// Marker size, px.
const MARKER: f64 = 9.0;

/// One point of a [`ScatterChart`].
#[derive(Debug, Clone, PartialEq)]
pub struct ChartPoint {
    /// x value, in the chart's x unit.
    pub x: f64,
    /// y value, in the chart's y unit.
    pub y: f64,
    /// Text written next to the point (e.g. the algorithm's name).
    pub label: String,
    /// Marker colour; `None` takes the next qualitative colour.
    pub color: Option<Color>,
}

/// An x-y chart of labelled points with an optional base-10 logarithmic x axis; labels are
/// placed next to their points so that they do not overlap each other or the markers where
/// that can be helped.
///
/// ```
/// use laserlines_render::ScatterChart;
/// let mut chart = ScatterChart::new("Accuracy against speed", "time per scan [us]", "walls found [%]");
/// chart.log_x = true;
/// chart.add(4.2, 100.0, "hough-split");
/// chart.add(480.0, 96.0, "split-and-merge");
/// let svg = chart.to_svg();
/// assert_eq!(svg.matches("class=\"chart-label\"").count(), 2);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ScatterChart {
    /// Figure title.
    pub title: String,
    /// x axis label with unit.
    pub x_label: String,
    /// y axis label with unit.
    pub y_label: String,
    /// Logarithmic x axis (points with `x <= 0` are then left out, with a note).
    pub log_x: bool,
    /// Plot area width, px. Default 560.
    pub width: f64,
    /// Plot area height, px. Default 360.
    pub height: f64,
    /// Fixed x range; `None` fits the points.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range; `None` fits the points.
    pub y_range: Option<(f64, f64)>,
    /// The points.
    pub points: Vec<ChartPoint>,
}

impl ScatterChart {
    /// An empty chart with linear axes.
    #[must_use]
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            log_x: false,
            width: 560.0,
            height: 360.0,
            x_range: None,
            y_range: None,
            points: Vec::new(),
        }
    }

    /// Adds a labelled point in the next qualitative colour.
    pub fn add(&mut self, x: f64, y: f64, label: impl Into<String>) {
        self.points.push(ChartPoint {
            x,
            y,
            label: label.into(),
            color: None,
        });
    }

    fn drawable(&self, p: &ChartPoint) -> bool {
        p.x.is_finite() && p.y.is_finite() && (!self.log_x || p.x > 0.0)
    }

    /// The SVG document.
    #[must_use]
    pub fn to_svg(&self) -> String {
        let shown: Vec<(usize, &ChartPoint)> = self
            .points
            .iter()
            .enumerate()
            .filter(|(_, p)| self.drawable(p))
            .collect();
        let xs: Vec<f64> = shown.iter().map(|(_, p)| p.x).collect();
        let ys: Vec<f64> = shown.iter().map(|(_, p)| p.y).collect();
        let (x0, x1) = match self.x_range {
            Some(r) => r,
            None if self.log_x => log_range(&xs),
            None => linear_range(&xs),
        };
        let (y0, y1) = self.y_range.unwrap_or_else(|| linear_range(&ys));
        let x_axis = if self.log_x {
            Axis::log(x0, x1, self.x_label.clone())
        } else {
            Axis::linear(x0, x1, self.x_label.clone())
        };
        let y_axis = Axis::linear(y0, y1, self.y_label.clone());
        let mut panel = Panel::chart(&x_axis, &y_axis, self.width, self.height);

        // Markers first, then labels placed around them.
        let mut occupied: Vec<[f64; 4]> = Vec::new();
        let mut placed: Vec<(Point2, [f64; 2], &ChartPoint, usize)> = Vec::new();
        for &(i, p) in &shown {
            let at = Point2::new(p.x, p.y);
            let Some(px) = panel.to_px(at) else { continue };
            let color = p.color.unwrap_or_else(|| category(i));
            panel.marker(
                at,
                Marker::Circle,
                MARKER,
                &Style::stroke(Color::INK, 0.9)
                    .with_fill(color)
                    .with_class("chart-point"),
            );
            let h = 0.5 * MARKER + 1.0;
            occupied.push([px[0] - h, px[1] - h, px[0] + h, px[1] + h]);
            placed.push((at, px, p, i));
        }
        let [w, h] = panel.plot_size();
        for (at, px, p, _) in &placed {
            if p.label.is_empty() {
                continue;
            }
            let (style, bbox) = place_label(&p.label, *px, &occupied, [w, h]);
            occupied.push(bbox);
            panel.text(*at, &p.label, &style);
        }
        let hidden = self.points.len() - shown.len();
        if self.points.is_empty() {
            panel.note("no data");
        } else if hidden > 0 {
            panel.note(format!(
                "{hidden} of {} points not shown (not finite{})",
                self.points.len(),
                if self.log_x {
                    ", or x <= 0 on the log axis"
                } else {
                    ""
                }
            ));
        }
        let mut canvas = Canvas::new(1);
        canvas.set_title(self.title.clone());
        canvas.add_panel(panel);
        canvas.to_svg()
    }
}

/// A padded, nicely rounded range holding `v` (`(0, 1)` when empty).
fn linear_range(v: &[f64]) -> (f64, f64) {
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let span = hi - lo;
    let span = if span > 0.0 {
        span
    } else {
        lo.abs().max(1.0) * 0.2
    };
    let pad = 0.08 * span;
    let step = nice_step(span / 5.0);
    let a = ((lo - pad) / step).floor() * step;
    let b = ((hi + pad) / step).ceil() * step;
    if a.is_finite() && b.is_finite() && b > a {
        (a, b)
    } else {
        (0.0, 1.0)
    }
}

/// Whole decades holding the positive values of `v`, with a margin (`(1, 10)` when empty).
fn log_range(v: &[f64]) -> (f64, f64) {
    let pos: Vec<f64> = v.iter().copied().filter(|x| *x > 0.0).collect();
    let lo = pos.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = pos.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !(lo.is_finite() && hi.is_finite()) {
        return (1.0, 10.0);
    }
    let a = (lo.log10() - 0.1).floor().clamp(-300.0, 300.0);
    let b = (hi.log10() + 0.1).ceil().clamp(-300.0, 300.0);
    let b = if b > a { b } else { a + 1.0 };
    (10f64.powf(a), 10f64.powf(b))
}

/// Picks the position around the point `px` whose label box overlaps the occupied boxes
/// least (and stays in the plot); returns the text style and the box.
fn place_label(
    label: &str,
    px: [f64; 2],
    occupied: &[[f64; 4]],
    [w, h]: [f64; 2],
) -> (TextStyle, [f64; 4]) {
    let tw = text_width(label, LABEL_FONT, false);
    let asc = 0.8 * LABEL_FONT;
    let gap = 0.5 * MARKER + 3.0;
    // (dx, dy of the baseline, anchor)
    let candidates = [
        (gap, 0.35 * LABEL_FONT, Anchor::Start),
        (-gap, 0.35 * LABEL_FONT, Anchor::End),
        (0.0, -gap - 1.0, Anchor::Middle),
        (0.0, gap + asc, Anchor::Middle),
        (gap - 2.0, -gap + 1.0, Anchor::Start),
        (gap - 2.0, gap + asc - 1.0, Anchor::Start),
        (-gap + 2.0, -gap + 1.0, Anchor::End),
        (-gap + 2.0, gap + asc - 1.0, Anchor::End),
    ];
    let mut best: Option<(f64, usize, [f64; 4])> = None;
    for (k, &(dx, dy, anchor)) in candidates.iter().enumerate() {
        let left = match anchor {
            Anchor::Start => px[0] + dx,
            Anchor::Middle => px[0] + dx - 0.5 * tw,
            Anchor::End => px[0] + dx - tw,
        };
        let base = px[1] + dy;
        let bbox = [left, base - asc, left + tw, base + 0.25 * LABEL_FONT];
        let mut cost: f64 = occupied.iter().map(|o| overlap(&bbox, o)).sum();
        let inside = [
            (bbox[0] - 2.0).min(0.0),
            (bbox[1] - 2.0).min(0.0),
            (w - 2.0 - bbox[2]).min(0.0),
            (h - 2.0 - bbox[3]).min(0.0),
        ];
        cost += 20.0 * inside.iter().map(|v| -v).sum::<f64>() * LABEL_FONT;
        if best.is_none_or(|(c, _, _)| cost < c - 1e-9) {
            best = Some((cost, k, bbox));
        }
    }
    let (_, k, bbox) = best.unwrap_or((0.0, 0, [px[0], px[1], px[0], px[1]]));
    let (dx, dy, anchor) = candidates[k];
    (
        TextStyle::size(LABEL_FONT)
            .anchored(anchor)
            .offset(dx, dy)
            .with_halo()
            .with_class("chart-label"),
        bbox,
    )
}

fn overlap(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    let w = (a[2].min(b[2]) - a[0].max(b[0])).max(0.0);
    let h = (a[3].min(b[3]) - a[1].max(b[1])).max(0.0);
    w * h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_hold_the_data() {
        let (a, b) = linear_range(&[0.3, 0.9]);
        assert!(a <= 0.3 && b >= 0.9 && b - a < 1.5);
        assert_eq!(linear_range(&[]), (0.0, 1.0));
        let (a, b) = linear_range(&[5.0, 5.0]);
        assert!(a < 5.0 && b > 5.0);
        let (a, b) = log_range(&[4.0, 480.0]);
        assert_eq!((a, b), (1.0, 1000.0));
        assert_eq!(log_range(&[-1.0]), (1.0, 10.0));
    }

    #[test]
    fn labels_avoid_each_other() {
        let occupied = [[100.0, 100.0, 200.0, 112.0]];
        let (_, bbox) = place_label("name", [95.0, 106.0], &occupied, [400.0, 300.0]);
        assert_eq!(overlap(&bbox, &occupied[0]), 0.0);
    }
}
