//! What the navigation tests share: the arenas of `../shared`, the start of an arena run,
//! an arena's outline.

#![allow(dead_code, clippy::expect_used)]

use laserlines::math::Isometry2;
use laserlines_sim::World;
use laserlines_sim::arena::{ArenaOutline, interior_start};
use laserlines_sim::robot::RobotParams;

#[path = "../../../../tests/shared_data.rs"]
mod shared_data;

/// The arena file `name` of `../shared/data/arenas`, or `None` (with a notice) when
/// `../shared` is not there.
pub fn shared_arena(name: &str) -> Option<std::path::PathBuf> {
    shared_data::available(shared_data::path("arenas").join(name), "this arena's test")
}

/// Every element of an arena is counted once: in the laser's plane, out of it, or
/// skipped.
pub fn accounted(report: &laserlines_sim::arena::ArenaReport) -> usize {
    [&report.in_plane, &report.out_of_plane, &report.skipped]
        .iter()
        .flat_map(|m| m.values())
        .sum()
}

/// The start of an arena run: the grid cell centre nearest the origin in the largest free
/// region inside the arena's outline (where the robot fits in any heading).
pub fn arena_start(world: &World) -> Isometry2 {
    interior_start(world, RobotParams::default().robot.footprint.circumradius())
        .expect("the arena encloses a free region")
}

/// The outline of `world` (see [`ArenaOutline`]).
pub fn outline_of(world: &World) -> ArenaOutline {
    ArenaOutline::new(world)
}

/// Runs `world` from `start` with each of the laser and odometry noise seeds 0-9 for at most
/// `duration_s`, asserting no collision and never leaving the arena, and counts the runs that
/// got beyond `y` (m) and saw at least 95 % of the arena.
pub fn runs_beyond(world: &World, start: Isometry2, duration_s: f64, y: f64) -> usize {
    let mut through = 0;
    for seed in 0..10 {
        let config = laserlines_harness::RunConfig {
            seed,
            duration_s,
            ..laserlines_harness::RunConfig::default()
        };
        let record = laserlines_harness::run(world, start, &config).expect("the run starts");
        let m = &record.metrics;
        assert_eq!(m.collisions, 0, "seed {seed}");
        assert!(!m.left_arena, "seed {seed}");
        let farthest = record.path.iter().map(|q| q.y).fold(f64::MIN, f64::max);
        if farthest > y && m.coverage >= 0.95 {
            through += 1;
        }
    }
    through
}
