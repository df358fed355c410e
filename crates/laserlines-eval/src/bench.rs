//! Running extractors side by side on the same scans, and the metrics they get.

use std::time::Instant;

use laserlines::{Line, LineExtractor};
use serde::Serialize;

use crate::coverage::{Coverage, ExplainParams, ratio};
use crate::matching::{MatchParams, Pair, ScanMatch, match_lines};
use crate::workload::BenchScan;

/// How a benchmark runs and scores.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BenchOptions {
    /// Timed extractions of each scan by each extractor; the fastest counts. Default 1.
    pub repeat: usize,
    /// The match of lines to ground truth.
    pub matching: MatchParams,
    /// The threshold of an explained point.
    pub explain: ExplainParams,
}

impl Default for BenchOptions {
    fn default() -> Self {
        Self {
            repeat: 1,
            matching: MatchParams::default(),
            explain: ExplainParams::default(),
        }
    }
}

/// Ground-truth counts of one or more scans; add them up with [`TruthTally::add`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TruthTally {
    /// Significant pieces.
    pub pieces: usize,
    /// Significant pieces found.
    pub found: usize,
    /// Lines.
    pub lines: usize,
    /// Lines matching no piece.
    pub false_lines: usize,
    /// False lines that lie on a wall.
    pub on_wall_lines: usize,
    /// Errors over the found pieces.
    pub accuracy: Accuracy,
}

impl TruthTally {
    /// Matches `lines` to `pieces` and counts.
    #[must_use]
    pub fn of_scan(
        lines: &[Line],
        pieces: &[crate::truth::ExpectedPiece],
        params: &MatchParams,
    ) -> Self {
        Self::of_match(&match_lines(lines, pieces, params))
    }

    /// The counts of one scan's match.
    #[must_use]
    pub fn of_match(m: &ScanMatch) -> Self {
        let mut t = Self {
            pieces: m.significant_pieces,
            found: m.found,
            lines: m.lines,
            false_lines: m.false_lines.len(),
            on_wall_lines: m.on_wall_lines.len(),
            ..Self::default()
        };
        for p in m.pairs.iter().filter(|p| p.significant) {
            t.accuracy.push(p);
        }
        t
    }

    /// Adds the counts of `other`.
    pub fn add(&mut self, other: &Self) {
        self.pieces += other.pieces;
        self.found += other.found;
        self.lines += other.lines;
        self.false_lines += other.false_lines;
        self.on_wall_lines += other.on_wall_lines;
        self.accuracy.add(&other.accuracy);
    }

    /// The metrics of these counts.
    #[must_use]
    pub fn metrics(&self) -> TruthMetrics {
        let tp = if self.pieces == 0 {
            1.0
        } else {
            ratio(self.found, self.pieces)
        };
        let fp = ratio(self.false_lines, self.lines);
        let precision = 1.0 - fp;
        let f1 = if tp + precision > 0.0 {
            2.0 * tp * precision / (tp + precision)
        } else {
            0.0
        };
        let acc = self.accuracy.metrics();
        TruthMetrics {
            pieces: self.pieces,
            found: self.found,
            true_positive_rate: tp,
            lines: self.lines,
            false_lines: self.false_lines,
            false_positive_rate: fp,
            on_wall_lines: self.on_wall_lines,
            f1,
            rms_dr_m: acc.rms_dr_m,
            rms_dalpha_rad: acc.rms_dalpha_rad,
            median_endpoint_error_m: acc.median_endpoint_error_m,
            p90_endpoint_error_m: acc.p90_endpoint_error_m,
        }
    }
}

/// The metrics of Nguyen et al. against ground truth (see the crate docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TruthMetrics {
    /// Significant visible pieces.
    pub pieces: usize,
    /// Of them, found.
    pub found: usize,
    /// `found / pieces` (1 when there is no piece to find).
    pub true_positive_rate: f64,
    /// Extracted lines.
    pub lines: usize,
    /// Of them, matching no piece.
    pub false_lines: usize,
    /// `false_lines / lines` (0 without lines).
    pub false_positive_rate: f64,
    /// False lines that lie on a real wall (a split wall's second line, a fragment, a line
    /// bridging an obstacle in front of a wall; see [`crate::matching`]), included in
    /// `false_lines`.
    pub on_wall_lines: usize,
    /// Harmonic mean of the true-positive rate and `1 - false_positive_rate`.
    pub f1: f64,
    /// RMS of `r` errors over found pieces, m.
    pub rms_dr_m: f64,
    /// RMS of `alpha` errors over found pieces, rad.
    pub rms_dalpha_rad: f64,
    /// Median distance between the end points of found pieces and of their lines, m.
    pub median_endpoint_error_m: f64,
    /// 90th percentile of those distances, m.
    pub p90_endpoint_error_m: f64,
}

