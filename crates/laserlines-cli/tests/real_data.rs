//! HoughSplit on every scan of the real BreezySLAM URG-04LX runs (the paper's sensor): with
//! the `complete` preset, lines from nearly every scan (a few sparse scans, with a few dozen
//! valid beams in short runs, hold no surface of 0.15 m), a plausible number per scan; with
//! the defaults, whose gates keep only lines known to 6 cm and 3 deg, a few more scans hold
//! no such line (exp1: 7 of 756, exp2: 17 of 641, where the robot sees short pieces of wall
//! at glancing angles).
//! Skips with a notice when the shared data folder is absent.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::PathBuf;

use laserlines::{HoughSplit, HoughSplitParams, LineExtractor};

mod common;
use common::shared_data;

fn shared(rel: &str) -> Option<PathBuf> {
    shared_data::available(shared_data::path("real").join(rel), "the real-data test")
}

#[test]
fn every_breezyslam_scan_gives_lines() {
    for (file, expected) in [("exp1.dat.gz", 756usize), ("exp2.dat.gz", 641)] {
        let Some(path) = shared(&format!("breezyslam-urg04lx/{file}")) else {
            return;
        };
        for (params, most_empty) in [
            (HoughSplitParams::complete(), 3),
            (HoughSplitParams::default(), 5),
        ] {
            check_run(&path, file, expected, params, most_empty);
        }
    }
}

/// Lines of every scan of `path` (`expected` scans) with `params`: at most `most_empty` % of
/// the scans without a line, 3 to 40 lines per scan on average, and every line at least
/// `min_line_length` long and running the way its beams do.
fn check_run(
    path: &std::path::Path,
    file: &str,
    expected: usize,
    params: HoughSplitParams,
    most_empty: usize,
) {
    let reader = laserlines_io::open(path, None).unwrap();
    let min_length = params.min_line_length;
    let mut hs = HoughSplit::new(params).unwrap();
    let mut lines = Vec::new();
    let (mut scans, mut total, mut empty) = (0usize, 0usize, 0usize);
    for rec in reader {
        let rec = rec.unwrap();
        hs.extract_into(&rec.scan, &mut lines);
        let point = |i: usize| {
            let (r, a) = (rec.scan.ranges[i], rec.scan.angle(i));
            laserlines::math::Vector2::new(r * a.cos(), r * a.sin())
        };
        for l in &lines {
            assert!(l.length() >= min_length, "{file} scan {scans}: {l:?}");
            let beams = point(l.last) - point(l.first);
            assert!(
                (l.end - l.start).dot(&beams) > 0.0,
                "{file} scan {scans}: a line reversed against its beams: {l:?}"
            );
        }
        empty += usize::from(lines.is_empty());
        scans += 1;
        total += lines.len();
    }
    assert_eq!(scans, expected, "{file}");
    let mean = total as f64 / scans as f64;
    println!("{file}: {scans} scans, {mean:.1} lines per scan, {empty} without a line");
    assert!(
        empty * 100 <= most_empty * scans,
        "{file}: {empty} scans without a line"
    );
    assert!(
        (3.0..=40.0).contains(&mean),
        "{file}: {mean} lines per scan"
    );
}
