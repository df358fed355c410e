//! Extreme but representable inputs to the coverage grid: huge and infinite ranges. Each
//! call returns (no overflow panic in a debug build) with a sensible answer.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines::math::{Isometry2, Point2};
use laserlines_harness::CoverageGrid;
use laserlines_sim::World;
use laserlines_sim::index::WorldIndex;

#[test]
fn huge_ranges_do_not_overflow_the_coverage_grid() {
    let mut world = World::new();
    world.add_polygon(&[
        Point2::new(-2.0, -2.0),
        Point2::new(2.0, -2.0),
        Point2::new(2.0, 2.0),
        Point2::new(-2.0, 2.0),
    ]);
    let index = WorldIndex::new(&world, 0.5);
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
