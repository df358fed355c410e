//! Where lines end, on scenes whose truth is known: a line ends where its surface does, not
//! at a corner with a wall behind it across empty space, and a wall split where no gap
//! parts its points comes out as one line, not as two pieces side by side with one fit.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::{Rng, nearest};
use laserlines::math::Point2;
use laserlines::{HoughSplit, HoughSplitParams, Line, LineExtractor, NoiseModel, RangeNoise, Scan};

/// A segment of a scene.
type Wall = (Point2, Point2);

/// The nearest hit of the beam at `angle` on `walls`.
fn cast(angle: f64, walls: &[Wall]) -> Option<f64> {
    nearest(angle, walls)
}

/// Distance from `q` to the segment `a`-`b`.
fn to_segment(q: Point2, (a, b): Wall) -> f64 {
    let e = b - a;
    let t = ((q - a).dot(&e) / e.norm_squared()).clamp(0.0, 1.0);
    (q - (a + e * t)).norm()
}

/// Length of `line` lying farther than 0.1 m from every wall (sampled every centimetre).
fn off_every_wall(line: &Line, walls: &[Wall]) -> f64 {
    let n = (line.length() / 0.01).ceil().max(1.0) as usize;
    let off = (0..=n)
        .filter(|&k| {
            let q = line.start + (line.end - line.start) * (k as f64 / n as f64);
            walls.iter().all(|&w| to_segment(q, w) > 0.1)
        })
        .count();
    line.length() * off as f64 / (n + 1) as f64
}

/// The URG-04LX's 682 beams on `walls` under its data sheet's noise, `max(10 mm, 1 %)`,
/// with `mixed` beams after each depth edge of more than 0.3 m read between the two
/// surfaces (mixed pixels); ranges rounded to 1 mm.
fn urg_scan(walls: &[Wall], mixed: usize, rng: &mut Rng) -> Scan {
    let (beams, inc) = (682, (360.0f64 / 1024.0).to_radians());
    let angle_min = -0.5 * (beams - 1) as f64 * inc;
    let truth: Vec<f64> = (0..beams)
        .map(|i| cast(angle_min + i as f64 * inc, walls).unwrap_or(f64::NAN))
        .collect();
    let mut ranges = truth.clone();
    for i in 1..beams {
        let (a, b) = (truth[i - 1], truth[i]);
        if (a - b).abs() > 0.3 {
            // The beams just past the edge, on the side of the farther surface, read between.
            let far_after = b > a;
            for k in 0..mixed {
                let j = if far_after { i + k } else { i - 1 - k };
                if let Some(r) = ranges.get_mut(j) {
                    let t = (k + 1) as f64 / (mixed + 1) as f64;
                    let (near, far) = (a.min(b), a.max(b));
                    *r = near + (far - near) * t;
                }
            }
        }
    }
    for r in &mut ranges {
        let sigma = (0.01 * *r).max(0.01);
        *r = ((*r + sigma * rng.gauss()) * 1000.0).round() / 1000.0;
    }
    Scan::new(angle_min, inc, 0.02, 5.6, ranges).unwrap()
}

/// Lines lying over 0.25 m off every wall, scans and the worst such length, for
/// `params` on a wall at x = 0.3-0.6 from y = 1 to `end` (3.8, 4 and 4.2 m), seen at 73-88 deg
/// of incidence, and a far wall at y = 5.4 behind it, with 0-2 mixed pixels at each edge:
/// their lines meet at (0.01-0.03, 5.4), 1.2-1.6 m past the near wall's end, where the beams
/// past that end see the far wall. Drawn to that corner, the near wall's line would cross
/// the empty space between.
fn phantoms(params: HoughSplitParams) -> (usize, usize, f64) {
    let mut hs = HoughSplit::new(params).unwrap();
    let mut rng = Rng(5);
    let (mut phantoms, mut scans) = (0, 0);
    let mut worst: f64 = 0.0;
    for end in [3.8, 4.0, 4.2] {
        let walls = [
            (
                Point2::new(0.6, 1.0),
                Point2::new(0.6 - 0.4 * (end - 1.0) / 3.0, end),
            ),
            (Point2::new(-2.0, 5.4), Point2::new(3.0, 5.4)),
        ];
        for mixed in 0..=2 {
            for _ in 0..20 {
                let lines = hs.extract(&urg_scan(&walls, mixed, &mut rng));
                for l in &lines {
                    let off = off_every_wall(l, &walls);
                    worst = worst.max(off);
                    phantoms += usize::from(off > 0.25);
                }
                scans += 1;
            }
        }
    }
    (phantoms, scans, worst)
}

