//! What several of these tests share: every extractor, built as `laserlines bench` builds it,
//! on simulated scans with their ground truth, judged by the field criteria.

use laserlines::extractors::ALGORITHMS;
use laserlines_eval::{BenchScan, MatchParams, TruthMetrics, TruthTally};
use laserlines_io::params::ParamsFile;

/// The field-criteria metrics of every extractor of [`ALGORITHMS`] (`hough-split` first) on
/// `scans`, each built from its defaults with its noise thresholds scaled by `noise_scale`
/// (`ParamsFile::extractor_for_noise`, the path `laserlines bench` takes); each printed after
/// `label`.
pub fn field_metrics(
    scans: &[BenchScan],
    noise_scale: f64,
    label: &str,
) -> Vec<(&'static str, TruthMetrics)> {
    let params = MatchParams::field();
    // No params file: every extractor's defaults.
    let defaults = ParamsFile::default();
    ALGORITHMS
        .iter()
        .map(|&algorithm| {
            let mut e = defaults
                .extractor_for_noise(algorithm, noise_scale)
                .expect("every registered extractor builds");
            let mut total = TruthTally::default();
            for s in scans {
                let truth = s.truth.as_ref().expect("simulated scans have a truth");
                total.add(&TruthTally::of_scan(&e.extract(&s.scan), truth, &params));
            }
            let m = total.metrics();
            println!(
                "{label} {algorithm:16} TP {:.3} FP {:.3} F1 {:.3}",
                m.true_positive_rate, m.false_positive_rate, m.f1
            );
            (algorithm, m)
        })
        .collect()
}