/// Errors over a set of found pieces; add them up with [`Accuracy::add`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Accuracy {
    /// Pieces.
    pub pieces: usize,
    /// Sum of `dr^2`, m^2.
    pub sum_sq_dr: f64,
    /// Sum of `dalpha^2`, rad^2.
    pub sum_sq_dalpha: f64,
    /// End-point errors (two per piece), m.
    pub endpoint_errors: Vec<f64>,
}

impl Accuracy {
    /// Adds one found piece.
    pub fn push(&mut self, pair: &Pair) {
        self.pieces += 1;
        self.sum_sq_dr += pair.dr * pair.dr;
        self.sum_sq_dalpha += pair.dalpha * pair.dalpha;
        self.endpoint_errors.push(pair.start_error);
        self.endpoint_errors.push(pair.end_error);
    }

    /// Adds the errors of `other`.
    pub fn add(&mut self, other: &Self) {
        self.pieces += other.pieces;
        self.sum_sq_dr += other.sum_sq_dr;
        self.sum_sq_dalpha += other.sum_sq_dalpha;
        self.endpoint_errors
            .extend_from_slice(&other.endpoint_errors);
    }

    /// RMS and median figures.
    #[must_use]
    pub fn metrics(&self) -> AccuracyMetrics {
        let rms = |s: f64| {
            if self.pieces == 0 {
                0.0
            } else {
                (s / self.pieces as f64).sqrt()
            }
        };
        AccuracyMetrics {
            pieces: self.pieces,
            rms_dr_m: rms(self.sum_sq_dr),
            rms_dalpha_rad: rms(self.sum_sq_dalpha),
            median_endpoint_error_m: median(&self.endpoint_errors).unwrap_or(0.0),
            p90_endpoint_error_m: quantile(&self.endpoint_errors, 0.9).unwrap_or(0.0),
        }
    }
}

/// Errors over a set of found pieces.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AccuracyMetrics {
    /// Pieces.
    pub pieces: usize,
    /// RMS of `r` errors, m.
    pub rms_dr_m: f64,
    /// RMS of `alpha` errors, rad.
    pub rms_dalpha_rad: f64,
    /// Median end-point error, m.
    pub median_endpoint_error_m: f64,
    /// 90th percentile of the end-point errors, m.
    pub p90_endpoint_error_m: f64,
}

/// Speed of one extractor over a run (single thread, reused extractor and buffer).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpeedMetrics {
    /// Median over scans of the time per scan, microseconds.
    pub median_us_per_scan: f64,
    /// Mean time per scan, microseconds.
    pub mean_us_per_scan: f64,
    /// Scans divided by the total time.
    pub scans_per_second: f64,
}

impl SpeedMetrics {
    /// Speed of per-scan times in seconds.
    #[must_use]
    pub fn of_times(times: &[f64]) -> Self {
        let total: f64 = times.iter().sum();
        let n = times.len();
        Self {
            median_us_per_scan: median(times).unwrap_or(0.0) * 1e6,
            mean_us_per_scan: if n == 0 { 0.0 } else { total / n as f64 * 1e6 },
            scans_per_second: if total > 0.0 { n as f64 / total } else { 0.0 },
        }
    }
}

/// Everything measured for one extractor on one group of scans (or all of them).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AlgorithmMetrics {
    /// The extractor's name.
    pub algorithm: String,
    /// The group (suite or file), or `all`.
    pub group: String,
    /// Scans.
    pub scans: usize,
    /// Lines extracted.
    pub lines: usize,
    /// Lines per scan.
    pub lines_per_scan: f64,
    /// Metrics against ground truth, when every scan had it.
    pub truth: Option<TruthMetrics>,
    /// Errors over the significant pieces that every extractor of the run found (the same
    /// pieces for all), when every scan had ground truth.
    pub common: Option<AccuracyMetrics>,
    /// Fraction of valid points explained by lines.
    pub explained_fraction: f64,
    /// RMS residual of the lines' supporting points, m.
    pub residual_rms_m: f64,
    /// Speed.
    pub speed: SpeedMetrics,
}

