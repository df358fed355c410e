//! Test helpers shared by the extractors' unit tests.

use super::breakpoints::Breakpoints;
use crate::math::Point2;
use crate::scan::ScanPoint;

/// Points at the given coordinates, as valid beams in order.
pub(crate) fn pts(xy: &[(f64, f64)]) -> Vec<ScanPoint> {
    xy.iter()
        .enumerate()
        .map(|(i, &(x, y))| ScanPoint {
            index: i,
            range: (x * x + y * y).sqrt(),
            angle: y.atan2(x),
            point: Point2::new(x, y),
        })
        .collect()
}

/// An L seen from the origin: wall x = 1 from y = -1 to the corner (1, 0.5), then wall
/// y = 0.5 back towards x = 0.2. Points every 0.05 m, corner at position `corner`.
pub(crate) fn l_shape() -> (Vec<ScanPoint>, usize) {
    let mut xy = Vec::new();
    for i in 0..=30 {
        xy.push((1.0, -1.0 + 0.05 * i as f64));
    }
    for i in 1..=16 {
        xy.push((1.0 - 0.05 * i as f64, 0.5));
    }
    (pts(&xy), 30)
}

/// A breakpoint rule loose enough for the L.
pub(crate) const RULE: Breakpoints = Breakpoints {
    incidence: 0.6,
    noise: 0.01,
    max_gap: 2,
};
