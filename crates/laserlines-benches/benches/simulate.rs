//! Simulation speed of a navigation run: the laser at 10 Hz, line extraction of every scan,
//! the explorer (sector objects, scan matching and its own map, frontier planning, the
//! safety layer), physics at 50 Hz and the coverage evaluation, one thread.
//!
//! One iteration is 60 s of simulated time in the bundled arena `inner_explore_test.raf`;
//! criterion's throughput is simulated seconds per wall-clock second (the real-time factor).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use laserlines::math::Isometry2;
use laserlines_nav::{RunConfig, arenas, run};
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
    group.finish();
}

criterion_group!(benches, simulate);
criterion_main!(benches);
