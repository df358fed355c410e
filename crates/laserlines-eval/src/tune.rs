//! Choosing an extractor's parameters from a training suite: a coordinate search over a few
//! documented parameters ("knobs") of each extractor.
//!
//! **Objective.** The F1 score of the true-positive rate and `1 - false-positive rate`
//! ([`crate::TruthMetrics::f1`]) over the training scans; ties (equal counts) go to the smaller
//! accuracy error `rms_dr / r_tolerance + rms_dalpha / alpha_tolerance` of the match
//! ([`crate::MatchParams`]), then to the value already held.
//!
//! **Search.** Start from the extractor's `Default` parameters. In a round, for each knob in
//! turn, try each of its candidate values with the other knobs held, and keep the best; a
//! value replaces the one held only when it raises F1 by more than [`MIN_GAIN`] (smaller
//! differences are noise on a training suite of a few thousand pieces), or leaves F1 exactly
//! equal and lowers the accuracy error by more than [`MIN_ERROR_GAIN`] of it. Stop after a round that changes nothing, or after
//! [`MAX_ROUNDS`] rounds. Every evaluation runs the extractor on all training scans; repeated
//! parameter sets are not re-evaluated.
//!
//! Only parameters that shape the result are knobs, never work budgets (iterations, trials),
//! which the objective would always push up. The knobs and their candidates are listed by
//! [`knobs`]; they span each parameter's documented sensible range, with one limit: the
//! minimum sizes of lines, segments and clusters stay below the size from which the metric
//! requires a piece to be found (10 beams, 0.2 m). A line shorter than that can only count as
//! false or not at all, so a search allowed to reach the bound would learn to drop every such
//! line, real small walls included: that would fit the metric, not the scenes.

use std::collections::HashMap;
use std::fmt::Debug;

use laserlines::extractors::{
    Em, EmParams, Iepf, IepfParams, Incremental, IncrementalParams, IterativeHough,
    IterativeHoughParams, LineRegression, LineRegressionParams, Ransac, RansacParams,
    SplitAndMerge, SplitAndMergeParams,
};
use laserlines::{HoughSplit, HoughSplitParams, LineExtractor};
use serde::Serialize;

use crate::bench::{TruthMetrics, score};
use crate::matching::MatchParams;
use crate::workload::BenchScan;

/// Most rounds of the coordinate search.
pub const MAX_ROUNDS: usize = 3;

/// Smallest rise of F1 for which a candidate value replaces the one held.
pub const MIN_GAIN: f64 = 0.001;

/// At equal F1, smallest relative fall of the accuracy error for which a candidate value
/// replaces the one held.
pub const MIN_ERROR_GAIN: f64 = 0.01;

/// Errors of [`tune`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TuneError {
    /// The algorithm has no knobs here (unknown name).
    #[error("unknown algorithm {0:?}: expected one of {list}", list = laserlines::extractors::ALGORITHMS.join(", "))]
    UnknownAlgorithm(String),
    /// No scan has ground truth to tune on.
    #[error("tuning needs scans with ground truth (a simulated suite)")]
    NoTruth,
    /// The starting parameters do not build an extractor.
    #[error("the default parameters of {0} are invalid")]
    BadDefaults(String),
}

/// One tunable parameter of a params struct `P`.
pub struct Knob<P> {
    /// The field's name (as in the params struct and the params file).
    pub name: &'static str,
    /// Candidate values (counts as whole numbers, angles in rad, distances in m).
    pub values: Vec<f64>,
    /// True for a count.
    pub integer: bool,
    get: fn(&P) -> f64,
    set: fn(&mut P, f64),
}

impl<P> Debug for Knob<P> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Knob")
            .field("name", &self.name)
            .field("values", &self.values)
            .finish_non_exhaustive()
    }
}

macro_rules! real {
    ($p:ty, $field:ident, $values:expr) => {
        Knob {
            name: stringify!($field),
            values: $values,
            integer: false,
            get: |p: &$p| p.$field,
            set: |p: &mut $p, v| p.$field = v,
        }
    };
}

macro_rules! count {
    ($p:ty, $field:ident, $values:expr) => {
        Knob {
            name: stringify!($field),
            values: $values,
            integer: true,
            get: |p: &$p| p.$field as f64,
            set: |p: &mut $p, v| p.$field = v.max(0.0).round() as usize,
        }
    };
}

fn degrees(values: &[f64]) -> Vec<f64> {
    values.iter().map(|d| d.to_radians()).collect()
}

macro_rules! line_filters {
    ($p:ty) => {
        [
            count!($p, min_line_points, vec![4.0, 6.0, 8.0]),
            real!($p, min_line_length, vec![0.05, 0.1, 0.15]),
        ]
    };
}