#[test]
fn a_wall_ending_before_a_far_wall_is_not_drawn_on_to_it() {
    // With the scanner's noise given, no line crosses the empty space (21 lines of these 180
    // scans did before the test of beams seen through at a corner, 43 with the noise
    // estimated).
    let given = HoughSplitParams {
        noise: NoiseModel::Fixed(RangeNoise::new(0.01, 0.01)),
        ..HoughSplitParams::default()
    };
    let (n, scans, worst) = phantoms(given);
    assert_eq!(
        n, 0,
        "{n} lines over 0.25 m off every wall in {scans} scans (worst {worst:.2} m)"
    );
    // With the noise estimated from each scan, a few still do: most returns of these scans lie
    // beyond 4 m, the estimate of the near noise then reads up to 10 cm, and the far wall's
    // points near the corner, on the near wall's line, join that line itself.
    let (n, scans, worst) = phantoms(HoughSplitParams::default());
    assert!(
        n <= 5,
        "{n} lines over 0.25 m off every wall in {scans} scans (worst {worst:.2} m)"
    );
}

#[test]
fn a_wall_split_without_a_gap_is_one_line() {
    // A UTM-30LX-like scanner (270 deg, 0.25 deg) in rooms of 5-8 x 4-7 m under heavy-tailed
    // range noise (Student's t of 3 degrees of freedom, scaled to 1 cm or 1 % of the range):
    // its rare large errors make the split part walls where no gap parts their points. Two
    // lines on neighbouring beams with one shared fit are one wall in two pieces.
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
    let mut rng = Rng(17);
    let (beams, inc) = (1081, 0.25f64.to_radians());
    let angle_min = -135f64.to_radians();
    let (mut twins, mut lines_seen) = (0, 0);
    for _ in 0..60 {
        let (w, h) = (5.0 + 3.0 * rng.unit(), 4.0 + 3.0 * rng.unit());
        let (x0, y0) = (-w * (0.2 + 0.3 * rng.unit()), -h * (0.3 + 0.4 * rng.unit()));
        let c = [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]
            .map(|(x, y)| Point2::new(x, y));
        let walls: Vec<Wall> = (0..4).map(|k| (c[k], c[(k + 1) % 4])).collect();
        let ranges: Vec<f64> = (0..beams)
            .map(|i| {
                let r = cast(angle_min + i as f64 * inc, &walls).unwrap_or(f64::NAN);
                let chi2: f64 = (0..3).map(|_| rng.gauss().powi(2)).sum();
                let t = rng.gauss() / (chi2 / 3.0).sqrt();
                ((r + (0.01 * r).max(0.01) * t) * 1000.0).round() / 1000.0
            })
            .collect();
        let lines = hs.extract(&Scan::new(angle_min, inc, 0.02, 30.0, ranges).unwrap());
        lines_seen += lines.len();
        twins += lines
            .windows(2)
            .filter(|w| w[1].first == w[0].last + 1 && (w[0].r, w[0].alpha) == (w[1].r, w[1].alpha))
            .count();
    }
    assert!(lines_seen >= 60 * 3, "{lines_seen} lines in 60 scans");
    assert_eq!(
        twins, 0,
        "{twins} walls in two pieces side by side, {lines_seen} lines"
    );
}

/// The lines of a URG-04LX scan (data sheet noise, seed `seed`) of a wall at x = 1.2 m from
/// y = -1.5 to 1.5 whose beams `gap` (around the straight-ahead beam 341) read `fill`.
fn wall_with_gap(gap: std::ops::Range<usize>, fill: f64, seed: u64) -> Vec<Line> {
    let wall = [(Point2::new(1.2, -1.5), Point2::new(1.2, 1.5))];
    let mut scan = urg_scan(&wall, 0, &mut Rng(seed));
    for r in &mut scan.ranges[gap] {
        *r = fill;
    }
    HoughSplit::new(HoughSplitParams::default())
        .unwrap()
        .extract(&scan)
}

