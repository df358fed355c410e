//! The ground truth as the evaluation sees it: every visible wall piece of a simulated scan,
//! trimmed to the beams the sensor actually reported, with the standard errors an ideal
//! least-squares fit of its beams would have under the simulated noise.

use laserlines::Scan;
use laserlines::line::beams;
pub use laserlines::line::{beam_span, beams_shared};
use laserlines::math::{Point2, Vector2};
use laserlines_sim::{MIN_PIECE_BEAMS, MIN_PIECE_LENGTH, Noise, SimScan, VisiblePiece};
use serde::Serialize;

/// A visible wall piece, trimmed to its seen beams (see [`expected_pieces`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ExpectedPiece {
    /// Index of the wall in the simulated world.
    pub wall: usize,
    /// First seen beam of the piece.
    pub first: usize,
    /// Last seen beam of the piece (inclusive): below `first` when the piece runs across the
    /// seam of a full turn ([`laserlines::Line`]).
    pub last: usize,
    /// Number of beams of the scan (0 for a hand-made piece, which never runs across a seam).
    pub scan_beams: usize,
    /// Distance of the wall's line from the sensor, m.
    pub r: f64,
    /// Direction of the wall's normal, rad, in `(-pi, pi]`.
    pub alpha: f64,
    /// Noise-free hit point of beam `first`, m, laser frame.
    #[serde(serialize_with = "ser_point")]
    pub start: Point2,
    /// Noise-free hit point of beam `last`, m, laser frame.
    #[serde(serialize_with = "ser_point")]
    pub end: Point2,
    /// True when an extractor must find the piece: at least [`MIN_PIECE_BEAMS`] beams and
    /// [`MIN_PIECE_LENGTH`] metres between its seen ends.
    pub significant: bool,
    /// Standard error of `r` of an ideal least-squares fit of the piece's beams, m.
    pub sigma_r: f64,
    /// Standard error of `alpha` of that fit, rad.
    pub sigma_alpha: f64,
}

fn ser_point<S: serde::Serializer>(p: &Point2, s: S) -> Result<S::Ok, S::Error> {
    [p.x, p.y].serialize(s)
}

impl ExpectedPiece {
    /// A piece with the given beams and geometry and no noise allowance (standard errors 0):
    /// for hand-made cases.
    #[must_use]
    pub fn exact(wall: usize, first: usize, last: usize, start: Point2, end: Point2) -> Self {
        let d = end - start;
        let mut normal = Vector2::new(-d.y, d.x);
        let len = normal.norm();
        if len > 0.0 {
            normal /= len;
        }
        let mut r = normal.dot(&start.coords);
        if r < 0.0 {
            r = -r;
            normal = -normal;
        }
        Self {
            wall,
            first,
            last,
            scan_beams: 0,
            r,
            alpha: normal.y.atan2(normal.x),
            start,
            end,
            significant: beam_span(first, last, 0) >= MIN_PIECE_BEAMS && len >= MIN_PIECE_LENGTH,
            sigma_r: 0.0,
            sigma_alpha: 0.0,
        }
    }

    /// Number of beams from `first` to `last` ([`beam_span`]).
    #[must_use]
    pub fn beams(&self) -> usize {
        beam_span(self.first, self.last, self.scan_beams)
    }

    /// Length between the seen ends, m.
    #[must_use]
    pub fn length(&self) -> f64 {
        (self.end - self.start).norm()
    }
}

/// The visible wall pieces of `sim`, each trimmed to its first and last beam whose reported
/// range is valid (a beam that hit the wall but whose return the noise pushed out of range, or
/// that the sensor dropped, was not seen), with its end points moved to those beams' noise-free
/// hits. Pieces with fewer than two seen beams are left out. `noise` is the simulated range
/// noise, for the standard errors. A piece across the seam of a full turn stays one piece.
#[must_use]
pub fn expected_pieces(sim: &SimScan, noise: &Noise) -> Vec<ExpectedPiece> {
    let window = sim.scan.range_window(None);
    let seen = |i: &usize| sim.scan.ranges.get(*i).is_some_and(|r| window.contains(*r));
    let n = sim.scan.ranges.len();
    let mut out = Vec::with_capacity(sim.truth.pieces.len());
    for piece in &sim.truth.pieces {
        let (Some(first), Some(last)) = (
            beams(piece.first, piece.last, n).find(seen),
            beams(piece.first, piece.last, n).rev().find(seen),
        ) else {
            continue;
        };
        if last == first {
            continue;
        }
        let start = sim.truth.point(&sim.scan, first).unwrap_or(piece.start);
        let end = sim.truth.point(&sim.scan, last).unwrap_or(piece.end);
        let (sigma_r, sigma_alpha) =
            ideal_fit_errors(&sim.scan, &sim.truth.ranges, noise, piece, first, last);
        let length = (end - start).norm();
        out.push(ExpectedPiece {
            wall: piece.wall,
            first,
            last,
            scan_beams: n,
            r: piece.r,
            alpha: piece.alpha,
            start,
            end,
            significant: beam_span(first, last, n) >= MIN_PIECE_BEAMS && length >= MIN_PIECE_LENGTH,
            sigma_r,
            sigma_alpha,
        });
    }
    out
}

