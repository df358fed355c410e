//! A scanner of tens of thousands of beams per turn (a Pepperl+Fuchs R2000 gives 25 200 at
//! 0.014 deg): the beams along a wall lie millimetres apart, far closer than the range noise,
//! so the breakpoint distance `D` is almost all noise term (`bridge_sigmas` times sqrt 2
//! sigma). Among thousands of neighbouring pairs some differ by more than that by chance
//! alone (one pair in 370 at 3 sigma); each such lone jump must not cut the wall (the unit
//! tests of the segments check that a point well off the wall still does).

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::{Rng, hit};
use laserlines::math::{Point2, Vector2, angle_diff};
use laserlines::{HoughSplit, HoughSplitParams, Line, LineExtractor, Scan};

/// Beams per turn.
const BEAMS: usize = 20_000;

/// A 360 deg scan of `BEAMS` beams seeing only the wall `a`-`b`, with range noise
/// `max(sigma_min, fraction r)` along the beams.
fn wall_scan(a: Point2, b: Point2, sigma_min: f64, fraction: f64, rng: &mut Rng) -> Scan {
    let increment = std::f64::consts::TAU / BEAMS as f64;
    let angle_min = -std::f64::consts::PI;
    let ranges = (0..BEAMS)
        .map(|i| match hit(angle_min + i as f64 * increment, a, b) {
            Some(r) => r + sigma_min.max(fraction * r) * rng.gauss(),
            None => f64::INFINITY,
        })
        .collect();
    Scan::new(angle_min, increment, 0.1, 12.0, ranges).unwrap()
}

/// The normal form `(r, alpha)` of the line through `a` and `b`.
fn normal_form(a: Point2, b: Point2) -> (f64, f64) {
    let e = (b - a).normalize();
    let mut n = Vector2::new(e.y, -e.x);
    if n.dot(&a.coords) < 0.0 {
        n = -n;
    }
    (n.dot(&a.coords), n.y.atan2(n.x))
}

fn extract(scan: &Scan) -> Vec<Line> {
    HoughSplit::new(HoughSplitParams::default())
        .unwrap()
        .extract(scan)
}

#[test]
fn a_wall_seen_by_twenty_thousand_beams_under_one_percent_is_one_line() {
    // Before lone jumps were told from edges, these ten walls came out as 37 lines (up to 6
    // each).
    let mut rng = Rng(11);
    for wall in 0..10 {
        // 8 m walls 2 to 4 m away, turned every which way short of the scan's seam behind.
        let d = 2.0 + 0.2 * wall as f64;
        let turn = -1.8 + 0.4 * wall as f64;
        let (c, s) = (turn.cos(), turn.sin());
        let at = |x: f64, y: f64| Point2::new(c * x - s * y, s * x + c * y);
        let (a, b) = (at(d, -4.0), at(d + 0.5, 4.0));
        let scan = wall_scan(a, b, 0.01, 0.01, &mut rng);
        let lines = extract(&scan);
        assert_eq!(lines.len(), 1, "wall {wall}: {lines:?}");
        let (r, alpha) = normal_form(a, b);
        let line = &lines[0];
        assert!(
            (line.r - r).abs() < 0.01,
            "wall {wall}: {line:?} against r {r}"
        );
        assert!(
            angle_diff(line.alpha, alpha).abs() < 0.2f64.to_radians(),
            "wall {wall}: {line:?} against alpha {alpha}"
        );
        // It holds nearly every beam on the wall: a few lone jumps at most are left out.
        let on_wall = scan.ranges.iter().filter(|r| r.is_finite()).count();
        assert!(
            line.points + 20 >= on_wall,
            "wall {wall}: {line:?} of {on_wall}"
        );
    }
}
