//! Other scanners than the paper's, as simulated sensors for the benchmark
//! ([`crate::workload::sensor`]): their geometry and resolution, their data sheet's noise as
//! one standard deviation (the presets of [`laserlines::noise::PRESETS`]; for the depth
//! cameras, noise and steps that grow with the square of the range), and the field
//! conditions of the URG-04LX suites (chair and table legs, dropouts; mixed pixels at depth
//! edges for the time-of-flight scanners and the depth cameras).

use laserlines::RangeNoise;
use laserlines_sim::{LaserModel, Noise};

use crate::workload::Sensor;

/// One scanner: angles in degrees, ranges in metres, 1 mm resolution.
struct Scanner {
    /// Its name as a sensor of the benchmark.
    name: &'static str,
    beams: usize,
    angle_min: f64,
    increment: f64,
    range: (f64, f64),
    /// Its noise.
    noise: ScannerNoise,
    /// Share of the beams without a return, drawn per scan from this range.
    dropout: (f64, f64),
    /// Mixed pixels at half of the depth edges (a time-of-flight scanner).
    mixed: bool,
}

/// A scanner's range noise.
#[derive(Clone, Copy)]
enum ScannerNoise {
    /// A preset of [`laserlines::noise::PRESETS`], by name.
    Preset(&'static str),
    /// A depth camera's ([`Noise::Depth`]): standard deviation at 1 m (m), step of the
    /// inverse range (1/m).
    Depth(f64, f64),
}

impl ScannerNoise {
    /// The simulated noise (`None` for a preset of another name).
    fn model(self) -> Option<Noise> {
        match self {
            Self::Preset(name) => RangeNoise::preset(name).map(Noise::Range),
            Self::Depth(coefficient, step) => Some(Noise::Depth { coefficient, step }),
        }
    }
}

/// The scanners, by name.
const SCANNERS: &[Scanner] = &[
    // Hokuyo UTM-30LX: 270 deg in 0.25 deg steps, 0.1-30 m, 30 mm noise.
    Scanner {
        name: "utm30lx",
        beams: 1081,
        angle_min: -135.0,
        increment: 0.25,
        range: (0.1, 30.0),
        noise: ScannerNoise::Preset("utm-30lx"),
        dropout: (0.0, 0.05),
        mixed: true,
    },
    // Hokuyo UST-10LX: 270 deg in 0.25 deg steps, 0.06-10 m, 40 mm noise at every range.
    Scanner {
        name: "ust10lx",
        beams: 1081,
        angle_min: -135.0,
        increment: 0.25,
        range: (0.06, 10.0),
        noise: ScannerNoise::Preset("ust-10lx"),
        dropout: (0.0, 0.05),
        mixed: true,
    },
    // SICK LMS111: 270 deg in 0.5 deg steps, 0.5-20 m, 12 mm noise.
    Scanner {
        name: "lms1xx",
        beams: 541,
        angle_min: -135.0,
        increment: 0.5,
        range: (0.5, 20.0),
        noise: ScannerNoise::Preset("lms1xx"),
        dropout: (0.0, 0.05),
        mixed: true,
    },
    // SICK LMS200 in its 8 m, mm mode: 180 deg in 1 deg steps, 15 mm noise.
    Scanner {
        name: "lms2xx",
        beams: 181,
        angle_min: -90.0,
        increment: 1.0,
        range: (0.02, 8.0),
        noise: ScannerNoise::Preset("lms2xx"),
        dropout: (0.0, 0.05),
        mixed: true,
    },
    // Slamtec RPLIDAR A1: 360 deg in 1 deg steps, 0.15-12 m, 1 % of the range
    // (triangulation: no mixed pixels).
    Scanner {
        name: "rplidar-a1",
        beams: 360,
        angle_min: -180.0,
        increment: 1.0,
        range: (0.15, 12.0),
        noise: ScannerNoise::Preset("rplidar-a1"),
        dropout: (0.0, 0.05),
        mixed: false,
    },
    // Slamtec RPLIDAR A2 at 10 Hz: 360 deg in 0.9 deg steps, 0.15-12 m, 2 % of the range (its
    // data sheet's worst band, at every range; triangulation: no mixed pixels).
    Scanner {
        name: "rplidar-a2",
        beams: 400,
        angle_min: -180.0,
        increment: 0.9,
        range: (0.15, 12.0),
        noise: ScannerNoise::Preset("rplidar-a2"),
        dropout: (0.0, 0.05),
        mixed: false,
    },
    // YDLIDAR X4: 360 deg in 0.85 deg steps, 0.12-10 m, 2 % of the range, 30-70 % of the
    // beams without a return (triangulation: no mixed pixels).
    Scanner {
        name: "ydlidar-x4",
        beams: 424,
        angle_min: -180.0,
        increment: 0.85,
        range: (0.12, 10.0),
        noise: ScannerNoise::Preset("ydlidar-x4"),
        dropout: (0.3, 0.7),
        mixed: false,
    },
    // A Microsoft Kinect (v1) depth camera through `depthimage_to_laserscan`: 640 columns over
    // 57 deg, 0.45-5 m; depth noise 1.425e-3 z^2 m and disparity steps of 2.85e-3 z^2 m
    // (1/8 pixel; Khoshelham and Elberink 2012); flying pixels at depth edges.
    Scanner {
        name: "kinect",
        beams: 640,
        angle_min: -28.5,
        increment: 57.0 / 639.0,
        range: (0.45, 5.0),
        noise: ScannerNoise::Depth(1.425e-3, 2.85e-3),
        dropout: (0.0, 0.05),
        mixed: true,
    },
    // An Intel RealSense D435 stereo depth camera through `depthimage_to_laserscan`: 848
    // columns over 87 deg, 0.3-6 m; depth noise 3.6e-3 z^2 m (0.08 pixel of subpixel error
    // at a 50 mm baseline and 447 pixels of focal length) in steps of 1/32 pixel of
    // disparity (1.4e-3 z^2 m); flying pixels at depth edges.
    Scanner {
        name: "realsense-d435",
        beams: 848,
        angle_min: -43.5,
        increment: 87.0 / 847.0,
        range: (0.3, 6.0),
        noise: ScannerNoise::Depth(3.6e-3, 1.4e-3),
        dropout: (0.0, 0.05),
        mixed: true,
    },
];

/// The scanner called `name` in the field conditions (0-8 legs of 3-12 cm, its dropouts, its
/// mixed pixels), or `None` for another name.
#[must_use]
pub fn sensor(name: &str) -> Option<Sensor> {
    let s = SCANNERS.iter().find(|s| s.name == name)?;
    let noise = s.noise.model()?;
    Some(Sensor {
        model: LaserModel {
            beams: s.beams,
            angle_min: s.angle_min.to_radians(),
            angle_increment: s.increment.to_radians(),
            range_min: s.range.0,
            range_max: s.range.1,
            noise,
            round_to: Some(0.001),
            mixed_pixels: if s.mixed { 0.5 } else { 0.0 },
            ..LaserModel::urg04lx()
        },
        dropout: Some(s.dropout),
        ..Sensor::field(1.0)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::workload::SENSORS;

    #[test]
    fn every_scanner_is_a_sensor_with_its_noise() {
        for s in SCANNERS {
            assert!(SENSORS.contains(&s.name), "{}", s.name);
            let sensor = sensor(s.name).unwrap_or_else(|| panic!("{}: no noise", s.name));
            assert_eq!(sensor.model.beams, s.beams);
            assert!(sensor.model.validate().is_ok(), "{}", s.name);
            // The last beam ends where the scanner's field of view does.
            let last = s.angle_min + (s.beams - 1) as f64 * s.increment;
            assert!(
                last <= 180.0 && last >= -s.angle_min - 1.0,
                "{}: {last}",
                s.name
            );
        }
        assert!(sensor("urg04lx").is_none());
        // The noise each is documented with: a data sheet's preset, or a depth camera's.
        let sigma = |name: &str, r: f64| sensor(name).map(|s| s.model.noise.sigma(r));
        assert_eq!(sigma("utm30lx", 4.0), Some(0.03));
        assert_eq!(sigma("rplidar-a2", 4.0), Some(0.08));
        let kinect = sigma("kinect", 4.0).unwrap_or_default();
        assert!((kinect - 0.0228).abs() < 1e-12, "{kinect}");
        let d435 = sigma("realsense-d435", 4.0).unwrap_or_default();
        assert!((d435 - 0.0576).abs() < 1e-12, "{d435}");
    }

    #[test]
    fn a_sensor_answers_to_every_spelling_of_its_name() {
        use crate::workload::sensor;
        for (spelt, name) in [
            ("UTM-30LX", "utm30lx"),
            ("urg-04lx-full", "urg04lx-full"),
            ("URG04LX_1.5x", "urg04lx-1.5x"),
            ("rplidar_a1", "rplidar-a1"),
        ] {
            assert!(sensor(name).is_some(), "{name}");
            assert_eq!(sensor(spelt), sensor(name), "{spelt}");
        }
        // Field levels differ in their noise, so the match is not loose.
        assert_ne!(sensor("urg04lx-full"), sensor("urg04lx-1.5x"));
        assert!(sensor("urg-04").is_none());
    }
}
