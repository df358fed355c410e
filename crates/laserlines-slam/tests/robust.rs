//! Any input: the mapper never panics, whatever the scans, lines and odometry.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines::{HoughSplit, HoughSplitParams, LineExtractor, Scan};
use laserlines_slam::{Mapper, MapperParams, Se2};
use proptest::prelude::*;

fn range() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => 0.05..12.0f64,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(-1.0),
        1 => Just(0.0),
        1 => Just(1e12),
    ]
}

fn odometry() -> impl Strategy<Value = Option<Se2>> {
    prop_oneof![
        3 => (-5.0..5.0f64, -5.0..5.0f64, -4.0..4.0f64).prop_map(|(x, y, t)| Some(Se2::new(x, y, t))),
        1 => Just(None),
        1 => Just(Some(Se2 { x: f64::NAN, y: 0.0, theta: 0.0 })),
        1 => Just(Some(Se2::new(1e15, -1e15, 0.0))),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn the_mapper_takes_any_scans_without_panicking(
        scans in proptest::collection::vec(
            (proptest::collection::vec(range(), 0..200), -3.2..0.0f64, prop_oneof![Just(0.01f64), Just(-0.02), Just(0.1)], odometry()),
            1..12,
        ),
    ) {
        let mut mapper = Mapper::new(MapperParams::default());
        let mut hs = HoughSplit::new(HoughSplitParams::mapping()).unwrap();
        let mut lines = Vec::new();
        let mut added = 0;
        for (ranges, angle_min, inc, odom) in scans {
            let Ok(scan) = Scan::new(angle_min, inc, 0.02, 30.0, ranges) else { continue };
            hs.extract_into(&scan, &mut lines);
            match mapper.add_scan(&scan, &lines, odom) {
                Ok(update) => {
                    prop_assert_eq!(update.node, added);
                    prop_assert!(update.pose.is_finite());
                    added += 1;
                }
                // Refused scans leave the mapper as it was.
                Err(_) => prop_assert!(odom.is_some_and(|o| !o.is_finite())),
            }
            prop_assert_eq!(mapper.poses().len(), added);
            prop_assert_eq!(mapper.scans().len(), added);
        }
        let _ = mapper.optimize();
        let _ = mapper.occupancy_grid(&Default::default());
        let _ = mapper.line_map(&Default::default());
    }
}
