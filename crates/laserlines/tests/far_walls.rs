//! A far wall seen beside a near one by a time-of-flight scanner whose noise does not grow
//! with the range: the noise estimate, read off the near wall, extrapolates its share of the
//! range to several centimetres at 25 m, but the far wall's points scatter by 1 cm, which
//! refuses that model for its line (`own_scatter`): its covariance is bounded by its own
//! scatter, and the line is kept.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::{Rng, nearest};
use laserlines::math::Point2;
use laserlines::{HoughSplit, HoughSplitParams, Line, LineExtractor, Scan};

/// A UTM-30LX-like scan (1081 beams of 0.25 deg over 270 deg, 30 m) of a 2.2 m wall on
/// x = 25 from y = 4 to 6.2 (19 beams at 9-14 deg; its `r` is 25 m, measured 5 m from the
/// wall, so a small error of its direction moves `r` five times as much) and of a wall at
/// x = -3 seen by 100 beams behind the scanner's left, each under 1 cm of noise.
fn scan(seed: u64) -> Scan {
    let (beams, inc) = (1081, 0.25f64.to_radians());
    let angle_min = -135f64.to_radians();
    let walls = [
        (Point2::new(25.0, 4.0), Point2::new(25.0, 6.2)),
        (Point2::new(-3.0, 0.5), Point2::new(-3.0, 12.0)),
    ];
    let mut rng = Rng(seed);
    let ranges = (0..beams)
        .map(|i| {
            let angle = angle_min + i as f64 * inc;
            nearest(angle, &walls).map_or(f64::NAN, |r| r + 0.01 * rng.gauss())
        })
        .collect();
    Scan::new(angle_min, inc, 0.02, 30.0, ranges).unwrap()
}

/// The line of the far wall, if any.
fn far_wall(lines: &[Line]) -> Option<&Line> {
    lines
        .iter()
        .find(|l| (l.r - 25.0).abs() < 0.05 && l.alpha.abs() < 3f64.to_radians())
}

#[test]
fn a_far_wall_beside_a_near_one_keeps_its_line() {
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
    let without = HoughSplitParams {
        own_scatter: false,
        ..HoughSplitParams::default()
    };
    let mut model_only = HoughSplit::new(without).unwrap();
    for seed in 0..10 {
        let s = scan(seed);
        let lines = hs.extract(&s);
        // The estimate reads the far wall's noise far above its 1 cm.
        let at_far = hs.stages().noise().sigma(25.0);
        assert!(at_far > 0.04, "seed {seed}: {at_far}");
        let far = far_wall(&lines);
        assert!(far.is_some(), "seed {seed}: {lines:?}");
        // Its `r` is known to a few centimetres (1 cm of noise over 19 points and a lever
        // arm of 5 m), where the model's noise gave it 15 cm and dropped the line.
        let sd = far.unwrap().covariance[(0, 0)].sqrt();
        assert!(sd < 0.05, "seed {seed}: {sd}");
        assert!(far_wall(&model_only.extract(&s)).is_none(), "seed {seed}");
    }
}
