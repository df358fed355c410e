//! Point-to-line ICP on simulated scans: known offsets recovered across the stated basin,
//! failure reported outside it.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use laserlines_sim::Rng;
use laserlines_slam::Se2;
use laserlines_slam::icp::{IcpParams, match_points};
use proptest::prelude::*;
use proptest::test_runner::TestCaseError;

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
    let r = match_points(
        &cloud,
        &common::surface(&scan),
        Se2::IDENTITY,
        None,
        &IcpParams::default(),
    )
    .unwrap();
    assert!(r.pose.distance(&truth) < 0.01, "{r:?}");
    assert!((r.pose.theta - truth.theta).abs() < 0.002, "{r:?}");
}

/// The stated convergence basin: guesses up to this far off converge.
const BASIN_M: f64 = 0.3;
const BASIN_RAD: f64 = 0.2;

/// True when both poses are well inside the room (0.4 m from everything).
fn free(x: f64, y: f64, dx: f64, dy: f64, yaw: f64) -> bool {
    let world = common::room();
    let b = Se2::new(x, y, yaw) * Se2::new(dx, dy, 0.0);
    world.clearance(laserlines::math::Point2::new(x, y)) > 0.4
        && world.clearance(laserlines::math::Point2::new(b.x, b.y)) > 0.4
}

fn offset_case(
    x: f64,
    y: f64,
    yaw: f64,
    dx: f64,
    dy: f64,
    dyaw: f64,
    seed: u64,
) -> (
    Se2,
    Result<laserlines_slam::IcpResult, laserlines_slam::IcpError>,
) {
    let world = common::room();
    let model = common::sick();
    let mut rng = Rng::new(seed);
    let a = Se2::new(x, y, yaw);
    let truth = Se2::new(dx, dy, dyaw);
    let ref_scan = common::scan_at(&world, a, &model, &mut rng);
    let scan = common::scan_at(&world, a * truth, &model, &mut rng);
    let cloud = common::cloud(&ref_scan, Se2::IDENTITY);
    // The guess is the reference pose itself: the whole offset is the error to recover.
    (
        truth,
        match_points(
            &cloud,
            &common::surface(&scan),
            Se2::IDENTITY,
            None,
            &IcpParams::default(),
        ),
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn recovers_any_offset_within_the_basin(
        x in -3.5..0.0f64, y in -2.0..2.0f64, yaw in -3.1..3.1f64,
        r in 0.0..BASIN_M, dir in -3.1..3.1f64, dyaw in -BASIN_RAD..BASIN_RAD, seed in 0u64..1000,
    ) {
        prop_assume!(free(x, y, r * dir.cos(), r * dir.sin(), yaw));
        let (truth, result) = offset_case(x, y, yaw, r * dir.cos(), r * dir.sin(), dyaw, seed);
        let m = result.map_err(|e| TestCaseError::fail(format!("{e}")))?;
        // Near the basin's edge a match can settle a few mrad off (5.4 mrad seen, kept in
        // icp.proptest-regressions): 2 cm and 10 mrad.
        prop_assert!(m.pose.distance(&truth) < 0.02, "{m:?} vs {truth:?}");
        prop_assert!((m.pose.theta - truth.theta).abs() < 0.01, "{m:?} vs {truth:?}");
    }

    #[test]
    fn outside_the_basin_fails_or_is_right(
        x in -3.5..0.0f64, y in -2.0..2.0f64, yaw in -3.1..3.1f64,
        r in BASIN_M..1.5f64, dir in -3.1..3.1f64, dyaw in BASIN_RAD..1.2f64, sign in proptest::bool::ANY, seed in 0u64..1000,
    ) {
        let dyaw = if sign { dyaw } else { -dyaw };
        prop_assume!(free(x, y, r * dir.cos(), r * dir.sin(), yaw));
        let (truth, result) = offset_case(x, y, yaw, r * dir.cos(), r * dir.sin(), dyaw, seed);
        if let Ok(m) = result {
            prop_assert!(m.pose.distance(&truth) < 0.02 && (m.pose.theta - truth.theta).abs() < 0.01,
                "a wrong pose was returned: {m:?} vs {truth:?}");
        }
    }
}
