//! Tests of step 5, the recursive split.

use super::*;

fn run(xy: &[(f64, f64)], p: &HoughSplitParams) -> Vec<u32> {
    let points = crate::hough_split::points::points_at(xy);
    let seg = Seg(&points);
    let mut scratch = SplitScratch::default();
    prefix_sums(seg, &mut scratch.prefix);
    let noise = RangeNoise::new(0.002, 0.0);
    linseg(seg, p, &noise, 8, &mut scratch);
    scratch.breaks
}

#[test]
fn linseg_splits_an_l_at_its_corner() {
    // An L: wall x = 1 from y = -1 up to the corner (1, 0), then wall y = 0 towards x = 0.5.
    let mut xy = Vec::new();
    for i in 0..=10 {
        xy.push((1.0, -1.0 + 0.1 * f64::from(i)));
    }
    for i in 1..=10 {
        xy.push((1.0 - 0.05 * f64::from(i), 0.0));
    }
    assert_eq!(run(&xy, &HoughSplitParams::default()), vec![0, 10, 20]);
    assert_eq!(run(&xy, &HoughSplitParams::paper()), vec![0, 10, 20]);
}

#[test]
fn linseg_keeps_a_straight_run_whole() {
    let xy: Vec<(f64, f64)> = (0..50).map(|i| (2.0, -1.0 + 0.04 * f64::from(i))).collect();
    assert_eq!(run(&xy, &HoughSplitParams::default()), vec![0, 49]);
}

/// A wall at x = 2 of 61 points 4 cm apart, the points `off` 0.25 m nearer.
fn wall_with(off: std::ops::Range<usize>) -> Vec<(f64, f64)> {
    (0..61)
        .map(|i| {
            let x = if off.contains(&i) { 1.75 } else { 2.0 };
            (x, -1.2 + 0.04 * i as f64)
        })
        .collect()
}

#[test]
fn a_leg_in_front_of_a_wall_is_cut_out_between_its_neighbours() {
    // Two points of a leg: a split at either leaves the other in both pieces and is
    // not significant; the points just before and after it become break points. The
    // piece of those four is split again at each leg point: a piece of one or two points
    // leaves no residual, so each side alone explains it (no line needs fewer than 8).
    let p = HoughSplitParams::default();
    assert_eq!(run(&wall_with(30..32), &p), vec![0, 29, 30, 31, 32, 60]);
    let uncut = HoughSplitParams {
        cut_excursions: false,
        ..HoughSplitParams::default()
    };
    assert_eq!(run(&wall_with(30..32), &uncut), vec![0, 60]);
    // Without the significance test, the paper's split isolates it too.
    let paper = run(&wall_with(30..32), &HoughSplitParams::paper());
    assert!(paper.contains(&29) && paper.contains(&32), "{paper:?}");
    // A run as long as a line's fewest points (8) is a surface of its own, never cut
    // out as an excursion: the split goes as without the cut.
    assert_eq!(run(&wall_with(26..34), &p), run(&wall_with(26..34), &uncut));
}

#[test]
fn an_outlier_beyond_the_distance_criterion_alone_does_not_split() {
    // A straight wall with one point 1 cm off (5 sigma of the test's 2 mm): the paper's
    // distance criterion splits there, the significance test does not.
    let xy: Vec<(f64, f64)> = (0..60)
        .map(|i| {
            (
                2.0 + if i == 20 { 0.01 } else { 0.0 },
                -1.2 + 0.04 * f64::from(i),
            )
        })
        .collect();
    assert_eq!(run(&xy, &HoughSplitParams::default()), vec![0, 59]);
    let paper = HoughSplitParams {
        noise: crate::NoiseModel::Auto,
        split_sigmas: 3.0,
        ..HoughSplitParams::paper()
    };
    assert!(run(&xy, &paper).len() > 2);
}

/// A wall along x = 2 of 81 points 2 cm apart (the noise of the test, 2 mm, left out):
/// `shape(y)` moves each point in x.
fn wall_shaped(shape: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
    (0..81)
        .map(|i| {
            let y = -0.8 + 0.02 * f64::from(i);
            (2.0 + shape(y), y)
        })
        .collect()
}

