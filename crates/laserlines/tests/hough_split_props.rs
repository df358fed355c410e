//! Invariants of `HoughSplit` on arbitrary scans: no panic, indices in range, every point in
//! at most one line, identical results on a second run, both weight functions; and the
//! documented bounds that keep lines off empty space and off scattered points: consecutive
//! supporting points of a line lie within the breakpoint distance `D` of each other
//! ([`HoughSplitParams::breakpoint_distance`] at the noise the extraction assumed, for the
//! scan's bridge: [`HoughSplitParams::bridge_for`] its dropout rate), and no
//! line's RMS residual exceeds `max_rms_sigmas` times the noise at its points' centroid.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use laserlines::hough_split::SILENT_GAP;
use laserlines::line::beams;
use laserlines::{HoughSplit, HoughSplitParams, Line, LineExtractor, Scan, Weight};
use proptest::prelude::*;

/// Scans with arbitrary values in every public field, valid or not.
fn any_scan() -> impl Strategy<Value = Scan> {
    (
        prop_oneof![4 => -3.2f64..3.2, 1 => Just(f64::NAN), 1 => Just(1e10)],
        common::any_increment(),
        prop_oneof![3 => Just(0.02), 1 => Just(0.0), 1 => Just(-1.0), 1 => Just(f64::NAN)],
        prop_oneof![3 => Just(5.6), 1 => Just(1e308), 1 => Just(f64::INFINITY), 1 => Just(0.01)],
        prop::collection::vec(common::any_range(4), 0..700),
    )
        .prop_map(
            |(angle_min, angle_increment, range_min, range_max, ranges)| Scan {
                angle_min,
                angle_increment,
                range_min,
                range_max,
                ranges,
                intensities: None,
                stamp: None,
            },
        )
}

/// Piecewise-smooth scans: runs of walls with noise, so that lines really come out.
fn wall_scan() -> impl Strategy<Value = Scan> {
    (
        (0.5f64..2.5, -0.5f64..0.5, 60usize..150),
        prop::collection::vec((0.3f64..5.0, -1.2f64..1.2, 5usize..120), 0..7),
        any::<u64>(),
        prop::bool::ANY,
    )
        .prop_map(|(long_wall, mut walls, seed, reversed)| {
            // At least one long, clearly visible wall.
            walls.insert(0, long_wall);
            let inc = 0.3515625f64.to_radians();
            let mut ranges = Vec::new();
            let mut state = seed;
            let mut i = 0usize;
            for (r, alpha, n) in walls {
                // The wall's normal is given relative to the middle beam of its run.
                let alpha = alpha + (-2.0 + (i + n / 2) as f64 * inc);
                for _ in 0..n {
                    let phi = -2.0 + i as f64 * inc;
                    state = state
                        .wrapping_mul(6364136223846793005)
                        .wrapping_add(1442695040888963407);
                    let noise = ((state >> 33) as f64 / (1u64 << 31) as f64 - 0.5) * 0.01;
                    let c = (phi - alpha).cos();
                    ranges.push(if c > 0.05 { r / c + noise } else { f64::NAN });
                    i += 1;
                }
            }
            let (angle_min, angle_increment) = if reversed {
                (-2.0 + (ranges.len().max(1) - 1) as f64 * inc, -inc)
            } else {
                (-2.0, inc)
            };
            if reversed {
                ranges.reverse();
            }
            Scan {
                angle_min,
                angle_increment,
                range_min: 0.02,
                range_max: 5.6,
                ranges,
                intensities: None,
                stamp: None,
            }
        })
}

fn check_invariants(scan: &Scan, lines: &[Line]) {
    let mut prev_last: Option<usize> = None;
    let n = scan.len();
    for (k, l) in lines.iter().enumerate() {
        assert!(l.first < n && l.last < n, "index out of range: {l:?}");
        // Only the last line of a full turn may run across its seam, clear of the first.
        if l.wraps() {
            assert!(scan.full_turn() && k + 1 == lines.len(), "{lines:?}");
            assert!(k == 0 || l.last < lines[0].first, "{lines:?}");
        }
        assert!(l.points >= 2 && l.points <= l.beam_span(n), "{l:?}");
        if let Some(p) = prev_last {
            assert!(l.first > p, "lines share or reorder beams: {lines:?}");
        }
        prev_last = Some(l.last);
        for v in [l.r, l.alpha, l.rms, l.start.x, l.start.y, l.end.x, l.end.y] {
            assert!(v.is_finite(), "non-finite value in {l:?}");
        }
        assert!(l.r >= 0.0);
        // Every supporting beam is a valid measurement.
        assert!(
            beams(l.first, l.last, n)
                .filter(|&i| scan.range_window(None).contains(scan.ranges[i]))
                .count()
                >= l.points
        );
    }
}

