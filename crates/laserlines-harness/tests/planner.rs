//! The frontier planner on maps of simulated scans: the nearest frontier, a path through the
//! middle, blocked spots and the tight clearance.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines::math::{Isometry2, Point2, Vector2};
use laserlines_nav::{Planner, PlannerParams, RobotMap};
use laserlines_sim::{LaserModel, Rng, World, simulate};

/// A 1.2 m corridor from x = -0.6 to 6, closed at the start, open at the far end,
/// with a side corridor at x = 3 going up.
fn corridor() -> World {
    let mut w = World::new();
    w.add_segment(Point2::new(-0.6, -0.6), Point2::new(-0.6, 0.6));
    w.add_segment(Point2::new(-0.6, -0.6), Point2::new(6.0, -0.6));
    w.add_segment(Point2::new(-0.6, 0.6), Point2::new(2.4, 0.6));
    w.add_segment(Point2::new(3.6, 0.6), Point2::new(6.0, 0.6));
    w.add_segment(Point2::new(2.4, 0.6), Point2::new(2.4, 4.0));
    w.add_segment(Point2::new(3.6, 0.6), Point2::new(3.6, 4.0));
    w
}

#[test]
fn the_nearest_frontier_and_a_path_through_the_middle() {
    let map = corridor_map(&corridor());
    let mut planner = Planner::new();
    let params = PlannerParams::default();
    let from = Point2::new(1.0, 0.0);
    let plan = planner
        .nearest_frontier(&map, from, &[], 0.5, None, &params)
        .unwrap();
    // The frontier is ahead, about 2.5 m from the laser's last position, in the
    // corridor (the side corridor's mouth or straight on).
    assert!(plan.goal.x > 2.4 && plan.goal.x < 4.2, "{plan:?}");
    assert!(plan.path.len() > 10);
    assert!((plan.path[0] - from).norm() < 0.1);
    // The path keeps to the middle.
    for p in &plan.path {
        assert!(p.y.abs() < 0.35 || p.x > 2.5, "{p:?}");
    }
    // Avoiding that frontier, another one (or none).
    if let Some(other) = planner.nearest_frontier(&map, from, &[plan.goal], 1.0, None, &params) {
        assert!((other.goal - plan.goal).norm() > 1.0);
    }
    // Keeping a goal a little farther than the nearest one.
    let far = planner
        .nearest_frontier(&map, from, &[plan.goal], 0.2, None, &params)
        .unwrap();
    let kept = planner
        .nearest_frontier(&map, from, &[], 0.5, Some((far.goal, 5.0)), &params)
        .unwrap();
    assert!((kept.goal - far.goal).norm() <= 0.3, "{kept:?} vs {far:?}");
    // Nothing is planned from outside the map, nor in an empty map.
    assert!(
        planner
            .nearest_frontier(&map, Point2::new(50.0, 0.0), &[], 0.5, None, &params)
            .is_none()
    );
    assert!(
        planner
            .nearest_frontier(&RobotMap::new(), from, &[], 0.5, None, &params)
            .is_none()
    );
}

/// The corridor's map seen from its closed end, as the robot would have it.
fn corridor_map(world: &World) -> RobotMap {
    let mut rng = Rng::new(3);
    let mut map = RobotMap::new();
    let model = LaserModel {
        range_max: 2.5,
        ..LaserModel::urg04lx()
    };
    for (x, yaw) in [
        (0.0, std::f64::consts::PI),
        (0.0, 0.0),
        (0.5, 0.0),
        (1.0, 0.0),
    ] {
        let pose = Isometry2::new(Vector2::new(x, 0.0), yaw);
        map.insert_scan(&pose, &simulate(world, pose, &model, &mut rng).scan);
    }
    map
}

#[test]
fn blocked_spots_close_the_way_but_never_around_the_robot() {
    let map = corridor_map(&corridor());
    let mut planner = Planner::new();
    let params = PlannerParams::default();
    let from = Point2::new(1.0, 0.0);
    assert!(
        planner
            .nearest_frontier(&map, from, &[], 0.5, None, &params)
            .is_some()
    );
    // The corridor closed at x = 1.8 (it is 1.2 m wide: a 0.6 m radius closes it):
    // no frontier lies behind the robot, so none is left.
    planner.set_blocked(&[Point2::new(1.8, 0.0)], 0.6);
    assert!(
        planner
            .nearest_frontier(&map, from, &[], 0.5, None, &params)
            .is_none()
    );
    // A spot on the robot itself does not shut it in.
    planner.set_blocked(&[from], 0.3);
    let plan = planner
        .nearest_frontier(&map, from, &[], 0.5, None, &params)
        .unwrap();
    assert!(plan.goal.x > 2.4, "{plan:?}");
    // Opened again.
    planner.set_blocked(&[], 0.0);
    assert!(
        planner
            .nearest_frontier(&map, from, &[], 0.5, None, &params)
            .is_some()
    );
}

#[test]
fn a_gap_too_narrow_for_the_usual_clearance_is_open_to_the_tight_one() {
    // The corridor with a post in its middle at x = 1.8: gaps of 0.6 - 0.03 = 0.57 m
    // on either side, passable at the explorer's tight clearance (0.2 m) but not at
    // 0.3 m (the map's occupied cells stand up to half a cell into the gap on either
    // side, so that the gap is about 0.47 m on the map).
    let mut world = corridor();
    world.add_disc(Point2::new(1.8, 0.0), 0.03);
    let map = corridor_map(&world);
    let mut planner = Planner::new();
    let from = Point2::new(0.6, 0.0);
    let usual = PlannerParams::default();
    let tight = PlannerParams {
        clearance_m: 0.2,
        ..usual
    };
    let found = planner.nearest_frontier(&map, from, &[], 0.5, None, &usual);
    assert!(found.as_ref().is_none_or(|p| p.goal.x < 1.8), "{found:?}");
    let plan = planner
        .nearest_frontier(&map, from, &[], 0.5, None, &tight)
        .unwrap();
    assert!(plan.goal.x > 1.8, "{plan:?}");
}