/// The knobs of `hough-split`. Its `min_line_length` is not one: it is the size of the
/// smallest surface that counts as a wall (legs and posts up to 12 cm give no line), a
/// definition rather than a tuning.
fn hough_split_knobs() -> Vec<Knob<HoughSplitParams>> {
    vec![
        real!(
            HoughSplitParams,
            criterion,
            vec![0.0, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0]
        ),
        real!(
            HoughSplitParams,
            split_sigmas,
            vec![2.5, 3.0, 3.5, 4.0, 5.0]
        ),
        real!(
            HoughSplitParams,
            split_significance,
            vec![10.0, 15.0, 20.0, 30.0, 40.0]
        ),
        real!(HoughSplitParams, bridge_sigmas, vec![2.0, 3.0, 4.0]),
        real!(HoughSplitParams, max_rms_sigmas, vec![2.0, 2.5, 3.0, 4.0]),
        count!(
            HoughSplitParams,
            min_segment_points,
            vec![3.0, 4.0, 6.0, 8.0]
        ),
        count!(HoughSplitParams, min_line_points, vec![4.0, 6.0, 8.0]),
    ]
}

fn iterative_hough_knobs() -> Vec<Knob<IterativeHoughParams>> {
    let mut k = vec![
        real!(
            IterativeHoughParams,
            min_votes,
            vec![5.0, 8.0, 10.0, 15.0, 20.0]
        ),
        real!(
            IterativeHoughParams,
            inlier_distance,
            vec![0.01, 0.015, 0.02, 0.03]
        ),
        real!(
            IterativeHoughParams,
            inlier_distance_per_metre,
            vec![0.005, 0.01, 0.015, 0.02]
        ),
        count!(IterativeHoughParams, max_skipped, vec![0.0, 1.0, 2.0, 3.0]),
    ];
    k.extend(line_filters!(IterativeHoughParams));
    k
}

macro_rules! split_knobs {
    ($p:ty) => {{
        let mut k: Vec<Knob<$p>> = vec![
            real!($p, split_distance, vec![0.01, 0.015, 0.02, 0.03]),
            real!(
                $p,
                split_distance_per_metre,
                vec![0.005, 0.01, 0.015, 0.02, 0.03]
            ),
            real!($p, breakpoint_incidence, degrees(&[5.0, 10.0, 15.0])),
            real!($p, breakpoint_noise, vec![0.005, 0.01, 0.02]),
            count!($p, min_cluster_points, vec![3.0, 5.0, 8.0]),
        ];
        k.extend(line_filters!($p));
        k
    }};
}

fn incremental_knobs() -> Vec<Knob<IncrementalParams>> {
    let mut k = vec![
        real!(
            IncrementalParams,
            track_distance,
            vec![0.01, 0.015, 0.02, 0.03]
        ),
        real!(
            IncrementalParams,
            track_distance_per_metre,
            vec![0.005, 0.01, 0.015, 0.02]
        ),
        count!(IncrementalParams, seed_points, vec![3.0, 5.0, 7.0, 10.0]),
        count!(IncrementalParams, max_outliers, vec![0.0, 1.0, 2.0]),
        real!(
            IncrementalParams,
            breakpoint_incidence,
            degrees(&[5.0, 10.0, 15.0])
        ),
    ];
    k.extend(line_filters!(IncrementalParams));
    k
}

fn line_regression_knobs() -> Vec<Knob<LineRegressionParams>> {
    let mut k = vec![
        count!(
            LineRegressionParams,
            window,
            vec![5.0, 7.0, 9.0, 11.0, 15.0]
        ),
        real!(
            LineRegressionParams,
            similarity,
            vec![4.0, 9.21, 16.0, 30.0]
        ),
        real!(
            LineRegressionParams,
            noise_sigma_per_metre,
            vec![0.0025, 0.005, 0.01]
        ),
        real!(
            LineRegressionParams,
            merge_distance_per_metre,
            vec![0.005, 0.01, 0.02]
        ),
        count!(LineRegressionParams, min_windows, vec![1.0, 2.0, 3.0, 5.0]),
    ];
    k.extend(line_filters!(LineRegressionParams));
    k
}

fn ransac_knobs() -> Vec<Knob<RansacParams>> {
    let mut k = vec![
        real!(RansacParams, inlier_distance, vec![0.01, 0.015, 0.02, 0.03]),
        real!(
            RansacParams,
            inlier_distance_per_metre,
            vec![0.005, 0.01, 0.015, 0.02]
        ),
        count!(RansacParams, min_inliers, vec![5.0, 8.0, 10.0, 15.0, 20.0]),
        count!(RansacParams, sample_span, vec![10.0, 20.0, 30.0, 50.0]),
        count!(RansacParams, max_skipped, vec![0.0, 1.0, 2.0, 3.0]),
    ];
    k.extend(line_filters!(RansacParams));
    k
}

