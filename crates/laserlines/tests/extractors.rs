//! The classic extractors: known walls recovered from analytic scans, invariants on arbitrary
//! scans, and the full Hough accumulator against a slow, obviously right implementation.

use laserlines::extractors::{self, ALGORITHMS, EmParams, RansacParams};
use laserlines::hough::{HoughAccumulator, HoughGrid};
use laserlines::math::{Point2, Vector2, angle_diff};
use laserlines::{Line, LineExtractor, Scan, ScanPoint, Weight};
use proptest::prelude::*;

// ---------------------------------------------------------------------------------------------
// Analytic scenes.

/// SplitMix64, for the test's own noise.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn unit(&mut self) -> f64 {
        ((self.next() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// Standard normal (Box-Muller).
    fn gauss(&mut self) -> f64 {
        let (u, v) = (self.unit(), self.unit());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// The URG-04LX: 682 beams of 360/1024 deg, centred on x.
const BEAMS: usize = 682;
fn increment() -> f64 {
    (360.0f64 / 1024.0).to_radians()
}
fn angle_min() -> f64 {
    -0.5 * (BEAMS - 1) as f64 * increment()
}

/// Range noise of the test scans, standard deviation: 2 mm up to 1 m, 0.2 % beyond (a fifth
/// of the URG-04LX's accuracy, so that the corner beams, 2 cm apart, are told apart).
fn sigma(r: f64) -> f64 {
    0.002 * r.max(1.0)
}

/// A wall piece seen by beams `first..=last`, in the sensor frame.
#[derive(Debug, Clone)]
struct Truth {
    first: usize,
    last: usize,
    r: f64,
    alpha: f64,
    start: Point2,
    end: Point2,
}

struct Scene {
    name: &'static str,
    /// Walls in the world frame.
    walls: Vec<(Point2, Point2)>,
    /// Sensor pose in the world: position and heading.
    at: Point2,
    heading: f64,
}

/// Exact ray casting; beams that hit nothing are NaN. Returns the noisy scan and the visible
/// wall pieces (maximal runs of consecutive beams on the same wall).
fn simulate(scene: &Scene, seed: u64) -> (Scan, Vec<Truth>) {
    let (s, c) = scene.heading.sin_cos();
    let to_sensor = |p: Point2| {
        let d = p - scene.at;
        Point2::new(c * d.x + s * d.y, -s * d.x + c * d.y)
    };
    let walls: Vec<(Point2, Point2)> = scene
        .walls
        .iter()
        .map(|&(a, b)| (to_sensor(a), to_sensor(b)))
        .collect();
    let mut rng = Rng(seed);
    let mut ranges = Vec::with_capacity(BEAMS);
    let mut hits: Vec<Option<(usize, Point2)>> = Vec::with_capacity(BEAMS);
    for i in 0..BEAMS {
        let phi = angle_min() + i as f64 * increment();
        let dir = Vector2::new(phi.cos(), phi.sin());
        let mut best: Option<(f64, usize)> = None;
        for (w, &(a, b)) in walls.iter().enumerate() {
            // Solve t dir = a + u (b - a), t > 0, u in [0, 1].
            let e = b - a;
            let den = dir.x * (-e.y) - dir.y * (-e.x);
            if den.abs() < 1e-12 {
                continue;
            }
            let t = (a.x * (-e.y) - a.y * (-e.x)) / den;
            let u = (dir.x * a.y - dir.y * a.x) / den;
            if t > 1e-9 && (0.0..=1.0).contains(&u) && best.is_none_or(|(bt, _)| t < bt) {
                best = Some((t, w));
            }
        }
        match best {
            Some((t, w)) => {
                ranges.push(t + sigma(t) * rng.gauss());
                hits.push(Some((w, Point2::from(dir * t))));
            }
            None => {
                ranges.push(f64::NAN);
                hits.push(None);
            }
        }
    }
    let mut truth: Vec<Truth> = Vec::new();
    let mut i = 0;
    while i < BEAMS {
        let Some((w, p)) = hits[i] else {
            i += 1;
            continue;
        };
        let mut j = i;
        while j + 1 < BEAMS && matches!(hits[j + 1], Some((w2, _)) if w2 == w) {
            j += 1;
        }
        let (a, b) = walls[w];
        let e = (b - a).normalize();
        let mut n = Vector2::new(-e.y, e.x);
        let mut r = n.dot(&a.coords);
        if r < 0.0 {
            r = -r;
            n = -n;
        }
        let end = hits[j].map(|(_, q)| q).unwrap_or(p);
        truth.push(Truth {
            first: i,
            last: j,
            r,
            alpha: n.y.atan2(n.x),
            start: p,
            end,
        });
        i = j + 1;
    }
    let scan = Scan {
        angle_min: angle_min(),
        angle_increment: increment(),
        range_min: 0.02,
        range_max: 5.6,
        ranges,
        intensities: None,
        stamp: None,
    };
    (scan, truth)
}

fn p(x: f64, y: f64) -> Point2 {
    Point2::new(x, y)
}

/// A closed polygon's edges.
fn polygon(corners: &[Point2]) -> Vec<(Point2, Point2)> {
    (0..corners.len())
        .map(|k| (corners[k], corners[(k + 1) % corners.len()]))
        .collect()
}

fn scenes() -> Vec<Scene> {
    // A 0.5 m x 0.7 m box turned by 50 deg, centred at (1.3, 0.2): two faces visible.
    let (s, c) = 50f64.to_radians().sin_cos();
    let boxc: Vec<Point2> = [(-0.25, -0.35), (0.25, -0.35), (0.25, 0.35), (-0.25, 0.35)]
        .iter()
        .map(|&(x, y)| p(1.3 + c * x - s * y, 0.2 + s * x + c * y))
        .collect();
    let mut box_walls = vec![(p(2.5, -1.5), p(2.5, 2.0))];
    box_walls.extend(polygon(&boxc));
    vec![
        Scene {
            name: "square room",
            walls: polygon(&[p(-1.5, -1.5), p(1.5, -1.5), p(1.5, 1.5), p(-1.5, 1.5)]),
            at: p(0.2, -0.1),
            heading: 10f64.to_radians(),
        },
        Scene {
            name: "L corner",
            walls: vec![(p(1.5, -1.5), p(1.5, 1.5)), (p(1.5, 1.5), p(-1.5, 1.5))],
            at: p(0.0, 0.0),
            heading: -5f64.to_radians(),
        },
        Scene {
            name: "box in front of a wall",
            walls: box_walls,
            at: p(0.0, 0.0),
            heading: 0.0,
        },
    ]
}

/// Errors of one extracted line against its wall piece.
#[derive(Debug, Clone, Copy, Default)]
struct Errors {
    r: f64,
    alpha_deg: f64,
    end: f64,
}

impl Errors {
    fn max(self, o: Self) -> Self {
        Self {
            r: self.r.max(o.r),
            alpha_deg: self.alpha_deg.max(o.alpha_deg),
            end: self.end.max(o.end),
        }
    }
}

/// Matches each piece with the line overlapping it most; panics on a wrong count.
fn match_lines(name: &str, scene: &str, truth: &[Truth], lines: &[Line]) -> Errors {
    assert_eq!(
        lines.len(),
        truth.len(),
        "{name} on {scene}: {} lines for {} walls\nlines: {lines:#?}\ntruth: {truth:#?}",
        lines.len(),
        truth.len()
    );
    let mut worst = Errors::default();
    for t in truth {
        let overlap = |l: &Line| (l.last.min(t.last) + 1).saturating_sub(l.first.max(t.first));
        let l = lines
            .iter()
            .max_by_key(|l| overlap(l))
            .filter(|l| overlap(l) > 0)
            .unwrap_or_else(|| panic!("{name} on {scene}: no line for {t:?}"));
        let e = Errors {
            r: (l.r - t.r).abs(),
            alpha_deg: angle_diff(l.alpha, t.alpha).to_degrees(),
            end: (l.start - t.start).norm().max((l.end - t.end).norm()),
        };
        assert!(
            e.r <= 0.01 && e.alpha_deg <= 0.5 && e.end <= 0.03,
            "{name} on {scene}: {e:?}\nline {l:?}\ntruth {t:?}"
        );
        worst = worst.max(e);
    }
    worst
}

#[test]
fn scenes_have_substantial_pieces() {
    for scene in scenes() {
        let (scan, truth) = simulate(&scene, 1);
        assert_eq!(scan.validate(), Ok(()));
        assert!(truth.len() >= 2, "{}", scene.name);
        for t in &truth {
            assert!(t.last - t.first >= 30, "{}: {t:?}", scene.name);
            assert!((t.end - t.start).norm() >= 0.3, "{}: {t:?}", scene.name);
        }
    }
}

#[test]
fn every_extractor_recovers_known_walls() {
    let mut report = String::new();
    // `hough-split` (first) has its own round-trip tests.
    for name in &ALGORITHMS[1..] {
        let mut e = extractors::by_name(name).unwrap();
        let mut worst = Errors::default();
        for scene in scenes() {
            for seed in 1..=5 {
                let (scan, truth) = simulate(&scene, seed);
                let lines = e.extract(&scan);
                worst = worst.max(match_lines(name, scene.name, &truth, &lines));
            }
        }
        report.push_str(&format!(
            "{name:16} max |dr| {:5.2} mm  max |dalpha| {:5.3} deg  max end {:5.1} mm\n",
            worst.r * 1e3,
            worst.alpha_deg,
            worst.end * 1e3
        ));
    }
    println!("{report}");
}

#[test]
fn noise_free_walls_are_exact() {
    // Without noise every extractor's lines lie on the walls (the fit is exact).
    for name in ALGORITHMS {
        let mut e = extractors::by_name(name).unwrap();
        let scene = &scenes()[1];
        let (mut scan, truth) = simulate(scene, 0);
        // Redo without noise.
        for (i, r) in scan.ranges.iter_mut().enumerate() {
            if let Some(t) = truth.iter().find(|t| (t.first..=t.last).contains(&i)) {
                let phi = scan.angle_min + i as f64 * scan.angle_increment;
                *r = t.r / (phi - t.alpha).cos();
            }
        }
        let lines = e.extract(&scan);
        assert_eq!(lines.len(), 2, "{name}");
        for (l, t) in lines.iter().zip(&truth) {
            assert!(
                (l.r - t.r).abs() < 1e-9 && angle_diff(l.alpha, t.alpha) < 1e-9,
                "{name}"
            );
        }
    }
}

#[test]
fn random_extractors_depend_on_their_seed_only() {
    let (scan, _) = simulate(&scenes()[2], 3);
    for seed in [0, 1, u64::MAX] {
        let mut a = extractors::Ransac::new(RansacParams {
            seed,
            ..RansacParams::default()
        })
        .unwrap();
        let first = a.extract(&scan);
        assert_eq!(first, a.extract(&scan));
        let mut b = extractors::Em::new(EmParams {
            seed,
            ..EmParams::default()
        })
        .unwrap();
        let first = b.extract(&scan);
        assert_eq!(first, b.extract(&scan));
    }
}

#[test]
fn bad_params_are_rejected_with_the_field_named() {
    use laserlines::extractors::*;
    let e = IterativeHough::new(IterativeHoughParams {
        angle_step: 0.0,
        ..Default::default()
    })
    .unwrap_err();
    assert!(matches!(e, ParamsError::Grid(_)), "{e}");
    let e = IterativeHough::new(IterativeHoughParams {
        distance_step: 1e-7,
        ..Default::default()
    })
    .unwrap_err();
    assert!(e.to_string().contains("exceeds"), "{e}");
    let e = SplitMerge::new(
        SplitLine::LeastSquares,
        SplitMergeParams {
            split_distance: -1.0,
            ..Default::default()
        },
    )
    .unwrap_err();
    assert_eq!(
        e,
        ParamsError::Negative {
            field: "split_distance",
            value: -1.0
        }
    );
    assert!(
        SplitMerge::new(
            SplitLine::Chord,
            SplitMergeParams {
                breakpoints: Breakpoints {
                    incidence: 2.0,
                    ..Default::default()
                },
                ..Default::default()
            }
        )
        .is_err()
    );
    assert!(
        Incremental::new(IncrementalParams {
            seed_points: 2,
            ..Default::default()
        })
        .is_err()
    );
    assert!(
        LineRegression::new(LineRegressionParams {
            similarity: f64::NAN,
            ..Default::default()
        })
        .is_err()
    );
    assert!(
        Ransac::new(RansacParams {
            inlier_distance: 0.0,
            inlier_distance_per_metre: 0.0,
            ..Default::default()
        })
        .is_err()
    );
    assert!(
        Em::new(EmParams {
            inlier_probability: 1.0,
            ..Default::default()
        })
        .is_err()
    );
}

// ---------------------------------------------------------------------------------------------
// Invariants on arbitrary scans.

fn any_range() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => 0.02f64..6.0,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(0.0),
        1 => -10.0f64..0.0,
        1 => Just(1e300),
        1 => Just(f64::MIN_POSITIVE),
    ]
}

fn any_increment() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => 0.001f64..0.05,
        2 => -0.05f64..-0.001,
        1 => Just(0.0),
        1 => Just(f64::NAN),
        1 => Just(1e-300),
    ]
}

