//! Extreme but representable inputs to a run: huge and infinite ranges on the coverage grid
//! (each call returns, with no overflow panic in a debug build, a sensible answer), a world
//! larger than the grid holds and a followed wall beyond the laser's reach (refused).

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines::math::{Isometry2, Point2};
use laserlines_harness::CoverageGrid;
use laserlines_sim::World;
use laserlines_sim::index::WorldIndex;

/// A square room of side `side` (m) around the origin.
fn square_room(side: f64) -> World {
    let h = side / 2.0;
    let mut world = World::new();
    world.add_polygon(&[
        Point2::new(-h, -h),
        Point2::new(h, -h),
        Point2::new(h, h),
        Point2::new(-h, h),
    ]);
    world
}

#[test]
fn huge_ranges_do_not_overflow_the_coverage_grid() {
    let index = WorldIndex::new(&square_room(4.0), 0.5);
    let mut coverage = CoverageGrid::new(&index, Point2::origin(), 0.3);
    coverage.mark_scan(&Isometry2::identity(), -1.0, 0.01, &[1e300; 201], 1e300);
    coverage.mark_scan(
        &Isometry2::identity(),
        -1.0,
        0.01,
        &[f64::INFINITY; 201],
        1e300,
    );
    let c = coverage.coverage();
    assert!(c > 0.0 && c <= 1.0, "{c}");
}

#[test]
fn a_world_larger_than_the_coverage_grid_is_refused() {
    use laserlines_harness::{RunConfig, RunError, run};
    // Square rooms of 190 m (with the grid's margin of 1 m: 192 m, within 200) and 210 m.
    assert_eq!(
        CoverageGrid::too_large(&square_room(190.0), Point2::origin()),
        None
    );
    let (w, h) = CoverageGrid::too_large(&square_room(210.0), Point2::origin()).unwrap();
    assert!(
        (w - 212.0).abs() < 0.11 && (h - 212.0).abs() < 0.11,
        "{w} x {h}"
    );
    // A run there is refused before it starts, naming the size and the limit.
    let config = RunConfig {
        duration_s: 1.0,
        ..RunConfig::default()
    };
    let err = run(&square_room(210.0), Isometry2::identity(), &config).unwrap_err();
    assert!(matches!(err, RunError::TooLarge { .. }), "{err:?}");
    let text = err.to_string();
    assert!(
        text.contains("212.0 m x 212.0 m") && text.contains("at most 200 m"),
        "{text}"
    );
}

#[test]
fn a_followed_wall_beyond_the_lasers_reach_is_refused() {
    use laserlines_harness::{RunConfig, run};
    let world = square_room(4.0);
    let mut config = RunConfig {
        duration_s: 1.0,
        ..RunConfig::default()
    };
    config.explorer.follow.distance = 100.0;
    let err = run(&world, Isometry2::identity(), &config)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("follow.distance must be at most 5.6 (the laser's range_max), got 100"),
        "{err}"
    );
    config.explorer.follow.distance = 0.6;
    config.explorer.follow.range = 6.0;
    let err = run(&world, Isometry2::identity(), &config)
        .unwrap_err()
        .to_string();
    assert!(err.contains("follow.range must be at most 5.6"), "{err}");
}
