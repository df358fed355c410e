//! The far ends of a scan's samples: all of them beyond 1 m, 1.25 m, 1.5 m, 1.75 m, 2 m,
//! 2.5 m, 3 m and so on (each octave of range in four equal quarters), each read for a step
//! of the noise with range
//! ([`super::envelope::fit_lower_envelope`]).
//!
//! A band of the estimate is an octave of range, and a step inside one (a URG-04LX at 4 mm to
//! 3 m and 1 % beyond, in the band of 2-4 m) leaves the band's median and lower quartile with
//! the near noise. The samples beyond the step are one of these far ends. Their medians and
//! lower quartiles are read from histograms of `|e|` in eighths of an octave (at most 12.5 %
//! apart, the rank interpolated within the step), so that reading every far end costs a few
//! passes over 96 counts rather than a selection per far end.

use super::envelope::{FarEnd, MEDIAN_TO_SIGMA, QUARTILE_TO_SIGMA, margin};
use super::estimator::MIN_POOLED_SAMPLES;

/// Quarter octaves of range from 1 m where far ends start (the last, from 56 m, open).
pub(super) const QUARTERS: usize = 24;

/// Steps of a histogram of `|e|`: eighths of an octave from `2^LOWEST` m (61 um; the first
/// step holds every residual below 69 um) to the last, from 234 mm, which holds the larger
/// ones.
const STEPS: usize = 96;

/// The octave of `|e|` where the histograms start, `2^LOWEST` m.
const LOWEST: i64 = -14;

/// The far ends' samples, counted per quarter octave of range.
#[derive(Debug, Clone, Default)]
pub(super) struct Tails {
    /// Per quarter octave, its samples per step of `|e|` (`QUARTERS` rows of `STEPS`).
    counts: Vec<u32>,
    /// Samples per quarter octave.
    samples: [u32; QUARTERS],
    /// Sum of the ranges of each quarter octave's samples, m.
    range_sum: [f64; QUARTERS],
}

/// The quarter octave from 1 m of range `r >= 1`: `4 floor(log2 r)` plus the top two bits of
/// its mantissa, clamped to the last.
#[inline]
fn quarter_of(r: f64) -> usize {
    // The exponent and the top two bits of the mantissa, read as one number (the sign bit
    // is 0), from the exponent of 1 on: `4 octave + quarter`.
    let q = (r.to_bits() >> 50).saturating_sub(1023 << 2);
    q.min(QUARTERS as u64 - 1) as usize
}

/// The step of a residual `|e|`: eighths of its octave from `2^LOWEST`, clamped.
#[inline]
fn step_of(e: f64) -> usize {
    // As in `quarter_of`, with three bits of the mantissa: `8 (octave - LOWEST) + eighth`
    // (the sign bit cleared, so that -0 is 0).
    let s = ((e.to_bits() << 1) >> 50).saturating_sub(((1023 + LOWEST) as u64) << 3);
    s.min(STEPS as u64 - 1) as usize
}

