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
//! standard errors under the simulated noise (independent normal errors); no fit of each
//! piece alone can expect more. Then `hough-split`'s TP rate, and that of fits that know the
//! truth ([`oracle_found`]): each piece's measured beams without its mixed pixels, weighted
//! by their noise across the wall, fitted alone and with the other pieces of its wall, a
//! reference that a segmentation of these beams rarely beats. A missed piece that such a fit
//! finds is marked so. `SCAN=NAME` (a scan's name as printed) also prints every piece, data
//! segment, split and line of that scan. The suite `arenas` takes its arenas from `ARENAS`,
//! `.raf` files separated by commas.

use laserlines::Line;
use laserlines::line::{beams, beams_shared};
use laserlines::registry;
use laserlines::{HoughSplit, HoughSplitParams, LineExtractor};
use laserlines_eval::truth::ExpectedPiece;
use laserlines_eval::workload::{BenchScan, Sensor, TEST_SEED, arena_scans, sensor, suite_scans};
use laserlines_eval::{MatchParams, match_lines};
use laserlines_sim::arena::{ArenaOptions, load_raf};

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
    let scans = if suite == "arenas" {
        arena_suite(seed, count, &sensor)
    } else {
        suite_scans(suite, seed, count, &sensor).map_err(Into::into)
    };
    let scans = match scans {
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
    let detail = std::env::var("SCAN").ok();
    let mut tally = Tally::default();
    let mut lines = Vec::new();
    for s in &scans {
        let Some(truth) = &s.truth else { continue };
        hs.extract_into(&s.scan, &mut lines);
        if detail.as_deref() == Some(s.name.as_str()) {
            print_detail(&hs, truth, &lines);
        }
        let found = oracle_found(&s.scan, truth, &params, &sensor.model.noise);
        tally.add(s, truth, &hs, &lines, &params, &found);
    }
    tally.print();
}

/// `count` scans in each arena of the `.raf` files listed in `ARENAS` (comma-separated).
fn arena_suite(
    seed: u64,
    count: usize,
    sensor: &Sensor,
) -> Result<Vec<BenchScan>, Box<dyn std::error::Error>> {
    let list = std::env::var("ARENAS").map_err(|_| "suite arenas needs ARENAS=a.raf,b.raf")?;
    let mut arenas = Vec::new();
    for path in list.split(',') {
        arenas.push(load_raf(
            std::path::Path::new(path),
            &ArenaOptions::default(),
        )?);
    }
    Ok(arena_scans(&arenas, seed, count, sensor))
}

/// What [`main`] counts over the scans.
#[derive(Default)]
struct Tally {
    /// Significant pieces.
    significant: usize,
    /// Sum over them of the chance that an ideal fit of their own beams is right.
    ceiling: f64,
    /// Found by `hough-split`.
    extracted: usize,
    /// Found by the fit that knows the truth: of the piece alone, of it alone or of its wall.
    oracle: [usize; 2],
    /// Missed by `hough-split`, found by the fit that knows the truth.
    findable_missed: usize,
    /// Found by `hough-split`, not by the fit that knows the truth.
    beyond_oracle: usize,
}

impl Tally {
    /// Counts one scan and prints what `hough-split` got wrong on it.
    fn add(
        &mut self,
        s: &BenchScan,
        truth: &[ExpectedPiece],
        hs: &HoughSplit,
        lines: &[Line],
        params: &MatchParams,
        found: &[(bool, bool)],
    ) {
        let m = match_lines(lines, truth, params);
        self.extracted += m.found;
        for (i, p) in truth.iter().enumerate().filter(|(_, p)| p.significant) {
            let (tr, ta) = params.tolerances(p);
            self.ceiling += within(tr, p.sigma_r) * within(ta, p.sigma_alpha);
            self.significant += 1;
            let (alone, either) = (found[i].0, found[i].0 || found[i].1);
            self.oracle[0] += usize::from(alone);
            self.oracle[1] += usize::from(either);
            let got = m.pairs.iter().any(|q| q.piece == i);
            self.beyond_oracle += usize::from(got && !either);
        }
        let missed: Vec<usize> = (0..truth.len())
            .filter(|&i| truth[i].significant && !m.pairs.iter().any(|p| p.piece == i))
            .collect();
        if missed.is_empty() && m.false_lines.is_empty() {
            return;
        }
        println!("{} noise {}", s.name, hs.stages().noise());
        for i in missed {
            let findable = found[i].0 || found[i].1;
            self.findable_missed += usize::from(findable);
            print_missed(i, &truth[i], lines, findable);
        }
        for &li in &m.false_lines {
            print_false_line(&lines[li], truth);
        }
    }

    /// The totals.
    fn print(&self) {
        let n = self.significant.max(1) as f64;
        println!(
            "ideal fit of each piece's own beams: TP rate {:.3} on average over {} significant pieces",
            self.ceiling / n,
            self.significant
        );
        println!("hough-split: TP rate {:.3}", self.extracted as f64 / n);
        println!(
            "fits that know the truth: TP rate {:.3} fitting each piece alone, {:.3} also \
             fitting all pieces of its wall together",
            self.oracle[0] as f64 / n,
            self.oracle[1] as f64 / n
        );
        println!(
            "missed pieces that a fit that knows the truth finds: {}; pieces found that it \
             does not: {}",
            self.findable_missed, self.beyond_oracle
        );
    }
}

