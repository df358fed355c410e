//! Extraction speed of every extractor (`laserlines::extractors::ALGORITHMS`, default
//! parameters), one scan at a time on one thread, with a reused extractor and buffer: on the
//! standard bench scan and on the bundled real URG-04LX scans.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use laserlines::extractors::{self, ALGORITHMS};
use laserlines_benches::{bench_scan, real_scans};

fn extract(c: &mut Criterion) {
    let scan = bench_scan();
    let real = real_scans();
    let mut lines = Vec::new();
    for name in ALGORITHMS {
        let Some(mut e) = extractors::by_name(name) else {
            continue;
        };
        let mut group = c.benchmark_group(*name);
        group.throughput(Throughput::Elements(1));
        group.bench_function("bench-scan", |b| {
            b.iter(|| e.extract_into(black_box(&scan), &mut lines));
        });
        if !real.is_empty() {
            group.throughput(Throughput::Elements(real.len() as u64));
            group.bench_function("urg04lx-real", |b| {
                b.iter(|| {
                    for s in &real {
                        e.extract_into(black_box(s), &mut lines);
                    }
                });
            });
        }
        group.finish();
    }
}

criterion_group!(benches, extract);
criterion_main!(benches);
