//! The classic extractors on arbitrary input: any scan (NaN, infinities, 0 and 1 beams, bad
//! increments) and any parameters, valid or not, never panic and keep the invariants (indices
//! in range, disjoint ordered beam ranges, finite lines, the same result on a second run).

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::{Rng, increment, sigma};
use laserlines::extractors::{self, *};
use laserlines::line::beams;
use laserlines::registry::ALGORITHMS;
use laserlines::{Line, LineExtractor, Scan, Weight};
use proptest::prelude::*;

// ---------------------------------------------------------------------------------------------
// Invariants on arbitrary scans.

/// Scans with arbitrary values in every public field, valid or not, with 0 and 1 beams often.
fn any_scan() -> impl Strategy<Value = Scan> {
    (
        prop_oneof![4 => -3.2f64..3.2, 1 => Just(f64::NAN), 1 => Just(1e10)],
        common::any_increment(),
        prop_oneof![3 => Just(0.02), 1 => Just(0.0), 1 => Just(-1.0), 1 => Just(f64::NAN)],
        prop_oneof![3 => Just(5.6), 1 => Just(1e308), 1 => Just(f64::INFINITY), 1 => Just(0.01)],
        prop_oneof![
            1 => prop::collection::vec(common::any_range(6), 0..2),
            4 => prop::collection::vec(common::any_range(6), 0..700),
        ],
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

/// Piecewise-smooth scans: runs of walls (the first one long: 40+ beams and 0.25+ m, more
/// than the smallest surface any extractor keeps) seen at incidences of at least 30 deg, with
/// noise and a few dropouts, forwards or reversed.
fn wall_scan() -> impl Strategy<Value = Scan> {
    (
        (0.3f64..3.0, -1.0f64..1.0, 40usize..150),
        prop::collection::vec((0.3f64..3.0, -1.0f64..1.0, 3usize..120), 0..7),
        any::<u64>(),
        prop::bool::ANY,
    )
        .prop_map(|(mut long, mut walls, seed, reversed)| {
            let inc = increment();
            long.2 = long.2.max((0.25 / (long.0 * inc)).ceil() as usize);
            walls.insert(0, long);
            let mut ranges = Vec::new();
            let mut rng = Rng(seed);
            let mut i = 0usize;
            for (r, offset, n) in walls {
                // The wall's normal, relative to the beam in the middle of its run.
                let alpha = -2.0 + (i as f64 + 0.5 * n as f64) * inc + offset;
                for _ in 0..n {
                    let phi = -2.0 + i as f64 * inc;
                    let c = (phi - alpha).cos();
                    let dropout = rng.unit() < 0.02;
                    ranges.push(if c > 0.05 && !dropout {
                        let range = r / c;
                        range + sigma(range) * rng.gauss()
                    } else {
                        f64::NAN
                    });
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

fn check_invariants(name: &str, scan: &Scan, lines: &[Line]) {
    let mut prev_last: Option<usize> = None;
    let window = scan.range_window(None);
    let n = scan.len();
    for (k, l) in lines.iter().enumerate() {
        assert!(
            l.first < n && l.last < n,
            "{name}: index out of range: {l:?}"
        );
        // Only the last line of a full turn may run across its seam, clear of the first.
        if l.wraps() {
            assert!(
                scan.full_turn() && k + 1 == lines.len(),
                "{name}: {lines:?}"
            );
            assert!(k == 0 || l.last < lines[0].first, "{name}: {lines:?}");
        }
        assert!(l.points >= 2 && l.points <= l.beam_span(n), "{name}: {l:?}");
        if let Some(p) = prev_last {
            assert!(
                l.first > p,
                "{name}: lines share or reorder beams: {lines:?}"
            );
        }
        prev_last = Some(l.last);
        for v in [l.r, l.alpha, l.rms, l.start.x, l.start.y, l.end.x, l.end.y] {
            assert!(v.is_finite(), "{name}: non-finite value in {l:?}");
        }
        for v in l.covariance.iter() {
            assert!(!v.is_nan(), "{name}: NaN covariance in {l:?}");
        }
        assert!(l.r >= 0.0, "{name}: {l:?}");
        // Both ends are valid measurements, and there are enough valid beams between them.
        assert!(window.contains(scan.ranges[l.first]) && window.contains(scan.ranges[l.last]));
        let valid = beams(l.first, l.last, n)
            .filter(|&i| window.contains(scan.ranges[i]))
            .count();
        assert!(valid >= l.points, "{name}: {l:?}");
    }
}

fn all_extractors() -> Vec<Box<dyn LineExtractor + Send>> {
    ALGORITHMS
        .iter()
        .filter_map(|n| extractors::by_name(n))
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn arbitrary_scans_never_break_invariants(scan in any_scan()) {
        let all = all_extractors();
        prop_assert_eq!(all.len(), ALGORITHMS.len());
        for mut e in all {
            let name = e.name();
            let first = e.extract(&scan);
            check_invariants(name, &scan, &first);
            // A scan with broken geometry or limits gives no line.
            if scan.validate().is_err() {
                prop_assert!(first.is_empty(), "{}: lines from an invalid scan", name);
            }
            // The same scan gives the same lines, on a reused and on a fresh extractor.
            let second = e.extract(&scan);
            prop_assert_eq!(&first, &second, "{}", name);
            let fresh = extractors::by_name(name).unwrap().extract(&scan);
            prop_assert_eq!(&first, &fresh, "{}", name);
        }
    }

    #[test]
    fn wall_scans_give_lines(scan in wall_scan()) {
        for mut e in all_extractors() {
            let lines = e.extract(&scan);
            check_invariants(e.name(), &scan, &lines);
            prop_assert!(!lines.is_empty(), "{}: no line from a scan of walls", e.name());
            prop_assert_eq!(&lines, &e.extract(&scan));
        }
    }

    #[test]
    fn seeded_extractors_are_deterministic_for_any_seed(scan in wall_scan(), seed in any::<u64>()) {
        let mut r = extractors::Ransac::new(RansacParams { seed, ..RansacParams::default() }).unwrap();
        let a = r.extract(&scan);
        check_invariants("ransac", &scan, &a);
        prop_assert_eq!(&a, &r.extract(&scan));
        let mut m = extractors::Em::new(EmParams { seed, ..EmParams::default() }).unwrap();
        let b = m.extract(&scan);
        check_invariants("em", &scan, &b);
        prop_assert_eq!(&b, &m.extract(&scan));
    }
}

/// Any float, valid or not, for a parameter.
fn any_param() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => 0.0f64..0.3,
        1 => 0.3f64..3.0,
        1 => Just(0.0),
        1 => Just(-1.0),
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(1e-12),
    ]
}

/// Any count for a parameter (bounded where the count is a work budget).
fn any_count() -> impl Strategy<Value = usize> {
    prop_oneof![4 => 0usize..20, 1 => Just(1usize), 1 => 100usize..1000, 1 => Just(usize::MAX)]
}

/// A work budget capped so that the test stays fast.
fn budget(x: usize) -> usize {
    x.min(300)
}

/// An extractor of kind `kind` (1..=7, the order of [`ALGORITHMS`]) built from arbitrary
/// parameters, or `None` when they are rejected. Work budgets are capped so the test stays fast.
fn build(kind: usize, f: &[f64], c: &[usize], seed: u64) -> Option<Box<dyn LineExtractor>> {
    match kind {
        1 => build_iterative_hough(f, c, seed),
        2 => build_split_and_merge(f, c, seed),
        3 => build_iepf(f, c, seed),
        4 => build_incremental(f, c, seed),
        5 => build_line_regression(f, c, seed),
        6 => build_ransac(f, c, seed),
        _ => build_em(f, c, seed),
    }
}

fn build_iterative_hough(f: &[f64], c: &[usize], seed: u64) -> Option<Box<dyn LineExtractor>> {
    Some(Box::new(
        IterativeHough::new(IterativeHoughParams {
            distance_step: f[0].max(0.01),
            max_distance: f[1] * 3.0,
            angle_step: (f[2] * 10.0).max(0.5f64.to_radians()),
            window: f[3],
            weight: if seed.is_multiple_of(2) {
                Weight::One
            } else {
                Weight::Range
            },
            min_votes: f[4] * 30.0,
            inlier_distance: f[5],
            inlier_distance_per_metre: f[6],
            refine_iterations: budget(c[0]),
            max_skipped: c[1],
            breakpoints: Breakpoints {
                incidence: f[7] * 5.0,
                noise: f[8],
                max_gap: c[2],
            },
            max_iterations: budget(c[3]),
            filter: LineFilter {
                min_points: c[4],
                min_length: f[9],
            },
            range_limits: None,
        })
        .ok()?,
    ))
}

fn build_split_and_merge(f: &[f64], c: &[usize], seed: u64) -> Option<Box<dyn LineExtractor>> {
    Some(Box::new(
        SplitMerge::new(
            SplitLine::LeastSquares,
            SplitMergeParams {
                breakpoints: Breakpoints {
                    incidence: f[0] * 5.0,
                    noise: f[1],
                    max_gap: c[0],
                },
                min_cluster_points: c[1],
                split_distance: f[2],
                split_distance_per_metre: f[3],
                merge_collinear: seed.is_multiple_of(2),
                filter: LineFilter {
                    min_points: c[2],
                    min_length: f[4],
                },
                range_limits: None,
            },
        )
        .ok()?,
    ))
}

fn build_iepf(f: &[f64], c: &[usize], seed: u64) -> Option<Box<dyn LineExtractor>> {
    Some(Box::new(
        SplitMerge::new(
            SplitLine::Chord,
            SplitMergeParams {
                breakpoints: Breakpoints {
                    incidence: f[0] * 5.0,
                    noise: f[1],
                    max_gap: c[0],
                },
                min_cluster_points: c[1],
                split_distance: f[2],
                split_distance_per_metre: f[3],
                merge_collinear: seed.is_multiple_of(2),
                filter: LineFilter {
                    min_points: c[2],
                    min_length: f[4],
                },
                range_limits: None,
            },
        )
        .ok()?,
    ))
}

fn build_incremental(f: &[f64], c: &[usize], _seed: u64) -> Option<Box<dyn LineExtractor>> {
    Some(Box::new(
        Incremental::new(IncrementalParams {
            breakpoints: Breakpoints {
                incidence: f[0] * 5.0,
                noise: f[1],
                max_gap: c[0],
            },
            seed_points: c[1],
            track_distance: f[2],
            track_distance_per_metre: f[3],
            max_outliers: c[2],
            filter: LineFilter {
                min_points: c[3],
                min_length: f[4],
            },
            range_limits: None,
        })
        .ok()?,
    ))
}

fn build_line_regression(f: &[f64], c: &[usize], seed: u64) -> Option<Box<dyn LineExtractor>> {
    Some(Box::new(
        LineRegression::new(LineRegressionParams {
            breakpoints: Breakpoints {
                incidence: f[0] * 5.0,
                noise: f[1],
                max_gap: c[0],
            },
            window: c[1],
            noise_sigma: f[2],
            noise_sigma_per_metre: f[3],
            similarity: f[4] * 30.0,
            min_windows: c[2],
            merge_collinear: seed.is_multiple_of(2),
            merge_distance: f[5],
            merge_distance_per_metre: f[6],
            filter: LineFilter {
                min_points: c[3],
                min_length: f[7],
            },
            range_limits: None,
        })
        .ok()?,
    ))
}

fn build_ransac(f: &[f64], c: &[usize], seed: u64) -> Option<Box<dyn LineExtractor>> {
    Some(Box::new(
        Ransac::new(RansacParams {
            seed,
            iterations: budget(c[0]),
            sample_span: c[1],
            inlier_distance: f[0],
            inlier_distance_per_metre: f[1],
            min_inliers: c[2],
            max_skipped: c[3],
            refine_iterations: budget(c[4]),
            breakpoints: Breakpoints {
                incidence: f[2] * 5.0,
                noise: f[3],
                max_gap: c[5],
            },
            max_lines: budget(c[6]),
            filter: LineFilter {
                min_points: c[7],
                min_length: f[4],
            },
            range_limits: None,
        })
        .ok()?,
    ))
}

fn build_em(f: &[f64], c: &[usize], seed: u64) -> Option<Box<dyn LineExtractor>> {
    Some(Box::new(
        Em::new(EmParams {
            seed,
            max_trials: budget(c[0]),
            max_failures: c[1],
            init_points: c[2],
            iterations: budget(c[3]),
            anneal_sigma_scale: 1.0 + f[0] * 10.0,
            noise_sigma: f[1],
            noise_sigma_per_metre: f[2],
            outlier_density: f[3],
            inlier_probability: f[4],
            max_skipped: c[4],
            breakpoints: Breakpoints {
                incidence: f[5] * 5.0,
                noise: f[6],
                max_gap: c[5],
            },
            filter: LineFilter {
                min_points: c[6],
                min_length: f[7],
            },
            range_limits: None,
        })
        .ok()?,
    ))
}

/// Scans of at most 200 beams: arbitrary, or walls.
fn small_scan() -> impl Strategy<Value = Scan> {
    prop_oneof![any_scan(), wall_scan()].prop_map(|mut s| {
        s.ranges.truncate(200);
        s
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn arbitrary_params_never_break_invariants(
        kind in 1usize..=7,
        in_domain in prop::collection::vec(1e-4f64..0.3, 10),
        anything in prop::collection::vec(any_param(), 10),
        valid in prop::bool::weighted(0.8),
        c in prop::collection::vec(any_count(), 8),
        seed in any::<u64>(),
        scan in small_scan(),
    ) {
        // Mostly parameters in their domains (so that extraction runs), sometimes anything.
        let f = if valid { in_domain } else { anything };
        if let Some(mut e) = build(kind, &f, &c, seed) {
            prop_assert_eq!(e.name(), ALGORITHMS[kind]);
            let first = e.extract(&scan);
            check_invariants(e.name(), &scan, &first);
            prop_assert_eq!(&first, &e.extract(&scan));
        }
    }
}

/// A scan proptest once found (two walls meeting at a shallow angle, a recess between them, the
/// beams clockwise): `em` converged across the two walls, cut each into runs shorter than its
/// filter's minimum length, took them, and gave no line at all.
#[test]
fn em_keeps_walls_a_hypothesis_across_two_walls_cut_short() {
    let ranges = vec![
        0.6112,
        0.6076,
        0.6110,
        0.6106,
        0.6129,
        0.6143,
        0.6148,
        0.6134,
        0.6230,
        0.6219,
        0.6212,
        0.6222,
        0.6253,
        0.6264,
        0.6279,
        0.6326,
        0.6314,
        0.6338,
        0.6356,
        0.6370,
        0.6336,
        0.6405,
        0.6419,
        0.6466,
        0.6482,
        0.6465,
        0.6538,
        0.6530,
        0.6558,
        0.6578,
        0.6658,
        0.6631,
        0.6640,
        0.6717,
        0.6686,
        0.6749,
        0.6763,
        0.6796,
        0.6791,
        0.6842,
        0.6840,
        0.6912,
        0.6947,
        0.6934,
        0.7005,
        0.7052,
        0.7000,
        0.7088,
        0.7102,
        0.7138,
        0.7145,
        1.0485,
        1.0466,
        1.0463,
        1.0487,
        1.0465,
        1.0516,
        1.0464,
        1.0478,
        1.0462,
        1.0451,
        1.0422,
        1.0446,
        1.0397,
        1.0435,
        1.0457,
        1.0429,
        1.0432,
        1.0399,
        1.0457,
        1.0424,
        1.0439,
        1.0448,
        1.0428,
        1.0429,
        1.0435,
        1.0442,
        1.0452,
        1.0443,
        1.0451,
        1.0460,
        1.04716,
        1.0466,
        1.0459,
        1.0483,
        f64::NAN,
        1.0474,
        1.0482,
        0.7878,
        0.7905,
        0.7887,
        0.7910,
        0.7961,
        0.7922,
        0.7916,
        0.7943,
        0.7978,
        0.8018,
        0.7989,
        0.7952,
        0.8049,
        0.7990,
        f64::NAN,
        0.8050,
        0.8076,
        0.8078,
        0.8080,
        0.8114,
        0.8163,
        0.8171,
        0.8175,
        0.8203,
        0.8225,
        0.8221,
        0.8255,
        0.8303,
        0.8262,
        0.8273,
        0.8290,
        0.8352,
        0.8369,
        0.8403,
        0.8390,
        0.8417,
        0.8485,
        0.8502,
        0.8493,
        0.8533,
        0.8547,
        0.8590,
        0.8596,
        0.8659,
        0.8651,
        0.8692,
        0.8749,
        0.8756,
        0.8796,
        0.8759,
        0.8818,
        0.8905,
        0.8897,
        0.8952,
        0.8932,
        0.9013,
        0.9055,
    ];
    let scan = Scan {
        angle_min: -1.1164,
        angle_increment: -0.006_135_923_151_542_565,
        range_min: 0.02,
        range_max: 5.6,
        ranges,
        intensities: None,
        stamp: None,
    };
    let lines = extractors::by_name("em").unwrap().extract(&scan);
    check_invariants("em", &scan, &lines);
    // The two walls (beams 0-50 and 88-146) and the recess (51-87) are each 0.15 m or more.
    assert_eq!(lines.len(), 3, "{lines:?}");
}
