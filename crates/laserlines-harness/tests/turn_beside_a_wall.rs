//! A robot beside a wall or a post may turn on the spot with a smaller margin than it keeps
//! when it drives: `SafetyParams::turn_margin` = 0.05 (the default is the full 8 cm).
//!
//! With the default, islands maze 134 (`laserlines simulate --maze 134 --islands`) ends at
//! 421 s, explored, with coverage 0.652: the robot passed a post through a 0.8 m gap into the
//! pocket below it and stood with its centre 0.36 m from the wall beside it, facing the wall
//! ahead, where a turn on the spot passes the wall by 4 cm (the footprint's circumradius is
//! 0.32 m). Forward and back it could go, never round; three frontiers were given up in 100 s.
//! With a turning margin of 5 cm the robot turns in tight spots where it could not before,
//! takes another way early on, and the run sees the whole maze (1.000, explored at 895 s).
//! The rule itself is tested in the explorer's `safety` module.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines_harness::{RunConfig, run};
use laserlines_sim::maze::{MazeParams, generate};

#[test]
fn with_a_turning_margin_a_robot_beside_a_wall_turns_where_it_stands() {
    let params = MazeParams {
        islands: 3,
        ..MazeParams::default()
    };
    let maze = generate(&params, 134);
    let mut config = RunConfig::default();
    config.explorer.safety.turn_margin = Some(0.05);
    let record = run(&maze.world, maze.start, &config).unwrap();
    let m = &record.metrics;
    assert_eq!(m.collisions, 0, "{m:?}");
    assert!(!m.left_arena, "{m:?}");
    // 1.000 at 895 s; 0.652 at 421 s with the default.
    assert!(m.coverage > 0.95, "{m:?}");
}
