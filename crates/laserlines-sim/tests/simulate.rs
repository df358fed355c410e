//! Simulated scans against known answers: ground truth of hand-built scenes, noise
//! statistics, the sensor's artefacts, determinism, and the standard bench scan.

use laserlines::RangeWindow;
use laserlines::math::{Isometry2, Point2, Vector2, angle_diff};
use laserlines_sim::scenes::BENCH_SEED;
use laserlines_sim::{
    LaserModel, MAX_BEAMS, Noise, Rng, SimScan, Target, World, bench_scan, bench_scene, simulate,
};
use std::f64::consts::{FRAC_PI_2, PI};

fn p(x: f64, y: f64) -> Point2 {
    Point2::new(x, y)
}

fn pose(x: f64, y: f64, yaw_deg: f64) -> Isometry2 {
    Isometry2::new(Vector2::new(x, y), yaw_deg.to_radians())
}

/// A square room of half-size `h` centred at the origin; walls 0..4 are bottom, right, top,
/// left.
fn square_room(h: f64) -> World {
    let mut w = World::new();
    w.add_polygon(&[p(-h, -h), p(h, -h), p(h, h), p(-h, h)]);
    w
}

fn close_pt(a: Point2, b: Point2, tol: f64) -> bool {
    (a - b).norm() < tol
}

#[test]
fn square_room_from_its_centre_gives_four_pieces_with_exact_geometry() {
    // Room [3,7]x[1,5] (centre (5,3), half-size 2), laser at the centre facing 30 deg. A full
    // turn of 1 deg beams starting half a degree past the bottom-right corner, so that the
    // scan's seam falls on a corner and no beam hits a corner exactly.
    let mut world = World::new();
    world.add_polygon(&[p(3.0, 1.0), p(7.0, 1.0), p(7.0, 5.0), p(3.0, 5.0)]);
    let model = LaserModel {
        beams: 360,
        angle_min: (-74.5f64).to_radians(),
        angle_increment: 1f64.to_radians(),
        range_min: 0.02,
        range_max: 10.0,
        ..LaserModel::urg04lx().ideal()
    };
    let sim = simulate(&world, pose(5.0, 3.0, 30.0), &model, &mut Rng::new(1));
    let truth = &sim.truth;
    assert_eq!(truth.pieces.len(), 4, "{:?}", truth.pieces);
    // (wall, first, last, alpha in the laser frame, deg): world normals 0, 90, 180, -90 deg
    // turned by -30 deg.
    let expected = [
        (1usize, 0usize, 89usize, -30.0f64),
        (2, 90, 179, 60.0),
        (3, 180, 269, 150.0),
        (0, 270, 359, -120.0),
    ];
    for (piece, (wall, first, last, alpha_deg)) in truth.pieces.iter().zip(expected) {
        assert_eq!(
            (piece.wall, piece.first, piece.last, piece.beams),
            (wall, first, last, 90)
        );
        assert!((piece.r - 2.0).abs() < 1e-9, "{piece:?}");
        assert!(
            angle_diff(piece.alpha, alpha_deg.to_radians()) < 1e-9,
            "{piece:?}"
        );
        assert!(piece.alpha > -PI && piece.alpha <= PI);
        // End points: the first and last beams cross the wall 44.5 deg off its normal.
        for (beam, point) in [(first, piece.start), (last, piece.end)] {
            let phi = model.angle(beam);
            let range = 2.0 / 44.5f64.to_radians().cos();
            assert!(close_pt(
                point,
                p(range * phi.cos(), range * phi.sin()),
                1e-9
            ));
            assert!((truth.ranges[beam] - range).abs() < 1e-9);
            // ... and lie on the piece's line.
            assert!((point.x * piece.alpha.cos() + point.y * piece.alpha.sin() - 2.0).abs() < 1e-9);
        }
        // 89 deg of a 2 m-distant wall: 2 * 2 * tan(44.5 deg).
        assert!((piece.length() - 4.0 * 44.5f64.to_radians().tan()).abs() < 1e-9);
        for beam in first..=last {
            assert_eq!(truth.beam_target[beam], Some(Target::Wall(wall)));
        }
    }
    // Beam 90 (laser 15.5 deg, world 45.5 deg) hits the top wall 2 m up.
    let expected_range = 2.0 / 44.5f64.to_radians().cos();
    assert!((sim.scan.ranges[90] - expected_range).abs() < 1e-9);
    assert_eq!(truth.significant_pieces().count(), 4);
    assert!(truth.mixed_pixels.is_empty() && truth.dropouts.is_empty());
    assert!(sim.scan.validate().is_ok());
}

