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

/// One seeded case of the tests below: a pose in the room, then an offset `(r, direction,
/// dyaw)` drawn by `offset`, then the noise seed, in that order; `None` (drawn all the same)
/// when either pose lies within 0.4 m of something.
fn seeded_case(
    rng: &mut Rng,
    offset: impl FnOnce(&mut Rng) -> (f64, f64, f64),
) -> Option<(
    Se2,
    Result<laserlines_slam::IcpResult, laserlines_slam::IcpError>,
)> {
    let (x, y, yaw) = (
        rng.range(-3.5, 0.0),
        rng.range(-2.0, 2.0),
        rng.range(-3.1, 3.1),
    );
    let (r, dir, dyaw) = offset(rng);
    let seed = rng.next_u64() % 1000;
    let (dx, dy) = (r * dir.cos(), r * dir.sin());
    free(x, y, dx, dy, yaw).then(|| offset_case(x, y, yaw, dx, dy, dyaw, seed))
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
        // A match can settle a few mrad or centimetres off in a shallow minimum (5.4 mrad and
        // 3.0 cm seen, kept in icp.proptest-regressions; how rare, see
        // `nearly_every_offset_within_the_basin_is_recovered_within_2_cm`): 3.5 cm and 10 mrad.
        prop_assert!(m.pose.distance(&truth) < 0.035, "{m:?} vs {truth:?}");
        prop_assert!((m.pose.theta - truth.theta).abs() < 0.01, "{m:?} vs {truth:?}");
    }
}

/// How often a match within the basin settles beyond 2 cm or 10 mrad, over 30 000 seeded
/// cases: 4 (the worst 3.0 cm off; a refinement with a tighter pairing gate would take
/// such a match to the truth). 16 s in a release build, about 30 s in the test build.
#[test]
fn nearly_every_offset_within_the_basin_is_recovered_within_2_cm() {
    let mut rng = Rng::new(777);
    let (mut cases, mut failed, mut beyond, mut worst) = (0, 0, 0, 0.0f64);
    while cases < 30_000 {
        let Some(case) = seeded_case(&mut rng, |rng| {
            let (r, dir) = (rng.range(0.0, BASIN_M), rng.range(-3.1, 3.1));
            (r, dir, rng.range(-BASIN_RAD, BASIN_RAD))
        }) else {
            continue;
        };
        cases += 1;
        match case {
            (_, Err(_)) => failed += 1,
            (truth, Ok(m)) => {
                let d = m.pose.distance(&truth);
                beyond += usize::from(d > 0.02 || (m.pose.theta - truth.theta).abs() > 0.01);
                worst = worst.max(d);
            }
        }
    }
    println!("{cases} cases: {failed} errors, {beyond} beyond 2 cm or 10 mrad, worst {worst:.4} m");
    assert_eq!(failed, 0);
    assert_eq!(beyond, 4);
    assert!(worst < 0.031, "{worst}");
}

/// From outside the basin (0.3-1.5 m and 0.2-1.2 rad off) the matcher fails or finds the true
/// pose, never a wrong one, over 1000 seeded cases (counts printed; today all 1000 fail). With the gate on the match's move at 0.5 m and 0.35 rad instead of 0.35 m and
/// 0.25 rad, 1 of the first 300 was a wrong pose between a room's parallel walls.
#[test]
fn outside_the_basin_no_wrong_pose() {
    let mut rng = Rng::new(20_260_101);
    let (mut cases, mut right, mut failed, mut wrong) = (0, 0, 0, 0);
    while cases < 1000 {
        let Some((truth, result)) = seeded_case(&mut rng, |rng| {
            let (r, dir) = (rng.range(BASIN_M, 1.5), rng.range(-3.1, 3.1));
            let dyaw = rng.range(BASIN_RAD, 1.2) * if rng.chance(0.5) { 1.0 } else { -1.0 };
            (r, dir, dyaw)
        }) else {
            continue;
        };
        cases += 1;
        match result {
            Err(_) => failed += 1,
            Ok(m)
                if m.pose.distance(&truth) < 0.02 && (m.pose.theta - truth.theta).abs() < 0.01 =>
            {
                right += 1;
            }
            Ok(m) => {
                wrong += 1;
                println!("wrong: {m:?}, truth {truth:?}");
            }
        }
    }
    println!("outside the basin: {cases} cases, {right} right, {failed} failed, {wrong} wrong");
    assert_eq!(wrong, 0, "{wrong} wrong poses in {cases} cases");
}
