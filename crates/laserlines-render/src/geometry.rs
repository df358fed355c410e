//! View extents, axis scales, tick placement and clipping in pixel space.

use laserlines::math::Point2;

/// An axis-aligned rectangle in world units (metres on maps), `min <= max` on both axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extent {
    /// Smallest x.
    pub min_x: f64,
    /// Smallest y.
    pub min_y: f64,
    /// Largest x.
    pub max_x: f64,
    /// Largest y.
    pub max_y: f64,
}

impl Extent {
    /// The rectangle `[min_x, max_x] x [min_y, max_y]`.
    #[must_use]
    pub const fn new(min_x: f64, min_y: f64, max_x: f64, max_y: f64) -> Self {
        Self {
            min_x,
            min_y,
            max_x,
            max_y,
        }
    }

    /// The smallest extent holding every finite point, or `None` when there is none.
    pub fn from_points<I: IntoIterator<Item = Point2>>(points: I) -> Option<Self> {
        let mut out: Option<Self> = None;
        for p in points {
            if !(p.x.is_finite() && p.y.is_finite()) {
                continue;
            }
            out = Some(match out {
                None => Self::new(p.x, p.y, p.x, p.y),
                Some(e) => e.including(p),
            });
        }
        out
    }

    /// True when every bound is finite, `min < max` on both axes and the size is drawable
    /// (neither degenerate nor astronomically large).
    #[must_use]
    pub fn is_valid(&self) -> bool {
        let w = self.max_x - self.min_x;
        let h = self.max_y - self.min_y;
        [self.min_x, self.min_y, self.max_x, self.max_y]
            .iter()
            .all(|v| v.is_finite() && v.abs() < 1e12)
            && w > 1e-9
            && h > 1e-9
            && w.is_finite()
            && h.is_finite()
    }

    /// The extent grown to hold `p` (non-finite points are ignored).
    #[must_use]
    pub fn including(self, p: Point2) -> Self {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return self;
        }
        Self::new(
            self.min_x.min(p.x),
            self.min_y.min(p.y),
            self.max_x.max(p.x),
            self.max_y.max(p.y),
        )
    }

    /// The extent grown by `margin` on every side.
    #[must_use]
    pub fn padded(self, margin: f64) -> Self {
        Self::new(
            self.min_x - margin,
            self.min_y - margin,
            self.max_x + margin,
            self.max_y + margin,
        )
    }

    /// Width, world units.
    #[must_use]
    pub fn width(&self) -> f64 {
        self.max_x - self.min_x
    }

    /// Height, world units.
    #[must_use]
    pub fn height(&self) -> f64 {
        self.max_y - self.min_y
    }

    /// The centre.
    #[must_use]
    pub fn center(&self) -> Point2 {
        Point2::new(
            0.5 * (self.min_x + self.max_x),
            0.5 * (self.min_y + self.max_y),
        )
    }

    /// An extent fitting a map of points: the points and the origin (the sensor), at least
    /// `min_span` wide and high, then padded by 6 % of the larger side. Falls back to a
    /// square of `min_span` (padded) around the origin when there is no finite point.
    #[must_use]
    pub fn fit_map<I: IntoIterator<Item = Point2>>(points: I, min_span: f64) -> Self {
        let min_span = if min_span.is_finite() && min_span > 0.0 {
            min_span
        } else {
            1.0
        };
        let base = Extent::from_points(points)
            .map_or_else(
                || Self::new(0.0, 0.0, 0.0, 0.0),
                |e| e.including(Point2::origin()),
            )
            // Astronomic ranges would make the picture useless and the numbers unreadable.
            .clamped(1e6);
        let mut e = base;
        for (lo, hi) in [(&mut e.min_x, &mut e.max_x), (&mut e.min_y, &mut e.max_y)] {
            let span = *hi - *lo;
            if span < min_span {
                let grow = 0.5 * (min_span - span);
                *lo -= grow;
                *hi += grow;
            }
        }
        e.padded(0.06 * e.width().max(e.height()))
    }

    fn clamped(self, limit: f64) -> Self {
        Self::new(
            self.min_x.clamp(-limit, limit),
            self.min_y.clamp(-limit, limit),
            self.max_x.clamp(-limit, limit),
            self.max_y.clamp(-limit, limit),
        )
    }
}

/// A monotone map from a data interval to a pixel interval, linear or base-10 logarithmic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Scale {
    pub(crate) min: f64,
    pub(crate) max: f64,
    pub(crate) log: bool,
    pub(crate) px0: f64,
    pub(crate) px1: f64,
}

impl Scale {
    fn t(&self, v: f64) -> Option<f64> {
        let (v, lo, hi) = if self.log {
            if v <= 0.0 {
                return None;
            }
            (v.log10(), self.min.log10(), self.max.log10())
        } else {
            (v, self.min, self.max)
        };
        let t = (v - lo) / (hi - lo);
        t.is_finite().then_some(t)
    }

