//! The navigation figures: the paper's Fig. 7 (the three sectors and the object selected in
//! each, [`sectors_svg`]) and Fig. 8 (an exploration: the arena, the robot's true, odometric
//! and estimated paths, the lines it saw and its own map, [`exploration_map_svg`]).
//!
//! Both take plain data (points, segments, the sector objects of `laserlines-nav`), so that
//! they draw a real robot's run as well as a simulated one.

use laserlines::math::{Isometry2, Point2};
use laserlines_nav::{Sector, SectorObjects};

use crate::{Anchor, Canvas, Color, Extent, LegendEntry, Marker, Panel, Style, Swatch, TextStyle};

/// What Fig. 8 shows, world frame. Ground truth (walls, discs, the true path, the reachable
/// cells never seen) may be empty, as on a real robot.
#[derive(Debug, Clone, Copy)]
pub struct ExplorationMap<'a> {
    /// The title (e.g. the world, coverage and distance).
    pub title: &'a str,
    /// Walls as end points.
    pub walls: &'a [(Point2, Point2)],
    /// Round obstacles: centre and radius, m.
    pub discs: &'a [(Point2, f64)],
    /// The robot's start pose; the robot's map frame and odometry frame are placed there.
    pub start: Isometry2,
    /// The true path.
    pub path: &'a [Point2],
    /// The path by the wheel odometry alone.
    pub odometry_path: &'a [Point2],
    /// The path by the robot's own estimate (odometry and scan matching).
    pub estimated_path: &'a [Point2],
    /// Extracted lines, placed by the robot's own pose estimate.
    pub lines_seen: &'a [(Point2, Point2)],
    /// Centres of the occupied cells (0.1 m) of the robot's own map.
    pub robot_map: &'a [Point2],
    /// Centres of the arena's free coverage cells (0.1 m) never seen.
    pub unseen: &'a [Point2],
    /// The corners of the explorer's fence, in order (none: no fence).
    pub fence: &'a [Point2],
}

const WALL: Color = Color::INK;
const PATH: Color = Color::rgb(0x1b, 0x9e, 0x3a);
const ODOM: Color = Color::rgb(0x99, 0x99, 0x99);
const SEEN: Color = Color::BLUE;
const SELECTED: Color = Color::rgb(0x10, 0x3c, 0xd6);
const ROBOT_MAP: Color = Color::rgb(0xf5, 0xa6, 0x23);
const UNSEEN: Color = Color::rgb(0xe0, 0x40, 0x40);
const FENCE: Color = Color::rgb(0x8e, 0x44, 0xad);

/// A path drawn with points at least 15 cm apart (and its last point): a third of the
/// scans' points at full speed, no visible corner cut at the picture's scale.
fn thin(path: &[Point2]) -> Vec<Point2> {
    let mut out: Vec<Point2> = Vec::with_capacity(path.len() / 2 + 1);
    for &p in path {
        if out.last().is_none_or(|q| (p - q).norm() >= 0.15) {
            out.push(p);
        }
    }
    if let (Some(&last), Some(&kept)) = (path.last(), out.last())
        && last != kept
    {
        out.push(last);
    }
    out
}

/// The paper's Fig. 8: the arena, the robot's path, the lines it saw and its own map.
#[must_use]
pub fn exploration_map_svg(map: &ExplorationMap<'_>) -> String {
    let mut canvas = Canvas::new(1);
    canvas.add_panel(exploration_panel(map));
    exploration_legend(&mut canvas, map);
    canvas.to_svg()
}

