//! # laserlines-hokuyo-emulator
//!
//! Scan feeds for the Hokuyo emulator of `laserlines-hokuyo`, kept apart so that the
//! driver crate does not depend on the simulator:
//!
//! - [`ArenaFeed`]: the simulator's laser model, set up as the emulated sensor (its steps,
//!   range limits, the URG-04LX noise, 1 mm rounding), moving slowly around a start
//!   point of a world (a RoboCup Rescue `.raf` arena);
//! - [`LogFeed`]: a recorded log replayed, each step reading where its ray meets the chord
//!   between the log's two beams beside it on one surface (else the nearest beam), over and
//!   over.

use std::f64::consts::TAU;

use laserlines::Scan;
use laserlines::math::{Isometry2, Vector2};
use laserlines_hokuyo::emulator::{Model, ScanFeed};
use laserlines_sim::index::WorldIndex;
use laserlines_sim::{LaserModel, Noise, Rng, World};

/// A reading as the sensor sends it, mm: 0 (no echo) for no return and beyond `DMAX`; a
/// reading below `DMIN` (an error code a log kept as a range, e.g. 0.007 m) stays as it
/// is.
fn to_mm(range: f64, model: &Model) -> u32 {
    if !range.is_finite() || range < 0.0 {
        return 0;
    }
    let mm = (range * 1000.0).round();
    if mm > f64::from(model.dmax_mm) {
        0
    } else {
        mm as u32
    }
}

/// The simulated sensor moving through a world: on a circle of `radius` around `centre`
/// (0.25 m, one turn per 30 s), turning as it goes.
pub struct ArenaFeed {
    index: WorldIndex,
    centre: Isometry2,
    laser: Option<LaserModel>,
    rng: Rng,
    scan: Scan,
    truth: Vec<f64>,
    k: u64,
    /// Radius of the circle, m.
    pub radius: f64,
}

impl std::fmt::Debug for ArenaFeed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ArenaFeed")
            .field("scan", &self.k)
            .finish_non_exhaustive()
    }
}

impl ArenaFeed {
    /// A feed in `world` around `centre` (a pose with room around it, e.g.
    /// `laserlines_sim::arena::interior_start`), noise seeded by `seed`.
    #[must_use]
    pub fn new(world: &World, centre: Isometry2, seed: u64) -> Self {
        Self {
            index: WorldIndex::new(world, 0.6),
            centre,
            laser: None,
            rng: Rng::new(seed),
            scan: Scan::default(),
            truth: Vec::new(),
            k: 0,
            radius: 0.25,
        }
    }

    /// The laser model of the emulated sensor.
    fn laser(model: &Model) -> LaserModel {
        LaserModel {
            beams: model.steps(),
            angle_min: model.step_angle(model.amin),
            angle_increment: TAU / f64::from(model.ares),
            range_min: f64::from(model.dmin_mm) / 1000.0,
            range_max: f64::from(model.dmax_mm) / 1000.0,
            noise: Noise::Urg04lx,
            round_to: Some(0.001),
            ..LaserModel::urg04lx()
        }
    }
}

impl ScanFeed for ArenaFeed {
    fn next_scan(&mut self, model: &Model) -> Vec<u32> {
        let laser = *self.laser.get_or_insert_with(|| Self::laser(model));
        let t = self.k as f64 * model.period_ms() as f64 / 1000.0;
        self.k += 1;
        let phase = TAU * t / 30.0;
        let offset = Vector2::new(self.radius * phase.cos(), self.radius * phase.sin());
        let pose = self.centre * Isometry2::new(offset, 0.3 * phase.sin());
        self.index.scan_into(
            &pose,
            &laser,
            &mut self.rng,
            &mut self.scan,
            &mut self.truth,
        );
        self.scan.ranges.iter().map(|&r| to_mm(r, model)).collect()
    }
}

/// Opens a log again (to replay it from its start).
pub type Reopen = Box<dyn FnMut() -> Result<Box<dyn Iterator<Item = Scan> + Send>, String> + Send>;

/// A recorded log replayed: scan after scan, from the start again at its end.
pub struct LogFeed {
    reopen: Reopen,
    scans: Option<Box<dyn Iterator<Item = Scan> + Send>>,
    /// Scans replayed.
    pub replayed: u64,
    /// Times the log was started over.
    pub restarts: u64,
}

impl std::fmt::Debug for LogFeed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LogFeed")
            .field("replayed", &self.replayed)
            .finish_non_exhaustive()
    }
}

