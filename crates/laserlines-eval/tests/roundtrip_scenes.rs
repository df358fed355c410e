//! Every extractor, with its default parameters, on the round-trip scenes of `HoughSplit`
//! (rectangular rooms, corridors with a door gap, corners, boxes in rooms and walls seen at
//! grazing angles, seeds 0..20 each, URG-04LX model) and the standard bench scan, scored by
//! this crate's matching: a significant visible piece is found when one line overlaps its beams
//! by half (intersection over union) with `r` within `max(1 cm, 4 sigma_r)` and `alpha` within
//! `max(0.5 deg, 4 sigma_alpha)`, the tolerances of `HoughSplit`'s round-trip tests.
//!
//! Each extractor's documented tolerance is its least true-positive rate and largest
//! false-positive rate below ([`TOLERANCE`], also in the README). **These bounds are a
//! ratchet**: each is set just under what the extractor measures on these scenes today (the
//! README lists both), so that a change that makes any extractor worse here fails; they are
//! not targets, and are raised when an extractor improves. The requirements every extractor
//! must meet on every suite are in `suites.rs`. `hough-split` is held to finding 98 % of the
//! pieces here: its line gates drop the lines of far or glancing pieces whose `r` is known
//! worse than 6 cm even with the fit they share with the rest of their wall (5 of the 356
//! pieces; its `complete` preset, with looser gates, is held to end points as well by
//! `crates/laserlines/tests/roundtrip.rs`). On the
//! bench scan every extractor must find all six pieces with no false line, except EM, which
//! may get one of them wrong.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines::extractors::{self, ALGORITHMS};
use laserlines_eval::{MatchParams, TruthTally, expected_pieces};
use laserlines_sim::scenes::{self, Scene};
use laserlines_sim::{LaserModel, Rng, SimScan};

/// `(algorithm, least true-positive rate, largest false-positive rate)` on the round-trip
/// scenes: a ratchet, just under today's measured figures (see the module docs).
const TOLERANCE: &[(&str, f64, f64)] = &[
    ("hough-split", 0.98, 0.01),
    ("iterative-hough", 0.98, 0.01),
    ("split-and-merge", 0.98, 0.03),
    ("iepf", 0.98, 0.02),
    ("incremental", 0.98, 0.02),
    ("line-regression", 0.98, 0.01),
    ("ransac", 0.98, 0.01),
    ("em", 0.97, 0.04),
];

fn scans() -> Vec<(String, SimScan)> {
    let model = LaserModel::urg04lx();
    let makers: [fn(&mut Rng) -> Scene; 5] = [
        scenes::rectangular_room,
        scenes::corridor_with_door_gap,
        scenes::corner,
        scenes::boxes_in_room,
        scenes::grazing_wall,
    ];
    let mut out = Vec::new();
    for make in makers {
        for seed in 0..20 {
            let mut rng = Rng::new(seed);
            let scene = make(&mut rng);
            let sim = scene.simulate(&model, &mut rng);
            out.push((format!("{} seed {seed}", scene.name), sim));
        }
    }
    out
}

#[test]
fn every_extractor_finds_the_round_trip_walls_within_its_tolerance() {
    assert_eq!(TOLERANCE.len(), ALGORITHMS.len());
    let model = LaserModel::urg04lx();
    let sims = scans();
    let params = MatchParams::default();
    let mut report = String::new();
    let mut failures = Vec::new();
    for &(name, least_tp, most_fp) in TOLERANCE {
        let mut e = extractors::by_name(name).unwrap();
        let mut total = TruthTally::default();
        let mut missed = Vec::new();
        for (what, sim) in &sims {
            let pieces = expected_pieces(sim, &model.noise);
            let t = TruthTally::of_scan(&e.extract(&sim.scan), &pieces, &params);
            if t.found < t.pieces {
                missed.push(format!("{what}: {} of {}", t.found, t.pieces));
            }
            total.add(&t);
        }
        let m = total.metrics();
        report.push_str(&format!(
            "{name:16} TP {:.4} ({}/{}), FP {:.4} ({}/{})\n",
            m.true_positive_rate, m.found, m.pieces, m.false_positive_rate, m.false_lines, m.lines
        ));
        if m.true_positive_rate < least_tp || m.false_positive_rate > most_fp {
            failures.push(format!(
                "{name}: TP {:.4} (least {least_tp}), FP {:.4} (most {most_fp}); missed in {}",
                m.true_positive_rate,
                m.false_positive_rate,
                missed.join(", ")
            ));
        }
    }
    println!("{report}");
    assert!(failures.is_empty(), "{}\n{report}", failures.join("\n"));
}

#[test]
fn every_extractor_finds_the_six_pieces_of_the_bench_scan() {
    let (_, model) = scenes::bench_scene();
    let sim = scenes::bench_scan();
    let pieces = expected_pieces(&sim, &model.noise);
    assert_eq!(pieces.iter().filter(|p| p.significant).count(), 6);
    for name in ALGORITHMS {
        let lines = extractors::by_name(name).unwrap().extract(&sim.scan);
        let m = TruthTally::of_scan(&lines, &pieces, &MatchParams::default()).metrics();
        // EM's tolerance: one of the six may be wrong (the box's short face, whose corner
        // points the neighbouring face's hypothesis takes).
        let (least, most_false) = if *name == "em" { (5, 1) } else { (6, 0) };
        assert!(m.found >= least, "{name}: {m:?}");
        assert!(m.false_lines <= most_false, "{name}: {m:?}");
    }
}
