//! The project's figures: the paper's four stages of one scan, and a scan with its lines.

use laserlines::math::Point2;
use laserlines::{HoughSplit, Line, Scan, ScanPoint, Weight};

use crate::canvas::{Canvas, LegendEntry, Swatch};
use crate::geometry::Extent;
use crate::panel::{Panel, sane_px};
use crate::style::{Color, Marker, Style, category, viridis};

/// Options of the figures.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    /// Width of the whole figure, px. Default 1000.
    pub width: f64,
    /// The world rectangle shown, metres in the sensor frame; `None` fits the valid points
    /// and the sensor. An invalid extent (not finite, empty) is treated as `None`.
    pub view: Option<Extent>,
    /// Figure title; `None` gives a title describing the figure.
    pub title: Option<String>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            width: 1000.0,
            view: None,
            title: None,
        }
    }
}

/// Size of the robot triangle, px.
const ROBOT_SIZE: f64 = 15.0;

/// Colour of scan points.
const POINT: Color = Color::INK;
/// Colour of faint context points.
const FAINT: Color = Color::rgb(0xb8, 0xb8, 0xb8);
/// Colour of the extracted lines.
const LINE: Color = Color::NAVY;
/// Colour of radius groups (the paper's blue lines).
const GROUP: Color = Color::rgb(0x4f, 0x9b, 0xd9);

/// Kept-cell colours from low to high value: the viridis map from green down to dark purple,
/// so that strong cells are the darkest marks on white paper.
fn cell_color(t: f64) -> Color {
    viridis(0.78 - 0.78 * t)
}

/// Position of `v` between `lo` and `hi` on a logarithmic scale (cell values span more than
/// a decade: a far wall seen head-on sums many long ranges), in `[0, 1]`.
fn log_position(v: f64, lo: f64, hi: f64) -> f64 {
    if lo > 0.0 && hi > lo {
        ((v / lo).ln() / (hi / lo).ln()).clamp(0.0, 1.0)
    } else if hi > lo {
        ((v - lo) / (hi - lo)).clamp(0.0, 1.0)
    } else {
        1.0
    }
}

fn robot_style() -> Style {
    Style::fill(Color::RED).with_class("robot")
}

fn points_of(points: &[ScanPoint]) -> Vec<Point2> {
    points.iter().map(|p| p.point).collect()
}

fn view_for(opts: &RenderOptions, points: &[Point2]) -> Extent {
    match opts.view {
        Some(v) if v.is_valid() => v,
        _ => Extent::fit_map(points.iter().copied(), 2.0),
    }
}

/// Plot width of each of `columns` map panels in a figure `width` px wide.
fn plot_width(width: f64, columns: usize) -> f64 {
    // Figure padding, the panels' axis margins and the gaps between them (see Canvas).
    let overhead = 2.0 * 14.0 + columns as f64 * (58.0 + 14.0) + (columns as f64 - 1.0) * 18.0;
    (sane_px(width, 1000.0).max(300.0) - overhead) / columns as f64
}

/// The point of beam `index` among `points` (sorted by beam index).
fn point_at(points: &[ScanPoint], index: usize) -> Option<Point2> {
    points
        .binary_search_by_key(&index, |p| p.index)
        .ok()
        .map(|k| points[k].point)
}

fn is_finite_point(p: Point2) -> bool {
    p.x.is_finite() && p.y.is_finite()
}

