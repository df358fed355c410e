//! The scene generators and suites: the sensor in free space, plausible geometry, and
//! deterministic, prefix-stable suites.

use laserlines::math::{Point2, Vector2, angle_diff};
use laserlines_sim::scenes::{
    self, ALL, MIN_SENSOR_CLEARANCE, ROBOCUP_GRID, SUITES, Scene, UnknownSuite,
};
use laserlines_sim::{LaserModel, Rng, Target, suite};

/// Suites whose scenes are closed rooms (every direction meets a wall).
const ENCLOSED: &[&str] = &["rooms", "maze", "boxes", "clutter", "far"];

#[test]
fn every_suite_puts_the_sensor_in_free_space_facing_walls() {
    let model = LaserModel::urg04lx();
    for name in SUITES {
        for seed in [1u64, 2, 3] {
            let scenes = suite(name, seed, 12).unwrap();
            assert_eq!(scenes.len(), 12);
            for (k, scene) in scenes.iter().enumerate() {
                assert!(
                    scene.name.starts_with(&format!("{name}/{k}/")),
                    "{}",
                    scene.name
                );
                let at = scene.laser_position();
                let clearance = scene.world.clearance(at);
                assert!(
                    clearance >= MIN_SENSOR_CLEARANCE,
                    "{}: sensor {clearance} m from an obstacle",
                    scene.name
                );
                if ENCLOSED.contains(name) {
                    assert!(
                        scene.world.encloses(at, 720, 50.0),
                        "{} is open",
                        scene.name
                    );
                }
                let sim = scene.simulate(&model, &mut Rng::new(seed));
                assert!(sim.scan.validate().is_ok());
                assert!(
                    sim.truth.significant_pieces().count() >= 1,
                    "{}: no wall to find",
                    scene.name
                );
                // Walls mostly within 5 m, except in the suite made to be far.
                let hits: Vec<f64> = sim
                    .truth
                    .ranges
                    .iter()
                    .copied()
                    .filter(|r| r.is_finite())
                    .collect();
                let within = hits.iter().filter(|r| **r <= 5.0).count();
                if *name != "far" {
                    assert!(
                        within * 10 >= hits.len() * 7,
                        "{}: only {within} of {} hits within 5 m",
                        scene.name,
                        hits.len()
                    );
                }
            }
        }
    }
}

#[test]
fn suites_are_deterministic_and_prefix_stable() {
    for name in SUITES {
        let five = suite(name, 42, 5).unwrap();
        let three = suite(name, 42, 3).unwrap();
        assert_eq!(&five[..3], &three[..]);
        assert_eq!(five, suite(name, 42, 5).unwrap());
        let other = suite(name, 43, 5).unwrap();
        assert_ne!(five, other, "{name}: the seed changes nothing");
        // Scenes within a suite differ from each other.
        assert_ne!(five[0].world, five[1].world, "{name}");
    }
    assert!(suite("rooms", 1, 0).unwrap().is_empty());
}

#[test]
fn all_is_every_suite_in_order_and_unknown_names_are_errors() {
    let all = suite(ALL, 9, 2).unwrap();
    assert_eq!(all.len(), 2 * SUITES.len());
    let mut expected: Vec<Scene> = Vec::new();
    for name in SUITES {
        expected.extend(suite(name, 9, 2).unwrap());
    }
    assert_eq!(all, expected);

    let err = suite("moon", 1, 3).unwrap_err();
    assert_eq!(
        err,
        UnknownSuite {
            name: "moon".into()
        }
    );
    let message = err.to_string();
    assert!(message.contains("\"moon\""));
    for name in SUITES.iter().chain([&ALL]) {
        assert!(message.contains(name), "{message} lacks {name}");
    }
    assert_eq!(
        SUITES,
        &[
            "rooms",
            "corridors",
            "maze",
            "boxes",
            "clutter",
            "glancing",
            "far"
        ]
    );
}

fn on_grid(v: f64) -> bool {
    let k = v / ROBOCUP_GRID;
    (k - k.round()).abs() < 1e-9
}

#[test]
fn maze_walls_lie_on_the_robocup_grid_and_collinear_edges_are_merged() {
    for scene in suite("maze", 4, 20).unwrap() {
        let walls = &scene.world.walls;
        assert!(walls.len() >= 4);
        for w in walls {
            assert!(on_grid(w.a.x) && on_grid(w.a.y) && on_grid(w.b.x) && on_grid(w.b.y));
            // Axis-aligned, a whole number of grid cells long.
            assert!((w.a.x - w.b.x).abs() < 1e-9 || (w.a.y - w.b.y).abs() < 1e-9);
            assert!(on_grid(w.length()) && w.length() >= ROBOCUP_GRID - 1e-9);
        }
        // No two walls on the same grid line touch end to end (they would be one wall).
        for (i, u) in walls.iter().enumerate() {
            for v in &walls[i + 1..] {
                let same_row = (u.a.y - u.b.y).abs() < 1e-9
                    && (v.a.y - v.b.y).abs() < 1e-9
                    && (u.a.y - v.a.y).abs() < 1e-9;
                let same_col = (u.a.x - u.b.x).abs() < 1e-9
                    && (v.a.x - v.b.x).abs() < 1e-9
                    && (u.a.x - v.a.x).abs() < 1e-9;
                if same_row || same_col {
                    let touch = [u.a, u.b]
                        .iter()
                        .any(|e| (e - v.a).norm() < 1e-9 || (e - v.b).norm() < 1e-9);
                    assert!(!touch, "{}: {u:?} and {v:?} should be one wall", scene.name);
                }
            }
        }
        // The sensor stands within 0.25 m of a cell centre.
        let at = scene.laser_position();
        let cx = (at.x / ROBOCUP_GRID).floor() + 0.5;
        let cy = (at.y / ROBOCUP_GRID).floor() + 0.5;
        let centre = Point2::new(cx * ROBOCUP_GRID, cy * ROBOCUP_GRID);
        assert!((at - centre).abs().max() <= 0.25 + 1e-12);
    }
}