#[test]
fn a_bow_within_min_bend_stays_one_line_but_a_step_or_a_bend_splits() {
    let p = HoughSplitParams::default();
    let tilted = HoughSplitParams {
        min_bend: 0.0,
        ..HoughSplitParams::default()
    };
    // A bow of 12 mm from crest to trough, 3 sigma of the test's noise either way.
    let bow = wall_shaped(|y| 0.006 * (std::f64::consts::PI * y / 0.8).cos());
    assert_eq!(run(&bow, &p), vec![0, 80]);
    assert!(run(&bow, &tilted).len() > 2, "{:?}", run(&bow, &tilted));
    // A step of 3 cm halfway (each line departs from the joint one by half of it, the
    // two lie 3 cm apart), and a bend of 6 deg there (8 cm over the second half): more
    // than a bow.
    let step = wall_shaped(|y| if y > 0.0 { 0.03 } else { 0.0 });
    assert!(run(&step, &p).len() > 2, "{:?}", run(&step, &p));
    let bend = wall_shaped(|y| 0.105 * y.max(0.0));
    assert_eq!(run(&bend, &p), vec![0, 40, 80]);
}

#[test]
fn two_short_sides_meeting_at_more_than_a_bow_s_angle_bend() {
    // A box's corner 1 cm deep: two sides of 6 points 1 cm apart, at 10 deg from their
    // joint line each, depart by less than `min_bend` but meet at 20 deg.
    let xy: Vec<(f64, f64)> = (0..11)
        .map(|i| {
            let y = 0.01 * f64::from(i) - 0.05;
            (1.0 + 0.176 * (0.05 - y.abs()), y)
        })
        .collect();
    let points = crate::hough_split::points::points_at(&xy);
    let seg = Seg(&points);
    let mut pre = Vec::new();
    prefix_sums(seg, &mut pre);
    assert!(bends(seg, &pre, (0, 5, 10), 0.015));
    // Seen as one plane with a bow of the same depth, it does not.
    let flat = wall_shaped(|y| 0.004 * (1.0 - (y / 0.8).powi(2)));
    let points = crate::hough_split::points::points_at(&flat);
    let seg = Seg(&points);
    prefix_sums(seg, &mut pre);
    assert!(!bends(seg, &pre, (0, 40, 80), 0.015));
}

#[test]
fn a_door_set_back_from_its_wall_is_split_at_its_edges() {
    // Beams 33..=73 of a simulated scan of a 1-degree scanner with 12 mm of noise: a
    // wall (beams 33-45, 1.46 m from the sensor's line), a door 12 cm behind it (46-61),
    // its jamb (62-63) and the wall again (64-73); two beams without a return (51, 58).
    let ranges = [
        1.531,
        1.551,
        1.56,
        1.55,
        1.562,
        1.576,
        1.602,
        1.638,
        1.617,
        1.621,
        1.642,
        1.64,
        1.677,
        1.849,
        1.849,
        1.877,
        1.905,
        1.922,
        f64::NAN,
        1.959,
        2.011,
        2.014,
        2.045,
        2.092,
        2.107,
        f64::NAN,
        2.193,
        2.207,
        2.275,
        2.294,
        2.263,
        2.217,
        2.268,
        2.333,
        2.357,
        2.427,
        2.455,
        2.512,
        2.577,
        2.66,
        2.738,
    ];
    let beams: Vec<usize> = (33..=73).filter(|&i| ranges[i - 33].is_finite()).collect();
    let xy: Vec<(f64, f64)> = beams
        .iter()
        .map(|&i| {
            let (r, phi) = (ranges[i - 33], (i as f64 - 90.0).to_radians());
            (r * phi.cos(), r * phi.sin())
        })
        .collect();
    let points = crate::hough_split::points::points_at(&xy);
    let seg = Seg(&points);
    let mut scratch = SplitScratch::default();
    prefix_sums(seg, &mut scratch.prefix);
    // The scan's own estimate.
    let noise = RangeNoise::new(0.0144, 0.0091);
    linseg(seg, &HoughSplitParams::default(), &noise, 8, &mut scratch);
    let at: Vec<usize> = scratch.breaks.iter().map(|&k| beams[k as usize]).collect();
    // Wall 33-45, the step 45-46, the door 46-61 (split at the farthest point of the
    // first chord, 53: its two pieces are merged later, as one surface), its jamb 61-64
    // and the wall 64-73. Without trying the split point on each side alone, the door
    // was split at 53 only, and each of its halves taken with a piece of wall.
    assert_eq!(at, vec![33, 45, 46, 53, 61, 64, 73]);
}
