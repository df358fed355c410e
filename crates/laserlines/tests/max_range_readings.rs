//! Drivers that clamp write the range limit itself for a beam that saw nothing within range
//! (the ROS driver of the SICK LMS1xx by default, Gazebo's classic laser plugin). Taken as
//! points, those readings lie on a circle around the sensor, which every extractor cut into
//! chords: lines across the open side of a room, a corridor's far end or a doorway. A
//! reading of `range_max` is no return, as `+inf` is, and so, where many beams read the
//! limit, is a band under it where a simulator's noise put the rest of its clamped
//! readings: every extractor gives the same lines for both, and none at the limit.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::{Rng, hit, nearest};
use laserlines::math::Point2;
use laserlines::registry::{self, ALGORITHMS};
use laserlines::{Line, Scan};

/// A scanner: beams, increment, limit (which it writes for no return, with noise of
/// `clamped_sigma` added before it is clamped to the limit), and its noise.
struct Scanner {
    beams: usize,
    increment_deg: f64,
    range_max: f64,
    clamped_sigma: f64,
    sigma: f64,
}

/// A URG-04LX (682 beams of 360/1024 deg, 5.6 m) and a SICK LMS111 (541 of 0.5 deg, 20 m),
/// both writing their limit, and a simulated URG-04LX as Gazebo's classic plugin gives it
/// (1 cm of noise on every beam, then clamped to the limit: half of the beams that hit
/// nothing read 5.6 m, the others a little less).
const SCANNERS: [Scanner; 3] = [
    Scanner {
        beams: 682,
        increment_deg: 360.0 / 1024.0,
        range_max: 5.6,
        clamped_sigma: 0.0,
        sigma: 0.004,
    },
    Scanner {
        beams: 541,
        increment_deg: 0.5,
        range_max: 20.0,
        clamped_sigma: 0.0,
        sigma: 0.012,
    },
    Scanner {
        beams: 682,
        increment_deg: 360.0 / 1024.0,
        range_max: 5.6,
        clamped_sigma: 0.01,
        sigma: 0.01,
    },
];

/// A room open ahead (walls at y = -1.4 and y = 1.1 from x = -0.8 to 3, a back wall at
/// x = -0.8, a 0.9 m doorway in the left wall from x = 1 to 1.9), seen by `s` from the
/// origin under its noise; a beam that hits nothing reads as the scanner writes it when
/// `clamped`, else `+inf`.
fn scan(s: &Scanner, seed: u64, clamped: bool) -> Scan {
    let walls = [
        (Point2::new(-0.8, -1.4), Point2::new(3.0, -1.4)),
        (Point2::new(-0.8, 1.1), Point2::new(1.0, 1.1)),
        (Point2::new(1.9, 1.1), Point2::new(3.0, 1.1)),
        (Point2::new(-0.8, -1.4), Point2::new(-0.8, 1.1)),
    ];
    let inc = s.increment_deg.to_radians();
    let angle_min = -0.5 * (s.beams - 1) as f64 * inc;
    let mut rng = Rng(seed);
    let mut nothing = Rng(seed + 1000);
    let mut no_return = || {
        let r = s.range_max + s.clamped_sigma * nothing.gauss();
        if clamped {
            r.min(s.range_max)
        } else {
            f64::INFINITY
        }
    };
    let ranges = (0..s.beams)
        .map(|i| {
            let angle = angle_min + i as f64 * inc;
            nearest(angle, &walls).map_or_else(&mut no_return, |r| r + s.sigma * rng.gauss())
        })
        .collect();
    Scan::new(angle_min, inc, 0.02, s.range_max, ranges).unwrap()
}

#[test]
fn readings_of_the_range_limit_are_no_return_for_every_extractor() {
    for s in &SCANNERS {
        for name in ALGORITHMS {
            let mut clamped = registry::by_name(name).unwrap();
            let mut reference = registry::by_name(name).unwrap();
            for seed in 0..5 {
                let lines: Vec<Line> = clamped.extract(&scan(s, seed, true));
                let expected = reference.extract(&scan(s, seed, false));
                let limit = s.range_max;
                // The walls are within 3.5 m; a chord of the limit's circle lies beyond 5 m.
                let at_limit = lines.iter().filter(|l| l.r > 5.0).count();
                assert_eq!(at_limit, 0, "{name}, {limit} m, seed {seed}: {lines:?}");
                assert_eq!(lines, expected, "{name}, {limit} m, seed {seed}");
                assert!(!lines.is_empty(), "{name}, {limit} m, seed {seed}");
            }
        }
    }
}

#[test]
fn a_reading_just_below_the_limit_is_still_a_point() {
    // The window keeps every reading below the limit: a wall 5.59 m away, 1 cm short of a
    // URG-04LX's limit, is one line.
    let (beams, inc) = (682, (360.0f64 / 1024.0).to_radians());
    let angle_min = -0.5 * (beams - 1) as f64 * inc;
    let ranges: Vec<f64> = (0..beams)
        .map(|i| {
            let angle = angle_min + i as f64 * inc;
            hit(angle, Point2::new(5.59, -0.4), Point2::new(5.59, 0.4))
                .map_or(f64::NAN, |r| r.min(5.6f64.next_down()))
        })
        .collect();
    let s = Scan::new(angle_min, inc, 0.02, 5.6, ranges).unwrap();
    let window = s.range_window(None);
    assert!(window.contains(5.6f64.next_down()) && !window.contains(5.6));
    let mut hs = registry::by_name("hough-split").unwrap();
    let lines = hs.extract(&s);
    assert_eq!(lines.len(), 1, "{lines:?}");
    assert!((lines[0].r - 5.59).abs() < 0.01, "{lines:?}");
}