fn em_knobs() -> Vec<Knob<EmParams>> {
    let mut k = vec![
        real!(
            EmParams,
            noise_sigma_per_metre,
            vec![0.0025, 0.005, 0.0075, 0.01]
        ),
        real!(EmParams, outlier_density, vec![0.05, 0.2, 1.0, 5.0]),
        real!(EmParams, inlier_probability, vec![0.3, 0.5, 0.7]),
        count!(EmParams, init_points, vec![5.0, 7.0, 10.0]),
    ];
    k.extend(line_filters!(EmParams));
    k
}

/// The knobs of `algorithm` as `(name, candidate values)`, or `None` for an unknown name.
#[must_use]
pub fn knobs(algorithm: &str) -> Option<Vec<(&'static str, Vec<f64>)>> {
    fn list<P>(k: Vec<Knob<P>>) -> Vec<(&'static str, Vec<f64>)> {
        k.into_iter().map(|k| (k.name, k.values)).collect()
    }
    Some(match algorithm {
        "hough-split" => list(hough_split_knobs()),
        "iterative-hough" => list(iterative_hough_knobs()),
        "split-and-merge" => list::<SplitAndMergeParams>(split_knobs!(SplitAndMergeParams)),
        "iepf" => list::<IepfParams>(split_knobs!(IepfParams)),
        "incremental" => list(incremental_knobs()),
        "line-regression" => list(line_regression_knobs()),
        "ransac" => list(ransac_knobs()),
        "em" => list(em_knobs()),
        _ => return None,
    })
}

/// A knob's value.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct KnobValue {
    /// The field's name.
    pub name: String,
    /// Its value.
    pub value: f64,
    /// True for a count.
    pub integer: bool,
}

impl KnobValue {
    fn toml(&self) -> String {
        if self.integer {
            format!("{} = {}", self.name, self.value.round())
        } else {
            format!("{} = {}", self.name, self.value)
        }
    }
}

/// The outcome of [`tune`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TuneResult {
    /// The algorithm tuned.
    pub algorithm: String,
    /// The knobs' values at the start (the current defaults).
    pub start: Vec<KnobValue>,
    /// The knobs' chosen values.
    pub chosen: Vec<KnobValue>,
    /// Training metrics at the start.
    pub start_metrics: TruthMetrics,
    /// Training metrics of the chosen values.
    pub chosen_metrics: TruthMetrics,
    /// Parameter sets evaluated.
    pub evaluations: usize,
}

impl TuneResult {
    /// The chosen values as a params-file table (`[algorithm]` and one `key = value` a line).
    #[must_use]
    pub fn to_toml(&self) -> String {
        let mut s = format!("[{}]\n", self.algorithm);
        for k in &self.chosen {
            s.push_str(&k.toml());
            s.push('\n');
        }
        s
    }

    /// The knobs whose chosen value differs from the start.
    #[must_use]
    pub fn changed(&self) -> Vec<(&KnobValue, &KnobValue)> {
        self.start
            .iter()
            .zip(&self.chosen)
            .filter(|(a, b)| a.value != b.value)
            .collect()
    }
}

#[derive(Debug, Clone)]
struct Score {
    metrics: TruthMetrics,
    error: f64,
}

impl Score {
    fn better_than(&self, other: &Self) -> bool {
        self.metrics.f1 > other.metrics.f1 + MIN_GAIN
            || (self.metrics.f1 == other.metrics.f1
                && self.error < other.error * (1.0 - MIN_ERROR_GAIN))
    }
}

struct Search<'a, P> {
    scans: &'a [BenchScan],
    matching: &'a MatchParams,
    build: fn(&P) -> Option<Box<dyn LineExtractor>>,
    cache: HashMap<String, Option<Score>>,
}

impl<P: Debug> Search<'_, P> {
    fn evaluate(&mut self, p: &P) -> Option<Score> {
        let key = format!("{p:?}");
        if let Some(s) = self.cache.get(&key) {
            return s.clone();
        }
        let s = (self.build)(p).map(|mut e| {
            let metrics = score(self.scans, e.as_mut(), self.matching).metrics();
            let error = metrics.rms_dr_m / self.matching.r_tolerance
                + metrics.rms_dalpha_rad / self.matching.alpha_tolerance;
            Score { metrics, error }
        });
        self.cache.insert(key, s.clone());
        s
    }
}

fn describe(m: &TruthMetrics) -> String {
    format!(
        "F1 {:.4} (TP {:.4}, FP {:.4}), rms dr {:.2} mm, rms dalpha {:.3} deg",
        m.f1,
        m.true_positive_rate,
        m.false_positive_rate,
        m.rms_dr_m * 1e3,
        m.rms_dalpha_rad.to_degrees()
    )
}

