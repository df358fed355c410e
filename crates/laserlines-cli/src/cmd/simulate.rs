//! `laserlines simulate`: an exploration run of the simulated NAJI V in a rescue arena or a
//! seeded maze, with metrics and the paper's Fig. 7 and Fig. 8 as SVG.

use std::fs;
use std::io::{self, IsTerminal};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use laserlines::math::{Isometry2, Point2};
use laserlines::robot::RobotDescription;
use laserlines::{HoughSplitParams, registry};
use laserlines_foxglove::{NavFrame, NavRecorder};
use laserlines_harness::{
    RunConfig, RunObserver, RunRecord, ScanFrame, StopReason, arenas, run_observed,
};
use laserlines_io::params::ParamsFile;
use laserlines_nav::ExplorerParams;
use laserlines_render::{ExplorationMap, exploration_map_svg, sectors_svg};
use laserlines_sim::World;
use laserlines_sim::arena::ArenaReport;
use laserlines_sim::robot::RobotParams;

use super::simulate_world::{
    check_start_inside, parse_start, warn_if_cramped, warn_of_fence, world_of,
};

/// Arguments of `laserlines simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// A RoboCup Rescue arena: a `.raf` file, or the name of a bundled one
    /// (maze_10m_x_14m, inner_explore_test, go2011_arena, rc_2015_arena_big). Default:
    /// maze_10m_x_14m.
    #[arg(long, conflicts_with = "maze")]
    pub(super) arena: Option<String>,
    /// A seeded procedural maze on the 1.2 m grid instead of an arena.
    #[arg(long, value_name = "SEED", value_parser = super::whole::<u64>, allow_negative_numbers = true)]
    pub(super) maze: Option<u64>,
    /// Give the maze islands (wall groups not connected to the outer wall).
    #[arg(long, requires = "maze", conflicts_with = "arena")]
    pub(super) islands: bool,
    /// Cut the corners of this many of the maze's turning cells by 45-degree walls (more
    /// than the maze has is refused, naming its number).
    #[arg(
        long,
        value_name = "N",
        requires = "maze",
        conflicts_with = "arena",
        value_parser = super::whole::<usize>,
        allow_negative_numbers = true
    )]
    pub(super) diagonals: Option<usize>,
    /// Simulated time limit, s, more than 0 up to 1e9.
    #[arg(long, default_value_t = 900.0, allow_negative_numbers = true)]
    duration: f64,
    /// Seed of the laser and odometry noise.
    #[arg(long, default_value_t = 0, value_parser = super::whole::<u64>, allow_negative_numbers = true)]
    seed: u64,
    /// Start pose `x,y,yaw_deg` (m, m, deg) in the arena frame; default for arenas: the
    /// grid cell centre nearest the origin in the largest free region inside the arena's
    /// outline (cell (0, 0) in the bundled arenas; an arena file's origin may lie in a
    /// pocket or outside the arena), facing +x; for mazes: the maze's start.
    #[arg(long, value_name = "X,Y,YAW_DEG", allow_hyphen_values = true)]
    start: Option<String>,
    /// Arena walls 1.0 m long (the plate's mesh) instead of the whole 1.2 m cell edge (arenas
    /// only).
    #[arg(long, conflicts_with = "maze")]
    pub(super) mesh_walls: bool,
    /// Simulated time of the sector picture, s, within the run (default: 20 s, or half the
    /// duration when that is shorter).
    #[arg(long, allow_negative_numbers = true)]
    snapshot: Option<f64>,
    /// Output folder.
    #[arg(short, long, default_value = "laserlines-simulate")]
    output: PathBuf,
    /// TOML file of settings: `[robot]` (footprint, drive limits, wheel base, laser mount),
    /// `[simulator]` (odometry noise, laser model, scan and physics periods, laser height),
    /// `[explorer]` (followed side, distances, speeds, timeouts) and `[hough-split]` (the
    /// line extractor); keys as in the README.
    #[arg(long, value_name = "FILE.toml")]
    params: Option<PathBuf>,
    /// Keep the robot inside the arena's bounds (the bounding box of its largest group of
    /// walls), as an operator who knows the arena's extent would: a virtual wall that the
    /// explorer follows and does not cross (`[explorer.fence]` in the params file sets any
    /// other rectangle; this flag replaces it). For arenas open at their entrance or with gaps
    /// in the outer wall.
    #[arg(long)]
    pub fence: bool,
    /// Also record the run as MCAP for Foxglove: arena, true and estimated poses, scans,
    /// lines, sector objects and the explorer's goal.
    #[arg(long, value_name = "FILE")]
    mcap: Option<PathBuf>,
}

