//! Round trips with known answers: scans simulated from known walls (URG-04LX model with its
//! noise), extracted, and compared with the simulator's ground truth.
//!
//! Every visible wall piece (a run of 10+ beams on one wall, 0.2+ m long) must come out as
//! exactly one line with r within 1 cm, alpha within 0.5 deg and end points within 3 cm; and
//! no line may stand where no wall is: both ends of every line lie on a wall its beams hit.
//!
//! The geometry is checked with [`HoughSplitParams::complete`]: the defaults differ from it
//! only by their line gates (a line's standard errors within 6 cm and 3 deg), which drop the
//! lines of far or glancing pieces whose `r` no fit can know that well; that they drop exactly
//! those lines and nothing else is `the_defaults_are_complete_less_the_gated_lines`.
//!
//! Where the sensor's noise makes a figure unreachable for any least-squares fit (short or
//! far pieces, end points seen at grazing incidence), the tolerance is widened to four times
//! the standard error an ideal fit of the piece's own beams would have under the simulated
//! noise, or to one and a half times the spacing of the beams at an end point (an end is known
//! only to a beam spacing); `Expected` computes both from the ground truth, never from the
//! extracted line.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines::math::{Point2, Vector2, angle_diff};
use laserlines::{HoughSplit, HoughSplitParams, Line, LineExtractor};
use laserlines_sim::scenes::{self, Scene};
use laserlines_sim::{LaserModel, Rng, SimScan, Target};

const R_TOL: f64 = 0.01;
const ALPHA_TOL: f64 = 0.5 * std::f64::consts::PI / 180.0;
const END_TOL: f64 = 0.03;
/// Standard errors allowed where the fixed tolerances are below what the noise permits.
const SIGMAS: f64 = 4.0;
/// Marks a failure by at most twice the tolerance: see [`run_scenes`].
const NEAR_MISS: &str = " (near miss)";

/// Standard errors of an ideal least-squares fit of beams `first..=last` of a wall with
/// normal `(r, alpha)`, under range noise `sigma(range)`.
struct Expected {
    r: f64,
    alpha: f64,
    start: f64,
    end: f64,
    /// Distance between the first two and between the last two beams' hits: an end point is
    /// known only to within the spacing of the beams there.
    start_spacing: f64,
    end_spacing: f64,
}

fn expected(sim: &SimScan, model: &LaserModel, first: usize, last: usize, alpha: f64) -> Expected {
    let n_hat = Vector2::new(alpha.cos(), alpha.sin());
    let dir = Vector2::new(-alpha.sin(), alpha.cos());
    let mut pts = Vec::new();
    for i in first..=last {
        let range = sim.truth.ranges[i];
        if !range.is_finite() {
            continue;
        }
        let phi = sim.scan.angle(i);
        let beam = Vector2::new(phi.cos(), phi.sin());
        let cos_inc = beam.dot(&n_hat).abs();
        let sigma = model.noise.sigma(range);
        // Range noise moves a point across the wall by sigma cos(inc), along it by sigma sin(inc).
        pts.push((
            beam * range,
            sigma * cos_inc,
            sigma * (1.0 - cos_inc * cos_inc).sqrt(),
        ));
    }
    let n = pts.len().max(1) as f64;
    let t_mean = pts.iter().map(|(p, _, _)| p.dot(&dir)).sum::<f64>() / n;
    let stt: f64 = pts
        .iter()
        .map(|(p, _, _)| (p.dot(&dir) - t_mean).powi(2))
        .sum();
    let var_c: f64 = pts.iter().map(|(_, s, _)| s * s).sum::<f64>() / (n * n);
    let var_a: f64 = if stt > 0.0 {
        pts.iter()
            .map(|(p, s, _)| (p.dot(&dir) - t_mean).powi(2) * s * s)
            .sum::<f64>()
            / (stt * stt)
    } else {
        f64::INFINITY
    };
    let cov_ca: f64 = if stt > 0.0 {
        pts.iter()
            .map(|(p, s, _)| (p.dot(&dir) - t_mean) * s * s)
            .sum::<f64>()
            / (n * stt)
    } else {
        0.0
    };
    // r = offset at the centroid, seen from the origin's foot: lever arm t_mean.
    let var_r = var_c + t_mean * t_mean * var_a - 2.0 * t_mean * cov_ca;
    let across_at = |t: f64| var_c + (t - t_mean).powi(2) * var_a + 2.0 * (t - t_mean) * cov_ca;
    let end_err = |k: usize| {
        pts.get(k).map_or(f64::INFINITY, |(p, _, along)| {
            (across_at(p.dot(&dir)).max(0.0) + along * along).sqrt()
        })
    };
    let spacing = |a: usize, b: usize| match (pts.get(a), pts.get(b)) {
        (Some((p, _, _)), Some((q, _, _))) => (p - q).norm(),
        _ => 0.0,
    };
    let k = pts.len().saturating_sub(1);
    Expected {
        start_spacing: spacing(0, 1),
        end_spacing: spacing(k, k.saturating_sub(1)),
        r: var_r.max(0.0).sqrt(),
        alpha: var_a.sqrt(),
        start: end_err(0),
        end: end_err(pts.len().saturating_sub(1)),
    }
}