/// The documented bounds of every line of the last extraction of `hs` on `scan`.
fn check_bounds(scan: &Scan, hs: &HoughSplit, lines: &[Line]) {
    let st = hs.stages();
    let noise = st.noise();
    let kept: std::collections::BTreeSet<usize> = st.kept().collect();
    let points = st.points();
    let p = HoughSplitParams::default();
    let step = scan.angle_increment.abs();
    // The scan's own bridge: wider on a sparse scan.
    let bridge = p.bridge_for(scan.angle_increment, st.dropout());
    for l in lines {
        // The line's support: the kept points of its beam span, all of them its own.
        // In beam order from `first` (across the seam of a full turn).
        let n = scan.len();
        let mut support: Vec<_> = points
            .iter()
            .filter(|q| l.covers(q.index) && kept.contains(&q.index))
            .collect();
        support.sort_by_key(|q| (q.index + n - l.first) % n);
        // A lone spike between two pieces of one surface that step 7 joined is kept, but is
        // not the line's: off it by more than the split's distance (`split_sigmas` times the
        // noise, the least by which the split cuts a point out), with the line's points on
        // both sides. A spike inside one piece is the line's (its RMS gate judged it), so
        // the line holds the support with or without the spikes; a line that holds all of
        // it has none to leave out.
        let all = support.len();
        let off = |q: &laserlines::ScanPoint| {
            (q.point.x * l.alpha.cos() + q.point.y * l.alpha.sin() - l.r).abs()
                > p.split_sigmas * noise.sigma(q.range).max(l.rms)
        };
        let spikes: Vec<usize> = (1..support.len().saturating_sub(1))
            .filter(|_| l.points < all)
            .filter(|&k| off(support[k]) && !off(support[k - 1]) && !off(support[k + 1]))
            .collect();
        for &k in spikes.iter().rev() {
            support.remove(k);
        }
        assert!(
            (support.len()..=all).contains(&l.points),
            "{l:?}: {} points without spikes, {all} with",
            support.len()
        );
        for w in support.windows(2) {
            let (a, b) = (w[0], w[1]);
            // Beams from `a` to `b`, across the seam of a full turn.
            let apart_beams = (b.index + n - a.index) % n;
            let gap = apart_beams as f64 * step;
            // Across beams that all returned nothing, two points within `SILENT_GAP` may
            // follow each other; else the beam bridge's bounds hold.
            let silent = (1..apart_beams)
                .map(|k| scan.ranges[(a.index + k) % n])
                .all(|r| r.is_nan() || r < scan.range_min.max(p.min_range));
            if apart_beams > 1 && silent && (b.point - a.point).norm() <= SILENT_GAP + 1e-9 {
                continue;
            }
            assert!(apart_beams <= bridge.max_gap + 1, "{l:?}");
            let d = p.breakpoint_distance(a.range, gap, bridge.spacing, noise.sigma(a.range));
            let Some(d) = d else {
                panic!(
                    "beams {} and {} are too far apart to join: {l:?}",
                    a.index, b.index
                );
            };
            let apart = (b.point - a.point).norm();
            assert!(
                apart <= d * (1.0 + 1e-9),
                "consecutive points {} m apart, D = {d} m: {l:?}",
                apart
            );
        }
        check_ends(l, support[0], support[support.len() - 1], &p, noise);
        let n = support.len() as f64;
        let (cx, cy) = support
            .iter()
            .fold((0.0, 0.0), |(x, y), q| (x + q.point.x, y + q.point.y));
        let centroid = (cx / n).hypot(cy / n);
        let limit = p.max_rms_sigmas * noise.sigma(centroid);
        assert!(
            l.rms <= limit * (1.0 + 1e-9),
            "rms {} > {limit}: {l:?}",
            l.rms
        );
    }
}

