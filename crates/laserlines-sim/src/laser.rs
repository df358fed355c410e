//! The laser model: beam geometry, range limits, noise and the sensor's artefacts.

use std::f64::consts::TAU;

/// The most beams [`crate::simulate`] produces; a model asking for more is cut to this many
/// (and fails [`LaserModel::validate`]). 65536 beams resolve 0.0055 deg over a full turn.
pub const MAX_BEAMS: usize = 1 << 16;

/// The URG-04LX's angular step: 360/1024 deg (0.3515625 deg), in rad.
pub const URG04LX_INCREMENT: f64 = TAU / 1024.0;

/// Range noise added to every return.
///
/// The draws are gaussian with a standard deviation that may depend on the true range.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Noise {
    /// No noise: ranges are exact (up to [`LaserModel::round_to`]).
    #[default]
    None,
    /// Gaussian noise of constant standard deviation `sigma`, m.
    Gaussian {
        /// Standard deviation, m (negative or NaN counts as 0).
        sigma: f64,
    },
    /// The Hokuyo URG-04LX accuracy specification, "+-10 mm up to 1 m, +-1 % of the range
    /// beyond", read as a 2-sigma bound on gaussian noise: sigma = 5 mm for ranges up to
    /// 1 m, sigma = 0.5 % of the range beyond (continuous at 1 m). About 95 % of returns then
    /// fall within the data sheet's band.
    Urg04lx,
    /// Gaussian noise of standard deviation `max(sigma_min, fraction * range)`, e.g. a data
    /// sheet's band ([`laserlines::noise::PRESETS`]).
    Range(laserlines::RangeNoise),
    /// Gaussian noise that steps up with range: standard deviation `near` below `knee` m, and
    /// `max(near, fraction * range)` from there on (a real URG-04LX's few millimetres near, its
    /// data sheet's 1 % far).
    Stepped {
        /// Standard deviation below the knee, m.
        near: f64,
        /// Range where the noise steps up, m.
        knee: f64,
        /// Fraction of the range from the knee on.
        fraction: f64,
    },
    /// A depth camera's depth read as ranges (a scan made by `depthimage_to_laserscan`):
    /// structured light and stereo measure disparity, so the noise grows with the square of
    /// the range, standard deviation `coefficient * range^2`, and the ranges come in the
    /// disparity's steps, `1 / range` a multiple of `step` (steps of `step * range^2` m).
    /// The range stands in for the depth along the optical axis (at most 14 % longer over
    /// the 57 deg of a Kinect, 3 % over its middle half; 38 % at the edges of a RealSense
    /// D435's 87 deg).
    Depth {
        /// Standard deviation at 1 m, m (per m^2 of range).
        coefficient: f64,
        /// Step of the inverse range, 1/m (0: no steps).
        step: f64,
    },
}

impl Noise {
    /// Standard deviation of the range noise at true range `range` (m), in m. Never negative
    /// or NaN for a finite range.
    #[must_use]
    pub fn sigma(&self, range: f64) -> f64 {
        match *self {
            Self::None => 0.0,
            Self::Gaussian { sigma } => sigma.max(0.0),
            Self::Urg04lx => {
                if range <= 1.0 {
                    0.005
                } else {
                    0.005 * range
                }
            }
            Self::Range(noise) => usable(noise.sigma(range)),
            Self::Stepped {
                near,
                knee,
                fraction,
            } => usable(if range >= knee {
                near.max(fraction * range)
            } else {
                near
            }),
            Self::Depth { coefficient, .. } => usable(coefficient * range * range),
        }
    }

    /// `range` as the sensor reports it in steps of its own: for [`Noise::Depth`] with a
    /// positive `step`, the range whose inverse is the multiple of `step` nearest to
    /// `1 / range` (ranges beyond `2 / step`, whose nearest multiple is 0, unchanged); any
    /// other range, and any other noise, unchanged. Rounding to
    /// [`LaserModel::round_to`] comes after.
    #[must_use]
    pub fn quantize(&self, range: f64) -> f64 {
        match *self {
            Self::Depth { step, .. } if step > 0.0 && range > 0.0 && range.is_finite() => {
                let k = (1.0 / (range * step)).round();
                if k >= 1.0 { 1.0 / (k * step) } else { range }
            }
            _ => range,
        }
    }
}

/// `s` as a standard deviation: 0 when negative or not finite.
fn usable(s: f64) -> f64 {
    if s.is_finite() { s.max(0.0) } else { 0.0 }
}

