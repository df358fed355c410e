//! Parameters of [`super::HoughSplit`].

use crate::scan::RangeWindow;

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

/// Errors in [`HoughSplitParams`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParamsError {
    /// A field that must be finite and positive is not.
    #[error("{field} must be finite and > 0, got {value}")]
    NotPositive {
        /// field name
        field: &'static str,
        /// offending value
        value: f64,
    },
    /// A field that must be finite and non-negative is not.
    #[error("{field} must be finite and >= 0, got {value}")]
    Negative {
        /// field name
        field: &'static str,
        /// offending value
        value: f64,
    },
}

/// Parameters of the paper's extractor, with the paper's grid as defaults (in SI units).
///
/// Thresholds that should grow with range do: the split threshold is
/// `split_distance + split_distance_per_metre * range`, and the beam bridge uses the adaptive
/// breakpoint distance of Borges and Aldon, which grows linearly with range. The Hough grid is
/// fixed in metres and radians, as in the paper; with [`Weight::Range`] the cell values
/// compensate for the density falling with range.
///
/// Defaults marked *tuned* were chosen by `laserlines bench --tune hough-split --suite all
/// --seed 1 --scans 100`: a coordinate search maximising the F1 score of found walls and false
/// lines on the training suite (seed 1, 100 simulated URG-04LX scans of each of the seven
/// scene suites; see `laserlines_eval::tune`). Results are reported on the test suite, seed 2.
/// The search kept the paper's grid and criterion.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct HoughSplitParams {
    /// Ring step `dd` of the accumulator, m. Paper: 0.03 m. Sensible: 0.01..0.10.
    pub ring_step: f64,
    /// Sector step `dgamma` of the accumulator, rad. Paper: 2.47 deg (about 7 beams of a
    /// URG-04LX). Sensible: 1..10 beam increments.
    pub sector_step: f64,
    /// Half-width `a` of the rectangular window `w`, m. Default `ring_step / 2` (each point
    /// votes in one ring, two when it falls on a boundary). Sensible: 0.5..1.5 ring steps.
    pub window: f64,
    /// Weight `g`. Default [`Weight::Range`].
    pub weight: Weight,
    /// Noise-cancelling criterion: cells whose weighted value is not above it are set to zero.
    /// With `g = 1` it counts points (the paper's Fig. 3 uses 1: cells of 2..7 points remain);
    /// with `g = r` it is in metres (sum of ranges). Default 0.5 (with `g = r`: a lone point
    /// nearer than 0.5 m is noise). Sensible: 0..3.
    pub criterion: f64,
    /// Cells bridged in the sector direction when grouping along a ring (the paper's
    /// adjustable radius-grouping threshold). Default 1. Sensible: 0..3.
    pub group_gap: usize,
    /// Also join consecutive valid beams whose points are closer than the adaptive breakpoint
    /// distance (Borges & Aldon 2004), so that walls seen at a grazing angle, whose points skip
    /// rings, stay one data segment. Not in the paper (set `false` for the paper's pure grid
    /// connectivity). Default `true`.
    pub bridge_beams: bool,
    /// Smallest incidence angle between beam and surface that the beam bridge still joins,
    /// rad (the `lambda` of Borges & Aldon). Default 10 deg. Sensible: 5..20 deg.
    pub bridge_incidence: f64,
    /// Range noise allowance of the beam bridge, m, added three times to the breakpoint
    /// distance. Default 0.01. Sensible: 0..0.05.
    pub bridge_noise: f64,
    /// Most missing (invalid or removed) beams the beam bridge may span. Default 2.
    /// Sensible: 0..5.
    pub bridge_max_gap: usize,
    /// Data segments with fewer surviving points are removed as clutter. Default 8 (tuned).
    /// Sensible: 3..10.
    pub min_segment_points: usize,
    /// Split threshold at zero range, m: Linseg splits where the farthest point from the chord
    /// lies farther than `split_distance + split_distance_per_metre * range`. Default 0.01
    /// (tuned). Sensible: 0.005..0.05.
    pub split_distance: f64,
    /// Growth of the split threshold with the range of the farthest point, m per m.
    /// Default 0.02 (about four standard deviations of the URG-04LX's range noise, whose
    /// accuracy is 1 % of the range beyond 1 m). Sensible: 0..0.04.
    pub split_distance_per_metre: f64,
    /// After splitting, merge neighbouring lines of one segment when all their points lie
    /// within the split threshold of their joint least-squares line. Not in the paper
    /// (`false` gives the paper's pure split). Default `true`.
    pub merge_collinear: bool,
    /// Lines with fewer supporting points are dropped. Default 8 (tuned). At least 2 is
    /// enforced.
    pub min_line_points: usize,
    /// Lines shorter than this are dropped, m. Default 0.05. Not tuned: the search would
    /// raise it to 0.15, dropping short lines on legs and debris, but sparse real scans then
    /// keep no line at all. Sensible: 0..0.5.
    pub min_line_length: f64,
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
            bridge_beams: true,
            bridge_incidence: 4.0_f64.to_radians(),
            bridge_noise: 0.01,
            bridge_max_gap: 2,
            min_segment_points: 8,
            split_distance: 0.01,
            split_distance_per_metre: 0.02,
            merge_collinear: true,
            min_line_points: 8,
            min_line_length: 0.05,
            range_limits: None,
        }
    }
}

impl HoughSplitParams {
    /// The defaults plus the paper's range limits (ranges outside 0.03..3.00 m are noise).
    #[must_use]
    pub fn paper() -> Self {
        Self {
            range_limits: Some(RangeWindow::PAPER),
            ..Self::default()
        }
    }

    /// Checks every field.
    ///
    /// # Errors
    /// A [`ParamsError`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ParamsError> {
        for (field, value) in [
            ("ring_step", self.ring_step),
            ("sector_step", self.sector_step),
            ("window", self.window),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(ParamsError::NotPositive { field, value });
            }
        }
        for (field, value) in [
            ("criterion", self.criterion),
            ("bridge_incidence", self.bridge_incidence),
            ("bridge_noise", self.bridge_noise),
            ("split_distance", self.split_distance),
            ("split_distance_per_metre", self.split_distance_per_metre),
            ("min_line_length", self.min_line_length),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(ParamsError::Negative { field, value });
            }
        }
        Ok(())
    }

    /// The split threshold for a point at `range` metres.
    #[must_use]
    pub fn split_threshold(&self, range: f64) -> f64 {
        self.split_distance + self.split_distance_per_metre * range
    }
}
