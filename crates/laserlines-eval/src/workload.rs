//! The scans a benchmark runs on: simulated scene suites with their ground truth, or any scans
//! without it (real logs).

use laserlines::{RangeNoise, Scan};
use laserlines_sim::arena::{Arena, arena_scenes};
use laserlines_sim::rng::mix_seed;
use laserlines_sim::scenes::{self, ALL, SUITES, Scene, UnknownSuite, add_legs};
use laserlines_sim::{LaserModel, Noise, Rng};

use crate::truth::{ExpectedPiece, expected_pieces};

/// Seed of the training suites, from which the extractors' default parameters were chosen.
pub const TRAIN_SEED: u64 = 1;
/// Seed of the test suites, on which the results are reported (other scenes, other noise).
pub const TEST_SEED: u64 = 2;
/// Scans per suite of a benchmark run, unless told otherwise.
pub const DEFAULT_SCANS_PER_SUITE: usize = 100;

/// The simulated sensors and conditions, by name, for [`sensor`].
pub const SENSORS: &[&str] = &[
    "urg04lx",
    "urg04lx-artefacts",
    "urg04lx-half",
    "urg04lx-full",
    "urg04lx-1.5x",
    "urg04lx-real",
    "utm30lx",
    "ust10lx",
    "lms1xx",
    "lms2xx",
    "rplidar-a1",
    "rplidar-a2",
    "ydlidar-x4",
    "kinect",
    "realsense-d435",
];

/// The noise levels of the field conditions (`urg04lx-half`, `-full`, `-1.5x`), as multiples
/// of the URG-04LX data sheet's band taken as one standard deviation.
pub const FIELD_LEVELS: &[(&str, f64)] = &[
    ("urg04lx-half", 0.5),
    ("urg04lx-full", 1.0),
    ("urg04lx-1.5x", 1.5),
];

/// A simulated sensor and the conditions of the scenes it sees.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sensor {
    /// The laser model. Its `dropout` is replaced per scan when `dropout` below is set.
    pub model: LaserModel,
    /// Per-scan dropout probability drawn uniformly from this range, when set.
    pub dropout: Option<(f64, f64)>,
    /// Chair and table legs added to every scene: up to this many (uniform from 0).
    pub legs: usize,
    /// Leg diameters, m.
    pub leg_diameter: (f64, f64),
    /// Share of the beams whose reading is spurious (sunlight, dust, a retroreflector's
    /// echo): replaced by a range drawn uniformly between the larger of `range_min` and
    /// 0.1 m and 0.1 m short of the nearer of `range_max` and 5.6 m (none when that leaves
    /// no room). The ground truth stays that of the clean scan.
    pub spurious: f64,
}

impl Sensor {
    /// `model` as it is, in the scenes as they are.
    #[must_use]
    pub fn plain(model: LaserModel) -> Self {
        Self {
            model,
            dropout: None,
            legs: 0,
            leg_diameter: (0.03, 0.12),
            spurious: 0.0,
        }
    }

    /// The factor from the noise the classic extractors' defaults were chosen for to this
    /// sensor's ([`laserlines::registry::noise_scale`]): 1 for the URG-04LX as simulated.
    #[must_use]
    pub fn noise_scale(&self) -> f64 {
        match self.model.noise {
            Noise::Range(n) => laserlines::registry::noise_scale(&n),
            Noise::Gaussian { sigma } => {
                laserlines::registry::noise_scale(&RangeNoise::new(sigma, 0.0))
            }
            // A depth camera's noise at 2 m, as a range noise's.
            Noise::Depth { .. } => laserlines::registry::noise_scale(&RangeNoise::new(
                self.model.noise.sigma(2.0),
                0.0,
            )),
            // A stepped noise has no one figure: the others keep the URG-04LX defaults.
            Noise::Urg04lx | Noise::None | Noise::Stepped { .. } => 1.0,
        }
    }

    /// The field conditions at `level` times the URG-04LX data sheet's band (+-10 mm to 1 m,
    /// +-1 % beyond, taken as one standard deviation): mixed pixels at half of the depth edges,
    /// 0-5 % of the returns dropped (drawn per scan), 0-8 chair and table legs of 3-12 cm
    /// diameter in every scene.
    #[must_use]
    pub fn field(level: f64) -> Self {
        Self {
            model: LaserModel {
                noise: Noise::Range(RangeNoise::new(0.01, 0.01).scaled(level)),
                mixed_pixels: 0.5,
                ..LaserModel::urg04lx()
            },
            dropout: Some((0.0, 0.05)),
            legs: 8,
            leg_diameter: (0.03, 0.12),
            spurious: 0.0,
        }
    }

    /// The field conditions of [`Sensor::field`] at the noise of a real URG-04LX: 4 mm
    /// (the BreezySLAM logs read 3-5 mm) below 3 m and the data sheet's 1 % of the range from
    /// there on, a step no `max(sigma_min, fraction r)` follows.
    #[must_use]
    pub fn field_real() -> Self {
        let mut s = Self::field(1.0);
        s.model.noise = Noise::Stepped {
            near: 0.004,
            knee: 3.0,
            fraction: 0.01,
        };
        s
    }
}