/// Errors found by [`LaserModel::validate`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// No beams, or more than [`MAX_BEAMS`].
    #[error("beams must be in 1..={max}, got {beams}")]
    BadBeams {
        /// the number asked for
        beams: usize,
        /// the largest allowed, [`MAX_BEAMS`]
        max: usize,
    },
    /// `angle_min` is NaN or infinite.
    #[error("angle_min must be finite, got {0}")]
    AngleMinNotFinite(f64),
    /// `angle_increment` is zero, NaN or infinite.
    #[error("angle_increment must be finite and non-zero, got {0}")]
    BadAngleIncrement(f64),
    /// The beams span more than a full turn.
    #[error("{beams} beams of {increment} rad span more than a full turn")]
    SpanTooLarge {
        /// number of beams
        beams: usize,
        /// angle increment, rad
        increment: f64,
    },
    /// The range limits are not `0 <= range_min < range_max`, both finite.
    #[error("range limits must satisfy 0 <= range_min < range_max (finite), got {min}..{max}")]
    BadRangeLimits {
        /// range_min, m
        min: f64,
        /// range_max, m
        max: f64,
    },
    /// A probability outside `[0, 1]`.
    #[error("{field} must be a probability in [0, 1], got {value}")]
    BadProbability {
        /// the field's name
        field: &'static str,
        /// its value
        value: f64,
    },
    /// A noise standard deviation that is negative or not finite.
    #[error("noise sigma must be finite and >= 0, got {0}")]
    BadNoise(f64),
    /// A rounding step that is not positive and finite.
    #[error("round_to must be positive and finite, got {0}")]
    BadRounding(f64),
}

/// A 2D laser range finder: where its beams point, what it can measure, and how it errs.
///
/// Beam `i` points at `angle_min + i * angle_increment` (rad, counter-clockwise, x forward in
/// the laser frame), as in [`laserlines::Scan`]. The defaults ([`LaserModel::urg04lx`]) are
/// the paper's sensor; change fields with struct update syntax:
///
/// ```
/// use laserlines_sim::{LaserModel, Noise};
/// let model = LaserModel { noise: Noise::Gaussian { sigma: 0.01 }, dropout: 0.05, ..LaserModel::urg04lx() };
/// assert_eq!(model.beams, 682);
/// assert!(model.validate().is_ok());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaserModel {
    /// Number of beams (at most [`MAX_BEAMS`]).
    pub beams: usize,
    /// Angle of the first beam, rad.
    pub angle_min: f64,
    /// Angle between consecutive beams, rad (non-zero; negative for clockwise scans).
    pub angle_increment: f64,
    /// Smallest measurable range, m. Obstacles nearer than this give no return (and hide
    /// what is behind them).
    pub range_min: f64,
    /// Largest measurable range, m. Obstacles farther away are not seen.
    pub range_max: f64,
    /// Range noise.
    pub noise: Noise,
    /// Probability, per depth edge, of a mixed pixel: where two consecutive beams hit
    /// different obstacles whose ranges differ by more than [`MIXED_PIXEL_MIN_JUMP`], one of
    /// the two beams (chosen at random) reports a range between the two surfaces instead.
    /// In `[0, 1]`; 0 disables.
    ///
    /// [`MIXED_PIXEL_MIN_JUMP`]: crate::MIXED_PIXEL_MIN_JUMP
    pub mixed_pixels: f64,
    /// Probability that a return is lost (reported as no return, NaN). In `[0, 1]`; 0
    /// disables.
    pub dropout: f64,
    /// When true, beams that hit nothing within `range_max` report `range_max` (as many
    /// drivers do) instead of no return (NaN).
    pub max_range_returns: bool,
    /// When set, every reported range is rounded to a multiple of this step, m (e.g.
    /// `Some(0.001)` for the sensor's 1 mm resolution).
    pub round_to: Option<f64>,
}

impl LaserModel {
    /// The Hokuyo URG-04LX as the paper used it (SCIP protocol, steps 44..=725 around the
    /// front step 384): 682 beams of 360/1024 deg, `angle_min = -340 * increment`
    /// (-119.53 deg) to `+341 * increment` (+119.88 deg), ranges 0.02..5.6 m,
    /// [`Noise::Urg04lx`], rounding to 1 mm; no dropouts, no mixed pixels, no max-range
    /// returns.
    #[must_use]
    pub fn urg04lx() -> Self {
        Self {
            beams: 682,
            angle_min: -340.0 * URG04LX_INCREMENT,
            angle_increment: URG04LX_INCREMENT,
            range_min: 0.02,
            range_max: 5.6,
            noise: Noise::Urg04lx,
            mixed_pixels: 0.0,
            dropout: 0.0,
            max_range_returns: false,
            round_to: Some(0.001),
        }
    }