/// A line's end points against its first and last supporting points `pf` and `pl`: the
/// segment runs the way its beams do, is `min_line_length` long, and gives up at most
/// `split_sigmas * sigma` of its points' extent at either end (ends move only to a corner
/// shared with the neighbouring line).
fn check_ends(
    l: &Line,
    pf: &laserlines::ScanPoint,
    pl: &laserlines::ScanPoint,
    p: &HoughSplitParams,
    noise: laserlines::RangeNoise,
) {
    let normal = laserlines::math::Vector2::new(l.alpha.cos(), l.alpha.sin());
    let project = |q: laserlines::math::Point2| q - normal * (q.coords.dot(&normal) - l.r);
    let (a, b) = (project(pf.point), project(pl.point));
    let extent = (b - a).norm();
    assert!(
        l.length() >= p.min_line_length - 1e-9,
        "a line shorter than min_line_length: {l:?}"
    );
    if extent == 0.0 {
        return;
    }
    let u = (b - a) / extent;
    let t = |q: laserlines::math::Point2| (q - a).dot(&u);
    let thr = |q: laserlines::math::Point2, range: f64| {
        p.split_sigmas * noise.sigma(q.coords.norm().max(range)) * (1.0 + 1e-9) + 1e-9
    };
    assert!(
        t(l.start) < t(l.end),
        "a line reversed against its beams: {l:?}"
    );
    assert!(
        t(l.start) <= thr(l.start, pf.range),
        "the start gives up its first point: {l:?}"
    );
    assert!(
        t(l.end) >= extent - thr(l.end, pl.range),
        "the end gives up its last point: {l:?}"
    );
}

/// Walls with clutter: some of a wall scan's beams replaced by arbitrary ranges, so that
/// points of no surface lie among and between the walls' points.
fn cluttered_wall_scan() -> impl Strategy<Value = Scan> {
    (
        wall_scan(),
        prop::collection::vec((0.0f64..1.0, 0.05f64..6.0), 0..80),
    )
        .prop_map(|(mut scan, clutter)| {
            let n = scan.ranges.len();
            for (at, r) in clutter {
                let i = ((at * n as f64) as usize).min(n.saturating_sub(1));
                if let Some(x) = scan.ranges.get_mut(i) {
                    *x = r;
                }
            }
            scan
        })
}

