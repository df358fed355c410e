//! The metric code on hand-made cases whose answers are known: a perfect line, lines off by
//! more (and less) than the tolerance, a split piece, a bridging line, a phantom line, a line
//! on a piece too small to be required, duplicates, and empty scans; then the aggregates
//! (rates, RMS, medians), coverage and speed.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines::math::{Matrix2, Point2};
use laserlines::{Line, Scan};
use laserlines_eval::{
    Coverage, ExpectedPiece, ExplainParams, MatchParams, SpeedMetrics, TruthTally, match_lines,
    median, quantile,
};

fn p(x: f64, y: f64) -> Point2 {
    Point2::new(x, y)
}

/// A line through `start` and `end` supported by beams `first..=last`.
fn line(first: usize, last: usize, start: Point2, end: Point2) -> Line {
    let piece = ExpectedPiece::exact(0, first, last, start, end);
    Line {
        start,
        end,
        r: piece.r,
        alpha: piece.alpha,
        first,
        last,
        points: last - first + 1,
        rms: 0.0,
        covariance: Matrix2::zeros(),
    }
}

/// The wall x = 2 m from y = -1 to y = 1, seen by beams 100..=199.
fn wall() -> ExpectedPiece {
    ExpectedPiece::exact(0, 100, 199, p(2.0, -1.0), p(2.0, 1.0))
}

fn params() -> MatchParams {
    MatchParams::default()
}

#[test]
fn a_perfect_line_is_found_with_zero_errors() {
    let l = line(100, 199, p(2.0, -1.0), p(2.0, 1.0));
    let m = match_lines(&[l], &[wall()], &params());
    assert_eq!((m.significant_pieces, m.found, m.lines), (1, 1, 1));
    assert!(m.false_lines.is_empty() && m.on_wall_lines.is_empty());
    let pair = m.pairs[0];
    assert_eq!((pair.line, pair.piece), (0, 0));
    assert!(pair.dr.abs() < 1e-12 && pair.dalpha < 1e-12);
    assert!(pair.start_error < 1e-12 && pair.end_error < 1e-12);
    assert!((pair.overlap - 1.0).abs() < 1e-12);
    let t = TruthTally::of_match(&m).metrics();
    assert_eq!(t.true_positive_rate, 1.0);
    assert_eq!(t.false_positive_rate, 0.0);
    assert_eq!(t.f1, 1.0);
}

#[test]
fn a_line_off_by_more_than_the_tolerance_is_missed_and_false() {
    // 2 cm too far (tolerance 1 cm).
    let far = line(100, 199, p(2.02, -1.0), p(2.02, 1.0));
    let m = match_lines(&[far], &[wall()], &params());
    assert_eq!(
        (m.found, m.false_lines.len(), m.on_wall_lines.len()),
        (0, 1, 0)
    );
    let t = TruthTally::of_match(&m).metrics();
    assert_eq!(
        (t.true_positive_rate, t.false_positive_rate, t.f1),
        (0.0, 1.0, 0.0)
    );
    // Turned by 1 deg about the wall's middle (tolerance 0.5 deg).
    let a = 1f64.to_radians();
    let turned = line(
        100,
        199,
        p(2.0 - a.sin(), -a.cos()),
        p(2.0 + a.sin(), a.cos()),
    );
    assert_eq!(match_lines(&[turned], &[wall()], &params()).found, 0);
    // Within the tolerances: found, and the error is reported.
    let near = line(100, 199, p(2.005, -1.0), p(2.005, 1.0));
    let m = match_lines(&[near], &[wall()], &params());
    assert_eq!(m.found, 1);
    assert!((m.pairs[0].dr - 0.005).abs() < 1e-9);
    assert!((m.pairs[0].start_error - 0.005).abs() < 1e-9);
}

