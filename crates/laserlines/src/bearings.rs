//! Readings at arbitrary bearings as a scan of evenly spaced beams.
//!
//! Spinning scanners with a rotating head (RPLIDAR, YDLIDAR, the LDS-01 and their kin) report
//! each reading with its own bearing: the bearings are not evenly spaced and drift from one
//! revolution to the next. A [`Scan`] has evenly spaced beams, `angle_min + i *
//! angle_increment`, as `sensor_msgs/LaserScan`; [`grid`] puts each reading on the beam of
//! such a grid nearest its bearing, as the ROS drivers of these scanners do.
//!
//! - Bearings are counter-clockwise seen from above (REP 103), in radians, any turn: they
//!   are taken modulo a full turn. (The RPLIDAR SDK gives clockwise degrees: pass
//!   `-theta.to_radians()`.)
//! - The spacing is the median spacing of the distinct bearings, or the one given.
//! - Readings that cover the circle (no gap wider than 4 spacings) make a full turn of
//!   `round(2 pi / spacing)` beams, the spacing then adjusted to close the turn; a sector
//!   starts at the reading after its widest gap (where a scanner's blind side is).
//! - A beam without a reading is NaN (no reading). Two readings on one beam keep the better:
//!   a measurement ([`RangeWindow::contains`]: finite, above 0, inside the limits) before
//!   anything else (a 0 that means "no return"), and of two measurements the nearer (an
//!   obstacle is not hidden). [`Gridded::shared`] counts the
//!   readings left out so.

use std::f64::consts::{PI, TAU};

use crate::scan::{MAX_ANGLE_MIN, RangeWindow, Scan, ScanError, Short};

/// The most beams [`grid`] makes (a tenth of a millidegree over a full turn is 3.6 million).
pub const MAX_GRID_BEAMS: usize = 1 << 22;

/// The widest gap, in spacings, of readings that go once round.
const FULL_TURN_GAP: f64 = 4.0;

/// Why readings do not make a scan.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GridError {
    /// As many bearings as ranges are needed.
    #[error("{bearings} bearings but {ranges} ranges: one bearing per range")]
    LengthMismatch {
        /// Bearings given.
        bearings: usize,
        /// Ranges given.
        ranges: usize,
    },
    /// No reading at all.
    #[error("no readings")]
    Empty,
    /// A bearing that is NaN, infinite or beyond [`MAX_ANGLE_MIN`] (where neighbouring
    /// bearings round to one) cannot be placed.
    #[error("bearing {index} must be finite and within +-1000 rad, got {}", Short(*value))]
    BearingNotFinite {
        /// Index of the reading.
        index: usize,
        /// Its bearing.
        value: f64,
    },
    /// The spacing given is not positive and finite, or none can be told from the bearings
    /// (a single distinct bearing).
    #[error(
        "the spacing of the beams must be positive and finite, got {} (give angle_increment \
         when every reading has the same bearing)",
        Short(*.0)
    )]
    BadIncrement(f64),
    /// The spacing is so fine that the grid would hold more than [`MAX_GRID_BEAMS`] beams.
    #[error("a spacing of {} rad over {} rad makes {beams} beams, more than {max}", Short(*increment), Short(*span))]
    TooManyBeams {
        /// The spacing, rad.
        increment: f64,
        /// The bearings' span, rad.
        span: f64,
        /// Beams it would take.
        beams: f64,
        /// [`MAX_GRID_BEAMS`].
        max: usize,
    },
    /// The range limits (or the scan built) are not valid.
    #[error(transparent)]
    Scan(#[from] ScanError),
}

/// A scan made by [`grid`], and what the gridding left out.
#[derive(Debug, Clone, PartialEq)]
pub struct Gridded {
    /// The scan: `angle_min` in `[-pi, pi)`, `angle_increment` positive.
    pub scan: Scan,
    /// Readings left out because their beam kept a better one.
    pub shared: usize,
}

