//! Simulating one scan of a world, with its ground truth.

use laserlines::Scan;
use laserlines::math::{Isometry2, Point2};

use crate::laser::{LaserModel, MAX_BEAMS};
use crate::rng::Rng;
use crate::world::{Target, World};

/// Smallest jump of the noise-free range between two consecutive beams on different
/// obstacles that counts as a depth edge where mixed pixels may appear, m.
pub const MIXED_PIXEL_MIN_JUMP: f64 = 0.05;

/// The fewest beams a visible piece needs to be one an extractor must find (issue criterion:
/// a run of 10+ beams on one wall).
pub const MIN_PIECE_BEAMS: usize = 10;

/// The shortest visible piece, m, that an extractor must find (0.2 m).
pub const MIN_PIECE_LENGTH: f64 = 0.2;

/// A simulated scan and what produced it.
#[derive(Debug, Clone, PartialEq)]
pub struct SimScan {
    /// The scan as the sensor reports it.
    pub scan: Scan,
    /// The ground truth.
    pub truth: Truth,
}

/// Ground truth of one simulated scan: what every beam hit, and the visible wall pieces.
///
/// Everything here comes from the noise-free geometry: dropouts, noise and mixed pixels change
/// the reported ranges, not the truth (they are listed so that they can be told apart).
/// `ranges` holds NaN for beams without a hit, so two truths of scans with such beams never
/// compare equal with `==`; compare their fields or the ranges' bits.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Truth {
    /// For each beam, what its noise-free ray hit within `range_min..=range_max`; `None` when
    /// it hit nothing in range (including an obstacle nearer than `range_min`).
    pub beam_target: Vec<Option<Target>>,
    /// For each beam, the noise-free range, m; NaN where `beam_target` is `None`.
    pub ranges: Vec<f64>,
    /// The visible wall pieces, in beam order. Discs are not pieces.
    pub pieces: Vec<VisiblePiece>,
    /// Beams whose reported range is a mixed pixel (a phantom between two surfaces), in
    /// increasing order.
    pub mixed_pixels: Vec<usize>,
    /// Beams whose return was dropped, in increasing order.
    pub dropouts: Vec<usize>,
}

impl Truth {
    /// The pieces of at least `min_beams` beams and `min_length` metres.
    pub fn pieces_at_least(
        &self,
        min_beams: usize,
        min_length: f64,
    ) -> impl Iterator<Item = &VisiblePiece> {
        self.pieces
            .iter()
            .filter(move |p| p.beams >= min_beams && p.length() >= min_length)
    }

    /// The pieces an extractor must find: at least [`MIN_PIECE_BEAMS`] beams and
    /// [`MIN_PIECE_LENGTH`] metres.
    pub fn significant_pieces(&self) -> impl Iterator<Item = &VisiblePiece> {
        self.pieces_at_least(MIN_PIECE_BEAMS, MIN_PIECE_LENGTH)
    }

    /// The noise-free hit point of beam `i` in the laser frame, m, given the scan's beam
    /// geometry; `None` when the beam hit nothing or `i` is out of range.
    #[must_use]
    pub fn point(&self, scan: &Scan, i: usize) -> Option<Point2> {
        let r = *self.ranges.get(i)?;
        if !r.is_finite() {
            return None;
        }
        let (s, c) = scan.angle(i).sin_cos();
        Some(Point2::new(r * c, r * s))
    }
}

/// A visible wall piece: a maximal run of consecutive beams whose noise-free hits all lie on
/// the same wall. In the LASER frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VisiblePiece {
    /// Index of the wall in [`World::walls`].
    pub wall: usize,
    /// First beam of the run.
    pub first: usize,
    /// Last beam of the run (inclusive). Below `first` when the run goes on across the seam
    /// of a scan that goes once round ([`laserlines::ScanView::full_turn`]): `first..n`,
    /// then `0..=last`.
    pub last: usize,
    /// Number of beams in the run (dropped returns included).
    pub beams: usize,
    /// Distance of the wall's infinite line from the laser, m (`>= 0`).
    pub r: f64,
    /// Direction of the line's normal, rad, in `(-pi, pi]`: the line is
    /// `x cos(alpha) + y sin(alpha) = r`.
    pub alpha: f64,
    /// Noise-free hit point of beam `first`, m.
    pub start: Point2,
    /// Noise-free hit point of beam `last`, m.
    pub end: Point2,
}

