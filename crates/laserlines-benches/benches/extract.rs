//! Extraction speed, one scan at a time on one thread, with a reused extractor and buffer.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use laserlines::{HoughSplit, HoughSplitParams, LineExtractor};
use laserlines_benches::{bench_scan, real_scans};

fn hough_split(c: &mut Criterion) {
    let scan = bench_scan();
    let real = real_scans();
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap_or_else(|e| panic!("{e}"));
    let mut lines = Vec::new();
    let mut group = c.benchmark_group("hough-split");
    group.throughput(Throughput::Elements(1));
    group.bench_function("bench-scan", |b| {
        b.iter(|| hs.extract_into(black_box(&scan), &mut lines));
    });
    group.throughput(Throughput::Elements(real.len() as u64));
    group.bench_function("urg04lx-real", |b| {
        b.iter(|| {
            for s in &real {
                hs.extract_into(black_box(s), &mut lines);
            }
        });
    });
    group.finish();
}

criterion_group!(benches, hough_split);
criterion_main!(benches);
