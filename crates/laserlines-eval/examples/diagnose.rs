//! Lists what `hough-split` got wrong on a simulated suite: every missed significant piece
//! (with the line that overlaps it most, or "no line on it") and every false line, with the
//! scan it came from, so that a failure can be looked at.
//!
//! ```sh
//! cargo run --release -p laserlines-eval --example diagnose -- clutter urg04lx-full 40
//! FIELD=1 cargo run --release -p laserlines-eval --example diagnose -- all urg04lx-full 100
//! ```
//!
//! `FIELD=1` judges by the field criteria; `SEED=S` takes the scenes of seed `S` (default
//! the test suite's); `PRESET=NAME` starts from a preset of
//! `hough-split` (`complete`, ...) instead of its defaults. At the end it prints the TP rate
//! an ideal least-squares fit of exactly each significant piece's beams would reach on
//! average: the chance that its `r` and angle land within the tolerances, from the piece's
//! standard errors under the simulated noise (independent normal errors). No extractor can
//! expect more.

use laserlines::Line;
use laserlines::registry;
use laserlines::{HoughSplit, HoughSplitParams, LineExtractor};
use laserlines_eval::truth::ExpectedPiece;
use laserlines_eval::workload::{TEST_SEED, sensor, suite_scans};
use laserlines_eval::{MatchParams, match_lines};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let suite = args.get(1).map_or("all", String::as_str);
    let name = args.get(2).map_or("urg04lx-full", String::as_str);
    let count: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(20);
    let Some(sensor) = sensor(name) else {
        eprintln!("unknown sensor {name}");
        std::process::exit(2);
    };
    let seed = std::env::var("SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(TEST_SEED);
    let scans = match suite_scans(suite, seed, count, &sensor) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let params = match std::env::var("PRESET") {
        Ok(name) => match registry::HOUGH_SPLIT.preset(&name) {
            Some(p) => p,
            None => {
                eprintln!("unknown preset {name} of hough-split");
                std::process::exit(2);
            }
        },
        Err(_) => HoughSplitParams::default(),
    };
    let Ok(mut hs) = HoughSplit::new(params) else {
        return;
    };
    let params = if std::env::var("FIELD").is_ok() {
        MatchParams::field()
    } else {
        MatchParams::default()
    };
    let mut lines = Vec::new();
    let (mut ceiling, mut significant) = (0.0, 0usize);
    for s in &scans {
        let Some(truth) = &s.truth else { continue };
        for p in truth.iter().filter(|p| p.significant) {
            let (tr, ta) = params.tolerances(p);
            ceiling += within(tr, p.sigma_r) * within(ta, p.sigma_alpha);
            significant += 1;
        }
        hs.extract_into(&s.scan, &mut lines);
        let m = match_lines(&lines, truth, &params);
        let missed: Vec<usize> = (0..truth.len())
            .filter(|&i| truth[i].significant && !m.pairs.iter().any(|p| p.piece == i))
            .collect();
        if missed.is_empty() && m.false_lines.is_empty() {
            continue;
        }
        println!("{} noise {}", s.name, hs.stages().noise());
        for i in missed {
            print_missed(i, &truth[i], &lines);
        }
        for &li in &m.false_lines {
            let l = &lines[li];
            let best = truth
                .iter()
                .enumerate()
                .max_by_key(|(_, p)| (l.last.min(p.last) + 1).saturating_sub(l.first.max(p.first)))
                .map(|(i, p)| {
                    format!(
                        "piece {i} (wall {} beams {}..{} r {:.3} alpha {:.1})",
                        p.wall,
                        p.first,
                        p.last,
                        p.r,
                        p.alpha.to_degrees()
                    )
                })
                .unwrap_or_default();
            println!(
                "  false line beams {}..{} r {:.3} alpha {:.1} len {:.2} rms {:.4} n {} sd_alpha {:.2} deg range {:.2}; nearest {best}",
                l.first,
                l.last,
                l.r,
                l.alpha.to_degrees(),
                l.length(),
                l.rms,
                l.points,
                l.covariance[(1, 1)].sqrt().to_degrees(),
                ((l.start + l.end.coords) * 0.5).coords.norm()
            );
        }
    }
    println!(
        "ideal fit of each piece's own beams: TP rate {:.3} on average over {significant} significant pieces",
        ceiling / significant.max(1) as f64
    );
}

/// Prints missed piece `i` and the line that overlaps it most, if any (with its errors and
/// standard errors).
fn print_missed(i: usize, p: &ExpectedPiece, lines: &[Line]) {
    println!(
        "  missed piece {i}: wall {} beams {}..{} r {:.3} alpha {:.1} len {:.2} sigma_r {:.4}",
        p.wall,
        p.first,
        p.last,
        p.r,
        p.alpha.to_degrees(),
        p.length(),
        p.sigma_r
    );
    if let Some(l) = lines
        .iter()
        .max_by_key(|l| (l.last.min(p.last) + 1).saturating_sub(l.first.max(p.first)))
        .filter(|l| l.last >= p.first && l.first <= p.last)
    {
        println!(
            "    nearest line beams {}..{} dr {:.3} dalpha {:.1} n {} sd_r {:.4} sd_alpha {:.2}",
            l.first,
            l.last,
            l.r - p.r,
            laserlines::math::angle_diff(l.alpha, p.alpha)
                .abs()
                .to_degrees(),
            l.points,
            l.covariance[(0, 0)].sqrt(),
            l.covariance[(1, 1)].sqrt().to_degrees()
        );
    } else {
        println!("    no line on it");
    }
}

/// The chance that a normal error of standard deviation `sd` lies within `tol`.
fn within(tol: f64, sd: f64) -> f64 {
    if sd <= 0.0 {
        return 1.0;
    }
    erf(tol / (sd * std::f64::consts::SQRT_2))
}

/// The error function (Abramowitz and Stegun 7.1.26, error below 1.5e-7).
fn erf(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.327_591_1 * x.abs());
    let poly = t
        * (0.254_829_592
            + t * (-0.284_496_736
                + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    let y = 1.0 - poly * (-x * x).exp();
    if x < 0.0 { -y } else { y }
}