/// The runs of seen beams in `first..=last` that no more than `max_gap` unseen beams in a row
/// interrupt, as `(first seen, last seen)`.
fn seen_runs(
    first: usize,
    last: usize,
    max_gap: usize,
    seen: impl Fn(usize) -> bool,
) -> Vec<(usize, usize)> {
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for i in (first..=last).filter(|&i| seen(i)) {
        match runs.last_mut() {
            Some(run) if i - run.1 <= max_gap + 1 => run.1 = i,
            _ => runs.push((i, i)),
        }
    }
    runs
}

/// Distance from `p` to the segment `a`-`b`.
fn to_segment(p: Point2, a: Point2, b: Point2) -> f64 {
    laserlines::line::distance_to_segment(p, a, b)
}

/// Checks one simulated scan of `scene`; returns a description of every failure and the
/// number of pieces whose tolerance the noise widened.
pub fn check_scan(
    scene: &Scene,
    model: &LaserModel,
    sim: &SimScan,
    lines: &[Line],
) -> (Vec<String>, usize) {
    let mut errors = Vec::new();
    let mut widened = 0;
    let max_gap = HoughSplitParams::default().bridge_max_gap;
    for whole in sim.truth.significant_pieces() {
        // A beam that hit the wall but whose return the noise pushed out of range (or the
        // sensor dropped) was not seen: a piece ends at its first and last seen beams, and
        // more than `bridge_max_gap` unseen beams in a row cut it (no line spans such a gap,
        // by design).
        let seen = |i: usize| sim.scan.range_window(None).contains(sim.scan.ranges[i]);
        for (first, last) in seen_runs(whole.first, whole.last, max_gap, seen) {
            let mut piece = *whole;
            if first != piece.first || last != piece.last {
                piece.start = sim.truth.point(&sim.scan, first).unwrap_or(piece.start);
                piece.end = sim.truth.point(&sim.scan, last).unwrap_or(piece.end);
                piece.first = first;
                piece.last = last;
                piece.beams = last - first + 1;
                if piece.beams < 10 || piece.length() < 0.2 {
                    continue;
                }
            }
            let piece = &piece;
            let overlapping: Vec<&Line> = lines
                .iter()
                .filter(|l| {
                    let lo = l.first.max(piece.first);
                    let hi = l.last.min(piece.last);
                    hi >= lo && (hi - lo + 1) * 2 >= piece.beams.min(l.last - l.first + 1)
                })
                .collect();
            let desc = format!(
                "piece on wall {} beams {}..={} (r {:.3}, alpha {:.2} deg, {:.2} m)",
                piece.wall,
                piece.first,
                piece.last,
                piece.r,
                piece.alpha.to_degrees(),
                piece.length()
            );
            let ex = expected(sim, model, piece.first, piece.last, piece.alpha);
            let tol_r = R_TOL.max(SIGMAS * ex.r);
            let tol_a = ALPHA_TOL.max(SIGMAS * ex.alpha);
            let tol_s = END_TOL.max(SIGMAS * ex.start).max(1.5 * ex.start_spacing);
            let tol_e = END_TOL.max(SIGMAS * ex.end).max(1.5 * ex.end_spacing);
            if tol_r > R_TOL || tol_a > ALPHA_TOL || tol_s > END_TOL || tol_e > END_TOL {
                widened += 1;
            }
            match overlapping.as_slice() {
                [] => errors.push(format!("{desc}: no line")),
                [l] => {
                    let dr = (l.r - piece.r).abs();
                    let da = angle_diff(l.alpha, piece.alpha);
                    let ds = (l.start - piece.start).norm();
                    let de = (l.end - piece.end).norm();
                    if dr > tol_r || da > tol_a || ds > tol_s || de > tol_e {
                        let worst = (dr / tol_r).max(da / tol_a).max(ds / tol_s).max(de / tol_e);
                        let near = if worst <= 2.0 { NEAR_MISS } else { "" };
                        errors.push(format!(
                        "{desc}{near}: line beams {}..={} off by r {dr:.4}/{tol_r:.4} m, alpha {:.3}/{:.3} deg, start {ds:.3}/{tol_s:.3} m, end {de:.3}/{tol_e:.3} m",
                        l.first,
                        l.last,
                        da.to_degrees(),
                        tol_a.to_degrees()
                    ));
                    }
                }
                many => errors.push(format!(
                    "{desc}: {} lines ({:?})",
                    many.len(),
                    many.iter().map(|l| (l.first, l.last)).collect::<Vec<_>>()
                )),
            }
        }
    }
    // No line where no wall is: both ends of every line lie on a wall its beams hit.
    let laser_from_world = scene.world_from_laser.inverse();
    for l in lines {
        let mut walls: Vec<usize> = (l.first..=l.last)
            .filter_map(|i| match sim.truth.beam_target.get(i) {
                Some(Some(Target::Wall(w))) => Some(*w),
                _ => None,
            })
            .collect();
        walls.sort_unstable();
        walls.dedup();
        let off_wall = |end: Point2, first: usize, last: usize| -> Option<(f64, f64)> {
            let mut best = (f64::INFINITY, END_TOL);
            for &w in &walls {
                let wall = &scene.world.walls[w];
                let (a, b) = (laser_from_world * wall.a, laser_from_world * wall.b);
                let alpha = laserlines_sim::world::polar_line(a, b).map_or(l.alpha, |(_, al)| al);
                let ex = expected(sim, model, first, last, alpha);
                let tol = END_TOL.max(SIGMAS * ex.start.max(ex.end));
                let d = to_segment(end, a, b);
                if d <= tol {
                    return None;
                }
                if d < best.0 {
                    best = (d, tol);
                }
            }
            Some(best)
        };
        for (name, end) in [("start", l.start), ("end", l.end)] {
            if let Some((d, tol)) = off_wall(end, l.first, l.last) {
                errors.push(format!(
                    "line beams {}..={} (r {:.3}, alpha {:.2} deg): {name} {d:.3} m from the walls its beams hit (tolerance {tol:.3} m)",
                    l.first,
                    l.last,
                    l.r,
                    l.alpha.to_degrees()
                ));
            }
        }
    }
    (errors, widened)
}

