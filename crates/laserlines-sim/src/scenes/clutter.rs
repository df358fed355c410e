//! Scenes of clutter: a room with legs and debris, and legs added to any scene.

use std::f64::consts::PI;
use std::ops::Range;

use laserlines::math::{Point2, Vector2};

use super::{Scene, p, pose, scene};
use crate::rng::Rng;
use crate::world::{World, box_corners};

/// A cluttered room: a 3.5..5.5 m rectangular room (walls 0..4) with one to three groups of
/// legs (a person's two legs of 5..8 cm radius, or the four legs of a table or chair of
/// 1.5..3 cm radius) and 4..12 pieces of debris along the floor line (the foot of the walls,
/// 2..25 cm in front of them): cables (chains of 3..7 tiny segments of 3..8 cm), tiny
/// segments (3..12 cm) and tiny discs (1..3 cm radius). Nothing comes within 0.4 m of the
/// sensor.
pub fn clutter_room(rng: &mut Rng) -> Scene {
    let w = rng.range(3.5, 5.5);
    let d = rng.range(3.5, 5.5);
    let mut world = World::new();
    let room = world.add_polygon(&[p(0.0, 0.0), p(w, 0.0), p(w, d), p(0.0, d)]);
    let sensor = p(rng.range(0.6, w - 0.6), rng.range(0.6, d - 0.6));
    let yaw = rng.range(-PI, PI);
    add_leg_groups(&mut world, rng, (w, d), sensor);
    add_debris(&mut world, rng, room, sensor);
    scene("clutter_room", world, pose(sensor.x, sensor.y, yaw))
}

/// One to three groups of legs in the room `[0, w] x [0, d]` of `world`: a person's two
/// legs or the four of a table or chair, each group tried up to 30 times for a place at
/// least 0.5 m from `sensor` and 0.1 m from everything else.
fn add_leg_groups(world: &mut World, rng: &mut Rng, (w, d): (f64, f64), sensor: Point2) {
    let far_from_sensor = |q: Point2, margin: f64| (q - sensor).norm() >= margin;
    let groups = 1 + rng.below(3);
    for _ in 0..groups {
        for _ in 0..30 {
            let c = p(rng.range(0.5, w - 0.5), rng.range(0.5, d - 0.5));
            let legs: Vec<(Point2, f64)> = if rng.chance(0.4) {
                let heading = rng.range(-PI, PI);
                let half = rng.range(0.2, 0.35) / 2.0;
                let radius = rng.range(0.05, 0.08);
                let off = Vector2::new(-heading.sin(), heading.cos()) * half;
                vec![(c + off, radius), (c - off, radius)]
            } else {
                let corners = box_corners(
                    c,
                    rng.range(0.4, 0.8),
                    rng.range(0.4, 0.8),
                    rng.range(-PI, PI),
                );
                let radius = rng.range(0.015, 0.03);
                corners.iter().map(|q| (*q, radius)).collect()
            };
            let ok = legs
                .iter()
                .all(|(q, r)| far_from_sensor(*q, 0.5 + r) && world.clearance(*q) >= r + 0.1);
            if ok {
                for (q, r) in legs {
                    world.add_disc(q, r);
                }
                break;
            }
        }
    }
}

/// 4..12 pieces of debris (cables, tiny segments, tiny discs) along the foot of the walls
/// of polygon `room` of `world`, none within 0.4 m of `sensor`.
fn add_debris(world: &mut World, rng: &mut Rng, room: Range<usize>, sensor: Point2) {
    let far_from_sensor = |q: Point2, margin: f64| (q - sensor).norm() >= margin;
    let walls: Vec<_> = world.walls[room].to_vec();
    let pieces = 4 + rng.below(9);
    for _ in 0..pieces {
        let Some(wall) = walls.get(rng.below(walls.len())).copied() else {
            break;
        };
        let e = wall.b - wall.a;
        let len = e.norm();
        if len <= 0.0 {
            continue;
        }
        let along = e / len;
        // The room is counter-clockwise: its inside is to the left of every wall.
        let inward = Vector2::new(-along.y, along.x);
        let t = rng.range(0.1, 0.9) * len;
        let offset = rng.range(0.02, 0.25);
        let at = |s: f64, o: f64| wall.a + along * s + inward * o;
        let kind = rng.uniform();
        if kind < 0.4 {
            // A cable: a wiggly chain of tiny segments roughly along the wall.
            let links = 3 + rng.below(5);
            let mut s = t;
            let mut o = offset;
            let mut chain = vec![at(s, o)];
            for _ in 0..links {
                s += rng.range(0.03, 0.07);
                o = (o + rng.range(-0.03, 0.03)).clamp(0.01, 0.3);
                chain.push(at(s.min(len - 0.01), o));
            }
            if chain.iter().all(|q| far_from_sensor(*q, 0.4)) {
                for pair in chain.windows(2) {
                    world.add_segment(pair[0], pair[1]);
                }
            }
        } else if kind < 0.7 {
            // A tiny straight piece, any orientation, kept off the wall.
            let half = rng.range(0.03, 0.12) / 2.0;
            let angle = rng.range(-PI, PI);
            let c = at(t, offset.max(half + 0.01));
            let h = Vector2::new(angle.cos(), angle.sin()) * half;
            if far_from_sensor(c, 0.4 + half) {
                world.add_segment(c - h, c + h);
            }
        } else {
            let radius = rng.range(0.01, 0.03);
            let c = at(t, offset.max(radius + 0.01));
            if far_from_sensor(c, 0.4 + radius) {
                world.add_disc(c, radius);
            }
        }
    }
}

/// Chair and table legs: adds `count` discs of `diameter.0..diameter.1` metres to `scene`,
/// each standing where the laser sees it (nothing between it and the laser, within
/// `max_range`), at least 0.05 m from every wall and other obstacle and at least 0.4 m from
/// the laser. Gives up on a leg after 50 tries (a cramped scene gets fewer). Returns how many
/// were placed.
pub fn add_legs(
    scene: &mut Scene,
    rng: &mut Rng,
    count: usize,
    diameter: (f64, f64),
    max_range: f64,
) -> usize {
    let laser = scene.laser_position();
    let mut placed = 0;
    for _ in 0..count {
        for _ in 0..50 {
            let radius = rng.range(diameter.0, diameter.1) / 2.0;
            let bearing = rng.range(-PI, PI);
            let dist = rng.range(0.4 + radius, max_range.max(0.5 + radius));
            let c = laser + Vector2::new(bearing.cos(), bearing.sin()) * dist;
            let visible = scene
                .world
                .cast(laser, bearing, dist)
                .is_none_or(|hit| hit.range >= dist - radius);
            if visible && scene.world.clearance(c) >= radius + 0.05 {
                scene.world.add_disc(c, radius);
                placed += 1;
                break;
            }
        }
    }
    placed
}
