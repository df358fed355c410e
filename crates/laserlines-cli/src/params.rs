//! Extractor parameters from a TOML file: one table per algorithm (named as in
//! `laserlines::extractors::ALGORITHMS`), keys as the library's params struct fields, SI
//! units (metres, radians). Unknown tables and keys are errors; a missing key keeps the
//! library's default. `range_limits = [lo, hi]` sets the optional extra range window.
//!
//! ```toml
//! [hough-split]
//! ring_step = 0.03          # m
//! sector_step = 0.0431      # rad
//! weight = "range"          # or "one"
//! criterion = 0.5
//! range_limits = [0.03, 3.0]
//!
//! [iterative-hough]
//! min_votes = 10.0
//! weight = "one"
//!
//! [ransac]
//! seed = 7
//! inlier_distance = 0.02    # m
//! ```
//!
//! `laserlines simulate` also reads `[robot]` (the simulated robot: footprint, drive limits,
//! odometry noise, the laser's mount, rates) and `[explorer]` (the wall follower and its
//! travel to frontiers); other commands leave those two tables alone.
//!
//! ```toml
//! [robot]
//! footprint_length = 0.6    # m
//! footprint_width = 0.45    # m
//! max_speed = 0.4           # m/s
//! laser_x = 0.2             # m ahead of the axle
//!
//! [explorer]
//! side = "right"            # the wall followed: "left" or "right"
//! follow_distance = 0.5     # m
//! ```

use std::path::Path;

use anyhow::{Context, Result, bail};
use laserlines::extractors::{
    self, Em, EmParams, Iepf, IepfParams, Incremental, IncrementalParams, IterativeHough,
    IterativeHoughParams, LineRegression, LineRegressionParams, Ransac, RansacParams,
    SplitAndMerge, SplitAndMergeParams,
};
use laserlines::{HoughSplit, HoughSplitParams, LineExtractor, RangeWindow, Weight};
use laserlines_nav::{ExplorerParams, WallSide};
use laserlines_sim::robot::RobotParams;
use serde::Deserialize;

/// The whole file.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParamsFile {
    #[serde(rename = "hough-split")]
    hough_split: Option<HoughSplitToml>,
    #[serde(rename = "iterative-hough")]
    iterative_hough: Option<IterativeHoughToml>,
    #[serde(rename = "split-and-merge")]
    split_and_merge: Option<SplitAndMergeToml>,
    iepf: Option<IepfToml>,
    incremental: Option<IncrementalToml>,
    #[serde(rename = "line-regression")]
    line_regression: Option<LineRegressionToml>,
    ransac: Option<RansacToml>,
    em: Option<EmToml>,
    robot: Option<RobotToml>,
    explorer: Option<ExplorerToml>,
}

/// `[robot]`: overrides of the simulated robot ([`RobotParams`]).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct RobotToml {
    footprint_length: Option<f64>,
    footprint_width: Option<f64>,
    max_speed: Option<f64>,
    max_reverse: Option<f64>,
    max_turn_rate: Option<f64>,
    max_accel: Option<f64>,
    max_angular_accel: Option<f64>,
    wheel_base: Option<f64>,
    wheel_sigma: Option<f64>,
    laser_x: Option<f64>,
    laser_y: Option<f64>,
    laser_yaw: Option<f64>,
    scan_period_s: Option<f64>,
    physics_dt_s: Option<f64>,
}

/// The followed side by name.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "lowercase")]
enum SideName {
    Left,
    Right,
}

/// `[explorer]`: overrides of the explorer ([`ExplorerParams`]); all lengths, speeds and
/// times must be positive and finite.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct ExplorerToml {
    side: Option<SideName>,
    follow_distance: Option<f64>,
    follow_range: Option<f64>,
    cruise_speed: Option<f64>,
    corner_speed: Option<f64>,
    turn_rate: Option<f64>,
    safety_margin: Option<f64>,
    travel_speed: Option<f64>,
    lookahead_m: Option<f64>,
    give_up_s: Option<f64>,
    idle_timeout_s: Option<f64>,
}

