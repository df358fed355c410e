//! The one table of extractors: for every algorithm its name, what it is, its parameters'
//! defaults and presets, its constructor and its tuning knobs. The command line, the
//! evaluation (`laserlines bench`, `--tune`) and every other front end find extractors here,
//! by name, so that an algorithm is listed once.
//!
//! Entries are [`Algorithm`]s typed by their params struct. Code that needs the params type
//! (to read a table of a params file with serde, to tune knobs) implements [`Visitor`] and
//! calls [`visit`] with a name; code that only needs an extractor calls [`by_name`] or
//! [`build`].
//!
//! ```
//! use laserlines::registry::{self, ALGORITHMS, Algorithm, Params, Visitor};
//! assert_eq!(ALGORITHMS[0], "hough-split");
//! // How many knobs each algorithm has, through its typed entry.
//! struct CountKnobs;
//! impl Visitor for CountKnobs {
//!     type Output = usize;
//!     fn visit<P: Params>(self, algorithm: &'static Algorithm<P>) -> usize {
//!         algorithm.knobs.len()
//!     }
//! }
//! assert_eq!(registry::visit("ransac", CountKnobs), Some(7));
//! assert!(registry::visit("no-such-algorithm", CountKnobs).is_none());
//! let e = registry::by_name("iepf").unwrap();
//! assert_eq!(e.name(), "iepf");
//! ```

mod knobs;

use std::fmt::Debug;

use crate::extractor::LineExtractor;
use crate::extractors::{
    Em, EmParams, Incremental, IncrementalParams, IterativeHough, IterativeHoughParams,
    LineRegression, LineRegressionParams, Ransac, RansacParams, SplitLine, SplitMerge,
    SplitMergeParams,
};
use crate::hough_split::{HoughSplit, HoughSplitParams};
use crate::params::ParamsError;

/// A boxed extractor, as the registry builds them.
pub type BoxedExtractor = Box<dyn LineExtractor + Send>;

/// One tunable parameter of a params struct `P`: a number (or a count) with the values a
/// search tries.
#[derive(Clone, Copy)]
pub struct Knob<P> {
    /// The parameter's path as a params file writes it (`split_distance`,
    /// `breakpoints.incidence`).
    pub name: &'static str,
    /// Candidate values (counts as whole numbers, angles in rad, distances in m).
    pub values: &'static [f64],
    /// True for a count.
    pub integer: bool,
    /// Reads the parameter.
    pub get: fn(&P) -> f64,
    /// Sets the parameter (a count rounded, at least 0).
    pub set: fn(&mut P, f64),
}

impl<P> Debug for Knob<P> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Knob")
            .field("name", &self.name)
            .field("values", &self.values)
            .field("integer", &self.integer)
            .finish_non_exhaustive()
    }
}

/// Serialize and Deserialize with the `serde` feature, nothing without it: the bound every
/// params struct meets.
#[cfg(feature = "serde")]
pub trait SerdeParams: serde::Serialize + serde::de::DeserializeOwned {}
#[cfg(feature = "serde")]
impl<T: serde::Serialize + serde::de::DeserializeOwned> SerdeParams for T {}
/// Serialize and Deserialize with the `serde` feature, nothing without it: the bound every
/// params struct meets.
#[cfg(not(feature = "serde"))]
pub trait SerdeParams {}
#[cfg(not(feature = "serde"))]
impl<T> SerdeParams for T {}

