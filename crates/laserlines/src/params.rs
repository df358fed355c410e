//! The one error of every parameter check in laserlines ([`ParamsError`]) and the checks
//! themselves, so that a bad value is reported the same way whatever it configures: an
//! extractor, the robot or the explorer.
//!
//! `field` is the parameter's path as a user writes it in a params file, relative to its
//! table: `split_distance`, `breakpoints.noise`, `footprint.length`.

use crate::hough::HoughError;
use crate::scan::{RangeWindow, Short};

/// A parameter out of its domain.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParamsError {
    /// A field that must be finite and positive is not.
    #[error("{field} must be finite and > 0, got {}", Short(*value))]
    NotPositive {
        /// field name
        field: &'static str,
        /// offending value
        value: f64,
    },
    /// A field that must be finite and non-negative is not.
    #[error("{field} must be finite and >= 0, got {}", Short(*value))]
    Negative {
        /// field name
        field: &'static str,
        /// offending value
        value: f64,
    },
    /// A field that must be finite is not.
    #[error("{field} must be finite, got {}", Short(*value))]
    NotFinite {
        /// field name
        field: &'static str,
        /// offending value
        value: f64,
    },
    /// A field outside its open interval.
    #[error("{field} must lie in ({lo}, {hi}), got {}", Short(*value))]
    OutOfRange {
        /// field name
        field: &'static str,
        /// offending value
        value: f64,
        /// lower bound (exclusive)
        lo: f64,
        /// upper bound (exclusive)
        hi: f64,
    },
    /// A field below its minimum (or not finite).
    #[error("{field} must be finite and >= {min}, got {}", Short(*value))]
    Below {
        /// field name
        field: &'static str,
        /// offending value
        value: f64,
        /// smallest allowed value
        min: f64,
    },
    /// A field above the value of another field.
    #[error("{field} must be at most {} ({limit_field}), got {}", Trimmed(*limit), Short(*value))]
    AboveField {
        /// field name
        field: &'static str,
        /// offending value
        value: f64,
        /// the field it must not exceed
        limit_field: &'static str,
        /// that field's value
        limit: f64,
    },
    /// A field not above another field's value.
    #[error("{field} must be above {other_field} ({other}), got {}", Short(*value))]
    NotAbove {
        /// field name
        field: &'static str,
        /// offending value
        value: f64,
        /// the field it must exceed
        other_field: &'static str,
        /// that field's value
        other: f64,
    },
    /// A count below its minimum.
    #[error("{field} must be at least {min}, got {value}")]
    TooFew {
        /// field name
        field: &'static str,
        /// offending value
        value: usize,
        /// smallest allowed value
        min: usize,
    },
    /// The Hough grid is invalid.
    #[error("Hough grid: {0}")]
    Grid(#[from] HoughError),
}

/// Checks that `value` is finite and `> 0`.
///
/// # Errors
/// [`ParamsError::NotPositive`].
pub fn positive(field: &'static str, value: f64) -> Result<(), ParamsError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(ParamsError::NotPositive { field, value })
    }
}

/// Checks that `value` is finite and `>= 0`.
///
/// # Errors
/// [`ParamsError::Negative`].
pub fn non_negative(field: &'static str, value: f64) -> Result<(), ParamsError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(ParamsError::Negative { field, value })
    }
}

/// Checks that `value` is finite.
///
/// # Errors
/// [`ParamsError::NotFinite`].
pub fn finite(field: &'static str, value: f64) -> Result<(), ParamsError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(ParamsError::NotFinite { field, value })
    }
}

/// Checks that `value` lies in the open interval `(lo, hi)`.
///
/// # Errors
/// [`ParamsError::OutOfRange`].
pub fn inside(field: &'static str, value: f64, lo: f64, hi: f64) -> Result<(), ParamsError> {
    if value > lo && value < hi {
        Ok(())
    } else {
        Err(ParamsError::OutOfRange {
            field,
            value,
            lo,
            hi,
        })
    }
}

/// Checks that a count is at least `min`.
///
/// # Errors
/// [`ParamsError::TooFew`].
pub fn at_least(field: &'static str, value: usize, min: usize) -> Result<(), ParamsError> {
    if value >= min {
        Ok(())
    } else {
        Err(ParamsError::TooFew { field, value, min })
    }
}

