//! A fence at an open arena's bounds keeps the robot in it (`laserlines simulate --fence`).
//!
//! `rc_2015_arena_small` is a few rooms with gaps wider than a wall element: without a fence
//! the robot covers it, then follows a wall out and roams the empty floor around it until the
//! time limit, its pose estimate drifting by metres with no wall in range. With the fence at
//! the arena's bounds it explores the arena and stops. `rc_2015_arena_big` (bundled) is open at
//! its entrance: without a fence the robot leaves it early and sees 0.68 of it; with the fence
//! it sees 0.92-1.00 of it, 0.97 on average, and keeps within the bounds (seeds 0-7), though
//! the bounds hold a strip above its top-left walls that its outline counts as outside (see
//! the README).

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use laserlines::math::{Isometry2, Point2};
use laserlines_harness::{RunConfig, RunRecord, StopReason, arenas, run};
use laserlines_sim::World;
use laserlines_sim::arena::{ArenaOptions, ArenaOutline, load_raf};

fn explore(world: &World, start: Isometry2, fence: bool, seed: u64) -> RunRecord {
    let mut config = RunConfig {
        seed,
        ..RunConfig::default()
    };
    if fence {
        config.explorer.fence = arenas::fence_of(world, &start);
        assert!(config.explorer.fence.is_some());
    }
    run(world, start, &config).unwrap()
}

#[test]
fn a_fence_keeps_the_robot_in_the_small_open_arena() {
    let Some(path) = common::shared_arena("rc_2015_arena_small.raf") else {
        return;
    };
    let world = load_raf(&path, &ArenaOptions::default()).unwrap().world;
    let start = common::arena_start(&world);
    let free = explore(&world, start, false, 0);
    assert!(free.metrics.left_arena, "{:?}", free.metrics);
    for seed in 0..3 {
        let m = explore(&world, start, true, seed).metrics;
        assert_eq!(m.collisions, 0, "seed {seed}: {m:?}");
        assert!(!m.left_arena, "seed {seed}: {m:?}");
        assert!(m.coverage > 0.99, "seed {seed}: {m:?}");
        // Explored at 201-224 s.
        assert_eq!(m.stop, StopReason::Explored, "seed {seed}: {m:?}");
        assert!(m.sim_time_s < 300.0, "seed {seed}: {m:?}");
        assert!(m.max_pose_error_m < 0.2, "seed {seed}: {m:?}");
    }
}

#[test]
fn a_fence_keeps_the_robot_within_the_big_arenas_bounds() {
    const SEEDS: u64 = 16;
    let world = arenas::bundled("rc_2015_arena_big", &ArenaOptions::default())
        .unwrap()
        .unwrap()
        .world;
    let start = common::arena_start(&world);
    let (lo, hi) = ArenaOutline::new(&world).bounds().unwrap();
    // How far the true path strays beyond the bounds, m (negative: within them).
    let beyond = |path: &[Point2]| {
        path.iter()
            .map(|q| (lo.x - q.x).max(q.x - hi.x).max(lo.y - q.y).max(q.y - hi.y))
            .fold(f64::MIN, f64::max)
    };
    let free = explore(&world, start, false, 0);
    assert!(free.metrics.coverage < 0.75, "{:?}", free.metrics);
    // 34 m beyond the bounds without the fence.
    assert!(beyond(&free.path) > 5.0, "{:?}", free.metrics);
    // Which run loses its pose, and with it part of the arena, turns on details as small as a
    // line's end: sixteen seeds, the mean and the share of good runs asserted.
    let (mut coverage, mut inside) = (Vec::new(), 0);
    for seed in 0..SEEDS {
        let record = explore(&world, start, true, seed);
        let m = &record.metrics;
        assert_eq!(m.collisions, 0, "seed {seed}: {m:?}");
        // The fence holds in the robot's own estimate, which in this arena drifts by up to
        // a few metres: the true path keeps within the bounds grown by that drift (within
        // the bounds themselves in 14 of these 16 runs; 1.93 m beyond them in seed 1, whose
        // estimate drifted 3.93 m, and 1.87 m in seed 2, 2.81 m).
        let out = beyond(&record.path);
        println!(
            "seed {seed}: {:?} {:.1} coverage {:.3}, {:.2} m inside the bounds, pose error {:.2} m, left at {}",
            m.stop,
            m.sim_time_s,
            m.coverage,
            -out,
            m.max_pose_error_m,
            m.left_arena_at_s
                .map_or_else(|| "no time (stayed)".to_owned(), |t| format!("{t:.1} s"))
        );
        assert!(
            out < m.max_pose_error_m,
            "seed {seed}: {out} m beyond the bounds: {m:?}"
        );
        inside += usize::from(out < 0.0);
        coverage.push(m.coverage);
    }
    // Mean 0.948, 5 of 16 runs below 0.90 (0.68 without the fence). Over seeds 0-39 this
    // build gives 0.949 with 12 of 40 below 0.90, the extractor before the far ends of the
    // noise estimate and the cut of lone end points 0.957 with 8 of 40 (0.972 and none on
    // seeds 0-7, which this test once took alone).
    let mean = coverage.iter().sum::<f64>() / coverage.len() as f64;
    let good = coverage.iter().filter(|&&c| c >= 0.9).count();
    assert!(mean > 0.94 && good >= 10, "{coverage:?}");
    assert!(
        inside as u64 >= SEEDS * 3 / 4,
        "{inside} of {SEEDS} runs within the bounds"
    );
}
