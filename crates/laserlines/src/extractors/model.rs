//! The small geometric models the extractors share: a distance threshold that grows with
//! range, and a line hypothesis in normal form.

use crate::fit::PolarFit;
use crate::math::{Point2, Vector2};

/// A threshold that grows linearly with range: `base + per_metre * range`, metres.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Scaled {
    pub(crate) base: f64,
    pub(crate) per_metre: f64,
}

impl Scaled {
    pub(crate) fn at(self, range: f64) -> f64 {
        self.base + self.per_metre * range
    }
}

/// A line as a unit normal `n` and distance `d`: points `p` with `n . p = d`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Hypothesis {
    pub(crate) normal: Vector2,
    pub(crate) d: f64,
}

impl Hypothesis {
    pub(crate) fn from_fit(fit: &PolarFit) -> Self {
        Self {
            normal: fit.normal(),
            d: fit.r,
        }
    }

    /// The line through two points, or `None` when they (nearly) coincide.
    pub(crate) fn through(a: Point2, b: Point2) -> Option<Self> {
        let ab = b - a;
        let len = ab.norm();
        if !(len.is_finite() && len > 1e-9) {
            return None;
        }
        let normal = Vector2::new(-ab.y / len, ab.x / len);
        Some(Self {
            normal,
            d: normal.dot(&a.coords),
        })
    }

    pub(crate) fn distance(&self, p: Point2) -> f64 {
        (self.normal.dot(&p.coords) - self.d).abs()
    }
}