/// The weight function by name, for the classic extractors' tables.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(rename_all = "lowercase")]
enum WeightName {
    One,
    Range,
}

impl From<WeightName> for Weight {
    fn from(w: WeightName) -> Self {
        match w {
            WeightName::One => Self::One,
            WeightName::Range => Self::Range,
        }
    }
}

/// A table of optional overrides for the params struct `$params`: one key per field (plus
/// `range_limits = [lo, hi]`), applied over the defaults.
macro_rules! table {
    ($toml:ident => $params:ty { $($f:ident: $t:ty),* $(,)? }) => {
        #[derive(Debug, Default, Deserialize)]
        #[serde(deny_unknown_fields)]
        struct $toml {
            $($f: Option<$t>,)*
            range_limits: Option<[f64; 2]>,
        }

        impl $toml {
            fn apply(&self, p: &mut $params) {
                $( if let Some(v) = self.$f { p.$f = v.into(); } )*
                if let Some([lo, hi]) = self.range_limits {
                    p.range_limits = Some(RangeWindow::new(lo, hi));
                }
            }
        }
    };
}

table!(IterativeHoughToml => IterativeHoughParams {
    distance_step: f64,
    max_distance: f64,
    angle_step: f64,
    window: f64,
    weight: WeightName,
    min_votes: f64,
    inlier_distance: f64,
    inlier_distance_per_metre: f64,
    refine_iterations: usize,
    max_skipped: usize,
    breakpoint_incidence: f64,
    breakpoint_noise: f64,
    breakpoint_max_gap: usize,
    max_iterations: usize,
    min_line_points: usize,
    min_line_length: f64,
});

table!(SplitAndMergeToml => SplitAndMergeParams {
    breakpoint_incidence: f64,
    breakpoint_noise: f64,
    breakpoint_max_gap: usize,
    min_cluster_points: usize,
    split_distance: f64,
    split_distance_per_metre: f64,
    merge_collinear: bool,
    min_line_points: usize,
    min_line_length: f64,
});

table!(IepfToml => IepfParams {
    breakpoint_incidence: f64,
    breakpoint_noise: f64,
    breakpoint_max_gap: usize,
    min_cluster_points: usize,
    split_distance: f64,
    split_distance_per_metre: f64,
    merge_collinear: bool,
    min_line_points: usize,
    min_line_length: f64,
});

table!(IncrementalToml => IncrementalParams {
    breakpoint_incidence: f64,
    breakpoint_noise: f64,
    breakpoint_max_gap: usize,
    seed_points: usize,
    track_distance: f64,
    track_distance_per_metre: f64,
    max_outliers: usize,
    min_line_points: usize,
    min_line_length: f64,
});

table!(LineRegressionToml => LineRegressionParams {
    breakpoint_incidence: f64,
    breakpoint_noise: f64,
    breakpoint_max_gap: usize,
    window: usize,
    noise_sigma: f64,
    noise_sigma_per_metre: f64,
    similarity: f64,
    min_windows: usize,
    merge_collinear: bool,
    merge_distance: f64,
    merge_distance_per_metre: f64,
    min_line_points: usize,
    min_line_length: f64,
});

table!(RansacToml => RansacParams {
    seed: u64,
    iterations: usize,
    sample_span: usize,
    inlier_distance: f64,
    inlier_distance_per_metre: f64,
    min_inliers: usize,
    max_skipped: usize,
    refine_iterations: usize,
    breakpoint_incidence: f64,
    breakpoint_noise: f64,
    breakpoint_max_gap: usize,
    max_lines: usize,
    min_line_points: usize,
    min_line_length: f64,
});

table!(EmToml => EmParams {
    seed: u64,
    max_trials: usize,
    max_failures: usize,
    init_points: usize,
    iterations: usize,
    anneal_sigma_scale: f64,
    noise_sigma: f64,
    noise_sigma_per_metre: f64,
    outlier_density: f64,
    inlier_probability: f64,
    max_skipped: usize,
    breakpoint_incidence: f64,
    breakpoint_noise: f64,
    breakpoint_max_gap: usize,
    min_line_points: usize,
    min_line_length: f64,
});

