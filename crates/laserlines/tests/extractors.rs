//! The classic extractors: known walls recovered from analytic scans, exact noise-free
//! walls, seeds, and bad parameters named. (Invariants on arbitrary scans and parameters are
//! in `extractor_props.rs`; the full Hough accumulator in `hough_accumulator.rs`.)

use laserlines::extractors::{self, ALGORITHMS, EmParams, RansacParams};
use laserlines::math::{Point2, Vector2, angle_diff};
mod common;

use common::{BEAMS, Rng, angle_min, increment, sigma};
use laserlines::{Line, LineExtractor, Scan};

// ---------------------------------------------------------------------------------------------
// Analytic scenes.

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
        match cast(&walls, dir) {
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
    let scan = Scan {
        angle_min: angle_min(),
        angle_increment: increment(),
        range_min: 0.02,
        range_max: 5.6,
        ranges,
        intensities: None,
        stamp: None,
    };
    (scan, pieces(&walls, &hits))
}

/// The nearest wall the ray from the origin along `dir` meets: its range and index.
fn cast(walls: &[(Point2, Point2)], dir: Vector2) -> Option<(f64, usize)> {
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
    best
}

/// The visible wall pieces: maximal runs of consecutive beams on one wall.
fn pieces(walls: &[(Point2, Point2)], hits: &[Option<(usize, Point2)>]) -> Vec<Truth> {
    let mut truth: Vec<Truth> = Vec::new();
    let mut i = 0;
    while i < hits.len() {
        let Some((w, p)) = hits[i] else {
            i += 1;
            continue;
        };
        let mut j = i;
        while j + 1 < hits.len() && matches!(hits[j + 1], Some((w2, _)) if w2 == w) {
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
    truth
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
    assert!(e.to_string().contains("beyond the limit of"), "{e}");
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
