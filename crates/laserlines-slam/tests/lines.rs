//! Line-to-line matching on the extractor's lines of simulated URG-04LX scans.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use laserlines::{HoughSplit, HoughSplitParams, LineExtractor};
use laserlines_sim::{LaserModel, Rng};
use laserlines_slam::Se2;
use laserlines_slam::lines::{LineMatchParams, match_lines};

#[test]
fn lines_of_two_scans_give_their_relative_pose() {
    let world = common::room();
    let model = LaserModel::urg04lx();
    let mut hs = HoughSplit::new(HoughSplitParams::mapping()).unwrap();
    for (seed, (a, truth)) in [
        (Se2::new(-1.0, 0.0, 0.1), Se2::new(0.15, -0.1, 0.05)),
        (Se2::new(2.0, -1.0, 2.0), Se2::new(-0.1, 0.2, -0.12)),
        (Se2::new(-3.0, 1.0, -1.0), Se2::new(0.25, 0.0, 0.1)),
    ]
    .into_iter()
    .enumerate()
    {
        let mut rng = Rng::new(seed as u64);
        let (mut la, mut lb) = (Vec::new(), Vec::new());
        hs.extract_into(&common::scan_at(&world, a, &model, &mut rng), &mut la);
        hs.extract_into(
            &common::scan_at(&world, a * truth, &model, &mut rng),
            &mut lb,
        );
        let m = match_lines(&la, &lb, Se2::IDENTITY, &LineMatchParams::default()).unwrap();
        assert!(m.pairs >= 3, "{m:?}");
        assert!(m.pose.distance(&truth) < 0.02, "{m:?} vs {truth:?}");
        assert!(
            (m.pose.theta - truth.theta).abs() < 0.005,
            "{m:?} vs {truth:?}"
        );
    }
}

#[test]
fn one_wall_does_not_fix_a_pose() {
    // A single line leaves the translation along it free: no answer rather than a guess.
    let mut hs = HoughSplit::new(HoughSplitParams::mapping()).unwrap();
    let inc = 0.5_f64.to_radians();
    let ranges: Vec<f64> = (0..121)
        .map(|i| 2.0 / (-std::f64::consts::FRAC_PI_6 + f64::from(i) * inc).cos())
        .collect();
    let scan = laserlines::Scan::new(-std::f64::consts::FRAC_PI_6, inc, 0.02, 5.6, ranges).unwrap();
    let mut l = Vec::new();
    hs.extract_into(&scan, &mut l);
    assert_eq!(l.len(), 1);
    assert!(match_lines(&l, &l, Se2::IDENTITY, &LineMatchParams::default()).is_none());
}