/// Defaults overridden by `table` when present; validated by `new` (the extractor's
/// constructor), whose error is reported under the table's name.
fn build<P: Default, T, E, X>(
    name: &str,
    table: Option<&T>,
    apply: fn(&T, &mut P),
    new: fn(P) -> Result<X, E>,
) -> Result<Box<dyn LineExtractor + Send>>
where
    E: std::error::Error + Send + Sync + 'static,
    X: LineExtractor + Send + 'static,
{
    let mut p = P::default();
    if let Some(t) = table {
        apply(t, &mut p);
    }
    Ok(Box::new(
        new(p).with_context(|| format!("[{name}] parameters"))?,
    ))
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
    /// The simulated robot: NAJI V's defaults overridden by `[robot]`, validated.
    pub fn robot(&self) -> Result<RobotParams> {
        let mut p = RobotParams::default();
        let Some(t) = &self.robot else {
            return Ok(p);
        };
        macro_rules! set {
            ($($key:ident => $field:expr),* $(,)?) => { $( if let Some(v) = t.$key { $field = v; } )* };
        }
        set!(
            footprint_length => p.robot.footprint.length,
            footprint_width => p.robot.footprint.width,
            max_speed => p.robot.limits.max_speed,
            max_reverse => p.robot.limits.max_reverse,
            max_turn_rate => p.robot.limits.max_turn_rate,
            max_accel => p.robot.limits.max_accel,
            max_angular_accel => p.robot.limits.max_angular_accel,
            wheel_base => p.robot.wheel_base,
            wheel_sigma => p.odometry.wheel_sigma,
            scan_period_s => p.scan_period_s,
            physics_dt_s => p.physics_dt_s,
            laser_x => p.robot.laser.x,
            laser_y => p.robot.laser.y,
            laser_yaw => p.robot.laser.yaw,
        );
        for (key, v) in [
            ("laser_x", p.robot.laser.x),
            ("laser_y", p.robot.laser.y),
            ("laser_yaw", p.robot.laser.yaw),
        ] {
            if !v.is_finite() {
                bail!("[robot] {key} = {v} is not a finite number");
            }
        }
        p.validate().context("[robot] parameters")?;
        Ok(p)
    }

    /// The explorer: defaults overridden by `[explorer]`, each value checked.
    pub fn explorer(&self) -> Result<ExplorerParams> {
        let mut p = ExplorerParams::default();
        let Some(t) = &self.explorer else {
            return Ok(p);
        };
        if let Some(side) = t.side {
            p.side = match side {
                SideName::Left => WallSide::Left,
                SideName::Right => WallSide::Right,
            };
        }
        macro_rules! set {
            ($($f:ident),* $(,)?) => { $(
                if let Some(v) = t.$f {
                    if !(v.is_finite() && v > 0.0) {
                        bail!("[explorer] {} = {v}: expected a positive, finite number", stringify!($f));
                    }
                    p.$f = v;
                }
            )* };
        }
        set!(
            follow_distance,
            follow_range,
            cruise_speed,
            corner_speed,
            turn_rate,
            safety_margin,
            travel_speed,
            lookahead_m,
            give_up_s,
            idle_timeout_s,
        );
        Ok(p)
    }

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
        match algorithm {
            "hough-split" => self.hough_split.is_some(),
            "iterative-hough" => self.iterative_hough.is_some(),
            "split-and-merge" => self.split_and_merge.is_some(),
            "iepf" => self.iepf.is_some(),
            "incremental" => self.incremental.is_some(),
            "line-regression" => self.line_regression.is_some(),
            "ransac" => self.ransac.is_some(),
            "em" => self.em.is_some(),
            _ => false,
        }
    }

    /// The extractor called `algorithm` (one of `laserlines::extractors::ALGORITHMS`), with
    /// its defaults overridden by its table when the file has one.
    pub fn extractor(&self, algorithm: &str) -> Result<Box<dyn LineExtractor + Send>> {
        let name = algorithm;
        match algorithm {
            "hough-split" => Ok(Box::new(HoughSplit::new(self.hough_split()?)?)),
            "iterative-hough" => build(
                name,
                self.iterative_hough.as_ref(),
                IterativeHoughToml::apply,
                IterativeHough::new,
            ),
            "split-and-merge" => build(
                name,
                self.split_and_merge.as_ref(),
                SplitAndMergeToml::apply,
                SplitAndMerge::new,
            ),
            "iepf" => build(name, self.iepf.as_ref(), IepfToml::apply, Iepf::new),
            "incremental" => build(
                name,
                self.incremental.as_ref(),
                IncrementalToml::apply,
                Incremental::new,
            ),
            "line-regression" => build(
                name,
                self.line_regression.as_ref(),
                LineRegressionToml::apply,
                LineRegression::new,
            ),
            "ransac" => build(name, self.ransac.as_ref(), RansacToml::apply, Ransac::new),
            "em" => build(name, self.em.as_ref(), EmToml::apply, Em::new),
            other => bail!(
                "unknown algorithm {other:?}: expected one of {}",
                extractors::ALGORITHMS.join(", ")
            ),
        }
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

    /// `key = value` lines for every field of a params struct, from its `Debug` form.
    fn every_field(debug: &str) -> String {
        let inner = &debug[debug.find('{').unwrap() + 1..debug.rfind('}').unwrap()];
        let mut out = String::new();
        for item in inner.split(", ") {
            let (k, v) = item.trim().split_once(": ").unwrap();
            let v = match v {
                "None" => continue,
                "One" => "\"one\"".to_string(),
                "Range" => "\"range\"".to_string(),
                v => v.to_string(),
            };
            out.push_str(&format!("{k} = {v}\n"));
        }
        out
    }

    #[test]
    fn every_field_of_every_params_struct_is_a_key() {
        let tables = [
            (
                "iterative-hough",
                format!("{:?}", IterativeHoughParams::default()),
            ),
            (
                "split-and-merge",
                format!("{:?}", SplitAndMergeParams::default()),
            ),
            ("iepf", format!("{:?}", IepfParams::default())),
            ("incremental", format!("{:?}", IncrementalParams::default())),
            (
                "line-regression",
                format!("{:?}", LineRegressionParams::default()),
            ),
            ("ransac", format!("{:?}", RansacParams::default())),
            ("em", format!("{:?}", EmParams::default())),
        ];
        for (name, debug) in tables {
            let text = format!(
                "[{name}]\n{}range_limits = [0.1, 2.0]\n",
                every_field(&debug)
            );
            let f: ParamsFile =
                toml::from_str(&text).unwrap_or_else(|e| panic!("{name}: {e}\n{text}"));
            assert!(f.has(name));
            let e = f.extractor(name).unwrap();
            assert_eq!(e.name(), name);
            let bad = format!("[{name}]\nno_such_key = 1\n");
            assert!(toml::from_str::<ParamsFile>(&bad).is_err(), "{name}");
        }
        assert!(toml::from_str::<ParamsFile>("[no-such-algorithm]\n").is_err());
    }

    #[test]
    fn tables_override_defaults_and_bad_values_are_errors() {
        let f: ParamsFile = toml::from_str(
            "[iterative-hough]\nweight = \"range\"\nmin_votes = 3.0\n[ransac]\nseed = 7\n",
        )
        .unwrap();
        let t = f.iterative_hough.as_ref().unwrap();
        let mut p = IterativeHoughParams::default();
        t.apply(&mut p);
        assert_eq!(p.weight, Weight::Range);
        assert_eq!(p.min_votes, 3.0);
        let mut r = RansacParams::default();
        f.ransac.as_ref().unwrap().apply(&mut r);
        assert_eq!(r.seed, 7);
        assert_eq!(r.iterations, RansacParams::default().iterations);
        // No table: defaults.
        assert!(f.extractor("em").is_ok());
        let bad: ParamsFile = toml::from_str("[em]\ninlier_probability = 2.0\n").unwrap();
        let err = format!("{:#}", bad.extractor("em").err().unwrap());
        assert!(
            err.contains("[em]") && err.contains("inlier_probability"),
            "{err}"
        );
        assert!(f.extractor("nope").is_err());
    }
}