/// The round-trip scene kinds.
const KINDS: [fn(&mut Rng) -> Scene; 5] = [
    scenes::rectangular_room,
    scenes::corridor_with_door_gap,
    scenes::corner,
    scenes::boxes_in_room,
    scenes::grazing_wall,
];

/// Checks 20 seeded scenes of one kind. Every piece must come out as one line; within their
/// tolerances, except that one piece in a hundred (plus one) may miss them by at most twice
/// (a "near miss"): where a line ends is a statistical decision (an end point is trimmed when
/// its deviation has less than a 1 % chance as noise), and the simulated noise makes such
/// chances happen.
fn run_scenes(make: fn(&mut Rng) -> Scene, seeds: std::ops::Range<u64>) {
    let (pieces, failures) = check_scenes(make, seeds.clone());
    assert!(pieces >= seeds.count(), "scenes without pieces to find");
    let near = failures.iter().filter(|f| f.contains(NEAR_MISS)).count();
    assert!(
        near == failures.len() && near <= 1 + pieces / 100,
        "{} failures ({near} near misses, {} allowed):\n{}",
        failures.len(),
        1 + pieces / 100,
        failures.join("\n")
    );
}

/// Checks the scenes of `make` with `seeds`; prints and returns the pieces and the failures.
fn check_scenes(make: fn(&mut Rng) -> Scene, seeds: std::ops::Range<u64>) -> (usize, Vec<String>) {
    let model = LaserModel::urg04lx();
    let mut hs = HoughSplit::new(HoughSplitParams::complete()).unwrap();
    let mut failures = Vec::new();
    let mut pieces = 0;
    let mut widened = 0;
    for seed in seeds.clone() {
        let mut rng = Rng::new(seed);
        let scene = make(&mut rng);
        let sim = scene.simulate(&model, &mut rng);
        pieces += sim.truth.significant_pieces().count();
        let lines = hs.extract(&sim.scan);
        let (errors, w) = check_scan(&scene, &model, &sim, &lines);
        widened += w;
        for e in errors {
            failures.push(format!("{} seed {seed}: {e}", scene.name));
        }
    }
    println!("{pieces} pieces, {widened} with a tolerance widened by the noise");
    for f in &failures {
        println!("{f}");
    }
    (pieces, failures)
}

