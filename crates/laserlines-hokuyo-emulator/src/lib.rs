//! # laserlines-hokuyo-emulator
//!
//! Scan feeds for the Hokuyo emulator of `laserlines-hokuyo`, kept apart so that the
//! driver crate does not depend on the simulator:
//!
//! - [`ArenaFeed`]: the simulator's laser model, set up as the emulated sensor (its steps,
//!   range limits, the URG-04LX noise, 1 mm rounding), moving slowly around a start
//!   point of a world (a RoboCup Rescue `.raf` arena);
//! - [`LogFeed`]: a recorded log replayed, each step taking the nearest beam of the log's
//!   scan, over and over.

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

/// The readings of `scan` at the steps of `model`: each step takes the beam of `scan`
/// nearest in angle; steps outside the log's scan, and beams that are no return (NaN,
/// beyond the log's `range_max`), read 0 (no echo); error codes kept as ranges below
/// `range_min` (URG logs keep 1..19 mm) are sent as they are.
#[must_use]
pub fn resample(scan: &Scan, model: &Model) -> Vec<u32> {
    let inc = scan.angle_increment;
    (model.amin..=model.amax)
        .map(|step| {
            if scan.ranges.is_empty() || inc == 0.0 || !inc.is_finite() {
                return 0;
            }
            let k = ((model.step_angle(step) - scan.angle_min) / inc).round();
            if k < 0.0 || k >= scan.ranges.len() as f64 {
                return 0;
            }
            let r = scan.ranges[k as usize];
            if r > scan.range_max {
                return 0;
            }
            to_mm(r, model)
        })
        .collect()
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