/// The readings `ranges[i]` at bearings `bearings[i]` (rad) on a grid of evenly spaced beams
/// `increment` apart (the bearings' median spacing when `None`), with range limits
/// `range_min`, `range_max` (m). See the module docs.
///
/// # Errors
/// [`GridError`]: lengths that differ, no readings, a bearing that is not finite, a spacing
/// that is not positive (or cannot be told), too many beams, limits out of order.
pub fn grid(
    bearings: &[f64],
    ranges: &[f64],
    increment: Option<f64>,
    range_min: f64,
    range_max: f64,
) -> Result<Gridded, GridError> {
    if bearings.len() != ranges.len() {
        return Err(GridError::LengthMismatch {
            bearings: bearings.len(),
            ranges: ranges.len(),
        });
    }
    if bearings.is_empty() {
        return Err(GridError::Empty);
    }
    // The limits are checked before any work.
    Scan::new(0.0, 1.0, range_min, range_max, Vec::new())?;
    let mut order = Vec::with_capacity(bearings.len());
    for (index, &value) in bearings.iter().enumerate() {
        if !(value.is_finite() && value.abs() <= MAX_ANGLE_MIN) {
            return Err(GridError::BearingNotFinite { index, value });
        }
        order.push((wrap(value), index));
    }
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
    let inc = match increment {
        Some(inc) => inc,
        None => median_spacing(&order),
    };
    if !(inc.is_finite() && inc > 0.0) {
        return Err(GridError::BadIncrement(inc));
    }
    let layout = Layout::of(&order, inc)?;
    let mut out = vec![f64::NAN; layout.beams];
    let mut taken = vec![false; layout.beams];
    let mut shared = 0;
    // A measurement (finite, above 0, inside the limits, below the saturated limit) first,
    // then the nearer; a NaN never wins (its comparison fails).
    let window = RangeWindow::new(range_min, crate::scan::saturated_below(range_max));
    let rank = |r: f64| (window.contains(r), r);
    for &(b, i) in &order {
        let (k, new) = (layout.beam(b), ranges[i]);
        if !taken[k] {
            (out[k], taken[k]) = (new, true);
            continue;
        }
        shared += 1;
        let (old, new) = (rank(out[k]), rank(new));
        if (new.0 && !old.0) || (new.0 == old.0 && new.1 < old.1) {
            out[k] = new.1;
        }
    }
    let scan = Scan::new(layout.start, layout.inc, range_min, range_max, out)?;
    Ok(Gridded { scan, shared })
}

/// `b` in `[-pi, pi)`.
fn wrap(b: f64) -> f64 {
    let w = b - TAU * ((b + PI) / TAU).floor();
    // Rounding may land on `pi` itself.
    if w >= PI { w - TAU } else { w }
}

