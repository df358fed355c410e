//! A whole scan at once: every beam of the laser cast by one angular sweep over the
//! obstacles in range, nearest first, instead of one ray walk per beam.

use laserlines::Scan;
use laserlines::geometry::{circle_ray_hit, segment_ray_hit_prepared};
use laserlines::math::{Isometry2, Point2, Vector2, ceil_i64, floor_i64};

use crate::index::{TIE_TOLERANCE, WorldIndex, finite, target_order};
use crate::laser::{LaserModel, MAX_BEAMS};
use crate::noise::{NO_HIT, report};
use crate::rng::Rng;
use crate::world::Target;

impl WorldIndex {
    /// Simulates one scan like [`crate::simulate`] into reused buffers: `scan` gets the
    /// reported ranges and the model's geometry, `true_ranges` the noise-free range of every
    /// beam (NaN where the beam hit nothing within `range_min..=range_max`). No visible
    /// pieces are computed.
    ///
    /// The beams are cast all at once by an angular sweep rather than one by one: every
    /// wall and disc within `range_max` of the laser is tested against the beams whose
    /// directions fall within the angle it subtends (one beam of margin on each side), with
    /// the exact intersection formulas of [`WorldIndex::cast`]; a beam already stopped
    /// nearer than the obstacle's nearest point skips it. Obstacles are taken nearest
    /// first, so that hidden ones cost one comparison per beam. The ranges are those of
    /// [`WorldIndex::cast_dir`] along the same directions.
    ///
    /// The noise-free ranges agree with [`crate::simulate`]'s to about 1e-12 m (the beam
    /// directions are computed by repeated rotation instead of a sine and cosine per beam).
    /// The range noise is drawn from `rng` by a ziggurat sampler of the standard normal
    /// distribution (Marsaglia and Tsang's method, in Doornik's form) rather than
    /// [`Rng::gaussian`]'s Box-Muller transform, which costs a logarithm, a square root, a
    /// sine and a cosine per pair of draws: the same distribution, other draws. Mixed
    /// pixels and dropouts draw as in [`crate::simulate`].
    pub fn scan_into(
        &self,
        world_from_laser: &Isometry2,
        model: &LaserModel,
        rng: &mut Rng,
        scan: &mut Scan,
        true_ranges: &mut Vec<f64>,
    ) {
        let n = model.beams.min(MAX_BEAMS);
        let origin = Point2::from(world_from_laser.translation.vector);
        let yaw = world_from_laser.rotation.angle();
        let range_max = if model.range_max.is_nan() {
            -1.0
        } else {
            model.range_max
        };
        true_ranges.clear();
        true_ranges.resize(n, f64::NAN);
        let mut targets: Vec<Option<Target>> = vec![None; n];
        let mut flags = vec![0_u8; n];
        let dirs = beam_directions(yaw + model.angle_min, model.angle_increment, n);
        let mut best: Vec<Option<(f64, Target)>> = vec![None; n];
        let fan = Fan {
            origin,
            base: yaw + model.angle_min,
            increment: model.angle_increment,
            dirs: &dirs,
            range_max,
        };
        if fan.is_valid() {
            self.sweep(&fan, &mut best);
        }
        for i in 0..n {
            match best[i] {
                Some((range, target)) if finite(origin + dirs[i] * range) => {
                    if range >= model.range_min && range > 0.0 {
                        true_ranges[i] = range;
                        targets[i] = Some(target);
                    }
                }
                _ => flags[i] |= NO_HIT,
            }
        }
        report(
            model,
            rng,
            true_ranges,
            &targets,
            &mut flags,
            &mut scan.ranges,
            range_max,
        );
        scan.angle_min = model.angle_min;
        scan.angle_increment = model.angle_increment;
        scan.range_min = model.range_min;
        scan.range_max = model.range_max;
        scan.intensities = None;
    }