/// What watches the run: the progress bar and, with `--mcap`, the recorder.
struct Watch<'a> {
    progress: &'a ProgressBar,
    mcap: Option<NavRecorder>,
}

impl RunObserver for Watch<'_> {
    fn on_scan(&mut self, frame: &ScanFrame<'_>) {
        if let Some(m) = &mut self.mcap {
            m.record(&NavFrame {
                time_s: frame.time_s,
                world_from_robot: frame.world_from_robot,
                odom_from_robot: Some(frame.odom_from_robot),
                estimated_world_from_robot: frame.estimated_world_from_robot,
                robot_from_laser: frame.robot_from_laser,
                scan: frame.scan,
                lines: frame.lines,
                decision: frame.decision,
                coverage: Some(frame.coverage),
            });
        }
    }
    fn on_progress(&mut self, time_s: f64) {
        self.progress.set_position(time_s as u64);
    }
}

/// What a run is made of: the world, its name, the start and the settings.
struct Setup {
    name: String,
    world: World,
    start: Isometry2,
    config: RunConfig,
    /// What the arena loader made of the elements (arenas only).
    arena: Option<ArenaReport>,
    /// Wall-clock time of reading the arena or generating the maze and finding the start.
    load_time_s: f64,
}

/// Runs the command.
pub fn run(args: &SimulateArgs) -> Result<()> {
    super::seconds("--duration", args.duration, false)?;
    let mut used = vec!["hough-split"];
    used.extend_from_slice(laserlines_io::params::RUN_TABLES);
    super::note_unused_tables(args.params.as_deref(), &used, "simulate")?;
    let setup = setup(args)?;
    // What would end the run at once ends it before any file is made.
    setup
        .config
        .check(&setup.world, setup.start)
        .with_context(|| {
            let with = args
                .params
                .as_deref()
                .map_or_else(String::new, |p| format!(" with {}", p.display()));
            format!("cannot run in {}{with}", setup.name)
        })?;
    if args.start.is_some() {
        let radius = setup.config.robot.robot.footprint.circumradius();
        warn_if_cramped(&setup.world, setup.start, radius);
    }
    // The snapshot is of a scan: at most the last one's time.
    let last_scan = setup.config.last_scan_s();
    if let Some(t) = args.snapshot
        && !(t.is_finite() && (0.0..=last_scan).contains(&t))
    {
        bail!(
            "--snapshot must lie within the run, from 0 to its last scan at {last_scan:.3} s \
             (--duration {} s), got {}",
            super::compact(args.duration),
            super::compact(t)
        );
    }
    // The recording's folder first (unless it is the output folder, made below): a failed
    // run leaves no empty output folder behind.
    if let Some(path) = &args.mcap {
        let arena = args.arena.as_deref().map(Path::new).filter(|a| a.is_file());
        let inputs: Vec<&Path> = [arena, args.params.as_deref()]
            .into_iter()
            .flatten()
            .collect();
        super::refuse_recording_over(path, &inputs, &args.output, &OUTPUT_FILES)?;
        if !path
            .parent()
            .is_some_and(|p| super::same_path(p, &args.output))
        {
            super::output_folder_exists(path)?;
        }
    }
    super::create_output_dir(&args.output)?;
    let (record, mcap_scans) = explore(args, &setup)?;
    let written = write_outputs(args, &setup, &record)?;
    print_summary(args, &setup, &record, &written);
    if let (Some(path), Some(scans)) = (&args.mcap, mcap_scans) {
        outln!(
            "  wrote {} ({})",
            path.display(),
            super::count(scans, "scan")
        );
    }
    Ok(())
}

