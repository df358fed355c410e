//! Scenes inside an arena for the extraction benchmark: the laser at random free poses, with
//! the arena's straight runs of wall panels joined into one wall each, so that the ground
//! truth has one piece where the sensor sees one flat surface.

use laserlines::math::{Isometry2, Point2};

use super::Arena;
use crate::cells::extent;
use crate::rng::{Rng, mix_seed};
use crate::scenes::Scene;
use crate::world::World;

/// Least distance from the laser to every wall and disc of an arena scene, m: a robot of
/// NAJI V's size stands there.
pub const SCENE_CLEARANCE: f64 = 0.35;

/// Most distance of a panel's ends from another's line for the two to be one wall, and most
/// gap between them along it, m (the arena's panels meet end to end on the 1.2 m grid).
pub const JOIN_TOLERANCE: f64 = 0.002;

/// Rays that must each hit a wall within [`ENCLOSED_RANGE`] for a pose to count as inside
/// the arena.
const ENCLOSED_RAYS: usize = 36;

/// See [`ENCLOSED_RAYS`], m.
const ENCLOSED_RANGE: f64 = 30.0;

/// Poses tried per scene asked for before giving up (an arena with little free floor), and
/// poses tried without finding any before deciding that an arena has no free floor inside.
const TRIES_PER_SCENE: usize = 2000;

/// `world` with every set of touching collinear walls (ends within [`JOIN_TOLERANCE`] of one
/// line, overlapping or meeting end to end) joined into one wall; its discs as they are.
#[must_use]
pub fn join_collinear_walls(world: &World) -> World {
    let mut walls: Vec<(Point2, Point2)> = world.walls.iter().map(|w| (w.a, w.b)).collect();
    // Each pass joins what it can; a joined wall may meet another in the next.
    let mut joined = true;
    while joined {
        joined = false;
        let mut i = 0;
        while i < walls.len() {
            let mut j = i + 1;
            while j < walls.len() {
                // Either way round: a wall too short for a direction of its own joins a longer
                // one only as the second.
                if let Some(both) = join(walls[i], walls[j]).or_else(|| join(walls[j], walls[i])) {
                    walls[i] = both;
                    walls.swap_remove(j);
                    joined = true;
                } else {
                    j += 1;
                }
            }
            i += 1;
        }
    }
    let mut out = World::new();
    for (a, b) in walls {
        out.add_segment(a, b);
    }
    out.discs.clone_from(&world.discs);
    out
}

/// The wall covering both `s` and `t` when they lie on one line and touch, else `None`.
fn join(s: (Point2, Point2), t: (Point2, Point2)) -> Option<(Point2, Point2)> {
    let d = s.1 - s.0;
    let len = d.norm();
    // A NaN length (from non-finite ends) joins nothing.
    if len.is_nan() || len <= JOIN_TOLERANCE {
        return None;
    }
    let u = d / len;
    let across = |p: Point2| {
        let v = p - s.0;
        (u.x * v.y - u.y * v.x).abs()
    };
    let (d0, d1) = (across(t.0), across(t.1));
    if d0.is_nan() || d1.is_nan() || d0.max(d1) > JOIN_TOLERANCE {
        return None;
    }
    let along = |p: Point2| u.dot(&(p - s.0));
    let (t0, t1) = (along(t.0), along(t.1));
    let (lo, hi) = (t0.min(t1), t0.max(t1));
    if lo > len + JOIN_TOLERANCE || hi < -JOIN_TOLERANCE {
        return None;
    }
    Some((s.0 + u * lo.min(0.0), s.0 + u * hi.max(len)))
}