    /// Pixel of data value `v`, `None` when it has none (non-finite, or `<= 0` on a log
    /// scale).
    pub(crate) fn map(&self, v: f64) -> Option<f64> {
        let t = self.t(v)?;
        let px = self.px0 + t * (self.px1 - self.px0);
        px.is_finite().then_some(px)
    }

    /// Pixels per data unit (linear scales).
    pub(crate) fn px_per_unit(&self) -> f64 {
        (self.px1 - self.px0).abs() / (self.max - self.min)
    }
}

/// The nice number (1, 2 or 5 times a power of ten) nearest above `x > 0`; `1` for
/// degenerate input.
#[must_use]
pub fn nice_step(x: f64) -> f64 {
    if !(x.is_finite() && x > 0.0) {
        return 1.0;
    }
    let p = 10f64.powf(x.log10().floor());
    let f = x / p;
    let m = if f <= 1.0 + 1e-9 {
        1.0
    } else if f <= 2.0 + 1e-9 {
        2.0
    } else if f <= 5.0 + 1e-9 {
        5.0
    } else {
        10.0
    };
    m * p
}

/// The largest nice number (1, 2 or 5 times a power of ten) not above `x > 0`; `1` for
/// degenerate input.
#[must_use]
pub fn nice_floor(x: f64) -> f64 {
    if !(x.is_finite() && x > 0.0) {
        return 1.0;
    }
    let p = 10f64.powf(x.log10().floor());
    let f = x / p;
    let m = if f >= 5.0 - 1e-9 {
        5.0
    } else if f >= 2.0 - 1e-9 {
        2.0
    } else {
        1.0
    };
    m * p
}

/// Decimals needed to print multiples of a nice `step` exactly (0 for 1, 2, 5, 10...).
#[must_use]
pub fn decimals_for(step: f64) -> usize {
    if !(step.is_finite() && step > 0.0) {
        return 0;
    }
    let d = -(step.log10() + 1e-9).floor();
    if d > 0.0 { (d as usize).min(9) } else { 0 }
}

/// Multiples of `step` within `[min, max]` (at most 200 of them).
#[must_use]
pub fn ticks(min: f64, max: f64, step: f64) -> Vec<f64> {
    let mut out = Vec::new();
    if !(min.is_finite() && max.is_finite() && step.is_finite() && step > 0.0 && min <= max) {
        return out;
    }
    let first = (min / step - 1e-9).ceil();
    let last = (max / step + 1e-9).floor();
    if !(first.is_finite() && last.is_finite()) || last - first > 200.0 {
        return out;
    }
    let mut k = first;
    while k <= last {
        let v = k * step;
        // Keep "0" rather than "-0".
        out.push(if v == 0.0 { 0.0 } else { v });
        k += 1.0;
    }
    out
}

/// A rectangle in pixels, for clipping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PxRect {
    pub(crate) x0: f64,
    pub(crate) y0: f64,
    pub(crate) x1: f64,
    pub(crate) y1: f64,
}

impl PxRect {
    pub(crate) fn contains(&self, p: [f64; 2]) -> bool {
        p[0] >= self.x0 && p[0] <= self.x1 && p[1] >= self.y0 && p[1] <= self.y1
    }

    /// The part of segment `a`-`b` inside the rectangle, if any. Clips against one edge
    /// at a time, computing each intersection from the end that is inside that edge, so that
    /// a segment towards a very far point keeps its direction near the plot.
    pub(crate) fn clip_segment(&self, a: [f64; 2], b: [f64; 2]) -> Option<([f64; 2], [f64; 2])> {
        let finite = |p: [f64; 2]| p[0].is_finite() && p[1].is_finite();
        if !(finite(a) && finite(b)) {
            return None;
        }
        let (mut a, mut b) = (a, b);
        for (axis, bound, greater) in [
            (0, self.x0, true),
            (0, self.x1, false),
            (1, self.y0, true),
            (1, self.y1, false),
        ] {
            let inside = |p: [f64; 2]| {
                if greater {
                    p[axis] >= bound
                } else {
                    p[axis] <= bound
                }
            };
            let (ai, bi) = (inside(a), inside(b));
            if !ai && !bi {
                return None;
            }
            if ai && bi {
                continue;
            }
            let (pin, pout) = if ai { (a, b) } else { (b, a) };
            let o = 1 - axis;
            let slope = (pout[o] - pin[o]) / (pout[axis] - pin[axis]);
            let mut cut = [0.0; 2];
            cut[axis] = bound;
            cut[o] = pin[o] + (bound - pin[axis]) * slope;
            if !finite(cut) {
                return None;
            }
            if ai {
                b = cut;
            } else {
                a = cut;
            }
        }
        Some((a, b))
    }

