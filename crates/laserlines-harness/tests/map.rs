//! The robot's own map on simulated scans: free and occupied cells (the scan matching that
//! places its scans is tested with `laserlines-slam`'s tracker).

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines::math::{Isometry2, Point2};
use laserlines_nav::{CellState, RobotMap};
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
