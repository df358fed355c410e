//! Range noise: the standard deviation of a scanner's range readings as a function of range,
//! from its data sheet or estimated from a scan itself.
//!
//! Every threshold of [`crate::HoughSplit`] is a multiple of `sigma(r)`, so that the same
//! defaults work on a URG-04LX at 5 mm and on a cheap triangulation scanner at 2 % of the
//! range. The model is the one data sheets state:
//!
//! ```text
//! sigma(r) = max(sigma_min, fraction * r)
//! ```
//!
//! [`NoiseModel::Auto`] (the default) estimates both numbers from the scan being processed,
//! with no history: for every beam `i` whose beams `i - k` and `i + k` are valid (`k` =
//! [`lag_for`]: [`LAG`] = 3 beams, fewer on scanners coarser than the URG-04LX), the range a
//! straight surface through those two would give on beam `i` is
//! `r_hat = 2 cos(dphi) r0 r2 / (r0 + r2)` with `dphi = k * angle_increment` (exact for
//! any line: `1 / r` of a line is a sinusoid of the beam angle), and `e = r1 - r_hat` has
//! the variance `1.5 sigma^2` on a smooth surface. Per range band (octaves from 0.5 m) the median of `|e|` gives a robust
//! `sigma_b = median|e| / (0.6745 sqrt(1.5))`: corners, depth edges and mixed pixels are a
//! minority and do not move a median. The model is the largest `max(sigma_min, fraction r)`
//! below every band's estimate: clutter only ever adds dispersion, so the cleanest band
//! tells the sensor's own noise. Noise that steps up with range (a URG-04LX at a few
//! millimetres to 3 m and 1 % beyond) raises the fraction where a band from 1 m on, or a far
//! end of the samples (all of them beyond 1 m, 1.25 m, 1.5 m, ... in quarter octaves), still
//! reads [`STEP_RATIO`] times the model at the low end of its interval. A scan too short for any band of its own (fewer than
//! [`MIN_BAND_SAMPLES`] in each) is read as one band when it has [`MIN_POOLED_SAMPLES`].
//! A sparse scan (a dropout rate of 0.2 or more) on which fewer than half of the triples
//! return whole is read from its consecutive returns instead, each at most `3 k` beams from
//! the next, the middle range predicted on the chord of the outer two,
//! `r0 r2 sin(a + b) / (r0 sin a + r2 sin b)` for the angles `a` and `b` between the beams, and
//! the residual scaled to the variance of an even triple's.

mod chords;
mod envelope;
mod estimator;
mod tails;

pub use envelope::{MAX_AUTO_FRACTION, STEP_RATIO};
pub use estimator::{
    BandEstimate, MIN_BAND_SAMPLES, MIN_POOLED_SAMPLES, NOISE_BANDS, NoiseEstimator,
};

/// True when `a` and `b` name the same sensor: they are equal but for ASCII case, hyphens
/// and underscores (`urg-04lx`, `urg04lx`, `URG_04LX`), as data sheets and drivers spell
/// model names every way.
#[must_use]
pub fn sensor_names_match(a: &str, b: &str) -> bool {
    fn key(s: &str) -> impl Iterator<Item = u8> + '_ {
        s.bytes()
            .filter(|c| !matches!(c, b'-' | b'_'))
            .map(|c| c.to_ascii_lowercase())
    }
    key(a).eq(key(b))
}

/// A range-noise model `sigma(r) = max(sigma_min, fraction * r)`, metres.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct RangeNoise {
    /// Standard deviation at short range, m.
    pub sigma_min: f64,
    /// Growth of the standard deviation with range, m per m (0.01 = 1 % of the range).
    pub fraction: f64,
}

/// A named preset of [`RangeNoise`] with the data-sheet figure it comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoisePreset {
    /// Name, as `--params` and the presets table use it (e.g. `urg-04lx`).
    pub name: &'static str,
    /// The model.
    pub noise: RangeNoise,
    /// What the data sheet states, and how it was read.
    pub source: &'static str,
}

