//! Every extractor on the simulator's scene suites (URG-04LX model: 682 beams, noise sigma
//! 5 mm up to 1 m and 0.5 % beyond, 1 mm rounding), scored against the ground truth.
//!
//! A significant visible piece (10+ beams, 0.2+ m) is found when one line covers at least half
//! of its beams with `|dr| <= 5 cm` and `dalpha <= 3 deg`; a line is false when it covers no
//! significant piece's beams by half of its own. These are loose, sanity-level criteria: the
//! benchmark reports the exact metrics. The test prints the table (`--nocapture`).

use laserlines::Line;
use laserlines::extractors::{self, ALGORITHMS};
use laserlines::math::angle_diff;
use laserlines_sim::scenes;
use laserlines_sim::simulation::VisiblePiece;
use laserlines_sim::{LaserModel, Rng};

/// Beams shared by `[a0, a1]` and `[b0, b1]`.
fn overlap(a0: usize, a1: usize, b0: usize, b1: usize) -> usize {
    (a1.min(b1) + 1).saturating_sub(a0.max(b0))
}

fn covers(l: &Line, p: &VisiblePiece) -> bool {
    2 * overlap(l.first, l.last, p.first, p.last) >= p.beams
        && (l.r - p.r).abs() <= 0.05
        && angle_diff(l.alpha, p.alpha) <= 3f64.to_radians()
}

#[derive(Default)]
struct Score {
    pieces: usize,
    found: usize,
    lines: usize,
    false_lines: usize,
    sq_r: f64,
    sq_alpha: f64,
}

#[test]
fn extractors_find_the_simulated_walls() {
    let model = LaserModel::urg04lx();
    let suites = [
        "rooms",
        "corridors",
        "maze",
        "boxes",
        "clutter",
        "glancing",
        "far",
    ];
    let mut table =
        String::from("suite      algorithm        TP rate  FP rate  rms dr mm  rms da deg\n");
    for suite in suites {
        let scenes = scenes::suite(suite, 11, 12).unwrap();
        let sims: Vec<_> = scenes
            .iter()
            .enumerate()
            .map(|(k, s)| s.simulate(&model, &mut Rng::new(1000 + k as u64)))
            .collect();
        for name in ALGORITHMS {
            let mut e = extractors::by_name(name).unwrap();
            let mut s = Score::default();
            for sim in &sims {
                let lines = e.extract(&sim.scan);
                let pieces: Vec<&VisiblePiece> = sim.truth.significant_pieces().collect();
                s.pieces += pieces.len();
                s.lines += lines.len();
                for p in &pieces {
                    if let Some(l) = lines.iter().find(|l| covers(l, p)) {
                        s.found += 1;
                        s.sq_r += (l.r - p.r).powi(2);
                        s.sq_alpha += angle_diff(l.alpha, p.alpha).to_degrees().powi(2);
                    }
                }
                for l in &lines {
                    let real = pieces
                        .iter()
                        .any(|p| 2 * overlap(l.first, l.last, p.first, p.last) > l.last - l.first);
                    if !real {
                        s.false_lines += 1;
                    }
                }
            }
            let tp = s.found as f64 / s.pieces.max(1) as f64;
            let fp = s.false_lines as f64 / s.lines.max(1) as f64;
            let found = s.found.max(1) as f64;
            table.push_str(&format!(
                "{suite:10} {name:16} {tp:7.3}  {fp:7.3}  {:9.2}  {:10.3}\n",
                (s.sq_r / found).sqrt() * 1e3,
                (s.sq_alpha / found).sqrt(),
            ));
            if suite == "rooms" || suite == "boxes" {
                assert!(tp >= 0.9, "{name} on {suite}: TP rate {tp}\n{table}");
            }
        }
    }
    println!("{table}");
}
