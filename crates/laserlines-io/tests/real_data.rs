//! Both BreezySLAM runs (`../shared/data/real/breezyslam-urg04lx`) read completely, with the
//! counts PROVENANCE.md states. Skipped, with a notice, when that folder is absent.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers outside #[test] fns

use std::path::PathBuf;

use laserlines_io::{ScanRecord, open};

#[path = "../../../tests/shared_data.rs"]
mod shared_data;

fn real_dir() -> Option<PathBuf> {
    let dir = shared_data::path("real/breezyslam-urg04lx");
    shared_data::available(dir.join("exp1.dat.gz"), "the real BreezySLAM data test")?;
    Some(dir)
}

fn read_run(name: &str) -> Option<Vec<ScanRecord>> {
    let path = real_dir()?.join(name);
    let mut reader = open(&path, None).unwrap();
    let records: Vec<ScanRecord> = reader.by_ref().map(|r| r.unwrap()).collect();
    assert!(reader.skipped().is_empty(), "{}", reader.skipped());
    Some(records)
}

/// Beam shift `s` minimising the mean |r_next(i) - r_prev(i + s)| over beams valid in both.
fn best_shift(prev: &ScanRecord, next: &ScanRecord) -> Option<i64> {
    let w = prev.scan.range_window(None);
    let n = prev.scan.len() as i64;
    let mut best: Option<(f64, i64)> = None;
    for s in -40..=40 {
        let (mut sum, mut count) = (0.0, 0usize);
        for i in 0..n {
            let j = i + s;
            if !(0..n).contains(&j) {
                continue;
            }
            let (a, b) = (next.scan.ranges[i as usize], prev.scan.ranges[j as usize]);
            if w.contains(a) && w.contains(b) {
                sum += (a - b).abs();
                count += 1;
            }
        }
        if count > 100 {
            let cost = sum / count as f64;
            if best.is_none_or(|(c, _)| cost < c) {
                best = Some((cost, s));
            }
        }
    }
    best.map(|(_, s)| s)
}

fn check_run(name: &str, scans: usize, valid: usize) {
    let Some(records) = read_run(name) else {
        return;
    };
    assert_eq!(records.len(), scans, "{name}");
    for r in &records {
        assert_eq!(r.scan.len(), 682, "{name}:{:?}", r.line);
        assert!(r.pose.unwrap().is_finite());
    }
    for w in records.windows(2) {
        assert!(
            w[1].scan.stamp.unwrap() > w[0].scan.stamp.unwrap(),
            "{name}:{:?}",
            w[1].line
        );
    }
    // Ranges: everything but 0 (no echo) and 1..19 mm (error codes) is a measurement.
    let n_valid: usize = records
        .iter()
        .map(|r| r.scan.count_valid(r.scan.range_window(None)))
        .sum();
    assert_eq!(n_valid, valid, "{name}");

    // Odometry against the scans: when the wheels say the robot turned, the range profile
    // turns the other way by about as many beams (robot turns left by d, the scene appears
    // d to the right, i.e. next(i) = prev(i + d / increment)).
    let inc = records[0].scan.angle_increment;
    let (mut agree, mut turns, mut errs, mut ratios) = (0, 0, Vec::new(), Vec::new());
    for w in records.windows(2) {
        let (p0, p1) = (w[0].pose.unwrap(), w[1].pose.unwrap());
        let dtheta = laserlines::math::wrap_angle(p1.theta - p0.theta);
        if dtheta.abs() < 3f64.to_radians() {
            continue;
        }
        let Some(s) = best_shift(&w[0], &w[1]) else {
            continue;
        };
        turns += 1;
        let odo_beams = dtheta / inc;
        if s != 0 && (s > 0) == (odo_beams > 0.0) {
            agree += 1;
        }
        errs.push((s as f64 - odo_beams).abs());
        ratios.push(s as f64 / odo_beams);
    }
    errs.sort_by(f64::total_cmp);
    ratios.sort_by(f64::total_cmp);
    let median_err = errs.get(errs.len() / 2).copied().unwrap_or(f64::NAN);
    let median_ratio = ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN);
    eprintln!(
        "{name}: {turns} turns of 3+ deg; {agree} agree in sign with the scan shift; median \
         shift / odometry {median_ratio:.2}, median |shift - odometry| {median_err:.1} beams"
    );
    // The shift estimate is crude (it ignores the robot's translation), so this checks the
    // sign convention and the scale (a factor 2 either way fails), not the precision.
    assert!(turns >= 50, "{name}: only {turns} turns");
    assert!(
        agree * 5 >= turns * 4,
        "{name}: {agree} of {turns} turns agree in sign"
    );
    assert!(
        (0.55..=1.35).contains(&median_ratio),
        "{name}: median shift / odometry {median_ratio}"
    );
}

#[test]
fn exp1_reads_completely() {
    // PROVENANCE.md: 515,592 values, 270,547 zeros, 14,375 error codes.
    check_run("exp1.dat.gz", 756, 515_592 - 270_547 - 14_375);
}

#[test]
fn exp2_reads_completely() {
    // PROVENANCE.md: 437,162 values, 241,623 zeros, 10,789 error codes.
    check_run("exp2.dat.gz", 641, 437_162 - 241_623 - 10_789);
}