/// Scans with arbitrary values in every public field, valid or not, with 0 and 1 beams often.
fn any_scan() -> impl Strategy<Value = Scan> {
    (
        prop_oneof![4 => -3.2f64..3.2, 1 => Just(f64::NAN), 1 => Just(1e10)],
        any_increment(),
        prop_oneof![3 => Just(0.02), 1 => Just(0.0), 1 => Just(-1.0), 1 => Just(f64::NAN)],
        prop_oneof![3 => Just(5.6), 1 => Just(1e308), 1 => Just(f64::INFINITY), 1 => Just(0.01)],
        prop_oneof![
            1 => prop::collection::vec(any_range(), 0..2),
            4 => prop::collection::vec(any_range(), 0..700),
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
    for l in lines {
        assert!(l.first <= l.last, "{name}: first > last: {l:?}");
        assert!(l.last < scan.len(), "{name}: index out of range: {l:?}");
        assert!(
            l.points >= 2 && l.points <= l.last - l.first + 1,
            "{name}: {l:?}"
        );
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
        let valid = (l.first..=l.last)
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

/// An extractor of kind `kind` (1..=7, the order of [`ALGORITHMS`]) built from arbitrary
/// parameters, or `None` when they are rejected. Work budgets are capped so the test stays fast.
fn build(kind: usize, f: &[f64], c: &[usize], seed: u64) -> Option<Box<dyn LineExtractor>> {
    use laserlines::extractors::*;
    let budget = |x: usize| x.min(300);
    let e: Box<dyn LineExtractor> = match kind {
        1 => Box::new(
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
        ),
        2 => Box::new(
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
        ),
        3 => Box::new(
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
        ),
        4 => Box::new(
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
        ),
        5 => Box::new(
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
        ),
        6 => Box::new(
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
        ),
        _ => Box::new(
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
        ),
    };
    Some(e)
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

// ---------------------------------------------------------------------------------------------
// The full Hough accumulator against eq. (1) evaluated cell by cell.

/// `C(d_j, gamma_k) = sum_i w(r_i cos(phi_i - gamma_k) - d_j) g_i` with window half-width `a`.
fn slow_hough(acc: &HoughAccumulator, points: &[ScanPoint], a: f64, weight: Weight) -> Vec<f64> {
    let mut out = vec![0.0; acc.rows() * acc.columns()];
    for k in 0..acc.columns() {
        let gamma = acc.angle(k);
        for j in 0..acc.rows() {
            let d = acc.distance(j);
            for sp in points {
                if (sp.range * (sp.angle - gamma).cos() - d).abs() <= a {
                    out[k * acc.rows() + j] += match weight {
                        Weight::One => 1.0,
                        Weight::Range => sp.range,
                    };
                }
            }
        }
    }
    out
}

fn polar_points() -> impl Strategy<Value = Vec<ScanPoint>> {
    prop::collection::vec((0.05f64..7.0, -3.2f64..3.2), 0..25).prop_map(|v| {
        v.into_iter()
            .enumerate()
            .map(|(index, (range, angle))| ScanPoint {
                index,
                range,
                angle,
                point: Point2::new(range * angle.cos(), range * angle.sin()),
            })
            .collect()
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn full_hough_matches_eq_1_cell_by_cell(
        points in polar_points(),
        distance_step in 0.05f64..0.5,
        max_distance in 0.5f64..8.0,
        angle_step_deg in 3.0f64..20.0,
        window_steps in 0.3f64..2.0,
        range_weight in prop::bool::ANY,
    ) {
        let grid = HoughGrid {
            distance_step,
            max_distance,
            angle_step: angle_step_deg.to_radians(),
            window: window_steps * distance_step,
        };
        let weight = if range_weight { Weight::Range } else { Weight::One };
        let mut acc = HoughAccumulator::new(grid).unwrap();
        acc.build(points.iter(), weight);
        // Rounding may move a point sitting exactly on a window edge: bound the fast values by
        // the slow ones with the window shrunk and grown by a hair.
        let eps = 1e-9;
        let lo = slow_hough(&acc, &points, grid.window - eps, weight);
        let hi = slow_hough(&acc, &points, grid.window + eps, weight);
        for (i, &v) in acc.values().iter().enumerate() {
            prop_assert!(lo[i] - 1e-9 <= v && v <= hi[i] + 1e-9,
                "cell {} (row {}, column {}): fast {} slow {}..{}",
                i, i % acc.rows(), i / acc.rows(), v, lo[i], hi[i]);
        }
        // Every point votes in every column where its projection is on the grid.
        if weight == Weight::One && window_steps >= 0.5 {
            for k in 0..acc.columns() {
                let column: f64 = (0..acc.rows()).map(|j| acc.value(j, k)).sum();
                let inside = points.iter().filter(|sp| {
                    let x = sp.point.x * acc.angle(k).cos() + sp.point.y * acc.angle(k).sin();
                    x.abs() + grid.window + eps < acc.distance(acc.rows() - 1)
                }).count() as f64;
                prop_assert!(column >= inside);
            }
        }
        // The peak is the maximum.
        let max = acc.values().iter().cloned().fold(0.0, f64::max);
        match acc.peak() {
            Some(peak) => {
                prop_assert_eq!(peak.value, max);
                prop_assert_eq!(acc.value(peak.row, peak.column), max);
            }
            None => prop_assert_eq!(max, 0.0),
        }
    }
}