/// True when one line spans the beams `gap` (its first beam before it, its last after).
fn spans(lines: &[Line], gap: &std::ops::Range<usize>) -> bool {
    lines
        .iter()
        .any(|l| l.first < gap.start && l.last >= gap.end)
}

#[test]
fn a_wall_behind_beams_that_returned_nothing_is_one_line() {
    // A dark patch, a socket or a mast of the robot: 3 to 20 beams without a return (NaN, 0,
    // a reading below the minimum range) hide 3-15 cm of the wall; the data segments part
    // there (the bridge reaches 2 missing beams), and both sides took one fit.
    for (k, fill) in [f64::NAN, 0.0, 0.01].into_iter().enumerate() {
        for width in [3, 5, 8, 20] {
            for seed in 0..5 {
                let gap = 330..330 + width;
                let lines = wall_with_gap(gap.clone(), fill, 100 * k as u64 + seed);
                assert!(
                    spans(&lines, &gap) && lines.len() == 1,
                    "{width} beams of {fill}, seed {seed}: {lines:?}"
                );
            }
        }
    }
}

#[test]
fn beams_that_saw_through_or_saw_something_keep_a_wall_in_two() {
    for seed in 0..5 {
        // A doorway: 40 beams without a return, 0.3 m of wall.
        let door = 320..360;
        assert!(!spans(&wall_with_gap(door.clone(), f64::NAN, seed), &door));
        // Beams that saw nothing in range (REP 117's `+inf`) or beyond the range limit saw
        // through the wall.
        let gap = 330..334;
        for far in [f64::INFINITY, 7.0] {
            assert!(
                !spans(&wall_with_gap(gap.clone(), far, seed), &gap),
                "{far}"
            );
        }
        // A thin post in front of the wall: its returns part the wall's points.
        assert!(!spans(&wall_with_gap(gap.clone(), 0.8, seed), &gap));
    }
}

/// A SICK LMS200-like scan (180 deg in 1 deg steps, 1 cm resolution, 5 mm of noise) of a
/// wall 3 m away (`r` 3.025 m, normal at -18.8 deg) whose first beams see into two recesses
/// beside it, 4 beams 0.26 m and 4 beams `recess` m behind its line: as a real scan of the
/// Intel Research Lab's log (its scan 679) shows one.
fn stepped_wall(recess: f64, rng: &mut Rng) -> Scan {
    let at = |theta: f64, r: f64, alpha: f64| r / (theta - alpha.to_radians()).cos();
    let ranges = (0..180)
        .map(|i| {
            let theta = f64::from(i - 90).to_radians();
            let r = match i {
                0..=45 => at(theta, 0.9, -107.0),
                46..=49 => at(theta, 3.29, -18.8),
                50..=53 => at(theta, 3.025 + recess, -18.8),
                54..=97 => at(theta, 3.025, -18.8),
                98..=140 => at(theta, 5.6, -19.0),
                141..=145 => f64::NAN,
                _ => at(theta, 1.25, 137.0),
            };
            ((r + 0.005 * rng.gauss()) * 100.0).round() / 100.0
        })
        .collect();
    Scan::new(
        -std::f64::consts::FRAC_PI_2,
        1f64.to_radians(),
        0.05,
        80.0,
        ranges,
    )
    .unwrap()
}

#[test]
fn a_wall_beside_the_few_points_of_a_step_keeps_its_line() {
    // Where lines end was refined onto the step's points, the wall's line took them in and
    // failed the RMS gate: no line on a wall of 44 points (180, 130 and 83 of the 200 scans
    // kept it with recesses of 5, 7 and 9.5 cm). The split's own piece gives the line.
    let normal = (-18.8f64).to_radians();
    for recess in [0.05, 0.07, 0.095] {
        let mut rng = Rng(3);
        let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
        let mut kept = 0;
        for _ in 0..200 {
            let lines = hs.extract(&stepped_wall(recess, &mut rng));
            kept += usize::from(lines.iter().any(|l| {
                (l.r - 3.025).abs() < 0.02
                    && (l.alpha - normal).abs() < 1f64.to_radians()
                    && l.points >= 40
            }));
        }
        assert!(
            kept >= 198,
            "recess {recess} m: the wall's line in {kept} of 200 scans"
        );
    }
}
