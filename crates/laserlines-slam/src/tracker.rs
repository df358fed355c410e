//! Tracking: a robot's pose at every scan, at once, by matching the scan onto one map of
//! everything seen so far (scan-to-map matching), seeded and held by the wheel odometry.
//!
//! Where the [`Mapper`](crate::Mapper) keeps a pose graph whose poses move when a loop
//! closes, the tracker gives each scan one pose that never moves afterwards: what a robot
//! that plans on its own map as it drives needs. It is made for small worlds seen again
//! and again (a building floor, a rescue arena): the map is one [`SurfaceMap`] in the map
//! frame, so that coming back to a place matches onto what was seen there before.
//!
//! For every scan: every [`TrackerParams::beam_stride`]-th beam within range becomes a point
//! with its normal ([`scan_normals`]); the odometry's motion since the previous scan
//! predicts the pose; point-to-line ICP ([`match_points`]) fits the points onto the map,
//! pulled toward the prediction by a prior ([`TrackerParams::odometry_sigma_m`],
//! [`TrackerParams::odometry_sigma_rad`]) so that directions the scan cannot fix (along a
//! featureless corridor) stay with the odometry. A match the ICP cannot vouch for keeps the
//! prediction. Every [`TrackerParams::insert_every`]-th scan's near points then enter the
//! map at the pose found, weighted by the inverse variance of their range noise.

use laserlines::math::{Point2, Vector2};
use laserlines::{RangeWindow, Scan, ScanPoint};
use nalgebra::{Matrix3, Vector3};

use crate::cloud::{SurfacePoint, scan_normals};
use crate::icp::{IcpError, IcpParams, IcpResult, match_points};
use crate::se2::Se2;
use crate::surface_map::SurfaceMap;

/// Settings of the [`Tracker`], with the defaults for a URG-04LX on a small indoor robot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackerParams {
    /// Where the laser sits on the robot (`robot_from_sensor`): odometry and the tracker's
    /// poses are the robot's, scans the sensor's (default: identity).
    pub robot_from_sensor: Se2,
    /// Every this many beams give a point (default 4: 1.4 deg apart on a URG-04LX, about 170
    /// points a scan; a stride rather than a spacing, so that the choice does not depend on
    /// the points' noise).
    pub beam_stride: usize,
    /// Points nearer than this are left out (the robot itself), m (default 0.1).
    pub min_range_m: f64,
    /// Points farther than this are not matched, m (default 5).
    pub max_range_m: f64,
    /// Points farther than this do not enter the map, m (default 4.5: the URG-04LX's noise
    /// is 2.2 cm there, and such points enter with a twentieth of a near point's weight; far
    /// walls hold the map's heading where the near ones are short).
    pub insert_range_m: f64,
    /// Points either side used to estimate a point's normal (default 2).
    pub normal_half_window: usize,
    /// Every this many scans enter the map (default 2; all are matched). The first always
    /// does.
    pub insert_every: usize,
    /// Side of a voxel of the map, m (default 0.05).
    pub voxel_m: f64,
    /// A voxel averages its points until their weights (1 for a point within 1 m, `1 /
    /// range^2` beyond) add up to this (default 40).
    pub voxel_weight: f64,
    /// Largest extent of the map along either axis, m (default 200).
    pub max_extent_m: f64,
    /// Standard deviation of the odometry's translation over one scan, m (default 0.003):
    /// the prior's weight.
    pub odometry_sigma_m: f64,
    /// Standard deviation of the odometry's heading over one scan, rad (default 0.009).
    pub odometry_sigma_rad: f64,
    /// The matching. Defaults for tracking: pairs within 0.1 m (the map's grid finds them
    /// within that of a cell's centre), at most 5 rounds, converged at steps under 1 mm and
    /// 1 mrad (2 to 3 rounds on simulated URG-04LX runs), Cauchy scale 2 cm, noise 1.5 cm,
    /// at least 20 pairs, no least share, and a match farther than 0.1 m or 0.1 rad from the
    /// prediction refused (the odometry errs by millimetres over one scan).
    pub icp: IcpParams,
}

