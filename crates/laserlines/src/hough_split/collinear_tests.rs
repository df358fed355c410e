//! Tests of step 7, the fits that the pieces of one surface share.

use super::*;
use crate::hough_split::points::Pt;

/// A line on the points `(x, y0 + dy(i))` for `xs`, with its candidate.
fn piece(xs: std::ops::Range<i32>, step: f64, y0: f64, noise: &RangeNoise) -> (Line, Candidate) {
    let pts: Vec<Point2> = xs
        .clone()
        .map(|i| {
            let dy = if i % 2 == 0 { 0.004 } else { -0.004 };
            Point2::new(f64::from(i) * step, y0 + dy)
        })
        .collect();
    piece_of(&pts, noise)
}

fn share(pieces: &[(Line, Candidate)], noise: &RangeNoise) -> Vec<Line> {
    share_seeing(pieces, noise, Seen::default())
}

/// [`share`] with the scan's returns of `seen`.
fn share_seeing(pieces: &[(Line, Candidate)], noise: &RangeNoise, seen: Seen<'_>) -> Vec<Line> {
    let mut lines: Vec<Line> = pieces.iter().map(|p| p.0).collect();
    let candidates: Vec<Candidate> = pieces.iter().map(|p| p.1).collect();
    let p = HoughSplitParams::default();
    share_fits(
        &mut lines,
        &candidates,
        &p,
        noise,
        seen,
        &mut Groups::default(),
    );
    lines
}

#[test]
fn two_pieces_of_a_wall_share_their_joint_fit() {
    let noise = RangeNoise::new(0.005, 0.0);
    // A wall at y = 2 seen on both sides of a leg: x = -1.0..-0.2 and 0.3..1.1.
    let pieces = [
        piece(-50..-10, 0.02, 2.0, &noise),
        piece(15..55, 0.02, 2.0, &noise),
    ];
    let lines = share(&pieces, &noise);
    assert_eq!(lines.len(), 2);
    assert_eq!((lines[0].r, lines[0].alpha), (lines[1].r, lines[1].alpha));
    assert!((lines[0].r - 2.0).abs() < 1e-3);
    // Each keeps its own beams and points; the joint fit knows the direction better.
    assert_eq!(lines[1].points, 40);
    for (shared, own) in lines.iter().zip(&pieces) {
        assert!(shared.covariance[(1, 1)] < 0.5 * own.0.covariance[(1, 1)]);
        assert!((shared.start.x - own.0.start.x).abs() < 1e-3);
    }
}