fn params_for(weight: Weight) -> HoughSplitParams {
    HoughSplitParams {
        weight,
        criterion: match weight {
            Weight::One => 1.0,
            Weight::Range => 0.5,
        },
        ..HoughSplitParams::default()
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn arbitrary_scans_never_break_invariants(scan in any_scan(), g_one in prop::bool::ANY) {
        let weight = if g_one { Weight::One } else { Weight::Range };
        let mut hs = HoughSplit::new(params_for(weight)).unwrap();
        let first = hs.extract(&scan);
        check_invariants(&scan, &first);
        check_bounds(&scan, &hs, &first);
        let second = hs.extract(&scan);
        prop_assert_eq!(&first, &second);
        // A fresh extractor agrees with a reused one.
        let fresh = HoughSplit::new(params_for(weight)).unwrap().extract(&scan);
        prop_assert_eq!(first, fresh);
    }

    #[test]
    fn the_papers_extractor_gives_no_line_from_an_invalid_scan(scan in any_scan()) {
        let mut paper = HoughSplit::new(HoughSplitParams::paper()).unwrap();
        let lines = paper.extract(&scan);
        check_invariants(&scan, &lines);
        if scan.validate().is_err() {
            prop_assert!(lines.is_empty());
            prop_assert!(paper.stages().points().is_empty());
        }
    }

    #[test]
    fn wall_scans_give_lines_under_both_weights(scan in wall_scan()) {
        for weight in [Weight::One, Weight::Range] {
            let mut hs = HoughSplit::new(params_for(weight)).unwrap();
            let lines = hs.extract(&scan);
            check_invariants(&scan, &lines);
            check_bounds(&scan, &hs, &lines);
            prop_assert!(!lines.is_empty(), "no line from a scan of walls ({weight:?})");
            // Stages are consistent: kept and removed partition the valid points.
            let st = hs.stages();
            prop_assert_eq!(st.kept().count() + st.removed().len(), st.points().len());
            for l in &lines {
                if l.wraps() {
                    // Across the seam of a full turn: its ends in segments.
                    prop_assert!(st.segments().any(|s| s.covers(l.first)));
                    prop_assert!(st.segments().any(|s| s.covers(l.last)));
                } else {
                    prop_assert!(st.segments().any(|s| s.first <= l.first && l.last <= s.last));
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn cluttered_walls_keep_lines_within_the_documented_bounds(scan in cluttered_wall_scan()) {
        let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
        let lines = hs.extract(&scan);
        check_invariants(&scan, &lines);
        check_bounds(&scan, &hs, &lines);
    }
}

/// Regression: squared distances overflowed to `inf <= inf`, so a point at 1e300 m was
/// bridged to its neighbours and joined their data segment.
#[test]
fn a_point_at_a_huge_range_is_never_bridged_into_a_segment() {
    // A wall x = 2 m.
    let mut ranges: Vec<f64> = (0..50)
        .map(|i| 2.0 / (-0.5 + 0.02 * f64::from(i)).cos())
        .collect();
    ranges[10] = 1e300;
    let scan = Scan::new(-0.5, 0.02, 0.0, f64::MAX, ranges).unwrap();
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
    let lines = hs.extract(&scan);
    assert!(!lines.is_empty());
    // The wall's points on both sides are one segment; the far point is not in it.
    assert!(hs.stages().kept().all(|k| k != 10));
    assert_eq!(hs.stages().segments().count(), 1);
}

/// After a scan with broken geometry (no valid scan, so no estimate), the extractor reports
/// the noise it assumes, not the last valid scan's estimate.
#[test]
fn an_invalid_scan_leaves_no_estimate_behind() {
    use laserlines::hough_split::FALLBACK_NOISE;
    let ranges: Vec<f64> = (0..400)
        .map(|i| 2.0 / (-1.0 + 0.005 * f64::from(i)).cos())
        .collect();
    let scan = Scan::new(-1.0, 0.005, 0.0, 30.0, ranges.clone()).unwrap();
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
    assert!(!hs.extract(&scan).is_empty());
    assert!(hs.stages().noise_estimated());
    assert_ne!(hs.range_noise(), Some(FALLBACK_NOISE));
    let broken = Scan {
        angle_increment: f64::NAN,
        ..scan
    };
    assert!(hs.extract(&broken).is_empty());
    assert_eq!(hs.range_noise(), Some(FALLBACK_NOISE));
    assert!(!hs.stages().noise_estimated());
    assert!(hs.stages().noise_bands().iter().all(|b| b.samples == 0));
}

/// Regression: two chair legs (6 cm, at 2.0 m and 1.6 m, 2.5 deg apart) before a wall at
/// 3.85 m, seen by a URG-04LX: the legs lie within the breakpoint distance of each other, and
/// were joined into a 0.4 m line across the beams between them, which see the wall behind.
#[test]
fn no_line_joins_two_legs_across_beams_that_see_the_wall_behind() {
    let inc = std::f64::consts::TAU / 1024.0;
    let angle_min = -120f64.to_radians();
    let legs = [
        (2.0, 0.0),
        (
            1.6 * 2.5f64.to_radians().cos(),
            1.6 * 2.5f64.to_radians().sin(),
        ),
    ];
    let mut rng = common::Rng(5);
    let ranges: Vec<f64> = (0..682)
        .map(|i| {
            let phi = angle_min + f64::from(i) * inc;
            let (c, s) = (phi.cos(), phi.sin());
            let mut r = if c > 0.05 { 3.85 / c } else { f64::NAN };
            for (x, y) in legs {
                // The near intersection of the ray with a circle of 3 cm radius.
                let along = x * c + y * s;
                let d2 = x * x + y * y - along * along;
                if d2 < 0.03 * 0.03 {
                    r = r.min(along - (0.03 * 0.03 - d2).sqrt());
                }
            }
            let sigma = 0.003_f64.max(0.0015 * r);
            r + sigma * rng.gauss()
        })
        .collect();
    let scan = Scan::new(angle_min, inc, 0.02, 5.6, ranges).unwrap();
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
    let lines = hs.extract(&scan);
    // The wall, in two pieces either side of the legs' shadow, and nothing else.
    assert!(!lines.is_empty());
    for l in &lines {
        assert!((l.r - 3.85).abs() < 0.05 && l.alpha.abs() < 0.05, "{l:?}");
    }
}

/// Regression: a line of one piece holds two points 8 and 13 cm behind its wall, the first
/// more than ten times the line's RMS off it, the second less; the bounds took the first for
/// a spike step 7 joined across and counted the line one point short.
#[test]
fn a_line_may_hold_a_spike_of_its_own_piece() {
    let text = include_str!("fixtures/wall_with_two_points_behind.txt");
    let mut rows = text.lines().filter(|l| !l.starts_with('#'));
    let head: Vec<f64> = rows
        .next()
        .unwrap()
        .split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect();
    let ranges: Vec<f64> = rows.map(|v| v.parse().unwrap()).collect();
    let scan = Scan::new(head[0], head[1], head[2], head[3], ranges).unwrap();
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
    let lines = hs.extract(&scan);
    let wall = lines
        .iter()
        .find(|l| l.first <= 352 && l.last >= 353)
        .unwrap();
    assert_eq!((wall.first, wall.last, wall.points), (343, 463, 114));
    check_invariants(&scan, &lines);
    check_bounds(&scan, &hs, &lines);
}
