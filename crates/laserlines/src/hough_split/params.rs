//! Parameters of [`super::HoughSplit`].

use crate::noise::{NoiseModel, SPARSE_DROPOUT};
use crate::params::ParamsError;
use crate::scan::RangeWindow;

/// The finest `ring_step`, m: finer rings would number beyond the accumulator's ring indices
/// at tens of metres.
pub const MIN_RING_STEP: f64 = 1e-4;

/// The widest `ring_step`, m: a ring wider than any 2D scanner's range holds every point of
/// a sector, and the Hough grouping means nothing.
pub const MAX_RING_STEP: f64 = 100.0;

/// The widest `window`, in `ring_step`s: a point votes in every ring its window meets.
pub const MAX_WINDOW_RINGS: f64 = 64.0;

/// Beams of the paper's sector (2.47 deg of the URG-04LX's 360/1024 deg steps), which
/// [`HoughSplitParams::criterion`] is stated for.
pub const PAPER_SECTOR_BEAMS: f64 = 2.47 / (360.0 / 1024.0);

/// The chance with which dropouts alone may leave a gap wider than the beam bridge spans
/// after a point ([`HoughSplitParams::bridge_for`]).
pub const GAP_CHANCE: f64 = 0.01;

/// Most missing beams in a row any beam bridge spans.
pub const MAX_BRIDGE_GAP: usize = 63;

/// The largest dropout rate the beam bridge adapts to: beyond it, a scan is read as one with
/// 95 % of its beams missing.
const MAX_DROPOUT: f64 = 0.95;

/// The dropout rate `dropout` clamped to `0..=MAX_DROPOUT` (NaN giving 0) and the longest gap
/// of missing beams that dropouts alone leave after a point with a chance above
/// [`GAP_CHANCE`]: the largest `g` with `dropout^g > GAP_CHANCE` (0 without dropouts).
fn gap_by_chance(dropout: f64) -> (f64, usize) {
    let p = if dropout.is_finite() {
        dropout.clamp(0.0, MAX_DROPOUT)
    } else {
        0.0
    };
    let by_chance = if p > 0.0 {
        // At most `ln(0.01) / ln(0.95)` = 90: no overflow.
        ((GAP_CHANCE.ln() / p.ln()).ceil() as usize).saturating_sub(1)
    } else {
        0
    };
    (p, by_chance)
}

/// The largest `lambda` of `D` that sparse returns raise it to (60 deg: `D` at most `0.53 r`).
const MAX_LAMBDA: f64 = std::f64::consts::FRAC_PI_3;

/// Fewest points a data segment or a line keeps on a sparse scan
/// ([`HoughSplitParams::min_points_for`]), when `min_segment_points` or `min_line_points`
/// asks for more. With 5, scans missing 85-90 % of their beams gave twice the false lines
/// of 8 (a fit of five points that far apart is often off by more than 5 cm or 3 deg, and
/// a stray point across a gap more often ends a line); 6 keeps most of the pieces found.
pub const MIN_SPARSE_POINTS: usize = 6;

/// The fewest points of one scan's data segments and lines
/// ([`HoughSplitParams::min_points_for`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MinPoints {
    /// Fewest surviving points of a data segment.
    pub segment: usize,
    /// Fewest supporting points of a line.
    pub line: usize,
}

/// The beam bridge of one scan: how far apart consecutive points of a data segment may be.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bridge {
    /// Most missing beams between consecutive points.
    pub max_gap: usize,
    /// The mean angle between returns that `D` is computed for, rad
    /// ([`HoughSplitParams::breakpoint_distance`]'s `step`).
    pub spacing: f64,
}

/// A limit that `inf` turns off, read from a number or, as JSON writes `inf`, from `null`.
#[cfg(feature = "serde")]
fn off_or_f64<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    use serde::Deserialize;
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::INFINITY))
}

/// The weight function `g` of the paper's eq. (1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(rename_all = "lowercase")
)]
pub enum Weight {
    /// `g = 1`: a cell's value counts its points.
    One,
    /// `g = r_i`: a cell's value sums the ranges of its points, metres. Recommended by the
    /// paper: it compensates the density of points falling with range.
    #[default]
    Range,
}

