//! Scenes with known walls, seeded generators of them, suites for comparing extractors, and
//! the standard bench scan.
//!
//! Every generator takes a [`Rng`] and varies sizes and the sensor pose plausibly, keeps the
//! sensor at least [`MIN_SENSOR_CLEARANCE`] from every obstacle, and keeps walls mostly within
//! 5 m of the sensor (the URG-04LX reaches 5.6 m). Worlds are in metres; the sensor pose is
//! `world_from_laser` (REP 103: x forward, y left, yaw counter-clockwise).

use std::f64::consts::PI;

use laserlines::math::{Isometry2, Point2, Vector2};

use crate::laser::{LaserModel, Noise};
use crate::rng::{Rng, mix_seed};
use crate::simulation::{SimScan, simulate};
use crate::world::World;

mod clutter;
mod maze;

pub use clutter::{add_legs, clutter_room};
pub use maze::maze;

/// The least distance (m) every generated scene keeps between the sensor and any wall or disc.
pub const MIN_SENSOR_CLEARANCE: f64 = 0.25;

/// The RoboCup Rescue arena grid, m: maze walls lie on multiples of it.
pub const ROBOCUP_GRID: f64 = 1.2;

/// A world and where the laser stands in it.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// A name saying what the scene is (for suites: `suite/index/kind`, e.g.
    /// `rooms/3/l_shaped_room`).
    pub name: String,
    /// The walls and obstacles.
    pub world: World,
    /// The laser's pose in the world.
    pub world_from_laser: Isometry2,
}

impl Scene {
    /// Simulates one scan of this scene with `model`, see [`simulate`].
    #[must_use]
    pub fn simulate(&self, model: &LaserModel, rng: &mut Rng) -> SimScan {
        simulate(&self.world, self.world_from_laser, model, rng)
    }

    /// The laser's position in the world, m.
    #[must_use]
    pub fn laser_position(&self) -> Point2 {
        Point2::from(self.world_from_laser.translation.vector)
    }
}

fn p(x: f64, y: f64) -> Point2 {
    Point2::new(x, y)
}

fn pose(x: f64, y: f64, yaw: f64) -> Isometry2 {
    Isometry2::new(Vector2::new(x, y), yaw)
}

fn scene(name: &str, world: World, world_from_laser: Isometry2) -> Scene {
    Scene {
        name: name.to_string(),
        world,
        world_from_laser,
    }
}

/// An axis-aligned rectangular room `[0, w] x [0, d]` with w, d in 2.5..5 m (walls 0..4:
/// bottom, right, top, left), the sensor anywhere at least 0.4 m from the walls, facing
/// any way.
pub fn rectangular_room(rng: &mut Rng) -> Scene {
    let w = rng.range(2.5, 5.0);
    let d = rng.range(2.5, 5.0);
    let mut world = World::new();
    world.add_polygon(&[p(0.0, 0.0), p(w, 0.0), p(w, d), p(0.0, d)]);
    let x = rng.range(0.4, w - 0.4);
    let y = rng.range(0.4, d - 0.4);
    let yaw = rng.range(-PI, PI);
    scene("rectangular_room", world, pose(x, y, yaw))
}

/// An L-shaped room: a 3.5..5.5 m rectangle with a corner of 1.2 m or more cut out (six
/// walls, one concave corner), the sensor inside at least 0.4 m from the walls, facing any
/// way.
pub fn l_shaped_room(rng: &mut Rng) -> Scene {
    let w = rng.range(3.5, 5.5);
    let d = rng.range(3.5, 5.5);
    let a = rng.range(1.2, w / 2.0);
    let b = rng.range(1.2, d / 2.0);
    let mut world = World::new();
    world.add_polygon(&[
        p(0.0, 0.0),
        p(w, 0.0),
        p(w, d - b),
        p(w - a, d - b),
        p(w - a, d),
        p(0.0, d),
    ]);
    let m = 0.4;
    let mut at = p((w - a) / 2.0, (d - b) / 2.0);
    for _ in 0..100 {
        let x = rng.range(m, w - m);
        let y = rng.range(m, d - m);
        if x <= w - a - m || y <= d - b - m {
            at = p(x, y);
            break;
        }
    }
    let yaw = rng.range(-PI, PI);
    scene("l_shaped_room", world, pose(at.x, at.y, yaw))
}