/// The world, the start and the settings of the arguments and the params file.
fn setup(args: &SimulateArgs) -> Result<Setup> {
    let file = ParamsFile::load_or_default(args.params.as_deref())?;
    let robot = robot_of(&file)?;
    let loading = std::time::Instant::now();
    let (name, world, default_start, arena) = world_of(args, &robot)?;
    let load_time_s = loading.elapsed().as_secs_f64();
    let start = match &args.start {
        Some(s) => {
            let start = parse_start(s)?;
            check_start_inside(&name, &world, start)?;
            start
        }
        None => default_start.with_context(|| {
            format!(
                "{name}: no place among its walls where the robot fits, {:.2} m from every \
                 obstacle; give a start with --start X,Y,YAW_DEG",
                robot.robot.footprint.circumradius()
            )
        })?,
    };
    let mut config = RunConfig {
        robot,
        explorer: file.read_valid(
            "explorer",
            ExplorerParams::default(),
            ExplorerParams::validate,
        )?,
        extractor: file
            .algorithm_params_over(&registry::HOUGH_SPLIT, HoughSplitParams::navigation())?,
        duration_s: args.duration,
        seed: args.seed,
        snapshot_at_s: snapshot_time(args),
        // The lines of one scan in 30 for the map picture (every 3 s).
        record_lines_every: 30,
        extraction_thread: false,
    };
    if args.fence {
        config.explorer.fence = Some(arenas::fence_of(&world, &start).with_context(|| {
            format!("--fence: {name} has no walls that bound an area to take as the fence")
        })?);
    } else if let Some(fence) = &config.explorer.fence {
        warn_of_fence(fence, config.robot.robot.footprint.circumradius());
    }
    Ok(Setup {
        name,
        world,
        start,
        config,
        arena,
        load_time_s,
    })
}

/// Simulated seconds as a progress bar on a terminal.
fn progress_bar(duration_s: f64) -> ProgressBar {
    if !io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let pb =
        ProgressBar::with_draw_target(Some(duration_s.ceil() as u64), ProgressDrawTarget::stderr());
    pb.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} s simulated, {elapsed} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    pb
}

/// The run, watched by the progress bar and, with `--mcap`, recorded; the number of scans
/// recorded.
fn explore(args: &SimulateArgs, setup: &Setup) -> Result<(RunRecord, Option<u64>)> {
    let progress = progress_bar(args.duration);
    let mcap = match &args.mcap {
        Some(path) => {
            let mut recorder = NavRecorder::create(
                path,
                &walls_of(&setup.world),
                &discs_of(&setup.world),
                setup.config.robot.robot.footprint,
                setup.start,
            )
            .with_context(|| format!("cannot record the run to {}", path.display()))?;
            let fence = fence_corners(setup);
            if !fence.is_empty() {
                recorder
                    .write_fence(&fence)
                    .with_context(|| format!("cannot record the run to {}", path.display()))?;
            }
            Some(recorder)
        }
        None => None,
    };
    let mut watch = Watch {
        progress: &progress,
        mcap,
    };
    let record = run_observed(&setup.world, setup.start, &setup.config, &mut watch)
        .with_context(|| format!("cannot run in {}", setup.name))?;
    progress.finish_and_clear();
    let scans = match (watch.mcap.take(), &args.mcap) {
        (Some(recorder), Some(path)) => Some(
            recorder
                .finish()
                .with_context(|| format!("cannot record the run to {}", path.display()))?,
        ),
        _ => None,
    };
    Ok((record, scans))
}

/// The files written: the metrics, the map and (when the run lasted until the snapshot) the
/// sector picture.
struct Written {
    metrics: PathBuf,
    map: PathBuf,
    sectors: Option<PathBuf>,
}

/// Every file `simulate` writes in its output folder.
const OUTPUT_FILES: [&str; 3] = ["metrics.json", "map.svg", "sectors.svg"];