/// A named preset: a name and the parameters it stands for.
pub type Preset<P> = (&'static str, fn() -> P);

/// What every params struct of the registry is.
pub trait Params: Clone + Debug + PartialEq + Send + Sync + 'static + SerdeParams {}
impl<T: Clone + Debug + PartialEq + Send + Sync + 'static + SerdeParams> Params for T {}

/// One extractor of the registry.
pub struct Algorithm<P: 'static> {
    /// Its name, as [`LineExtractor::name`] gives it.
    pub name: &'static str,
    /// What it is, in one line.
    pub summary: &'static str,
    /// The parameters a params file's table starts from.
    pub defaults: fn() -> P,
    /// Named alternatives to the defaults: a table with `NAME = true` starts from the
    /// preset instead (`paper` for `hough-split`).
    pub presets: &'static [Preset<P>],
    /// The extractor with validated parameters.
    pub build: fn(P) -> Result<BoxedExtractor, ParamsError>,
    /// The knobs `laserlines bench --tune` searches: parameters that shape the result, never
    /// work budgets, spanning each parameter's sensible range.
    pub knobs: &'static [Knob<P>],
    /// Multiplies every distance threshold that stands for the sensor's range noise by `k`,
    /// so that an extractor whose defaults were chosen for the URG-04LX ([`TUNED_NOISE`]) can
    /// be given another sensor's noise, `k = sigma / sigma_tuned` ([`noise_scale`]). A no-op
    /// for `hough-split`, which takes its noise model itself.
    pub scale_noise: fn(&mut P, f64),
}

/// The range noise the classic extractors' defaults were chosen for: the simulated URG-04LX
/// (its data sheet's band read as two standard deviations, `max(5 mm, 0.5 % of the range)`).
pub const TUNED_NOISE: crate::RangeNoise = crate::RangeNoise::new(0.005, 0.005);

/// The factor by which [`Algorithm::scale_noise`] turns thresholds chosen for
/// [`TUNED_NOISE`] into thresholds for `noise`: the ratio of their standard deviations at
/// 2 m, a typical range of the walls the thresholds apply to.
#[must_use]
pub fn noise_scale(noise: &crate::RangeNoise) -> f64 {
    noise.sigma(2.0) / TUNED_NOISE.sigma(2.0)
}

impl<P> Debug for Algorithm<P> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Algorithm")
            .field("name", &self.name)
            .field("summary", &self.summary)
            .finish_non_exhaustive()
    }
}

impl<P: Params> Algorithm<P> {
    /// The extractor with its default parameters.
    ///
    /// # Errors
    /// A [`ParamsError`] when the defaults are invalid (a defect: tested for every entry).
    pub fn build_default(&self) -> Result<BoxedExtractor, ParamsError> {
        (self.build)((self.defaults)())
    }

    /// The preset called `name`, if any.
    #[must_use]
    pub fn preset(&self, name: &str) -> Option<P> {
        self.presets
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, make)| make())
    }
}

fn boxed<E: LineExtractor + Send + 'static>(
    e: Result<E, impl Into<ParamsError>>,
) -> Result<BoxedExtractor, ParamsError> {
    e.map(|e| Box::new(e) as BoxedExtractor).map_err(Into::into)
}

/// The paper's extractor.
pub static HOUGH_SPLIT: Algorithm<HoughSplitParams> = Algorithm {
    name: "hough-split",
    summary: "the paper's g-weighted Hough transform, data segments and recursive split",
    defaults: HoughSplitParams::default,
    presets: &[
        ("paper", HoughSplitParams::paper),
        ("navigation", HoughSplitParams::navigation),
        ("walls", HoughSplitParams::walls),
        ("complete", HoughSplitParams::complete),
    ],
    build: |p| boxed(HoughSplit::new(p)),
    knobs: knobs::HOUGH_SPLIT,
    scale_noise: |_, _| {},
};

/// Iterative Hough on the full accumulator.
pub static ITERATIVE_HOUGH: Algorithm<IterativeHoughParams> = Algorithm {
    name: "iterative-hough",
    summary: "full Hough accumulator: take the peak, fit its inliers, remove them, repeat",
    defaults: IterativeHoughParams::default,
    presets: &[],
    build: |p| boxed(IterativeHough::new(p)),
    knobs: knobs::ITERATIVE_HOUGH,
    scale_noise: |p, k| {
        p.inlier_distance *= k;
        p.inlier_distance_per_metre *= k;
        p.breakpoints.noise *= k;
    },
};