#[test]
fn pieces_that_follow_each_other_with_one_fit_are_one_line() {
    let noise = RangeNoise::new(0.005, 0.0);
    // A wall at y = 2 split at x = -0.2 with nothing between the pieces.
    let mut pieces = [
        piece(-50..-10, 0.02, 2.0, &noise),
        piece(-10..30, 0.02, 2.0, &noise),
    ];
    assert_eq!(share(&pieces, &noise).len(), 2);
    pieces[1].1.follows = true;
    let lines = share(&pieces, &noise);
    assert_eq!(lines.len(), 1);
    assert_eq!(lines[0].points, 80);
    assert!((lines[0].start.x + 1.0).abs() < 1e-3 && (lines[0].end.x - 0.58).abs() < 1e-3);
    assert!((lines[0].rms - 0.004).abs() < 1e-4);
    // Its beams run from the first piece's first to the second's last; its RMS is that
    // of all the points (the second piece twice as rough: sqrt((16 + 64) / 2) mm).
    let rough: Vec<Point2> = (-10..30)
        .map(|i| {
            let dy = if i % 2 == 0 { 0.008 } else { -0.008 };
            Point2::new(f64::from(i) * 0.02, 2.0 + dy)
        })
        .collect();
    pieces[1] = piece_of(&rough, &noise);
    pieces[1].1.follows = true;
    pieces[0].0.first = 100;
    pieces[0].0.last = 139;
    pieces[1].0.first = 140;
    pieces[1].0.last = 179;
    let lines = share(&pieces, &noise);
    assert_eq!(lines.len(), 1);
    assert_eq!((lines[0].first, lines[0].last), (100, 179));
    let pooled = 40f64.sqrt() * 1e-3;
    assert!((lines[0].rms - pooled).abs() < 1e-4, "{}", lines[0].rms);
    // Pieces of two surfaces never take one fit, and stay two lines.
    let mut apart = [
        piece(-50..-10, 0.02, 2.0, &noise),
        piece(-10..30, 0.02, 1.95, &noise),
    ];
    apart[1].1.follows = true;
    assert_eq!(share(&apart, &noise).len(), 2);
    // Two walls seen in turns, each piece in the group of its own wall: neighbours of two
    // groups never join, whatever their points.
    let mut turns = [
        piece(-60..-40, 0.02, 2.0, &noise),
        piece(-40..-20, 0.02, 2.5, &noise),
        piece(-20..0, 0.02, 2.0, &noise),
        piece(0..20, 0.02, 2.5, &noise),
    ];
    for t in &mut turns[1..] {
        t.1.follows = true;
    }
    let lines = share(&turns, &noise);
    assert_eq!(lines.len(), 4);
    assert_eq!((lines[0].r, lines[0].alpha), (lines[2].r, lines[2].alpha));
}

#[test]
fn parallel_surfaces_apart_keep_their_own_fits() {
    let noise = RangeNoise::new(0.005, 0.0);
    // A box face 5 cm in front of the wall: 10 standard deviations of the noise.
    let pieces = [
        piece(-50..-10, 0.02, 2.0, &noise),
        piece(15..55, 0.02, 1.95, &noise),
    ];
    let lines = share(&pieces, &noise);
    assert_eq!(lines.len(), 2);
    for (kept, own) in lines.iter().zip(&pieces) {
        assert_eq!(kept, &own.0);
    }
}

#[test]
fn a_piece_too_uncertain_alone_is_kept_when_its_wall_pins_it_down() {
    // 3 cm noise: a 10-point piece 0.18 m long knows its direction to about 8 deg.
    let noise = RangeNoise::new(0.03, 0.0);
    let short = piece(60..70, 0.02, 2.0, &noise);
    assert!(!short.1.certain);
    assert!(share(std::slice::from_ref(&short), &noise).is_empty());
    let long = piece(-60..10, 0.02, 2.0, &noise);
    let lines = share(&[long, short], &noise);
    assert_eq!(lines.len(), 2);
    assert_eq!(lines[1].points, 10);
    assert!(certain(&lines[1].covariance, &HoughSplitParams::default()));
}

/// A line and its candidate on `points`.
fn piece_of(points: &[Point2], noise: &RangeNoise) -> (Line, Candidate) {
    let sums = FitSums::from_points(points.iter().copied());
    let fit = sums.fit().unwrap();
    let n = points.len();
    let mut line = Line::from_fit(&fit, (0, points[0]), (n - 1, points[n - 1]));
    line.covariance = floored_covariance(&fit, noise, true);
    let certain = certain(&line.covariance, &HoughSplitParams::default());
    let ends = (points[0], points[n - 1]);
    let span = (0, n as u32);
    (
        line,
        Candidate {
            sums,
            ends,
            certain,
            span,
            follows: false,
        },
    )
}