/// Writes `metrics.json`, `map.svg` (Fig. 8) and `sectors.svg` (Fig. 7).
fn write_outputs(args: &SimulateArgs, setup: &Setup, record: &RunRecord) -> Result<Written> {
    let write = |path: &PathBuf, text: String| {
        fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
    };
    let name = &setup.name;
    let metrics = args.output.join("metrics.json");
    write(
        &metrics,
        format!("{:#}\n", metrics_json(name, args, setup, record)?),
    )?;
    let map = args.output.join("map.svg");
    write(&map, map_figure(name, setup, record))?;
    let sectors = match &record.snapshot {
        Some(snap) => {
            let path = args.output.join("sectors.svg");
            let title = format!(
                "{name}, t = {:.1} s: three sectors and the selected objects (robot frame)",
                snap.time_s
            );
            let svg = sectors_svg(&title, &snap.points, &snap.lines, &snap.objects);
            write(&path, svg)?;
            Some(path)
        }
        None => {
            // A picture of an earlier run in the same folder would pass for this one's.
            let stale = args.output.join("sectors.svg");
            let removed = stale.exists() && std::fs::remove_file(&stale).is_ok();
            errln!(
                "laserlines: sectors.svg not written{}: no scan came at or after the snapshot \
                 at {:.3} s (--snapshot) before the run ended at {:.3} s (a scan every {} s)",
                if removed {
                    " (an earlier run's removed)"
                } else {
                    ""
                },
                snapshot_time(args),
                record.metrics.sim_time_s,
                super::compact(setup.config.robot.scan_period_s)
            );
            None
        }
    };
    Ok(Written {
        metrics,
        map,
        sectors,
    })
}

/// The one-line summary and the files written, on standard output.
fn print_summary(args: &SimulateArgs, setup: &Setup, record: &RunRecord, written: &Written) {
    let m = &record.metrics;
    let start = setup.start.translation.vector;
    outln!(
        "laserlines simulate: {}, seed {}, start ({:.2}, {:.2}): coverage {:.1} % of {:.1} m^2 ({}), collisions {}, min clearance {:.3} m, path {:.1} m, {:.0} s simulated in {:.2} s ({:.0}x real time), 90 % coverage {}, pose error at most {:.2} m, stop {}{}",
        setup.name,
        args.seed,
        start.x,
        start.y,
        100.0 * m.coverage,
        m.arena_area_m2,
        m.coverage_region.name(),
        m.collisions,
        m.min_clearance_m,
        m.path_length_m,
        m.sim_time_s,
        m.wall_time_s,
        m.sim_time_s / m.wall_time_s.max(1e-9),
        m.time_to_90_percent_s
            .map_or_else(|| "not reached".to_owned(), |t| format!("at {t:.0} s")),
        m.max_pose_error_m,
        m.stop.name(),
        m.left_arena_at_s
            .map_or_else(String::new, |t| format!(", LEFT THE ARENA at {t:.1} s")),
    );
    outln!(
        "  wrote {}, {}{}",
        written.metrics.display(),
        written.map.display(),
        written
            .sectors
            .as_ref()
            .map_or_else(String::new, |p| format!(", {}", p.display()))
    );
    if m.arena_area_m2 <= 0.0 {
        outln!(
            "  the region to cover has no free floor (0 m^2): there was nothing to cover, and \
             the coverage figures say nothing"
        );
    } else if m.path_length_m < 0.05 && m.stop == StopReason::Explored && m.reachable_coverage < 0.9
    {
        outln!(
            "  the robot did not move from its start: its planner found no way from there to \
             any frontier of its map (a start this near an obstacle can leave it none), so \
             the run ended with what the start shows"
        );
    }
    if m.left_arena && setup.config.explorer.fence.is_none() {
        outln!("  the robot left the arena: --fence keeps it inside the arena's bounds");
    }
}

/// Checks the tables of a params file that `simulate` reads (`[robot]`, `[simulator]`,
/// `[explorer]`) as `simulate` would, for a command that does not read them.
pub fn check_run_tables(file: &ParamsFile) -> Result<()> {
    robot_of(file)?;
    file.read_valid(
        "explorer",
        ExplorerParams::default(),
        ExplorerParams::validate,
    )?;
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
    let both = RobotParams { robot, ..simulated };
    both.validate_motion()
        .map_err(|e| file.invalid("robot", e))?;
    Ok(both)
}