    /// The nearest hit of every beam of `fan` (see [`WorldIndex::scan_into`]) into `best`
    /// (one slot per beam, `None` on entry).
    fn sweep(&self, fan: &Fan<'_>, best: &mut [Option<(f64, Target)>]) {
        for (d_near, target) in self.near_obstacles(fan) {
            // The wall's direction and length, once for all its beams.
            let (e, len) = match target {
                Target::Wall(k) => {
                    let w = &self.world().walls[k];
                    let e = w.b - w.a;
                    (e, e.norm())
                }
                Target::Disc(_) => (Vector2::zeros(), 1.0),
            };
            if !(len > 0.0 && len.is_finite()) {
                // A degenerate wall is never hit.
                continue;
            }
            let hidden_below = d_near - TIE_TOLERANCE;
            let mut test = |i: usize| {
                if let Some((bt, _)) = best[i]
                    && bt < hidden_below
                {
                    return;
                }
                let t = self.ray_hit(target, e, len, fan.origin, fan.dirs[i]);
                if let Some(t) = t
                    && t.is_finite()
                    && t <= fan.range_max
                    && best[i].is_none_or(|(bt, tb)| {
                        t < bt - TIE_TOLERANCE
                            || (t <= bt + TIE_TOLERANCE && target_order(target, tb))
                    })
                {
                    best[i] = Some((t, target));
                }
            };
            match self.subtended(fan, d_near, target) {
                None => (0..fan.dirs.len()).for_each(&mut test),
                Some((from, to)) => {
                    for (a, b) in fan.beams_between(from, to) {
                        (a..=b).for_each(&mut test);
                    }
                }
            }
        }
    }

    /// Where the ray from `origin` along `dir` meets `target` (a wall of direction `e` and
    /// length `len`, or a disc).
    fn ray_hit(
        &self,
        target: Target,
        e: Vector2,
        len: f64,
        origin: Point2,
        dir: Vector2,
    ) -> Option<f64> {
        match target {
            Target::Wall(k) => {
                let w = &self.world().walls[k];
                segment_ray_hit_prepared(w.a, w.b, e, len, origin, dir)
            }
            Target::Disc(k) => {
                let d = &self.world().discs[k];
                circle_ray_hit(d.centre, d.radius, origin, dir)
            }
        }
    }

    /// The obstacles within the fan's range, nearest first, with the distance to their
    /// nearest point.
    fn near_obstacles(&self, fan: &Fan<'_>) -> Vec<(f64, Target)> {
        let (origin, range_max) = (fan.origin, fan.range_max);
        let world = self.world();
        let mut near: Vec<(f64, Target)> = Vec::new();
        let add = |t: Target, near: &mut Vec<(f64, Target)>| match t {
            Target::Wall(i) => {
                let w = &world.walls[i];
                if finite(w.a) && finite(w.b) {
                    let d = laserlines::geometry::distance_to_segment(origin, w.a, w.b);
                    if d <= range_max {
                        near.push((d, t));
                    }
                }
            }
            Target::Disc(i) => {
                let d = &world.discs[i];
                if d.radius > 0.0 && d.radius.is_finite() && finite(d.centre) {
                    let gap = ((d.centre - origin).norm() - d.radius).max(0.0);
                    if gap <= range_max {
                        near.push((gap, t));
                    }
                }
            }
        };
        let walls = world.walls.len();
        let count = walls + world.discs.len();
        if count <= SWEEP_ALL_BELOW || !range_max.is_finite() {
            for i in 0..walls {
                add(Target::Wall(i), &mut near);
            }
            for i in 0..world.discs.len() {
                add(Target::Disc(i), &mut near);
            }
        } else {
            let mut listed = vec![false; count];
            let r = Vector2::new(range_max, range_max);
            self.near_box(origin - r, origin + r, |t| {
                let k = match t {
                    Target::Wall(i) => i,
                    Target::Disc(i) => walls + i,
                };
                if !listed[k] {
                    listed[k] = true;
                    add(t, &mut near);
                }
            });
        }
        near.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        near
    }

    /// The relative angles `(from, to)` the obstacle subtends seen from the fan's origin;
    /// `None` when the origin is on it (every beam may hit it).
    fn subtended(&self, fan: &Fan<'_>, d_near: f64, target: Target) -> Option<(f64, f64)> {
        let origin = fan.origin;
        match target {
            Target::Wall(i) => {
                let w = &self.world().walls[i];
                if d_near <= 1e-9 * (1.0 + (w.a - origin).norm()) {
                    return None;
                }
                let ra = fan.relative(w.a - origin);
                let rb = fan.relative(w.b - origin);
                let (lo, hi) = if ra <= rb { (ra, rb) } else { (rb, ra) };
                Some(if hi - lo <= std::f64::consts::PI {
                    (lo, hi)
                } else {
                    (hi, lo + std::f64::consts::TAU)
                })
            }
            Target::Disc(i) => {
                let d = &self.world().discs[i];
                let c = d.centre - origin;
                let dist = c.norm();
                if dist <= d.radius * (1.0 + 1e-9) + 1e-12 {
                    return None;
                }
                let half = (d.radius / dist).min(1.0).asin();
                let rc = fan.relative(c);
                Some((rc - half, rc + half))
            }
        }
    }
}