/// A straight corridor 1.2..2.2 m wide and 8..12 m long along x, closed at both ends, with
/// a door gap of 0.8..1.1 m in the left wall (`y = width`) opening into a small room behind
/// it, and, half of the time, a second gap in the right wall (`y = 0`) that opens onto
/// nothing. The sensor stands near the middle, at least 0.4 m from the side walls, looking
/// along the corridor (either way, +-0.5 rad).
pub fn corridor_with_door_gap(rng: &mut Rng) -> Scene {
    let width = rng.range(1.2, 2.2);
    let len = rng.range(8.0, 12.0);
    let sx = rng.range(len / 2.0 - 1.5, len / 2.0 + 1.5);
    let sy = rng.range(0.4, width - 0.4);
    let mut world = World::new();
    // Ends.
    world.add_segment(p(0.0, 0.0), p(0.0, width));
    world.add_segment(p(len, 0.0), p(len, width));
    // The door and the room behind it.
    let gap = rng.range(0.8, 1.1);
    let x0 = (sx + rng.range(-2.5, 1.5)).clamp(1.5, len - 1.5 - gap);
    let left = rng.range(0.3, 1.0);
    let right = rng.range(0.3, 1.0);
    let depth = rng.range(1.5, 3.0);
    world.add_segment(p(0.0, width), p(x0, width));
    world.add_segment(p(x0 + gap, width), p(len, width));
    let (rx0, rx1, ry) = (x0 - left, x0 + gap + right, width + depth);
    world.add_segment(p(rx0, width), p(rx0, ry));
    world.add_segment(p(rx0, ry), p(rx1, ry));
    world.add_segment(p(rx1, ry), p(rx1, width));
    // The right wall, perhaps with an open gap.
    if rng.chance(0.5) {
        let gap2 = rng.range(0.8, 1.1);
        let x1 = (sx + rng.range(-2.5, 1.5)).clamp(1.5, len - 1.5 - gap2);
        world.add_segment(p(0.0, 0.0), p(x1, 0.0));
        world.add_segment(p(x1 + gap2, 0.0), p(len, 0.0));
    } else {
        world.add_segment(p(0.0, 0.0), p(len, 0.0));
    }
    let heading = if rng.chance(0.5) { 0.0 } else { PI };
    let yaw = heading + rng.range(-0.5, 0.5);
    scene("corridor_with_door_gap", world, pose(sx, sy, yaw))
}

/// A concave corner: two walls of 2..4.5 m meeting at the origin at 70..110 deg (wall 0
/// along +x, ending at the corner; wall 1 starting there). The sensor stands inside the
/// angle, 1..3 m from the corner and at least 0.3 rad off either wall, looking towards the
/// corner (+-0.6 rad).
pub fn corner(rng: &mut Rng) -> Scene {
    let theta = rng.range(70f64.to_radians(), 110f64.to_radians());
    let l1 = rng.range(2.0, 4.5);
    let l2 = rng.range(2.0, 4.5);
    let mut world = World::new();
    world.add_segment(p(l1, 0.0), p(0.0, 0.0));
    world.add_segment(p(0.0, 0.0), p(l2 * theta.cos(), l2 * theta.sin()));
    let s = rng.range(1.0, 3.0);
    let half = theta / 2.0;
    let bearing = half + rng.range(-(half - 0.3), half - 0.3);
    let at = p(s * bearing.cos(), s * bearing.sin());
    let yaw = (-at.y).atan2(-at.x) + rng.range(-0.6, 0.6);
    scene("corner", world, pose(at.x, at.y, yaw))
}