#[test]
fn a_wall_across_the_seam_of_a_full_turn_is_one_piece() {
    // The room above with the turn beginning 45 deg later: the seam falls in the middle of
    // the wall that beams 0-44 and 315-359 see, which is one run of 90 beams.
    let mut world = World::new();
    world.add_polygon(&[p(3.0, 1.0), p(7.0, 1.0), p(7.0, 5.0), p(3.0, 5.0)]);
    let model = LaserModel {
        beams: 360,
        angle_min: (-29.5f64).to_radians(),
        angle_increment: 1f64.to_radians(),
        range_min: 0.02,
        range_max: 10.0,
        ..LaserModel::urg04lx().ideal()
    };
    let sim = simulate(&world, pose(5.0, 3.0, 30.0), &model, &mut Rng::new(1));
    assert!(sim.scan.full_turn());
    let pieces = &sim.truth.pieces;
    let runs: Vec<_> = pieces
        .iter()
        .map(|q| (q.wall, q.first, q.last, q.beams))
        .collect();
    assert_eq!(
        runs,
        [
            (2, 45, 134, 90),
            (3, 135, 224, 90),
            (0, 225, 314, 90),
            (1, 315, 44, 90)
        ]
    );
    // From the hit of beam 315 to that of beam 44, the wall's corners 0.5 deg beyond.
    let across = pieces[3];
    let hit = |beam: usize| {
        let phi = model.angle(beam);
        p(phi.cos(), phi.sin()) * sim.truth.ranges[beam]
    };
    assert!(close_pt(across.start, hit(315), 1e-9) && close_pt(across.end, hit(44), 1e-9));
    assert!((across.length() - 4.0 * 44.5f64.to_radians().tan()).abs() < 1e-9);
    // A scan one beam short of the turn has no seam: the wall is two runs.
    let short = LaserModel {
        beams: 358,
        ..model
    };
    let sim = simulate(&world, pose(5.0, 3.0, 30.0), &short, &mut Rng::new(1));
    assert!(!sim.scan.full_turn());
    let walls: Vec<_> = sim.truth.pieces.iter().map(|q| q.wall).collect();
    assert_eq!(walls, [1, 2, 3, 0, 1]);
}

#[test]
fn urg04lx_noise_has_the_specified_sigma_in_both_regimes() {
    let model = LaserModel {
        round_to: None,
        ..LaserModel::urg04lx()
    };
    let mut rng = Rng::new(11);
    // Near regime: a room of half-size 0.6 m, every range in 0.6..0.85 m (sigma 5 mm).
    // Far regime: half-size 2.5 m, ranges 2.5..3.54 m (sigma 0.5 % of range).
    for (half, near) in [(0.6, true), (2.5, false)] {
        let world = square_room(half);
        let mut normalised = Vec::new();
        let mut raw = Vec::new();
        let mut inside_band = 0usize;
        for _ in 0..40 {
            let sim = simulate(&world, Isometry2::identity(), &model, &mut rng);
            for (r, t) in sim.scan.ranges.iter().zip(&sim.truth.ranges) {
                assert!(r.is_finite() && t.is_finite());
                assert_eq!(*t <= 1.0, near);
                let e = r - t;
                normalised.push(e / Noise::Urg04lx.sigma(*t));
                raw.push(if near { e } else { e / t });
                // The data sheet's band: +-10 mm up to 1 m, +-1 % beyond.
                let band = if *t <= 1.0 { 0.010 } else { 0.01 * t };
                if e.abs() <= band {
                    inside_band += 1;
                }
            }
        }
        let (mean, sd) = mean_sd(&normalised);
        assert!(mean.abs() < 0.03, "near {near}: mean {mean}");
        assert!((sd - 1.0).abs() < 0.03, "near {near}: normalised sd {sd}");
        let (_, raw_sd) = mean_sd(&raw);
        let want = 0.005; // 5 mm near, 0.5 % of range far
        assert!(
            (raw_sd / want - 1.0).abs() < 0.03,
            "near {near}: raw sd {raw_sd}"
        );
        // A 2-sigma band holds 95.45 % of gaussian draws.
        let frac = inside_band as f64 / normalised.len() as f64;
        assert!(
            (frac - 0.9545).abs() < 0.01,
            "near {near}: inside band {frac}"
        );
    }
}

