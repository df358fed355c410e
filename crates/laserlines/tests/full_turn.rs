//! A 360 deg scanner's seam: the wall behind the sensor where the turn begins is seen by the
//! last beams and the first. The extractor walks a full turn from the widest gap between its
//! returns, so that wall is one line across the seam (`first > last`); two walls meeting at
//! the seam keep their own lines; and turning the scan's beams round (the same scan, begun at
//! another beam) changes nothing but the beam indices.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::{Rng, hit};
use laserlines::math::{Point2, angle_diff};
use laserlines::{HoughSplit, HoughSplitParams, Line, LineExtractor, Scan};

const PI: f64 = std::f64::consts::PI;

/// A turn of `beams` beams 1 deg apart from -180 deg seeing the closed polygon `corners`
/// (sensor frame), with range noise of 1 % of the range.
fn turn(corners: &[Point2], beams: usize, rng: &mut Rng) -> Scan {
    let increment = 1f64.to_radians();
    let ranges = (0..beams)
        .map(|i| {
            let angle = -PI + i as f64 * increment;
            let nearest = (0..corners.len())
                .filter_map(|k| hit(angle, corners[k], corners[(k + 1) % corners.len()]))
                .fold(f64::INFINITY, f64::min);
            nearest * (1.0 + 0.01 * rng.gauss())
        })
        .collect();
    Scan::new(-PI, increment, 0.15, 12.0, ranges).unwrap()
}

fn extract(scan: &Scan) -> Vec<Line> {
    extract_with(scan, HoughSplitParams::default())
}

fn extract_with(scan: &Scan, p: HoughSplitParams) -> Vec<Line> {
    HoughSplit::new(p).unwrap().extract(scan)
}

/// A 4 m x 5 m room with the sensor 1.5 m in front of the wall behind it (`x = -1.5`).
fn room() -> Vec<Point2> {
    vec![
        Point2::new(-1.5, -2.0),
        Point2::new(2.5, -2.0),
        Point2::new(2.5, 3.0),
        Point2::new(-1.5, 3.0),
    ]
}

/// Whether `l` lies on the line `x = -1.5` (`r = 1.5`, `alpha = pi`) within `tol` m and 2 deg.
fn on_back_wall(l: &Line, tol: f64) -> bool {
    (l.r - 1.5).abs() < tol && angle_diff(l.alpha, PI).abs() < 2f64.to_radians()
}

#[test]
fn the_wall_across_the_seam_is_one_line() {
    for seed in 1..=20 {
        let scan = turn(&room(), 360, &mut Rng(seed));
        let lines = extract(&scan);
        // Four walls, four lines; the one behind runs across the seam and comes last.
        assert_eq!(lines.len(), 4, "seed {seed}: {lines:?}");
        let back = lines[3];
        assert!(on_back_wall(&back, 0.03), "{lines:?}");
        assert!(
            back.wraps() && back.covers(0) && back.covers(359),
            "{back:?}"
        );
        assert!(lines[..3].iter().all(|l| !l.wraps() && !l.covers(0)));
        // From the corner at y = 3 (beam 297) to the one at y = -2 (beam 53), within two of
        // the beams' spacings along the wall there (13 cm and 6 cm).
        assert!(
            (back.start - Point2::new(-1.5, 3.0)).norm() < 0.26,
            "{back:?}"
        );
        assert!(
            (back.end - Point2::new(-1.5, -2.0)).norm() < 0.12,
            "{back:?}"
        );
        assert!((back.beam_span(360) as i64 - 117).abs() <= 2, "{back:?}");
        assert!(back.points + 3 >= back.beam_span(360), "{back:?}");
    }
}

/// `scan` begun `k` beams later: the same beams, in the same directions.
fn turned(scan: &Scan, k: usize) -> Scan {
    let n = scan.ranges.len();
    let ranges = (0..n).map(|i| scan.ranges[(i + k) % n]).collect();
    let angle_min = scan.angle(k);
    Scan::new(angle_min, scan.angle_increment, 0.15, 12.0, ranges).unwrap()
}

#[test]
fn where_a_turn_begins_changes_only_the_beam_indices() {
    let corners = [
        Point2::new(-1.5, -2.0),
        Point2::new(1.0, -2.0),
        Point2::new(1.0, -1.2),
        Point2::new(2.5, -1.2),
        Point2::new(2.5, 3.0),
        Point2::new(-1.5, 3.0),
    ];
    for seed in 1..=6 {
        let scan = turn(&corners, 360, &mut Rng(seed));
        let lines = extract(&scan);
        assert_eq!(lines.len(), 6, "seed {seed}: {lines:?}");
        for k in [1, 90, 181, 300, 359] {
            let mut other = extract(&turned(&scan, k));
            assert_eq!(other.len(), lines.len(), "seed {seed}, k {k}");
            // Back in this scan's beam indices, and in its order.
            for l in &mut other {
                (l.first, l.last) = ((l.first + k) % 360, (l.last + k) % 360);
            }
            other.sort_by_key(|l| l.first);
            for (a, b) in lines.iter().zip(&other) {
                assert_eq!((a.first, a.last, a.points), (b.first, b.last, b.points));
                assert!((a.r - b.r).abs() < 1e-9, "seed {seed}, k {k}: {a:?} {b:?}");
                assert!(angle_diff(a.alpha, b.alpha).abs() < 1e-9);
                assert!((a.start - b.start).norm() < 1e-9 && (a.end - b.end).norm() < 1e-9);
            }
        }
    }
}

#[test]
fn two_walls_meeting_at_the_seam_keep_their_own_lines() {
    // The corner of the room lies straight behind the sensor: the wall `x = -1.5` above it
    // and one turned 27 deg from it below.
    let corner = Point2::new(-1.5, 0.0);
    let corners = [
        corner,
        Point2::new(-1.5 + 2.0 * 30f64.to_radians().sin(), -2.0),
        Point2::new(2.5, -2.0),
        Point2::new(2.5, 3.0),
        Point2::new(-1.5, 3.0),
    ];
    for seed in 1..=10 {
        let lines = extract(&turn(&corners, 360, &mut Rng(seed)));
        assert_eq!(lines.len(), 5, "seed {seed}: {lines:?}");
        let back = lines
            .iter()
            .find(|l| on_back_wall(l, 0.05))
            .expect("back wall");
        let slant = lines
            .iter()
            .find(|l| {
                angle_diff(l.alpha, back.alpha).abs() > 20f64.to_radians()
                    && l.nearest_distance() < 1.5
            })
            .expect("slanted wall");
        // Each reaches the corner from its own side.
        let at_corner = |l: &Line| (l.start - corner).norm().min((l.end - corner).norm());
        let (a, b) = (at_corner(back), at_corner(slant));
        assert!(a < 0.1 && b < 0.1, "seed {seed}: {a} {b} {lines:?}");
    }
}