/// Prints a false line and the piece whose beams it overlaps most.
fn print_false_line(l: &Line, truth: &[ExpectedPiece]) {
    let best = truth
        .iter()
        .enumerate()
        .max_by_key(|(_, p)| beams_shared((l.first, l.last), (p.first, p.last), p.scan_beams))
        .map(|(i, p)| format!("piece {i} ({})", piece_text(p)))
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

/// A piece as the listings show it.
fn piece_text(p: &ExpectedPiece) -> String {
    format!(
        "wall {} beams {}..{} r {:.3} alpha {:.1} len {:.2}",
        p.wall,
        p.first,
        p.last,
        p.r,
        p.alpha.to_degrees(),
        p.length()
    )
}

/// Per piece of `truth` (significant ones; `(false, false)` for the others): whether a fit of
/// exactly its measured beams lies within the tolerances, `(the piece alone, all pieces of its
/// wall)`. The fit knows the truth: points more than 5 of their sigmas across the true wall
/// (mixed pixels) are left out, the others weighted by `1 / (sigma(r) cos(incidence))^2`
/// (the cosine taken at least 0.1, sigma at least 0.1 mm). The joint fit skips the overlap
/// condition, so either fit being right is a reference that a segmentation of these beams
/// rarely beats (it can, piece by piece, by chance).
fn oracle_found(
    scan: &laserlines::Scan,
    truth: &[ExpectedPiece],
    params: &MatchParams,
    noise: &laserlines_sim::Noise,
) -> Vec<(bool, bool)> {
    let window = scan.range_window(None);
    // The beams of `q` as points `(x, y, sigma across p's wall)`.
    let points = |q: &ExpectedPiece, p: &ExpectedPiece| -> Vec<(f64, f64, f64)> {
        let normal = (p.alpha.cos(), p.alpha.sin());
        beams(q.first, q.last, q.scan_beams)
            .filter_map(|i| {
                let r = *scan.ranges.get(i)?;
                let (sin, cos) = scan.angle(i).sin_cos();
                let across =
                    (noise.sigma(r) * (cos * normal.0 + sin * normal.1).abs().max(0.1)).max(1e-4);
                let (x, y) = (r * cos, r * sin);
                let off = (x * normal.0 + y * normal.1 - p.r).abs();
                (window.contains(r) && off <= 5.0 * across).then_some((x, y, across))
            })
            .collect()
    };
    let passes = |fit: Option<(f64, f64)>, p: &ExpectedPiece| {
        let (tr, ta) = params.tolerances(p);
        fit.is_some_and(|(r, alpha)| {
            (r - p.r).abs() <= tr && laserlines::math::angle_diff(alpha, p.alpha).abs() <= ta
        })
    };
    let mut found = vec![(false, false); truth.len()];
    for (p, f) in truth.iter().zip(&mut found).filter(|(p, _)| p.significant) {
        let own = points(p, p);
        let wall: Vec<_> = truth
            .iter()
            .filter(|q| q.wall == p.wall)
            .flat_map(|q| points(q, p))
            .collect();
        *f = (
            passes(weighted_fit(&own), p),
            passes(weighted_fit(&wall), p),
        );
    }
    found
}

/// Weighted total least squares of `(x, y, sigma)` (weights `1 / sigma^2`): `(r, alpha)`.
fn weighted_fit(pts: &[(f64, f64, f64)]) -> Option<(f64, f64)> {
    let (mut w, mut sx, mut sy, mut count) = (0.0, 0.0, 0.0, 0);
    for &(x, y, sd) in pts {
        let wi = 1.0 / (sd * sd);
        (w, sx, sy, count) = (w + wi, sx + wi * x, sy + wi * y, count + 1);
    }
    if count < 2 {
        return None;
    }
    let (cx, cy) = (sx / w, sy / w);
    let (mut mxx, mut myy, mut mxy) = (0.0, 0.0, 0.0);
    for &(x, y, sd) in pts {
        let wi = 1.0 / (sd * sd);
        let (dx, dy) = (x - cx, y - cy);
        (mxx, myy, mxy) = (mxx + wi * dx * dx, myy + wi * dy * dy, mxy + wi * dx * dy);
    }
    let mut alpha = 0.5 * (-2.0 * mxy).atan2(myy - mxx);
    let mut r = cx * alpha.cos() + cy * alpha.sin();
    if r < 0.0 {
        r = -r;
        alpha += std::f64::consts::PI;
    }
    Some((r, laserlines::math::wrap_angle(alpha)))
}

/// Prints every piece, data segment, split and line of the last scan `hs` extracted.
fn print_detail(hs: &HoughSplit, truth: &[ExpectedPiece], lines: &[Line]) {
    for (i, p) in truth.iter().enumerate() {
        println!("piece {i}: {} significant {}", piece_text(p), p.significant);
    }
    let st = hs.stages();
    println!("removed beams {:?}", st.removed());
    for (seg, splits) in st.segments().zip(st.split_points()) {
        println!(
            "segment {}..{} ({} points), splits {splits:?}",
            seg.first, seg.last, seg.points
        );
    }
    for l in lines {
        println!(
            "line beams {}..{} r {:.3} alpha {:.1} len {:.2} n {} rms {:.4}",
            l.first,
            l.last,
            l.r,
            l.alpha.to_degrees(),
            l.length(),
            l.points,
            l.rms
        );
    }
}

/// Prints missed piece `i` and the line that overlaps it most, if any (with its errors and
/// standard errors).
fn print_missed(i: usize, p: &ExpectedPiece, lines: &[Line], findable: bool) {
    println!(
        "  missed piece {i}: {} sigma_r {:.4}{}",
        piece_text(p),
        p.sigma_r,
        if findable {
            " (a fit that knows the truth finds it)"
        } else {
            ""
        }
    );
    if let Some(l) = lines
        .iter()
        .max_by_key(|l| beams_shared((l.first, l.last), (p.first, p.last), p.scan_beams))
        .filter(|l| beams_shared((l.first, l.last), (p.first, p.last), p.scan_beams) > 0)
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
