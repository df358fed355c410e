//! What the simulated laser reports of the true ranges: gaussian range noise drawn by a
//! ziggurat sampler, mixed pixels at depth edges, dropouts, rounding to the resolution, the
//! range limits and max-range returns (see [`crate::LaserModel`]).

use crate::laser::{LaserModel, Noise};
use crate::rng::Rng;
use crate::simulation::MIXED_PIXEL_MIN_JUMP;
use crate::world::Target;

/// Flag of a beam that hit nothing within range.
pub(crate) const NO_HIT: u8 = 1;
/// Flag of a beam turned into a mixed pixel.
const MIXED: u8 = 2;
/// Flag of a beam dropped.
const DROPPED: u8 = 4;

/// The ranges the laser reports, from the noise-free `true_ranges` (NaN where nothing was
/// hit), the target of each beam and its flags (`NO_HIT` set where nothing was hit), drawing
/// from `rng`; `range_max` is the model's limit (-1 for NaN).
pub(crate) fn report(
    model: &LaserModel,
    rng: &mut Rng,
    true_ranges: &[f64],
    targets: &[Option<Target>],
    flags: &mut [u8],
    ranges: &mut Vec<f64>,
    range_max: f64,
) {
    ranges.clear();
    ranges.extend_from_slice(true_ranges);
    for r in ranges.iter_mut() {
        if r.is_finite() {
            let sigma = model.noise.sigma(*r);
            if sigma > 0.0 {
                *r += sigma * standard_normal(rng);
            }
        }
    }
    if model.mixed_pixels > 0.0 {
        mixed_pixels(model, rng, true_ranges, targets, flags, ranges);
    }
    if model.dropout > 0.0 {
        for (i, r) in ranges.iter_mut().enumerate() {
            if r.is_finite() && rng.chance(model.dropout) {
                *r = f64::NAN;
                flags[i] |= DROPPED;
            }
        }
    }
    if matches!(model.noise, Noise::Depth { step, .. } if step > 0.0) {
        for r in ranges.iter_mut() {
            *r = model.noise.quantize(*r);
        }
    }
    let step = model.round_to.filter(|q| q.is_finite() && *q > 0.0);
    if let Some(q) = step {
        let per_step = 1.0 / q;
        for r in ranges.iter_mut() {
            *r = round_half_away(*r * per_step) * q;
        }
    }
    // Measurable: positive, within the limits, finite (NaN fails every comparison).
    let lowest = model.range_min.max(f64::MIN_POSITIVE);
    for r in ranges.iter_mut() {
        if !(*r >= lowest && *r <= range_max && *r < f64::INFINITY) {
            *r = f64::NAN;
        }
    }
    if model.max_range_returns {
        for (r, &f) in ranges.iter_mut().zip(flags.iter()) {
            if f & NO_HIT != 0 && f & DROPPED == 0 {
                *r = model.range_max;
            }
        }
    }
}

/// At each depth edge between two targets, with the model's probability, one of the two
/// beams reports a range between them.
fn mixed_pixels(
    model: &LaserModel,
    rng: &mut Rng,
    true_ranges: &[f64],
    targets: &[Option<Target>],
    flags: &mut [u8],
    ranges: &mut [f64],
) {
    for i in 1..true_ranges.len() {
        let (ra, rb) = (true_ranges[i - 1], true_ranges[i]);
        let edge = ra.is_finite()
            && rb.is_finite()
            && targets[i - 1] != targets[i]
            && (ra - rb).abs() > MIXED_PIXEL_MIN_JUMP;
        if !edge || flags[i - 1] & MIXED != 0 || !rng.chance(model.mixed_pixels) {
            continue;
        }
        let j = if rng.chance(0.5) { i - 1 } else { i };
        let (near, far) = if ra < rb { (ra, rb) } else { (rb, ra) };
        ranges[j] = near + (far - near) * rng.range(0.05, 0.95);
        flags[j] |= MIXED;
    }
}

/// Layers of the ziggurat.
const ZIGGURAT_LAYERS: usize = 128;
/// The ziggurat's base layer starts at this x (Marsaglia and Tsang's 128-layer value).
const ZIGGURAT_R: f64 = 3.442_619_855_899;
/// The area of each layer (and of the base with its tail).
const ZIGGURAT_V: f64 = 9.912_563_035_262_17e-3;

/// The ziggurat's tables: the layers' right edges `x[0..=128]` (`x[0]` the base's width
/// with its tail folded in, `x[1] = R`, `x[128] = 0`) and the ratios `x[i + 1] / x[i]`.
struct Ziggurat {
    x: [f64; ZIGGURAT_LAYERS + 1],
    ratio: [f64; ZIGGURAT_LAYERS],
}

