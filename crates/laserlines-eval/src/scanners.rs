//! Other scanners than the paper's, as simulated sensors for the benchmark
//! ([`crate::workload::sensor`]): their geometry and resolution, their data sheet's noise as
//! one standard deviation (the presets of [`laserlines::noise::PRESETS`]), and the field
//! conditions of the URG-04LX suites (chair and table legs, dropouts; mixed pixels at depth
//! edges for the time-of-flight scanners).

use laserlines::RangeNoise;
use laserlines_sim::{LaserModel, Noise};

use crate::workload::Sensor;

/// The noise preset `name` (one of [`laserlines::noise::PRESETS`]).
fn preset(name: &str) -> Noise {
    Noise::Range(RangeNoise::preset(name).unwrap_or_default())
}

/// A scanner of `beams` beams from `angle_min` in steps of `increment` (degrees), ranges
/// `range` (m) in steps of `round_to`, with the noise preset `noise`.
fn scanner(
    beams: usize,
    (angle_min, increment): (f64, f64),
    range: (f64, f64),
    noise: &str,
    round_to: f64,
) -> LaserModel {
    LaserModel {
        beams,
        angle_min: angle_min.to_radians(),
        angle_increment: increment.to_radians(),
        range_min: range.0,
        range_max: range.1,
        noise: preset(noise),
        round_to: Some(round_to),
        ..LaserModel::urg04lx()
    }
}

/// The field conditions seen by `model`: 0-8 legs of 3-12 cm, dropouts drawn per scan from
/// `dropout`, mixed pixels at half of the depth edges when `mixed`.
fn field(model: LaserModel, dropout: (f64, f64), mixed: bool) -> Sensor {
    Sensor {
        model: LaserModel {
            mixed_pixels: if mixed { 0.5 } else { 0.0 },
            ..model
        },
        dropout: Some(dropout),
        ..Sensor::field(1.0)
    }
}

/// Hokuyo UTM-30LX: 270 deg in 0.25 deg steps (1081 beams), 0.1-30 m, 1 mm, 30 mm noise.
#[must_use]
pub fn utm30lx() -> Sensor {
    let model = scanner(1081, (-135.0, 0.25), (0.1, 30.0), "utm-30lx", 0.001);
    field(model, (0.0, 0.05), true)
}

/// SICK LMS200 in its 8 m, mm mode: 180 deg in 1 deg steps (181 beams), 15 mm noise.
#[must_use]
pub fn lms2xx() -> Sensor {
    let model = scanner(181, (-90.0, 1.0), (0.02, 8.0), "lms2xx", 0.001);
    field(model, (0.0, 0.05), true)
}

/// Slamtec RPLIDAR A1: 360 deg in 1 deg steps (360 beams), 0.15-12 m, 1 mm, 1 % of the range
/// (a triangulation scanner: no mixed pixels).
#[must_use]
pub fn rplidar_a1() -> Sensor {
    let model = scanner(360, (-180.0, 1.0), (0.15, 12.0), "rplidar-a1", 0.001);
    field(model, (0.0, 0.05), false)
}

/// YDLIDAR X4: 360 deg in 0.85 deg steps (424 beams), 0.12-10 m, 1 mm, 2 % of the range, and
/// 30-70 % of the beams without a return (a triangulation scanner: no mixed pixels).
#[must_use]
pub fn ydlidar_x4() -> Sensor {
    let model = scanner(424, (-180.0, 0.85), (0.12, 10.0), "ydlidar-x4", 0.001);
    field(model, (0.3, 0.7), false)
}
