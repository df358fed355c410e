//! Every extractor on the simulated suites of the other scanners (`laserlines bench --sensor
//! utm30lx | ust10lx | lms1xx | lms2xx | rplidar-a1 | rplidar-a2 | ydlidar-x4 | kinect |
//! realsense-d435`,
//! [`laserlines_eval::scanners`]): each at its data sheet's noise, in the field conditions
//! (legs, dropouts, mixed pixels on the time-of-flight scanners), judged by the field
//! criteria. The classic extractors get the scanner's noise as `laserlines bench` gives it to
//! them (`ParamsFile::extractor_for_noise`: their noise thresholds scaled,
//! [`laserlines::registry::noise_scale`]); `hough-split` estimates its own.
//!
//! On seed 5, 10 scenes of each of the seven suites, `hough-split` must find what it is
//! documented to and lead the other seven by F1 (bounds just under what it measures here):
//! by 0.14 on the UTM-30LX, 0.18 on the UST-10LX, 0.04 on the LMS1xx and the RPLIDAR A1, 0.13
//! on the RPLIDAR A2, 0.4 on the YDLIDAR X4 and 0.25-0.3 on the depth cameras. On the SICK
//! LMS200 (1 deg beams, 15 mm, few pieces of 10 beams or more) the four best lie within 0.01
//! on these 70 scans, `hough-split` 0.007 below `iterative-hough`; it leads on 700 (`laserlines
//! bench --sensor lms2xx --criteria field --seed 5`: 0.972 against 0.960), so there it must
//! stay within 0.01 of the best.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use laserlines::extractors::ALGORITHMS;
use laserlines_eval::workload::{sensor, suite_scans};

mod common;

/// `(scanner, least TP rate, largest FP rate, least lead in F1 over the best other)` of
/// `hough-split`; measured in this order: TP 0.958, 0.939, 0.965, 0.954, 0.972, 0.921 and
/// 0.778, FP 0.029, 0.036, 0.015, 0.033, 0.021, 0.020 and 0.044, lead 0.154, 0.196, 0.043,
/// -0.007, 0.052, 0.139 and 0.490. Without the advance test of glancing lines
/// (`min_advance_t = 0`) the UTM-30LX's and the UST-10LX's FP rates here are 0.055 and 0.085.
/// The YDLIDAR X4's TP rate was 0.742 (FP 0.037) while its lines and data segments needed
/// the 8 points of a dense scan ([`laserlines::HoughSplitParams::min_points_for`]); on 700
/// scans of the same seed (`laserlines bench --sensor ydlidar-x4 --criteria field --seed
/// 5`) it is 0.785 / 0.037. The depth cameras read as scans (`kinect`, `realsense-d435`):
/// TP 0.980 and 0.879, FP 0.025 and 0.047, lead 0.283 and 0.366.
const BOUNDS: &[(&str, f64, f64, f64)] = &[
    ("utm30lx", 0.945, 0.04, 0.14),
    ("ust10lx", 0.93, 0.045, 0.18),
    ("lms1xx", 0.955, 0.025, 0.04),
    ("lms2xx", 0.94, 0.04, -0.01),
    ("rplidar-a1", 0.96, 0.03, 0.04),
    ("rplidar-a2", 0.91, 0.03, 0.13),
    ("ydlidar-x4", 0.76, 0.05, 0.45),
    ("kinect", 0.965, 0.035, 0.25),
    ("realsense-d435", 0.86, 0.055, 0.3),
];

#[test]
fn hough_split_leads_on_other_scanners() {
    assert_eq!(ALGORITHMS[0], "hough-split");
    let mut failures = Vec::new();
    for &(name, least_tp, most_fp, least_lead) in BOUNDS {
        let sensor = sensor(name).unwrap();
        let scans = suite_scans("all", 5, 10, &sensor).unwrap();
        let mut f1 = Vec::new();
        for (algorithm, m) in common::field_metrics(&scans, sensor.noise_scale(), name) {
            if algorithm == "hough-split"
                && (m.true_positive_rate < least_tp || m.false_positive_rate > most_fp)
            {
                failures.push(format!(
                    "{name}: hough-split TP {:.3} (least {least_tp}), FP {:.3} (most {most_fp})",
                    m.true_positive_rate, m.false_positive_rate
                ));
            }
            f1.push((algorithm, m.f1));
        }
        let ours = f1[0].1;
        let best = f1[1..]
            .iter()
            .copied()
            .fold(("", f64::MIN), |a, b| if b.1 > a.1 { b } else { a });
        if ours - best.1 < least_lead {
            failures.push(format!(
                "{name}: hough-split F1 {ours:.3}, the best other {best:?} (least lead {least_lead})"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