impl Ziggurat {
    fn new() -> Self {
        let mut x = [0.0; ZIGGURAT_LAYERS + 1];
        let mut f = (-0.5 * ZIGGURAT_R * ZIGGURAT_R).exp();
        x[0] = ZIGGURAT_V / f;
        x[1] = ZIGGURAT_R;
        for i in 2..ZIGGURAT_LAYERS {
            x[i] = (-2.0 * (ZIGGURAT_V / x[i - 1] + f).ln()).sqrt();
            f = (-0.5 * x[i] * x[i]).exp();
        }
        x[ZIGGURAT_LAYERS] = 0.0;
        let mut ratio = [0.0; ZIGGURAT_LAYERS];
        for i in 0..ZIGGURAT_LAYERS {
            ratio[i] = x[i + 1] / x[i];
        }
        Self { x, ratio }
    }
}

/// A draw from the standard normal distribution by the ziggurat method: one draw of the
/// generator and a multiplication nearly always (99 %), a rejection test with two
/// exponentials in the layers' wedges, and the tail beyond `R` by Marsaglia's method.
pub(crate) fn standard_normal(rng: &mut Rng) -> f64 {
    static TABLES: std::sync::OnceLock<Ziggurat> = std::sync::OnceLock::new();
    let z = TABLES.get_or_init(Ziggurat::new);
    loop {
        let bits = rng.next_u64();
        // The layer from the low 7 bits, a signed uniform from the top 53.
        let i = (bits & (ZIGGURAT_LAYERS as u64 - 1)) as usize;
        let u = 2.0 * ((bits >> 11) as f64 * (1.0 / (1_u64 << 53) as f64)) - 1.0;
        if u.abs() < z.ratio[i] {
            return u * z.x[i];
        }
        if i == 0 {
            // The tail beyond R.
            loop {
                let a = (1.0 - rng.uniform()).ln() / ZIGGURAT_R;
                let b = (1.0 - rng.uniform()).ln();
                if -2.0 * b >= a * a {
                    return if u < 0.0 {
                        a - ZIGGURAT_R
                    } else {
                        ZIGGURAT_R - a
                    };
                }
            }
        }
        let x = u * z.x[i];
        let f0 = (-0.5 * (z.x[i] * z.x[i] - x * x)).exp();
        let f1 = (-0.5 * (z.x[i + 1] * z.x[i + 1] - x * x)).exp();
        if f1 + rng.uniform() * (f0 - f1) < 1.0 {
            return x;
        }
    }
}

/// `x.round()` (halves away from zero) without a library call; `x` unchanged when it is
/// not finite or too large to have a fraction.
#[inline]
fn round_half_away(x: f64) -> f64 {
    if x.is_nan() || x.abs() >= 4_503_599_627_370_496.0 {
        return x;
    }
    let t = (x.abs() + 0.5) as i64 as f64;
    // x.abs() + 0.5 may round up just below a half: keep f64::round's answer there.
    let t = if x.abs() < t - 0.5 { t - 1.0 } else { t };
    t.copysign(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use laserlines::math::{ceil_i64, floor_i64};

    #[test]
    fn the_ziggurat_draws_a_standard_normal() {
        let mut rng = Rng::new(21);
        let n = 2_000_000;
        let (mut sum, mut sum2, mut beyond2, mut beyond3, mut beyond4) = (0.0, 0.0, 0, 0, 0);
        let mut positive = 0;
        for _ in 0..n {
            let x = standard_normal(&mut rng);
            assert!(x.is_finite());
            sum += x;
            sum2 += x * x;
            beyond2 += usize::from(x.abs() > 2.0);
            beyond3 += usize::from(x.abs() > 3.0);
            beyond4 += usize::from(x.abs() > 4.0);
            positive += usize::from(x > 0.0);
        }
        let nf = n as f64;
        let mean = sum / nf;
        let var = sum2 / nf - mean * mean;
        assert!(mean.abs() < 0.003, "mean {mean}");
        assert!((var - 1.0).abs() < 0.005, "variance {var}");
        // P(|x| > 2) = 0.0455, P(|x| > 3) = 0.0027, P(|x| > 4) = 6.3e-5.
        let p = |k: usize| k as f64 / nf;
        assert!((p(beyond2) - 0.045_5).abs() < 0.001, "{}", p(beyond2));
        assert!((p(beyond3) - 0.002_70).abs() < 0.000_2, "{}", p(beyond3));
        assert!((p(beyond4) - 6.33e-5).abs() < 2.5e-5, "{}", p(beyond4));
        assert!((p(positive) - 0.5).abs() < 0.002);
    }

    #[test]
    fn fast_rounding_agrees_with_the_library() {
        let mut rng = Rng::new(5);
        let specials = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            2.5,
            -2.5,
            0.499_999_999_999_999_94,
            1e15 + 0.5,
            4_503_599_627_370_495.5,
            1e300,
            -7.000_000_000_000_001,
        ];
        for x in specials
            .into_iter()
            .chain((0..10_000).map(|_| rng.range(-5000.0, 5000.0)))
        {
            assert_eq!(round_half_away(x).to_bits(), x.round().to_bits(), "{x}");
            if x.abs() < 1e15 {
                assert_eq!(floor_i64(x), x.floor() as i64, "{x}");
                assert_eq!(ceil_i64(x), x.ceil() as i64, "{x}");
            }
        }
        assert!(round_half_away(f64::NAN).is_nan());
        assert_eq!(round_half_away(f64::INFINITY), f64::INFINITY);
    }
}
