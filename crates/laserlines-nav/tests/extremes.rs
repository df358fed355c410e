//! Extreme but representable inputs to the map and the planner: huge
//! ranges and coordinates, infinite radii, a huge clearance cost. Each call returns (no
//! overflow panic in a debug build, no endless loop) with a sensible answer.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines::Scan;
use laserlines::math::{Isometry2, Point2, Vector2};
use laserlines_nav::{Planner, PlannerParams, RobotMap};

/// A map of a 4 m x 4 m room seen from its middle.
fn room_map() -> RobotMap {
    let n = 682;
    let inc = 360.0_f64.to_radians() / 1024.0;
    let angle_min = -inc * (n as f64 - 1.0) / 2.0;
    let ranges = (0..n)
        .map(|i| {
            let phi = angle_min + inc * i as f64;
            // Distance to the square |x|, |y| <= 2 along the beam.
            2.0 / phi.cos().abs().max(phi.sin().abs())
        })
        .collect();
    let scan = Scan::new(angle_min, inc, 0.02, 5.6, ranges).unwrap();
    let mut map = RobotMap::new();
    map.insert_scan(&Isometry2::identity(), &scan);
    map
}

#[test]
fn huge_ranges_do_not_overflow_the_map() {
    let mut map = room_map();
    let scan = Scan::new(-1.0, 0.01, 0.0, 1e300, vec![1e200; 201]).unwrap();
    map.insert_scan(&Isometry2::identity(), &scan);
    map.insert_scan(
        &Isometry2::new(Vector2::new(-1e20, 3e19), 0.3),
        &Scan::new(-1.0, 0.01, 0.0, 5.0, vec![2.0; 201]).unwrap(),
    );
    let mut near = Vec::new();
    map.occupied_near(Point2::new(-1e20, 0.0), 1e300, &mut near);
    assert!(near.is_empty());
    map.occupied_near(Point2::origin(), 1e300, &mut near);
    // Every wall of the room is within reach.
    assert!(!near.is_empty());
    assert!(near.iter().all(|p| p.x.abs() <= 2.2 && p.y.abs() <= 2.2));
    assert_eq!(map.unknown_around(Point2::new(-1e20, 0.0), 2), 25);
}

#[test]
fn the_planner_answers_for_far_starts_infinite_radii_and_huge_costs() {
    let map = room_map();
    let mut planner = Planner::new();
    let usual = PlannerParams::default();
    assert!(
        planner
            .nearest_frontier(&map, Point2::new(-1e20, 0.0), &[], 0.5, None, &usual)
            .is_none()
    );
    // Whatever the settings, a plan (if any) stays in the room, and matches the one with the
    // usual settings where they change nothing that matters here.
    let inside = |p: Point2| p.x.abs() < 2.0 && p.y.abs() < 2.0;
    for params in [
        PlannerParams {
            escape_radius_m: f64::INFINITY,
            ..usual
        },
        PlannerParams {
            clearance_cost: 1e12,
            ..usual
        },
        PlannerParams {
            clearance_cost: f64::INFINITY,
            ..usual
        },
    ] {
        let plan = planner.nearest_frontier(&map, Point2::origin(), &[], 0.5, None, &params);
        if let Some(plan) = plan {
            assert!(inside(plan.goal), "{params:?}: {plan:?}");
            assert!(plan.path.iter().all(|&p| inside(p)), "{params:?}: {plan:?}");
            assert!(plan.length_m.is_finite());
        }
    }
    // A blocked radius that is not finite closes nothing (it is taken as 0).
    planner.set_blocked(
        &[Point2::new(-1e300, 0.0), Point2::new(1.0, 1.0)],
        f64::INFINITY,
    );
    if let Some(plan) = planner.nearest_frontier(&map, Point2::origin(), &[], 0.5, None, &usual) {
        assert!(inside(plan.goal), "{plan:?}");
    }
}