/// A rectangular room of 3.5..5.5 m with one to three boxes (0.3..1 m sides, any
/// orientation) standing free of the walls, of each other and of the sensor (at least 0.4 m).
/// Walls 0..4 are the room, then four walls per box.
pub fn boxes_in_room(rng: &mut Rng) -> Scene {
    let w = rng.range(3.5, 5.5);
    let d = rng.range(3.5, 5.5);
    let mut world = World::new();
    world.add_polygon(&[p(0.0, 0.0), p(w, 0.0), p(w, d), p(0.0, d)]);
    let sensor = p(rng.range(0.5, w - 0.5), rng.range(0.5, d - 0.5));
    let yaw = rng.range(-PI, PI);
    let count = 1 + rng.below(3);
    let mut placed: Vec<(Point2, f64)> = Vec::new();
    for _ in 0..count {
        for _ in 0..50 {
            let sx = rng.range(0.3, 1.0);
            let sy = rng.range(0.3, 1.0);
            let box_yaw = rng.range(-PI, PI);
            let half_diag = sx.hypot(sy) / 2.0;
            let m = half_diag + 0.2;
            let c = p(rng.range(m, w - m), rng.range(m, d - m));
            let clear_of_sensor = (c - sensor).norm() >= half_diag + 0.4;
            let clear_of_boxes = placed
                .iter()
                .all(|(o, h)| (c - o).norm() >= half_diag + h + 0.2);
            if clear_of_sensor && clear_of_boxes {
                world.add_box(c, sx, sy, box_yaw);
                placed.push((c, half_diag));
                break;
            }
        }
    }
    scene("boxes_in_room", world, pose(sensor.x, sensor.y, yaw))
}

/// A long straight wall seen at a grazing angle: the wall runs along x at 0.6..1.2 m to one
/// side of the sensor and ends where the incidence reaches 75..80 deg (less when the range
/// limit would cut it first: every point stays within 5.4 m). Half of the time a second
/// wall runs on the other side 1..2 m away, as in a corridor seen lengthwise. The sensor
/// looks roughly along the wall(s).
pub fn grazing_wall(rng: &mut Rng) -> Scene {
    let side = if rng.chance(0.5) { 1.0 } else { -1.0 };
    let mut world = World::new();
    let mut add_wall = |rng: &mut Rng, offset: f64, lo_deg: f64, hi_deg: f64| {
        let reach = (offset.abs() / 5.4).clamp(-1.0, 1.0).acos();
        let incidence = rng
            .range(lo_deg.to_radians(), hi_deg.to_radians())
            .min(reach);
        let x_end = offset.abs() * incidence.tan();
        world.add_segment(p(-1.5, offset), p(x_end, offset));
    };
    let d = rng.range(0.6, 1.2);
    add_wall(rng, side * d, 75.0, 80.0);
    if rng.chance(0.5) {
        let d2 = rng.range(1.0, 2.0);
        add_wall(rng, -side * d2, 70.0, 80.0);
    }
    let yaw = side * rng.range(-0.2, 0.3);
    scene("grazing_wall", world, pose(0.0, 0.0, yaw))
}

/// A hall whose walls lie near the range limit: the front wall 4.3..5.3 m ahead, side walls
/// 4..5.2 m to either side, a back wall 1..3 m behind. The sensor looks ahead (+-0.3 rad).
/// The front corners are beyond 5.6 m, so the front and side walls are cut by the range
/// limit and their pieces end there.
pub fn far_walls(rng: &mut Rng) -> Scene {
    let front = rng.range(4.3, 5.3);
    let left = rng.range(4.0, 5.2);
    let right = rng.range(4.0, 5.2);
    let back = rng.range(1.0, 3.0);
    let mut world = World::new();
    world.add_polygon(&[
        p(-back, -right),
        p(front, -right),
        p(front, left),
        p(-back, left),
    ]);
    let yaw = rng.range(-0.3, 0.3);
    scene("far_walls", world, pose(0.0, 0.0, yaw))
}

/// The names of the scene suites, for [`suite`]. The name [`ALL`] selects all of them.
///
/// - `rooms`: rectangular ([`rectangular_room`], 60 %) and L-shaped ([`l_shaped_room`]) rooms;
/// - `corridors`: [`corridor_with_door_gap`];
/// - `maze`: [`maze`], corners on the 1.2 m RoboCup grid;
/// - `boxes`: [`boxes_in_room`];
/// - `clutter`: [`clutter_room`], legs and cables;
/// - `glancing`: [`grazing_wall`];
/// - `far`: [`far_walls`], long walls near the 5.6 m range limit.
pub const SUITES: &[&str] = &[
    "rooms",
    "corridors",
    "maze",
    "boxes",
    "clutter",
    "glancing",
    "far",
];

/// The suite name that selects every suite of [`SUITES`].
pub const ALL: &str = "all";