/// Range-noise presets from the makers' data sheets. The stated accuracy band is taken as one
/// standard deviation (a conservative reading: a URG-04LX measured on real logs shows about
/// half of its band); where a data sheet states a statistical (repeatability) error, that is
/// used.
pub const PRESETS: &[NoisePreset] = &[
    NoisePreset {
        name: "urg-04lx",
        noise: RangeNoise::new(0.010, 0.010),
        source: "Hokuyo URG-04LX: +-10 mm from 60 to 1000 mm, +-1 % of the range to 4095 mm",
    },
    NoisePreset {
        name: "utm-30lx",
        noise: RangeNoise::new(0.030, 0.0017),
        source: "Hokuyo UTM-30LX: +-30 mm from 0.1 to 10 m, +-50 mm from 10 to 30 m",
    },
    NoisePreset {
        name: "ust-10lx",
        noise: RangeNoise::new(0.040, 0.0),
        source: "Hokuyo UST-10LX / UST-20LX: +-40 mm",
    },
    NoisePreset {
        name: "lms1xx",
        noise: RangeNoise::new(0.012, 0.0),
        source: "SICK LMS1xx: statistical error 12 mm (typical)",
    },
    NoisePreset {
        name: "lms2xx",
        noise: RangeNoise::new(0.015, 0.0),
        source: "SICK LMS2xx (LMS200/291): +-15 mm in mm mode, 1 to 8 m",
    },
    NoisePreset {
        name: "rplidar-a1",
        noise: RangeNoise::new(0.005, 0.010),
        source: "Slamtec RPLIDAR A1: resolution below 0.5 mm under 1.5 m, 1 % of the range",
    },
    NoisePreset {
        name: "rplidar-a2",
        noise: RangeNoise::new(0.005, 0.020),
        source: "Slamtec RPLIDAR A2: 1 % of the range to 3 m, 2 % from 3 to 5 m",
    },
    NoisePreset {
        name: "ydlidar-x4",
        noise: RangeNoise::new(0.010, 0.020),
        source: "YDLIDAR X4 (triangulation, 0.12 to 10 m): 2 % of the range, 10 mm at short range",
    },
];

impl RangeNoise {
    /// A model with the given short-range sigma (m) and fraction of the range.
    #[must_use]
    pub const fn new(sigma_min: f64, fraction: f64) -> Self {
        Self {
            sigma_min,
            fraction,
        }
    }

    /// The preset called `name` (see [`PRESETS`]; the name is matched by
    /// [`sensor_names_match`]: `urg04lx` and `URG-04LX` name `urg-04lx`).
    #[must_use]
    pub fn preset(name: &str) -> Option<Self> {
        PRESETS
            .iter()
            .find(|p| sensor_names_match(p.name, name))
            .map(|p| p.noise)
    }

    /// Standard deviation at range `r`, m.
    #[inline]
    #[must_use]
    pub fn sigma(&self, r: f64) -> f64 {
        // `max` by one comparison (a NaN product gives `sigma_min`, as `f64::max` does).
        let v = self.fraction * r;
        if v > self.sigma_min {
            v
        } else {
            self.sigma_min
        }
    }

    /// The model scaled by `k` (both numbers).
    #[must_use]
    pub fn scaled(&self, k: f64) -> Self {
        Self::new(self.sigma_min * k, self.fraction * k)
    }

    /// True when both numbers are finite and non-negative and `sigma` is not zero
    /// everywhere.
    #[must_use]
    pub fn is_valid(&self) -> bool {
        self.sigma_min.is_finite()
            && self.fraction.is_finite()
            && self.sigma_min >= 0.0
            && self.fraction >= 0.0
            && (self.sigma_min > 0.0 || self.fraction > 0.0)
    }
}

impl std::fmt::Display for RangeNoise {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "sigma = max({:.1} mm, {:.2} % of the range)",
            self.sigma_min * 1e3,
            self.fraction * 100.0
        )
    }
}

/// Where an extractor's range noise comes from.
///
/// In a params file (feature `serde`): `noise = "auto"`, a preset's name
/// (`noise = "urg-04lx"`, see [`PRESETS`]) or a model (`noise = { sigma_min = 0.01,
/// fraction = 0.01 }`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum NoiseModel {
    /// Estimated from each scan by [`NoiseEstimator`] (the default).
    #[default]
    Auto,
    /// A fixed model, e.g. a [`PRESETS`] entry.
    Fixed(RangeNoise),
}