fn plural(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// Draws the extracted lines with red circles at their end points; returns the number drawn.
fn draw_lines(panel: &mut Panel, lines: &[Line]) {
    let style = Style::stroke(LINE, 2.4).with_class("extracted-line");
    let mut ends = Vec::with_capacity(2 * lines.len());
    for l in lines {
        if is_finite_point(l.start) && is_finite_point(l.end) {
            panel.line(l.start, l.end, &style);
            ends.push(l.start);
            ends.push(l.end);
        }
    }
    panel.markers(
        &ends,
        Marker::Circle,
        7.0,
        &Style::stroke(Color::RED, 1.5)
            .with_fill(Color::WHITE)
            .with_class("line-end"),
    );
}

fn robot(panel: &mut Panel) {
    panel.robot(Point2::origin(), 0.0, ROBOT_SIZE, &robot_style());
}

fn line_legend(canvas: &mut Canvas) {
    canvas.add_legend(LegendEntry::new(
        Swatch::Line(Style::stroke(LINE, 2.4)),
        "extracted line",
    ));
    canvas.add_legend(LegendEntry::new(
        Swatch::Marker(
            Marker::Circle,
            7.0,
            Style::stroke(Color::RED, 1.5).with_fill(Color::WHITE),
        ),
        "line end point",
    ));
}

fn robot_legend(canvas: &mut Canvas) {
    canvas.add_legend(LegendEntry::new(
        Swatch::Marker(Marker::TriangleRight, 12.0, Style::fill(Color::RED)),
        "robot at the sensor origin, facing +x",
    ));
}

/// The paper's figures for one scan as a 2 x 2 grid of panels in one SVG document:
///
/// - (a) the raw scan: its valid points and the robot, a red triangle at the origin facing
///   +x (paper Fig. 3a);
/// - (b) the accumulator cells above the criterion, the "spider net" (Fig. 3b): every kept
///   cell is a short tangent line at its ring's distance across its sector's angular width,
///   coloured and thickened by its value; cells that voted but fell below the criterion are
///   faint grey;
/// - (c) grouping (Fig. 4): radius groups as blue arcs, the points of each data segment in
///   its own colour, a red line from each segment's start point to its end point (squares
///   mark both), removed points as grey crosses;
/// - (d) the extracted lines with red circles at their end points (Fig. 5), over the faint
///   valid points.
///
/// Every panel has axes in metres (x forward to the right, y left upwards) and a scale bar;
/// the figure has one legend. `hs` must hold the stages of extracting `scan` (the call that
/// returned `lines`). Nothing panics: an empty or all-invalid scan gives empty panels with a
/// note, and non-finite values are left out.
#[must_use]
pub fn render_hough_split(
    scan: &Scan,
    hs: &HoughSplit,
    lines: &[Line],
    opts: &RenderOptions,
) -> String {
    let raw = scan.points(scan.range_window(None));
    let raw_pts = points_of(&raw);
    let view = view_for(opts, &raw_pts);
    let pw = plot_width(opts.width, 2);
    let mut canvas = Canvas::new(2);
    canvas.set_title(opts.title.clone().unwrap_or_else(|| {
        format!(
            "Hough-split line extraction of one scan ({} beams, {} valid; noise {}{})",
            scan.len(),
            raw.len(),
            hs.stages().noise(),
            match (hs.stages().noise_estimated(), hs.stages().range_quantum()) {
                (true, Some(q)) => format!(", estimated; ranges in {:.1} mm steps", q * 1e3),
                (true, None) => ", estimated".to_owned(),
                _ => String::new(),
            }
        )
    }));
    let (a, unused) = raw_panel(scan, hs, &raw, view, pw);
    canvas.add_panel(a);
    let (b, values, rejected) = net_panel(scan, hs, view, pw);
    canvas.add_panel(b);
    let (c, removed) = grouping_panel(scan, hs, view, pw);
    canvas.add_panel(c);
    canvas.add_panel(lines_panel(lines, &raw_pts, view, pw));
    hough_legend(&mut canvas, hs, values, unused, rejected, removed);
    canvas.to_svg()
}

/// (a) The raw scan: the points the extractor used and those it did not (out of the
/// range limits); whether there were any of the latter.
fn raw_panel(
    scan: &Scan,
    hs: &HoughSplit,
    raw: &[ScanPoint],
    view: Extent,
    pw: f64,
) -> (Panel, bool) {
    let used_points = hs.stages().points();
    let used = &used_points[..];
    let mut a = Panel::map(view, pw);
    a.set_title(format!(
        "(a) raw scan: {} of {}",
        plural(raw.len(), "valid point", "valid points"),
        plural(scan.len(), "beam", "beams")
    ));
    draw_field_of_view(&mut a, scan, &view);
    let outside: Vec<Point2> = raw
        .iter()
        .filter(|p| used.binary_search_by_key(&p.index, |u| u.index).is_err())
        .map(|p| p.point)
        .collect();
    a.markers(
        &outside,
        Marker::Dot,
        3.0,
        &Style::fill(FAINT).with_class("unused-point"),
    );
    a.markers(
        &points_of(used),
        Marker::Dot,
        3.0,
        &Style::fill(POINT).with_class("raw-point"),
    );
    robot(&mut a);
    if raw.is_empty() {
        a.note("no valid points");
    }
    (a, !outside.is_empty())
}

/// (b) The spider net: the accumulator's cells as tangent lines, kept ones coloured by
/// value; the range of the kept values, and whether any cell was rejected.
fn net_panel(scan: &Scan, hs: &HoughSplit, view: Extent, pw: f64) -> (Panel, (f64, f64), bool) {
    let stages = hs.stages();
    let mut b = Panel::map(view, pw);
    let cells = stages.cells();
    let mut kept: Vec<_> = cells.iter().filter(|c| c.kept).collect();
    let criterion = stages.criterion();
    b.set_title(format!(
        "(b) accumulator: {} of {} above {}",
        kept.len(),
        plural(cells.len(), "cell", "cells"),
        cell_value_text(criterion, hs.params().weight)
    ));
    let half = 0.5 * hs.params().sector_step;
    let tangent = |ring: u32, sector: u32| {
        let d = stages.ring_distance(ring);
        let gamma = stages.sector_angle(scan, sector);
        let reach = d / half.cos();
        (
            Point2::new(reach * (gamma - half).cos(), reach * (gamma - half).sin()),
            Point2::new(reach * (gamma + half).cos(), reach * (gamma + half).sin()),
        )
    };
    let rejected = Style::stroke(Color::LIGHT_GREY, 0.9).with_class("cell-rejected");
    for c in cells.iter().filter(|c| !c.kept) {
        let (p, q) = tangent(c.ring, c.sector);
        b.line(p, q, &rejected);
    }
    // Strong cells last, so that they are drawn on top.
    kept.sort_by(|x, y| x.value.total_cmp(&y.value));
    let (vmin, vmax) = value_range(kept.iter().map(|c| c.value));
    for c in &kept {
        let t = log_position(c.value, vmin, vmax);
        let (p, q) = tangent(c.ring, c.sector);
        b.line(
            p,
            q,
            &Style::stroke(cell_color(t), 1.2 + 1.4 * t).with_class("cell-kept"),
        );
    }
    robot(&mut b);
    if kept.is_empty() {
        b.note(if cells.is_empty() {
            "no accumulator cells"
        } else {
            "no cell above the criterion"
        });
    }
    (b, (vmin, vmax), cells.len() > kept.len())
}

/// (c) Grouping and segmentation: radius groups, each data segment's points and chord,
/// the removed points; whether any point was removed.
fn grouping_panel(scan: &Scan, hs: &HoughSplit, view: Extent, pw: f64) -> (Panel, bool) {
    let stages = hs.stages();
    let used_points = stages.points();
    let used = &used_points[..];
    let half = 0.5 * hs.params().sector_step;
    let mut c = Panel::map(view, pw);
    let groups = stages.radius_groups();
    let segments: Vec<_> = stages.segments().collect();
    let removed = stages.removed();
    c.set_title(format!(
        "(c) grouping: {}, {}, {}",
        plural(groups.len(), "radius group", "radius groups"),
        plural(segments.len(), "data segment", "data segments"),
        plural(removed.len(), "removed point", "removed points")
    ));
    let group_style = Style::stroke(GROUP, 1.6).with_class("radius-group");
    for g in &groups {
        let d = stages.ring_distance(g.ring);
        let s0 = stages.sector_angle(scan, g.first_sector);
        let s1 = stages.sector_angle(scan, g.last_sector);
        let (lo, hi) = (s0.min(s1) - half, s0.max(s1) + half);
        c.arc(Point2::origin(), d, lo, hi, &group_style);
    }
    let removed_pts: Vec<Point2> = removed.iter().filter_map(|&i| point_at(used, i)).collect();
    c.markers(
        &removed_pts,
        Marker::Cross,
        5.0,
        &Style::stroke(Color::GREY, 1.1).with_class("removed-point"),
    );
    let kept_idx: Vec<usize> = stages.kept().collect();
    let chord = Style::stroke(Color::RED, 1.6).with_class("segment-chord");
    let mut seg_ends = Vec::with_capacity(2 * segments.len());
    for (t, s) in segments.iter().enumerate() {
        let pts: Vec<Point2> = kept_idx
            .iter()
            .filter(|&&i| s.covers(i))
            .filter_map(|&i| point_at(used, i))
            .collect();
        c.markers(
            &pts,
            Marker::Dot,
            3.6,
            &Style::fill(category(t)).with_class("segment-point"),
        );
        if let (Some(p), Some(q)) = (point_at(used, s.first), point_at(used, s.last)) {
            c.line(p, q, &chord);
            seg_ends.push(p);
            seg_ends.push(q);
        }
    }
    c.markers(
        &seg_ends,
        Marker::Square,
        5.0,
        &Style::fill(Color::RED).with_class("segment-end"),
    );
    robot(&mut c);
    if segments.is_empty() {
        c.note("no data segment");
    }
    (c, !removed_pts.is_empty())
}

/// (d) The extracted lines over the faint valid points.
fn lines_panel(lines: &[Line], raw_pts: &[Point2], view: Extent, pw: f64) -> Panel {
    let mut d = Panel::map(view, pw);
    d.set_title(format!(
        "(d) extracted lines: {} from {}",
        plural(lines.len(), "line", "lines"),
        plural(
            lines.iter().map(|l| l.points).sum::<usize>(),
            "point",
            "points"
        )
    ));
    d.markers(
        raw_pts,
        Marker::Dot,
        2.6,
        &Style::fill(FAINT).with_class("faint-point"),
    );
    draw_lines(&mut d, lines);
    robot(&mut d);
    if lines.is_empty() {
        d.note("no lines");
    }
    d
}

fn hough_legend(
    canvas: &mut Canvas,
    hs: &HoughSplit,
    (vmin, vmax): (f64, f64),
    unused: bool,
    rejected: bool,
    removed: bool,
) {
    canvas.add_legend(LegendEntry::new(
        Swatch::Marker(Marker::Dot, 4.0, Style::fill(POINT)),
        "valid point",
    ));
    if unused {
        canvas.add_legend(LegendEntry::new(
            Swatch::Marker(Marker::Dot, 4.0, Style::fill(FAINT)),
            "outside the extractor's range limits",
        ));
    }
    robot_legend(canvas);
    let weight = hs.params().weight;
    let ramp: Vec<Color> = (0..8).map(|k| cell_color(f64::from(k) / 7.0)).collect();
    let label = if vmax >= vmin {
        format!(
            "kept cell, value C from {} to {} (log scale)",
            cell_value_text(vmin, Weight::One),
            cell_value_text(vmax, weight)
        )
    } else {
        "kept cell, by value C".to_owned()
    };
    canvas.add_legend(LegendEntry::new(Swatch::Ramp(ramp), label));
    if rejected {
        canvas.add_legend(LegendEntry::new(
            Swatch::Line(Style::stroke(Color::LIGHT_GREY, 1.2)),
            "cell below the criterion",
        ));
    }
    canvas.add_legend(LegendEntry::new(
        Swatch::Line(Style::stroke(GROUP, 1.6)),
        "radius group",
    ));
    canvas.add_legend(LegendEntry::new(
        Swatch::Palette(Marker::Dot, (0..4).map(category).collect()),
        "points of one data segment",
    ));
    canvas.add_legend(LegendEntry::new(
        Swatch::Line(Style::stroke(Color::RED, 1.6)),
        "segment start to end",
    ));
    canvas.add_legend(LegendEntry::new(
        Swatch::Marker(Marker::Square, 5.0, Style::fill(Color::RED)),
        "segment start and end point",
    ));
    if removed {
        canvas.add_legend(LegendEntry::new(
            Swatch::Marker(Marker::Cross, 6.0, Style::stroke(Color::GREY, 1.1)),
            "removed point",
        ));
    }
    line_legend(canvas);
}

/// A cell value with its unit: metres for `g = r`, points for `g = 1` (the unit is left out
/// when `weight` is `One`, for the lower end of a range).
fn cell_value_text(v: f64, weight: Weight) -> String {
    let num = crate::svg::fmt_trimmed(v, 2);
    match weight {
        Weight::Range => format!("{num} m"),
        Weight::One => num,
    }
}

/// The smallest and largest finite value (`(1, 0)` when there is none).
fn value_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values
        .filter(|v| v.is_finite())
        .fold((1.0, 0.0), |(lo, hi): (f64, f64), v| {
            if lo > hi {
                (v, v)
            } else {
                (lo.min(v), hi.max(v))
            }
        })
}