/// The simulated time of the sector picture: `--snapshot`, or 20 s, or half the run when
/// that is shorter.
fn snapshot_time(args: &SimulateArgs) -> f64 {
    args.snapshot.unwrap_or(20.0_f64.min(0.5 * args.duration))
}

/// What `wall_time_s` of `metrics.json` includes, in words.
const WALL_TIME_INCLUDES: &str = "the closed loop from the first scan to the last step: \
    laser simulation, line extraction, explorer, physics, ground-truth coverage, progress \
    bar and MCAP recording; not load_time_s (reading the arena, finding the start), \
    setup_time_s (obstacle index, coverage grid), starting the process or writing the outputs";

/// `metrics.json`: the run's settings, its [`laserlines_harness::Metrics`] and, for an
/// arena, what the loader made of its elements.
fn metrics_json(
    name: &str,
    args: &SimulateArgs,
    setup: &Setup,
    record: &RunRecord,
) -> Result<serde_json::Value> {
    let start = setup.start;
    let s = start.translation.vector;
    let mut json = serde_json::to_value(record.metrics)?;
    if let Some(map) = json.as_object_mut() {
        let params = args.params.as_ref().map(|p| p.display().to_string());
        map.insert("world".to_owned(), name.into());
        map.insert("seed".to_owned(), args.seed.into());
        map.insert("params".to_owned(), params.into());
        map.insert(
            "fence".to_owned(),
            serde_json::to_value(setup.config.explorer.fence)?,
        );
        map.insert(
            "start".to_owned(),
            serde_json::json!([s.x, s.y, start.rotation.angle().to_degrees()]),
        );
        map.insert("duration_s".to_owned(), args.duration.into());
        map.insert("wall_time_includes".to_owned(), WALL_TIME_INCLUDES.into());
        map.insert("load_time_s".to_owned(), setup.load_time_s.into());
        if let Some(report) = &setup.arena {
            map.insert(
                "arena".to_owned(),
                serde_json::json!({
                    "elements": report.elements,
                    "laser_height_m": report.laser_height_m,
                    "in_plane": report.in_plane,
                    "out_of_plane": report.out_of_plane,
                    "skipped": report.skipped,
                    "skipped_count": report.skipped_count(),
                }),
            );
        }
    }
    Ok(json)
}

/// The paper's Fig. 8 of the run.
fn map_figure(name: &str, setup: &Setup, record: &RunRecord) -> String {
    let (world, start) = (&setup.world, setup.start);
    let m = &record.metrics;
    let title = format!(
        "{name}: coverage {:.1} %, {} collisions, {:.0} m in {:.0} s",
        100.0 * m.coverage,
        m.collisions,
        m.path_length_m,
        m.sim_time_s
    );
    let (walls, discs) = (walls_of(world), discs_of(world));
    // The robot's own map, placed by its start pose.
    let robot_map: Vec<Point2> = record
        .map
        .occupied_cells()
        .into_iter()
        .map(|p| start * p)
        .collect();
    let fence = fence_corners(setup);
    exploration_map_svg(&ExplorationMap {
        title: &title,
        walls: &walls,
        discs: &discs,
        start,
        path: &record.path,
        odometry_path: &record.odometry_path,
        estimated_path: &record.estimated_path,
        lines_seen: &record.lines_seen,
        robot_map: &robot_map,
        unseen: &record.unseen,
        fence: &fence,
    })
}

/// The explorer's fence as corners in the world frame, placed by the start pose as the
/// robot's map is (none without a fence).
fn fence_corners(setup: &Setup) -> Vec<Point2> {
    setup
        .config
        .explorer
        .fence
        .map(|f| f.corners().map(|c| setup.start * c).to_vec())
        .unwrap_or_default()
}

/// The world's walls by their end points.
fn walls_of(world: &World) -> Vec<(Point2, Point2)> {
    world.walls.iter().map(|w| (w.a, w.b)).collect()
}

/// The world's discs by centre and radius.
fn discs_of(world: &World) -> Vec<(Point2, f64)> {
    world.discs.iter().map(|d| (d.centre, d.radius)).collect()
}