/// `count` scenes of `arena` (fewer when its free floor is too small to find them, none when
/// 2000 poses in a row find none): the laser at poses drawn uniformly over the walls'
/// bounding box with any heading, kept when they lie [`SCENE_CLEARANCE`] from everything and
/// inside the arena (every one of 36 rays hits a wall within 30 m), in the arena with its
/// collinear walls joined ([`join_collinear_walls`]). Named `arenas/<index>/<arena name>`;
/// seeded by `seed`.
#[must_use]
pub fn arena_scenes(arena: &Arena, seed: u64, count: usize) -> Vec<Scene> {
    let world = join_collinear_walls(&arena.world);
    let Some((lo, hi)) = extent(world.walls.iter().flat_map(|w| [w.a, w.b])) else {
        return Vec::new();
    };
    let name = arena.name.strip_suffix(".raf").unwrap_or(&arena.name);
    let mut rng = Rng::new(mix_seed(seed, 0x6172_656E_6173));
    let mut out = Vec::new();
    let mut tries = 0usize;
    while out.len() < count && tries < TRIES_PER_SCENE.saturating_mul(count) {
        if out.is_empty() && tries >= TRIES_PER_SCENE {
            break;
        }
        tries += 1;
        let p = Point2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
        let yaw = rng.range(-std::f64::consts::PI, std::f64::consts::PI);
        if !world.is_free(p, SCENE_CLEARANCE) || !world.encloses(p, ENCLOSED_RAYS, ENCLOSED_RANGE) {
            continue;
        }
        out.push(Scene {
            name: format!("arenas/{}/{name}", out.len()),
            world: world.clone(),
            world_from_laser: Isometry2::new(p.coords, yaw),
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arena::{ArenaOptions, parse_raf};

    fn p(x: f64, y: f64) -> Point2 {
        Point2::new(x, y)
    }

    #[test]
    fn panels_end_to_end_become_one_wall_and_corners_stay_apart() {
        let mut w = World::new();
        // Three panels in a row (one reversed), a panel at a right angle to them, a
        // collinear panel beyond a 0.5 m door gap, and an overlapping duplicate; first of all
        // a sliver (too short for a direction) on the row, which joins it only as the second.
        w.add_segment(p(2.0, 0.0), p(2.001, 0.0));
        w.add_segment(p(0.0, 0.0), p(1.2, 0.0));
        w.add_segment(p(2.4, 0.0), p(1.2, 0.0));
        w.add_segment(p(2.4, 0.0), p(3.6, 0.0));
        w.add_segment(p(3.6, 0.0), p(3.6, 1.2));
        w.add_segment(p(4.1, 0.0), p(5.3, 0.0));
        w.add_segment(p(0.5, 0.0), p(1.0, 0.0));
        w.add_disc(p(1.0, 1.0), 0.29);
        let j = join_collinear_walls(&w);
        assert_eq!(j.walls.len(), 3, "{:?}", j.walls);
        let long = j.walls.iter().find(|s| (s.b - s.a).norm() > 3.0).unwrap();
        let (a, b) = if long.a.x < long.b.x {
            (long.a, long.b)
        } else {
            (long.b, long.a)
        };
        assert!((a - p(0.0, 0.0)).norm() < 1e-12 && (b - p(3.6, 0.0)).norm() < 1e-12);
        assert_eq!(j.discs.len(), 1);
    }

    #[test]
    fn a_straight_run_of_panels_in_an_arena_file_is_one_wall() {
        // Panels on the north edges of three cells in a row, and on the east edge of the last.
        let text = r#"<elements>
            <element type="small_wall" rotation="0" x="0" y="0"/>
            <element type="small_wall" rotation="0" x="1" y="0"/>
            <element type="small_wall" rotation="0" x="2" y="0"/>
            <element type="small_wall" rotation="90" x="2" y="0"/>
        </elements>"#;
        let arena = parse_raf(text, "row.raf", &ArenaOptions::default()).unwrap();
        assert_eq!(arena.world.walls.len(), 4);
        let joined = join_collinear_walls(&arena.world);
        assert_eq!(joined.walls.len(), 2);
        let lengths: Vec<f64> = joined.walls.iter().map(|w| (w.b - w.a).norm()).collect();
        assert!(
            lengths.iter().any(|l| (l - 3.6).abs() < 1e-9),
            "{lengths:?}"
        );
    }

    #[test]
    fn scenes_stand_clear_inside_the_arena() {
        let mut w = World::new();
        w.add_polygon(&[p(0.0, 0.0), p(6.0, 0.0), p(6.0, 4.0), p(0.0, 4.0)]);
        let arena = Arena {
            name: "box.raf".into(),
            world: w,
            report: Default::default(),
        };
        let scenes = arena_scenes(&arena, 3, 20);
        assert_eq!(scenes.len(), 20);
        for s in &scenes {
            let at = s.laser_position();
            assert!(s.world.clearance(at) >= SCENE_CLEARANCE, "{}", s.name);
            assert!(at.x > 0.0 && at.x < 6.0 && at.y > 0.0 && at.y < 4.0);
        }
        assert_eq!(scenes[4].name, "arenas/4/box");
        // The same seed gives the same scenes, another seed others.
        assert_eq!(
            arena_scenes(&arena, 3, 20)[7].world_from_laser,
            scenes[7].world_from_laser
        );
        assert_ne!(
            arena_scenes(&arena, 4, 20)[7].world_from_laser,
            scenes[7].world_from_laser
        );
        // No floor to stand on: no scene, and no endless search, however many are asked for.
        let none = Arena {
            name: "none".into(),
            world: World::new(),
            report: Default::default(),
        };
        assert!(arena_scenes(&none, 1, 3).is_empty());
        let mut open = World::new();
        open.add_segment(p(0.0, 0.0), p(6.0, 0.0));
        open.add_segment(p(0.0, 1.0), p(6.0, 2.0));
        let open = Arena {
            name: "open".into(),
            world: open,
            report: Default::default(),
        };
        assert!(arena_scenes(&open, 1, usize::MAX).is_empty());
    }

    #[test]
    fn scenes_lie_inside_an_l_shaped_room() {
        let mut w = World::new();
        w.add_polygon(&[
            p(0.0, 0.0),
            p(6.0, 0.0),
            p(6.0, 2.0),
            p(2.0, 2.0),
            p(2.0, 6.0),
            p(0.0, 6.0),
        ]);
        let arena = Arena {
            name: "l.raf".into(),
            world: w,
            report: Default::default(),
        };
        let scenes = arena_scenes(&arena, 9, 40);
        assert_eq!(scenes.len(), 40);
        for s in &scenes {
            let at = s.laser_position();
            // Never in the bounding box's empty corner, outside the walls.
            assert!(at.x < 2.0 || at.y < 2.0, "{at}");
        }
    }
}
