//! Navigation end to end: perception figures against the simulator's ground truth, the
//! arena loader on real files, bad input, determinism (the acceptance runs are in
//! `acceptance.rs`).

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::{accounted, arena_start, outline_of, shared_arena};

use laserlines::math::{Isometry2, Point2, Vector2};
use laserlines::{HoughSplit, HoughSplitParams, LineExtractor};
use laserlines_harness::{CoverageGrid, RunConfig, RunError, arenas, run};
use laserlines_nav::sectors::{describe, select_segments};
use laserlines_nav::{Sector, SectorParams, select_objects};
use laserlines_sim::arena::{ArenaError, ArenaOptions, interior_start, load_raf, parse_raf};
use laserlines_sim::maze::{MazeParams, generate};
use laserlines_sim::robot::{RobotError, RobotParams, RobotSim};
use laserlines_sim::{LaserModel, Rng, World, simulate};

fn pose(x: f64, y: f64, yaw_deg: f64) -> Isometry2 {
    Isometry2::new(Vector2::new(x, y), yaw_deg.to_radians())
}

/// The perceived sector objects match the ones selected from the true visible wall pieces:
/// distance within 3 cm, angle within 1 deg, width within 5 cm, on clean walls.
#[test]
fn perception_matches_ground_truth_on_clean_walls() {
    let robot_from_laser = RobotParams::default().robot.laser.robot_from_laser();
    let model = LaserModel::urg04lx();
    let params = SectorParams::default();
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
    // A 1.2 m corridor with a wall across its end, and a 4 m x 3 m room.
    let mut corridor = World::new();
    corridor.add_segment(Point2::new(-5.0, 0.6), Point2::new(5.0, 0.6));
    corridor.add_segment(Point2::new(-5.0, -0.6), Point2::new(5.0, -0.6));
    corridor.add_segment(Point2::new(5.0, -0.6), Point2::new(5.0, 0.6));
    let mut room = World::new();
    room.add_box(Point2::new(0.0, 0.0), 4.0, 3.0, 0.0);
    let mut rng = Rng::new(11);
    let mut compared = 0;
    for (world, poses) in [
        (
            &corridor,
            vec![
                pose(0.0, 0.0, 0.0),
                pose(2.0, 0.1, 10.0),
                pose(3.5, -0.1, -15.0),
                pose(1.0, 0.0, 20.0),
            ],
        ),
        (
            &room,
            vec![
                pose(0.0, 0.0, 0.0),
                pose(0.5, 0.3, 30.0),
                pose(-0.8, -0.4, -60.0),
                pose(1.0, 0.5, 135.0),
            ],
        ),
    ] {
        for world_from_robot in poses {
            for _ in 0..5 {
                let world_from_laser = world_from_robot * robot_from_laser;
                let sim = simulate(world, world_from_laser, &model, &mut rng);
                let lines = hs.extract(&sim.scan);
                let seen = select_objects(&lines, &robot_from_laser, &params);
                // Ground truth: the visible pieces, moved into the robot frame.
                let pieces: Vec<_> = sim.truth.significant_pieces().copied().collect();
                let truth: Vec<(Point2, Point2)> = pieces
                    .iter()
                    .map(|p| (robot_from_laser * p.start, robot_from_laser * p.end))
                    .collect();
                // Where a piece ends at a grazing angle, its true end lies somewhere between
                // its last beam and the next one, and the range noise moves the last points
                // along the wall by sigma / sin(incidence): the width is known to that only.
                let end_slack: Vec<f64> = pieces
                    .iter()
                    .map(|p| {
                        let gap = |i: Option<usize>, end: Point2| {
                            i.and_then(|i| sim.truth.point(&sim.scan, i))
                                .map_or(0.0, |q| (q - end).norm())
                        };
                        let along = (p.end - p.start).normalize();
                        let grazing = |end: Point2| {
                            let r = end.coords.norm();
                            let beam = end.coords / r;
                            let sin = (beam.x * along.y - beam.y * along.x).abs().max(0.05);
                            2.0 * model.noise.sigma(r) / sin
                        };
                        gap(p.first.checked_sub(1), p.start)
                            + gap(Some(p.last + 1), p.end)
                            + grazing(p.start)
                            + grazing(p.end)
                    })
                    .collect();
                let want = select_segments(&truth, &params);
                for sector in Sector::ALL {
                    let (Some(got), Some(best)) = (seen.get(sector), want.get(sector)) else {
                        assert_eq!(
                            seen.get(sector).is_some(),
                            want.get(sector).is_some_and(|o| o.width_m > 0.2),
                            "{sector:?} at {world_from_robot:?}"
                        );
                        continue;
                    };
                    // The selected wall is the true one of the highest score, or one within
                    // a few per cent of it (two walls of a symmetric corridor): compare with
                    // the true piece of the wall that was selected.
                    let exp = truth
                        .iter()
                        .enumerate()
                        .filter_map(|(k, &(a, b))| describe(a, b, sector, k, &params))
                        .min_by(|x, y| {
                            let dx = (x.nearest - got.nearest).norm();
                            let dy = (y.nearest - got.nearest).norm();
                            dx.total_cmp(&dy)
                        })
                        .unwrap();
                    assert!(
                        exp.score >= 0.9 * best.score,
                        "selection {got:?} vs {best:?}"
                    );
                    // Clean walls: long visible pieces only.
                    if exp.width_m < 0.3 {
                        continue;
                    }
                    compared += 1;
                    let ctx = format!("{sector:?} at {world_from_robot:?}: {got:?} vs {exp:?}");
                    assert!(
                        (got.distance_m - exp.distance_m).abs() < 0.03,
                        "distance {ctx}"
                    );
                    let da = (got.angle_rad - exp.angle_rad).abs();
                    let da = da.min(std::f64::consts::PI - da);
                    assert!(da < 1f64.to_radians(), "angle {ctx}");
                    let slack = end_slack[exp.line];
                    assert!(
                        (got.width_m - exp.width_m).abs() < 0.05 + slack,
                        "width {ctx}"
                    );
                }
            }
        }
    }
    assert!(compared >= 80, "only {compared} objects compared");
}