/// The median of the spacings between consecutive distinct bearings of `sorted` (NaN when
/// all are one).
fn median_spacing(sorted: &[(f64, usize)]) -> f64 {
    let mut gaps: Vec<f64> = sorted
        .windows(2)
        .map(|w| w[1].0 - w[0].0)
        .filter(|g| *g > 1e-12)
        .collect();
    if gaps.is_empty() {
        return f64::NAN;
    }
    let mid = gaps.len() / 2;
    *gaps.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// Where the grid starts, its spacing and beams.
struct Layout {
    start: f64,
    inc: f64,
    beams: usize,
    /// The grid goes once round: beam indices wrap.
    turn: bool,
}

impl Layout {
    fn of(sorted: &[(f64, usize)], inc: f64) -> Result<Self, GridError> {
        let first = sorted[0].0;
        let last = sorted[sorted.len() - 1].0;
        // The widest gap between neighbouring bearings, round the circle.
        let (mut widest, mut after) = (first + TAU - last, 0);
        for (k, w) in sorted.windows(2).enumerate() {
            if w[1].0 - w[0].0 > widest {
                (widest, after) = (w[1].0 - w[0].0, k + 1);
            }
        }
        let too_many = |beams: f64, span: f64| GridError::TooManyBeams {
            increment: inc,
            span,
            beams,
            max: MAX_GRID_BEAMS,
        };
        // Jittered bearings leave gaps of up to two spacings; a blind side is far wider.
        if widest <= FULL_TURN_GAP * inc {
            let beams = (TAU / inc).round();
            if beams > MAX_GRID_BEAMS as f64 {
                return Err(too_many(beams, TAU));
            }
            let beams = (beams as usize).max(3);
            return Ok(Self {
                start: first,
                inc: TAU / beams as f64,
                beams,
                turn: true,
            });
        }
        let start = sorted[after].0;
        let span = TAU - widest;
        let beams = (span / inc).round() + 1.0;
        if beams > MAX_GRID_BEAMS as f64 {
            return Err(too_many(beams, span));
        }
        // A sector wider than a turn less one spacing would repeat its first beam.
        let beams = (beams as usize).min((TAU / inc).floor() as usize).max(1);
        Ok(Self {
            start,
            inc,
            beams,
            turn: false,
        })
    }

    /// The beam nearest bearing `b` (in `[-pi, pi)`).
    fn beam(&self, b: f64) -> usize {
        let mut u = b - self.start;
        if u < 0.0 {
            u += TAU;
        }
        let k = (u / self.inc).round() as usize;
        if self.turn {
            k % self.beams
        } else {
            k.min(self.beams - 1)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{HoughSplit, HoughSplitParams, LineExtractor};

    /// A deterministic generator of numbers in `[0, 1)`.
    struct Lcg(u64);

    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// The range at bearing `b` from `(px, py)` inside the room `[-2, 2] x [-1.5, 1.5]`.
    fn room_range(px: f64, py: f64, b: f64) -> f64 {
        let (c, s) = (b.cos(), b.sin());
        let mut best = f64::INFINITY;
        for (d, along) in [(2.0 - px, c), (-2.0 - px, c), (1.5 - py, s), (-1.5 - py, s)] {
            let t = d / along;
            if t > 0.0 && t < best {
                best = t;
            }
        }
        best
    }

    #[test]
    fn evenly_spaced_readings_in_any_order_give_their_scan_back() {
        let inc = 1f64.to_radians();
        // A full turn of 360 beams, given from 0 to 2 pi and shuffled.
        let bearings: Vec<f64> = (0..360).map(|i| f64::from(i) * inc).collect();
        let ranges: Vec<f64> = (0..360).map(|i| 1.0 + f64::from(i) * 0.01).collect();
        let mut rng = Lcg(7);
        let mut order: Vec<usize> = (0..360).collect();
        for i in (1..order.len()).rev() {
            order.swap(i, (rng.next() * (i + 1) as f64) as usize);
        }
        let b: Vec<f64> = order.iter().map(|&i| bearings[i]).collect();
        let r: Vec<f64> = order.iter().map(|&i| ranges[i]).collect();
        let g = grid(&b, &r, None, 0.1, 12.0).unwrap();
        assert_eq!(g.shared, 0);
        assert!(g.scan.full_turn());
        assert_eq!(g.scan.ranges.len(), 360);
        assert!((g.scan.angle_increment - inc).abs() < 1e-12);
        // The turn starts at the smallest bearing in [-pi, pi): beam 180 of the input.
        assert!((g.scan.angle_min + PI).abs() < 1e-9, "{}", g.scan.angle_min);
        for (k, got) in g.scan.ranges.iter().enumerate() {
            assert_eq!(*got, ranges[(k + 180) % 360], "beam {k}");
        }
    }

    #[test]
    fn a_sector_starts_after_its_widest_gap() {
        // Bearings from -2 to 2 rad, given in [0, 2 pi): the gap behind the scanner.
        let inc = 0.5f64.to_radians();
        let n = (4.0 / inc).round() as usize + 1;
        let bearings: Vec<f64> = (0..n)
            .map(|i| (-2.0 + i as f64 * inc).rem_euclid(TAU))
            .collect();
        let ranges: Vec<f64> = (0..n).map(|i| 2.0 + i as f64 * 1e-3).collect();
        let g = grid(&bearings, &ranges, None, 0.1, 12.0).unwrap();
        assert!(!g.scan.full_turn());
        assert!(
            (g.scan.angle_min + 2.0).abs() < 1e-9,
            "{}",
            g.scan.angle_min
        );
        assert_eq!(g.scan.ranges, ranges);
    }

    #[test]
    fn jittered_readings_of_a_room_give_its_four_walls() {
        // An RPLIDAR-like turn: about 0.9 deg apart, each bearing off by up to 0.4 of that,
        // 1 cm of range noise, a few readings without a return (0).
        let (px, py) = (0.5, -0.3);
        let mut rng = Lcg(11);
        let step = 0.9f64.to_radians();
        let mut bearings = Vec::new();
        let mut ranges = Vec::new();
        let mut b = 0.3;
        while b < 0.3 + TAU - 0.5 * step {
            let jitter = (rng.next() - 0.5) * 0.8 * step;
            let bearing = b + jitter;
            let noise = (rng.next() + rng.next() + rng.next() - 1.5) * 0.02;
            let r = if rng.next() < 0.03 {
                0.0
            } else {
                room_range(px, py, bearing) + noise
            };
            bearings.push(bearing);
            ranges.push(r);
            b += step * (1.0 + 0.05 * (rng.next() - 0.5));
        }
        let g = grid(&bearings, &ranges, None, 0.15, 12.0).unwrap();
        assert!(g.scan.full_turn());
        // Every reading is on a beam or counted as shared (all ranges here are numbers).
        let held = g.scan.ranges.iter().filter(|r| !r.is_nan()).count();
        assert_eq!(held + g.shared, bearings.len());
        assert!(g.shared > 0);
        let lines = HoughSplit::new(HoughSplitParams::default())
            .unwrap()
            .extract(&g.scan);
        // The walls x = 2, x = -2, y = 1.5, y = -1.5 seen from (0.5, -0.3): (r, alpha).
        let walls = [(1.5, 0.0), (2.5, PI), (1.8, PI / 2.0), (1.2, -PI / 2.0)];
        for (r, alpha) in walls {
            let found = lines.iter().any(|l| {
                let da = (l.alpha - alpha + PI).rem_euclid(TAU) - PI;
                (l.r - r).abs() < 0.03 && da.abs() < 2f64.to_radians()
            });
            assert!(found, "wall r {r} alpha {alpha}: {lines:?}");
        }
    }

    #[test]
    fn readings_on_one_beam_keep_the_better_and_are_counted() {
        let inc = 1f64.to_radians();
        let bearings = [0.0, inc, inc * 1.1, 2.0 * inc, 2.0 * inc + 1e-4, 3.0 * inc];
        let ranges = [1.0, 3.0, 2.5, 0.0, 4.0, 1.0];
        let g = grid(&bearings, &ranges, Some(inc), 0.15, 12.0).unwrap();
        // Beam 1: 2.5 is nearer than 3.0; beam 2: 4.0 lies inside the limits, 0 does not.
        assert_eq!(g.scan.ranges, vec![1.0, 2.5, 4.0, 1.0]);
        assert_eq!(g.shared, 2);
        // A 0 ("no return") loses to a reading even when the limits start at 0.
        let g = grid(&[0.0, 1e-4], &[0.0, 4.0], Some(inc), 0.0, 12.0).unwrap();
        assert_eq!(g.scan.ranges, vec![4.0]);
        // A beam without a reading is NaN.
        let g = grid(&[0.0, 2.0 * inc], &[1.0, 1.0], Some(inc), 0.15, 12.0).unwrap();
        assert_eq!(g.scan.ranges.len(), 3);
        assert!(g.scan.ranges[1].is_nan());
    }

    #[test]
    fn bad_readings_are_errors_naming_them() {
        let e = grid(&[0.0, 1.0], &[1.0], None, 0.1, 5.0).unwrap_err();
        assert_eq!(
            e.to_string(),
            "2 bearings but 1 ranges: one bearing per range"
        );
        let e = grid(&[0.0, f64::NAN, 0.2], &[1.0; 3], None, 0.1, 5.0).unwrap_err();
        assert!(
            matches!(e, GridError::BearingNotFinite { index: 1, value } if value.is_nan()),
            "{e}"
        );
        assert_eq!(
            e.to_string(),
            "bearing 1 must be finite and within +-1000 rad, got NaN"
        );
        let e = grid(&[0.0, 1e300], &[1.0; 2], None, 0.1, 5.0).unwrap_err();
        assert!(
            matches!(e, GridError::BearingNotFinite { index: 1, .. }),
            "{e}"
        );
        assert!(matches!(
            grid(&[0.5, 0.5], &[1.0, 2.0], None, 0.1, 5.0),
            Err(GridError::BadIncrement(_))
        ));
        assert!(matches!(
            grid(&[0.0, 1.0], &[1.0, 2.0], Some(-0.1), 0.1, 5.0),
            Err(GridError::BadIncrement(_))
        ));
        assert!(matches!(
            grid(&[0.0, 1.0], &[1.0, 2.0], Some(1e-9), 0.1, 5.0),
            Err(GridError::TooManyBeams { .. })
        ));
        assert!(matches!(
            grid(&[0.0, 1.0], &[1.0, 2.0], None, 5.0, 0.1),
            Err(GridError::Scan(ScanError::BadRangeLimits { .. }))
        ));
        assert_eq!(grid(&[], &[], None, 0.1, 5.0), Err(GridError::Empty));
    }
}
