//! `laserlines simulate`: its world, and the checks and notes of the world, the start pose
//! and the fence.

use anyhow::{Result, bail};
use laserlines::math::{Isometry2, Point2, Vector2};
use laserlines_harness::arenas;
use laserlines_sim::World;
use laserlines_sim::arena::{ArenaOptions, ArenaOutline, ArenaReport, WallLength, interior_start};
use laserlines_sim::cells::extent;
use laserlines_sim::maze::{MazeParams, generate};
use laserlines_sim::robot::RobotParams;

/// Says on standard error which elements the arena loader skipped, by type and count.
pub fn report_skipped(name: &str, report: &ArenaReport) {
    if report.skipped_count() == 0 {
        return;
    }
    let list = report
        .skipped
        .iter()
        .map(|(t, n)| format!("{t} x {n}"))
        .collect::<Vec<_>>()
        .join(", ");
    errln!(
        "laserlines: {name}: skipped {} elements whose shape at the laser's height of {} m is not modelled: {list}",
        report.skipped_count(),
        report.laser_height_m
    );
    let unknown = report.unknown_types();
    if !unknown.is_empty() {
        errln!(
            "laserlines: {name}: unknown element types: {}",
            unknown.join(", ")
        );
    }
}

/// An arena must have walls round a floor: the bounding box of its largest group of walls
/// ([`ArenaOutline::bounds`]) at least the robot's width (`radius`: its turning radius) in
/// both directions. Walls on one line, or a single wall, enclose nothing to explore.
pub fn check_floor(name: &str, world: &World, radius: f64) -> Result<()> {
    let bounds = ArenaOutline::new(world).bounds();
    let (w, h) = bounds.map_or((0.0, 0.0), |(lo, hi)| (hi.x - lo.x, hi.y - lo.y));
    if w < 2.0 * radius || h < 2.0 * radius {
        bail!(
            "{name}: its walls enclose no floor: their largest group spans {w:.2} m x {h:.2} m, \
             narrower than the robot ({:.2} m across); an arena needs walls round a floor",
            2.0 * radius
        );
    }
    Ok(())
}

/// A start given by hand must lie among the walls: within their bounding box.
pub fn check_start_inside(name: &str, world: &World, start: Isometry2) -> Result<()> {
    let ends = world.walls.iter().flat_map(|w| [w.a, w.b]);
    // No walls: nothing is among them.
    let (lo, hi) = extent(ends).unwrap_or((
        Point2::new(f64::INFINITY, f64::INFINITY),
        Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    ));
    let p = start.translation.vector;
    let inside = lo.x <= p.x && p.x <= hi.x && lo.y <= p.y && p.y <= hi.y;
    if !inside {
        bail!(
            "--start ({}, {}): outside {name}, whose walls span x {:.2}..{:.2} m, y {:.2}..{:.2} m",
            p.x,
            p.y,
            lo.x,
            hi.x,
            lo.y,
            hi.y
        );
    }
    Ok(())
}

/// Says on standard error when a start given by hand lies nearer an obstacle than the
/// robot's turning radius: turning on the spot there touches it (the run counts it).
pub fn warn_if_cramped(world: &World, start: Isometry2, radius: f64) {
    let p = Point2::from(start.translation.vector);
    let clearance = world.clearance(p);
    if clearance < radius {
        errln!(
            "laserlines: warning: --start ({}, {}) lies {clearance:.2} m from the nearest obstacle, \
             within the robot's turning radius of {radius:.2} m: turning on the spot there \
             touches it",
            p.x,
            p.y
        );
    }
}

/// `--start x,y,yaw_deg` (m, m, deg) as a pose.
pub fn parse_start(s: &str) -> Result<Isometry2> {
    let [x, y, yaw] = super::xy_yaw_deg("--start", s)?;
    Ok(Isometry2::new(Vector2::new(x, y), yaw))
}

/// The world to explore, its name, the default start (`None` in an arena with no room for
/// the robot) and, for an arena, the loader's report.
pub fn world_of(
    args: &super::simulate::SimulateArgs,
    robot: &RobotParams,
) -> Result<(String, World, Option<Isometry2>, Option<ArenaReport>)> {
    if let Some(seed) = args.maze {
        let params = MazeParams {
            islands: if args.islands { 3 } else { 0 },
            diagonals: args.diagonals.unwrap_or(0),
            ..MazeParams::default()
        };
        let maze = generate(&params, seed);
        if maze.diagonals < params.diagonals {
            bail!(
                "--diagonals {}: maze {seed} has {} turning cells whose corner can be cut, so \
                 --diagonals must be from 0 to {} for it",
                params.diagonals,
                maze.diagonals,
                maze.diagonals
            );
        }
        let mut name = format!("maze {seed}");
        if args.islands {
            name.push_str(&format!(" with {} islands", maze.islands));
        }
        if maze.diagonals > 0 {
            name.push_str(&format!(", {} corners cut at 45 degrees", maze.diagonals));
        }
        return Ok((name, maze.world, Some(maze.start), None));
    }
    let options = ArenaOptions {
        wall_length: if args.mesh_walls {
            WallLength::Mesh
        } else {
            WallLength::Full
        },
        laser_height: robot.laser_height_m,
    };
    let which = args.arena.as_deref().unwrap_or("maze_10m_x_14m");
    let arena = arenas::load(which, &options)?;
    report_skipped(&arena.name, &arena.report);
    let radius = robot.robot.footprint.circumradius();
    check_floor(&arena.name, &arena.world, radius)?;
    let start = interior_start(&arena.world, radius);
    // The run's name says which walls it had (metrics.json, the pictures' titles).
    let name = if args.mesh_walls {
        format!("{}, 1.0 m mesh walls", arena.name)
    } else {
        arena.name.clone()
    };
    Ok((name, arena.world, start, Some(arena.report)))
}

/// Warns of an `[explorer.fence]` that does not hold the start (the origin of the explorer's
/// map frame: it then acts only once the robot is inside it) or that leaves a robot of
/// circumradius `radius` (m) less than its own width to move in.
pub fn warn_of_fence(fence: &laserlines_nav::Fence, radius: f64) {
    if !fence.contains(Point2::origin()) {
        errln!(
            "laserlines: warning: [explorer.fence] does not hold the start (the origin of the \
             explorer's map frame): it keeps the robot in only once the robot is inside it"
        );
    }
    let [a, b] = fence.half_extent;
    if a.min(b) < 2.0 * radius {
        errln!(
            "laserlines: warning: [explorer.fence] is {:.2} m x {:.2} m: a robot {:.2} m \
             across has less than its own width to move in it",
            2.0 * a,
            2.0 * b,
            2.0 * radius
        );
    }
}