#[test]
fn bundled_arenas_load_with_the_documented_geometry() {
    let opts = ArenaOptions::default();
    let maze = arenas::bundled("maze_10m_x_14m", &opts).unwrap().unwrap();
    assert_eq!(maze.report.elements, 113);
    assert_eq!(maze.report.wall_elements, 113);
    assert!(maze.report.skipped.is_empty() && maze.report.out_of_plane.is_empty());
    assert_eq!(
        maze.world.walls.len() + maze.report.duplicate_walls,
        113,
        "every wall element is a wall or a duplicate"
    );
    let inner = arenas::bundled("inner_explore_test.raf", &opts)
        .unwrap()
        .unwrap();
    assert_eq!(inner.report.wall_elements, 60);
    // First element: small_wall rotation 270 at (0, 0): the -x edge of the cell at the
    // origin, from (-0.6, -0.6) to (-0.6, 0.6).
    let w = inner.world.walls[0];
    assert!((w.a - Point2::new(-0.6, -0.6)).norm() < 1e-12, "{w:?}");
    assert!((w.b - Point2::new(-0.6, 0.6)).norm() < 1e-12, "{w:?}");
    // Third: small_wall rotation 90 at (-1, 2): the +x edge of the cell centred at
    // (-1.2, 2.4), i.e. x = -0.6 from y = 3.0 down to 1.8.
    let w = inner.world.walls[2];
    assert!((w.a - Point2::new(-0.6, 3.0)).norm() < 1e-12, "{w:?}");
    assert!((w.b - Point2::new(-0.6, 1.8)).norm() < 1e-12, "{w:?}");
}

#[test]
fn the_bundled_competition_arenas_model_every_element() {
    let opts = ArenaOptions::default();
    let go = arenas::bundled("go2011_arena", &opts).unwrap().unwrap();
    let r = &go.report;
    assert_eq!(r.elements, 178);
    assert_eq!(accounted(r), 178);
    assert!(r.skipped.is_empty(), "{:?}", r.skipped);
    // Six diagonal walls and six diagonal corners (two plates each).
    assert_eq!(r.in_plane.get("wall_diag_120"), Some(&6));
    assert_eq!(r.in_plane.get("corner_diag_120"), Some(&6));
    let diagonal = go
        .world
        .walls
        .iter()
        .filter(|w| {
            let d = w.b - w.a;
            (d.x.abs() - d.y.abs()).abs() < 1e-9 && d.x.abs() > 0.1
        })
        .count();
    assert_eq!(diagonal, 6 + 2 * 6);
    // Barrels: eight halves back to back make four discs, one half stands alone.
    assert_eq!(r.barrels, 4);
    assert_eq!(go.world.discs.len(), 4);
    // Below the laser at 0.45 m: ramps (0.17 m, 0.34 m), step fields (0.40 m), the stairs'
    // open treads around it; above it: the shelves, spectators, barrels on elevated
    // floors.
    for (kind, n) in [
        ("half_ramp", 40),
        ("full_ramp", 19),
        ("stepfield_red_diagonal", 5),
        ("stairs_120", 1),
        ("manip_storage", 1),
        ("spectator_120", 3),
        ("fiducial_barrel_high", 3),
    ] {
        assert_eq!(r.out_of_plane.get(kind), Some(&n), "{kind}");
    }
    let big = arenas::bundled("rc_2015_arena_big.raf", &opts)
        .unwrap()
        .unwrap();
    let r = &big.report;
    assert_eq!((r.elements, accounted(r)), (233, 233));
    assert!(r.skipped.is_empty(), "{:?}", r.skipped);
    assert_eq!(r.in_plane.get("wall_diag_120"), Some(&3));
    assert_eq!(r.in_plane.get("corner_diag_120"), Some(&4));
    // Its stray wall 19 m east of the rest stays out of the arena's bounds.
    let outline = laserlines_sim::arena::ArenaOutline::new(&big.world);
    let (_, hi) = outline.bounds().unwrap();
    assert!((hi.x - 9.0).abs() < 1e-9, "{hi:?}");
    // Both start at their origin, in the arena their walls enclose.
    for arena in [&go, &big] {
        let start = arena_start(&arena.world);
        assert!(start.translation.vector.norm() < 1e-9, "{}", arena.name);
        assert!(outline_of(&arena.world).encloses(Point2::origin()));
    }
}

