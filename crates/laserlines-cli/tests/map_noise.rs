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

/// Maps the log with `noise` added by three draws (seeds 1-3), each scored on the
/// relations: the translational (m) and rotational (deg) errors of each draw.
fn three_draws(log: &Path, relations: &Path, noise: (f64, f64)) -> [(f64, f64); 3] {
    [1, 2, 3].map(|seed| {
        let name = format!("mit-{}pc-{seed}", noise.1 * 100.0);
        let noisy = tmp(&format!("{name}.clf"));
        add_noise(log, &noisy, noise, seed);
        let (t, r, _) = map_and_score(&noisy, relations, &name);
        eprintln!("{name}: {t} m, {r} deg");
        // A noisy copy of the log and its map are megabytes each: not left behind.
        let _ = std::fs::remove_file(&noisy);
        let _ = std::fs::remove_dir_all(tmp(&name));
        (t, r)
    })
}

/// The middle of three values.
fn median(mut v: [f64; 3]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[1]
}

#[test]
fn mit_csail_maps_under_a_cheap_scanners_noise() {
    let Some((log, relations)) = mit_csail() else {
        return;
    };
    // Measured on seeds 1-3: 1 %: 0.038, 0.036 and 0.036 m, 0.42-0.44 deg (3-6 scans not
    // matched); the clean log 0.027 m and 0.34 deg. Every draw holds at 1 %.
    for (k, &(t, r)) in three_draws(&log, &relations, (0.01, 0.01))
        .iter()
        .enumerate()
    {
        assert!(
            t <= 0.05,
            "1 %, draw {}: translational error {t} m (bound 0.05 m)",
            k + 1
        );
        assert!(
            r <= 0.6,
            "1 %, draw {}: rotational error {r} deg (bound 0.6 deg)",
            k + 1
        );
    }
    // 2 %: 0.080, 0.095 and 0.066 m, 1.2-1.8 deg (136-162 scans not matched; before the
    // mixed-pixel test allowed for interleaved sweeps the first draw bent by 1.43 m). At this
    // noise a wrong match now and then bends part of the map (README, Mapping): the middle draw is
    // bounded, far below the log's odometry (1.68 m) and the neighbourhood normals alone
    // (1.62 m on one draw).
    let e = three_draws(&log, &relations, (0.02, 0.02));
    let (t, r) = (median(e.map(|e| e.0)), median(e.map(|e| e.1)));
    assert!(
        t <= 0.3,
        "2 %: middle translational error {t} m (bound 0.3 m): {e:?}"
    );
    assert!(
        r <= 3.5,
        "2 %: middle rotational error {r} deg (bound 3.5 deg): {e:?}"
    );
}