/// Split-and-merge on breakpoint clusters.
pub static SPLIT_AND_MERGE: Algorithm<SplitMergeParams> = Algorithm {
    name: "split-and-merge",
    summary: "breakpoint clusters, recursive split on the least-squares line, collinear merge",
    defaults: SplitMergeParams::split_and_merge,
    presets: &[],
    build: |p| boxed(SplitMerge::new(SplitLine::LeastSquares, p)),
    knobs: knobs::SPLIT_MERGE,
    scale_noise: |p, k| {
        p.split_distance *= k;
        p.split_distance_per_metre *= k;
        p.breakpoints.noise *= k;
    },
};

/// Iterative end-point fit on breakpoint clusters.
pub static IEPF: Algorithm<SplitMergeParams> = Algorithm {
    name: "iepf",
    summary: "breakpoint clusters, recursive split on the chord (Linseg without the Hough stage)",
    defaults: SplitMergeParams::iepf,
    presets: &[],
    build: |p| boxed(SplitMerge::new(SplitLine::Chord, p)),
    knobs: knobs::SPLIT_MERGE,
    scale_noise: |p, k| {
        p.split_distance *= k;
        p.split_distance_per_metre *= k;
        p.breakpoints.noise *= k;
    },
};

/// Incremental line tracking.
pub static INCREMENTAL: Algorithm<IncrementalParams> = Algorithm {
    name: "incremental",
    summary: "line tracking: grow a line point by point while the fit holds",
    defaults: IncrementalParams::default,
    presets: &[],
    build: |p| boxed(Incremental::new(p)),
    knobs: knobs::INCREMENTAL,
    scale_noise: |p, k| {
        p.track_distance *= k;
        p.track_distance_per_metre *= k;
        p.breakpoints.noise *= k;
    },
};

/// Line regression.
pub static LINE_REGRESSION: Algorithm<LineRegressionParams> = Algorithm {
    name: "line-regression",
    summary: "sliding-window fits clustered in (r, alpha) space (Arras and Siegwart)",
    defaults: LineRegressionParams::default,
    presets: &[],
    build: |p| boxed(LineRegression::new(p)),
    knobs: knobs::LINE_REGRESSION,
    scale_noise: |p, k| {
        p.noise_sigma *= k;
        p.noise_sigma_per_metre *= k;
        p.merge_distance *= k;
        p.merge_distance_per_metre *= k;
        p.breakpoints.noise *= k;
    },
};

/// Seeded RANSAC.
pub static RANSAC: Algorithm<RansacParams> = Algorithm {
    name: "ransac",
    summary: "seeded random sampling with minimum inliers and consistent runs",
    defaults: RansacParams::default,
    presets: &[],
    build: |p| boxed(Ransac::new(p)),
    knobs: knobs::RANSAC,
    scale_noise: |p, k| {
        p.inlier_distance *= k;
        p.inlier_distance_per_metre *= k;
        p.breakpoints.noise *= k;
    },
};

/// Seeded expectation-maximisation.
pub static EM: Algorithm<EmParams> = Algorithm {
    name: "em",
    summary: "expectation-maximisation of line hypotheses against an outlier class",
    defaults: EmParams::default,
    presets: &[],
    build: |p| boxed(Em::new(p)),
    knobs: knobs::EM,
    scale_noise: |p, k| {
        p.noise_sigma *= k;
        p.noise_sigma_per_metre *= k;
        p.breakpoints.noise *= k;
    },
};

