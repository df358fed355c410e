//! A small deterministic pseudo-random number generator: xoshiro256** seeded by splitmix64.
//!
//! The simulator must give the same scan for the same seed on every platform and every
//! version of its dependencies, so it carries its own generator instead of depending on a
//! crate whose streams may change. Both algorithms are the public-domain reference designs
//! of Blackman and Vigna (<https://prng.di.unimi.it/>); they are fast, have a 2^256 - 1
//! period and pass the usual statistical batteries. They are not cryptographic.

use std::f64::consts::TAU;

/// One step of splitmix64: advances `state` and returns the next output.
///
/// Used to expand a 64-bit seed into the 256-bit xoshiro state, and to mix seeds.
#[must_use]
pub fn splitmix64(state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Combines a seed with a stream number into a new, well-mixed seed.
///
/// Used to give every scene of a suite its own generator, so that scene `k` is the same
/// whatever the number of scenes asked for.
#[must_use]
pub fn mix_seed(seed: u64, stream: u64) -> u64 {
    let mut s = seed ^ stream.wrapping_mul(0xD1B5_4A32_D192_ED03);
    let a = splitmix64(&mut s);
    let mut t = a ^ stream;
    splitmix64(&mut t)
}

/// A seeded pseudo-random number generator (xoshiro256**), with uniform and gaussian draws.
///
/// The same seed always gives the same sequence.
///
/// ```
/// use laserlines_sim::Rng;
/// let mut a = Rng::new(7);
/// let mut b = Rng::new(7);
/// assert_eq!(a.uniform().to_bits(), b.uniform().to_bits());
/// let u = a.range(-1.0, 1.0);
/// assert!((-1.0..1.0).contains(&u));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Rng {
    s: [u64; 4],
    /// The second value of the last Box-Muller pair, not yet returned.
    spare: Option<f64>,
}

impl Rng {
    /// A generator seeded with `seed`: the xoshiro256** state is four successive outputs of
    /// splitmix64 started at `seed`, as its authors recommend (never all zero).
    #[must_use]
    pub fn new(seed: u64) -> Self {
        let mut sm = seed;
        let s = [
            splitmix64(&mut sm),
            splitmix64(&mut sm),
            splitmix64(&mut sm),
            splitmix64(&mut sm),
        ];
        Self { s, spare: None }
    }

    /// A generator started from a raw xoshiro256** state (used to check the reference
    /// sequence). An all-zero state would only give zeros, so it is replaced by `new(0)`.
    #[cfg(test)]
    fn from_state(s: [u64; 4]) -> Self {
        if s == [0; 4] {
            return Self::new(0);
        }
        Self { s, spare: None }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        let result = self.s[1].wrapping_mul(5).rotate_left(7).wrapping_mul(9);
        let t = self.s[1] << 17;
        self.s[2] ^= self.s[0];
        self.s[3] ^= self.s[1];
        self.s[1] ^= self.s[2];
        self.s[0] ^= self.s[3];
        self.s[2] ^= t;
        self.s[3] = self.s[3].rotate_left(45);
        result
    }