#[test]
fn real_arenas_report_every_element() {
    let Some(path) = shared_arena("exploration_eval_arena.raf") else {
        return;
    };
    let a = load_raf(&path, &ArenaOptions::default()).unwrap();
    let r = &a.report;
    assert_eq!(r.elements, 220);
    assert_eq!(accounted(r), 220);
    // small_wall 65, tall_wall 14, wall_holes1 16.
    assert_eq!(r.wall_elements, 95);
    // 14 half barrels: six pairs back to back, and one half placed twice at (-3, -4).
    assert_eq!(r.in_plane.get("fiducial_barrel"), Some(&14));
    assert_eq!(r.barrels, 6);
    assert_eq!(a.world.discs.len(), 6);
    assert_eq!(r.out_of_plane.get("half_ramp"), Some(&46));
    assert_eq!(r.out_of_plane.get("full_ramp"), Some(&19));
    assert_eq!(r.out_of_plane.get("stepfield_red_diagonal"), Some(&10));
    assert_eq!(r.out_of_plane.get("fiducial_barrel_high"), Some(&16));
    // Victims in boxes: on the wall at 0.3 m or 0.6 m (in the plane) or at 0.9 m or on
    // the floor (not).
    let victims = r.in_plane.get("victim_with_box1").unwrap_or(&0)
        + r.out_of_plane.get("victim_with_box1").unwrap_or(&0);
    assert_eq!(victims, 15);
    assert!(r.skipped.is_empty() && r.unknown_types().is_empty());
    if let Some(path) = shared_arena("go2013_arena.raf") {
        let a = load_raf(&path, &ArenaOptions::default()).unwrap();
        assert_eq!(a.report.in_plane.get("wall_diag_120"), Some(&19));
        assert_eq!(a.report.out_of_plane.get("stairs_120"), Some(&1));
        assert_eq!(accounted(&a.report), a.report.elements);
    }
}

#[test]
fn bad_input_gives_clear_errors() {
    let opts = ArenaOptions::default();
    // An unknown element type is reported, not dropped.
    let a = parse_raf(
        r#"<elements><element type="small_wall" rotation="0" x="0" y="0"/>
           <element type="laser_trap" rotation="90" x="1" y="1"/></elements>"#,
        "odd.raf",
        &opts,
    )
    .unwrap();
    assert_eq!(a.report.skipped.get("laser_trap"), Some(&1));
    assert_eq!(a.report.unknown_types(), vec!["laser_trap"]);
    // An empty arena.
    let e = parse_raf("<elements/>", "empty.raf", &opts).unwrap_err();
    assert!(matches!(e, ArenaError::Empty { .. }), "{e}");
    assert!(e.to_string().contains("empty.raf"));
    // An unreadable file.
    let e = load_raf(std::path::Path::new("/nonexistent/arena.raf"), &opts).unwrap_err();
    assert!(matches!(e, ArenaError::Io { .. }), "{e}");
    // A start inside a wall.
    let maze = arenas::bundled("maze_10m_x_14m", &opts).unwrap().unwrap();
    let on_wall = pose(-0.6, 0.0, 0.0);
    let e = run(&maze.world, on_wall, &RunConfig::default()).unwrap_err();
    assert!(
        matches!(e, RunError::Robot(RobotError::StartInCollision { .. })),
        "{e}"
    );
    assert!(e.to_string().contains("wall"), "{e}");
    let e = RobotSim::new(&maze.world, on_wall, RobotParams::default(), 0).unwrap_err();
    assert!(e.to_string().contains("start pose"), "{e}");
    // A laser mounted backwards: the explorer would drive into what it cannot see.
    let free = pose(0.0, 0.0, 0.0);
    let mut backwards = RunConfig::default();
    backwards.robot.robot.laser.yaw = std::f64::consts::PI;
    let e = run(&maze.world, free, &backwards).unwrap_err();
    assert!(matches!(e, RunError::FrontUnseen { .. }), "{e}");
    assert!(e.to_string().contains("sees 60.5 to 299.9 deg"), "{e}");
    // Turned by 65 deg either way, or by a full turn, it still sees the front sector.
    for yaw in [
        65f64.to_radians(),
        -65f64.to_radians(),
        std::f64::consts::TAU,
    ] {
        let mut turned = RunConfig::default();
        turned.robot.robot.laser.yaw = yaw;
        turned.duration_s = 0.5;
        assert!(run(&maze.world, free, &turned).is_ok(), "yaw {yaw}");
    }
    // A bad duration.
    let e = run(
        &maze.world,
        pose(0.0, 0.0, 0.0),
        &RunConfig {
            duration_s: f64::NAN,
            ..RunConfig::default()
        },
    )
    .unwrap_err();
    assert!(matches!(e, RunError::Setting(_)), "{e}");
}

