//! The files `laserlines map` writes.
//!
//! | file | content |
//! |---|---|
//! | `trajectory.tum` | one line per scan, `t x y z qx qy qz qw`, stamped with the scan's time |
//! | `log-poses.tum` | the log's own poses (CARMEN's laser pose: a log's corrected poses), when every scan has one |
//! | `odometry.tum` | the log's odometry, when every scan has it |
//! | `map.pgm`, `map.yaml` | the occupancy grid in ROS `map_server` form |
//! | `map.png` | the same grid as a PNG |
//! | `lines.json` | the line map: `{"frame": "map", "lines": [{"start", "end", "r", "alpha", "scan_lines", "points"}]}` |
//! | `map.svg` | grid, line map, path and loop closures, as the paper's Fig. 8 |

use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use laserlines::math::Point2;
use laserlines_foxglove::McapSceneWriter;
use laserlines_io::Pose2;
use laserlines_io::trajectory::{MapImage, StampedPose, write_map_server, write_tum};
use laserlines_render::{GreyMap, MapFigure, encode_grey_png, render_map};
use laserlines_slam::{LineMapParams, MapLine, Mapper, OccupancyGrid, OccupancyParams, Se2};
use serde::Serialize;

/// What the outputs are made of.
pub struct Outputs<'a> {
    /// Output directory.
    pub dir: &'a Path,
    /// The log's name, for titles.
    pub name: &'a str,
    /// The mapper after its final optimisation.
    pub mapper: &'a Mapper,
    /// Each scan's time, s.
    pub stamps: &'a [f64],
    /// Each scan's pose in the log, when it had one.
    pub log_poses: &'a [Option<Pose2>],
    /// Each scan's odometry in the log, when it had one.
    pub log_odometry: &'a [Option<Pose2>],
    /// Occupancy grid cell, m.
    pub resolution_m: f64,
}

/// Makes the output directory `dir` and tries a file in it, so that a directory that cannot
/// be written fails before the mapping.
pub fn prepare_dir(dir: &Path) -> Result<()> {
    super::create_output_dir(dir)?;
    let probe = dir.join(".laserlines-write-check");
    File::create(&probe)
        .and_then(|_| fs::remove_file(&probe))
        .with_context(|| format!("cannot write in {}", dir.display()))
}

/// Writes every file into the output directory; returns their paths.
pub fn write_all(o: &Outputs<'_>) -> Result<Vec<PathBuf>> {
    fs::create_dir_all(o.dir).with_context(|| format!("cannot create {}", o.dir.display()))?;
    let mut files = Vec::new();
    let poses = o.mapper.poses();
    let traj: Vec<StampedPose> = o
        .stamps
        .iter()
        .zip(poses)
        .map(|(&t, p)| stamped(t, p))
        .collect();
    files.push(write_file(o.dir, "trajectory.tum", |w| {
        write_tum(w, &traj)
    })?);
    for (poses, file) in [
        (o.log_poses, "log-poses.tum"),
        (o.log_odometry, "odometry.tum"),
    ] {
        if poses.iter().all(Option::is_some) {
            let logged: Vec<StampedPose> = o
                .stamps
                .iter()
                .zip(poses.iter().flatten())
                .map(|(&t, &pose)| StampedPose { t, pose })
                .collect();
            files.push(write_file(o.dir, file, |w| write_tum(w, &logged))?);
        } else {
            remove_stale(o.dir, &[file]);
        }
    }
    let walls = o.mapper.line_map(&LineMapParams::default());
    files.push(write_file(o.dir, "lines.json", |w| {
        write_line_map(w, &walls)
    })?);
    let grid = o
        .mapper
        .occupancy_grid(&OccupancyParams {
            resolution_m: o.resolution_m,
            ..OccupancyParams::default()
        })
        .map_err(|e| {
            remove_stale(o.dir, MAP_FILES);
            anyhow::anyhow!(
                "{}: occupancy grid: {e} (cells of {} m would fit; the trajectory and \
                 lines.json are written in {})",
                o.name,
                e.fitting_resolution(),
                o.dir.display()
            )
        })?;
    let pixels = grid.to_pixels();
    let image = MapImage {
        pixels: &pixels,
        width: grid.width,
        height: grid.height,
        resolution_m: grid.resolution,
        origin: (grid.origin.x, grid.origin.y),
    };
    let pgm = o.dir.join("map.pgm");
    let mut pgm_out = create(&pgm)?;
    files.push(write_file(o.dir, "map.yaml", |w| {
        write_map_server(&mut pgm_out, w, "map.pgm", &image)
    })?);
    pgm_out
        .flush()
        .with_context(|| format!("cannot write {}", pgm.display()))?;
    files.push(pgm);
    let png = encode_grey_png(&pixels, grid.width, grid.height).context("map.png")?;
    files.push(write_file(o.dir, "map.png", |w| w.write_all(&png))?);
    let svg = map_svg(o, &grid, &pixels, &walls)?;
    files.push(write_file(o.dir, "map.svg", |w| {
        w.write_all(svg.as_bytes())
    })?);
    Ok(files)
}

/// Every file `map` writes in its output folder, the occupancy grid's last.
pub const OUTPUT_FILES: [&str; 8] = [
    "trajectory.tum",
    "log-poses.tum",
    "odometry.tum",
    "lines.json",
    "map.pgm",
    "map.yaml",
    "map.png",
    "map.svg",
];