    /// A uniform draw in `[0, 1)`, with 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A uniform draw between `lo` and `hi`: `lo + (hi - lo) * u` with `u` from
    /// [`Rng::uniform`], so in `[lo, hi)` when `lo < hi` (up to the rounding of that
    /// expression), `lo` when they are equal. Non-finite bounds give non-finite results; no
    /// panic.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// A uniform integer in `0..n` (`0` when `n` is 0).
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            return 0;
        }
        // Lemire's multiply-shift; the bias is below 2^-64 * n, far too small to matter here.
        let wide = u128::from(self.next_u64()) * n as u128;
        (wide >> 64) as usize
    }

    /// True with probability `p` (never for `p <= 0` or NaN, always for `p >= 1`).
    pub fn chance(&mut self, p: f64) -> bool {
        self.uniform() < p
    }

    /// A draw from the standard normal distribution (mean 0, standard deviation 1), by the
    /// Box-Muller transform. Draws come in pairs; the second of a pair is kept for the next
    /// call, so the sequence is deterministic for a seed.
    pub fn gaussian(&mut self) -> f64 {
        if let Some(z) = self.spare.take() {
            return z;
        }
        // u1 in (0, 1], so that ln(u1) is finite.
        let u1 = 1.0 - self.uniform();
        let u2 = self.uniform();
        let radius = (-2.0 * u1.ln()).sqrt();
        let (s, c) = (TAU * u2).sin_cos();
        self.spare = Some(radius * s);
        radius * c
    }

    /// A draw from the normal distribution with the given mean and standard deviation.
    pub fn normal(&mut self, mean: f64, sigma: f64) -> f64 {
        mean + sigma * self.gaussian()
    }

    /// A new generator seeded from this one: an independent stream for a sub-task.
    pub fn fork(&mut self) -> Self {
        Self::new(self.next_u64())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix64_matches_the_reference_sequence() {
        // The reference implementation's outputs for seed 1234567.
        let mut s = 1_234_567u64;
        let got: Vec<u64> = (0..5).map(|_| splitmix64(&mut s)).collect();
        assert_eq!(
            got,
            vec![
                6_457_827_717_110_365_317,
                3_203_168_211_198_807_973,
                9_817_491_932_198_370_423,
                4_593_380_528_125_082_431,
                16_408_922_859_458_223_821,
            ]
        );
    }

    #[test]
    fn xoshiro256starstar_matches_hand_computed_steps() {
        // State [1, 2, 3, 4]: first output rotl(2 * 5, 7) * 9 = 1280 * 9 = 11520; after one
        // step s[1] = 2 ^ (3 ^ 1) = 0, so the second output is 0.
        let mut r = Rng::from_state([1, 2, 3, 4]);
        assert_eq!(r.next_u64(), 11_520);
        assert_eq!(r.next_u64(), 0);
        assert_eq!(Rng::from_state([0; 4]), Rng::new(0));
    }

    #[test]
    fn same_seed_same_sequence_different_seed_different() {
        let mut a = Rng::new(42);
        let mut b = Rng::new(42);
        let mut c = Rng::new(43);
        let sa: Vec<u64> = (0..16).map(|_| a.next_u64()).collect();
        let sb: Vec<u64> = (0..16).map(|_| b.next_u64()).collect();
        let sc: Vec<u64> = (0..16).map(|_| c.next_u64()).collect();
        assert_eq!(sa, sb);
        assert_ne!(sa, sc);
    }

    #[test]
    fn uniform_is_in_unit_interval_with_the_right_moments() {
        let mut r = Rng::new(1);
        let n = 200_000;
        let mut sum = 0.0;
        let mut sum2 = 0.0;
        for _ in 0..n {
            let u = r.uniform();
            assert!((0.0..1.0).contains(&u));
            sum += u;
            sum2 += u * u;
        }
        let mean = sum / n as f64;
        let var = sum2 / n as f64 - mean * mean;
        assert!((mean - 0.5).abs() < 0.005, "mean {mean}");
        assert!((var - 1.0 / 12.0).abs() < 0.002, "variance {var}");
    }

    #[test]
    fn range_below_and_chance_stay_in_bounds() {
        let mut r = Rng::new(5);
        let mut seen = [false; 7];
        let mut hits = 0;
        for _ in 0..10_000 {
            let x = r.range(-2.0, 3.0);
            assert!((-2.0..3.0).contains(&x));
            let k = r.below(7);
            assert!(k < 7);
            seen[k] = true;
            if r.chance(0.25) {
                hits += 1;
            }
        }
        assert!(seen.iter().all(|s| *s));
        assert!((2300..2700).contains(&hits), "hits {hits}");
        assert_eq!(r.below(0), 0);
        assert!(!r.chance(0.0) && !r.chance(f64::NAN) && r.chance(1.0));
        assert!((r.range(1.5, 1.5) - 1.5).abs() < 1e-15);
    }

    #[test]
    fn gaussian_has_zero_mean_unit_sigma_and_normal_tails() {
        let mut r = Rng::new(9);
        let n = 200_000;
        let xs: Vec<f64> = (0..n).map(|_| r.gaussian()).collect();
        assert!(xs.iter().all(|x| x.is_finite()));
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1) as f64;
        assert!(mean.abs() < 0.01, "mean {mean}");
        assert!((var.sqrt() - 1.0).abs() < 0.01, "sigma {}", var.sqrt());
        // P(|z| > 2) = 4.55 %.
        let beyond2 = xs.iter().filter(|x| x.abs() > 2.0).count() as f64 / n as f64;
        assert!((beyond2 - 0.0455).abs() < 0.003, "tail {beyond2}");
    }

    #[test]
    fn mixed_seeds_differ_per_stream() {
        assert_ne!(mix_seed(1, 0), mix_seed(1, 1));
        assert_ne!(mix_seed(1, 0), mix_seed(2, 0));
        assert_eq!(mix_seed(3, 4), mix_seed(3, 4));
        let mut f = Rng::new(3);
        let mut g = f.fork();
        assert_ne!(f.next_u64(), g.next_u64());
    }
}
