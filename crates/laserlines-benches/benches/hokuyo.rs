//! The Hokuyo path at UST-10LX size (1081 beams): from the last byte of a scan to its
//! lines with `hough-split`, on one core.
//!
//! - `decode+extract/ust10lx-bytes`: one scan message as the emulator sends it (the
//!   simulated UST-10LX in the bundled arena `maze_10m_x_14m`), parsed, checked, decoded
//!   into a `Scan` and extracted;
//! - `tcp/ust10lx-last-byte-to-lines`: the driver reading the emulator over local TCP
//!   (streaming as fast as it can, 1000 scans/s), timed from the moment the scan's last
//!   byte was read to its lines.

use std::hint::black_box;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use laserlines::{HoughSplit, HoughSplitParams, LineExtractor, Scan};
use laserlines_hokuyo::emulator::{
    Emulator, Faults, Model, ModelName, ScanFeed, ServedLog, scan_message,
};
use laserlines_hokuyo::reply::Reply;
use laserlines_hokuyo::{Endpoint, Scanner, ScannerOptions};
use laserlines_hokuyo_emulator::ArenaFeed;
use laserlines_sim::arena::{ArenaOptions, interior_start};

fn arena_feed() -> ArenaFeed {
    let arena = laserlines_harness::arenas::bundled("maze_10m_x_14m", &ArenaOptions::default())
        .and_then(Result::ok)
        .map(|a| a.world)
        .unwrap_or_default();
    let start = interior_start(&arena, 0.5).unwrap_or_default();
    ArenaFeed::new(&arena, start, 1)
}

fn hokuyo(c: &mut Criterion) {
    let model = Model::new(ModelName::Ust10lx);
    let mut feed = arena_feed();
    let values = feed.next_scan(&model);
    let message = scan_message(
        b"MD0000108001000",
        b"99",
        123_456,
        &values,
        laserlines_hokuyo::codec::Encoding::Three,
    );
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap_or_else(|_| unreachable!());
    let mut lines = Vec::new();
    let mut decoded = Vec::new();
    let step = std::f64::consts::TAU / 1440.0;
    let mut group = c.benchmark_group("decode+extract");
    group.throughput(Throughput::Elements(1));
    group.bench_function("ust10lx-bytes", |b| {
        b.iter(|| {
            let r = Reply::parse_unchecked(black_box(&message)).unwrap_or_else(|_| unreachable!());
            let ok = r
                .check_scan_layout(laserlines_hokuyo::codec::Encoding::Three, 1081)
                .is_ok()
                && r.verify_data().is_ok();
            let _ = r.scan_into(
                laserlines_hokuyo::codec::Encoding::Three,
                1081,
                &mut decoded,
            );
            let scan = Scan {
                angle_min: -540.0 * step,
                angle_increment: step,
                range_min: 0.02,
                range_max: 10.0,
                ranges: decoded.iter().map(|&mm| f64::from(mm) / 1000.0).collect(),
                intensities: None,
                stamp: Some(0.0),
            };
            hs.extract_into(&scan, &mut lines);
            black_box((ok, lines.len()))
        });
    });
    group.finish();

    let mut fast = Model::new(ModelName::Ust10lx);
    fast.scan_rpm = 60_000;
    let Ok(emulator) = Emulator::new(
        fast,
        Box::new(arena_feed()),
        Faults::default(),
        ServedLog::default(),
    )
    .serve_tcp("127.0.0.1:0") else {
        return;
    };
    let Some(Ok(endpoint)) = emulator
        .local_addr()
        .map(|a| a.to_string().parse::<Endpoint>())
    else {
        return;
    };
    let Ok(mut scanner) = Scanner::open(&endpoint, ScannerOptions::default()) else {
        return;
    };
    let stop = AtomicBool::new(false);
    let mut group = c.benchmark_group("tcp");
    group.throughput(Throughput::Elements(1));
    group.bench_function("ust10lx-last-byte-to-lines", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let Some(s) = scanner.next_scan(&stop) else {
                    break;
                };
                hs.extract_into(&s.scan, &mut lines);
                total += Instant::now().saturating_duration_since(s.received);
            }
            total
        });
    });
    group.finish();
    eprintln!(
        "hokuyo bench: dropped {}, reconnects {}",
        scanner.stats().dropped,
        scanner.stats().reconnects
    );
    let _ = scanner.close();
    let _ = emulator.stop();
}

criterion_group!(benches, hokuyo);
criterion_main!(benches);