impl LogFeed {
    /// A feed that opens its scans with `reopen` (called again at the end of the log).
    ///
    /// # Errors
    /// The error of the first opening.
    pub fn new(mut reopen: Reopen) -> Result<Self, String> {
        let scans = reopen()?;
        Ok(Self {
            reopen,
            scans: Some(scans),
            replayed: 0,
            restarts: 0,
        })
    }

    fn next_log_scan(&mut self) -> Option<Scan> {
        for _ in 0..2 {
            if let Some(s) = self.scans.as_mut().and_then(Iterator::next) {
                return Some(s);
            }
            self.restarts += 1;
            self.scans = (self.reopen)().ok();
        }
        None
    }
}

/// The readings of `scan` at the steps of `model`. A step between two beams of `scan` that
/// both returned, with ranges as close as one surface gives ([`between`]), reads where its ray
/// meets the chord between their points (exact on a straight surface, so a sensor finer than
/// the log sees no staircase of repeated readings); across a wider depth step, or beside a
/// beam without a return, it takes the beam nearest in angle. Steps outside the
/// log's scan, and beams that are no return (NaN, at or beyond the log's `range_max`: beyond
/// the top of its window, [`Scan::range_window`]), read 0 (no echo); error codes kept as
/// ranges below `range_min` (URG logs keep 1..19 mm) are sent as they are.
#[must_use]
pub fn resample(scan: &Scan, model: &Model) -> Vec<u32> {
    let inc = scan.angle_increment;
    let hi = scan.range_window(None).max;
    (model.amin..=model.amax)
        .map(|step| {
            if scan.ranges.is_empty() || inc == 0.0 || !inc.is_finite() {
                return 0;
            }
            let t = (model.step_angle(step) - scan.angle_min) / inc;
            let k = t.round();
            if k < 0.0 || k >= scan.ranges.len() as f64 {
                return 0;
            }
            let r = between(scan, hi, t).unwrap_or(scan.ranges[k as usize]);
            if r > hi {
                return 0;
            }
            to_mm(r, model)
        })
        .collect()
}

/// Widest depth step, as a multiple of the range times the angle between two beams, that
/// [`between`] takes for one surface: a surface seen at up to 80 deg of incidence
/// (`tan 80 deg`).
const SURFACE_SLOPE: f64 = 5.67;

/// The range at the fractional beam `t` of `scan` on the chord between the points of the
/// beams either side of it, when both returned (within the scan's window) and their ranges
/// differ by at most what one surface gives ([`SURFACE_SLOPE`] times the nearer range times
/// the angle between them, plus 2 cm: 9 cm at 2 m between a URG-04LX's beams, so that a
/// smaller step, a post just in front of a wall, is bridged as one surface would be);
/// `None` otherwise, on a beam exactly, and for beams more than 0.1 rad apart. `hi` is the
/// top of the scan's window.
fn between(scan: &Scan, hi: f64, t: f64) -> Option<f64> {
    let dphi = scan.angle_increment;
    if dphi.abs() > 0.1 {
        return None;
    }
    let k0 = t.floor();
    let f = t - k0;
    if !(f > 1e-9 && f < 1.0 - 1e-9) || k0 < 0.0 {
        return None;
    }
    let k0 = k0 as usize;
    let (&r0, &r1) = (scan.ranges.get(k0)?, scan.ranges.get(k0 + 1)?);
    let valid = |r: f64| r >= scan.range_min && r <= hi;
    if !(valid(r0) && valid(r1)) || (r1 - r0).abs() > SURFACE_SLOPE * r0.min(r1) * dphi.abs() + 0.02
    {
        return None;
    }
    // The ray at angle `f dphi` from beam k0 meets the chord from (r0, 0) to (r1, dphi):
    // r = r0 r1 sin(dphi) / (r0 sin(f dphi) + r1 sin((1 - f) dphi)).
    let den = r0 * (f * dphi).sin() + r1 * ((1.0 - f) * dphi).sin();
    let r = r0 * r1 * dphi.sin() / den;
    r.is_finite().then_some(r)
}

