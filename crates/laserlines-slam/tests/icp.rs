//! Point-to-line ICP on simulated scans: known offsets recovered across the stated basin,
//! failure reported outside it.

mod common;

use laserlines_sim::Rng;
use laserlines_slam::Se2;
use laserlines_slam::icp::{IcpParams, match_points};
use proptest::prelude::*;

#[test]
fn recovers_a_known_offset() {
    let world = common::room();
    let model = common::sick();
    let mut rng = Rng::new(1);
    let a = Se2::new(-1.0, 0.0, 0.1);
    let truth = Se2::new(0.2, -0.1, 0.08);
    let b = a * truth;
    let ref_scan = common::scan_at(&world, a, &model, &mut rng);
    let scan = common::scan_at(&world, b, &model, &mut rng);
    let cloud = common::cloud(&ref_scan, Se2::IDENTITY);
    let r = match_points(&cloud, &common::surface(&scan), Se2::IDENTITY, None, &IcpParams::default()).unwrap();
    assert!(r.pose.distance(&truth) < 0.01, "{r:?}");
    assert!((r.pose.theta - truth.theta).abs() < 0.002, "{r:?}");
}
