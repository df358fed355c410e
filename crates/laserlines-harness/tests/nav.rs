//! Navigation end to end: perception figures against the simulator's ground truth, the
//! arena loader on real files, bad input, determinism, and the acceptance runs.

#![allow(clippy::unwrap_used, clippy::expect_used)]

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
    assert!(maze.report.ignored.is_empty());
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

fn shared_arena(name: &str) -> Option<std::path::PathBuf> {
    let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data/arenas")
        .join(name);
    if p.exists() {
        Some(p)
    } else {
        skip_notice(&p, "this arena's test");
        None
    }
}

#[test]
fn real_arenas_report_what_they_ignore() {
    let Some(path) = shared_arena("exploration_eval_arena.raf") else {
        return;
    };
    let a = load_raf(&path, &ArenaOptions::default()).unwrap();
    let r = &a.report;
    assert_eq!(r.elements, 220);
    // small_wall 65, tall_wall 14, wall_holes1 16.
    assert_eq!(r.wall_elements, 95);
    assert_eq!(r.barrels, 30);
    assert_eq!(a.world.discs.len(), 30);
    assert_eq!(r.ignored.get("half_ramp"), Some(&46));
    assert_eq!(r.ignored.get("full_ramp"), Some(&19));
    assert_eq!(r.ignored.get("victim_with_box1"), Some(&15));
    assert_eq!(r.ignored.get("stepfield_red_diagonal"), Some(&10));
    assert_eq!(r.ignored_count(), 220 - 95 - 30);
    assert!(r.unknown_types().is_empty());
    if let Some(path) = shared_arena("go2013_arena.raf") {
        let a = load_raf(&path, &ArenaOptions::default()).unwrap();
        assert_eq!(a.report.ignored.get("wall_diag_120"), Some(&19));
        assert_eq!(a.report.ignored.get("stairs_120"), Some(&1));
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
    assert_eq!(a.report.ignored.get("laser_trap"), Some(&1));
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

/// The start of an arena run: the grid cell centre nearest the origin in the largest free
/// region the walls enclose (where the robot fits in any heading).
fn arena_start(world: &World) -> Isometry2 {
    interior_start(world, RobotParams::default().robot.footprint.circumradius())
        .expect("the arena encloses a free region")
}

#[test]
fn arena_starts_lie_in_the_largest_enclosed_region() {
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
    // exploration_eval_arena's origin lies in a 1.4 m^2 pocket closed by barrels; its
    // start is in the 34 m^2 main hall instead.
    if let Some(path) = shared_arena("exploration_eval_arena.raf") {
        let arena = load_raf(&path, &opts).unwrap();
        let origin_pocket = CoverageGrid::new(
            &laserlines_sim::index::WorldIndex::new(&arena.world, 0.6),
            Point2::origin(),
            0.32,
        );
        assert!(origin_pocket.reachable_area_m2() < 2.0);
        let start = arena_start(&arena.world);
        let p = Point2::from(start.translation.vector);
        let grid = CoverageGrid::new(
            &laserlines_sim::index::WorldIndex::new(&arena.world, 0.6),
            p,
            0.32,
        );
        assert!(
            grid.reachable_area_m2() > 30.0,
            "{}",
            grid.reachable_area_m2()
        );
    }
    // No enclosed region: no start.
    let mut open = World::new();
    open.add_segment(Point2::new(0.0, 0.0), Point2::new(5.0, 0.0));
    assert!(interior_start(&open, 0.32).is_none());
}

/// What the runs of one world gave.
struct Tally {
    name: String,
    runs: usize,
    collisions: u64,
    min_coverage: f64,
    mean_coverage: f64,
    max_pose_error: f64,
    t90: Vec<f64>,
}

impl Tally {
    fn new(name: String) -> Self {
        Self {
            name,
            runs: 0,
            collisions: 0,
            min_coverage: 1.0,
            mean_coverage: 0.0,
            max_pose_error: 0.0,
            t90: Vec::new(),
        }
    }
}

fn runs(name: &str, world: &World, start: Isometry2, seeds: std::ops::Range<u64>) -> Tally {
    let mut t = Tally::new(name.to_owned());
    for seed in seeds {
        let config = RunConfig {
            seed,
            ..RunConfig::default()
        };
        let m = run(world, start, &config).unwrap().metrics;
        assert!(m.sim_time_s <= 900.0 + 1e-9);
        t.runs += 1;
        t.collisions += m.collisions;
        t.min_coverage = t.min_coverage.min(m.coverage);
        t.mean_coverage += m.coverage;
        t.max_pose_error = t.max_pose_error.max(m.max_pose_error_m);
        t.t90.extend(m.time_to_90_percent_s);
    }
    t.mean_coverage /= t.runs.max(1) as f64;
    let (lo, hi) = t
        .t90
        .iter()
        .fold((f64::INFINITY, 0.0_f64), |(a, b), &x| (a.min(x), b.max(x)));
    // A row of the README's table.
    println!(
        "| {} | {} | {} | {:.3} | {:.3} | {} | {:.2} |",
        t.name,
        t.runs,
        t.collisions,
        t.min_coverage,
        t.mean_coverage,
        if t.t90.is_empty() {
            "never".to_owned()
        } else if t.t90.len() == t.runs {
            format!("{lo:.0}-{hi:.0} s")
        } else {
            format!("{lo:.0}-{hi:.0} s ({} of {} runs)", t.t90.len(), t.runs)
        },
        t.max_pose_error,
    );
    t
}

/// The acceptance runs of the two bundled arenas: 20 seeded runs of (at most) 15 simulated
/// minutes each, zero collisions and coverage at least 0.90 in every run. Run with
/// optimisations (`cargo test --release -p laserlines-harness`); CI does.
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "slow without optimisations: run with --release"
)]
fn acceptance_bundled_arenas() {
    let opts = ArenaOptions::default();
    for name in ["inner_explore_test", "maze_10m_x_14m"] {
        let arena = arenas::bundled(name, &opts).unwrap().unwrap();
        let start = arena_start(&arena.world);
        let t = runs(
            &format!("`{name}.raf` (bundled)"),
            &arena.world,
            start,
            0..20,
        );
        assert_eq!(t.collisions, 0, "{name}");
        assert!(
            t.min_coverage >= 0.90,
            "{name}: coverage {}",
            t.min_coverage
        );
    }
}