/// The unit directions of `n` beams from `base` by `increment` (rad), by repeated rotation:
/// no sine or cosine per beam.
fn beam_directions(base: f64, increment: f64, n: usize) -> Vec<Vector2> {
    let (s0, c0) = base.sin_cos();
    let (s_inc, c_inc) = increment.sin_cos();
    let mut dirs = Vec::with_capacity(n);
    let mut dir = Vector2::new(c0, s0);
    for i in 0..n {
        if i > 0 {
            dir = Vector2::new(c_inc * dir.x - s_inc * dir.y, s_inc * dir.x + c_inc * dir.y);
        }
        dirs.push(dir);
    }
    dirs
}

/// Below this many walls and discs a sweep lists them all instead of asking the grid.
const SWEEP_ALL_BELOW: usize = 512;

/// The beams of one scan, for [`WorldIndex::sweep`].
struct Fan<'a> {
    origin: Point2,
    /// Direction of beam 0, rad, world frame.
    base: f64,
    /// Angle between beams, rad (either sign).
    increment: f64,
    /// The unit direction of every beam, world frame.
    dirs: &'a [Vector2],
    range_max: f64,
}

impl Fan<'_> {
    fn is_valid(&self) -> bool {
        finite(self.origin)
            && self.base.is_finite()
            && self.increment.is_finite()
            && self.increment != 0.0
            && self.range_max >= 0.0
            && !self.dirs.is_empty()
    }

    /// The angle of the direction `v` counted from beam 0 in the beams' sense of rotation,
    /// in `[0, 2 pi)`: beam `i` is at `i * |increment|`.
    fn relative(&self, v: Vector2) -> f64 {
        let a = self.increment.signum() * (fast_atan2(v.y, v.x) - self.base);
        a.rem_euclid(std::f64::consts::TAU)
    }

    /// The index ranges of the beams at relative angles `from..=to` (`to - from` below
    /// `2 pi`, any start), widened by one beam and a little on each side.
    fn beams_between(&self, from: f64, to: f64) -> impl Iterator<Item = (usize, usize)> + use<> {
        let step = self.increment.abs();
        let margin = step + 1e-9;
        let last = self.dirs.len() as f64 - 1.0;
        let tau = std::f64::consts::TAU;
        [-1.0, 0.0, 1.0].into_iter().filter_map(move |k: f64| {
            let lo = ceil_i64((from + k * tau - margin) / step).max(0);
            let hi = (floor_i64((to + k * tau + margin) / step) as f64).min(last) as i64;
            (lo <= hi).then_some((lo as usize, hi as usize))
        })
    }
}

