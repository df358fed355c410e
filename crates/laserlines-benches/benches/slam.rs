//! Mapping speed (`laserlines-slam`) on the bundled real URG-04LX excerpt (40 scans with
//! wheel odometry), one thread: one point-to-line ICP match of a scan onto the one before,
//! and the whole excerpt through the `Mapper` (matching, submaps, loop search, a final
//! optimisation), with the lines `laserlines map` extracts (`HoughSplitParams::mapping`).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use laserlines::{HoughSplit, HoughSplitParams, LineExtractor};
use laserlines_slam::cloud::{PointCloud, SurfacePoint, scan_surface};
use laserlines_slam::icp::{IcpParams, match_points};
use laserlines_slam::{Mapper, MapperParams, Se2};

fn surface(scan: &laserlines::Scan) -> Vec<SurfacePoint> {
    scan_surface(scan, scan.range_window(None), 3)
}

fn slam(c: &mut Criterion) {
    let Ok(records) = laserlines_io::demo::urg04lx_excerpt() else {
        return;
    };
    let mut hs = match HoughSplit::new(HoughSplitParams::mapping()) {
        Ok(hs) => hs,
        Err(_) => return,
    };
    let lines: Vec<Vec<laserlines::Line>> = records
        .iter()
        .map(|r| {
            let mut l = Vec::new();
            hs.extract_into(&r.scan, &mut l);
            l
        })
        .collect();
    let mut group = c.benchmark_group("slam");
    // One match: scan 21 onto scan 20, seeded by the odometry.
    let (a, b) = (&records[20], &records[21]);
    let mut cloud = PointCloud::new(0.03, 0.2);
    for p in surface(&a.scan) {
        cloud.insert(p);
    }
    let query = surface(&b.scan);
    let pose = |r: &laserlines_io::ScanRecord| {
        r.pose
            .map_or(Se2::IDENTITY, |p| Se2::new(p.x, p.y, p.theta))
    };
    let guess = pose(a).between(&pose(b));
    group.throughput(Throughput::Elements(1));
    group.bench_function("icp-scan-to-scan", |bch| {
        bch.iter(|| {
            match_points(
                black_box(&cloud),
                black_box(&query),
                guess,
                None,
                &IcpParams::default(),
            )
        })
    });
    group.throughput(Throughput::Elements(records.len() as u64));
    group.bench_function("mapper-excerpt", |bch| {
        bch.iter(|| {
            let mut mapper = Mapper::new(MapperParams::default());
            for (r, l) in records.iter().zip(&lines) {
                let _ = mapper.add_scan(&r.scan, l, Some(pose(r)));
            }
            let _ = mapper.optimize();
            black_box(mapper.poses().len())
        })
    });
    group.finish();
}

criterion_group!(benches, slam);
criterion_main!(benches);