/// Parameters of the paper's extractor, with the paper's grid as defaults (in SI units).
///
/// Every decision after the accumulator is taken in units of the range noise `sigma(r)`
/// ([`crate::noise`]), estimated from each scan by default: the same defaults serve a
/// URG-04LX at its real 3-5 mm and a cheap scanner at 1.5 % of the range. With
/// [`Weight::Range`] the cell values compensate for the density falling with range.
///
/// A line is kept only when its standard errors place it about within the tolerances of a
/// user who wants walls (`max_r_sd` 6 cm, `max_alpha_sd` 3 deg): a short piece far off under
/// heavy noise, which no fit can place that well, gives no line. [`HoughSplitParams::complete`]
/// keeps those too.
///
/// [`HoughSplitParams::paper`] turns every extension off: the paper's pipeline alone.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct HoughSplitParams {
    /// Ring step `dd` of the accumulator, m. Paper: 0.03 m. Sensible: 0.01..0.10; from
    /// [`MIN_RING_STEP`] to [`MAX_RING_STEP`].
    pub ring_step: f64,
    /// Sector step `dgamma` of the accumulator, rad. Paper: 2.47 deg (about 7 beams of a
    /// URG-04LX). Sensible: 1..10 beam increments; below a full turn.
    pub sector_step: f64,
    /// Half-width `a` of the rectangular window `w`, m. Default `ring_step / 2` (each point
    /// votes in one ring, two when it falls on a boundary). Sensible: 0.5..1.5 ring steps; at
    /// most [`MAX_WINDOW_RINGS`] ring steps.
    pub window: f64,
    /// Weight `g`. Default [`Weight::Range`].
    pub weight: Weight,
    /// Noise-cancelling criterion: cells whose weighted value is not above it are set to zero.
    /// With `g = 1` it counts points (the paper's Fig. 3 uses 1: cells of 2..7 points remain);
    /// with `g = r` it is in metres (sum of ranges). Default 0.5 (with `g = r`: a lone point
    /// nearer than 0.5 m is noise). Stated for sectors of 7 beams, as the paper's; scaled
    /// down where a sector holds fewer ([`HoughSplitParams::criterion_for`]). Sensible: 0..3.
    pub criterion: f64,
    /// Cells bridged in the sector direction when grouping along a ring (the paper's
    /// adjustable radius-grouping threshold). Default 1. Sensible: 0..3.
    pub group_gap: usize,
    /// The range noise every later threshold is a multiple of: [`NoiseModel::Auto`] (default)
    /// estimates it from each scan; [`NoiseModel::Fixed`] takes a data sheet's model
    /// ([`crate::noise::PRESETS`]).
    pub noise: NoiseModel,
    /// The least standard deviation used, m: quantisation and the surfaces' own roughness
    /// stay even when a scan looks perfect. Default 0.002. Sensible: 0.0005..0.01.
    pub noise_floor: f64,
    /// Also join consecutive valid points (up to `bridge_max_gap` missing beams apart) closer
    /// than the breakpoint distance `D` (see [`HoughSplitParams::breakpoint_distance`]), so
    /// that a wall whose noisy or grazing points skip rings stays one data segment. Not in
    /// the paper (`false` gives the paper's pure grid connectivity). Default `true`.
    pub bridge_beams: bool,
    /// Smallest angle between beam and surface that `D` still joins, rad (the `lambda` of
    /// Borges & Aldon 2004): a corridor wall seen lengthwise stays one segment down to this
    /// angle. On coarse scanners it is raised to ten beam steps (10 deg for a 1 deg
    /// scanner), where a shallower surface's points lie too far apart to tell it from a gap.
    /// Default 4 deg. Sensible: 3..15 deg.
    pub bridge_incidence: f64,
    /// Noise allowance of `D`, in standard deviations of the distance between two points
    /// (`sqrt(2) sigma(r)`). Default 3. Sensible: 2..5.
    pub bridge_sigmas: f64,
    /// Most missing (invalid or removed) beams between consecutive points of a data segment,
    /// and so of a line, on a scan whose beams mostly return. On a sparse one (a fraction `p`
    /// of the returns followed by a missing beam) the bridge spans as many as dropouts alone
    /// leave after a point with 1 % chance, if that is more ([`HoughSplitParams::bridge_for`]).
    /// Default 2. Sensible: 0..5.
    pub bridge_max_gap: usize,
    /// With `bridge_beams`, also join the points of a surface that returns few of its beams
    /// (glass, a dark or shiny panel) on a scan that returns most of them, across gaps beyond
    /// `bridge_max_gap` where every beam between and 30 % of those around returned nothing
    /// (the local bridge, `hough_split::LOCAL_DROPOUT`). Not in the paper. Default `true`;
    /// off in [`HoughSplitParams::mapping`].
    pub local_bridge: bool,
    /// Data segments with fewer surviving points are removed as clutter (on a sparse scan,
    /// fewer: [`HoughSplitParams::min_points_for`]). Default 8. Sensible: 3..10.
    pub min_segment_points: usize,
    /// Linseg's criterion: a piece is split at its farthest point from the chord when that
    /// point lies farther than `split_sigmas * sigma(r)` (times the cosine of the beam's
    /// incidence on the chord with `noise_along_beams`). Default 3. Sensible: 2..6.
    pub split_sigmas: f64,
    /// ...and when two lines explain the piece significantly better than one: the drop of the
    /// sum of squared residuals must exceed `split_significance` times the noise variance
    /// (the larger of the noise across the line, `sigma(r)^2` or with `noise_along_beams`
    /// `sigma(r)^2 cos^2(incidence)` at the centroid, and the residual variance of the two
    /// lines). 0 gives the paper's pure distance criterion (with `noise_along_beams =
    /// false`). Default 20 (a chi-square of 2 degrees of freedom beyond the 1e-4 level,
    /// allowing for the split point being the worst of many). Sensible: 10..40.
    pub split_significance: f64,
    /// ...and when the two lines bend away from the one line of the piece by more than this,
    /// m: they lie farther apart at the split point, or the points where they pass the
    /// piece's ends and the split point lie farther from the one line (or do in the mean
    /// square over the points); or else meet at more than 5 deg, or the one line would
    /// fail the RMS gate (`max_rms_sigmas`). Real walls are not flat to a millimetre, and
    /// real scanners' range errors include a part that changes slowly along a surface (a
    /// URG-04LX's accuracy is +-10 mm below 1 m against its 3-5 mm of noise, a SICK
    /// LMS200's systematic error +-15 mm against 5 mm), which the noise estimate, read
    /// between neighbouring beams, does not see: with hundreds of points the significance
    /// test alone split a wall at every such bow. Applies with `split_significance > 0` (the merge reads the same test). Not in
    /// the paper. Default 0.015. Sensible: 0..0.03.
    pub min_bend: f64,
    /// At a step (a door set back a hand's width from its wall) the split point lies on one
    /// side only, and the line of the other side, bent through it, hid the step from the
    /// significance test: a door 12 cm back came out as one line tilted across door and
    /// wall. With `split_steps` the test also takes the split point on each side alone,
    /// where it lies off the other side's line by more than `split_significance` noise
    /// variances and the points beside it split significantly without it (so that a lone
    /// outlier at the split point, which a short line bends to reach, splits nothing).
    /// Applies with `split_significance > 0`. Not in the paper; off in
    /// [`HoughSplitParams::mapping`] and [`HoughSplitParams::navigation`]. Default `true`.
    pub split_steps: bool,
    /// Range noise lies along the beams: the split (its distance criterion and significance
    /// test), the merge, where lines end (the cut between two pieces and the trimming of
    /// their ends) and the shared fits take the noise across a line as
    /// `sigma(r) cos(incidence)` at the points tested (incidence taken at most 84 deg), so
    /// that a surface seen at a glancing angle must lie on its line as closely as its noise
    /// allows, and two objects far apart do not share a line that meets both at a grazing
    /// angle. `false` takes `sigma(r)` across every line. Not in the paper. Default `true`.
    pub noise_along_beams: bool,
    /// After splitting, merge neighbouring pieces of one segment whose joint line explains
    /// them as well as two lines do (the same test as the split). Not in the paper.
    /// Default `true`.
    pub merge_collinear: bool,
    /// A piece that fails the RMS gate of a line and whose split is not significant has an
    /// excursion cut out around its farthest point: the run of fewer than
    /// `min_line_points` consecutive points (fewer on a sparse scan:
    /// [`HoughSplitParams::min_points_for`]) there that all lie more than 5 sigma from the
    /// chord (a thin leg just before a wall, which the breakpoint distance joined to it), so
    /// that the wall comes out on both sides of it instead of not at all. Needs
    /// `split_significance > 0`. Also ends a line where a run of returns beyond it sees
    /// through it (an opening: a doorway seen at a glancing angle), in step 6 and where two
    /// lines would meet at a corner. Not in the paper; off in
    /// [`HoughSplitParams::mapping`]. Default `true`.
    pub cut_excursions: bool,
    /// Where a piece whose ends `refine_ends` moved gives no line, take it within the
    /// split's own bounds: a cut moved onto the few points of a step beside a wall made the
    /// wall's line fail the RMS gate, and the wall had none. Not in the paper; off in
    /// [`HoughSplitParams::mapping`] and [`HoughSplitParams::navigation`]. Default `true`.
    pub keep_split_bounds: bool,
    /// Lines of one surface on both sides of a gap (a leg or a box in front of a wall, a door,
    /// missing beams) share one fit: when one line explains the points of two lines (their
    /// joint line's sum of squared residuals exceeds theirs by less than the chi-square
    /// quantile of 2 degrees of freedom at the 1e-3 level, 13.8 variances of the noise across
    /// that line), each keeps its own points and extent but takes the joint `r`, `alpha` and
    /// covariance, and the gates `max_alpha_sd` and `max_r_sd` judge that covariance. Not in
    /// the paper. Default `true`.
    pub share_fits: bool,
    /// Refine where pieces end: the shared split point and its neighbours (over the angle of
    /// four URG-04LX beams) go to the line that explains them best, a short corner leg or
    /// mixed pixel at a line's end is trimmed by a chi-square test, and neighbouring lines
    /// that meet at a corner share their end point at the intersection. Not in the paper.
    /// Default `true`.
    pub refine_ends: bool,
    /// Lines with fewer supporting points are dropped (on a sparse scan, fewer:
    /// [`HoughSplitParams::min_points_for`]). Default 8. At least 2 is enforced.
    pub min_line_points: usize,
    /// Lines shorter than this are dropped, m: the smallest surface that is a wall, not a
    /// leg or a post. Default 0.15 (legs and posts up to 12 cm across give no line, wall
    /// pieces of 0.2 m and more are kept). Sensible: 0..0.5.
    pub min_line_length: f64,
    /// Lines whose RMS residual exceeds this many `sigma(r)` (at their centroid) are dropped:
    /// a line through scattered clutter is no surface. Default 2.5. `inf` turns it off.
    #[cfg_attr(feature = "serde", serde(deserialize_with = "off_or_f64"))]
    pub max_rms_sigmas: f64,
    /// A line seen at more than 60 deg of incidence (at its centroid) is kept only when its
    /// points advance along it with their beams: the slope of their positions along the
    /// line against their beam numbers lies at least this many standard errors from zero.
    /// Range noise lies along the beams, so where it exceeds the beam spacing (a UTM-30LX's
    /// 30 mm at 0.25 deg within 7 m), a leg, a post or a depth edge between two surfaces
    /// gives a streak of points along the beams that fits a line at a glancing angle within
    /// every RMS and covariance limit; its points scatter along it in no order, where those
    /// of a real glancing surface move `r dphi / cos(incidence)` a beam. Not in the paper.
    /// Default 8 (chosen on the training scenes, from 0, 5, 8 and 12: the false-positive
    /// rate fell from 0.039 to 0.031 at 1.5 times the URG-04LX's band and from 0.054 to 0.033
    /// on a UTM-30LX, the true-positive rate by at most 0.004). 0 turns it off.
    pub min_advance_t: f64,
    /// Two neighbouring lines of a data segment are dropped as chords of a round obstacle (a
    /// barrel, a pillar) when a circle of at most 1 m radius, bulging towards the sensor,
    /// explains their points better than the two lines, charged 4 noise variances for their
    /// two extra parameters (Akaike's 2 each), by more than this many times the noise
    /// variance at their centroid: the circle may leave up to `4 - arc_significance`
    /// variances more than the lines (the default 2: 2 more). A line is tried with the
    /// piece beside it also when that piece gave no line (8 points or more: a barrel's next
    /// chord too short or too uncertain for one), the pair then judged against the pieces'
    /// own scatter as well. Not in the paper. 0 turns it off; small values above 0 drop the
    /// most.
    pub arc_significance: f64,
    /// Lines whose direction is known worse than this (one standard deviation of `alpha`
    /// from their covariance), rad, are dropped: a short far piece under heavy noise gives a
    /// line whose direction says little. Default 3 deg ([`complete`](Self::complete): 5 deg).
    /// `inf` turns it off.
    #[cfg_attr(feature = "serde", serde(deserialize_with = "off_or_f64"))]
    pub max_alpha_sd: f64,
    /// Lines whose distance from the sensor is known worse than this (one standard deviation
    /// of `r` from their covariance), m, are dropped. A short piece seen far off or at a
    /// glancing angle gives a line whose `r` (its direction's error times the lever arm from
    /// its points to the foot of the normal) says little, though the segment lies where its
    /// points are. Default 0.06: on the training scenes it keeps the TP rate at or above
    /// 0.95 at the URG-04LX's full data-sheet noise with the FP rate below 0.05 at every level
    /// (0.05 fell 0.001 short of that TP) ([`complete`](Self::complete): `inf`, off).
    #[cfg_attr(feature = "serde", serde(deserialize_with = "off_or_f64"))]
    pub max_r_sd: f64,
    /// A line's covariance takes the larger of its residual variance and the noise model's
    /// variance across it, unless its own points refuse the model: with `own_scatter`, when
    /// their sum of squared residuals in variances of the model lies below the chi-square
    /// quantile of `n - 2` degrees of freedom at the 1e-3 level (at least 10 points), the
    /// variance is the residual sum over that quantile instead (the model, read off other
    /// surfaces or extrapolated past them, does not hold for this line). Not in the paper;
    /// off in [`HoughSplitParams::mapping`], whose matcher weighs lines by these variances.
    /// Default `true`.
    pub own_scatter: bool,
    /// Leave out points that lie on neither neighbouring surface (mixed pixels at depth
    /// edges, spikes): more than three standard deviations from the extrapolations of both
    /// neighbouring pairs of beams. Not in the paper. Default `true`.
    pub remove_mixed_pixels: bool,
    /// Points nearer than this never form lines, m: the robot's own body (a footprint radius
    /// around the laser). Default 0 (the scan's `range_min` only).
    pub min_range: f64,
    /// Extra limits on valid ranges, on top of the scan's own `range_min..range_max`.
    /// Default none; [`HoughSplitParams::paper`] uses the paper's 0.03..3.00 m.
    pub range_limits: Option<RangeWindow>,
}