/// The panel of Fig. 8.
fn exploration_panel(map: &ExplorationMap<'_>) -> Panel {
    let pts = map
        .walls
        .iter()
        .flat_map(|&(a, b)| [a, b])
        .chain(map.path.iter().copied());
    let view = Extent::fit_map(pts, 4.0).padded(0.5);
    let mut panel = Panel::map(view, 820.0);
    panel.set_title(map.title.to_owned());
    panel.set_labels("x [m]", "y [m]");
    let seen = Style::stroke(SEEN, 1.0)
        .with_opacity(0.35)
        .with_class("line-seen");
    for &(a, b) in map.lines_seen {
        panel.line(a, b, &seen);
    }
    // The robot's own map (occupied cells, placed by its start pose) and the reachable
    // cells it never saw.
    let cell_px = (0.1 * panel.px_per_unit()).max(1.0);
    panel.markers(
        map.robot_map,
        Marker::Square,
        cell_px,
        &Style::fill(ROBOT_MAP).with_class("robot-map"),
    );
    panel.markers(
        map.unseen,
        Marker::Square,
        cell_px,
        &Style::fill(UNSEEN).with_opacity(0.6).with_class("unseen"),
    );
    if let Some(&first) = map.fence.first() {
        let closed: Vec<Point2> = map.fence.iter().copied().chain([first]).collect();
        panel.polyline(
            &closed,
            &Style::stroke(FENCE, 1.6)
                .with_dash(8.0, 4.0)
                .with_class("fence"),
        );
    }
    let wall = Style::stroke(WALL, 2.2).with_class("wall");
    for &(a, b) in map.walls {
        panel.line(a, b, &wall);
    }
    let disc = Style::stroke(WALL, 1.5)
        .with_fill(Color::LIGHT_GREY)
        .with_class("disc");
    for &(centre, radius) in map.discs {
        panel.circle(centre, radius, &disc);
    }
    panel.polyline(
        &thin(map.odometry_path),
        &Style::stroke(ODOM, 1.0)
            .with_dash(4.0, 3.0)
            .with_class("odometry"),
    );
    panel.polyline(
        &thin(map.estimated_path),
        &Style::stroke(ROBOT_MAP, 1.0).with_class("estimated-path"),
    );
    panel.polyline(
        &thin(map.path),
        &Style::stroke(PATH, 1.8).with_class("path"),
    );
    let s = Point2::from(map.start.translation.vector);
    panel.circle(
        s,
        0.25,
        &Style::stroke(PATH, 2.0)
            .with_fill(Color::WHITE)
            .with_class("start"),
    );
    if let Some(end) = map.path.last() {
        panel.marker(*end, Marker::Circle, 8.0, &Style::fill(Color::RED));
    }
    panel
}

/// The legend of Fig. 8.
fn exploration_legend(canvas: &mut Canvas, map: &ExplorationMap<'_>) {
    canvas.add_legend(LegendEntry::new(
        Swatch::Line(Style::stroke(WALL, 2.2)),
        "wall",
    ));
    canvas.add_legend(LegendEntry::new(
        Swatch::Line(Style::stroke(PATH, 1.8)),
        "robot path (true)",
    ));
    canvas.add_legend(LegendEntry::new(
        Swatch::Line(Style::stroke(ODOM, 1.0).with_dash(4.0, 3.0)),
        "path by odometry",
    ));
    canvas.add_legend(LegendEntry::new(
        Swatch::Line(Style::stroke(ROBOT_MAP, 1.0)),
        "path by the robot's estimate (odometry and scan matching)",
    ));
    canvas.add_legend(LegendEntry::new(
        Swatch::Line(Style::stroke(SEEN, 1.0).with_opacity(0.35)),
        "extracted lines, placed by the robot's own pose estimate (1 scan in 3 s)",
    ));
    canvas.add_legend(LegendEntry::new(
        Swatch::Marker(Marker::Square, 8.0, Style::fill(ROBOT_MAP)),
        "the robot's own map: occupied cells (0.1 m), placed by its start",
    ));
    if !map.unseen.is_empty() {
        canvas.add_legend(LegendEntry::new(
            Swatch::Marker(Marker::Square, 8.0, Style::fill(UNSEEN)),
            "arena cells never seen",
        ));
    }
    if !map.fence.is_empty() {
        canvas.add_legend(LegendEntry::new(
            Swatch::Line(Style::stroke(FENCE, 1.6).with_dash(8.0, 4.0)),
            "fence the robot keeps inside, placed by its start",
        ));
    }
    canvas.add_legend(LegendEntry::new(
        Swatch::Marker(Marker::Circle, 10.0, Style::stroke(PATH, 2.0)),
        "start",
    ));
}