impl VisiblePiece {
    /// Length of the piece from `start` to `end`, m.
    #[must_use]
    pub fn length(&self) -> f64 {
        (self.end - self.start).norm()
    }
}

/// Simulates one scan of `world` by a laser at `world_from_laser` (its pose in the world).
///
/// Per beam: the exact nearest hit within `range_max` (obstacles nearer than `range_min` give
/// no return and hide what is behind them); gaussian noise by [`LaserModel::noise`]; then
/// mixed pixels at depth edges, dropouts, the noise's own steps ([`crate::Noise::quantize`]),
/// rounding to [`LaserModel::round_to`]. A reported
/// range that ends up outside `range_min..=range_max` (or not positive) is no return.
/// No return is NaN; beams that hit nothing report `range_max` instead when
/// [`LaserModel::max_range_returns`] is set.
///
/// Deterministic: the same world, pose, model and generator state give the same scan. Never
/// panics; at most [`MAX_BEAMS`] beams are simulated.
#[must_use]
pub fn simulate(
    world: &World,
    world_from_laser: Isometry2,
    model: &LaserModel,
    rng: &mut Rng,
) -> SimScan {
    let range_max = if model.range_max.is_nan() {
        -1.0
    } else {
        model.range_max
    };
    let (truth_ranges, beam_target, no_hit) =
        cast_beams(world, &world_from_laser, model, range_max);
    // Noise.
    let mut ranges = truth_ranges.clone();
    for r in &mut ranges {
        if r.is_finite() {
            let sigma = model.noise.sigma(*r);
            if sigma > 0.0 {
                *r += sigma * rng.gaussian();
            }
        }
    }
    let mixed = mixed_pixels(model, rng, &truth_ranges, &beam_target, &mut ranges);
    // Dropouts.
    let mut dropped = vec![false; ranges.len()];
    if model.dropout > 0.0 {
        for (i, r) in ranges.iter_mut().enumerate() {
            if r.is_finite() && rng.chance(model.dropout) {
                *r = f64::NAN;
                dropped[i] = true;
            }
        }
    }
    // Rounding, the measurable window, and beams without a hit.
    let step = model.round_to.filter(|q| q.is_finite() && *q > 0.0);
    for (i, r) in ranges.iter_mut().enumerate() {
        *r = model.noise.quantize(*r);
        if let Some(q) = step {
            *r = (*r / q).round() * q;
        }
        let measurable = r.is_finite() && *r > 0.0 && *r >= model.range_min && *r <= range_max;
        if !measurable {
            *r = f64::NAN;
        }
        if no_hit[i] && model.max_range_returns && !dropped[i] {
            *r = model.range_max;
        }
    }
    let laser_from_world = world_from_laser.inverse();
    let pieces = visible_pieces(world, &laser_from_world, model, &beam_target, &truth_ranges);
    let truth = Truth {
        beam_target,
        ranges: truth_ranges,
        pieces,
        mixed_pixels: indices(&mixed),
        dropouts: indices(&dropped),
    };
    let scan = Scan {
        angle_min: model.angle_min,
        angle_increment: model.angle_increment,
        range_min: model.range_min,
        range_max: model.range_max,
        ranges,
        intensities: None,
        stamp: None,
    };
    SimScan { scan, truth }
}