#[test]
fn grazing_walls_are_seen_up_to_75_to_80_degrees_of_incidence() {
    let model = LaserModel::urg04lx().ideal();
    for scene in suite("glancing", 8, 20).unwrap() {
        let sim = scene.simulate(&model, &mut Rng::new(0));
        let wall = scene.world.walls[0];
        let normal = {
            let e = wall.b - wall.a;
            Vector2::new(-e.y, e.x).normalize()
        };
        let yaw = scene.world_from_laser.rotation.angle();
        let mut max_incidence: f64 = 0.0;
        for (i, target) in sim.truth.beam_target.iter().enumerate() {
            if *target == Some(Target::Wall(0)) {
                let phi = yaw + model.angle(i);
                let cos = (phi.cos() * normal.x + phi.sin() * normal.y).abs();
                max_incidence = max_incidence.max(cos.acos().to_degrees());
            }
        }
        assert!(
            (74.5..=80.0).contains(&max_incidence),
            "{}: incidence reaches {max_incidence} deg",
            scene.name
        );
        // The whole wall is in range: the farthest hit is its far end, within 5.4 m.
        let far = sim
            .truth
            .ranges
            .iter()
            .copied()
            .filter(|r| r.is_finite())
            .fold(0.0, f64::max);
        assert!(far <= 5.4 + 1e-9);
    }
}

#[test]
fn far_walls_reach_the_range_limit() {
    let model = LaserModel::urg04lx().ideal();
    for scene in suite("far", 6, 15).unwrap() {
        let sim = scene.simulate(&model, &mut Rng::new(0));
        let far = sim
            .truth
            .ranges
            .iter()
            .copied()
            .filter(|r| r.is_finite())
            .fold(0.0, f64::max);
        assert!(far > 5.4, "{}: farthest hit {far}", scene.name);
        // Some beams go unanswered: walls beyond 5.6 m.
        assert!(sim.truth.ranges.iter().any(|r| r.is_nan()));
        // The front wall is a long piece at least 4.3 m away.
        assert!(
            sim.truth
                .significant_pieces()
                .any(|p| p.r >= 4.3 - 1e-9 && p.length() > 1.5),
            "{}",
            scene.name
        );
    }
}

#[test]
fn corner_shows_both_walls_and_boxes_stand_free() {
    let model = LaserModel::urg04lx();
    let mut rng = Rng::new(77);
    for _ in 0..20 {
        let scene = scenes::corner(&mut rng);
        assert!(scene.world.clearance(scene.laser_position()) >= MIN_SENSOR_CLEARANCE);
        let sim = scene.simulate(&model, &mut rng);
        let mut walls: Vec<usize> = sim.truth.significant_pieces().map(|p| p.wall).collect();
        walls.sort_unstable();
        assert_eq!(walls, vec![0, 1], "{:?}", sim.truth.pieces);
        // Both pieces reach the corner (the world's origin): one of their end beams is
        // within one beam of the corner's bearing.
        let corner = scene.world_from_laser.inverse() * Point2::origin();
        let bearing = corner.y.atan2(corner.x);
        for piece in sim.truth.significant_pieces() {
            let off = [piece.first, piece.last]
                .iter()
                .map(|i| angle_diff(model.angle(*i), bearing))
                .fold(f64::INFINITY, f64::min);
            assert!(
                off <= model.angle_increment + 1e-12,
                "{piece:?} ends {off} rad off"
            );
        }
    }
    for _ in 0..20 {
        let scene = scenes::boxes_in_room(&mut rng);
        let boxes = (scene.world.walls.len() - 4) / 4;
        assert!((1..=3).contains(&boxes));
        assert_eq!(scene.world.walls.len(), 4 + 4 * boxes);
        assert!(scene.world.clearance(scene.laser_position()) >= 0.4 - 1e-9);
    }
}

#[test]
fn clutter_has_legs_and_debris() {
    for scene in suite("clutter", 3, 10).unwrap() {
        let discs = &scene.world.discs;
        assert!(discs.len() >= 2, "{}: no legs", scene.name);
        assert!(discs.iter().all(|d| d.radius > 0.0 && d.radius <= 0.08));
        // Debris: tiny walls beyond the room's four.
        let tiny = scene.world.walls[4..]
            .iter()
            .filter(|w| w.length() <= 0.12)
            .count();
        assert_eq!(tiny, scene.world.walls.len() - 4);
        assert!(tiny + discs.len() >= 6, "{}", scene.name);
    }
}