impl Default for HoughSplitParams {
    fn default() -> Self {
        Self {
            ring_step: 0.03,
            sector_step: 2.47_f64.to_radians(),
            window: 0.015,
            weight: Weight::Range,
            criterion: 0.5,
            group_gap: 1,
            noise: NoiseModel::Auto,
            noise_floor: 0.002,
            bridge_beams: true,
            bridge_incidence: 4.0_f64.to_radians(),
            bridge_sigmas: 3.0,
            bridge_max_gap: 2,
            local_bridge: true,
            min_segment_points: 8,
            split_sigmas: 3.0,
            split_significance: 20.0,
            min_bend: 0.015,
            split_steps: true,
            noise_along_beams: true,
            merge_collinear: true,
            cut_excursions: true,
            keep_split_bounds: true,
            share_fits: true,
            refine_ends: true,
            min_line_points: 8,
            min_line_length: 0.15,
            max_rms_sigmas: 2.5,
            min_advance_t: 8.0,
            arc_significance: 2.0,
            max_alpha_sd: 3f64.to_radians(),
            max_r_sd: 0.06,
            own_scatter: true,
            remove_mixed_pixels: true,
            min_range: 0.0,
            range_limits: None,
        }
    }
}

impl HoughSplitParams {
    /// Checks every field.
    ///
    /// # Errors
    /// A [`ParamsError`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ParamsError> {
        for (field, value) in [
            ("ring_step", self.ring_step),
            ("sector_step", self.sector_step),
            ("window", self.window),
            ("split_sigmas", self.split_sigmas),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(ParamsError::NotPositive { field, value });
            }
        }
        for (field, value) in [
            ("criterion", self.criterion),
            ("noise_floor", self.noise_floor),
            ("bridge_incidence", self.bridge_incidence),
            ("bridge_sigmas", self.bridge_sigmas),
            ("split_significance", self.split_significance),
            ("min_bend", self.min_bend),
            ("min_line_length", self.min_line_length),
            ("min_advance_t", self.min_advance_t),
            ("arc_significance", self.arc_significance),
            ("min_range", self.min_range),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(ParamsError::Negative { field, value });
            }
        }
        for (field, value) in [
            ("max_rms_sigmas", self.max_rms_sigmas),
            ("max_alpha_sd", self.max_alpha_sd),
            ("max_r_sd", self.max_r_sd),
        ] {
            if value.is_nan() || value <= 0.0 {
                return Err(ParamsError::NotPositive { field, value });
            }
        }
        self.validate_grid()?;
        crate::params::range_limits(self.range_limits)?;
        if let NoiseModel::Fixed(n) = self.noise
            && !n.is_valid()
        {
            let ok = |v: f64| v.is_finite() && v >= 0.0;
            return Err(if !ok(n.sigma_min) {
                ParamsError::Negative {
                    field: "noise.sigma_min",
                    value: n.sigma_min,
                }
            } else if !ok(n.fraction) {
                ParamsError::Negative {
                    field: "noise.fraction",
                    value: n.fraction,
                }
            } else {
                // Both zero: no noise at all.
                ParamsError::NotPositive {
                    field: "noise.sigma_min",
                    value: n.sigma_min,
                }
            });
        }
        Ok(())
    }

    /// The grid and angle checks of [`HoughSplitParams::validate`]: bounds that keep the
    /// accumulator's size and the bridge's geometry within reason.
    fn validate_grid(&self) -> Result<(), ParamsError> {
        use std::f64::consts::{FRAC_PI_2, TAU};
        if self.bridge_incidence > FRAC_PI_2 {
            return Err(ParamsError::AboveField {
                field: "bridge_incidence",
                value: self.bridge_incidence,
                limit_field: "90 deg",
                limit: FRAC_PI_2,
            });
        }
        if self.sector_step >= TAU {
            return Err(ParamsError::OutOfRange {
                field: "sector_step",
                value: self.sector_step,
                lo: 0.0,
                hi: TAU,
            });
        }
        // Rings of 0.1 mm and finer would number beyond the accumulator's ring indices, and
        // a window of many rings has every point vote in all of them.
        if self.ring_step < MIN_RING_STEP {
            return Err(ParamsError::Below {
                field: "ring_step",
                value: self.ring_step,
                min: MIN_RING_STEP,
            });
        }
        if self.ring_step > MAX_RING_STEP {
            return Err(ParamsError::AboveField {
                field: "ring_step",
                value: self.ring_step,
                limit_field: "100 m",
                limit: MAX_RING_STEP,
            });
        }
        if self.window > MAX_WINDOW_RINGS * self.ring_step {
            return Err(ParamsError::AboveField {
                field: "window",
                value: self.window,
                limit_field: "64 ring_step",
                limit: MAX_WINDOW_RINGS * self.ring_step,
            });
        }
        Ok(())
    }

    /// The noise-cancelling criterion for beams `increment` rad apart: `criterion` scaled by
    /// the beams a sector holds over the paper's (its 2.47 deg sectors hold 7.03 beams of the
    /// URG-04LX), when fewer. The criterion removes a cell holding too few of the points a
    /// surface would put there: with `g = r`, a lone point nearer than 0.5 m is one of seven
    /// on a URG-04LX, but one of 2.5 on a 1 deg scanner, where every cell of a wall 0.2 m away
    /// would weigh less than 0.5 and the wall would vanish. Unchanged on the URG-04LX and on
    /// finer scanners.
    #[must_use]
    pub fn criterion_for(&self, increment: f64) -> f64 {
        let beams = self.sector_step / increment.abs();
        // A URG-04LX's sectors, up to the rounding of the angles, are the paper's.
        if beams < PAPER_SECTOR_BEAMS * (1.0 - 1e-9) {
            self.criterion * beams / PAPER_SECTOR_BEAMS
        } else {
            self.criterion
        }
    }

    /// The fewest points of a data segment and of a line on a scan of whose returns the
    /// fraction `dropout` is followed by a missing beam ([`super::Stages::dropout`]).
    /// `min_segment_points` and `min_line_points` count the points of a surface seen by
    /// every beam; on a sparse scan (`dropout` from 0.2 on, as for the noise estimate) the
    /// same surface returns `1 - dropout` of them, and each count is scaled by that (rounded
    /// up), but not below [`MIN_SPARSE_POINTS`]: a YDLIDAR X4 that misses half of its beams
    /// sees a wall piece of 8 beams with 4 points, and lost most pieces of under 15 beams.
    /// Dense scans keep both counts as they are.
    #[must_use]
    pub fn min_points_for(&self, dropout: f64) -> MinPoints {
        let kept = if dropout >= SPARSE_DROPOUT {
            1.0 - dropout.min(MAX_DROPOUT)
        } else {
            1.0
        };
        let scaled = |n: usize| {
            let want = (n as f64 * kept).ceil() as usize;
            n.min(want.max(MIN_SPARSE_POINTS))
        };
        MinPoints {
            segment: scaled(self.min_segment_points),
            line: scaled(self.min_line_points),
        }
    }

    /// The beam bridge of a scan with beams `increment` rad apart, of whose returns the
    /// fraction `dropout` is followed by a missing beam ([`super::Stages::dropout`]): dropouts
    /// alone leave a gap of `g` missing beams or more after a point with chance `dropout^g`,
    /// so the bridge spans the larger of `bridge_max_gap` and the gap they leave with
    /// [`GAP_CHANCE`] (at most [`MAX_BRIDGE_GAP`]), and `D` is computed for the mean angle
    /// between returns, `increment / (1 - dropout)`: a YDLIDAR X4 whose beams return one in
    /// seven is read as the scanner of 6 deg it is. With a few dropouts (under 10 % on a
    /// URG-04LX) this is the bridge of a scan without.
    #[must_use]
    pub fn bridge_for(&self, increment: f64, dropout: f64) -> Bridge {
        let (p, by_chance) = gap_by_chance(dropout);
        Bridge {
            max_gap: self.bridge_max_gap.max(by_chance).min(MAX_BRIDGE_GAP),
            spacing: increment.abs() / (1.0 - p),
        }
    }

    /// The fewest missing beams before a line's last points (at most three) that make
    /// `hough-split` cut those points from the line, on a scan of whose returns the fraction
    /// `dropout` is followed by a missing beam: one more than the longest gap that dropouts
    /// leave with a chance above [`GAP_CHANCE`], and at least 2 (2 up to 10 % of dropouts, 3
    /// just above, 7 at 50 %). One missing beam says too little: a wall 5.5 m from a
    /// URG-04LX, near its 5.6 m limit, lost 11 cm of its end to a single one. The bridge may
    /// span more (`bridge_max_gap`), but a line's end beyond such a gap needs more points
    /// than that (with `refine_ends`; not in [`HoughSplitParams::paper`]).
    #[must_use]
    pub fn lone_gap_for(&self, dropout: f64) -> usize {
        (gap_by_chance(dropout).1 + 1).max(2)
    }

    /// The breakpoint distance `D`, m: the farthest apart two consecutive points of one
    /// surface can lie when the first is at range `r` and the beams are `dphi` rad apart,
    /// `D = r sin(dphi) / sin(lambda - dphi) + bridge_sigmas * sqrt(2) * sigma` (Borges &
    /// Aldon's adaptive breakpoint with `lambda = max(bridge_incidence, min(10 * step, 60
    /// deg))` for returns `step` rad apart ([`Bridge::spacing`]), and the noise `sigma` at
    /// `r`). `None` when `dphi` exceeds `lambda / 3`: points that far apart in angle are never
    /// joined, so that `D` stays below `r / 2` plus the noise allowance on dense scans (at
    /// most `0.53 r` on the sparsest) and no gap is taken for a surface.
    #[must_use]
    pub fn breakpoint_distance(&self, r: f64, dphi: f64, step: f64, sigma: f64) -> Option<f64> {
        let lambda = self
            .bridge_incidence
            .max((10.0 * step.abs()).min(MAX_LAMBDA));
        let denom = (lambda - dphi).sin();
        let reach = lambda / 3.0 + 1e-12;
        (dphi.is_finite() && dphi >= 0.0 && dphi <= reach && denom > 0.0)
            .then(|| r * dphi.sin() / denom + self.bridge_sigmas * std::f64::consts::SQRT_2 * sigma)
    }

    /// The geometric part of `D` per metre of range for points 1 to `bridge.max_gap + 1`
    /// beams apart (beams `increment` rad apart) into `out`, in that order: NaN where `D`
    /// joins none.
    pub(crate) fn breakpoint_factors(&self, increment: f64, bridge: Bridge, out: &mut Vec<f64>) {
        let step = increment.abs();
        out.clear();
        out.extend((1..=bridge.max_gap + 1).map(|g| {
            self.breakpoint_distance(1.0, step * g as f64, bridge.spacing, 0.0)
                .unwrap_or(f64::NAN)
        }));
    }
}

#[cfg(test)]
#[path = "params_tests.rs"]
mod tests;