    /// The same model without noise, rounding, dropouts or mixed pixels: ranges are the
    /// exact distances to the hit points.
    #[must_use]
    pub fn ideal(self) -> Self {
        Self {
            noise: Noise::None,
            mixed_pixels: 0.0,
            dropout: 0.0,
            round_to: None,
            ..self
        }
    }

    /// Angle of beam `i`, rad, laser frame.
    #[must_use]
    pub fn angle(&self, i: usize) -> f64 {
        self.angle_min + i as f64 * self.angle_increment
    }

    /// Angle of the last beam, rad (`angle_min` when there are no beams).
    #[must_use]
    pub fn angle_max(&self) -> f64 {
        self.angle(self.beams.saturating_sub(1))
    }

    /// Checks the model: beam count, angles, range limits, noise, probabilities, rounding.
    /// [`crate::simulate`] never panics on a model that fails, but its scans may then not
    /// validate as [`laserlines::Scan`]s.
    ///
    /// # Errors
    /// The first [`ModelError`] found.
    pub fn validate(&self) -> Result<(), ModelError> {
        if self.beams == 0 || self.beams > MAX_BEAMS {
            return Err(ModelError::BadBeams {
                beams: self.beams,
                max: MAX_BEAMS,
            });
        }
        if !self.angle_min.is_finite() {
            return Err(ModelError::AngleMinNotFinite(self.angle_min));
        }
        if !self.angle_increment.is_finite() || self.angle_increment == 0.0 {
            return Err(ModelError::BadAngleIncrement(self.angle_increment));
        }
        if (self.beams - 1) as f64 * self.angle_increment.abs() > TAU + 1e-9 {
            return Err(ModelError::SpanTooLarge {
                beams: self.beams,
                increment: self.angle_increment,
            });
        }
        if !(self.range_min.is_finite()
            && self.range_max.is_finite()
            && self.range_min >= 0.0
            && self.range_min < self.range_max)
        {
            return Err(ModelError::BadRangeLimits {
                min: self.range_min,
                max: self.range_max,
            });
        }
        if let Noise::Gaussian { sigma } = self.noise
            && !(sigma.is_finite() && sigma >= 0.0)
        {
            return Err(ModelError::BadNoise(sigma));
        }
        if let Noise::Range(noise) = self.noise
            && !noise.is_valid()
        {
            return Err(ModelError::BadNoise(noise.sigma_min));
        }
        if let Noise::Stepped {
            near,
            knee,
            fraction,
        } = self.noise
        {
            for v in [near, knee, fraction] {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(ModelError::BadNoise(v));
                }
            }
        }
        if let Noise::Depth { coefficient, step } = self.noise {
            for v in [coefficient, step] {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(ModelError::BadNoise(v));
                }
            }
        }
        for (field, value) in [
            ("mixed_pixels", self.mixed_pixels),
            ("dropout", self.dropout),
        ] {
            if !(0.0..=1.0).contains(&value) {
                return Err(ModelError::BadProbability { field, value });
            }
        }
        if let Some(q) = self.round_to
            && !(q.is_finite() && q > 0.0)
        {
            return Err(ModelError::BadRounding(q));
        }
        Ok(())
    }
}

