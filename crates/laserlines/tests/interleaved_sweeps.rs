//! Scans of a scanner that fills its 0.5 deg steps with two interleaved 1 deg sweeps (a SICK
//! LMS in its 0.5 deg modes, as in the MIT CSAIL and Freiburg logs): the second sweep's
//! ranges sit a centimetre or two off the first's, so a straight wall reads as a zigzag of
//! neighbouring beams. The noise estimate, read two beams apart, sees one sweep alone; the
//! mixed-pixel test, which compares neighbouring beams, must allow for the offset, or it finds
//! every other beam off both its neighbours' lines and whole stretches of wall lose their
//! points.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use common::{Rng, hit};
use laserlines::math::Point2;
use laserlines::{HoughSplit, HoughSplitParams, LineExtractor, Scan};

/// 361 beams of 0.5 deg over 180 deg, centred on x.
const BEAMS: usize = 361;

fn angle(i: usize) -> f64 {
    (-90.0 + 0.5 * i as f64).to_radians()
}

/// A corridor 2.4 m wide seen from its middle, 1 m from its end wall: the true range of each
/// beam (its nearest wall).
fn truth() -> Vec<f64> {
    let p = Point2::new;
    let walls = [
        (p(-8.0, -1.2), p(1.0, -1.2)),
        (p(1.0, -1.2), p(1.0, 1.2)),
        (p(1.0, 1.2), p(-8.0, 1.2)),
    ];
    (0..BEAMS)
        .map(|i| {
            walls
                .iter()
                .filter_map(|&(a, b)| hit(angle(i), a, b))
                .fold(f64::INFINITY, f64::min)
        })
        .collect()
}

/// The corridor of true ranges `truth` read with the odd beams `offset` m long, 3 mm of
/// noise and 1 cm steps (as CARMEN logs print them).
fn scan(truth: &[f64], offset: f64, rng: &mut Rng) -> Scan {
    let ranges = truth
        .iter()
        .enumerate()
        .map(|(i, &r)| {
            let sweep = if i % 2 == 1 { offset } else { 0.0 };
            ((r + sweep + 0.003 * rng.gauss()) * 100.0).round() / 100.0
        })
        .collect();
    Scan::new(angle(0), 0.5f64.to_radians(), 0.0, 81.0, ranges).unwrap()
}

#[test]
fn walls_of_two_interleaved_sweeps_keep_their_points() {
    let mut rng = Rng(5);
    let mut hs = HoughSplit::new(HoughSplitParams::default()).unwrap();
    let truth = truth();
    let near: Vec<usize> = (0..BEAMS).filter(|&i| truth[i] < 3.0).collect();
    for offset in [0.0, 0.01, 0.015, 0.02] {
        for _ in 0..20 {
            let s = scan(&truth, offset, &mut rng);
            let lines = hs.extract(&s);
            // The side walls' far ends are read at a glancing angle: only the beams that see
            // a wall within 3 m are counted.
            let removed = hs.stages().removed();
            let lost = near.iter().filter(|i| removed.contains(i)).count();
            assert!(
                lost * 50 <= near.len(),
                "offset {offset}: {lost} of {} beams within 3 m removed",
                near.len()
            );
            // The end wall (x = 1 m, seen from 1 m) is one line through its beams.
            let end: Vec<_> = lines
                .iter()
                .filter(|l| (l.r - 1.0).abs() < 0.03 && l.alpha.cos() > 0.999)
                .collect();
            assert_eq!(end.len(), 1, "offset {offset}: {lines:?}");
            assert!(end[0].length() > 2.0, "offset {offset}: {:?}", end[0]);
        }
    }
}