/// Zero collisions in the other arenas (when `../shared` is there) and in seeded mazes with
/// islands; their coverage is printed for the README's table.
#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "slow without optimisations: run with --release"
)]
fn acceptance_no_collisions_elsewhere() {
    for name in [
        "exploration_eval_arena.raf",
        "exploration_eval_arena_2.raf",
        "go2013_arena.raf",
        "rc_2015_arena_small.raf",
        "slam_lc_02.raf",
    ] {
        let Some(path) = shared_arena(name) else {
            continue;
        };
        let arena = load_raf(&path, &ArenaOptions::default()).unwrap();
        let start = arena_start(&arena.world);
        let t = runs(&format!("`{name}`"), &arena.world, start, 0..3);
        assert_eq!(t.collisions, 0, "{name}");
    }
    // The mazes the explorer's settings were chosen on, and twenty it has not seen.
    island_mazes("mazes 0-9", 0..10, 0..2);
    island_mazes("mazes 10-29 (held out)", 10..30, 0..1);
}

/// Runs seeded island mazes `mazes`, each with noise seeds `seeds`, asserting zero
/// collisions; prints one row per maze and one for all.
fn island_mazes(name: &str, mazes: std::ops::Range<u64>, seeds: std::ops::Range<u64>) {
    let mut all = Tally::new(format!(
        "{name} with 3+ islands (`--maze N --islands`), {}",
        if seeds.end - seeds.start == 1 {
            format!("seed {}", seeds.start)
        } else {
            format!("seeds {}-{}", seeds.start, seeds.end - 1)
        }
    ));
    for seed in mazes {
        let maze = generate(
            &MazeParams {
                islands: 3,
                ..MazeParams::default()
            },
            seed,
        );
        assert!(maze.islands >= 3);
        let t = runs(
            &format!("maze {seed} with islands"),
            &maze.world,
            maze.start,
            seeds.clone(),
        );
        assert_eq!(t.collisions, 0, "maze {seed}");
        all.runs += t.runs;
        all.collisions += t.collisions;
        all.min_coverage = all.min_coverage.min(t.min_coverage);
        all.mean_coverage += t.mean_coverage * t.runs as f64;
        all.max_pose_error = all.max_pose_error.max(t.max_pose_error);
        all.t90.extend(t.t90);
    }
    all.mean_coverage /= all.runs as f64;
    println!(
        "| {} | {} | {} | {:.3} | {:.3} | {} of {} runs reach 0.90 | {:.2} |",
        all.name,
        all.runs,
        all.collisions,
        all.min_coverage,
        all.mean_coverage,
        all.t90.len(),
        all.runs,
        all.max_pose_error,
    );
}

/// Says that `what` is skipped because `path` is absent, on the terminal even when the test
/// passes (libtest captures only `print!` and `eprint!`, not writes to the stream itself); in
/// CI (`LASERLINES_REQUIRE_SHARED=1`, where `../shared` is there) the absence fails instead.
fn skip_notice(path: &std::path::Path, what: &str) {
    use std::io::Write as _;
    let required = std::env::var_os("LASERLINES_REQUIRE_SHARED").is_some_and(|v| v == "1");
    assert!(
        !required,
        "{} is absent, and LASERLINES_REQUIRE_SHARED=1 requires it",
        path.display()
    );
    let _ = writeln!(
        std::io::stderr(),
        "notice: {} is absent; skipping {what}",
        path.display()
    );
}
