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
//! which the objective would always push up. The knobs and their candidates are listed in
//! the extractors' registry ([`laserlines::registry::Algorithm::knobs`], [`knobs`] by name);
//! they span each parameter's documented sensible range, with one limit: the minimum sizes
//! of lines, segments and clusters stay below the size from which the metric requires a
//! piece to be found (10 beams, 0.2 m). A line shorter than that can only count as false or
//! not at all, so a search allowed to reach the bound would learn to drop every such line,
//! real small walls included: that would fit the metric, not the scenes.

use std::collections::HashMap;
use std::fmt::Debug;

use laserlines::registry::{self, Algorithm, Knob, Params, Visitor};
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
    #[error("unknown algorithm {0:?}: expected one of {list}", list = registry::ALGORITHMS.join(", "))]
    UnknownAlgorithm(String),
    /// No scan has ground truth to tune on.
    #[error("tuning needs scans with ground truth (a simulated suite)")]
    NoTruth,
    /// The starting parameters do not build an extractor.
    #[error("the default parameters of {0} are invalid")]
    BadDefaults(String),
}

/// The knobs of `algorithm` as `(name, candidate values)`, or `None` for an unknown name.
#[must_use]
pub fn knobs(algorithm: &str) -> Option<Vec<(&'static str, Vec<f64>)>> {
    struct List;
    impl Visitor for List {
        type Output = Vec<(&'static str, Vec<f64>)>;
        fn visit<P: Params>(self, algorithm: &'static Algorithm<P>) -> Self::Output {
            algorithm
                .knobs
                .iter()
                .map(|k| (k.name, k.values.to_vec()))
                .collect()
        }
    }
    registry::visit(algorithm, List)
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

struct Search<'a, P: 'static> {
    scans: &'a [BenchScan],
    matching: &'a MatchParams,
    algorithm: &'static Algorithm<P>,
    cache: HashMap<String, Option<Score>>,
}

impl<P: Params> Search<'_, P> {
    fn evaluate(&mut self, p: &P) -> Option<Score> {
        let key = format!("{p:?}");
        if let Some(s) = self.cache.get(&key) {
            return s.clone();
        }
        let built = (self.algorithm.build)(p.clone()).ok();
        let s = built.map(|mut e| {
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

fn search<P: Params>(
    entry: &'static Algorithm<P>,
    scans: &[BenchScan],
    matching: &MatchParams,
    log: &mut dyn FnMut(&str),
) -> Result<TuneResult, TuneError> {
    let algorithm = entry.name;
    let start = (entry.defaults)();
    let knobs = entry.knobs;
    let mut s = Search {
        scans,
        matching,
        algorithm: entry,
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
            for &v in knob.values {
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
    struct Tune<'a, 'l> {
        scans: &'a [BenchScan],
        matching: &'a MatchParams,
        log: &'l mut dyn FnMut(&str),
    }
    impl Visitor for Tune<'_, '_> {
        type Output = Result<TuneResult, TuneError>;
        fn visit<P: Params>(self, entry: &'static Algorithm<P>) -> Self::Output {
            search(entry, self.scans, self.matching, self.log)
        }
    }
    registry::visit(
        algorithm,
        Tune {
            scans,
            matching,
            log,
        },
    )
    .unwrap_or_else(|| Err(TuneError::UnknownAlgorithm(algorithm.to_string())))
}
