//! A robot that cannot turn on the spot where it stands, beside a post, gets out by moving to
//! where it can.
//!
//! The world is the start of seeded maze 103 with islands (`laserlines simulate --maze 103
//! --islands`), closed above its third row of cells: from the start cell the way leads right,
//! up, and back left into the cell above the start, with a post of 8.1 cm radius near its
//! lower right corner (its centre 0.33 m above the wall below it); the way on leads up past
//! the post. Going round it, the robot stood facing the outer wall with its centre 0.45 m
//! from the post's (0.37 m from its edge), too near to turn on the spot (the footprint's
//! circumradius is 0.32 m, the safety margin 8 cm); the wanted turn and the safety layer's
//! turn the other way alternated, and the escape, which chose the motion that left the
//! footprint clearest all round, moved it along the wall and back: the maze's run ended at
//! 152 s, nothing new seen, with coverage 0.051. The escape now adds the room to turn on the
//! spot (the least distance from the robot's centre to a point, less the circumradius) to the
//! footprint's clearance.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use laserlines::math::{Isometry2, Point2, Vector2};
use laserlines_sim::World;

/// The first two columns and three rows of maze 103's cells (1.2 m; the start cell's centre
/// at (0.6, 0.6)), closed all round.
fn pocket_with_post() -> World {
    let p = Point2::new;
    let mut world = World::new();
    world.add_polygon(&[p(0.0, 0.0), p(2.4, 0.0), p(2.4, 3.6), p(0.0, 3.6)]);
    world.add_segment(p(0.0, 1.2), p(1.2, 1.2));
    world.add_segment(p(1.2, 2.4), p(2.4, 2.4));
    world.add_disc(p(0.879, 1.531), 0.081);
    world
}

#[test]
fn the_robot_beside_a_post_moves_to_where_it_can_turn() {
    let world = pocket_with_post();
    let start = Isometry2::new(Vector2::new(0.6, 0.6), 0.0);
    // Ten seeds of the laser and odometry noise; a run counts when it reached the top row
    // (y beyond 2.4 m, past the post) and saw everything. With the escape that kept the
    // footprint clearest all round, eight did (in the other two the robot gave up at the
    // post, coverage 0.911-0.914); now all ten do (at least nine asserted).
    let through = common::runs_beyond(&world, start, 300.0, 2.4);
    assert!(through >= 9, "{through} of 10 runs got past the post");
}