/// The result of [`run`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BenchReport {
    /// What ran on what (free text given by the caller).
    pub source: String,
    /// Scans run.
    pub scans: usize,
    /// The options used.
    pub options: BenchOptions,
    /// Per extractor, over all scans, in the order the extractors were given.
    pub overall: Vec<AlgorithmMetrics>,
    /// Per group and extractor, groups in order of first appearance.
    pub by_group: Vec<AlgorithmMetrics>,
    /// Per extractor, the time of each scan, s (in scan order).
    #[serde(skip)]
    pub times: Vec<Vec<f64>>,
}

/// The ratio of the speeds of two extractors measured in one run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpeedRatio {
    /// Median time per scan of the slower divided by that of the faster one.
    pub of_medians: f64,
    /// Median over scans of the per-scan ratio of the two times.
    pub median_of_ratios: f64,
}

impl BenchReport {
    /// The overall metrics of `algorithm`.
    #[must_use]
    pub fn get(&self, algorithm: &str) -> Option<&AlgorithmMetrics> {
        self.overall.iter().find(|m| m.algorithm == algorithm)
    }

    /// How many times faster `fast` is than `slow`, in this run; `None` when either did not
    /// run or a time is zero.
    #[must_use]
    pub fn speed_ratio(&self, fast: &str, slow: &str) -> Option<SpeedRatio> {
        let i = self.overall.iter().position(|m| m.algorithm == fast)?;
        let j = self.overall.iter().position(|m| m.algorithm == slow)?;
        let (a, b) = (self.times.get(i)?, self.times.get(j)?);
        let of_medians = median(b)? / median(a)?;
        let ratios: Vec<f64> = a
            .iter()
            .zip(b)
            .filter(|(x, _)| **x > 0.0)
            .map(|(x, y)| y / x)
            .collect();
        let median_of_ratios = median(&ratios)?;
        (of_medians.is_finite() && median_of_ratios.is_finite()).then_some(SpeedRatio {
            of_medians,
            median_of_ratios,
        })
    }

    /// The group names, in order.
    #[must_use]
    pub fn groups(&self) -> Vec<&str> {
        let mut out: Vec<&str> = Vec::new();
        for m in &self.by_group {
            if !out.contains(&m.group.as_str()) {
                out.push(&m.group);
            }
        }
        out
    }
}

/// The `q` quantile of `values` (`0 <= q <= 1`; the smallest value with at least a share `q`
/// of the values at or below it), or `None` when empty. NaNs sort last.
#[must_use]
pub fn quantile(values: &[f64], q: f64) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let rank = (q.clamp(0.0, 1.0) * v.len() as f64).ceil() as usize;
    v.get(rank.saturating_sub(1)).copied()
}

/// The median of `values` (mean of the middle two for an even count), or `None` when empty.
/// NaNs sort last.
#[must_use]
pub fn median(values: &[f64]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    })
}

#[derive(Debug, Default, Clone)]
struct Tally {
    scans: usize,
    lines: usize,
    truth: TruthTally,
    common: Accuracy,
    all_truth: bool,
    coverage: Coverage,
    times: Vec<f64>,
}

impl Tally {
    fn new() -> Self {
        Self {
            all_truth: true,
            ..Self::default()
        }
    }

    fn metrics(&self, algorithm: &str, group: &str) -> AlgorithmMetrics {
        AlgorithmMetrics {
            algorithm: algorithm.to_string(),
            group: group.to_string(),
            scans: self.scans,
            lines: self.lines,
            lines_per_scan: ratio(self.lines, self.scans),
            truth: (self.all_truth && self.scans > 0).then(|| self.truth.metrics()),
            common: (self.all_truth && self.scans > 0).then(|| self.common.metrics()),
            explained_fraction: self.coverage.explained_fraction(),
            residual_rms_m: self.coverage.residual_rms(),
            speed: SpeedMetrics::of_times(&self.times),
        }
    }
}