/// Checks a threshold that grows with range, `base + per_metre * range`: both finite and
/// non-negative, and not both zero.
///
/// # Errors
/// [`ParamsError::Negative`] or [`ParamsError::NotPositive`] naming `base` or `per_metre`.
pub fn scaled(
    base: (&'static str, f64),
    per_metre: (&'static str, f64),
) -> Result<(), ParamsError> {
    non_negative(base.0, base.1)?;
    non_negative(per_metre.0, per_metre.1)?;
    if base.1 + per_metre.1 > 0.0 {
        Ok(())
    } else {
        Err(ParamsError::NotPositive {
            field: base.0,
            value: base.1,
        })
    }
}

/// Checks an extractor's own valid ranges, `range_limits = [min, max]`: `min` finite and
/// `>= 0`, `max` above it (`inf` for no upper limit). `None` (the scan's own limits) passes.
///
/// # Errors
/// [`ParamsError::Negative`] naming `range_limits[0]`, or [`ParamsError::NotAbove`] naming
/// `range_limits[1]`.
pub fn range_limits(limits: Option<RangeWindow>) -> Result<(), ParamsError> {
    let Some(w) = limits else { return Ok(()) };
    non_negative("range_limits[0]", w.min)?;
    if w.max > w.min {
        Ok(())
    } else {
        Err(ParamsError::NotAbove {
            field: "range_limits[1]",
            value: w.max,
            other_field: "range_limits[0]",
            other: w.min,
        })
    }
}

/// An upper limit computed from other values, rounded down to four decimals without trailing
/// zeros (0.5701 for 0.5701562118716424, 100 for 100.0), so that a value printed at the limit
/// meets it; as [`Short`] writes it where four decimals would change it by more than a
/// thousandth (0.00002, 1e20).
struct Trimmed(f64);

impl std::fmt::Display for Trimmed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let v = self.0;
        let down = (v * 1e4).floor() / 1e4;
        if !(v.abs() < 1e16 && (down - v).abs() <= 1e-3 * v.abs()) {
            return write!(f, "{}", Short(v));
        }
        let text = format!("{down:.4}");
        f.write_str(text.trim_end_matches('0').trim_end_matches('.'))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_computed_limit_is_printed_rounded_down_to_four_decimals() {
        let e = ParamsError::AboveField {
            field: "laser.x",
            value: 0.6,
            limit_field: "the footprint's circumradius + 0.25 m",
            limit: 0.570_156_211_871_642_4,
        };
        assert_eq!(
            e.to_string(),
            "laser.x must be at most 0.5701 (the footprint's circumradius + 0.25 m), got 0.6"
        );
        for (v, text) in [
            (100.0, "100"),
            (0.25, "0.25"),
            (1.666_666_7, "1.6666"),
            (-0.5, "-0.5"),
            (2e-5, "0.00002"),
            (1e20, "1e20"),
            (0.0, "0"),
        ] {
            assert_eq!(Trimmed(v).to_string(), text, "{v}");
        }
    }

    #[test]
    fn checks_name_the_field_and_the_value() {
        assert!(positive("a", 1.0).is_ok());
        let e = positive("footprint.length", 0.0).unwrap_err();
        assert_eq!(
            e.to_string(),
            "footprint.length must be finite and > 0, got 0"
        );
        assert!(non_negative("a", 0.0).is_ok() && non_negative("a", -1.0).is_err());
        assert!(non_negative("a", f64::INFINITY).is_err());
        assert!(finite("a", -3.0).is_ok() && finite("a", f64::NAN).is_err());
        assert!(inside("a", 0.5, 0.0, 1.0).is_ok() && inside("a", 1.0, 0.0, 1.0).is_err());
        assert!(at_least("a", 2, 2).is_ok() && at_least("a", 1, 2).is_err());
        assert!(scaled(("b", 0.0), ("p", 0.01)).is_ok());
        let e = scaled(("b", 0.0), ("p", 0.0)).unwrap_err();
        assert!(matches!(e, ParamsError::NotPositive { field: "b", .. }));
        assert!(range_limits(None).is_ok());
        assert!(range_limits(Some(RangeWindow::new(0.03, f64::INFINITY))).is_ok());
        let e = range_limits(Some(RangeWindow::new(3.0, 0.03))).unwrap_err();
        assert_eq!(
            e.to_string(),
            "range_limits[1] must be above range_limits[0] (3), got 0.03"
        );
        for (min, max) in [(f64::NAN, 1.0), (-1.0, 1.0), (0.5, f64::NAN), (0.5, 0.5)] {
            assert!(
                range_limits(Some(RangeWindow::new(min, max))).is_err(),
                "{min} {max}"
            );
        }
    }
}