#[test]
fn gaussian_noise_has_its_sigma_and_rounding_gives_whole_millimetres() {
    let model = LaserModel {
        noise: Noise::Gaussian { sigma: 0.01 },
        round_to: None,
        ..LaserModel::urg04lx()
    };
    let world = square_room(2.5);
    let mut rng = Rng::new(12);
    let mut errors = Vec::new();
    for _ in 0..40 {
        let sim = simulate(&world, Isometry2::identity(), &model, &mut rng);
        errors.extend(
            sim.scan
                .ranges
                .iter()
                .zip(&sim.truth.ranges)
                .map(|(r, t)| r - t),
        );
    }
    let (mean, sd) = mean_sd(&errors);
    assert!(mean.abs() < 0.0003, "mean {mean}");
    assert!((sd / 0.01 - 1.0).abs() < 0.03, "sd {sd}");

    let rounded = simulate(
        &world,
        Isometry2::identity(),
        &LaserModel::urg04lx(),
        &mut rng,
    );
    for r in &rounded.scan.ranges {
        let mm = r * 1000.0;
        assert!(
            (mm - mm.round()).abs() < 1e-6,
            "{r} is not a whole millimetre"
        );
    }
    // Without noise the rounded range is the true range to the nearest millimetre.
    let exact = LaserModel {
        noise: Noise::None,
        ..LaserModel::urg04lx()
    };
    let sim = simulate(&world, Isometry2::identity(), &exact, &mut rng);
    for (r, t) in sim.scan.ranges.iter().zip(&sim.truth.ranges) {
        assert!((r - t).abs() <= 0.0005 + 1e-12);
    }
}

fn mean_sd(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let mean = xs.iter().sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0);
    (mean, var.sqrt())
}

fn bits(sim: &SimScan) -> Vec<u64> {
    sim.scan.ranges.iter().map(|r| r.to_bits()).collect()
}

#[test]
fn same_seed_gives_the_identical_scan_and_another_seed_does_not() {
    let (scene, _) = bench_scene();
    let model = LaserModel {
        mixed_pixels: 0.5,
        dropout: 0.05,
        ..LaserModel::urg04lx()
    };
    let a = scene.simulate(&model, &mut Rng::new(99));
    let b = scene.simulate(&model, &mut Rng::new(99));
    let c = scene.simulate(&model, &mut Rng::new(100));
    assert_eq!(bits(&a), bits(&b));
    assert_eq!(a.truth, b.truth);
    assert_ne!(bits(&a), bits(&c));
    // The geometry does not depend on the seed; the artefacts do.
    assert_eq!(a.truth.pieces, c.truth.pieces);
    assert_eq!(a.truth.beam_target, c.truth.beam_target);
    assert_ne!(a.truth.dropouts, c.truth.dropouts);
}

#[test]
fn range_limits_and_max_range_returns() {
    // A wall 3 m ahead (x = 3, |y| <= 1) and nothing else.
    let mut world = World::new();
    world.add_segment(p(3.0, -1.0), p(3.0, 1.0));
    let ideal = LaserModel::urg04lx().ideal();

    // Beyond range_max: not seen at all.
    let short = LaserModel {
        range_max: 2.5,
        ..ideal
    };
    let sim = simulate(&world, Isometry2::identity(), &short, &mut Rng::new(1));
    assert!(sim.scan.ranges.iter().all(|r| r.is_nan()));
    assert!(sim.truth.pieces.is_empty());

    // Seen: the beams within atan(1/3) of the front; the rest report no return, or range_max.
    let sim = simulate(&world, Isometry2::identity(), &ideal, &mut Rng::new(1));
    let valid = sim.scan.count_valid(RangeWindow::UNLIMITED);
    let expected = (0..ideal.beams)
        .filter(|i| ideal.angle(*i).abs() <= (1.0f64 / 3.0).atan())
        .count();
    assert_eq!(valid, expected);
    let with_max = LaserModel {
        max_range_returns: true,
        ..ideal
    };
    let sim_max = simulate(&world, Isometry2::identity(), &with_max, &mut Rng::new(1));
    for (i, (a, b)) in sim.scan.ranges.iter().zip(&sim_max.scan.ranges).enumerate() {
        if a.is_nan() {
            assert_eq!(*b, 5.6, "beam {i}");
            assert_eq!(sim_max.truth.beam_target[i], None);
        } else {
            assert_eq!(a, b);
        }
    }

    // An obstacle nearer than range_min gives no return and hides the wall behind it.
    world.add_disc(p(0.05, 0.0), 0.04);
    let sim = simulate(&world, Isometry2::identity(), &with_max, &mut Rng::new(1));
    let front = 340; // beam at 0 rad
    assert!(ideal.angle(front).abs() < 1e-12);
    assert!(sim.scan.ranges[front].is_nan());
    assert_eq!(sim.truth.beam_target[front], None);
}

