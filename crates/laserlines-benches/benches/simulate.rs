//! Simulation speed of a navigation run: the laser at 10 Hz, line extraction of every scan,
//! the explorer (sector objects, scan matching and its own map, frontier planning, the
//! safety layer), physics at 50 Hz and the coverage evaluation, one thread.
//!
//! `inner_explore_test-60s`: one iteration is the first 60 s of simulated time in the bundled
//! arena `inner_explore_test.raf`. `maze_10m_x_14m-whole`: one whole exploration of the
//! bundled `maze_10m_x_14m.raf` (seed 0, until the explorer finds no frontier left: 603 s of
//! simulated time). Criterion's throughput is simulated seconds per wall-clock second (the
//! real-time factor).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use laserlines::math::Isometry2;
use laserlines_harness::{RunConfig, arenas, run};
use laserlines_sim::arena::ArenaOptions;

fn simulate(c: &mut Criterion) {
    let arena = arenas::bundled("inner_explore_test", &ArenaOptions::default())
        .and_then(Result::ok)
        .unwrap_or_else(|| panic!("the bundled arena loads"));
    let config = RunConfig {
        duration_s: 60.0,
        seed: 1,
        record_lines_every: 0,
        ..RunConfig::default()
    };
    let mut group = c.benchmark_group("simulate");
    group.sample_size(10);
    group.throughput(Throughput::Elements(60));
    group.bench_function("inner_explore_test-60s", |b| {
        b.iter(|| {
            let r = run(black_box(&arena.world), Isometry2::identity(), &config)
                .unwrap_or_else(|e| panic!("{e}"));
            black_box(r.metrics.coverage)
        });
    });
    let maze = arenas::bundled("maze_10m_x_14m", &ArenaOptions::default())
        .and_then(Result::ok)
        .unwrap_or_else(|| panic!("the bundled arena loads"));
    let whole = RunConfig {
        seed: 0,
        record_lines_every: 0,
        ..RunConfig::default()
    };
    // The simulated time of the whole run, for the throughput.
    let sim_s = run(&maze.world, Isometry2::identity(), &whole)
        .unwrap_or_else(|e| panic!("{e}"))
        .metrics
        .sim_time_s;
    group.throughput(Throughput::Elements(sim_s.round() as u64));
    group.bench_function("maze_10m_x_14m-whole", |b| {
        b.iter(|| {
            let r = run(black_box(&maze.world), Isometry2::identity(), &whole)
                .unwrap_or_else(|e| panic!("{e}"));
            black_box(r.metrics.coverage)
        });
    });
    group.finish();
}

criterion_group!(benches, simulate);
criterion_main!(benches);