/// `2^k` for `k` from `LOWEST` to 0, built from its exponent bits.
#[inline]
fn pow2(k: i64) -> f64 {
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// The `ranks[0]`-th and `ranks[1]`-th smallest (from 0, in order) of the `|e|` counted in
/// `hist`, each interpolated within its step: the step's lower end plus its width times the
/// share of its counts below the rank and half of its own; 0 in the first step, whose
/// residuals (below 69 um) are finer than any scanner's noise.
fn quantiles(hist: &[u32; STEPS], ranks: [usize; 2]) -> [f64; 2] {
    let mut out = [0.0; 2];
    let mut k = 0;
    let mut below = 0usize;
    for (i, &c) in hist.iter().enumerate() {
        let c = c as usize;
        while k < 2 && below + c > ranks[k] {
            let share = ((ranks[k] - below) as f64 + 0.5) / c as f64;
            out[k] = if i == 0 {
                0.0
            } else {
                pow2((i / 8) as i64 + LOWEST) * (1.0 + ((i % 8) as f64 + share) / 8.0)
            };
            k += 1;
        }
        if k == 2 {
            break;
        }
        below += c;
    }
    out
}

impl Tails {
    /// Forgets the samples of the last scan (clearing only the rows it touched).
    pub(super) fn clear(&mut self) {
        if self.counts.len() != QUARTERS * STEPS {
            self.counts = vec![0; QUARTERS * STEPS];
        }
        for (row, n) in self.counts.chunks_exact_mut(STEPS).zip(&mut self.samples) {
            if *n > 0 {
                row.fill(0);
                *n = 0;
            }
        }
        self.range_sum = [0.0; QUARTERS];
    }

    /// Counts the residual `e` of a sample at range `r` (from 1 m; nearer ones are no far end's).
    #[inline]
    pub(super) fn push(&mut self, r: f64, e: f64) {
        if r >= 1.0 {
            let q = quarter_of(r);
            self.counts[q * STEPS + step_of(e)] += 1;
            self.samples[q] += 1;
            self.range_sum[q] += r;
        }
    }

    /// Appends to `out` every far end with [`MIN_POOLED_SAMPLES`] samples or more, from the
    /// farthest: the smaller of its median's and lower quartile's sigma lowered by its
    /// margin, and its mean range.
    pub(super) fn read(&self, out: &mut Vec<FarEnd>) {
        let mut hist = [0u32; STEPS];
        let (mut n, mut range_sum) = (0usize, 0.0);
        for q in (0..QUARTERS).rev() {
            if self.samples[q] == 0 {
                continue;
            }
            let row = &self.counts[q * STEPS..(q + 1) * STEPS];
            for (h, &c) in hist.iter_mut().zip(row) {
                *h += c;
            }
            n += self.samples[q] as usize;
            range_sum += self.range_sum[q];
            if n >= MIN_POOLED_SAMPLES {
                let [quartile, median] = quantiles(&hist, [n / 2 / 2, n / 2]);
                let (median, quartile) = (median * MEDIAN_TO_SIGMA, quartile * QUARTILE_TO_SIGMA);
                out.push(FarEnd {
                    low: median.min(quartile) * (1.0 - margin(n)),
                    range: range_sum / n as f64,
                });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarters_and_steps_are_read_from_the_bits() {
        for (r, q) in [
            (1.0, 0),
            (1.24, 0),
            (1.25, 1),
            (1.99, 3),
            (2.0, 4),
            (3.0, 6),
            (3.5, 7),
        ] {
            assert_eq!(quarter_of(r), q, "{r}");
        }
        assert_eq!(quarter_of(55.9), QUARTERS - 2);
        assert_eq!(quarter_of(56.0), QUARTERS - 1);
        assert_eq!(quarter_of(1e9), QUARTERS - 1);
        assert_eq!(step_of(0.0), 0);
        assert_eq!(step_of(-0.0), 0);
        assert_eq!(step_of(pow2(LOWEST) * 1.125), 1);
        assert_eq!(step_of(0.2343), STEPS - 2);
        assert_eq!(step_of(0.234_375), STEPS - 1);
        assert_eq!(step_of(1e-9), 0);
        assert_eq!(step_of(1.0), STEPS - 1);
        // 4 mm is 2^-8 (3.9 mm) and 3/128 of it: octave 6 from 2^-14 (counted from 0), its
        // first eighth.
        assert_eq!(step_of(0.004), 6 * 8);
        assert_eq!(step_of(0.0045), 6 * 8 + 1);
    }

    #[test]
    fn quantiles_of_a_histogram_lie_within_their_step() {
        let mut tails = Tails::default();
        tails.clear();
        // 100 residuals from 1 to 100 mm at 2 m, and 30 of 0.1 mm at 1.1 m.
        for k in 1..=100 {
            tails.push(2.0, f64::from(k) * 1e-3);
        }
        for _ in 0..30 {
            tails.push(1.1, 1e-4);
        }
        let mut out = Vec::new();
        tails.read(&mut out);
        assert_eq!(out.len(), 2, "{out:?}");
        // The far end from 2 m: median 51 mm, lower quartile 26 mm (rank 25 of 0..100).
        let m = 0.051 * MEDIAN_TO_SIGMA;
        let q = 0.026 * QUARTILE_TO_SIGMA;
        let want = m.min(q) * (1.0 - margin(100));
        assert!(
            (out[0].low / want - 1.0).abs() < 0.07,
            "{:?} {want}",
            out[0]
        );
        assert!((out[0].range - 2.0).abs() < 1e-12);
        // From 1 m: 130 samples, of which 30 at 0.1 mm.
        assert!((out[1].range - (200.0 + 33.0) / 130.0).abs() < 1e-9);
        assert!(out[1].low < out[0].low);
        // Residuals finer than the first step's 69 um read as nothing.
        let mut fine = Tails::default();
        fine.clear();
        for _ in 0..20 {
            fine.push(2.0, 1e-9);
        }
        let mut none = Vec::new();
        fine.read(&mut none);
        assert_eq!(none.len(), 1);
        assert!(none[0].low == 0.0, "{none:?}");
        // Cleared, nothing is read.
        tails.clear();
        out.clear();
        tails.read(&mut out);
        assert!(out.is_empty());
    }
}
