//! # laserlines-eval
//!
//! How good and how fast is a line extractor? This crate answers with the metrics of Nguyen
//! et al. ("A comparison of line extraction algorithms using 2D range data for indoor mobile
//! robotics", IROS 2005; Autonomous Robots 2007) on simulated scans with ground truth, and with
//! coverage metrics on real logs without it. `laserlines bench` is its command line.
//!
//! ## On scans with ground truth
//!
//! The ground truth of a simulated scan ([`truth`]) is its visible wall pieces: maximal runs
//! of consecutive beams whose noise-free rays hit one wall, trimmed to the first and last beam
//! the sensor reported. A piece is **significant** (it must be found) when it has at least 10
//! beams and its seen ends are at least 0.2 m apart.
//!
//! Lines are matched to pieces one to one ([`matching`]): a line and a piece are compatible
//! when the intersection over union of their beam ranges is at least 1/2, `|dr|` is within
//! `max(1 cm, 4 sigma_r)` and the angle between their normals within
//! `max(0.5 deg, 4 sigma_alpha)`, where `sigma_r` and `sigma_alpha` are the standard errors of
//! an ideal least-squares fit of the piece's beams under the simulated noise; compatible pairs
//! are assigned greedily by decreasing overlap. Then, over all scans of a run:
//!
//! - **true-positive rate** = significant pieces with a line assigned / significant pieces;
//! - **false-positive rate** = lines with no piece assigned / lines (Nguyen et al.:
//!   `(extracted - matched) / extracted`). A second line on an already matched piece is false,
//!   and so is a line bridging an obstacle in front of a wall (both are counted apart as *on a
//!   wall*); a line assigned to a real but non-significant piece is neither found nor false;
//! - **F1** = harmonic mean of the true-positive rate and `1 - false-positive rate`;
//! - **RMS error of r and of alpha** over the found pieces (line minus piece);
//! - **median end-point error**: the median, over both ends of every found piece, of the
//!   distance between the line's end point and the piece's noise-free hit at its first or last
//!   seen beam (and its 90th percentile, for the tails);
//! - **lines per scan**.
//!
//! Since every extractor finds a somewhat different set of pieces, and hard pieces (far,
//! short, grazing) have larger errors, the same error figures are also reported over the
//! *common* pieces: the significant pieces that every extractor of the run found.
//!
//! ## On any scans (real logs)
//!
//! [`coverage`]: lines per scan; the fraction of valid points within
//! `max(15 mm, 1.5 % of the range)` (three standard deviations of the URG-04LX range noise) of
//! a line segment; the RMS residual of the lines' supporting points.
//!
//! ## Speed
//!
//! Each extractor runs in one thread on one scan at a time, with its working memory and its
//! output buffer reused; only [`laserlines::LineExtractor::extract_into`] is timed. Reported:
//! the median over scans of the time per scan (µs) and scans per second (scans / total time).
//! [`bench::run`] lets the extractors take turns on each scan, so that they share the
//! machine's load alike and ratios between them are fair even on a busy machine.
//!
//! ## Tuning
//!
//! [`tune`]: a coordinate search over a few parameters of an extractor, maximising F1 on a
//! training suite ([`TRAIN_SEED`]); results are reported on a test suite with another seed
//! ([`TEST_SEED`]).
//!
//! ```
//! use laserlines::extractors;
//! use laserlines_eval::{BenchOptions, run, sensor, suite_scans};
//!
//! let scans = suite_scans("rooms", 7, 2, &sensor("urg04lx").unwrap()).unwrap();
//! let mut contenders = vec![extractors::by_name("hough-split").unwrap()];
//! let report = run("rooms", &scans, &mut contenders, &BenchOptions::default(), &mut |_| {});
//! let t = report.overall[0].truth.unwrap();
//! assert!(t.true_positive_rate > 0.5 && t.false_positive_rate < 0.5);
//! assert!(report.to_markdown().contains("| hough-split |"));
//! ```

pub mod bench;
pub mod coverage;
pub mod matching;
mod report;
pub mod scanners;
pub mod truth;
pub mod tune;
pub mod workload;

pub use bench::{
    Accuracy, AccuracyMetrics, AlgorithmMetrics, BenchOptions, BenchReport, SpeedMetrics,
    SpeedRatio, TruthMetrics, TruthTally, median, quantile, run, score,
};
pub use coverage::{Coverage, ExplainParams};
pub use matching::{MatchParams, Pair, ScanMatch, match_lines};
pub use truth::{ExpectedPiece, expected_pieces};
pub use tune::{TuneError, TuneResult, tune};
pub use workload::{
    BenchScan, DEFAULT_SCANS_PER_SUITE, SENSORS, TEST_SEED, TRAIN_SEED, arena_scans,
    arena_scans_counted, plain_scans, sensor, suite_scans,
};