#[test]
fn the_same_seed_gives_the_same_metrics() {
    let maze = generate(
        &MazeParams {
            cols: 5,
            rows: 5,
            islands: 1,
            ..MazeParams::default()
        },
        9,
    );
    let config = RunConfig {
        duration_s: 40.0,
        seed: 3,
        ..RunConfig::default()
    };
    let a = run(&maze.world, maze.start, &config).unwrap();
    let b = run(&maze.world, maze.start, &config).unwrap();
    let mut ma = a.metrics;
    let mut mb = b.metrics;
    ma.wall_time_s = 0.0;
    mb.wall_time_s = 0.0;
    ma.setup_time_s = 0.0;
    mb.setup_time_s = 0.0;
    assert_eq!(ma, mb);
    assert_eq!(a.path, b.path);
    let c = run(
        &maze.world,
        maze.start,
        &RunConfig {
            seed: 4,
            ..config.clone()
        },
    )
    .unwrap();
    assert_ne!(a.odometry_path, c.odometry_path);
}

#[test]
fn arena_starts_lie_in_the_arena() {
    let opts = ArenaOptions::default();
    // The bundled arenas start at the centre of cell (0, 0), as their files intend.
    for name in ["maze_10m_x_14m", "inner_explore_test"] {
        let arena = arenas::bundled(name, &opts).unwrap().unwrap();
        let start = arena_start(&arena.world);
        assert!(start.translation.vector.norm() < 1e-9, "{name}: {start:?}");
        // The region reached from there is the arena's inside, not the open space
        // around it: well inside the walls' bounding box.
        let robot = RobotSim::new(&arena.world, start, RobotParams::default(), 0).unwrap();
        let grid = CoverageGrid::new(robot.index(), Point2::origin(), 0.32);
        let area = grid.reachable_area_m2();
        assert!(area > 15.0 && area < 80.0, "{name}: {area} m^2");
    }
    // The other arenas start in the arena their walls enclose, and from there the robot
    // reaches nearly all of its floor (in exploration_eval_arena its half barrels, two
    // back to back on a cell edge, no longer close off the origin as whole barrels at the
    // cell centres did).
    for name in [
        "exploration_eval_arena.raf",
        "go2013_arena.raf",
        "slam_lc_02.raf",
    ] {
        let Some(path) = shared_arena(name) else {
            continue;
        };
        let arena = load_raf(&path, &opts).unwrap();
        let start = arena_start(&arena.world);
        let p = Point2::from(start.translation.vector);
        assert!(outline_of(&arena.world).encloses(p), "{name}");
        let grid = CoverageGrid::new(
            &laserlines_sim::index::WorldIndex::new(&arena.world, 0.6),
            p,
            0.32,
        );
        assert_eq!(
            grid.region_kind(),
            laserlines_harness::CoverageRegion::Enclosed
        );
        assert!(
            grid.reachable_area_m2() > 0.95 * grid.region_area_m2(),
            "{name}: {} of {}",
            grid.reachable_area_m2(),
            grid.region_area_m2()
        );
    }
    // No enclosed region: no start.
    let mut open = World::new();
    open.add_segment(Point2::new(0.0, 0.0), Point2::new(5.0, 0.0));
    assert!(interior_start(&open, 0.32).is_none());
}
