//! From the samples' residuals to the model: robust sigmas, their margins and the lower
//! envelope `max(sigma_min, fraction r)` of the bands (see the module docs of [`crate::noise`]).

use super::RangeNoise;
use super::estimator::{BandEstimate, MIN_POOLED_SAMPLES};

/// `median |e| / (0.6745 sqrt(1.5))`: the factor from the median absolute residual to sigma.
pub(super) const MEDIAN_TO_SIGMA: f64 = 1.0 / (0.674_489_750_196_081_7 * 1.224_744_871_391_589);

/// `1 / (Phi^-1(5/8) sqrt(1.5))`: the factor from the lower quartile of `|e|` to sigma.
pub(super) const QUARTILE_TO_SIGMA: f64 = 1.0 / (0.318_639_363_964_375_2 * 1.224_744_871_391_589);

/// The largest fraction of the range [`NoiseModel::Auto`](super::NoiseModel::Auto) reports:
/// no 2D laser scanner we know of is noisier than 2 % of the range, and a larger estimate
/// means clutter, not noise.
pub const MAX_AUTO_FRACTION: f64 = 0.02;

/// How far above the lower envelope a band's (or a far end's) estimate must lie, at the low
/// end of its confidence interval, to raise the fraction of the range (see [`crate::noise`]).
pub const STEP_RATIO: f64 = 1.5;

/// Sigma from the lower quartile of samples whose lower half is `v` (not empty; the bits
/// of `|e|`, after [`median_sigma`] put the lower half first): the median of that half.
pub(super) fn quartile_sigma(v: &mut [u64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    let (_, m, _) = v.select_nth_unstable(v.len() / 2);
    f64::from_bits(*m) * QUARTILE_TO_SIGMA
}

/// The relative margin of a band's sigma from `n` samples: 1.5 standard errors of a median
/// (`1.17 / sqrt(n)` relative each).
pub(super) fn margin(n: usize) -> f64 {
    1.75 / (n as f64).sqrt()
}

/// Sigma from the median of the samples `v` (not empty), the bits of `|e|`.
pub(super) fn median_sigma(v: &mut [u64]) -> f64 {
    // The samples are the bits of non-negative floats, which order as the floats.
    let (_, m, _) = v.select_nth_unstable(v.len() / 2);
    f64::from_bits(*m) * MEDIAN_TO_SIGMA
}

/// The far end of a scan's samples (those beyond some range, [`super::tails`]): the low end
/// of its sigma's interval and its mean range, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct FarEnd {
    pub(super) low: f64,
    pub(super) range: f64,
}

/// The largest `max(sigma_min, fraction r)` (with `fraction <= MAX_AUTO_FRACTION`) below
/// the bound of every band with `min_samples` samples or more, at least `floor`; `None`
/// without such a band. A band's bound is its
/// estimate raised by 1.5 standard errors of a median of `n` samples (`1.17 / sqrt(n)`
/// relative), so that a band whose few samples happen to read low does not pull the model
/// down.
///
/// Noise that steps up with range beyond what one fraction describes (a URG-04LX at a few
/// millimetres to 3 m and 1 % beyond) has no such model that fits every band: the envelope
/// then follows the near bands, and far walls, seen through noise three times the model's,
/// failed the RMS limit or broke into pieces. So where a band from 1 m on (with
/// [`MIN_POOLED_SAMPLES`] samples or more) still reads [`STEP_RATIO`] times the model at
/// the low end of its interval (its estimate lowered by 1.75 / sqrt(n), the estimate being
/// the smaller of the median's and the lower quartile's sigma in `low`, so that clutter,
/// which inflates the upper residuals of a band more than its lower ones, raises nothing),
/// the fraction is raised to the smallest such low end over the band's range: the model then
/// errs high on the nearer bands, which costs far less than erring low on the far ones.
///
/// A band is an octave, and a step inside one (at 3 m, in the band of 2-4 m) leaves its
/// median and lower quartile with the near noise. The far ends (`far`: the samples beyond
/// each quarter octave from 1 m, [`super::tails`]) are read the same way, those above 1.5
/// times the floor; where some of them step, the fraction is at least the largest of their
/// low ends over their ranges. A far end that reaches nearer than the step mixes the near
/// noise in and reads low, so the largest is the one beyond the step; each is a low end
/// already, and the far ends only ever raise the bands' figure.
pub(super) fn fit_lower_envelope(
    bands: &[BandEstimate],
    low: &[f64],
    far: &[FarEnd],
    min_samples: usize,
    floor: f64,
) -> Option<RangeNoise> {
    let usable = || {
        bands
            .iter()
            .filter(|b| b.samples >= min_samples)
            .map(|b| BandEstimate {
                sigma: b.sigma * (1.0 + margin(b.samples)),
                ..*b
            })
    };
    let sigma_min = usable().map(|b| b.sigma).reduce(f64::min)?;
    // Bands beyond 1 m bound the growth with range (where a scan has too few far points for
    // a band of their own, the nearer bands' bound is extrapolated: right for the usual
    // noise proportional to range, generous for a constant one).
    let envelope = usable()
        .filter(|b| b.range >= 1.0)
        .map(|b| b.sigma / b.range)
        .reduce(f64::min)
        .unwrap_or(0.0);
    let steps = |it: &mut dyn Iterator<Item = FarEnd>, pick: fn(f64, f64) -> f64| {
        it.filter(|e| e.low > STEP_RATIO * (envelope * e.range).max(sigma_min))
            .map(|e| e.low / e.range)
            .reduce(pick)
    };
    let in_bands = steps(
        &mut bands
            .iter()
            .zip(low)
            .filter(|(b, _)| b.samples >= MIN_POOLED_SAMPLES && b.range >= 1.0)
            .map(|(b, &q)| FarEnd {
                low: b.sigma.min(q) * (1.0 - margin(b.samples)),
                range: b.range,
            }),
        f64::min,
    );
    // A far end's figure is only read above 1.5 times the floor: below it, residuals say
    // nothing.
    let far_ends = steps(
        &mut far.iter().copied().filter(|e| e.low > STEP_RATIO * floor),
        f64::max,
    );
    let stepped = [in_bands, far_ends].into_iter().flatten().reduce(f64::max);
    let fraction = stepped.unwrap_or(envelope).min(MAX_AUTO_FRACTION);
    Some(RangeNoise::new(sigma_min.max(floor), fraction))
}