impl ScanFeed for LogFeed {
    fn next_scan(&mut self, model: &Model) -> Vec<u32> {
        match self.next_log_scan() {
            Some(s) => {
                self.replayed += 1;
                resample(&s, model)
            }
            None => vec![0; model.steps()],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use laserlines::math::Point2;
    use laserlines_hokuyo::emulator::ModelName;

    #[test]
    fn the_arena_feed_sees_the_walls_of_a_room() {
        let mut world = World::new();
        world.add_polygon(&[
            Point2::new(-2.0, -2.0),
            Point2::new(2.0, -2.0),
            Point2::new(2.0, 2.0),
            Point2::new(-2.0, 2.0),
        ]);
        let model = Model::new(ModelName::Urg04lx);
        let mut feed = ArenaFeed::new(&world, Isometry2::identity(), 3);
        feed.radius = 0.0;
        let v = feed.next_scan(&model);
        assert_eq!(v.len(), 682);
        // Straight ahead (step 384) the wall is 2 m away (noise: 10 mm at 2 sigma).
        let ahead = v[(384 - 44) as usize];
        assert!((1950..=2050).contains(&ahead), "{ahead}");
    }

    /// A URG-04LX log scan of a room, noise-free: the wall `x = 2` ahead, the walls
    /// `y = 1.5` and `y = -1.5` beside, and a box whose front is `x = 1` for `|y| <= 0.3`.
    fn room_log() -> Scan {
        let inc = TAU / 1024.0;
        let ranges = (0..682)
            .map(|i| {
                let (s, c) = ((f64::from(i) - 340.0) * inc).sin_cos();
                let mut r = f64::INFINITY;
                if c > 1e-9 {
                    r = r.min(2.0 / c);
                    if (s / c).abs() <= 0.3 {
                        r = r.min(1.0 / c);
                    }
                }
                if s.abs() > 1e-9 {
                    r = r.min(1.5 / s.abs());
                }
                r
            })
            .collect();
        Scan::new(-340.0 * inc, inc, 0.02, 5.6, ranges).unwrap()
    }

    #[test]
    fn a_finer_sensor_reads_the_log_on_its_surfaces_without_a_staircase() {
        // The UST-10LX's 0.25 deg steps between the log's 0.35 deg beams: each reading lies
        // on the surface its ray meets (within the 1 mm rounding; the chord between a beam on
        // each wall of a corner cuts it by up to 2 mm at these ranges), none
        // between the box and the wall behind it, and no two neighbouring readings on a side
        // wall, seen at a slant, are equal (the nearest beam, repeated, made a staircase).
        let log = room_log();
        let model = Model::new(ModelName::Ust10lx);
        let v = resample(&log, &model);
        let last = log.angle_min + 681.0 * log.angle_increment;
        let (mut on, mut repeated) = (0, 0);
        for (i, &mm) in v.iter().enumerate() {
            let step = model.amin + i as u32;
            let a = model.step_angle(step);
            if mm == 0 || !(log.angle_min..=last).contains(&a) {
                continue;
            }
            let r = f64::from(mm) / 1000.0;
            let (x, y) = (r * a.cos(), r * a.sin());
            let box_front = (x - 1.0).abs() + if y.abs() > 0.31 { 1.0 } else { 0.0 };
            let off = [(x - 2.0).abs(), (y.abs() - 1.5).abs(), box_front]
                .into_iter()
                .fold(f64::INFINITY, f64::min);
            assert!(
                off < 0.003,
                "step {step}: ({x:.4}, {y:.4}) on no surface ({off:.4} m)"
            );
            on += 1;
            let side = (y.abs() - 1.5).abs() < 0.002 && x > 1.0;
            repeated += usize::from(i > 0 && v[i - 1] == mm && side);
        }
        assert!(on > 900, "{on} readings on the surfaces");
        assert_eq!(
            repeated, 0,
            "neighbouring readings repeated on the side walls"
        );
    }

    #[test]
    fn a_log_scan_is_resampled_to_the_steps() {
        let model = Model::new(ModelName::Urg04lx);
        let inc = TAU / 1024.0;
        // A log scan at the same steps, ranges 1 m + 1 mm per beam, one no return.
        let mut ranges: Vec<f64> = (0..682).map(|i| 1.0 + i as f64 * 0.001).collect();
        ranges[10] = f64::NAN;
        ranges[11] = 0.007;
        let scan = Scan::new(-340.0 * inc, inc, 0.02, 5.6, ranges).unwrap();
        let v = resample(&scan, &model);
        assert_eq!(v[0], 1000);
        assert_eq!(v[681], 1681);
        assert_eq!(v[10], 0);
        assert_eq!(v[11], 7);
        let mut feed = LogFeed::new(Box::new(move || {
            Ok(Box::new(vec![scan.clone()].into_iter()) as Box<dyn Iterator<Item = Scan> + Send>)
        }))
        .unwrap();
        feed.next_scan(&model);
        feed.next_scan(&model);
        assert_eq!((feed.replayed, feed.restarts), (2, 1));
    }
}