#[test]
fn uncertain_pieces_of_two_walls_share_no_fit() {
    // A 360 deg scanner of 0.5 deg steps at 2 % noise (the noise its scan gave): 17
    // beams on a wall at r 7.72 m, alpha -66.4 deg, and 8 beams on a perpendicular wall
    // at r 6.63 m, alpha 23.6 deg, 9 m further round. Each alone is too uncertain to
    // keep. One line through both centroids, 25 and 65 deg off the walls, passes the
    // test of a group with a certain line (chi-square 13.79), not the stricter one.
    let noise = RangeNoise::new(0.07, 0.0183);
    let step = std::f64::consts::PI / 360.0;
    let beams = |first: usize, ranges: &[f64]| -> Vec<Point2> {
        let bearing = |i: usize| -std::f64::consts::PI + (first + i) as f64 * step;
        let at = |(i, r): (usize, &f64)| Point2::new(r * bearing(i).cos(), r * bearing(i).sin());
        ranges.iter().enumerate().map(at).collect()
    };
    let a = beams(
        198,
        &[
            8.2089, 8.1877, 7.8291, 7.8637, 8.0933, 7.9215, 8.0305, 7.8365, 7.9858, 7.9725, 7.6823,
            7.6082, 7.7192, 7.9927, 7.707, 7.5798, 7.6375,
        ],
    );
    let b = beams(
        342,
        &[
            7.8821, 7.7426, 7.8797, 7.8018, 7.7763, 7.9665, 7.4543, 7.6862,
        ],
    );
    let pieces = [piece_of(&a, &noise), piece_of(&b, &noise)];
    assert!(!pieces[0].1.certain && !pieces[1].1.certain);
    let (sa, sb) = (&pieces[0].1.sums, &pieces[1].1.sums);
    assert!(one_line(sa, sb, &noise, true, SHARE_CHI2));
    assert!(!one_line(sa, sb, &noise, true, SHARE_CHI2_UNANCHORED));
    // Neither takes a joint fit, so neither is pinned down: both are dropped.
    assert!(share(&pieces, &noise).is_empty());
}

#[test]
fn uncertain_pieces_of_one_wall_still_pin_each_other_down() {
    // 3 cm noise: two 10-point pieces 0.18 m long, 1.4 m apart on the wall y = 2.
    let noise = RangeNoise::new(0.03, 0.0);
    let pieces = [
        piece(-10..0, 0.02, 2.0, &noise),
        piece(60..70, 0.02, 2.0, &noise),
    ];
    assert!(!pieces[0].1.certain && !pieces[1].1.certain);
    let lines = share(&pieces, &noise);
    assert_eq!(lines.len(), 2);
    assert!((lines[0].r - 2.0).abs() < 0.01 && (lines[1].r - 2.0).abs() < 0.01);
}

#[test]
fn uncertain_pieces_with_an_open_view_between_share_no_fit() {
    // Two uncertain 10-point pieces on the line y = 2, 3 m apart (beams 0..=9 and
    // 100..=109), and on the beams between them returns at y = 4: beyond the line, where
    // they meet it from x = 0.1 to 2.9, no wall runs. Two surfaces that happen to line up.
    let noise = RangeNoise::new(0.03, 0.0);
    let mut pieces = [
        piece(-10..0, 0.02, 2.0, &noise),
        piece(150..160, 0.02, 2.0, &noise),
    ];
    pieces[1].0.first = 100;
    pieces[1].0.last = 109;
    pieces[0].0.last = 9;
    assert!(!pieces[0].1.certain && !pieces[1].1.certain);
    let returns = |y: f64| -> Vec<Pt> {
        (10..100)
            .map(|idx| {
                let x = 0.2 + 5.6 * (idx - 10) as f64 / 89.0 * y / 4.0;
                Pt {
                    x,
                    y,
                    range: x.hypot(y),
                    idx,
                }
            })
            .collect()
    };
    let beyond = returns(4.0);
    let seen = Seen {
        returns: &beyond,
        step: 0.0,
    };
    assert!(share_seeing(&pieces, &noise, seen).is_empty());
    // Something in front of the line between them (a box at y = 1): the wall may run
    // behind it, and the pieces pin each other down.
    let front = returns(1.0);
    let seen = Seen {
        returns: &front,
        step: 0.0,
    };
    let lines = share_seeing(&pieces, &noise, seen);
    assert_eq!(lines.len(), 2);
    assert!((lines[0].r - 2.0).abs() < 0.01);
    // A doorway's view beyond (x from 1 to 2.5 m of the line): still one line.
    let door: Vec<Pt> = beyond
        .iter()
        .filter(|q| (2.0..5.0).contains(&q.x))
        .copied()
        .collect();
    let seen = Seen {
        returns: &door,
        step: 0.0,
    };
    assert_eq!(share_seeing(&pieces, &noise, seen).len(), 2);
}

