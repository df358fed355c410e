//! The RoboCup Rescue arenas bundled with the project, so that runs and tests need no
//! download, copied byte for byte from the repository
//! `tu-darmstadt-ros-pkg/hector_nist_arenas_gazebo` (folder `hector_nist_arena_worlds/arenas/`,
//! BSD license; see `data/README.md`): two mazes of plain walls, `maze_10m_x_14m.raf` (113
//! walls, about 12.0 m x 15.6 m) and `inner_explore_test.raf` (60 walls), and two
//! competition arenas with diagonal pieces, barrels, ramps, step fields, stairs and
//! victims, `go2011_arena.raf` (178 elements, GermanOpen 2011) and `rc_2015_arena_big.raf`
//! (233 elements, RoboCup 2015).

use std::path::Path;

use laserlines::math::Isometry2;
use laserlines_nav::Fence;
use laserlines_sim::World;
use laserlines_sim::arena::{Arena, ArenaError, ArenaOptions, ArenaOutline, load_raf, parse_raf};

/// `maze_10m_x_14m.raf`: a pure maze of 113 wall elements.
pub const MAZE_10M_X_14M: &str = include_str!("../../../data/arenas/maze_10m_x_14m.raf");

/// `inner_explore_test.raf`: a maze-like test arena of 60 wall elements.
pub const INNER_EXPLORE_TEST: &str = include_str!("../../../data/arenas/inner_explore_test.raf");

/// `go2011_arena.raf`: the GermanOpen 2011 arena, 178 elements, diagonal walls and
/// corners among them.
pub const GO2011_ARENA: &str = include_str!("../../../data/arenas/go2011_arena.raf");

/// `rc_2015_arena_big.raf`: the larger RoboCup 2015 arena, 233 elements, diagonal walls
/// and corners among them.
pub const RC_2015_ARENA_BIG: &str = include_str!("../../../data/arenas/rc_2015_arena_big.raf");

/// The bundled arenas by name (the file name without `.raf`).
pub const BUNDLED: &[(&str, &str)] = &[
    ("maze_10m_x_14m", MAZE_10M_X_14M),
    ("inner_explore_test", INNER_EXPLORE_TEST),
    ("go2011_arena", GO2011_ARENA),
    ("rc_2015_arena_big", RC_2015_ARENA_BIG),
];

/// Loads a bundled arena by name (with or without `.raf`); `None` for an unknown name.
///
/// ```
/// use laserlines_harness::arenas::bundled;
/// use laserlines_sim::arena::ArenaOptions;
/// let arena = bundled("maze_10m_x_14m", &ArenaOptions::default()).unwrap().unwrap();
/// assert_eq!(arena.report.wall_elements, 113);
/// assert!(bundled("nowhere", &ArenaOptions::default()).is_none());
/// ```
#[must_use]
pub fn bundled(name: &str, options: &ArenaOptions) -> Option<Result<Arena, ArenaError>> {
    let stem = name.strip_suffix(".raf").unwrap_or(name);
    BUNDLED
        .iter()
        .find(|(n, _)| *n == stem)
        .map(|(n, text)| parse_raf(text, &format!("{n}.raf"), options))
}

/// Errors of [`load`].
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// Neither a file nor a bundled arena.
    #[error("no arena file {0:?} (bundled arenas: {list})", list = bundled_names())]
    NotFound(String),
    /// The file does not read as an arena.
    #[error(transparent)]
    Arena(#[from] ArenaError),
}

fn bundled_names() -> String {
    BUNDLED
        .iter()
        .map(|(n, _)| *n)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The arena `which`: a `.raf` file when one is there, else the bundled arena of that name.
///
/// # Errors
/// [`LoadError::NotFound`] for neither, [`LoadError::Arena`] for a file that does not read.
pub fn load(which: &str, options: &ArenaOptions) -> Result<Arena, LoadError> {
    let path = Path::new(which);
    if path.exists() {
        return Ok(load_raf(path, options)?);
    }
    match bundled(which, options) {
        Some(arena) => Ok(arena?),
        None => Err(LoadError::NotFound(which.to_owned())),
    }
}

/// The fence an operator who knows the arena's extent gives the explorer: the bounds of the
/// world's largest group of walls ([`ArenaOutline::bounds`]) in the map frame of a robot
/// starting at `start` (world frame); `None` for a world without walls, or whose walls lie
/// on one straight line.
#[must_use]
pub fn fence_of(world: &World, start: &Isometry2) -> Option<Fence> {
    let (lo, hi) = ArenaOutline::new(world).bounds()?;
    let fence = Fence::from_box(lo, hi, start);
    fence.validate().is_ok().then_some(fence)
}