/// A suite name that [`suite`] does not know.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown scene suite {name:?}; known suites: rooms, corridors, maze, boxes, clutter, glancing, far, all"
)]
pub struct UnknownSuite {
    /// The name asked for.
    pub name: String,
}

/// `count` scenes of the suite `name` (one of [`SUITES`]), seeded by `seed`; for [`ALL`],
/// `count` scenes of every suite in the order of [`SUITES`].
///
/// Scene `k` of a suite has its own generator, seeded from `seed`, the suite and `k`, so it
/// is the same whatever `count` is: a longer suite extends a shorter one. Scene names are
/// `suite/k/kind`.
///
/// # Errors
/// [`UnknownSuite`] when `name` is neither in [`SUITES`] nor [`ALL`].
///
/// ```
/// let scenes = laserlines_sim::scenes::suite("maze", 7, 3).unwrap();
/// assert_eq!(scenes.len(), 3);
/// assert!(scenes[0].name.starts_with("maze/0/"));
/// assert!(laserlines_sim::scenes::suite("moon", 7, 3).is_err());
/// ```
pub fn suite(name: &str, seed: u64, count: usize) -> Result<Vec<Scene>, UnknownSuite> {
    if name == ALL {
        let mut out = Vec::new();
        for index in 0..SUITES.len() {
            out.extend(generate(index, seed, count));
        }
        return Ok(out);
    }
    let index = SUITES
        .iter()
        .position(|s| *s == name)
        .ok_or_else(|| UnknownSuite {
            name: name.to_string(),
        })?;
    Ok(generate(index, seed, count))
}

fn generate(index: usize, seed: u64, count: usize) -> Vec<Scene> {
    let suite_name = SUITES.get(index).copied().unwrap_or("unknown");
    let mut out = Vec::new();
    for k in 0..count {
        let stream = ((index as u64) << 40) ^ k as u64;
        let mut rng = Rng::new(mix_seed(seed, stream));
        let mut scene = match suite_name {
            "rooms" => {
                if rng.chance(0.6) {
                    rectangular_room(&mut rng)
                } else {
                    l_shaped_room(&mut rng)
                }
            }
            "corridors" => corridor_with_door_gap(&mut rng),
            "maze" => maze(&mut rng),
            "boxes" => boxes_in_room(&mut rng),
            "clutter" => clutter_room(&mut rng),
            "glancing" => grazing_wall(&mut rng),
            _ => far_walls(&mut rng),
        };
        scene.name = format!("{suite_name}/{k}/{}", scene.name);
        out.push(scene);
    }
    out
}

/// The seed of the standard bench scan's noise.
pub const BENCH_SEED: u64 = 2007;

/// The standard bench scene and laser (issue 2, "Speed"): a 4 m x 6 m room `[0,4]x[0,6]`
/// (walls 0..4: bottom, right, top, left) with a 1.0 m x 0.6 m box centred at (1.8, 4.5)
/// rotated 30 deg (walls 4..8); the sensor at (1.3, 1.8) facing yaw 100 deg; 682 beams from
/// -120 deg in steps of 0.352 deg, ranges 0.02..5.6 m, gaussian range noise of sigma 10 mm,
/// rounded to 1 mm.
#[must_use]
pub fn bench_scene() -> (Scene, LaserModel) {
    let mut world = World::new();
    world.add_polygon(&[p(0.0, 0.0), p(4.0, 0.0), p(4.0, 6.0), p(0.0, 6.0)]);
    world.add_box(p(1.8, 4.5), 1.0, 0.6, 30f64.to_radians());
    let model = LaserModel {
        beams: 682,
        angle_min: (-120f64).to_radians(),
        angle_increment: 0.352f64.to_radians(),
        range_min: 0.02,
        range_max: 5.6,
        noise: Noise::Gaussian { sigma: 0.01 },
        mixed_pixels: 0.0,
        dropout: 0.0,
        max_range_returns: false,
        round_to: Some(0.001),
    };
    let scene = scene("bench", world, pose(1.3, 1.8, 100f64.to_radians()));
    (scene, model)
}

/// The standard bench scan: [`bench_scene`] simulated with the noise seed [`BENCH_SEED`].
/// Its ground truth has six significant visible pieces.
#[must_use]
pub fn bench_scan() -> SimScan {
    let (scene, model) = bench_scene();
    scene.simulate(&model, &mut Rng::new(BENCH_SEED))
}
