//! What the navigation tests share: the arenas of `../shared`, the start of an arena run,
//! an arena's outline.

#![allow(dead_code, clippy::expect_used)]

use laserlines::math::Isometry2;
use laserlines_sim::World;
use laserlines_sim::arena::{ArenaOutline, interior_start};
use laserlines_sim::robot::RobotParams;

/// The arena file `name` of `../shared/data/arenas`, or `None` (with a notice) when
/// `../shared` is not there.
pub fn shared_arena(name: &str) -> Option<std::path::PathBuf> {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data/arenas")
        .join(name);
    if p.exists() {
        Some(p)
    } else {
        skip_notice(&p, "this arena's test");
        None
    }
}

/// Says that `what` is skipped because `path` is absent, on the terminal even when the test
/// passes (libtest captures only `print!` and `eprint!`, not writes to the stream itself); in
/// CI (`LASERLINES_REQUIRE_SHARED=1`, where `../shared` is there) the absence fails instead.
fn skip_notice(path: &std::path::Path, what: &str) {
    use std::io::Write as _;
    let required = std::env::var_os("LASERLINES_REQUIRE_SHARED").is_some_and(|v| v == "1");
    assert!(
        !required,
        "{} is absent, and LASERLINES_REQUIRE_SHARED=1 requires it",
        path.display()
    );
    let _ = writeln!(
        std::io::stderr(),
        "notice: {} is absent; skipping {what}",
        path.display()
    );
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
