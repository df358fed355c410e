//! `laserlines simulate`: an exploration run of the simulated NAJI V in a rescue arena or a
//! seeded maze, with metrics and the paper's Fig. 7 and Fig. 8 as SVG.

use std::fs;
use std::io::{self, IsTerminal};
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use laserlines::math::{Isometry2, Point2, Vector2};
use laserlines::registry;
use laserlines::robot::RobotDescription;
use laserlines_harness::{RunConfig, RunObserver, RunRecord, ScanFrame, arenas, run_observed};
use laserlines_io::params::ParamsFile;
use laserlines_nav::{ExplorerParams, Sector, SectorObjects};
use laserlines_render::{Canvas, Color, Extent, LegendEntry, Marker, Panel, Style, Swatch};
use laserlines_sim::World;
use laserlines_sim::arena::{ArenaOptions, WallLength, interior_start, load_raf};
use laserlines_sim::maze::{MazeParams, generate};
use laserlines_sim::robot::RobotParams;

use super::simulate_mcap::McapRecorder;

/// Arguments of `laserlines simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// A RoboCup Rescue arena: a `.raf` file, or the name of a bundled one
    /// (maze_10m_x_14m, inner_explore_test). Default: maze_10m_x_14m.
    #[arg(long, conflicts_with = "maze")]
    arena: Option<String>,
    /// A seeded procedural maze on the 1.2 m grid instead of an arena.
    #[arg(long, value_name = "SEED")]
    maze: Option<u64>,
    /// Give the maze islands (wall groups not connected to the outer wall).
    #[arg(long, requires = "maze")]
    islands: bool,
    /// Simulated time limit, s.
    #[arg(long, default_value_t = 900.0)]
    duration: f64,
    /// Seed of the laser and odometry noise.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Start pose `x,y,yaw_deg` (m, m, deg) in the arena frame; default for arenas: the
    /// grid cell centre nearest the origin in the largest free region the walls enclose
    /// (cell (0, 0) in the bundled arenas; an arena file's origin may lie in a pocket
    /// closed by barrels or outside the arena), facing +x; for mazes: the maze's start.
    #[arg(long, value_name = "X,Y,YAW_DEG", allow_hyphen_values = true)]
    start: Option<String>,
    /// Arena walls 1.0 m long (the plate's mesh) instead of the whole 1.2 m cell edge.
    #[arg(long)]
    mesh_walls: bool,
    /// Simulated time of the sector picture, s.
    #[arg(long, default_value_t = 20.0)]
    snapshot: f64,
    /// Output folder.
    #[arg(short, long, default_value = "laserlines-simulate")]
    output: PathBuf,
    /// TOML file of settings: `[robot]` (footprint, drive limits, odometry noise, laser
    /// mount, rates), `[explorer]` (followed side, distances, speeds, timeouts) and
    /// `[hough-split]` (the line extractor); keys as in the README.
    #[arg(long, value_name = "FILE.toml")]
    params: Option<PathBuf>,
    /// Also record the run as MCAP for Foxglove: arena, true and estimated poses, scans,
    /// lines, sector objects and the explorer's goal.
    #[arg(long, value_name = "FILE")]
    mcap: Option<PathBuf>,
}

/// What watches the run: the progress bar and, with `--mcap`, the recorder.
struct Watch<'a> {
    progress: &'a ProgressBar,
    mcap: Option<McapRecorder>,
}

impl RunObserver for Watch<'_> {
    fn on_scan(&mut self, frame: &ScanFrame<'_>) {
        if let Some(m) = &mut self.mcap {
            m.on_scan(frame);
        }
    }
    fn on_progress(&mut self, time_s: f64) {
        self.progress.set_position(time_s as u64);
    }
}