/// Standard errors `(r, alpha)` (m, rad) of an ideal least-squares fit of beams
/// `first..=last` (across the seam of a full turn when `last < first`) of `piece`'s wall, whose noise-free ranges are `truth_ranges`, under range
/// noise `noise` (range noise moves a point across the wall by `sigma cos(incidence)`).
/// Infinite when the beams cannot determine the line.
#[must_use]
pub fn ideal_fit_errors(
    scan: &Scan,
    truth_ranges: &[f64],
    noise: &Noise,
    piece: &VisiblePiece,
    first: usize,
    last: usize,
) -> (f64, f64) {
    let n_hat = Vector2::new(piece.alpha.cos(), piece.alpha.sin());
    let dir = Vector2::new(-piece.alpha.sin(), piece.alpha.cos());
    // (position along the wall, standard deviation across it)
    let n = truth_ranges.len();
    let mut pts: Vec<(f64, f64)> = Vec::with_capacity(beam_span(first, last, n));
    for i in beams(first, last, n) {
        let Some(&range) = truth_ranges.get(i) else {
            break;
        };
        if !range.is_finite() {
            continue;
        }
        let (s, c) = scan.angle(i).sin_cos();
        let beam = Vector2::new(c, s);
        let across = noise.sigma(range) * beam.dot(&n_hat).abs();
        pts.push(((beam * range).dot(&dir), across));
    }
    if pts.len() < 2 {
        return (f64::INFINITY, f64::INFINITY);
    }
    let n = pts.len() as f64;
    let t_mean = pts.iter().map(|(t, _)| t).sum::<f64>() / n;
    let stt: f64 = pts.iter().map(|(t, _)| (t - t_mean).powi(2)).sum();
    if !(stt > 0.0 && stt.is_finite()) {
        return (f64::INFINITY, f64::INFINITY);
    }
    let var_c: f64 = pts.iter().map(|(_, s)| s * s).sum::<f64>() / (n * n);
    let var_a: f64 = pts
        .iter()
        .map(|(t, s)| (t - t_mean).powi(2) * s * s)
        .sum::<f64>()
        / (stt * stt);
    let cov_ca: f64 = pts.iter().map(|(t, s)| (t - t_mean) * s * s).sum::<f64>() / (n * stt);
    // r is the offset at the foot of the perpendicular from the sensor: lever arm t_mean.
    let var_r = var_c + t_mean * t_mean * var_a - 2.0 * t_mean * cov_ca;
    (var_r.max(0.0).sqrt(), var_a.max(0.0).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use laserlines::math::Isometry2;
    use laserlines_sim::{LaserModel, Rng, World};

    #[test]
    fn pieces_of_a_square_room_are_significant_with_small_errors() {
        let mut world = World::new();
        world.add_polygon(&[
            Point2::new(-2.0, -2.0),
            Point2::new(2.0, -2.0),
            Point2::new(2.0, 2.0),
            Point2::new(-2.0, 2.0),
        ]);
        let model = LaserModel::urg04lx();
        let sim = laserlines_sim::simulate(&world, Isometry2::identity(), &model, &mut Rng::new(3));
        let pieces = expected_pieces(&sim, &model.noise);
        assert!(pieces.len() >= 3);
        for p in &pieces {
            assert!(p.significant);
            assert!(p.sigma_r > 0.0 && p.sigma_r < 0.005, "{p:?}");
            assert!(p.sigma_alpha > 0.0 && p.sigma_alpha < 0.01, "{p:?}");
        }
        // Without noise, no allowance.
        let ideal = expected_pieces(&sim, &Noise::None);
        assert!(
            ideal
                .iter()
                .all(|p| p.sigma_r == 0.0 && p.sigma_alpha == 0.0)
        );
    }

    #[test]
    fn exact_piece_has_the_polar_form_of_its_ends() {
        let p = ExpectedPiece::exact(0, 10, 60, Point2::new(2.0, -1.0), Point2::new(2.0, 1.0));
        assert!((p.r - 2.0).abs() < 1e-12 && p.alpha.abs() < 1e-12);
        assert_eq!(p.beams(), 51);
        assert!(p.significant);
        let q = ExpectedPiece::exact(0, 10, 60, Point2::new(-1.0, -2.0), Point2::new(1.0, -2.0));
        assert!((q.r - 2.0).abs() < 1e-12);
        assert!((q.alpha + std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        let short = ExpectedPiece::exact(0, 10, 15, Point2::new(2.0, 0.0), Point2::new(2.0, 0.1));
        assert!(!short.significant);
    }
}