/// `atan2(y, x)` to within 1e-7 rad without a library call (arguments reduced to
/// `|u| <= tan(pi/8)`, then eight terms of the series of `atan u`): for choosing the beams
/// a wall subtends, whose one-beam margin (6 mrad for the URG-04LX) is far wider.
#[inline]
fn fast_atan2(y: f64, x: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    let (ax, ay) = (x.abs(), y.abs());
    let (big, small) = if ax >= ay { (ax, ay) } else { (ay, ax) };
    if big.is_nan() || big <= 0.0 || big.is_infinite() {
        return y.atan2(x);
    }
    let t = small / big;
    // atan t = pi/4 + atan((t - 1) / (t + 1)) brings t in [0, 1] to |u| <= tan(pi/8).
    let (u, base) = if t > 0.414_213_562_373_095 {
        ((t - 1.0) / (t + 1.0), FRAC_PI_4)
    } else {
        (t, 0.0)
    };
    let u2 = u * u;
    let series = u
        * (1.0
            + u2 * (-1.0 / 3.0
                + u2 * (1.0 / 5.0
                    + u2 * (-1.0 / 7.0
                        + u2 * (1.0 / 9.0 + u2 * (-1.0 / 11.0 + u2 * (1.0 / 13.0 - u2 / 15.0)))))));
    let mut a = base + series;
    if ay > ax {
        a = FRAC_PI_2 - a;
    }
    if x < 0.0 {
        a = PI - a;
    }
    if y < 0.0 { -a } else { a }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::World;

    /// The sweep of `scan_into` gives, beam by beam, what `cast_dir` gives along the same
    /// direction: random worlds, poses on and off walls, both senses of rotation, full turns.
    #[test]
    fn the_sweep_agrees_with_casting_beam_by_beam() {
        let mut rng = Rng::new(17);
        let (mut hits, mut misses) = (0, 0);
        for trial in 0..40 {
            let mut world = World::new();
            for _ in 0..(if trial % 5 == 0 { 700 } else { 40 }) {
                let a = Point2::new(rng.range(-6.0, 6.0), rng.range(-6.0, 6.0));
                let b = a + Vector2::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
                world.add_segment(a, b);
            }
            for k in -3..3 {
                let x = 1.2 * f64::from(k);
                world.add_segment(Point2::new(x, -0.6), Point2::new(x, 0.6));
            }
            for _ in 0..8 {
                world.add_disc(
                    Point2::new(rng.range(-6.0, 6.0), rng.range(-6.0, 6.0)),
                    rng.range(0.05, 0.5),
                );
            }
            let index = WorldIndex::new(&world, 0.6);
            let mut model = LaserModel::urg04lx().ideal();
            match trial % 4 {
                1 => {
                    model.angle_increment = -model.angle_increment;
                    model.angle_min = -model.angle_min;
                }
                2 => {
                    model.beams = 1024;
                    model.angle_min = -std::f64::consts::PI;
                }
                3 => model.range_max = 30.0,
                _ => {}
            }
            for _ in 0..20 {
                let o = if rng.chance(0.1) {
                    // On a wall's line, or at a wall's end.
                    let w = world.walls[rng.below(world.walls.len())];
                    if rng.chance(0.5) {
                        w.a
                    } else {
                        w.a + (w.b - w.a) * 0.5
                    }
                } else {
                    Point2::new(rng.range(-7.0, 7.0), rng.range(-7.0, 7.0))
                };
                let yaw = if rng.chance(0.3) {
                    f64::from(rng.below(8) as u32) * std::f64::consts::FRAC_PI_4
                } else {
                    rng.range(-4.0, 4.0)
                };
                let pose = laserlines::math::Isometry2::new(o.coords, yaw);
                let mut scan = Scan::default();
                let mut truth = Vec::new();
                index.scan_into(&pose, &model, &mut Rng::new(1), &mut scan, &mut truth);
                let (s0, c0) = (yaw + model.angle_min).sin_cos();
                let (si, ci) = model.angle_increment.sin_cos();
                let mut dir = Vector2::new(c0, s0);
                for (i, &got) in truth.iter().enumerate() {
                    if i > 0 {
                        dir = Vector2::new(ci * dir.x - si * dir.y, si * dir.x + ci * dir.y);
                    }
                    let want = index
                        .cast_dir(o, dir, model.range_max)
                        .map(|h| h.range)
                        .filter(|&r| r >= model.range_min && r > 0.0);
                    if want.is_some() {
                        hits += 1;
                    } else {
                        misses += 1;
                    }
                    match want {
                        Some(w) => assert!(
                            (got - w).abs() <= 1e-12 * (1.0 + w),
                            "trial {trial} beam {i}: {got} vs {w} at {o} yaw {yaw}"
                        ),
                        None => assert!(got.is_nan(), "trial {trial} beam {i}: {got} vs none"),
                    }
                }
            }
        }
        assert!(
            hits > 100_000 && misses > 1000,
            "{hits} hits, {misses} misses"
        );
    }

    #[test]
    fn fast_atan2_is_close() {
        let mut rng = Rng::new(8);
        let mut worst: f64 = 0.0;
        for _ in 0..200_000 {
            let (x, y) = (rng.range(-10.0, 10.0), rng.range(-10.0, 10.0));
            worst = worst.max((fast_atan2(y, x) - y.atan2(x)).abs());
        }
        for (x, y) in [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0), (1.0, 1.0)] {
            worst = worst.max((fast_atan2(y, x) - f64::atan2(y, x)).abs());
        }
        assert!(worst < 1e-7, "{worst}");
        assert!(fast_atan2(f64::NAN, 1.0).is_nan());
    }
}