/// Code that needs an algorithm's params type: called by [`visit`] with the entry.
pub trait Visitor {
    /// What the visit gives.
    type Output;
    /// Called with the entry of the algorithm named in [`visit`].
    fn visit<P: Params>(self, algorithm: &'static Algorithm<P>) -> Self::Output;
}

/// The registry itself: every entry once, the paper's first. [`ALGORITHMS`] and [`visit`]
/// are generated from this one list.
macro_rules! registry {
    ($($entry:ident),* $(,)?) => {
        /// The names of every extractor, the paper's first.
        pub const ALGORITHMS: &[&str] = &[$($entry.name),*];

        /// Calls `visitor` with the entry of the algorithm called `name`; `None` for an
        /// unknown name.
        pub fn visit<V: Visitor>(name: &str, visitor: V) -> Option<V::Output> {
            $(
                if name == $entry.name {
                    return Some(visitor.visit(&$entry));
                }
            )*
            None
        }
    };
}

registry!(
    HOUGH_SPLIT,
    ITERATIVE_HOUGH,
    SPLIT_AND_MERGE,
    IEPF,
    INCREMENTAL,
    LINE_REGRESSION,
    RANSAC,
    EM,
);

/// The names of the presets of the algorithm called `name` (empty when it has none), or
/// `None` for an unknown name.
#[must_use]
pub fn presets(name: &str) -> Option<Vec<&'static str>> {
    struct Names;
    impl Visitor for Names {
        type Output = Vec<&'static str>;
        fn visit<P: Params>(self, algorithm: &'static Algorithm<P>) -> Vec<&'static str> {
            algorithm.presets.iter().map(|(n, _)| *n).collect()
        }
    }
    visit(name, Names)
}

/// The summary of the algorithm called `name`.
#[must_use]
pub fn summary(name: &str) -> Option<&'static str> {
    struct Summary;
    impl Visitor for Summary {
        type Output = &'static str;
        fn visit<P: Params>(self, algorithm: &'static Algorithm<P>) -> &'static str {
            algorithm.summary
        }
    }
    visit(name, Summary)
}

/// The extractor called `name` with its default parameters.
///
/// # Errors
/// `None` for an unknown name; `Some(Err)` only if the defaults were invalid.
#[must_use]
pub fn build(name: &str) -> Option<Result<BoxedExtractor, ParamsError>> {
    struct Default;
    impl Visitor for Default {
        type Output = Result<BoxedExtractor, ParamsError>;
        fn visit<P: Params>(self, algorithm: &'static Algorithm<P>) -> Self::Output {
            algorithm.build_default()
        }
    }
    visit(name, Default)
}

/// The extractor called `name` (one of [`ALGORITHMS`]) with its default parameters, or `None`
/// for an unknown name.
#[must_use]
pub fn by_name(name: &str) -> Option<BoxedExtractor> {
    build(name)?.ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_builds_and_reports_itself() {
        for name in ALGORITHMS {
            let e = by_name(name).unwrap();
            assert_eq!(e.name(), *name);
            assert!(summary(name).is_some_and(|s| !s.is_empty()));
        }
        assert!(by_name("no-such-algorithm").is_none());
        assert_eq!(ALGORITHMS.len(), 8);
        assert_eq!(HOUGH_SPLIT.preset("paper"), Some(HoughSplitParams::paper()));
        assert_eq!(
            presets("hough-split"),
            Some(vec!["paper", "navigation", "walls", "complete"])
        );
        assert_eq!(presets("iepf"), Some(vec![]));
        assert_eq!(presets("no-such-algorithm"), None);
        assert!(HOUGH_SPLIT.preset("none").is_none());
    }

    /// Every knob reads and writes its own field: setting a candidate value reads it back,
    /// and changes nothing else of the parameters' debug form but that field.
    #[test]
    fn knobs_read_and_write_their_field() {
        struct Check;
        impl Visitor for Check {
            type Output = ();
            fn visit<P: Params>(self, algorithm: &'static Algorithm<P>) {
                let start = (algorithm.defaults)();
                let mut names = Vec::new();
                for knob in algorithm.knobs {
                    assert!(!names.contains(&knob.name), "{}", knob.name);
                    names.push(knob.name);
                    for &v in knob.values {
                        let mut p = start.clone();
                        (knob.set)(&mut p, v);
                        assert_eq!((knob.get)(&p), v, "{} {}", algorithm.name, knob.name);
                        assert!((algorithm.build)(p).is_ok(), "{}", knob.name);
                    }
                }
            }
        }
        for name in ALGORITHMS {
            visit(name, Check);
        }
    }
}