/// The files of the occupancy grid.
const MAP_FILES: &[&str] = OUTPUT_FILES.split_at(4).1;

/// Removes the files `names` of `dir` that an earlier run wrote and this one does not, so
/// that none passes for this run's (a `log-poses.tum` of another log beside this
/// trajectory), and says so.
fn remove_stale(dir: &Path, names: &[&str]) {
    let removed: Vec<&str> = names
        .iter()
        .copied()
        .filter(|n| fs::remove_file(dir.join(n)).is_ok())
        .collect();
    if !removed.is_empty() {
        errln!(
            "laserlines: removed {} of an earlier run from {}: this run does not write {}",
            removed.join(", "),
            dir.display(),
            if removed.len() == 1 { "it" } else { "them" }
        );
    }
}

fn stamped(t: f64, p: &Se2) -> StampedPose {
    StampedPose {
        t,
        pose: Pose2::new(p.x, p.y, p.theta),
    }
}

fn create(path: &Path) -> Result<BufWriter<File>> {
    Ok(BufWriter::new(File::create(path).with_context(|| {
        format!("cannot create {}", path.display())
    })?))
}

/// Creates `dir/name`, fills it with `fill`, flushes it; returns its path.
fn write_file(
    dir: &Path,
    name: &str,
    fill: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> Result<PathBuf> {
    let path = dir.join(name);
    let mut out = create(&path)?;
    fill(&mut out)
        .and_then(|()| out.flush())
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(path)
}

#[derive(Serialize)]
struct LineMapFile<'a> {
    frame: &'a str,
    lines: Vec<WallRecord>,
}

#[derive(Serialize)]
struct WallRecord {
    start: [f64; 2],
    end: [f64; 2],
    r: f64,
    alpha: f64,
    scan_lines: usize,
    points: usize,
}

fn write_line_map(w: &mut impl Write, walls: &[MapLine]) -> std::io::Result<()> {
    let file = LineMapFile {
        frame: "map",
        lines: walls
            .iter()
            .map(|m| WallRecord {
                start: [m.start.x, m.start.y],
                end: [m.end.x, m.end.y],
                r: m.r,
                alpha: m.alpha,
                scan_lines: m.lines,
                points: m.points,
            })
            .collect(),
    };
    serde_json::to_writer(&mut *w, &file)?;
    writeln!(w)
}

/// The paper's Fig. 8 for a log: grid, walls, path, closures.
fn map_svg(
    o: &Outputs<'_>,
    grid: &OccupancyGrid,
    pixels: &[u8],
    walls: &[MapLine],
) -> Result<String> {
    let poses = o.mapper.poses();
    let path: Vec<Point2> = poses.iter().map(|p| Point2::new(p.x, p.y)).collect();
    let wall_segments: Vec<(Point2, Point2)> = walls
        .iter()
        .filter(|w| w.lines >= 2)
        .map(|w| (w.start, w.end))
        .collect();
    let closures: Vec<(Point2, Point2)> = o
        .mapper
        .graph()
        .edges()
        .iter()
        .filter(|e| e.to != e.from + 1)
        .map(|e| (path[e.from], path[e.to]))
        .collect();
    let s = o.mapper.stats();
    let file = Path::new(o.name)
        .file_name()
        .map_or_else(|| o.name.into(), |f| f.to_string_lossy());
    let fig = MapFigure {
        title: format!(
            "{file}: {}, {}, {}",
            super::count(s.scans as u64, "scan"),
            super::count(s.closures_accepted as u64, "loop closure"),
            super::count(wall_segments.len() as u64, "wall")
        ),
        grid: Some(GreyMap {
            pixels,
            width: grid.width,
            height: grid.height,
            resolution_m: grid.resolution,
            origin: grid.origin,
        }),
        walls: &wall_segments,
        path: &path,
        closures: &closures,
    };
    render_map(&fig).context("map.svg")
}

/// The run for Foxglove: per scan the estimated pose, the scan and its lines; the map as
/// `foxglove.Grid` on `/map` (frame `world`) at the first scan's time.
pub fn write_mcap(
    mut w: McapSceneWriter<BufWriter<File>>,
    o: &Outputs<'_>,
    kept: &[(laserlines_io::ScanRecord, Vec<laserlines::Line>)],
) -> Result<()> {
    let grid = o.mapper.occupancy_grid(&OccupancyParams {
        resolution_m: o.resolution_m,
        ..OccupancyParams::default()
    })?;
    let first = o.stamps.first().copied().unwrap_or(0.0);
    let msg = laserlines_foxglove::grid::occupancy_grid(
        &grid.to_occupancy_percent(),
        grid.width,
        grid.height,
        grid.resolution,
        (grid.origin.x, grid.origin.y),
        laserlines_foxglove::WORLD_FRAME,
        first,
    )
    .context("map grid")?;
    w.write_message("/map", &msg, first)?;
    for ((record, lines), (&t, pose)) in kept.iter().zip(o.stamps.iter().zip(o.mapper.poses())) {
        for tf in
            laserlines_foxglove::scene::pose_transforms(Pose2::new(pose.x, pose.y, pose.theta), t)
        {
            w.write_transform(&tf)?;
        }
        w.write_scan_lines_at(&record.scan, lines, t)?;
    }
    w.finish()?;
    Ok(())
}
