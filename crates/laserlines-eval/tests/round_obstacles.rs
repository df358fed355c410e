//! Round obstacles give no lines, box corners keep theirs (`arc_significance`): a barrel of
//! the rescue arenas (0.58 m across) and a box of 0.4 m turned 45 deg, each in front of a wall
//! 4 m away, seen by the URG-04LX at its real noise (3 mm, 0.15 % of the range) and at half
//! its data sheet's band, 50 scans each; and a pillar seen by a fine 270 deg scanner.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines::line::beams;
use laserlines::math::{Isometry2, Point2, Vector2};
use laserlines::{HoughSplit, HoughSplitParams, LineExtractor, RangeNoise};
use laserlines_sim::scenes::Scene;
use laserlines_sim::{LaserModel, Noise, Rng, Target, World};

/// The barrel's radius, m (`fiducial_barrel`, `red_barrel`).
const BARREL: f64 = 0.29;

/// A wall across the view 4 m ahead and the obstacle `add`s in front of it.
fn scene(add: impl Fn(&mut World)) -> Scene {
    let mut world = World::new();
    world.add_segment(Point2::new(4.0, -4.0), Point2::new(4.0, 4.0));
    add(&mut world);
    Scene {
        name: "obstacle before a wall".into(),
        world,
        world_from_laser: Isometry2::new(Vector2::zeros(), 0.0),
    }
}

/// Over 50 scans of `scene` under `noise`: the lines whose beams mostly hit the obstacle
/// (anything but wall 0), and the scans with a line on the wall.
fn lines_on_obstacle(scene: &Scene, noise: RangeNoise, params: HoughSplitParams) -> (usize, usize) {
    let model = LaserModel {
        noise: Noise::Range(noise),
        ..LaserModel::urg04lx()
    };
    lines_on_obstacle_seen_by(scene, &model, params)
}

/// [`lines_on_obstacle`] with the laser `model`.
fn lines_on_obstacle_seen_by(
    scene: &Scene,
    model: &LaserModel,
    params: HoughSplitParams,
) -> (usize, usize) {
    let mut hs = HoughSplit::new(params).unwrap();
    let (mut on_obstacle, mut wall_seen) = (0, 0);
    for seed in 0..50 {
        let sim = scene.simulate(model, &mut Rng::new(seed));
        let lines = hs.extract(&sim.scan);
        for l in &lines {
            let n = sim.scan.len();
            let on_wall = beams(l.first, l.last, n)
                .filter(|&i| sim.truth.beam_target[i] == Some(Target::Wall(0)))
                .count();
            if 2 * on_wall < l.beam_span(n) {
                on_obstacle += 1;
            }
        }
        wall_seen += usize::from(lines.iter().any(|l| (l.r - 4.0).abs() < 0.05));
    }
    (on_obstacle, wall_seen)
}

/// The defaults without the test of round obstacles.
fn without_the_test() -> HoughSplitParams {
    HoughSplitParams {
        arc_significance: 0.0,
        ..HoughSplitParams::default()
    }
}

const LEVELS: [(&str, RangeNoise); 2] = [
    ("real noise", RangeNoise::new(0.003, 0.0015)),
    ("half band", RangeNoise::new(0.005, 0.005)),
];

#[test]
fn a_barrel_gives_few_lines() {
    // Measured over the ten cases, lines on the barrel: 6 with the test (all at 3 m under the
    // real noise), 495 without; 124 with and 430 without before the cut between pieces
    // weighed each line's noise and a chord was tried beside a piece that gave no line, and
    // 149 with the test before two lines were charged for their extra parameters.
    let (mut with, mut without) = (0, 0);
    for d in [0.7, 1.0, 1.5, 2.0, 3.0] {
        let barrel = scene(|w| {
            w.add_disc(Point2::new(d, 0.3), BARREL);
        });
        for (what, noise) in LEVELS {
            let (on, seen) = lines_on_obstacle(&barrel, noise, HoughSplitParams::default());
            let (on_off, _) = lines_on_obstacle(&barrel, noise, without_the_test());
            println!("barrel at {d} m, {what}: {on} lines with the test, {on_off} without");
            assert_eq!(seen, 50, "{d} m, {what}: the wall");
            with += on;
            without += on_off;
        }
    }
    assert!(without >= 300, "{without} lines without the test");
    assert!(
        20 * with <= without,
        "{with} lines with the test, {without} without"
    );
}

#[test]
fn a_pillar_seen_by_a_fine_scanner_gives_few_lines() {
    // A pillar of 0.52 m across 1.2 m ahead, seen in 0.25 deg steps over 270 deg under 1 cm
    // of range noise: the algebraic circle of its chords is too small (about 0.21 m for
    // 0.26 m) and fits them worse than two lines; the geometric fit does not. Measured: 1
    // line on the pillar with the test, 102 without (18 before a chord was tried beside a
    // piece that gave no line; before two lines were charged for their extra parameters, 39
    // with the test and 79 with the algebraic circle alone).
    let pillar = scene(|w| {
        w.add_disc(Point2::new(1.2, 0.0), 0.26);
    });
    let model = LaserModel {
        beams: 1081,
        angle_min: -135f64.to_radians(),
        angle_increment: 0.25f64.to_radians(),
        range_max: 30.0,
        noise: Noise::Range(RangeNoise::new(0.01, 0.0)),
        ..LaserModel::urg04lx()
    };
    let (with, seen) = lines_on_obstacle_seen_by(&pillar, &model, HoughSplitParams::default());
    let (without, _) = lines_on_obstacle_seen_by(&pillar, &model, without_the_test());
    println!("pillar: {with} lines with the test, {without} without");
    assert_eq!(seen, 50, "the wall");
    assert!(without >= 70, "{without} lines without the test");
    assert!(
        20 * with <= without,
        "{with} lines with the test, {without} without"
    );
}

