//! The tuning knobs of every extractor: the parameters `laserlines bench --tune` searches and
//! the values it tries (see `laserlines_eval::tune`).
//!
//! Only parameters that shape the result are knobs, never work budgets (iterations, trials),
//! which the objective would always push up. The candidates span each parameter's documented
//! sensible range, with one limit: the minimum sizes of lines, segments and clusters stay
//! below the size from which the metric requires a piece to be found (10 beams, 0.2 m), so
//! that the search cannot learn to drop every line the metric does not require.

use super::Knob;
use crate::extractors::{
    EmParams, IncrementalParams, IterativeHoughParams, LineRegressionParams, RansacParams,
    SplitMergeParams,
};
use crate::hough_split::HoughSplitParams;

/// A knob on a real-valued field (`$($f).+` is its path in the struct).
macro_rules! real {
    ($p:ty, $name:literal, $($f:ident).+, $values:expr) => {
        Knob {
            name: $name,
            values: $values,
            integer: false,
            get: |p: &$p| p.$($f).+,
            set: |p: &mut $p, v| p.$($f).+ = v,
        }
    };
}

/// A knob on a count.
macro_rules! count {
    ($p:ty, $name:literal, $($f:ident).+, $values:expr) => {
        Knob {
            name: $name,
            values: $values,
            integer: true,
            get: |p: &$p| p.$($f).+ as f64,
            set: |p: &mut $p, v| p.$($f).+ = v.max(0.0).round() as usize,
        }
    };
}

/// Candidate breakpoint incidence angles: 5, 10 and 15 deg.
const INCIDENCES: &[f64] = &[
    5.0_f64.to_radians(),
    10.0_f64.to_radians(),
    15.0_f64.to_radians(),
];

/// The knobs of the line filter of the classic extractors, last in their lists.
macro_rules! filter {
    ($p:ty) => {
        [
            count!($p, "filter.min_points", filter.min_points, &[4.0, 6.0, 8.0]),
            real!(
                $p,
                "filter.min_length",
                filter.min_length,
                &[0.05, 0.1, 0.15]
            ),
        ]
    };
}

/// `hough-split`. Its `min_line_length` is not a knob: it is the size of the smallest
/// surface that counts as a wall (legs and posts up to 12 cm give no line), a definition
/// rather than a tuning.
pub(super) static HOUGH_SPLIT: &[Knob<HoughSplitParams>] = &[
    real!(
        HoughSplitParams,
        "criterion",
        criterion,
        &[0.0, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0]
    ),
    real!(
        HoughSplitParams,
        "split_sigmas",
        split_sigmas,
        &[2.5, 3.0, 3.5, 4.0, 5.0]
    ),
    real!(
        HoughSplitParams,
        "split_significance",
        split_significance,
        &[10.0, 15.0, 20.0, 30.0, 40.0]
    ),
    real!(
        HoughSplitParams,
        "bridge_sigmas",
        bridge_sigmas,
        &[2.0, 3.0, 4.0]
    ),
    real!(
        HoughSplitParams,
        "max_rms_sigmas",
        max_rms_sigmas,
        &[2.0, 2.5, 3.0, 4.0]
    ),
    real!(
        HoughSplitParams,
        "min_advance_t",
        min_advance_t,
        &[0.0, 5.0, 8.0, 12.0]
    ),
    real!(
        HoughSplitParams,
        "arc_significance",
        arc_significance,
        &[0.0, 1.0, 2.0, 4.0, 9.0]
    ),
    count!(
        HoughSplitParams,
        "min_segment_points",
        min_segment_points,
        &[3.0, 4.0, 6.0, 8.0]
    ),
    count!(
        HoughSplitParams,
        "min_line_points",
        min_line_points,
        &[4.0, 6.0, 8.0]
    ),
];

type Ih = IterativeHoughParams;
/// `iterative-hough`.
pub(super) static ITERATIVE_HOUGH: &[Knob<Ih>] = &{
    let [a, b] = filter!(Ih);
    [
        real!(Ih, "min_votes", min_votes, &[5.0, 8.0, 10.0, 15.0, 20.0]),
        real!(
            Ih,
            "inlier_distance",
            inlier_distance,
            &[0.01, 0.015, 0.02, 0.03]
        ),
        real!(
            Ih,
            "inlier_distance_per_metre",
            inlier_distance_per_metre,
            &[0.005, 0.01, 0.015, 0.02]
        ),
        count!(Ih, "max_skipped", max_skipped, &[0.0, 1.0, 2.0, 3.0]),
        a,
        b,
    ]
};