#[test]
fn the_tolerance_widens_with_the_ideal_fit_error() {
    let far = line(100, 199, p(2.02, -1.0), p(2.02, 1.0));
    // A piece whose ideal fit has sigma_r = 1 cm: tolerance 4 cm.
    let noisy = ExpectedPiece {
        sigma_r: 0.01,
        ..wall()
    };
    assert_eq!(params().tolerances(&noisy).0, 0.04);
    assert_eq!(match_lines(&[far], &[noisy], &params()).found, 1);
}

#[test]
fn a_beam_overlap_below_one_half_is_not_a_match() {
    // The right geometry on 40 of the piece's 100 beams: IoU 0.4.
    let short = line(100, 139, p(2.0, -1.0), p(2.0, -0.2));
    let m = match_lines(&[short], &[wall()], &params());
    assert_eq!((m.found, m.false_lines.len()), (0, 1));
    // It lies on the wall all the same.
    assert_eq!(m.on_wall_lines, vec![0]);
    // 60 beams: IoU 0.6, found; the end point error is the missing part of the wall.
    let longer = line(100, 159, p(2.0, -1.0), p(2.0, 0.2));
    let m = match_lines(&[longer], &[wall()], &params());
    assert_eq!(m.found, 1);
    assert!((m.pairs[0].end_error - 0.8).abs() < 1e-9);
}

#[test]
fn a_split_piece_counts_once_found_and_once_false() {
    let a = line(100, 159, p(2.0, -1.0), p(2.0, 0.2));
    let b = line(160, 199, p(2.0, 0.2), p(2.0, 1.0));
    let m = match_lines(&[a, b], &[wall()], &params());
    assert_eq!((m.found, m.lines), (1, 2));
    assert_eq!(m.pairs[0].line, 0, "the larger half is the match");
    assert_eq!(m.false_lines, vec![1]);
    assert_eq!(m.on_wall_lines, vec![1]);
    let t = TruthTally::of_match(&m).metrics();
    assert_eq!(t.true_positive_rate, 1.0);
    assert_eq!(t.false_positive_rate, 0.5);
    assert_eq!(t.on_wall_lines, 1);
    // Split in equal halves: still exactly one match (the tie goes to the lower index).
    let a = line(100, 149, p(2.0, -1.0), p(2.0, 0.0));
    let b = line(150, 199, p(2.0, 0.0), p(2.0, 1.0));
    let m = match_lines(&[a, b], &[wall()], &params());
    assert_eq!((m.found, m.false_lines.len()), (1, 1));
    assert_eq!(m.pairs[0].line, 0);
}

#[test]
fn a_line_bridging_an_obstacle_is_false_but_on_a_wall() {
    // The wall seen in two pieces, beams 100..=139 and 160..=199, a leg in front between.
    let left = ExpectedPiece::exact(0, 100, 139, p(2.0, -1.0), p(2.0, -0.2));
    let right = ExpectedPiece::exact(0, 160, 199, p(2.0, 0.2), p(2.0, 1.0));
    let bridge = line(100, 199, p(2.0, -1.0), p(2.0, 1.0));
    let m = match_lines(&[bridge], &[left, right], &params());
    assert_eq!((m.significant_pieces, m.found), (2, 0));
    assert_eq!(m.false_lines, vec![0]);
    assert_eq!(m.on_wall_lines, vec![0]);
    // Two lines, one per piece: both found.
    let a = line(100, 139, p(2.0, -1.0), p(2.0, -0.2));
    let b = line(160, 199, p(2.0, 0.2), p(2.0, 1.0));
    let m = match_lines(&[a, b], &[left, right], &params());
    assert_eq!((m.found, m.false_lines.len()), (2, 0));
}

#[test]
fn a_phantom_line_is_false_and_not_on_a_wall() {
    let real = line(100, 199, p(2.0, -1.0), p(2.0, 1.0));
    // Beams where no wall is (e.g. across a mixed pixel and a leg).
    let phantom = line(300, 320, p(-1.0, 1.5), p(-1.3, 1.2));
    let m = match_lines(&[real, phantom], &[wall()], &params());
    assert_eq!(m.found, 1);
    assert_eq!(m.false_lines, vec![1]);
    assert!(m.on_wall_lines.is_empty());
    // On the wall's beams but the wrong geometry (a leg in front of it): not on the wall.
    let leg = line(140, 160, p(1.5, -0.1), p(1.5, 0.1));
    let m = match_lines(&[leg], &[wall()], &params());
    assert_eq!(
        (m.found, m.false_lines.len(), m.on_wall_lines.len()),
        (0, 1, 0)
    );
}