#[test]
fn a_group_with_a_certain_line_takes_pieces_by_the_looser_test() {
    // 3 cm noise: a 10-point piece 6 cm off the wall lies between the two quantiles of
    // its chi-square against a 70-point piece of the wall.
    let noise = RangeNoise::new(0.03, 0.0);
    let long = piece(-60..10, 0.02, 2.0, &noise);
    let off = piece(60..70, 0.02, 2.06, &noise);
    assert!(long.1.certain && !off.1.certain);
    let (a, b) = (&long.1.sums, &off.1.sums);
    assert!(one_line(a, b, &noise, true, SHARE_CHI2));
    assert!(!one_line(a, b, &noise, true, SHARE_CHI2_UNANCHORED));
    let shared = |lines: &[Line]| {
        lines
            .windows(2)
            .all(|w| (w[0].r, w[0].alpha) == (w[1].r, w[1].alpha))
    };
    // The certain line first, or joining the uncertain one.
    for pieces in [[long, off], [off, long]] {
        let lines = share(&pieces, &noise);
        assert!(lines.len() == 2 && shared(&lines), "{lines:?}");
    }
    // A group made certain by a later line: an uncertain piece on the wall, the certain
    // one, then a piece 5 cm off the wall, between the quantiles against the two.
    let before = piece(-80..-70, 0.02, 2.0, &noise);
    let off = piece(60..70, 0.02, 2.05, &noise);
    assert!(!before.1.certain);
    let group = before.1.sums.join(&long.1.sums);
    assert!(one_line(&group, &off.1.sums, &noise, true, SHARE_CHI2));
    assert!(!one_line(
        &group,
        &off.1.sums,
        &noise,
        true,
        SHARE_CHI2_UNANCHORED
    ));
    let lines = share(&[before, long, off], &noise);
    assert!(lines.len() == 3 && shared(&lines), "{lines:?}");
}

/// The sums of `n` points from `a` to `b`.
fn run(a: Point2, b: Point2, n: usize) -> FitSums {
    FitSums::from_points((0..n).map(|i| a + (b - a) * (i as f64 / (n - 1) as f64)))
}

#[test]
fn objects_far_apart_share_no_line_that_grazes_both() {
    let noise = RangeNoise::new(0.01, 0.01);
    // Two faces of 6 cm at 3 and 5 m, facing the sensor: the line x = 0.5 passes within
    // 3 cm of every point, well within sigma(4 m) = 4 cm, but at 80 and 84 deg of
    // incidence, where the noise across it is 5 and 4 mm.
    let a = run(Point2::new(0.47, 3.0), Point2::new(0.53, 3.0), 8);
    let b = run(Point2::new(0.47, 5.0), Point2::new(0.53, 5.0), 8);
    assert!(!one_line(&a, &b, &noise, true, SHARE_CHI2));
    assert!(one_line(&a, &b, &noise, false, SHARE_CHI2));
    // Two pieces of that line itself, as glancing as they are, do share it.
    let a = run(Point2::new(0.5, 2.9), Point2::new(0.5, 3.1), 8);
    let b = run(Point2::new(0.5, 4.9), Point2::new(0.5, 5.1), 8);
    assert!(one_line(&a, &b, &noise, true, SHARE_CHI2));
    assert!(one_line(&a, &b, &noise, false, SHARE_CHI2));
}
