//! A corridor's wall with recessed doors, seen along the corridor: the few beams that reach
//! into each recess see through the wall's line, which must not run on across the doorway
//! (a line across empty space), while the plain wall opposite stays one line.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::{Rng, hit};
use laserlines::math::Point2;
use laserlines::{HoughSplit, HoughSplitParams, Line, LineExtractor, Scan};

/// Where the doors in the right-hand wall `y = -1` begin (before the corridor's shift): each
/// is 0.9 m wide and recessed 0.15 m.
const DOORS: [f64; 4] = [3.5, 5.5, 7.5, 11.0];

/// The corridor: the right-hand wall `y = -1` with its recessed doors (back and jambs) moved
/// `shift` along it, the plain left-hand wall `y = 1.2`, both from `x = -1` to its end
/// `x = 16`.
fn corridor(shift: f64) -> Vec<(Point2, Point2)> {
    let p = Point2::new;
    let mut walls = vec![(p(-1.0, 1.2), p(16.0, 1.2)), (p(16.0, 1.2), p(16.0, -1.0))];
    let mut x = -1.0;
    for d in DOORS.map(|d| d + shift) {
        walls.push((p(x, -1.0), p(d, -1.0)));
        walls.push((p(d, -1.0), p(d, -1.15)));
        walls.push((p(d, -1.15), p(d + 0.9, -1.15)));
        walls.push((p(d + 0.9, -1.15), p(d + 0.9, -1.0)));
        x = d + 0.9;
    }
    walls.push((p(x, -1.0), p(16.0, -1.0)));
    walls
}

/// The beams of a SICK LMS2xx-like scanner at the origin: 180 deg in 0.5 deg steps.
fn beams() -> impl Iterator<Item = f64> {
    (0..361).map(|i| (-90.0 + 0.5 * f64::from(i)).to_radians())
}

/// Where each beam meets the corridor (doors moved `shift`), without noise.
fn hits(shift: f64) -> Vec<(f64, Point2)> {
    let walls = corridor(shift);
    beams()
        .map(|angle| {
            let r = walls
                .iter()
                .filter_map(|&(a, b)| hit(angle, a, b))
                .fold(f64::INFINITY, f64::min);
            (r, Point2::new(r * angle.cos(), r * angle.sin()))
        })
        .collect()
}

/// The scan of the corridor with 15 mm of range noise, ranges in centimetres.
fn scan(shift: f64, rng: &mut Rng) -> Scan {
    let ranges = hits(shift)
        .iter()
        .map(|&(r, _)| ((r + 0.015 * rng.gauss()) * 100.0).round() / 100.0)
        .collect();
    Scan::new(
        -std::f64::consts::FRAC_PI_2,
        0.5f64.to_radians(),
        0.05,
        30.0,
        ranges,
    )
    .unwrap()
}

/// The doors (their first `x`) that two or more beams see into, more than 5 cm beyond the
/// wall: the ones a scan shows. Beyond 8 m the beams meet the wall half a metre apart or
/// more, and one at most reaches into a door, which nothing can tell from noise.
fn seen_doors(shift: f64) -> Vec<f64> {
    let hits = hits(shift);
    DOORS
        .map(|d| d + shift)
        .into_iter()
        .filter(|&d| {
            let into = |q: &Point2| q.x > d && q.x < d + 0.9 && q.y < -1.05;
            hits.iter().filter(|(_, q)| into(q)).count() >= 2
        })
        .collect()
}

/// The lines along the wall `y = y0` (normal along `y`, within 3 deg and 5 cm), as the
/// `x` extents of their end points.
fn along(lines: &[Line], y0: f64) -> Vec<(f64, f64)> {
    lines
        .iter()
        .filter(|l| l.alpha.cos().abs() < 3f64.to_radians().sin())
        .filter(|l| (l.alpha.sin() * l.r - y0).abs() < 0.05)
        .map(|l| (l.start.x.min(l.end.x), l.start.x.max(l.end.x)))
        .collect()
}

#[test]
fn no_line_runs_across_a_recessed_door_and_the_plain_wall_stays_whole() {
    let mut rng = Rng(7);
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
    let (mut doors, mut across, mut near_wall, mut plain) = (0, Vec::new(), 0, 0);
    let scans = 300;
    for k in 0..scans {
        let shift = rng.unit();
        let lines = hs.extract(&scan(shift, &mut rng));
        let right = along(&lines, -1.0);
        for d in seen_doors(shift) {
            doors += 1;
            // The door's middle lies inside a line.
            let middle = d + 0.45;
            if let Some(l) = right.iter().find(|&&(x0, x1)| x0 < middle && x1 > middle) {
                across.push((k, d, *l));
            }
        }
        // The stretch of wall before the first door, 2.3 m from 1 m on, is a line.
        if right.iter().any(|&(x0, x1)| x0 < 1.2 && x1 > 3.3) {
            near_wall += 1;
        }
        // The plain wall is one line over its stretch along the first two doors.
        let left = along(&lines, 1.2);
        if left
            .iter()
            .filter(|&&(x0, x1)| x0 < 2.0 && x1 > 7.0)
            .count()
            == 1
        {
            plain += 1;
        }
    }
    // Most scans show the first door, some the second.
    assert!(doors > scans / 2, "{doors}");
    assert!(across.is_empty(), "lines across a door: {across:?}");
    assert_eq!(near_wall, scans);
    assert_eq!(plain, scans);
}
