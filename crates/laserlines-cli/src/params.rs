//! Extractor parameters from a TOML file: one table per algorithm, keys as the library's
//! params struct fields, SI units. Unknown keys are errors.
//!
//! ```toml
//! [hough-split]
//! ring_step = 0.03          # m
//! sector_step = 0.0431      # rad
//! weight = "range"          # or "one"
//! criterion = 0.5
//! range_limits = [0.03, 3.0]
//! ```

use std::path::Path;

use anyhow::{Context, Result, bail};
use laserlines::{HoughSplitParams, RangeWindow, Weight};
use serde::Deserialize;

/// The whole file.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParamsFile {
    #[serde(rename = "hough-split")]
    hough_split: Option<HoughSplitToml>,
}

#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct HoughSplitToml {
    ring_step: Option<f64>,
    sector_step: Option<f64>,
    window: Option<f64>,
    weight: Option<String>,
    criterion: Option<f64>,
    group_gap: Option<usize>,
    bridge_beams: Option<bool>,
    bridge_incidence: Option<f64>,
    bridge_noise: Option<f64>,
    bridge_max_gap: Option<usize>,
    min_segment_points: Option<usize>,
    split_distance: Option<f64>,
    split_distance_per_metre: Option<f64>,
    merge_collinear: Option<bool>,
    min_line_points: Option<usize>,
    min_line_length: Option<f64>,
    range_limits: Option<[f64; 2]>,
    paper: Option<bool>,
}

impl ParamsFile {
    /// Reads and parses a params file.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read params file {}", path.display()))?;
        toml::from_str(&text).with_context(|| format!("{}: invalid params file", path.display()))
    }

    /// The `hough-split` parameters: defaults (or the paper preset) overridden by the file.
    pub fn hough_split(&self) -> Result<HoughSplitParams> {
        let Some(t) = &self.hough_split else {
            return Ok(HoughSplitParams::default());
        };
        let mut p = if t.paper == Some(true) {
            HoughSplitParams::paper()
        } else {
            HoughSplitParams::default()
        };
        macro_rules! set {
            ($($f:ident),*) => { $( if let Some(v) = t.$f { p.$f = v; } )* };
        }
        set!(
            ring_step,
            sector_step,
            window,
            criterion,
            group_gap,
            bridge_beams,
            bridge_incidence,
            bridge_noise,
            bridge_max_gap,
            min_segment_points,
            split_distance,
            split_distance_per_metre,
            merge_collinear,
            min_line_points,
            min_line_length
        );
        if let Some(w) = &t.weight {
            p.weight = match w.as_str() {
                "one" => Weight::One,
                "range" => Weight::Range,
                other => {
                    bail!("hough-split.weight: expected \"one\" or \"range\", found {other:?}")
                }
            };
        }
        if let Some([lo, hi]) = t.range_limits {
            p.range_limits = Some(RangeWindow::new(lo, hi));
        }
        p.validate().context("hough-split")?;
        Ok(p)
    }

    /// True when the file has a table for `algorithm`.
    pub fn has(&self, algorithm: &str) -> bool {
        algorithm == "hough-split" && self.hough_split.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_overrides_defaults_and_rejects_unknown_keys() {
        let f: ParamsFile = toml::from_str(
            "[hough-split]\nring_step = 0.05\nweight = \"one\"\nrange_limits = [0.1, 2.0]\n",
        )
        .unwrap();
        let p = f.hough_split().unwrap();
        assert_eq!(p.ring_step, 0.05);
        assert_eq!(p.weight, Weight::One);
        assert_eq!(p.range_limits, Some(RangeWindow::new(0.1, 2.0)));
        assert_eq!(p.criterion, HoughSplitParams::default().criterion);
        assert!(toml::from_str::<ParamsFile>("[hough-split]\nring_stp = 1.0\n").is_err());
        let bad: ParamsFile = toml::from_str("[hough-split]\nring_step = -1.0\n").unwrap();
        assert!(bad.hough_split().is_err());
    }
}