fn values<P>(p: &P, knobs: &[Knob<P>]) -> Vec<KnobValue> {
    knobs
        .iter()
        .map(|k| KnobValue {
            name: k.name.to_string(),
            value: (k.get)(p),
            integer: k.integer,
        })
        .collect()
}

fn search<P: Clone + Debug>(
    algorithm: &str,
    start: P,
    knobs: &[Knob<P>],
    build: fn(&P) -> Option<Box<dyn LineExtractor>>,
    scans: &[BenchScan],
    matching: &MatchParams,
    log: &mut dyn FnMut(&str),
) -> Result<TuneResult, TuneError> {
    let mut s = Search {
        scans,
        matching,
        build,
        cache: HashMap::new(),
    };
    let Some(start_score) = s.evaluate(&start) else {
        return Err(TuneError::BadDefaults(algorithm.to_string()));
    };
    log(&format!(
        "{algorithm} defaults: {}",
        describe(&start_score.metrics)
    ));
    let mut best = start.clone();
    let mut best_score = start_score.clone();
    for round in 1..=MAX_ROUNDS {
        let mut changed = false;
        for knob in knobs {
            let held = (knob.get)(&best);
            for &v in &knob.values {
                if v == held {
                    continue;
                }
                let mut p = best.clone();
                (knob.set)(&mut p, v);
                let Some(sc) = s.evaluate(&p) else { continue };
                if sc.better_than(&best_score) {
                    log(&format!(
                        "round {round}: {} = {v}: {}",
                        knob.name,
                        describe(&sc.metrics)
                    ));
                    best = p;
                    best_score = sc;
                    changed = true;
                }
            }
        }
        if !changed {
            break;
        }
    }
    Ok(TuneResult {
        algorithm: algorithm.to_string(),
        start: values(&start, knobs),
        chosen: values(&best, knobs),
        start_metrics: start_score.metrics,
        chosen_metrics: best_score.metrics,
        evaluations: s.cache.len(),
    })
}

fn boxed<E: LineExtractor + 'static>(e: Option<E>) -> Option<Box<dyn LineExtractor>> {
    e.map(|e| Box::new(e) as Box<dyn LineExtractor>)
}

/// Tunes `algorithm` on the scans with ground truth among `scans` (see the module docs),
/// reporting progress lines to `log`.
///
/// # Errors
/// [`TuneError`] for an unknown algorithm or scans without ground truth.
pub fn tune(
    algorithm: &str,
    scans: &[BenchScan],
    matching: &MatchParams,
    log: &mut dyn FnMut(&str),
) -> Result<TuneResult, TuneError> {
    if !scans.iter().any(|s| s.truth.is_some()) {
        return Err(TuneError::NoTruth);
    }
    match algorithm {
        "hough-split" => search(
            algorithm,
            HoughSplitParams::default(),
            &hough_split_knobs(),
            |p| boxed(HoughSplit::new(p.clone()).ok()),
            scans,
            matching,
            log,
        ),
        "iterative-hough" => search(
            algorithm,
            IterativeHoughParams::default(),
            &iterative_hough_knobs(),
            |p| boxed(IterativeHough::new(p.clone()).ok()),
            scans,
            matching,
            log,
        ),
        "split-and-merge" => search(
            algorithm,
            SplitAndMergeParams::default(),
            &split_knobs!(SplitAndMergeParams),
            |p| boxed(SplitAndMerge::new(p.clone()).ok()),
            scans,
            matching,
            log,
        ),
        "iepf" => search(
            algorithm,
            IepfParams::default(),
            &split_knobs!(IepfParams),
            |p| boxed(Iepf::new(p.clone()).ok()),
            scans,
            matching,
            log,
        ),
        "incremental" => search(
            algorithm,
            IncrementalParams::default(),
            &incremental_knobs(),
            |p| boxed(Incremental::new(p.clone()).ok()),
            scans,
            matching,
            log,
        ),
        "line-regression" => search(
            algorithm,
            LineRegressionParams::default(),
            &line_regression_knobs(),
            |p| boxed(LineRegression::new(p.clone()).ok()),
            scans,
            matching,
            log,
        ),
        "ransac" => search(
            algorithm,
            RansacParams::default(),
            &ransac_knobs(),
            |p| boxed(Ransac::new(p.clone()).ok()),
            scans,
            matching,
            log,
        ),
        "em" => search(
            algorithm,
            EmParams::default(),
            &em_knobs(),
            |p| boxed(Em::new(p.clone()).ok()),
            scans,
            matching,
            log,
        ),
        other => Err(TuneError::UnknownAlgorithm(other.to_string())),
    }
}