/// Faint dashed rays along the first and last beam: the scan's field of view (none for a
/// scan that goes once round).
fn draw_field_of_view(panel: &mut Panel, scan: &Scan, view: &Extent) {
    if scan.is_empty()
        || !scan.angle_min.is_finite()
        || !scan.angle_increment.is_finite()
        || scan.full_turn()
    {
        return;
    }
    let reach = 2.0 * (view.width() + view.height());
    let style = Style::stroke(Color::LIGHT_GREY, 1.0)
        .with_dash(5.0, 4.0)
        .with_class("field-of-view");
    for a in [scan.angle_min, scan.angle_max()] {
        let end = Point2::new(reach * a.cos(), reach * a.sin());
        panel.line(Point2::origin(), end, &style);
    }
}

/// One map panel of a scan and its lines, from any extractor: the valid points, the lines
/// with red circles at their end points, and the robot at the origin facing +x; axes in
/// metres, a scale bar and a legend.
///
/// Nothing panics: an empty or all-invalid scan gives an empty panel with a note, and lines
/// with non-finite end points are left out.
#[must_use]
pub fn render_scan_lines(scan: &Scan, lines: &[Line], opts: &RenderOptions) -> String {
    let raw = scan.points(scan.range_window(None));
    let raw_pts = points_of(&raw);
    let view = view_for(opts, &raw_pts);
    let mut canvas = Canvas::new(1);
    canvas.set_title(opts.title.clone().unwrap_or_else(|| {
        format!(
            "{} from {}",
            plural(lines.len(), "line", "lines"),
            plural(raw.len(), "valid point", "valid points")
        )
    }));
    let mut p = Panel::map(view, plot_width(opts.width, 1));
    p.markers(
        &raw_pts,
        Marker::Dot,
        3.0,
        &Style::fill(Color::GREY).with_class("raw-point"),
    );
    draw_lines(&mut p, lines);
    robot(&mut p);
    if raw.is_empty() {
        p.note("no valid points");
    }
    canvas.add_panel(p);
    canvas.add_legend(LegendEntry::new(
        Swatch::Marker(Marker::Dot, 4.0, Style::fill(Color::GREY)),
        "valid point",
    ));
    line_legend(&mut canvas);
    robot_legend(&mut canvas);
    canvas.to_svg()
}
