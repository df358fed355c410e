//! Settings of the [`Mapper`](crate::Mapper), with their units, defaults and sensible ranges.

use crate::icp::IcpParams;
use crate::se2::Se2;

/// Settings of the whole mapping pipeline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapperParams {
    /// Where the laser sits on the robot (`robot_from_sensor`): odometry poses are the
    /// robot's, scans and the mapper's poses the sensor's (default: identity).
    pub robot_from_sensor: Se2,
    /// Points farther than this from the sensor are not used for matching, m (default 30;
    /// 5..80). Long ranges fix headings well but are sparse.
    pub max_range_m: f64,
    /// Points nearer than this are not used (the robot itself), m (default 0.1).
    pub min_range_m: f64,
    /// Beams either side used to estimate a point's normal (default 3; 2..6).
    pub normal_half_window: usize,
    /// Points that support an extracted line take the line's normal
    /// ([`line_normals`](crate::cloud::line_normals); default `true`) ...
    pub line_normals: bool,
    /// ... all of them on a line whose RMS residual is this or more, m, only those without a
    /// normal of their own on a smoother one (default 0: every point of every line; `inf`:
    /// only the points without one). With ranges noisy to 1-2 % of the range the
    /// neighbourhoods of seven beams give few normals, and poor ones, and matching fails:
    /// MIT CSAIL with 2 % noise added left 566 of 1988 scans unmatched and the relations'
    /// error at 1.62 m with neighbourhood normals alone.
    pub line_normals_rms_m: f64,
    /// Scans inserted into a submap before it is finished (default 40; 10..100). A new
    /// submap starts halfway, so that one well-filled submap is always there to match on.
    pub scans_per_submap: usize,
    /// A scan is inserted into the submaps only after the robot moved this far since the
    /// last insertion, m (default 0.1) ...
    pub insert_distance_m: f64,
    /// ... or turned this far, rad (default 0.05).
    pub insert_rotation_rad: f64,
    /// Submap points are thinned to one per square voxel of this side, m (default 0.03;
    /// 0.01..0.1).
    pub voxel_m: f64,
    /// Scan-to-submap matching. Defaults: [`IcpParams`]'s, with the match allowed to move
    /// 0.5 m and 0.35 rad from its guess (the matches are retried from guesses turned by up
    /// to twice [`MapperParams::retry_rotation_rad`], and the motion's correlative search and
    /// the odometry's prior guard them; the line match is gated by the same bounds).
    pub icp: IcpParams,
    /// A match fitting at least this share of the scan's points is taken at once; a weaker
    /// one is tried again from other seeds (default 0.8).
    pub confident_fraction: f64,
    /// Rotation between the retried seeds, rad (default 0.15).
    pub retry_rotation_rad: f64,
    /// Without odometry, the motion between two scans is searched within this distance of
    /// the last motion, itself cut to this distance (and rotation), m (default 1.5) ...
    pub motion_window_m: f64,
    /// ... and this rotation, rad (default 1.0).
    pub motion_window_rad: f64,
    /// Smallest correlative score of that search (default 0.3).
    pub motion_min_score: f64,
    /// Standard deviation of odometry's translation per metre travelled (default 0.1).
    pub odometry_sigma_per_m: f64,
    /// Standard deviation of odometry's heading per radian turned (default 0.5).
    pub odometry_sigma_per_rad: f64,
    /// Floor of the odometry's translation standard deviation per scan, m (default 0.02).
    pub odometry_sigma_min_m: f64,
    /// Floor of the odometry's heading standard deviation per scan, rad (default 0.05).
    pub odometry_sigma_min_rad: f64,
    /// Factor on the scan matcher's covariance in the pose graph (default 4; its
    /// `(J^T J)^-1` ignores that consecutive matches share a submap).
    pub match_covariance_scale: f64,
    /// Loop closure.
    pub loops: LoopParams,
}

impl Default for MapperParams {
    fn default() -> Self {
        Self {
            robot_from_sensor: Se2::IDENTITY,
            max_range_m: 30.0,
            min_range_m: 0.1,
            normal_half_window: 3,
            line_normals: true,
            line_normals_rms_m: 0.0,
            scans_per_submap: 40,
            insert_distance_m: 0.1,
            insert_rotation_rad: 0.05,
            voxel_m: 0.03,
            icp: IcpParams {
                basin_translation_m: 0.5,
                basin_rotation_rad: 0.35,
                ..IcpParams::default()
            },
            confident_fraction: 0.8,
            retry_rotation_rad: 0.15,
            motion_window_m: 1.5,
            motion_window_rad: 1.0,
            motion_min_score: 0.3,
            odometry_sigma_per_m: 0.1,
            odometry_sigma_per_rad: 0.5,
            odometry_sigma_min_m: 0.02,
            odometry_sigma_min_rad: 0.05,
            match_covariance_scale: 4.0,
            loops: LoopParams::default(),
        }
    }
}

/// Settings of loop closure: which earlier submaps a scan is searched in, the search, and
/// the checks a closure must pass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoopParams {
    /// Search every this many scans (default 5; 1..20; 0 turns loop closure off).
    pub every_scans: usize,
    /// A finished submap is searched when its centre is within this distance of the scan's
    /// estimated position, m (default 12).
    pub search_radius_m: f64,
    /// Half width of the translations searched, m (default 2; must cover the drift since
    /// the last closure).
    pub linear_window_m: f64,
    /// Half width of the headings searched, rad (default 0.3).
    pub angular_window_rad: f64,
    /// Side of a search grid cell, m (default 0.1).
    pub grid_resolution_m: f64,
    /// Spread of a surface in the search grid, m (default 0.07).
    pub grid_sigma_m: f64,
    /// Max-pooled levels of the search grid (default 6: blocks of up to 32 cells).
    pub grid_levels: usize,
    /// A submap is not searched again for this many scans after a closure to it (default
    /// 30).
    pub skip_after_closure_scans: usize,
    /// Scan points farther than this are not used in the search, m (default 20).
    pub search_range_m: f64,
    /// Scan points used in the search, at most (default 180; spread evenly).
    pub search_points: usize,
    /// Smallest correlative score (mean cell value, 0..1) worth verifying (default 0.6).
    pub min_score: f64,
    /// Smallest share of the scan's points that must fit the submap after ICP (default 0.7).
    pub min_inlier_fraction: f64,
    /// Scale of the Cauchy kernel on closure edges, in standard deviations (default 3).
    pub cauchy_scale: f64,
    /// The graph is optimised after a closure once this many scans passed since the last
    /// optimisation (default 50).
    pub optimize_every_scans: usize,
}

impl Default for LoopParams {
    fn default() -> Self {
        Self {
            every_scans: 5,
            search_radius_m: 12.0,
            linear_window_m: 2.0,
            angular_window_rad: 0.3,
            grid_resolution_m: 0.1,
            grid_sigma_m: 0.07,
            grid_levels: 6,
            skip_after_closure_scans: 30,
            search_range_m: 20.0,
            search_points: 180,
            min_score: 0.6,
            min_inlier_fraction: 0.7,
            cauchy_scale: 3.0,
            optimize_every_scans: 50,
        }
    }
}