/// Adds each extractor's errors on the significant pieces (of `pieces`) that every
/// extractor found to its overall and group tallies.
fn add_common(
    pieces: usize,
    matches: &[Option<ScanMatch>],
    overall: &mut [Tally],
    group: &mut [Tally],
) {
    let found_by_all = |pi: usize| {
        matches.iter().all(|m| {
            m.as_ref()
                .is_some_and(|m| m.pairs.iter().any(|p| p.piece == pi && p.significant))
        })
    };
    let common: Vec<usize> = (0..pieces).filter(|&pi| found_by_all(pi)).collect();
    for (a, m) in matches.iter().enumerate() {
        let Some(m) = m else { continue };
        let mut acc = Accuracy::default();
        for p in m.pairs.iter().filter(|p| common.contains(&p.piece)) {
            acc.push(p);
        }
        overall[a].common.add(&acc);
        group[a].common.add(&acc);
    }
}

/// The name `all` of the overall group.
pub const OVERALL: &str = "all";

/// Runs every extractor on every scan, in one thread, and scores them.
///
/// The extractors take turns on each scan (the first to run rotates from scan to scan), so
/// that a change of the machine's load affects all of them alike; each is timed around
/// [`LineExtractor::extract_into`] alone, with its buffer reused, `options.repeat` times (the
/// fastest counts). `progress` is called with the number of scans done after each scan.
pub fn run(
    source: &str,
    scans: &[BenchScan],
    extractors: &mut [Box<dyn LineExtractor + Send>],
    options: &BenchOptions,
    progress: &mut dyn FnMut(usize),
) -> BenchReport {
    let n = extractors.len();
    let mut overall: Vec<Tally> = (0..n).map(|_| Tally::new()).collect();
    let mut groups: Vec<(String, Vec<Tally>)> = Vec::new();
    let mut lines: Vec<Line> = Vec::new();
    for (k, bs) in scans.iter().enumerate() {
        let gi = match groups.iter().position(|(g, _)| *g == bs.group) {
            Some(i) => i,
            None => {
                groups.push((bs.group.clone(), (0..n).map(|_| Tally::new()).collect()));
                groups.len() - 1
            }
        };
        let mut matches: Vec<Option<ScanMatch>> = vec![None; n];
        for turn in 0..n {
            let a = (k + turn) % n;
            let e = &mut extractors[a];
            let mut best = f64::INFINITY;
            for _ in 0..options.repeat.max(1) {
                let t = Instant::now();
                e.extract_into(&bs.scan, &mut lines);
                best = best.min(t.elapsed().as_secs_f64());
            }
            let coverage = Coverage::of_scan(&bs.scan, &lines, &options.explain);
            let m = bs
                .truth
                .as_ref()
                .map(|pieces| match_lines(&lines, pieces, &options.matching));
            let truth = m.as_ref().map(TruthTally::of_match);
            for tally in [&mut overall[a], &mut groups[gi].1[a]] {
                tally.scans += 1;
                tally.lines += lines.len();
                tally.coverage.add(&coverage);
                tally.times.push(best);
                match &truth {
                    Some(t) => tally.truth.add(t),
                    None => tally.all_truth = false,
                }
            }
            matches[a] = m;
        }
        // The significant pieces every extractor found, and each one's errors on them.
        if let Some(pieces) = &bs.truth {
            let (all, group) = (&mut overall, &mut groups[gi].1);
            add_common(pieces.len(), &matches, all, group);
        }
        progress(k + 1);
    }
    let names: Vec<&'static str> = extractors.iter().map(|e| e.name()).collect();
    BenchReport {
        source: source.to_string(),
        scans: scans.len(),
        options: *options,
        overall: overall
            .iter()
            .zip(&names)
            .map(|(t, name)| t.metrics(name, OVERALL))
            .collect(),
        by_group: groups
            .iter()
            .flat_map(|(g, tallies)| {
                tallies
                    .iter()
                    .zip(&names)
                    .map(move |(t, name)| t.metrics(name, g))
            })
            .collect(),
        times: overall.into_iter().map(|t| t.times).collect(),
    }
}

/// The ground-truth counts of one extractor over `scans` (scans without truth are skipped),
/// without timing: what tuning needs.
pub fn score(
    scans: &[BenchScan],
    extractor: &mut dyn LineExtractor,
    matching: &MatchParams,
) -> TruthTally {
    let mut total = TruthTally::default();
    let mut lines = Vec::new();
    for bs in scans {
        if let Some(pieces) = &bs.truth {
            extractor.extract_into(&bs.scan, &mut lines);
            total.add(&TruthTally::of_scan(&lines, pieces, matching));
        }
    }
    total
}