/// The noise-free range of every beam (NaN for none), what it hit, and whether it hit
/// nothing within `range_max` (an obstacle nearer than `range_min` is a hit, with no range).
fn cast_beams(
    world: &World,
    world_from_laser: &Isometry2,
    model: &LaserModel,
    range_max: f64,
) -> (Vec<f64>, Vec<Option<Target>>, Vec<bool>) {
    let n = model.beams.min(MAX_BEAMS);
    let origin = Point2::from(world_from_laser.translation.vector);
    let yaw = world_from_laser.rotation.angle();
    let mut truth_ranges = vec![f64::NAN; n];
    let mut beam_target = vec![None; n];
    let mut no_hit = vec![false; n];
    for i in 0..n {
        match world.cast(origin, yaw + model.angle(i), range_max) {
            Some(hit) if hit.range >= model.range_min && hit.range > 0.0 => {
                truth_ranges[i] = hit.range;
                beam_target[i] = Some(hit.target);
            }
            Some(_) => {}
            None => no_hit[i] = true,
        }
    }
    (truth_ranges, beam_target, no_hit)
}

/// Mixed pixels at depth edges (see [`LaserModel::mixed_pixels`]); which beams became one.
fn mixed_pixels(
    model: &LaserModel,
    rng: &mut Rng,
    truth_ranges: &[f64],
    beam_target: &[Option<Target>],
    ranges: &mut [f64],
) -> Vec<bool> {
    let n = truth_ranges.len();
    let mut mixed = vec![false; n];
    if model.mixed_pixels > 0.0 {
        for i in 1..n {
            let (ra, rb) = (truth_ranges[i - 1], truth_ranges[i]);
            let edge = ra.is_finite()
                && rb.is_finite()
                && beam_target[i - 1] != beam_target[i]
                && (ra - rb).abs() > MIXED_PIXEL_MIN_JUMP;
            if !edge || mixed[i - 1] || !rng.chance(model.mixed_pixels) {
                continue;
            }
            let j = if rng.chance(0.5) { i - 1 } else { i };
            let (near, far) = if ra < rb { (ra, rb) } else { (rb, ra) };
            ranges[j] = near + (far - near) * rng.range(0.05, 0.95);
            mixed[j] = true;
        }
    }
    mixed
}

/// The maximal runs of consecutive beams on one wall.
fn visible_pieces(
    world: &World,
    laser_from_world: &Isometry2,
    model: &LaserModel,
    beam_target: &[Option<Target>],
    ranges: &[f64],
) -> Vec<VisiblePiece> {
    let point = |i: usize| {
        let (s, c) = model.angle(i).sin_cos();
        Point2::new(ranges[i] * c, ranges[i] * s)
    };
    let mut pieces = Vec::new();
    let n = beam_target.len().min(ranges.len());
    let mut i = 0;
    while i < n {
        if let Some(Target::Wall(w)) = beam_target[i] {
            let first = i;
            while i + 1 < n && beam_target[i + 1] == Some(Target::Wall(w)) {
                i += 1;
            }
            let last = i;
            if let Some((r, alpha)) = world
                .walls
                .get(w)
                .and_then(|x| x.polar_in(laser_from_world))
            {
                pieces.push(VisiblePiece {
                    wall: w,
                    first,
                    last,
                    beams: last - first + 1,
                    r,
                    alpha,
                    start: point(first),
                    end: point(last),
                });
            }
        }
        i += 1;
    }
    let turn = laserlines::ScanView {
        angle_min: model.angle_min,
        angle_increment: model.angle_increment,
        range_min: model.range_min,
        range_max: model.range_max,
        ranges: &ranges[..n],
    };
    if turn.full_turn() {
        join_at_seam(&mut pieces, n);
    }
    pieces
}

/// A full turn's run on one wall that ends at the last beam and goes on at beam 0 is one
/// piece: the last takes in the first, which is removed.
fn join_at_seam(pieces: &mut Vec<VisiblePiece>, n: usize) {
    let (Some(&first), Some(&last)) = (pieces.first(), pieces.last()) else {
        return;
    };
    if pieces.len() < 2 || first.wall != last.wall || first.first != 0 || last.last + 1 != n {
        return;
    }
    if let Some(joined) = pieces.last_mut() {
        joined.last = first.last;
        joined.beams = last.beams + first.beams;
        joined.end = first.end;
        pieces.remove(0);
    }
}

fn indices(flags: &[bool]) -> Vec<usize> {
    flags
        .iter()
        .enumerate()
        .filter_map(|(i, f)| f.then_some(i))
        .collect()
}