#[test]
fn dropouts_lose_returns_at_the_given_rate() {
    let world = square_room(2.0);
    let all_lost = LaserModel {
        dropout: 1.0,
        ..LaserModel::urg04lx()
    };
    let sim = simulate(&world, Isometry2::identity(), &all_lost, &mut Rng::new(3));
    assert!(sim.scan.ranges.iter().all(|r| r.is_nan()));
    assert_eq!(sim.truth.dropouts.len(), 682);
    // The truth keeps the geometry.
    assert_eq!(sim.truth.pieces.len(), 3);

    let some_lost = LaserModel {
        dropout: 0.3,
        ..LaserModel::urg04lx()
    };
    let mut lost = 0;
    for seed in 0..20 {
        let sim = simulate(
            &world,
            Isometry2::identity(),
            &some_lost,
            &mut Rng::new(seed),
        );
        for i in &sim.truth.dropouts {
            assert!(sim.scan.ranges[*i].is_nan());
        }
        let nan = sim.scan.ranges.iter().filter(|r| r.is_nan()).count();
        assert_eq!(nan, sim.truth.dropouts.len());
        lost += nan;
    }
    let rate = lost as f64 / (20.0 * 682.0);
    assert!((rate - 0.3).abs() < 0.015, "rate {rate}");
}

#[test]
fn mixed_pixels_fall_between_the_two_surfaces_at_depth_edges() {
    // A wall 3 m ahead with a narrow board 1 m ahead in front of it: two depth edges.
    let mut world = World::new();
    world.add_segment(p(3.0, -2.0), p(3.0, 2.0));
    world.add_segment(p(1.0, -0.2), p(1.0, 0.2));
    let model = LaserModel {
        mixed_pixels: 1.0,
        ..LaserModel::urg04lx().ideal()
    };
    let sim = simulate(&world, Isometry2::identity(), &model, &mut Rng::new(5));
    let t = &sim.truth;
    assert_eq!(t.mixed_pixels.len(), 2, "{:?}", t.mixed_pixels);
    for &j in &t.mixed_pixels {
        // The mixed beam is one side of an edge between the board and the wall.
        let other = if t.beam_target[j] == Some(Target::Wall(1)) {
            [j.wrapping_sub(1), j + 1]
                .into_iter()
                .find(|k| t.beam_target.get(*k) == Some(&Some(Target::Wall(0))))
        } else {
            [j.wrapping_sub(1), j + 1]
                .into_iter()
                .find(|k| t.beam_target.get(*k) == Some(&Some(Target::Wall(1))))
        };
        let other = other.unwrap();
        let (lo, hi) = {
            let (a, b) = (t.ranges[j], t.ranges[other]);
            (a.min(b), a.max(b))
        };
        let r = sim.scan.ranges[j];
        assert!(
            r > lo + 0.04 * (hi - lo) && r < hi - 0.04 * (hi - lo),
            "{r} not in {lo}..{hi}"
        );
    }
    // All other beams are exact, and the truth is unchanged.
    for (i, (r, tr)) in sim.scan.ranges.iter().zip(&t.ranges).enumerate() {
        if !t.mixed_pixels.contains(&i) && tr.is_finite() {
            assert_eq!(r, tr);
        }
    }
    let clean = simulate(
        &world,
        Isometry2::identity(),
        &model.ideal(),
        &mut Rng::new(5),
    );
    assert!(clean.truth.mixed_pixels.is_empty());
    assert_eq!(clean.truth.pieces, t.pieces);
    // The board splits the wall into two pieces: wall 0, board, wall 0.
    let walls: Vec<usize> = t.pieces.iter().map(|p| p.wall).collect();
    assert_eq!(walls, vec![0, 1, 0]);
}

