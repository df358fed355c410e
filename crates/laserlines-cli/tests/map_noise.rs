//! `laserlines map` on a real log read as a cheaper scanner would read it: the Freiburg
//! benchmark's MIT CSAIL log (a SICK LMS, about 1 cm of noise) with Gaussian noise added to
//! every range, 1 % and 2 % of the range (at least 1 and 2 cm), as triangulation scanners
//! (RPLIDAR, YDLIDAR) read. Scored on the benchmark's ground-truth relations (needs
//! `../shared`; a notice when it is absent).

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod common;

use std::io::{BufRead, Write};
use std::path::Path;

use common::{map_and_score, mit_csail, tmp};

/// A standard normal deviate from SplitMix64 (Box-Muller).
struct Gauss(u64);

impl Gauss {
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    fn next(&mut self) -> f64 {
        let u = self.unit().max(f64::MIN_POSITIVE);
        let v = self.unit();
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// Writes `log` (gzipped CARMEN) to `out` with `max(sigma_min, fraction r)` of noise added to
/// every `FLASER` range below 50 m (the log's "no return" readings stay as they are),
/// rounded to the millimetre as the log writes them.
fn add_noise(log: &Path, out: &Path, (sigma_min, fraction): (f64, f64), seed: u64) {
    let file = std::fs::File::open(log).unwrap();
    let plain =
        laserlines_io::open_input("mit-csail", Box::new(std::io::BufReader::new(file)), true)
            .unwrap();
    let mut w = std::io::BufWriter::new(std::fs::File::create(out).unwrap());
    let mut gauss = Gauss(seed);
    for line in plain.lines() {
        let line = line.unwrap();
        let mut t: Vec<String> = line.split_whitespace().map(str::to_owned).collect();
        if t.first().map(String::as_str) == Some("FLASER") {
            let n: usize = t[1].parse().unwrap();
            for token in &mut t[2..2 + n] {
                let r: f64 = token.parse().unwrap();
                if r > 0.0 && r < 50.0 {
                    let noisy = r + sigma_min.max(fraction * r) * gauss.next();
                    *token = format!("{:.3}", noisy.max(0.0));
                }
            }
            writeln!(w, "{}", t.join(" ")).unwrap();
        } else {
            writeln!(w, "{line}").unwrap();
        }
    }
    w.flush().unwrap();
}

#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "maps 1988 scans twice: needs optimisations, cargo test --release (.ci/run does)"
)]
fn mit_csail_maps_under_a_cheap_scanners_noise() {
    let Some((log, relations)) = mit_csail() else {
        return;
    };
    // Measured: 1 %: 0.038 m and 0.47 deg (5 scans not matched); 2 %: 0.074 m and 1.36 deg
    // (206 not matched); the clean log 0.027 m and 0.34 deg. With the normals of the points'
    // neighbourhoods alone (before the extracted lines gave theirs), on the same noise drawn
    // by another generator: 0.063 m, and 1.62 m with 566 of 1988 scans not matched.
    for (noise, bound_m, bound_deg) in [((0.01, 0.01), 0.05, 0.6), ((0.02, 0.02), 0.09, 2.0)] {
        let name = format!("mit-{}pc", noise.1 * 100.0);
        let noisy = tmp(&format!("{name}.clf"));
        add_noise(&log, &noisy, noise, 1);
        let (t, r, _) = map_and_score(&noisy, &relations, &name);
        eprintln!("{name}: {t} m, {r} deg");
        assert!(
            t <= bound_m,
            "{name}: translational error {t} m (bound {bound_m} m)"
        );
        assert!(
            r <= bound_deg,
            "{name}: rotational error {r} deg (bound {bound_deg} deg)"
        );
    }
}