#[test]
fn a_line_on_a_piece_too_small_to_require_is_neither_found_nor_false() {
    let small = ExpectedPiece::exact(3, 400, 407, p(1.0, 0.0), p(1.0, 0.1));
    assert!(!small.significant);
    let l = line(400, 407, p(1.0, 0.0), p(1.0, 0.1));
    let m = match_lines(&[l], &[wall(), small], &params());
    assert_eq!((m.significant_pieces, m.found), (1, 0));
    assert!(m.false_lines.is_empty());
    assert_eq!(m.pairs.len(), 1);
    assert!(!m.pairs[0].significant);
    let t = TruthTally::of_match(&m);
    assert_eq!(
        t.accuracy.pieces, 0,
        "only significant pieces count in the errors"
    );
    assert_eq!(t.metrics().false_positive_rate, 0.0);
}

#[test]
fn the_assignment_is_one_to_one() {
    // The same line twice (overlapping beam ranges, as a broken extractor might give).
    let l = line(100, 199, p(2.0, -1.0), p(2.0, 1.0));
    let closer = line(100, 199, p(2.001, -1.0), p(2.001, 1.0));
    let m = match_lines(&[l, closer], &[wall()], &params());
    assert_eq!(m.found, 1);
    assert_eq!(
        m.pairs[0].line, 0,
        "the smaller error wins the tie in overlap"
    );
    assert_eq!(m.false_lines, vec![1]);
}

#[test]
fn empty_scans_give_defined_rates() {
    // Nothing to find, nothing found.
    let m = match_lines(&[], &[], &params());
    let t = TruthTally::of_match(&m).metrics();
    assert_eq!((t.pieces, t.lines), (0, 0));
    assert_eq!(t.true_positive_rate, 1.0);
    assert_eq!(t.false_positive_rate, 0.0);
    assert_eq!((t.rms_dr_m, t.median_endpoint_error_m), (0.0, 0.0));
    // A wall and no line.
    let t = TruthTally::of_match(&match_lines(&[], &[wall()], &params())).metrics();
    assert_eq!(
        (t.true_positive_rate, t.false_positive_rate, t.f1),
        (0.0, 0.0, 0.0)
    );
    // A line and no wall.
    let l = line(100, 199, p(2.0, -1.0), p(2.0, 1.0));
    let t = TruthTally::of_match(&match_lines(&[l], &[], &params())).metrics();
    assert_eq!((t.true_positive_rate, t.false_positive_rate), (1.0, 1.0));
}

#[test]
fn non_finite_lines_match_nothing_and_do_not_panic() {
    let mut l = line(100, 199, p(2.0, -1.0), p(2.0, 1.0));
    l.r = f64::NAN;
    let mut reversed = line(100, 199, p(2.0, -1.0), p(2.0, 1.0));
    reversed.first = 199;
    reversed.last = 100;
    let m = match_lines(&[l, reversed], &[wall()], &params());
    assert_eq!((m.found, m.false_lines.len()), (0, 2));
}