#[test]
fn discs_hide_walls_but_are_not_pieces() {
    let mut world = World::new();
    world.add_segment(p(3.0, -2.0), p(3.0, 2.0));
    world.add_disc(p(1.5, 0.0), 0.1);
    let model = LaserModel::urg04lx().ideal();
    let sim = simulate(&world, Isometry2::identity(), &model, &mut Rng::new(5));
    let t = &sim.truth;
    assert_eq!(t.pieces.len(), 2);
    assert!(
        t.pieces
            .iter()
            .all(|p| p.wall == 0 && (p.r - 3.0).abs() < 1e-9)
    );
    assert_eq!(t.beam_target[340], Some(Target::Disc(0)));
    assert!((t.ranges[340] - 1.4).abs() < 1e-12);
    // The disc's shadow lies between the two pieces, over asin(0.1 / 1.5) either way.
    let gap = t.pieces[1].first - t.pieces[0].last - 1;
    let half = (0.1f64 / 1.5).asin();
    let disc_beams = (0..model.beams)
        .filter(|i| model.angle(*i).abs() <= half)
        .count();
    assert!(
        gap.abs_diff(disc_beams) <= 1,
        "gap {gap}, disc {disc_beams}"
    );
}

#[test]
fn pieces_of_generated_scenes_are_consistent_with_the_beams() {
    let model = LaserModel::urg04lx();
    for scene in laserlines_sim::suite("all", 5, 4).unwrap() {
        let sim = scene.simulate(&model, &mut Rng::new(1));
        let t = &sim.truth;
        assert_eq!(t.beam_target.len(), 682);
        assert_eq!(t.ranges.len(), 682);
        let mut covered = vec![false; 682];
        for piece in &t.pieces {
            assert_eq!(piece.beams, piece.last - piece.first + 1);
            assert!(piece.r >= 0.0 && piece.alpha > -PI && piece.alpha <= PI);
            for (i, seen) in covered
                .iter_mut()
                .enumerate()
                .take(piece.last + 1)
                .skip(piece.first)
            {
                assert_eq!(t.beam_target[i], Some(Target::Wall(piece.wall)));
                assert!(!*seen, "beam {i} in two pieces");
                *seen = true;
                let q = t.point(&sim.scan, i).unwrap();
                let off = q.x * piece.alpha.cos() + q.y * piece.alpha.sin() - piece.r;
                assert!(
                    off.abs() < 1e-9,
                    "{}: beam {i} off its line by {off}",
                    scene.name
                );
            }
            assert_eq!(Some(piece.start), t.point(&sim.scan, piece.first));
            assert_eq!(Some(piece.end), t.point(&sim.scan, piece.last));
            // Maximal runs: the neighbours are on something else.
            if piece.first > 0 {
                assert_ne!(
                    t.beam_target[piece.first - 1],
                    Some(Target::Wall(piece.wall))
                );
            }
            if piece.last + 1 < 682 {
                assert_ne!(
                    t.beam_target[piece.last + 1],
                    Some(Target::Wall(piece.wall))
                );
            }
        }
        // Every beam on a wall is in a piece.
        for (i, target) in t.beam_target.iter().enumerate() {
            assert_eq!(matches!(target, Some(Target::Wall(_))), covered[i]);
        }
    }
}