/// The sensor called `name` (one of [`SENSORS`], matched as
/// [`laserlines::noise::sensor_names_match`] matches names):
/// - `urg04lx`: [`LaserModel::urg04lx`], the paper's sensor with its data-sheet band read as
///   two standard deviations, 1 mm rounding, as the round-trip tests use it;
/// - `urg04lx-artefacts`: the same with mixed pixels at half of the depth edges and 1 % of
///   returns dropped;
/// - `urg04lx-half`, `urg04lx-full`, `urg04lx-1.5x`: the field conditions of
///   [`Sensor::field`] at half, once and 1.5 times the data sheet's band as one standard
///   deviation;
/// - `urg04lx-real`: the field conditions at a real URG-04LX's noise ([`Sensor::field_real`]);
/// - `utm30lx`, `ust10lx`, `lms1xx`, `lms2xx`, `rplidar-a1`, `rplidar-a2`, `ydlidar-x4`: other
///   scanners at their data sheet's noise, and `kinect`, `realsense-d435`: depth cameras read
///   as scans, in the field conditions ([`crate::scanners`]).
#[must_use]
pub fn sensor(name: &str) -> Option<Sensor> {
    // Spelt any way a model name is (`urg-04lx-full`, `UTM30LX`): one of SENSORS.
    let name = *SENSORS
        .iter()
        .find(|s| laserlines::noise::sensor_names_match(s, name))?;
    if let Some((_, level)) = FIELD_LEVELS.iter().find(|(n, _)| *n == name) {
        return Some(Sensor::field(*level));
    }
    match name {
        "urg04lx" => Some(Sensor::plain(LaserModel::urg04lx())),
        "urg04lx-real" => Some(Sensor::field_real()),
        "urg04lx-artefacts" => Some(Sensor::plain(LaserModel {
            mixed_pixels: 0.5,
            dropout: 0.01,
            ..LaserModel::urg04lx()
        })),
        other => crate::scanners::sensor(other),
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
    sensor: &Sensor,
) -> Result<Vec<BenchScan>, UnknownSuite> {
    let names: Vec<&str> = if name == ALL {
        SUITES.to_vec()
    } else {
        vec![name]
    };
    let mut out = Vec::new();
    for (si, suite) in names.iter().enumerate() {
        let scenes = scenes::suite(suite, seed, count)?;
        out.extend(simulate_scenes(suite, si as u64, &scenes, seed, sensor));
    }
    Ok(out)
}

/// Stream of the arena suite's scans (the scene suites use their position in the run: 0
/// for a single suite, their index in [`SUITES`] for `all`).
const ARENA_STREAM: u64 = 0x61;

/// `count` scans in each of `arenas` (group `arenas`): the laser at random free poses inside
/// each ([`laserlines_sim::arena::arena_scenes`], straight runs of panels joined into one
/// wall), seen by `sensor` in its conditions, with the ground truth. Scenes the extractors'
/// defaults were not chosen on: their parameters come from the scene suites.
#[must_use]
pub fn arena_scans(arenas: &[Arena], seed: u64, count: usize, sensor: &Sensor) -> Vec<BenchScan> {
    arena_scans_counted(arenas, seed, count, sensor).0
}

/// [`arena_scans`], with the number of scans each arena gave (fewer than `count` when its
/// free floor is small, none when none was found).
#[must_use]
pub fn arena_scans_counted(
    arenas: &[Arena],
    seed: u64,
    count: usize,
    sensor: &Sensor,
) -> (Vec<BenchScan>, Vec<usize>) {
    let mut out = Vec::new();
    let mut counts = Vec::with_capacity(arenas.len());
    for (k, arena) in arenas.iter().enumerate() {
        let stream = mix_seed(ARENA_STREAM, k as u64);
        let scenes = arena_scenes(arena, mix_seed(seed, stream), count);
        counts.push(scenes.len());
        out.extend(simulate_scenes("arenas", stream, &scenes, seed, sensor));
    }
    (out, counts)
}

/// Scans of `scenes` (group `group`, random stream `index`) seen by `sensor` in its
/// conditions, with their ground truth.
fn simulate_scenes(
    group: &str,
    index: u64,
    scenes: &[Scene],
    seed: u64,
    sensor: &Sensor,
) -> Vec<BenchScan> {
    let mut out = Vec::with_capacity(scenes.len());
    for (k, scene) in scenes.iter().enumerate() {
        let stream = (index << 40) ^ k as u64;
        let mut rng = Rng::new(mix_seed(mix_seed(seed, stream), 0x006E_6F69_7365));
        let mut model = sensor.model;
        let mut scene = scene.clone();
        if sensor.legs > 0 || sensor.dropout.is_some() {
            // The conditions draw from their own stream: the plain scans stay as they were.
            let mut extra = Rng::new(mix_seed(mix_seed(seed, stream), 0x6C65_6773));
            if let Some((lo, hi)) = sensor.dropout {
                model.dropout = extra.range(lo, hi);
            }
            let legs = extra.below(sensor.legs + 1);
            add_legs(
                &mut scene,
                &mut extra,
                legs,
                sensor.leg_diameter,
                // Where the URG-04LX would see them, whatever the scanner's reach.
                model.range_max.min(5.6) - 0.6,
            );
        }
        let mut sim = scene.simulate(&model, &mut rng);
        let truth = expected_pieces(&sim, &model.noise);
        let (bottom, top) = (model.range_min.max(0.1), model.range_max.min(5.6) - 0.1);
        if sensor.spurious > 0.0 && bottom < top {
            // Their own stream too.
            let mut extra = Rng::new(mix_seed(mix_seed(seed, stream), 0x7370_7572));
            for r in &mut sim.scan.ranges {
                if extra.range(0.0, 1.0) < sensor.spurious {
                    *r = extra.range(bottom, top);
                }
            }
        }
        out.push(BenchScan {
            name: scene.name.clone(),
            group: group.to_string(),
            truth: Some(truth),
            scan: sim.scan,
        });
    }
    out
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