/// The paper's Fig. 7: the three sectors around the robot, the scan points, the extracted
/// lines and the selected object of each sector with its figures, robot frame. The view
/// reaches 3 m, or as far as the scan points when they are farther (at most 10 m).
#[must_use]
pub fn sectors_svg(
    title: &str,
    points: &[Point2],
    lines: &[(Point2, Point2)],
    objects: &SectorObjects,
) -> String {
    let (panel, fills) = sectors_panel(title, points, lines, objects);
    let mut canvas = Canvas::new(1);
    canvas.add_panel(panel);
    sectors_legend(&mut canvas, &fills);
    canvas.to_svg()
}

/// The panel of Fig. 7 and the sectors' fill colours.
fn sectors_panel(
    title: &str,
    points: &[Point2],
    lines: &[(Point2, Point2)],
    objects: &SectorObjects,
) -> (Panel, [Color; 3]) {
    let reach = points
        .iter()
        .map(|p| p.coords.norm())
        .filter(|r| r.is_finite())
        .fold(2.5_f64, f64::max);
    let half = (reach + 0.5).clamp(3.0, 10.0);
    let view = Extent::new(-half, -half, half, half);
    let mut panel = Panel::map(view, 560.0);
    panel.set_title(title.to_owned());
    let fills = [
        Color::rgb(0xfd, 0xe0, 0xc0),
        Color::rgb(0xd8, 0xec, 0xd8),
        Color::rgb(0xd8, 0xe0, 0xf4),
    ];
    for sector in Sector::ALL {
        let (from, to) = sector.bounds_rad();
        let style = Style::fill(fills[sector.index()])
            .with_opacity(0.7)
            .with_class(format!("sector-{}", sector.name()));
        panel.wedge(Point2::origin(), 0.0, half - 0.1, from, to, &style);
    }
    panel.markers(
        points,
        Marker::Dot,
        2.5,
        &Style::fill(Color::GREY).with_class("scan-point"),
    );
    let line = Style::stroke(Color::NAVY, 1.6).with_class("extracted-line");
    for &(a, b) in lines {
        panel.line(a, b, &line);
    }
    let selected = Style::stroke(SELECTED, 5.0)
        .with_opacity(0.85)
        .with_class("selected-object");
    let row_step = 0.1 * half;
    for obj in objects.objects.iter().flatten() {
        panel.line(obj.start, obj.end, &selected);
        panel.line(
            Point2::origin(),
            obj.nearest,
            &Style::stroke(SELECTED, 1.0).with_dash(3.0, 3.0),
        );
        // The figures in the lower left corner, one row per sector (left, front, right), so
        // that no label leaves the plot.
        let row = obj.sector.index() as f64;
        panel.text(
            Point2::new(view.min_x + 0.1, view.min_y + (2.5 - row) * row_step),
            &format!(
                "{}: distance {:.2} m, width {:.2} m, direction {:.0} deg",
                obj.sector.name(),
                obj.distance_m,
                obj.width_m,
                // Rounded first: a small negative angle reads 0, not -0.
                obj.angle_rad.to_degrees().round() + 0.0
            ),
            &TextStyle::size(11.0).anchored(Anchor::Start).with_halo(),
        );
    }
    panel.robot(Point2::origin(), 0.0, 14.0, &Style::fill(Color::RED));
    (panel, fills)
}

/// The legend of Fig. 7.
fn sectors_legend(canvas: &mut Canvas, fills: &[Color; 3]) {
    for sector in Sector::ALL {
        let (from, to) = sector.bounds_rad();
        canvas.add_legend(LegendEntry::new(
            Swatch::Patch(Style::fill(fills[sector.index()])),
            format!(
                "{} sector {:.0}..{:.0} deg",
                sector.name(),
                from.to_degrees(),
                to.to_degrees()
            ),
        ));
    }
    canvas.add_legend(LegendEntry::new(
        Swatch::Line(Style::stroke(SELECTED, 5.0)),
        "selected object (biggest and nearest: max width / distance)",
    ));
    canvas.add_legend(LegendEntry::new(
        Swatch::Line(Style::stroke(Color::NAVY, 1.6)),
        "extracted line",
    ));
}