impl Default for TrackerParams {
    fn default() -> Self {
        Self {
            robot_from_sensor: Se2::IDENTITY,
            beam_stride: 4,
            min_range_m: 0.1,
            max_range_m: 5.0,
            insert_range_m: 4.5,
            normal_half_window: 2,
            insert_every: 2,
            voxel_m: 0.05,
            voxel_weight: 40.0,
            max_extent_m: 200.0,
            odometry_sigma_m: 0.003,
            odometry_sigma_rad: 0.009,
            icp: IcpParams {
                max_correspondence_m: 0.1,
                cauchy_scale_m: 0.02,
                max_iterations: 5,
                converge_translation_m: 1e-3,
                converge_rotation_rad: 1e-3,
                noise_m: 0.015,
                inlier_distance_m: 0.05,
                min_inliers: 20,
                min_inlier_fraction: 0.0,
                basin_translation_m: 0.1,
                basin_rotation_rad: 0.1,
                ..IcpParams::default()
            },
        }
    }
}

/// What [`Tracker::add_scan`] tells about one scan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackUpdate {
    /// The scan's index (from 0).
    pub scan: usize,
    /// `map_from_robot` at the scan.
    pub pose: Se2,
    /// The match, when the map placed the scan (else the odometry's prediction was kept).
    pub matched: Option<IcpResult>,
    /// Why the map did not place the scan, when it tried (`None` for the first scan).
    pub match_error: Option<IcpError>,
    /// The scan entered the map.
    pub inserted: bool,
}

/// Why [`Tracker::add_scan`] refused a scan (the tracker stays as it was).
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum TrackerError {
    /// The odometry pose is not finite.
    #[error("scan {scan}: the odometry pose is not finite")]
    OdometryNotFinite {
        /// The index the scan would have had.
        scan: usize,
    },
    /// The pose could not be computed as finite numbers (odometry far beyond any map).
    #[error("scan {scan}: no finite pose")]
    PoseNotFinite {
        /// The index the scan would have had.
        scan: usize,
    },
}

/// The tracker (see the [module docs](self)).
#[derive(Debug, Clone)]
pub struct Tracker {
    params: TrackerParams,
    map: SurfaceMap,
    map_from_odom: Se2,
    pose: Se2,
    scans: usize,
    unmatched: usize,
    /// The beam directions of the last scan's geometry: `(angle_min, increment, n)` and
    /// the unit vectors of every `beam_stride`-th beam.
    beams: ((f64, f64, usize), Vec<Vector2>),
    points: Vec<ScanPoint>,
    /// The scan's points with a normal, robot frame, and their ranges.
    surface: Vec<SurfacePoint>,
    ranges: Vec<f64>,
}

impl Tracker {
    /// A tracker with an empty map. The map frame is the odometry frame at the start: the
    /// first scan's pose is its odometry pose.
    #[must_use]
    pub fn new(params: TrackerParams) -> Self {
        Self {
            map: SurfaceMap::new(
                params.voxel_m,
                params.icp.max_correspondence_m,
                params.voxel_weight,
                params.max_extent_m,
            ),
            params,
            map_from_odom: Se2::IDENTITY,
            pose: Se2::IDENTITY,
            scans: 0,
            unmatched: 0,
            beams: ((f64::NAN, f64::NAN, 0), Vec::new()),
            points: Vec::new(),
            surface: Vec::new(),
            ranges: Vec::new(),
        }
    }

    /// The settings.
    #[must_use]
    pub fn params(&self) -> &TrackerParams {
        &self.params
    }

    /// The map matched onto: surface points in the map frame.
    #[must_use]
    pub fn map(&self) -> &SurfaceMap {
        &self.map
    }

    /// `map_from_robot` at the last scan (the identity before the first).
    #[must_use]
    pub fn pose(&self) -> Se2 {
        self.pose
    }

    /// `map_from_odom`: the correction the matching has made to the odometry so far.
    #[must_use]
    pub fn map_from_odom(&self) -> Se2 {
        self.map_from_odom
    }

    /// Scans added.
    #[must_use]
    pub fn scans(&self) -> usize {
        self.scans
    }

    /// Scans after the first that the map did not place (their pose is the odometry's
    /// prediction).
    #[must_use]
    pub fn unmatched(&self) -> usize {
        self.unmatched
    }

