//! A short exploration, the quick check of the explorer (`acceptance.rs` and `nav.rs` run
//! the long ones): the bundled `inner_explore_test` arena, seed 0, 80 s of
//! simulated time. The robot covers 90 % of the reachable area within those 80 s (the README
//! gives 60-77 s over 20 seeds), without a collision, its own pose estimate within 0.2 m of
//! the truth. Measured: coverage 0.961, 90 % at 74 s, 30.9 m driven.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines::robot::Footprint;
use laserlines_harness::{RunConfig, arenas, run};
use laserlines_sim::arena::{ArenaOptions, interior_start};

#[test]
fn a_short_run_covers_the_small_arena_without_a_collision() {
    let arena = arenas::bundled("inner_explore_test", &ArenaOptions::default())
        .unwrap()
        .unwrap();
    let start = interior_start(&arena.world, Footprint::naji_v().circumradius()).unwrap();
    let config = RunConfig {
        duration_s: 80.0,
        seed: 0,
        ..RunConfig::default()
    };
    let record = run(&arena.world, start, &config).unwrap();
    let m = record.metrics;
    assert_eq!(m.collisions, 0, "{m:?}");
    assert!(m.coverage >= 0.9, "{m:?}");
    assert!(m.time_to_90_percent_s.is_some_and(|t| t <= 80.0), "{m:?}");
    assert!(m.max_pose_error_m < 0.2, "{m:?}");
    // The coverage curve rises: never down, and from nothing to what the metrics say.
    let curve = &record.coverage_curve;
    assert!(curve.windows(2).all(|w| w[1].1 >= w[0].1));
    assert_eq!(curve.last().map(|c| c.1), Some(m.coverage));
}

/// Extraction on a second thread gives the same run as in line: every figure but the clocks.
#[test]
fn the_extraction_thread_changes_nothing_but_the_clock() {
    let arena = arenas::bundled("inner_explore_test", &ArenaOptions::default())
        .unwrap()
        .unwrap();
    let start = interior_start(&arena.world, Footprint::naji_v().circumradius()).unwrap();
    let metrics = |extraction_thread| {
        let config = RunConfig {
            duration_s: 30.0,
            extraction_thread,
            ..RunConfig::default()
        };
        let mut m = run(&arena.world, start, &config).unwrap().metrics;
        (m.wall_time_s, m.setup_time_s) = (0.0, 0.0);
        m
    };
    let inline = metrics(false);
    assert!(inline.lines > 0 && inline.path_length_m > 1.0, "{inline:?}");
    assert_eq!(inline, metrics(true));
}
