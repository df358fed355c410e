//! The robot's own map on simulated scans: free and occupied cells, and scan matching that
//! undoes an offset of the odometry.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines::math::{Isometry2, Point2, Vector2};
use laserlines_nav::{CellState, MatchParams, MatchPoint, RobotMap};
use laserlines_sim::{LaserModel, Rng, World, simulate};

fn room() -> World {
    let mut w = World::new();
    w.add_box(Point2::new(1.0, 0.5), 4.0, 3.0, 0.0);
    // A pillar, so that every direction is fixed.
    w.add_box(Point2::new(2.0, 1.2), 0.4, 0.3, 0.0);
    w
}

#[test]
fn a_scan_maps_free_and_occupied_cells() {
    let world = room();
    let mut rng = Rng::new(1);
    let pose = Isometry2::identity();
    let sim = simulate(&world, pose, &LaserModel::urg04lx(), &mut rng);
    let mut map = RobotMap::new();
    let newly = map.insert_scan(&pose, &sim.scan);
    assert!(newly > 300, "{newly}");
    assert_eq!(newly, map.known_cells());
    assert_eq!(map.state(Point2::new(1.0, 0.0)), CellState::Free);
    // The wall x = 3 ahead, on the boundary between two columns of cells.
    let wall = [Point2::new(2.95, 0.3), Point2::new(3.05, 0.3)];
    assert!(wall.iter().any(|&p| map.state(p) == CellState::Occupied));
    // Behind the laser's 240 degrees, and outside the room: unknown.
    assert_eq!(map.state(Point2::new(-0.8, 0.0)), CellState::Unknown);
    assert_eq!(map.state(Point2::new(3.5, 0.0)), CellState::Unknown);
}

#[test]
fn matching_undoes_an_offset() {
    let world = room();
    let mut rng = Rng::new(2);
    let model = LaserModel::urg04lx();
    let mut map = RobotMap::new();
    // Map from a few poses, then place a scan from an offset guess.
    for k in 0..5 {
        let pose = Isometry2::new(Vector2::new(0.1 * f64::from(k), 0.0), 0.0);
        let sim = simulate(&world, pose, &model, &mut rng);
        map.insert_scan(&pose, &sim.scan);
    }
    let truth = Isometry2::new(Vector2::new(0.3, -0.2), 0.3);
    let sim = simulate(&world, truth, &model, &mut rng);
    let window = sim.scan.range_window(None);
    let points: Vec<MatchPoint> = sim
        .scan
        .points(window)
        .iter()
        .step_by(3)
        .map(|p| MatchPoint {
            point: p.point,
            normal: None,
            weight: 1.0,
        })
        .collect();
    // Offsets of one scan's odometry error with the default prior; offsets of several
    // centimetres and degrees with a weak prior.
    let weak = MatchParams {
        prior_xy: 0.5,
        prior_theta: 0.5,
        ..MatchParams::default()
    };
    for (dx, dy, dt, params) in [
        (0.0, 0.0, 0.0, MatchParams::default()),
        (0.01, -0.01, 0.01, MatchParams::default()),
        (-0.01, 0.005, -0.01, MatchParams::default()),
        (0.04, -0.03, 0.03, weak),
        (-0.05, 0.02, -0.04, weak),
    ] {
        let guess = Isometry2::new(Vector2::new(0.3 + dx, -0.2 + dy), 0.3 + dt);
        let got = map.match_scan(&points, &guess, &params).unwrap();
        let e = got.translation.vector - truth.translation.vector;
        assert!(e.norm() < 0.02, "{e:?} from {dx} {dy} {dt}");
        assert!((got.rotation.angle() - 0.3).abs() < 0.012, "{got:?}");
    }
    // An empty map places nothing.
    assert!(
        RobotMap::new()
            .match_scan(&points, &truth, &MatchParams::default())
            .is_none()
    );
}