#[test]
fn a_box_corner_keeps_its_two_faces() {
    for d in [1.0, 2.0] {
        let boxed = scene(|w| {
            w.add_box(Point2::new(d, 0.3), 0.4, 0.4, 45f64.to_radians());
        });
        for (what, noise) in LEVELS {
            let (with, seen) = lines_on_obstacle(&boxed, noise, HoughSplitParams::default());
            let (without, _) = lines_on_obstacle(&boxed, noise, without_the_test());
            println!("box at {d} m, {what}: {with} lines with the test, {without} without");
            // Both faces in nearly every scan, and the same lines with the test as without.
            assert!(without >= 95, "{d} m, {what}: {without}");
            assert_eq!(with, without, "{d} m, {what}");
            assert_eq!(seen, 50, "{d} m, {what}: the wall");
        }
    }
}

#[test]
fn convex_corners_under_heavy_noise_keep_what_they_had_without_the_test() {
    // The data sheet's band and 1.5 times it, where a circle fits two faces' points nearly
    // as well as two lines and the lines are charged for their extra parameters: a box's
    // corner (90 deg) and two panels of 0.4 m meeting at 135 deg (a rescue arena's diagonal
    // wall), the corner towards the sensor. Measured: 100 lines with the test and without
    // for the box at 0.7-1.6 m (99 at 1.6 m and 1.5 times), for the panels at 1 m at both
    // levels and at 1.5 m under the band; at 1.5 m and 1.5 times the band, 81 with the test
    // and 84 without (84 with the lines charged nothing, or 2 variances): the price of the
    // charge's 4.
    let heavy = [
        ("full band", RangeNoise::new(0.01, 0.01)),
        ("1.5 times the band", RangeNoise::new(0.015, 0.015)),
    ];
    // Each scene with the lines the test may cost it over its 50 scans at either level.
    let mut scenes = Vec::new();
    for d in [0.7, 1.0, 1.3, 1.6] {
        scenes.push((
            format!("box at {d} m"),
            0,
            scene(|w| {
                w.add_box(Point2::new(d, 0.3), 0.4, 0.4, 45f64.to_radians());
            }),
        ));
    }
    for d in [1.0, 1.5] {
        // The corner at (d, 0.3); each panel 0.4 m long, 22.5 deg from the beam's normal.
        let (c, s) = (22.5f64.to_radians().cos(), 22.5f64.to_radians().sin());
        scenes.push((
            format!("panels at {d} m"),
            4,
            scene(|w| {
                let corner = Point2::new(d, 0.3);
                w.add_segment(corner + Vector2::new(0.4 * s, 0.4 * c), corner);
                w.add_segment(corner, corner + Vector2::new(0.4 * s, -0.4 * c));
            }),
        ));
    }
    for (name, allowed, obstacle) in &scenes {
        for (what, noise) in heavy {
            let (with, _) = lines_on_obstacle(obstacle, noise, HoughSplitParams::default());
            let (without, _) = lines_on_obstacle(obstacle, noise, without_the_test());
            println!("{name}, {what}: {with} lines with the test, {without} without");
            assert!(without >= 80, "{name}, {what}: {without}");
            if *allowed == 0 {
                assert_eq!(with, without, "{name}, {what}");
            } else {
                assert!(
                    with + allowed >= without,
                    "{name}, {what}: {with} against {without}"
                );
            }
        }
    }
}

#[test]
fn a_round_room_seen_from_inside_keeps_its_lines() {
    // A room of 1 m radius (a 90-gon), the sensor 0.7 m off its centre: the walls' arc
    // bends away from the sensor, which lies inside the circle. Every line stays.
    let mut world = World::new();
    let corners: Vec<Point2> = (0..90)
        .map(|k| {
            let t = f64::from(k) * std::f64::consts::TAU / 90.0;
            Point2::new(0.7 + t.cos(), t.sin())
        })
        .collect();
    world.add_polygon(&corners);
    let room = Scene {
        name: "round room".into(),
        world,
        world_from_laser: Isometry2::new(Vector2::zeros(), 0.0),
    };
    for (what, noise) in LEVELS {
        let model = LaserModel {
            noise: Noise::Range(noise),
            ..LaserModel::urg04lx()
        };
        let mut with = HoughSplit::new(HoughSplitParams::default()).unwrap();
        let mut without = HoughSplit::new(without_the_test()).unwrap();
        let (mut a, mut b) = (0, 0);
        for seed in 0..20 {
            let sim = room.simulate(&model, &mut Rng::new(seed));
            a += with.extract(&sim.scan).len();
            b += without.extract(&sim.scan).len();
        }
        println!("round room, {what}: {a} lines with the test, {b} without");
        assert!(b >= 100, "{what}: {b}");
        assert_eq!(a, b, "{what}");
    }
}
