//! Inputs shared by the benchmarks of every extractor: the standard bench scan and real
//! URG-04LX scans.

use laserlines::Scan;

/// The standard bench scan: 682 beams from -120 deg by 0.352 deg, a 4 m x 6 m room with a
/// rotated box, 10 mm gaussian noise rounded to 1 mm, fixed seed; six visible wall pieces.
#[must_use]
pub fn bench_scan() -> Scan {
    laserlines_sim::bench_scan().scan
}

/// The real Hokuyo URG-04LX scans bundled with laserlines (BreezySLAM exp1 excerpt).
///
/// # Panics
/// Never in practice: the bundled data is checked by the tests of `laserlines-io`.
#[must_use]
pub fn real_scans() -> Vec<Scan> {
    laserlines_io::demo::urg04lx_excerpt()
        .map(|records| records.into_iter().map(|r| r.scan).collect())
        .unwrap_or_default()
}