/// Runs the command.
pub fn run(args: &SimulateArgs) -> Result<()> {
    if !(args.duration.is_finite() && args.duration > 0.0) {
        bail!(
            "--duration must be a positive number of seconds, got {}",
            args.duration
        );
    }
    let file = ParamsFile::load_or_default(args.params.as_deref())?;
    let robot = robot_of(&file)?;
    let (name, world, default_start) = world_of(args, &robot)?;
    let start = match &args.start {
        Some(s) => parse_start(s)?,
        None => default_start,
    };
    let config = RunConfig {
        robot,
        explorer: file.read_valid(
            "explorer",
            ExplorerParams::default(),
            ExplorerParams::validate,
        )?,
        extractor: file.algorithm_params(&registry::HOUGH_SPLIT)?,
        duration_s: args.duration,
        seed: args.seed,
        snapshot_at_s: args.snapshot,
        // The lines of one scan in 30 for the map picture (every 3 s).
        record_lines_every: 30,
    };

    let progress = if io::stderr().is_terminal() {
        let pb = ProgressBar::with_draw_target(
            Some(args.duration.ceil() as u64),
            ProgressDrawTarget::stderr(),
        );
        pb.set_style(
            ProgressStyle::with_template("{bar:40} {pos}/{len} s simulated, {elapsed} {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        pb
    } else {
        ProgressBar::hidden()
    };
    fs::create_dir_all(&args.output)
        .with_context(|| format!("cannot create {}", args.output.display()))?;
    let mcap = match &args.mcap {
        Some(path) => Some(
            McapRecorder::create(path, &world, config.robot.robot.footprint, start)
                .with_context(|| format!("cannot record the run to {}", path.display()))?,
        ),
        None => None,
    };
    let mut watch = Watch {
        progress: &progress,
        mcap,
    };
    let record = run_observed(&world, start, &config, &mut watch)
        .with_context(|| format!("cannot run in {name}"))?;
    progress.finish_and_clear();
    let mcap_scans = match (watch.mcap.take(), &args.mcap) {
        (Some(recorder), Some(path)) => Some((
            path,
            recorder
                .finish()
                .with_context(|| format!("cannot record the run to {}", path.display()))?,
        )),
        _ => None,
    };
    let metrics = metrics_json(&name, args, start, &record);
    let metrics_path = args.output.join("metrics.json");
    fs::write(&metrics_path, format!("{metrics:#}\n"))
        .with_context(|| format!("cannot write {}", metrics_path.display()))?;
    let map_path = args.output.join("map.svg");
    fs::write(&map_path, map_svg(&name, &world, start, &record))
        .with_context(|| format!("cannot write {}", map_path.display()))?;
    let sectors_path = args.output.join("sectors.svg");
    if let Some(snap) = &record.snapshot {
        let title = format!(
            "{name}, t = {:.1} s: three sectors and the selected objects (robot frame)",
            snap.time_s
        );
        fs::write(
            &sectors_path,
            sectors_svg(&title, &snap.points, &snap.lines, &snap.objects),
        )
        .with_context(|| format!("cannot write {}", sectors_path.display()))?;
    }

    let m = &record.metrics;
    outln!(
        "laserlines simulate: {name}, seed {}, start ({:.2}, {:.2}): coverage {:.3}, collisions {}, min clearance {:.3} m, path {:.1} m, {:.0} s simulated in {:.2} s ({:.0}x real time), 90% coverage at {}, pose error at most {:.2} m, stop {}",
        args.seed,
        start.translation.vector.x,
        start.translation.vector.y,
        m.coverage,
        m.collisions,
        m.min_clearance_m,
        m.path_length_m,
        m.sim_time_s,
        m.wall_time_s,
        m.sim_time_s / m.wall_time_s.max(1e-9),
        m.time_to_90_percent_s
            .map_or_else(|| "never".to_owned(), |t| format!("{t:.0} s")),
        m.max_pose_error_m,
        m.stop.name(),
    );
    outln!(
        "  wrote {}, {}{}",
        metrics_path.display(),
        map_path.display(),
        if record.snapshot.is_some() {
            format!(", {}", sectors_path.display())
        } else {
            String::new()
        }
    );
    if let Some((path, scans)) = mcap_scans {
        outln!("  wrote {} ({scans} scans)", path.display());
    }
    Ok(())
}

/// The simulated robot: its description from `[robot]`, the simulator's settings from
/// `[simulator]`.
fn robot_of(file: &ParamsFile) -> Result<RobotParams> {
    let robot = file.read_valid(
        "robot",
        RobotDescription::default(),
        RobotDescription::validate,
    )?;
    let simulated = file.read_valid(
        "simulator",
        RobotParams::default(),
        RobotParams::validate_simulation,
    )?;
    Ok(RobotParams { robot, ..simulated })
}

/// The world to explore, its name and the default start.
fn world_of(args: &SimulateArgs, robot: &RobotParams) -> Result<(String, World, Isometry2)> {
    if let Some(seed) = args.maze {
        let params = MazeParams {
            islands: if args.islands { 3 } else { 0 },
            ..MazeParams::default()
        };
        let maze = generate(&params, seed);
        let name = format!(
            "maze {seed}{}",
            if args.islands {
                format!(" with {} islands", maze.islands)
            } else {
                String::new()
            }
        );
        return Ok((name, maze.world, maze.start));
    }
    let options = ArenaOptions {
        wall_length: if args.mesh_walls {
            WallLength::Mesh
        } else {
            WallLength::Full
        },
    };
    let which = args.arena.as_deref().unwrap_or("maze_10m_x_14m");
    let path = PathBuf::from(which);
    let arena = if path.exists() {
        load_raf(&path, &options)?
    } else if let Some(a) = arenas::bundled(which, &options) {
        a?
    } else {
        bail!(
            "no arena file {which:?} (bundled arenas: {})",
            arenas::BUNDLED
                .iter()
                .map(|(n, _)| *n)
                .collect::<Vec<_>>()
                .join(", ")
        );
    };
    let report = &arena.report;
    if report.ignored_count() > 0 {
        let list = report
            .ignored
            .iter()
            .map(|(t, n)| format!("{t} x {n}"))
            .collect::<Vec<_>>()
            .join(", ");
        eprintln!(
            "laserlines: {}: ignored {} elements that are not walls or barrels: {list}",
            arena.name,
            report.ignored_count()
        );
        let unknown = report.unknown_types();
        if !unknown.is_empty() {
            eprintln!(
                "laserlines: {}: unknown element types (treated as not walls): {}",
                arena.name,
                unknown.join(", ")
            );
        }
    }
    let start = interior_start(&arena.world, robot.robot.footprint.circumradius())
        .unwrap_or_else(|| Isometry2::new(Vector2::zeros(), 0.0));
    Ok((arena.name.clone(), arena.world, start))
}

fn parse_start(s: &str) -> Result<Isometry2> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .with_context(|| format!("--start {s:?}: expected x,y,yaw_deg"))?;
    match v.as_slice() {
        [x, y, yaw] if v.iter().all(|a| a.is_finite()) => {
            Ok(Isometry2::new(Vector2::new(*x, *y), yaw.to_radians()))
        }
        _ => bail!("--start {s:?}: expected three finite numbers x,y,yaw_deg"),
    }
}

fn metrics_json(
    name: &str,
    args: &SimulateArgs,
    start: Isometry2,
    record: &RunRecord,
) -> serde_json::Value {
    let m = &record.metrics;
    let s = start.translation.vector;
    serde_json::json!({
        "world": name,
        "seed": args.seed,
        "params": args.params.as_ref().map(|p| p.display().to_string()),
        "start": [s.x, s.y, start.rotation.angle().to_degrees()],
        "duration_s": args.duration,
        "coverage": m.coverage,
        "collisions": m.collisions,
        "min_clearance_m": m.min_clearance_m,
        "path_length_m": m.path_length_m,
        "sim_time_s": m.sim_time_s,
        "wall_time_s": m.wall_time_s,
        "time_to_90_percent_s": m.time_to_90_percent_s,
        "reachable_area_m2": m.reachable_area_m2,
        "scans": m.scans,
        "lines": m.lines,
        "loops": m.loops,
        "frontiers": m.frontiers,
        "max_pose_error_m": m.max_pose_error_m,
        "max_heading_error_rad": m.max_heading_error_rad,
        "unmatched_scans": m.unmatched_scans,
        "stop": m.stop.name(),
    })
}

const WALL: Color = Color::INK;
const PATH: Color = Color::rgb(0x1b, 0x9e, 0x3a);
const ODOM: Color = Color::rgb(0x99, 0x99, 0x99);
const SEEN: Color = Color::BLUE;
const SELECTED: Color = Color::rgb(0x10, 0x3c, 0xd6);
const ROBOT_MAP: Color = Color::rgb(0xf5, 0xa6, 0x23);
const UNSEEN: Color = Color::rgb(0xe0, 0x40, 0x40);

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

/// The paper's Fig. 8: the arena, the robot's path and the lines it saw.
fn map_svg(name: &str, world: &World, start: Isometry2, record: &RunRecord) -> String {
    let pts = world
        .walls
        .iter()
        .flat_map(|w| [w.a, w.b])
        .chain(record.path.iter().copied());
    let view = Extent::fit_map(pts, 4.0).padded(0.5);
    let mut panel = Panel::map(view, 820.0);
    let m = &record.metrics;
    panel.set_title(format!(
        "{name}: coverage {:.1} %, {} collisions, {:.0} m in {:.0} s",
        100.0 * m.coverage,
        m.collisions,
        m.path_length_m,
        m.sim_time_s
    ));
    panel.set_labels("x [m]", "y [m]");
    let seen = Style::stroke(SEEN, 1.0)
        .with_opacity(0.35)
        .with_class("line-seen");
    for &(a, b) in &record.lines_seen {
        panel.line(a, b, &seen);
    }
    // The robot's own map (occupied cells, placed by its start pose) and the reachable
    // cells it never saw.
    let cell_px = (0.1 * panel.px_per_unit()).max(1.0);
    let robot_map: Vec<Point2> = record
        .map
        .occupied_cells()
        .into_iter()
        .map(|p| start * p)
        .collect();
    panel.markers(
        &robot_map,
        Marker::Square,
        cell_px,
        &Style::fill(ROBOT_MAP).with_class("robot-map"),
    );
    panel.markers(
        &record.unseen,
        Marker::Square,
        cell_px,
        &Style::fill(UNSEEN).with_opacity(0.6).with_class("unseen"),
    );
    let wall = Style::stroke(WALL, 2.2).with_class("wall");
    for w in &world.walls {
        panel.line(w.a, w.b, &wall);
    }
    let disc = Style::stroke(WALL, 1.5)
        .with_fill(Color::LIGHT_GREY)
        .with_class("disc");
    for d in &world.discs {
        panel.circle(d.centre, d.radius, &disc);
    }
    panel.polyline(
        &thin(&record.odometry_path),
        &Style::stroke(ODOM, 1.0)
            .with_dash(4.0, 3.0)
            .with_class("odometry"),
    );
    panel.polyline(
        &thin(&record.estimated_path),
        &Style::stroke(ROBOT_MAP, 1.0).with_class("estimated-path"),
    );
    panel.polyline(
        &thin(&record.path),
        &Style::stroke(PATH, 1.8).with_class("path"),
    );
    let s = Point2::from(start.translation.vector);
    panel.circle(
        s,
        0.25,
        &Style::stroke(PATH, 2.0)
            .with_fill(Color::WHITE)
            .with_class("start"),
    );
    if let Some(end) = record.path.last() {
        panel.marker(*end, Marker::Circle, 8.0, &Style::fill(Color::RED));
    }
    let mut canvas = Canvas::new(1);
    canvas.add_panel(panel);
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
    if !record.unseen.is_empty() {
        canvas.add_legend(LegendEntry::new(
            Swatch::Marker(Marker::Square, 8.0, Style::fill(UNSEEN)),
            "reachable cells never seen",
        ));
    }
    canvas.add_legend(LegendEntry::new(
        Swatch::Marker(Marker::Circle, 10.0, Style::stroke(PATH, 2.0)),
        "start",
    ));
    canvas.to_svg()
}

/// The paper's Fig. 7: the three sectors around the robot, the scan points, the extracted
/// lines and the selected object of each sector with its figures, robot frame. The view
/// reaches 3 m, or as far as the scan points when they are farther (at most 10 m).
pub(crate) fn sectors_svg(
    title: &str,
    points: &[Point2],
    lines: &[(Point2, Point2)],
    objects: &SectorObjects,
) -> String {
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
                "{}: distance {:.2} m, width {:.2} m, angle {:.0} deg",
                obj.sector.name(),
                obj.distance_m,
                obj.width_m,
                obj.angle_rad.to_degrees()
            ),
            &laserlines_render::TextStyle::size(11.0)
                .anchored(laserlines_render::Anchor::Start)
                .with_halo(),
        );
    }
    panel.robot(Point2::origin(), 0.0, 14.0, &Style::fill(Color::RED));
    let mut canvas = Canvas::new(1);
    canvas.add_panel(panel);
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
    canvas.to_svg()
}
