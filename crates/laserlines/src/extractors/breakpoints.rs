//! Where a scan breaks into clusters: the adaptive breakpoint detector of Borges and Aldon.

use super::runs::Run;
use crate::params::{self, ParamsError};
use crate::scan::ScanPoint;

/// The adaptive breakpoint detector of Borges and Aldon (2004): consecutive valid points `a`,
/// `b` belong to different clusters when `|b - a| > r_a sin(dphi) / sin(lambda - dphi) + 3
/// sigma`. The limit grows linearly with range (the distance between beams does), and with the
/// angle between the two beams, so that a few dropped beams do not break a wall; more than
/// `max_gap` missing (invalid) beams between them always do, since the limit grows without
/// bound as `dphi` nears `lambda`.
///
/// The classic extractors cut their clusters and runs with it; its settings are the nested
/// `breakpoints` table of their parameters (`breakpoints.incidence = 0.17` in a params file).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct Breakpoints {
    /// `lambda`, rad: the smallest incidence angle between beam and surface that still joins
    /// two consecutive points. Default 10 deg. Sensible: 5..20 deg.
    pub incidence: f64,
    /// `sigma`, m: range noise allowance, added three times. Default 0.01. Sensible: 0..0.05.
    pub noise: f64,
    /// Most missing (invalid) beams between two consecutive points that may still be joined.
    /// Default 2. Sensible: 0..5.
    pub max_gap: usize,
}

impl Default for Breakpoints {
    fn default() -> Self {
        Self {
            incidence: 10.0_f64.to_radians(),
            noise: 0.01,
            max_gap: 2,
        }
    }
}

impl Breakpoints {
    /// Checks the settings: `incidence` in `(0, pi/2)`, `noise` finite and `>= 0`.
    ///
    /// # Errors
    /// A [`ParamsError`] naming `breakpoints.incidence` or `breakpoints.noise`.
    pub fn validate(&self) -> Result<(), ParamsError> {
        params::inside(
            "breakpoints.incidence",
            self.incidence,
            0.0,
            std::f64::consts::FRAC_PI_2,
        )?;
        params::non_negative("breakpoints.noise", self.noise)
    }

    /// True when `points[a]` and `points[b]` (`a < b`) are not neighbours on one surface. The
    /// valid points between them, if any, are skipped, not missing.
    pub(crate) fn is_break(&self, points: &[ScanPoint], a: usize, b: usize) -> bool {
        let (a, b, between) = (&points[a], &points[b], b.abs_diff(a));
        let missing = b.index.abs_diff(a.index).saturating_sub(between);
        if missing > self.max_gap {
            return true;
        }
        let dphi = (b.angle - a.angle).abs();
        let denom = (self.incidence - dphi).sin();
        if !(dphi.is_finite() && dphi < self.incidence && denom > 0.0) {
            return true;
        }
        let limit = a.range * dphi.sin() / denom + 3.0 * self.noise;
        let dist = (b.point - a.point).norm();
        dist.is_nan() || limit.is_nan() || dist > limit
    }

    /// Cuts `points` into clusters at every breakpoint; keeps those of at least `min_points`.
    pub(crate) fn clusters(&self, points: &[ScanPoint], min_points: usize, out: &mut Vec<Run>) {
        out.clear();
        let mut start = 0;
        for i in 1..=points.len() {
            if i == points.len() || self.is_break(points, i - 1, i) {
                if i - start >= min_points.max(1) {
                    out.push(Run { start, end: i });
                }
                start = i;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Point2;

    #[test]
    fn breakpoints_cut_at_depth_jumps_only() {
        let inc = 0.01f64;
        let mut pts = Vec::new();
        for i in 0..40 {
            let phi = -0.2 + i as f64 * inc;
            let r = if i < 20 {
                2.0 / phi.cos()
            } else {
                1.0 / phi.cos()
            };
            pts.push(ScanPoint {
                index: i,
                range: r,
                angle: phi,
                point: Point2::new(r * phi.cos(), r * phi.sin()),
            });
        }
        let rule = Breakpoints {
            incidence: 10f64.to_radians(),
            noise: 0.01,
            max_gap: 0,
        };
        let mut out = Vec::new();
        rule.clusters(&pts, 1, &mut out);
        assert_eq!(
            out,
            vec![Run { start: 0, end: 20 }, Run { start: 20, end: 40 }]
        );
        rule.clusters(&pts, 21, &mut out);
        assert!(out.is_empty());
    }

    #[test]
    fn settings_are_checked() {
        assert!(Breakpoints::default().validate().is_ok());
        let bad = Breakpoints {
            incidence: 2.0,
            ..Breakpoints::default()
        };
        assert!(
            bad.validate()
                .unwrap_err()
                .to_string()
                .starts_with("breakpoints.incidence")
        );
    }
}