type Sm = SplitMergeParams;
/// `split-and-merge` and `iepf` (one engine).
pub(super) static SPLIT_MERGE: &[Knob<Sm>] = &{
    let [a, b] = filter!(Sm);
    [
        real!(
            Sm,
            "split_distance",
            split_distance,
            &[0.01, 0.015, 0.02, 0.03]
        ),
        real!(
            Sm,
            "split_distance_per_metre",
            split_distance_per_metre,
            &[0.005, 0.01, 0.015, 0.02, 0.03]
        ),
        real!(
            Sm,
            "breakpoints.incidence",
            breakpoints.incidence,
            INCIDENCES
        ),
        real!(
            Sm,
            "breakpoints.noise",
            breakpoints.noise,
            &[0.005, 0.01, 0.02]
        ),
        count!(
            Sm,
            "min_cluster_points",
            min_cluster_points,
            &[3.0, 5.0, 8.0]
        ),
        a,
        b,
    ]
};

type Inc = IncrementalParams;
/// `incremental`.
pub(super) static INCREMENTAL: &[Knob<Inc>] = &{
    let [a, b] = filter!(Inc);
    [
        real!(
            Inc,
            "track_distance",
            track_distance,
            &[0.01, 0.015, 0.02, 0.03]
        ),
        real!(
            Inc,
            "track_distance_per_metre",
            track_distance_per_metre,
            &[0.005, 0.01, 0.015, 0.02]
        ),
        count!(Inc, "seed_points", seed_points, &[3.0, 5.0, 7.0, 10.0]),
        count!(Inc, "max_outliers", max_outliers, &[0.0, 1.0, 2.0]),
        real!(
            Inc,
            "breakpoints.incidence",
            breakpoints.incidence,
            INCIDENCES
        ),
        a,
        b,
    ]
};

type Lr = LineRegressionParams;
/// `line-regression`.
pub(super) static LINE_REGRESSION: &[Knob<Lr>] = &{
    let [a, b] = filter!(Lr);
    [
        count!(Lr, "window", window, &[5.0, 7.0, 9.0, 11.0, 15.0]),
        real!(Lr, "similarity", similarity, &[4.0, 9.21, 16.0, 30.0]),
        real!(
            Lr,
            "noise_sigma_per_metre",
            noise_sigma_per_metre,
            &[0.0025, 0.005, 0.01]
        ),
        real!(
            Lr,
            "merge_distance_per_metre",
            merge_distance_per_metre,
            &[0.005, 0.01, 0.02]
        ),
        count!(Lr, "min_windows", min_windows, &[1.0, 2.0, 3.0, 5.0]),
        a,
        b,
    ]
};

type Rs = RansacParams;
/// `ransac`.
pub(super) static RANSAC: &[Knob<Rs>] = &{
    let [a, b] = filter!(Rs);
    [
        real!(
            Rs,
            "inlier_distance",
            inlier_distance,
            &[0.01, 0.015, 0.02, 0.03]
        ),
        real!(
            Rs,
            "inlier_distance_per_metre",
            inlier_distance_per_metre,
            &[0.005, 0.01, 0.015, 0.02]
        ),
        count!(
            Rs,
            "min_inliers",
            min_inliers,
            &[5.0, 8.0, 10.0, 15.0, 20.0]
        ),
        count!(Rs, "sample_span", sample_span, &[10.0, 20.0, 30.0, 50.0]),
        count!(Rs, "max_skipped", max_skipped, &[0.0, 1.0, 2.0, 3.0]),
        a,
        b,
    ]
};

/// `em`.
pub(super) static EM: &[Knob<EmParams>] = &{
    let [a, b] = filter!(EmParams);
    [
        real!(
            EmParams,
            "noise_sigma_per_metre",
            noise_sigma_per_metre,
            &[0.0025, 0.005, 0.0075, 0.01]
        ),
        real!(
            EmParams,
            "outlier_density",
            outlier_density,
            &[0.05, 0.2, 1.0, 5.0]
        ),
        real!(
            EmParams,
            "inlier_probability",
            inlier_probability,
            &[0.3, 0.5, 0.7]
        ),
        count!(EmParams, "init_points", init_points, &[5.0, 7.0, 10.0]),
        a,
        b,
    ]
};