/// Beams between a point and each of the two it is predicted from. Real scanners' errors are
/// correlated between neighbouring beams (the URG-04LX's residuals grow two to three times from
/// one beam to three on real logs), so the noise that splitting and merging see over tens of
/// beams is read three beams apart; for independent noise any lag reads the same.
pub const LAG: usize = 3;

/// The dropout rate (the fraction of returns whose next beam returned nothing) from which a
/// scan is sparse: its noise is estimated from consecutive returns rather than from triples
/// of consecutive beams, and `hough-split` takes a reading beyond the range limit on it for
/// a dropout rather than for a view through (scanners that report a missing return as their
/// maximum range or beyond would otherwise cut every gap of a sparse scan).
pub(crate) const SPARSE_DROPOUT: f64 = 0.2;

/// The lag used on a scan with beams `increment` rad apart: [`LAG`] beams, but never a wider
/// angle than [`LAG`] beams of the URG-04LX (1.05 deg), so that on coarse scanners (a SICK LMS
/// at 1 deg: one beam) the triples see as little of the scene's own shape as on fine ones.
#[must_use]
pub fn lag_for(increment: f64) -> usize {
    const SPAN: f64 = LAG as f64 * 0.006_135_923_151_542_565;
    let beams = (SPAN / increment.abs()).round();
    if beams.is_finite() && beams >= 1.0 {
        (beams as usize).min(LAG)
    } else {
        1
    }
}

#[cfg(feature = "serde")]
mod serde_impl {
    use super::{NoiseModel, PRESETS, RangeNoise};
    use serde::de::{self, MapAccess, Visitor};
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    impl Serialize for NoiseModel {
        fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
            match self {
                Self::Auto => s.serialize_str("auto"),
                Self::Fixed(n) => n.serialize(s),
            }
        }
    }

    struct ModelVisitor;

    impl<'de> Visitor<'de> for ModelVisitor {
        type Value = NoiseModel;

        fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str("\"auto\", a preset name or { sigma_min, fraction }")
        }

        fn visit_str<E: de::Error>(self, v: &str) -> Result<NoiseModel, E> {
            if v == "auto" {
                return Ok(NoiseModel::Auto);
            }
            RangeNoise::preset(v).map(NoiseModel::Fixed).ok_or_else(|| {
                let names: Vec<&str> = PRESETS.iter().map(|p| p.name).collect();
                E::custom(format!(
                    "unknown noise {v:?}: expected \"auto\", one of {} or {{ sigma_min, fraction }}",
                    names.join(", ")
                ))
            })
        }

        fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<NoiseModel, A::Error> {
            RangeNoise::deserialize(de::value::MapAccessDeserializer::new(map))
                .map(NoiseModel::Fixed)
        }
    }

    impl<'de> Deserialize<'de> for NoiseModel {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            d.deserialize_any(ModelVisitor)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lag_spans_at_most_three_urg_beams() {
        let deg = std::f64::consts::PI / 180.0;
        // URG-04LX (0.3516 deg) and finer: three beams; 0.5 deg: two; 1 deg (SICK LMS): one.
        for (step, lag) in [(0.351_562_5, 3), (0.25, 3), (0.5, 2), (1.0, 1), (-1.0, 1)] {
            assert_eq!(lag_for(step * deg), lag, "{step} deg");
        }
        // Degenerate geometry (no valid scan has it): one beam.
        assert_eq!(lag_for(0.0), 1);
        assert_eq!(lag_for(f64::NAN), 1);
    }

    #[test]
    fn presets_have_names_and_valid_models() {
        for p in PRESETS {
            assert!(p.noise.is_valid(), "{}", p.name);
            assert_eq!(RangeNoise::preset(p.name), Some(p.noise));
        }
        assert!(RangeNoise::preset("nonsense").is_none());
        // Spellings of a model name.
        for name in ["urg04lx", "URG-04LX", "urg_04lx"] {
            assert_eq!(RangeNoise::preset(name), RangeNoise::preset("urg-04lx"));
        }
        assert_eq!(RangeNoise::preset("lms-1xx"), Some(PRESETS[3].noise));
        assert!(RangeNoise::preset("urg-04").is_none());
        let urg = RangeNoise::preset("urg-04lx").unwrap();
        assert!((urg.sigma(0.5) - 0.01).abs() < 1e-15);
        assert!((urg.sigma(3.0) - 0.03).abs() < 1e-15);
    }
}
