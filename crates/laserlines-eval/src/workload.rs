//! The scans a benchmark runs on: simulated scene suites with their ground truth, or any scans
//! without it (real logs).

use laserlines::Scan;
use laserlines_sim::rng::mix_seed;
use laserlines_sim::scenes::{self, ALL, SUITES, UnknownSuite};
use laserlines_sim::{LaserModel, Rng};

use crate::truth::{ExpectedPiece, expected_pieces};

/// Seed of the training suites, from which the extractors' default parameters were chosen.
pub const TRAIN_SEED: u64 = 1;
/// Seed of the test suites, on which the results are reported (other scenes, other noise).
pub const TEST_SEED: u64 = 2;
/// Scans per suite of a benchmark run, unless told otherwise.
pub const DEFAULT_SCANS_PER_SUITE: usize = 100;

/// The simulated sensors, by name, for [`sensor`].
pub const SENSORS: &[&str] = &["urg04lx", "urg04lx-artefacts"];

/// The sensor called `name` (one of [`SENSORS`]):
/// - `urg04lx`: [`LaserModel::urg04lx`], the paper's sensor with its data-sheet noise,
///   1 mm rounding, as the round-trip tests use it;
/// - `urg04lx-artefacts`: the same with mixed pixels at half of the depth edges and 1 % of
///   returns dropped.
#[must_use]
pub fn sensor(name: &str) -> Option<LaserModel> {
    match name {
        "urg04lx" => Some(LaserModel::urg04lx()),
        "urg04lx-artefacts" => Some(LaserModel {
            mixed_pixels: 0.5,
            dropout: 0.01,
            ..LaserModel::urg04lx()
        }),
        _ => None,
    }
}

/// One scan of a benchmark.
#[derive(Debug, Clone, PartialEq)]
pub struct BenchScan {
    /// What the scan is (`suite/k/kind` for simulated scans, `file:k` for logs).
    pub name: String,
    /// The group it is reported under (the suite, or the file).
    pub group: String,
    /// The scan.
    pub scan: Scan,
    /// The visible wall pieces, when known.
    pub truth: Option<Vec<ExpectedPiece>>,
}

/// `count` scans of each suite selected by `name` (one of [`SUITES`], or [`ALL`] for all of
/// them in that order), simulated with `model`. Scene `k` of a suite is the scene
/// [`scenes::suite`] generates for `seed`; its noise comes from a generator seeded from
/// `seed`, the suite and `k`, so the same arguments always give the same scans, and a longer
/// run extends a shorter one.
///
/// # Errors
/// [`UnknownSuite`] for an unknown suite name.
pub fn suite_scans(
    name: &str,
    seed: u64,
    count: usize,
    model: &LaserModel,
) -> Result<Vec<BenchScan>, UnknownSuite> {
    let names: Vec<&str> = if name == ALL {
        SUITES.to_vec()
    } else {
        vec![name]
    };
    let mut out = Vec::new();
    for (si, suite) in names.iter().enumerate() {
        let scenes = scenes::suite(suite, seed, count)?;
        for (k, scene) in scenes.iter().enumerate() {
            let stream = ((si as u64) << 40) ^ k as u64;
            let mut rng = Rng::new(mix_seed(mix_seed(seed, stream), 0x006E_6F69_7365));
            let sim = scene.simulate(model, &mut rng);
            out.push(BenchScan {
                name: scene.name.clone(),
                group: (*suite).to_string(),
                truth: Some(expected_pieces(&sim, &model.noise)),
                scan: sim.scan,
            });
        }
    }
    Ok(out)
}

/// Scans without ground truth (e.g. from a real log), grouped under `group`, named
/// `group:k`.
#[must_use]
pub fn plain_scans(group: &str, scans: impl IntoIterator<Item = Scan>) -> Vec<BenchScan> {
    scans
        .into_iter()
        .enumerate()
        .map(|(k, scan)| BenchScan {
            name: format!("{group}:{k}"),
            group: group.to_string(),
            scan,
            truth: None,
        })
        .collect()
}