#[test]
fn bench_scan_has_six_visible_pieces() {
    let (scene, model) = bench_scene();
    assert_eq!(model.beams, 682);
    assert!((model.angle_min.to_degrees() + 120.0).abs() < 1e-9);
    assert!((model.angle_increment.to_degrees() - 0.352).abs() < 1e-12);
    assert_eq!(model.noise, Noise::Gaussian { sigma: 0.01 });
    assert_eq!(model.round_to, Some(0.001));
    assert!((scene.laser_position() - p(1.3, 1.8)).norm() < 1e-12);
    assert!((scene.world_from_laser.rotation.angle().to_degrees() - 100.0).abs() < 1e-9);

    let sim = bench_scan();
    assert_eq!(sim, bench_scan());
    assert_eq!(
        sim,
        scene.simulate(&model, &mut Rng::new(BENCH_SEED)),
        "bench_scan is bench_scene with BENCH_SEED"
    );
    let pieces: Vec<_> = sim.truth.significant_pieces().collect();
    assert_eq!(pieces.len(), 6, "{pieces:?}");
    assert_eq!(sim.truth.pieces.len(), 6);
    // Right wall, top wall (split by the box), two faces of the box, left wall. The room's
    // walls are 0 bottom, 1 right (x = 4), 2 top (y = 6), 3 left (x = 0); 4..8 the box.
    let walls: Vec<usize> = pieces.iter().map(|p| p.wall).collect();
    assert_eq!(walls, vec![1, 2, 4, 7, 2, 3]);
    // Distances from (1.3, 1.8): 2.7 m to x = 4, 4.2 m to y = 6, 1.3 m to x = 0; normals
    // turned by -100 deg.
    for (piece, (r, alpha_deg)) in pieces.iter().filter(|p| p.wall < 4).zip([
        (2.7, -100.0),
        (4.2, -10.0),
        (4.2, -10.0),
        (1.3, 80.0),
    ]) {
        assert!((piece.r - r).abs() < 1e-9, "{piece:?}");
        assert!(angle_diff(piece.alpha, f64::to_radians(alpha_deg)) < 1e-9);
    }
    for piece in &pieces {
        assert!(piece.beams >= 10 && piece.length() >= 0.2);
    }
    // Noise of sigma 10 mm, in whole millimetres.
    let errors: Vec<f64> = sim
        .scan
        .ranges
        .iter()
        .zip(&sim.truth.ranges)
        .map(|(r, t)| r - t)
        .collect();
    assert_eq!(errors.len(), 682);
    let (_, sd) = mean_sd(&errors);
    assert!((sd - 0.01).abs() < 0.001, "sd {sd}");
    assert!(sim.scan.validate().is_ok());
}

#[test]
fn odd_models_and_poses_never_panic() {
    let (scene, base) = bench_scene();
    let odd = [
        LaserModel { beams: 0, ..base },
        LaserModel { beams: 1, ..base },
        LaserModel {
            beams: usize::MAX,
            angle_increment: 1e-9,
            ..base
        },
        LaserModel {
            angle_min: f64::NAN,
            ..base
        },
        LaserModel {
            angle_increment: -base.angle_increment,
            angle_min: FRAC_PI_2,
            ..base
        },
        LaserModel {
            range_min: f64::NAN,
            range_max: f64::NAN,
            ..base
        },
        LaserModel {
            range_max: f64::INFINITY,
            max_range_returns: true,
            ..base
        },
        LaserModel {
            noise: Noise::Gaussian {
                sigma: f64::INFINITY,
            },
            mixed_pixels: f64::NAN,
            dropout: -1.0,
            round_to: Some(f64::NAN),
            ..base
        },
        LaserModel {
            round_to: Some(0.0),
            mixed_pixels: 2.0,
            ..base
        },
    ];
    for model in odd {
        for pose in [
            scene.world_from_laser,
            Isometry2::new(Vector2::new(f64::NAN, 0.0), 0.0),
            Isometry2::new(Vector2::new(1e300, -1e300), 3.0),
        ] {
            let sim = simulate(&scene.world, pose, &model, &mut Rng::new(0));
            let n = model.beams.min(MAX_BEAMS);
            assert_eq!(sim.scan.ranges.len(), n);
            assert_eq!(sim.truth.beam_target.len(), n);
            for piece in &sim.truth.pieces {
                assert!(piece.r.is_finite() && piece.alpha.is_finite());
                assert!(piece.start.x.is_finite() && piece.end.y.is_finite());
            }
        }
    }
    // A negative increment scans clockwise: the same room, the beams reversed.
    let reversed = LaserModel {
        angle_min: base.angle_min + 681.0 * base.angle_increment,
        angle_increment: -base.angle_increment,
        ..base.ideal()
    };
    let fwd = scene.simulate(&base.ideal(), &mut Rng::new(0));
    let rev = scene.simulate(&reversed, &mut Rng::new(0));
    for i in 0..682 {
        assert!((fwd.truth.ranges[i] - rev.truth.ranges[681 - i]).abs() < 1e-9);
    }
    assert_eq!(fwd.truth.pieces.len(), rev.truth.pieces.len());
}