#[test]
fn rectangular_room() {
    run_scenes(scenes::rectangular_room, 0..20);
}

#[test]
fn corridor_with_door_gap() {
    run_scenes(scenes::corridor_with_door_gap, 0..20);
}

#[test]
fn corner() {
    run_scenes(scenes::corner, 0..20);
}

#[test]
fn boxes_in_room() {
    run_scenes(scenes::boxes_in_room, 0..20);
}

#[test]
fn grazing_wall() {
    run_scenes(scenes::grazing_wall, 0..20);
}

#[test]
fn bench_scan_gives_its_six_pieces() {
    let (scene, model) = scenes::bench_scene();
    let sim = scenes::bench_scan();
    assert_eq!(sim.truth.significant_pieces().count(), 6);
    let lines = HoughSplit::new(HoughSplitParams::default())
        .unwrap()
        .extract(&sim.scan);
    let (errors, _) = check_scan(&scene, &model, &sim, &lines);
    assert!(errors.is_empty(), "{}", errors.join("\n"));
}

/// The defaults give `complete`'s lines less those whose standard errors exceed their gates,
/// on every round-trip scene kind: the gates are a filter on the final lines (after lines of
/// one surface share their fit), and they bite.
#[test]
fn the_defaults_are_complete_less_the_gated_lines() {
    let model = LaserModel::urg04lx();
    let p = HoughSplitParams::default();
    let mut defaults = HoughSplit::new(p.clone()).unwrap();
    let mut complete = HoughSplit::new(HoughSplitParams::complete()).unwrap();
    let mut unshared = HoughSplit::new(HoughSplitParams {
        share_fits: false,
        ..HoughSplitParams::complete()
    })
    .unwrap();
    let passes = |l: &Line| {
        l.covariance[(0, 0)] <= p.max_r_sd * p.max_r_sd
            && l.covariance[(1, 1)] <= p.max_alpha_sd * p.max_alpha_sd
    };
    let mut gated = 0;
    for make in KINDS {
        for seed in 0..20 {
            let mut rng = Rng::new(seed);
            let sim = make(&mut rng).simulate(&model, &mut rng);
            let all = complete.extract(&sim.scan);
            // The same lines before sharing: the gates on their own fits decide which lines
            // share their corners.
            let own = unshared.extract(&sim.scan);
            assert_eq!(own.len(), all.len(), "seed {seed}");
            let kept: Vec<usize> = (0..all.len()).filter(|&i| passes(&all[i])).collect();
            gated += all.len() - kept.len();
            let got = defaults.extract(&sim.scan);
            assert_eq!(got.len(), kept.len(), "seed {seed}");
            // The same lines; an end point may differ only at or beside a line that the gates
            // dropped, or would have dropped on its own fit: lines certain on their own fits
            // share their corners.
            let key = |l: &Line| (l.first, l.last, l.points, l.r, l.alpha, l.rms, l.covariance);
            let uncertain = |k: usize| !passes(&all[k]) || !passes(&own[k]);
            for (g, &i) in got.iter().zip(&kept) {
                assert_eq!(key(g), key(&all[i]), "seed {seed}");
                let beside_gated = uncertain(i)
                    || (i > 0 && uncertain(i - 1))
                    || (i + 1 < all.len() && uncertain(i + 1));
                assert!(
                    beside_gated || (g.start == all[i].start && g.end == all[i].end),
                    "seed {seed}: {g:?} against {:?}",
                    all[i]
                );
            }
        }
    }
    // Measured: 10 of 362 lines.
    assert!(gated >= 3, "{gated} lines gated");
}

/// The same check on 60 further seeds of every scene kind, seeds the parameters were never
/// looked at on: at most 2 % of the pieces miss (the figure in the README); run with
/// `cargo test --release -p laserlines --test roundtrip -- --ignored --nocapture`.
#[test]
#[ignore = "held-out measurement for the README: run in release with --ignored"]
fn held_out_seeds() {
    let (mut pieces, mut failures) = (0, Vec::new());
    for make in KINDS {
        let (p, f) = check_scenes(make, 100..160);
        pieces += p;
        failures.extend(f);
    }
    let near = failures.iter().filter(|f| f.contains(NEAR_MISS)).count();
    println!(
        "held out: {} of {pieces} pieces miss ({near} by at most twice the tolerance)",
        failures.len()
    );
    assert!(failures.len() * 50 <= pieces, "{}", failures.join("\n"));
}
