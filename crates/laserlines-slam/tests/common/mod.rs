//! Simulated scenes shared by the tests.
#![allow(clippy::unwrap_used, clippy::expect_used)]
#![allow(dead_code)]

use laserlines::Scan;
use laserlines::math::{Isometry2, Point2, Vector2};
use laserlines_sim::{LaserModel, Rng, World, simulate};
use laserlines_slam::Se2;
use laserlines_slam::cloud::{PointCloud, SurfacePoint, scan_surface};

/// A 10 m x 7 m room with an inner wall, two boxes and a pillar: enough structure to fix
/// every direction of a pose from anywhere inside.
pub fn room() -> World {
    let mut w = World::new();
    w.add_polygon(&[
        Point2::new(-5.0, -3.5),
        Point2::new(5.0, -3.5),
        Point2::new(5.0, 3.5),
        Point2::new(-5.0, 3.5),
    ]);
    w.add_segment(Point2::new(1.0, -3.5), Point2::new(1.0, 0.5));
    w.add_box(Point2::new(-2.5, 1.5), 1.0, 0.6, 0.4);
    w.add_box(Point2::new(3.0, 2.0), 0.8, 0.8, -0.2);
    w.add_disc(Point2::new(-1.0, -2.0), 0.2);
    w
}

/// A SICK-like laser: 361 beams over 180 deg, 1 cm noise, 30 m.
pub fn sick() -> LaserModel {
    LaserModel {
        beams: 361,
        angle_min: -std::f64::consts::FRAC_PI_2,
        angle_increment: 0.5_f64.to_radians(),
        range_min: 0.1,
        range_max: 30.0,
        noise: laserlines_sim::Noise::Gaussian { sigma: 0.01 },
        round_to: None,
        ..LaserModel::urg04lx()
    }
}

/// A scan of `world` from `pose` with `model`.
pub fn scan_at(world: &World, pose: Se2, model: &LaserModel, rng: &mut Rng) -> Scan {
    let iso = Isometry2::new(Vector2::new(pose.x, pose.y), pose.theta);
    simulate(world, iso, model, rng).scan
}

/// The scan's points that have normals (sensor frame).
pub fn surface(scan: &Scan) -> Vec<SurfacePoint> {
    scan_surface(scan, scan.range_window(None), 3)
}

/// A cloud of the scan's surface points seen from `pose`.
pub fn cloud(scan: &Scan, pose: Se2) -> PointCloud {
    let mut c = PointCloud::new(0.02, 0.5);
    for p in surface(scan) {
        c.insert(SurfacePoint {
            point: pose.transform(p.point),
            normal: pose.rotate(p.normal),
        });
    }
    c
}

/// A driver that bounces around a closed space: straight on at 0.4 m/s until something is
/// within 0.7 m ahead (within 0.5 rad of the laser's axis), then on the spot, alternating
/// sides, until the way is clear for 1.2 m.
#[derive(Debug, Default)]
pub struct Bounce {
    turning: Option<f64>,
    turns: u32,
}

impl Bounce {
    /// The command for the latest scan.
    pub fn command(&mut self, scan: &Scan) -> laserlines_sim::robot::VelocityCommand {
        use laserlines_sim::robot::VelocityCommand;
        let ahead = (0..scan.len())
            .filter(|&i| scan.angle(i).abs() < 0.5)
            .map(|i| scan.ranges[i])
            .filter(|r| r.is_finite() && *r > scan.range_min)
            .fold(f64::INFINITY, f64::min);
        match self.turning {
            Some(dir) if ahead < 1.2 => VelocityCommand {
                linear_m_s: 0.0,
                angular_rad_s: dir,
            },
            _ if ahead < 0.7 => {
                self.turns += 1;
                let dir = if self.turns.is_multiple_of(2) {
                    0.8
                } else {
                    -0.8
                };
                self.turning = Some(dir);
                VelocityCommand {
                    linear_m_s: 0.0,
                    angular_rad_s: dir,
                }
            }
            _ => {
                self.turning = None;
                VelocityCommand {
                    linear_m_s: 0.4,
                    angular_rad_s: 0.0,
                }
            }
        }
    }
}

/// The bundled arena `inner_explore_test` and a start in its largest enclosed region.
pub fn inner_explore_test() -> (World, Isometry2) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/arenas/inner_explore_test.raf"
    );
    let arena =
        laserlines_sim::arena::load_raf(std::path::Path::new(path), &Default::default()).unwrap();
    let start = laserlines_sim::arena::interior_start(&arena.world, 0.4).unwrap();
    (arena.world, start)
}
