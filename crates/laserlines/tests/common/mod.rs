//! What the extractor tests share: their own seeded noise and the URG-04LX's beams.

#![allow(dead_code)]

use laserlines::math::{Point2, Vector2};

/// SplitMix64, for the test's own noise.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    pub fn unit(&mut self) -> f64 {
        ((self.next() >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// Standard normal (Box-Muller).
    pub fn gauss(&mut self) -> f64 {
        let (u, v) = (self.unit(), self.unit());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

/// The URG-04LX: 682 beams of 360/1024 deg, centred on x.
pub const BEAMS: usize = 682;
pub fn increment() -> f64 {
    (360.0f64 / 1024.0).to_radians()
}
pub fn angle_min() -> f64 {
    -0.5 * (BEAMS - 1) as f64 * increment()
}

/// Range noise of the test scans, standard deviation: 2 mm up to 1 m, 0.2 % beyond (a fifth
/// of the URG-04LX's accuracy, so that the corner beams, 2 cm apart, are told apart).
pub fn sigma(r: f64) -> f64 {
    0.002 * r.max(1.0)
}

/// Ranges of every kind a driver may hand over: valid ones (weight `valid`, against 1 for each
/// other kind), NaN, both infinities, zero, negative, absurdly far and denormally near.
pub fn any_range(valid: u32) -> impl proptest::strategy::Strategy<Value = f64> {
    use proptest::prelude::*;
    prop_oneof![
        valid => 0.02f64..6.0,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(0.0),
        1 => -10.0f64..0.0,
        1 => Just(1e300),
        1 => Just(f64::MIN_POSITIVE),
    ]
}

/// Beam increments of every kind: counter-clockwise, clockwise, zero, NaN, vanishing.
pub fn any_increment() -> impl proptest::strategy::Strategy<Value = f64> {
    use proptest::prelude::*;
    prop_oneof![
        4 => 0.001f64..0.05,
        2 => -0.05f64..-0.001,
        1 => Just(0.0),
        1 => Just(f64::NAN),
        1 => Just(1e-300),
    ]
}

/// Range of the beam at `angle` to the segment `a`-`b`, if it meets it.
pub fn hit(angle: f64, a: Point2, b: Point2) -> Option<f64> {
    let d = Vector2::new(angle.cos(), angle.sin());
    let e = b - a;
    let den = d.x * e.y - d.y * e.x;
    if den.abs() < 1e-12 {
        return None;
    }
    let t = (a.x * e.y - a.y * e.x) / den;
    let s = (a.x * d.y - a.y * d.x) / den;
    (t > 0.0 && (0.0..=1.0).contains(&s)).then_some(t)
}

/// Range of the beam at `angle` to the nearest of `walls` it meets, if any.
pub fn nearest(angle: f64, walls: &[(Point2, Point2)]) -> Option<f64> {
    walls
        .iter()
        .filter_map(|&(a, b)| hit(angle, a, b))
        .min_by(f64::total_cmp)
}