impl Default for LaserModel {
    /// [`LaserModel::urg04lx`].
    fn default() -> Self {
        Self::urg04lx()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn urg04lx_matches_the_data_sheet() {
        let m = LaserModel::urg04lx();
        assert_eq!(m.beams, 682);
        assert!((m.angle_increment.to_degrees() - 0.351_562_5).abs() < 1e-12);
        // Steps 44 and 725 around the front step 384.
        assert!((m.angle(0) - (44.0 - 384.0) * URG04LX_INCREMENT).abs() < 1e-12);
        assert!((m.angle_max() - (725.0 - 384.0) * URG04LX_INCREMENT).abs() < 1e-12);
        assert!((m.angle(340)).abs() < 1e-12);
        assert!((m.range_min - 0.02).abs() < 1e-12 && (m.range_max - 5.6).abs() < 1e-12);
        assert_eq!(m.noise, Noise::Urg04lx);
        assert_eq!(m.round_to, Some(0.001));
        assert!(m.mixed_pixels == 0.0 && m.dropout == 0.0 && !m.max_range_returns);
        assert_eq!(m.validate(), Ok(()));
        assert_eq!(LaserModel::default(), m);
    }

    #[test]
    fn urg04lx_sigma_is_half_the_accuracy_band() {
        let n = Noise::Urg04lx;
        assert!((n.sigma(0.3) - 0.005).abs() < 1e-15);
        assert!((n.sigma(1.0) - 0.005).abs() < 1e-15);
        assert!((n.sigma(2.0) - 0.010).abs() < 1e-15);
        assert!((n.sigma(5.0) - 0.025).abs() < 1e-15);
        assert!((Noise::Gaussian { sigma: 0.01 }.sigma(3.0) - 0.01).abs() < 1e-15);
        assert!(Noise::Gaussian { sigma: f64::NAN }.sigma(3.0) == 0.0);
        assert!(Noise::Gaussian { sigma: -1.0 }.sigma(3.0) == 0.0);
        assert!(Noise::None.sigma(3.0) == 0.0);
    }

    #[test]
    fn validation_names_the_problem() {
        let ok = LaserModel::urg04lx();
        let bad = |m: LaserModel| m.validate().unwrap_err();
        assert!(matches!(
            bad(LaserModel { beams: 0, ..ok }),
            ModelError::BadBeams { beams: 0, .. }
        ));
        assert!(matches!(
            bad(LaserModel {
                angle_increment: 0.0,
                ..ok
            }),
            ModelError::BadAngleIncrement(_)
        ));
        assert!(matches!(
            bad(LaserModel {
                angle_increment: 0.1,
                ..ok
            }),
            ModelError::SpanTooLarge { .. }
        ));
        assert!(matches!(
            bad(LaserModel {
                range_min: 6.0,
                ..ok
            }),
            ModelError::BadRangeLimits { .. }
        ));
        assert!(matches!(
            bad(LaserModel { dropout: 1.5, ..ok }),
            ModelError::BadProbability {
                field: "dropout",
                ..
            }
        ));
        assert!(matches!(
            bad(LaserModel {
                noise: Noise::Gaussian { sigma: -0.1 },
                ..ok
            }),
            ModelError::BadNoise(_)
        ));
        assert!(matches!(
            bad(LaserModel {
                round_to: Some(0.0),
                ..ok
            }),
            ModelError::BadRounding(_)
        ));
        let ideal = ok.ideal();
        assert_eq!(ideal.noise, Noise::None);
        let stepped = Noise::Stepped {
            near: 0.004,
            knee: 3.0,
            fraction: 0.01,
        };
        assert_eq!(stepped.sigma(2.99), 0.004);
        assert_eq!(stepped.sigma(3.0), 0.03);
        assert_eq!(stepped.sigma(f64::NAN), 0.004);
        let bad = LaserModel {
            noise: Noise::Stepped {
                near: 0.004,
                knee: f64::NAN,
                fraction: 0.01,
            },
            ..LaserModel::urg04lx()
        };
        assert!(bad.validate().is_err());
        assert_eq!(ideal.round_to, None);
        assert_eq!(ideal.beams, 682);
    }

    #[test]
    fn depth_noise_grows_and_steps_with_the_square_of_the_range() {
        let kinect = Noise::Depth {
            coefficient: 1.425e-3,
            step: 2.85e-3,
        };
        assert!((kinect.sigma(1.0) - 1.425e-3).abs() < 1e-15);
        assert!((kinect.sigma(4.0) - 0.0228).abs() < 1e-12);
        // 1 / range a multiple of the step: at 1 m steps of 2.85 mm, at 4 m of 45.6 mm.
        for r in [0.5, 1.0, 2.345, 4.0, 4.97] {
            let q = kinect.quantize(r);
            let k = 1.0 / (q * 2.85e-3);
            assert!((k - k.round()).abs() < 1e-6, "{r}: {q}");
            assert!((q - r).abs() <= 0.5 * 2.85e-3 * q * r * 1.01, "{r}: {q}");
        }
        let (a, b) = (kinect.quantize(4.0), kinect.quantize(4.05));
        assert!(b - a > 0.04 && b - a < 0.05, "{a} {b}");
        // What is not a range stays as it is; other noises have no steps.
        assert!(kinect.quantize(f64::NAN).is_nan());
        assert_eq!(kinect.quantize(1e6), 1e6);
        assert_eq!(Noise::Gaussian { sigma: 0.01 }.quantize(2.3456), 2.3456);
        let bad = LaserModel {
            noise: Noise::Depth {
                coefficient: -1e-3,
                step: 0.0,
            },
            ..LaserModel::urg04lx()
        };
        assert!(matches!(bad.validate(), Err(ModelError::BadNoise(_))));
    }
}
