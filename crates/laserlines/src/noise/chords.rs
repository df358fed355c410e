//! The geometry of a sparse scan's triples (see `NoiseEstimator::sample_sparse`): for beams
//! `k0` and `k1` steps apart, the sines and factors that predict the middle range on the
//! chord of the outer two. They depend only on the two gaps and the beam increment, so they
//! are computed once per scan shape and kept between scans.

/// What a triple of gaps `(k0, k1)` needs.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Pair {
    /// `sin(a + b)`, `a = k0 inc`, `b = k1 inc`.
    pub(super) sin_ab: f64,
    /// `sin a`.
    pub(super) sin_a: f64,
    /// `sin b`.
    pub(super) sin_b: f64,
    /// The largest relative difference of the outer ranges on one smooth surface.
    pub(super) spread: f64,
    /// Scales the residual to the variance of an evenly spaced triple's.
    pub(super) scale: f64,
}

impl Pair {
    /// The factors for gaps of `k0` and `k1` beams of `inc` rad.
    fn new(k0: usize, k1: usize, inc: f64) -> Self {
        let (a, b) = (k0 as f64 * inc, k1 as f64 * inc);
        let ab = a + b;
        Self {
            sin_ab: ab.sin(),
            sin_a: a.sin(),
            sin_b: b.sin(),
            spread: 6.0 * ab + 0.1,
            scale: (1.5 / (1.0 + (a * a + b * b) / (ab * ab))).sqrt(),
        }
    }
}

/// [`Pair`] for every two gaps of 1 to `max_gap` beams, for one increment.
#[derive(Debug, Clone, Default)]
pub(super) struct Chords {
    /// The increment (rad) the table holds (`None` before the first sparse scan).
    inc: Option<f64>,
    max_gap: usize,
    /// `pairs[(k0 - 1) * max_gap + k1 - 1]`.
    pairs: Vec<Pair>,
}

impl Chords {
    /// Makes the table hold `inc` and `max_gap` (recomputed only when either changed).
    pub(super) fn prepare(&mut self, inc: f64, max_gap: usize) {
        if self.inc.map(f64::to_bits) == Some(inc.to_bits()) && self.max_gap == max_gap {
            return;
        }
        self.inc = Some(inc);
        self.max_gap = max_gap;
        self.pairs.clear();
        for k0 in 1..=max_gap {
            for k1 in 1..=max_gap {
                self.pairs.push(Pair::new(k0, k1, inc));
            }
        }
    }

    /// The factors of gaps `k0` and `k1`, each in `1..=max_gap` of the last
    /// [`Chords::prepare`].
    #[inline]
    pub(super) fn pair(&self, k0: usize, k1: usize) -> Pair {
        self.pairs[(k0 - 1) * self.max_gap + (k1 - 1)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_table_holds_the_factors_of_each_pair_of_gaps() {
        let inc = 0.85_f64.to_radians();
        let mut c = Chords::default();
        c.prepare(inc, 3);
        let p = c.pair(1, 3);
        let (a, b) = (inc, 3.0 * inc);
        assert_eq!(p.sin_ab, (a + b).sin());
        assert_eq!(p.sin_a, a.sin());
        assert_eq!(p.sin_b, b.sin());
        assert_eq!(p.spread, 6.0 * (a + b) + 0.1);
        // Evenly spaced: (a^2 + b^2) / (a + b)^2 = 1/2, so the scale is 1.
        assert!((c.pair(2, 2).scale - 1.0).abs() < 1e-12);
        // A new increment replaces the table.
        c.prepare(2.0 * inc, 3);
        assert_eq!(c.pair(1, 1).sin_a, (2.0 * inc).sin());
    }
}