    /// Places a scan: `odom_from_robot` is the wheel odometry's pose at the scan's time (any
    /// fixed odometry frame).
    ///
    /// # Errors
    /// [`TrackerError`] for non-finite odometry, or odometry so far out that no finite pose
    /// follows; the tracker stays as it was.
    pub fn add_scan(
        &mut self,
        scan: &Scan,
        odom_from_robot: Se2,
    ) -> Result<TrackUpdate, TrackerError> {
        let index = self.scans;
        if !odom_from_robot.is_finite() {
            return Err(TrackerError::OdometryNotFinite { scan: index });
        }
        let predicted = self.map_from_odom * odom_from_robot;
        if !predicted.is_finite() {
            return Err(TrackerError::PoseNotFinite { scan: index });
        }
        self.scan_surface(scan);
        let (pose, matched, match_error) = if index == 0 {
            (predicted, None, None)
        } else {
            match self.match_scan(predicted) {
                Ok(r) => (r.pose, Some(r), None),
                Err(e) => (predicted, None, Some(e)),
            }
        };
        let map_from_odom = pose * odom_from_robot.inverse();
        if !map_from_odom.is_finite() {
            return Err(TrackerError::PoseNotFinite { scan: index });
        }
        self.unmatched += usize::from(index > 0 && matched.is_none());
        self.pose = pose;
        self.map_from_odom = map_from_odom;
        let inserted = index.is_multiple_of(self.params.insert_every.max(1));
        if inserted {
            self.insert(pose);
        }
        self.scans += 1;
        Ok(TrackUpdate {
            scan: index,
            pose,
            matched,
            match_error,
            inserted,
        })
    }

    /// The scan's points with normals, robot frame, into `surface` (and their ranges into
    /// `ranges`).
    fn scan_surface(&mut self, scan: &Scan) {
        let p = &self.params;
        let stride = p.beam_stride.max(1);
        let geometry = (scan.angle_min, scan.angle_increment, scan.ranges.len());
        if self.beams.0 != geometry {
            let step = scan.angle_increment * stride as f64;
            self.beams = (
                geometry,
                (0..scan.ranges.len().div_ceil(stride))
                    .map(|k| {
                        let (s, c) = (scan.angle_min + step * k as f64).sin_cos();
                        Vector2::new(c, s)
                    })
                    .collect(),
            );
        }
        let window = scan.range_window(Some(RangeWindow::new(p.min_range_m, p.max_range_m)));
        self.points.clear();
        for (k, dir) in self.beams.1.iter().enumerate() {
            let index = k * stride;
            let Some(&range) = scan.ranges.get(index) else {
                break;
            };
            if window.contains(range) {
                self.points.push(ScanPoint {
                    index,
                    range,
                    angle: scan.angle_min + scan.angle_increment * index as f64,
                    point: Point2::from(dir * range),
                });
            }
        }
        let normals = scan_normals(
            &self.points,
            scan.angle_increment * stride as f64,
            p.normal_half_window,
        );
        self.surface.clear();
        self.ranges.clear();
        let mount = p.robot_from_sensor;
        for (sp, n) in self.points.iter().zip(normals) {
            if let Some(normal) = n {
                self.surface.push(SurfacePoint {
                    point: mount.transform(sp.point),
                    normal: mount.rotate(normal),
                });
                self.ranges.push(sp.range);
            }
        }
    }

    /// ICP of the scan's points onto the map from `predicted`, held toward it by the
    /// odometry's prior.
    fn match_scan(&self, predicted: Se2) -> Result<IcpResult, IcpError> {
        let p = &self.params;
        let (sm, sr) = (p.odometry_sigma_m.max(1e-9), p.odometry_sigma_rad.max(1e-9));
        let prior = Matrix3::from_diagonal(&Vector3::new(
            1.0 / (sm * sm),
            1.0 / (sm * sm),
            1.0 / (sr * sr),
        ));
        match_points(&self.map, &self.surface, predicted, Some(&prior), &p.icp)
    }

    /// Adds the scan's near points to the map at `map_from_robot`, each weighted by the
    /// inverse variance of its range noise relative to a point within 1 m.
    fn insert(&mut self, map_from_robot: Se2) {
        let max = self.params.insert_range_m;
        for (s, &range) in self.surface.iter().zip(&self.ranges) {
            if range > max {
                continue;
            }
            let weight = 1.0 / range.max(1.0).powi(2);
            self.map.insert(
                SurfacePoint {
                    point: map_from_robot.transform(s.point),
                    normal: map_from_robot.rotate(s.normal),
                },
                weight,
            );
        }
    }
}
