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

#[test]
fn a_turn_whose_last_beam_repeats_the_first_is_a_full_turn() {
    // 361 beams of 1 deg: the last points where the first does, as some drivers give a turn.
    for seed in 1..=10 {
        let scan = turn(&room(), 361, &mut Rng(seed));
        assert!(scan.full_turn());
        let lines = extract(&scan);
        assert_eq!(lines.len(), 4, "seed {seed}: {lines:?}");
        let back = lines[3];
        assert!(on_back_wall(&back, 0.03), "{lines:?}");
        assert!(
            back.covers(0) && back.covers(360) && back.covers(359),
            "{back:?}"
        );
    }
    // One beam short of a full turn, or half a beam, is none.
    for beams in [359, 358] {
        assert!(!turn(&room(), beams, &mut Rng(1)).full_turn());
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

/// `scan` with the beams `missing` returning nothing (NaN).
fn without(scan: &Scan, missing: &[usize]) -> Scan {
    let mut ranges = scan.ranges.clone();
    for &i in missing {
        ranges[i] = f64::NAN;
    }
    Scan::new(scan.angle_min, scan.angle_increment, 0.15, 12.0, ranges).unwrap()
}

#[test]
fn beams_without_a_return_at_the_seam_leave_the_wall_one_line() {
    // The wall behind, 1.5 m away, with one or two beams on either side of the seam
    // missing: the beam bridge spans them, as anywhere else on the wall.
    for missing in [&[0usize][..], &[359], &[0, 1], &[359, 0], &[358, 359]] {
        for seed in 1..=10 {
            let scan = without(&turn(&room(), 360, &mut Rng(seed)), missing);
            let lines = extract(&scan);
            assert_eq!(lines.len(), 4, "{missing:?}, seed {seed}: {lines:?}");
            let back = lines[3];
            assert!(
                on_back_wall(&back, 0.03) && back.wraps(),
                "{missing:?}: {lines:?}"
            );
            // The same scan begun 5 beams later gives the same line.
            let other = extract(&turned(&scan, 5));
            let same = other
                .iter()
                .find(|l| on_back_wall(l, 0.03))
                .expect("back wall");
            assert_eq!(
                ((same.first + 5) % 360, (same.last + 5) % 360),
                (back.first, back.last)
            );
        }
    }
}

#[test]
fn a_gap_the_bridge_spans_leaves_the_wall_one_line() {
    // A 10 m x 5 m room with the sensor 4.3 m from the wall behind it, two beams of which
    // return nothing 10 deg from the seam: no break to begin the walk at (the bridge spans
    // them), so it begins at the farthest corner and the wall is one line across the seam.
    // Three missing beams are a break, as the bridge of a 1 deg scanner spans no more than
    // two: the walk begins after them, and the wall is two lines, as it is away from the
    // seam.
    let corners = [
        Point2::new(-4.3, -2.0),
        Point2::new(5.7, -2.0),
        Point2::new(5.7, 3.0),
        Point2::new(-4.3, 3.0),
    ];
    let back = |lines: &[Line]| -> Vec<Line> {
        lines
            .iter()
            .filter(|l| (l.r - 4.3).abs() < 0.05 && angle_diff(l.alpha, PI).abs() < 0.05)
            .copied()
            .collect()
    };
    for seed in 1..=10 {
        let scan = turn(&corners, 360, &mut Rng(seed));
        let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
        let lines = hs.extract(&without(&scan, &[10, 11]));
        let on_back = back(&lines);
        assert_eq!(on_back.len(), 1, "seed {seed}: {lines:?}");
        assert!(on_back[0].covers(9) && on_back[0].covers(12) && on_back[0].covers(0));
        // The walk begins at the farthest return: near the corner (5.7, 3.0), at 27.8 deg
        // (beam 208), where 1 % of noise (6 cm) exceeds the ranges' fall along the walls.
        let seam = hs.stages().seam();
        assert!((seam as i64 - 208).abs() <= 5, "{seam}");
        let lines = hs.extract(&without(&scan, &[10, 11, 12]));
        assert_eq!(hs.stages().seam(), 13);
        let pieces = back(&lines);
        assert_eq!(pieces.len(), 2, "seed {seed}: {lines:?}");
        assert_eq!((pieces[0].first, pieces[1].last), (13, 9), "{pieces:?}");
    }
}