#[test]
fn tallies_add_up_to_rates_rms_and_medians() {
    let mut total = TruthTally::default();
    // Scan 1: found with dr = +3 mm; scan 2: found with dr = -4 mm and a phantom.
    let a = line(100, 199, p(2.003, -1.0), p(2.003, 1.0));
    total.add(&TruthTally::of_scan(&[a], &[wall()], &params()));
    let b = line(100, 199, p(1.996, -1.0), p(1.996, 1.0));
    let phantom = line(300, 320, p(-1.0, 1.5), p(-1.3, 1.2));
    total.add(&TruthTally::of_scan(&[b, phantom], &[wall()], &params()));
    // Scan 3: missed.
    total.add(&TruthTally::of_scan(&[], &[wall()], &params()));
    let t = total.metrics();
    assert_eq!((t.pieces, t.found, t.lines, t.false_lines), (3, 2, 3, 1));
    assert!((t.true_positive_rate - 2.0 / 3.0).abs() < 1e-12);
    assert!((t.false_positive_rate - 1.0 / 3.0).abs() < 1e-12);
    assert!((t.f1 - 2.0 / 3.0).abs() < 1e-12);
    let rms = ((0.003f64.powi(2) + 0.004f64.powi(2)) / 2.0).sqrt();
    assert!((t.rms_dr_m - rms).abs() < 1e-9);
    assert!(t.rms_dalpha_rad < 1e-12);
    // End-point errors 3, 3, 4, 4 mm: median 3.5 mm, 90th percentile 4 mm.
    assert!((t.median_endpoint_error_m - 0.0035).abs() < 1e-9);
    assert!((t.p90_endpoint_error_m - 0.004).abs() < 1e-9);
}

#[test]
fn medians_and_speed() {
    assert_eq!(median(&[]), None);
    assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
    assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), Some(2.5));
    let ten: Vec<f64> = (1..=10).map(f64::from).collect();
    assert_eq!(quantile(&ten, 0.9), Some(9.0));
    assert_eq!(quantile(&ten, 1.0), Some(10.0));
    assert_eq!(quantile(&ten, 0.0), Some(1.0));
    assert_eq!(quantile(&[], 0.5), None);
    let s = SpeedMetrics::of_times(&[10e-6, 30e-6, 20e-6, 40e-6]);
    assert!((s.median_us_per_scan - 25.0).abs() < 1e-9);
    assert!((s.mean_us_per_scan - 25.0).abs() < 1e-9);
    assert!((s.scans_per_second - 40_000.0).abs() < 1e-6);
    let none = SpeedMetrics::of_times(&[]);
    assert_eq!((none.median_us_per_scan, none.scans_per_second), (0.0, 0.0));
}

#[test]
fn coverage_counts_points_near_segments() {
    // Beams every 0.5 deg from -10 deg; a wall at x = 2 m, except beam 5 (an outlier 0.5 m
    // nearer), beam 6 (no return) and beams 30.. (an object 1 m away, off the segment).
    let inc = 0.5f64.to_radians();
    let a0 = -10f64.to_radians();
    let ranges: Vec<f64> = (0..40)
        .map(|i| {
            let r = 2.0 / (a0 + i as f64 * inc).cos();
            match i {
                5 => r - 0.5,
                6 => f64::NAN,
                30.. => 1.0,
                _ => r,
            }
        })
        .collect();
    let scan = Scan::new(a0, inc, 0.02, 5.6, ranges).unwrap();
    let y = |i: usize| 2.0 * (a0 + i as f64 * inc).tan();
    let mut l = line(0, 29, p(2.0, y(0)), p(2.0, y(29)));
    l.points = 28;
    l.rms = 0.002;
    let c = Coverage::of_scan(&scan, &[l], &ExplainParams::default());
    assert_eq!(c.points, 39);
    assert_eq!(
        c.explained, 28,
        "all but the outlier, the gap and the object"
    );
    assert!((c.explained_fraction() - 28.0 / 39.0).abs() < 1e-12);
    assert!((c.residual_rms() - 0.002).abs() < 1e-12);
    let none = Coverage::of_scan(&scan, &[], &ExplainParams::default());
    assert_eq!((none.explained, none.residual_rms()), (0, 0.0));
    let empty = Coverage::of_scan(&Scan::default(), &[], &ExplainParams::default());
    assert_eq!((empty.points, empty.explained_fraction()), (0, 0.0));
    // The threshold: 15 mm, and 1.5 % of the range beyond 1 m.
    let e = ExplainParams::default();
    assert_eq!((e.threshold(0.5), e.threshold(4.0)), (0.015, 0.06));
}