    /// Sutherland-Hodgman: the polygon clipped to the rectangle (possibly empty).
    pub(crate) fn clip_polygon(&self, poly: &[[f64; 2]]) -> Vec<[f64; 2]> {
        let mut out: Vec<[f64; 2]> = poly
            .iter()
            .copied()
            .filter(|p| p[0].is_finite() && p[1].is_finite())
            .collect();
        // (axis, bound, keep_if_greater)
        for (axis, bound, greater) in [
            (0, self.x0, true),
            (0, self.x1, false),
            (1, self.y0, true),
            (1, self.y1, false),
        ] {
            if out.is_empty() {
                break;
            }
            let inside = |p: &[f64; 2]| {
                if greater {
                    p[axis] >= bound
                } else {
                    p[axis] <= bound
                }
            };
            let input = std::mem::take(&mut out);
            let mut prev = input[input.len() - 1];
            for &cur in &input {
                let (ci, pi) = (inside(&cur), inside(&prev));
                if ci != pi {
                    let t = (bound - prev[axis]) / (cur[axis] - prev[axis]);
                    out.push([
                        prev[0] + t * (cur[0] - prev[0]),
                        prev[1] + t * (cur[1] - prev[1]),
                    ]);
                }
                if ci {
                    out.push(cur);
                }
                prev = cur;
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_numbers() {
        assert_eq!(nice_step(0.7), 1.0);
        assert_eq!(nice_step(1.3), 2.0);
        assert_eq!(nice_step(3.0), 5.0);
        assert_eq!(nice_step(6.0), 10.0);
        assert!((nice_step(0.013) - 0.02).abs() < 1e-12);
        assert_eq!(nice_floor(0.7), 0.5);
        assert_eq!(nice_floor(4.9), 2.0);
        assert_eq!(nice_floor(f64::NAN), 1.0);
        assert_eq!(decimals_for(0.5), 1);
        assert_eq!(decimals_for(0.25), 1);
        assert_eq!(decimals_for(0.05), 2);
        assert_eq!(decimals_for(2.0), 0);
    }

    #[test]
    fn ticks_cover_the_interval() {
        assert_eq!(ticks(-0.3, 1.1, 0.5), vec![0.0, 0.5, 1.0]);
        assert_eq!(ticks(0.0, 1.0, 0.5), vec![0.0, 0.5, 1.0]);
        assert!(ticks(0.0, 1e9, 1e-3).is_empty());
        assert!(ticks(f64::NAN, 1.0, 0.5).is_empty());
    }

    #[test]
    fn fit_map_holds_points_and_origin() {
        let e = Extent::fit_map([Point2::new(2.0, 1.0), Point2::new(3.0, -1.0)], 1.0);
        assert!(e.min_x < 0.0 && e.max_x > 3.0 && e.min_y < -1.0 && e.max_y > 1.0);
        let empty = Extent::fit_map(std::iter::empty(), 2.0);
        assert!(empty.is_valid() && (empty.width() - 2.24).abs() < 1e-12);
        let nan = Extent::fit_map([Point2::new(f64::NAN, 1.0)], 2.0);
        assert!(nan.is_valid());
        let huge = Extent::fit_map([Point2::new(1e300, 1.0)], 2.0);
        assert!(huge.is_valid());
    }

    #[test]
    fn clipping() {
        let r = PxRect {
            x0: 0.0,
            y0: 0.0,
            x1: 10.0,
            y1: 10.0,
        };
        let (a, b) = r.clip_segment([-5.0, 5.0], [15.0, 5.0]).unwrap();
        assert_eq!((a, b), ([0.0, 5.0], [10.0, 5.0]));
        assert!(r.clip_segment([-5.0, -5.0], [-1.0, 20.0]).is_none());
        assert!(r.clip_segment([0.0, 0.0], [f64::INFINITY, 1.0]).is_none());
        let tri = r.clip_polygon(&[[5.0, 5.0], [20.0, 5.0], [5.0, 20.0]]);
        assert!(tri.iter().all(|p| r.contains(*p)));
        assert_eq!(tri.len(), 4);
        assert!(
            r.clip_polygon(&[[20.0, 20.0], [30.0, 20.0], [25.0, 30.0]])
                .is_empty()
        );
    }

    #[test]
    fn log_scale_rejects_non_positive() {
        let s = Scale {
            min: 1.0,
            max: 100.0,
            log: true,
            px0: 0.0,
            px1: 200.0,
        };
        assert_eq!(s.map(10.0), Some(100.0));
        assert_eq!(s.map(0.0), None);
        assert_eq!(s.map(f64::NAN), None);
    }
}
