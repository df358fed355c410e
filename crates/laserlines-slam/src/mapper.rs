//! The online mapper: scan by scan, with or without odometry, a pose estimate now and a map
//! at any time.
//!
//! For every scan: predict its pose (odometry, else a search around the last motion), match
//! it onto the older of the two active submaps with point-to-line ICP, add it to the pose graph
//! with an edge from the previous scan, insert it into the active submaps when the robot
//! has moved, and every few scans search the finished submaps nearby for a loop closure
//! (branch-and-bound correlative search, verified by ICP). Accepted closures enter the graph
//! with a Cauchy kernel, and the graph is optimised.

use laserlines::math::Point2;
use laserlines::{Line, RangeWindow, Scan};
use nalgebra::Matrix3;

use crate::cloud::{SurfacePoint, line_normals, scan_normals};
use crate::correlative::{CorrelativeGrid, SearchWindow};
use crate::graph::{
    Edge, GraphError, OptimizeParams, OptimizeReport, PoseGraph, RobustKernel,
    covariance_in_parent, information_in_frame,
};
use crate::icp::{IcpError, match_points};
use crate::linemap::{LineMapParams, MapLine, build_line_map};
use crate::lines::{LineMatchParams, match_lines};
use crate::loops::{LoopOutcome, try_closure};
use crate::occupancy::{GridTooLarge, OccupancyGrid, OccupancyParams};
use crate::params::MapperParams;
use crate::se2::Se2;
use crate::submap::Submap;

/// Why [`Mapper::add_scan`] failed: a refused scan leaves the mapper as it was.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MapperError {
    /// The odometry pose given with the scan is not finite.
    #[error("scan {node}: the odometry pose is not finite")]
    OdometryNotFinite {
        /// The index the scan would have had.
        node: usize,
    },
    /// The scan's pose could not be computed as finite numbers (e.g. odometry far beyond
    /// any map).
    #[error("scan {node}: no finite pose")]
    PoseNotFinite {
        /// The index the scan would have had.
        node: usize,
    },
    /// The pose graph could not be optimised after the scan was added (the scan is kept).
    #[error(transparent)]
    Graph(#[from] GraphError),
}

/// What the mapper keeps of each scan.
#[derive(Debug, Clone)]
pub struct ScanNode {
    /// The scan's time stamp, s, when it had one.
    pub stamp: Option<f64>,
    /// Its valid points within the matching range, sensor frame, m (for the maps).
    pub points: Vec<Point2>,
    /// The lines extracted from it, sensor frame.
    pub lines: Vec<Line>,
    /// True when scan matching placed it (false: the prediction was kept).
    pub matched: bool,
}

/// What [`Mapper::add_scan`] tells about one scan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanUpdate {
    /// The scan's index (node) in the map.
    pub node: usize,
    /// `map_from_scan` now (after any optimisation this scan triggered).
    pub pose: Se2,
    /// Why matching failed, when it did (the prediction was used).
    pub match_error: Option<IcpError>,
    /// Loop closures accepted at this scan.
    pub closures_accepted: usize,
    /// Loop closures found by the search but refused by verification at this scan.
    pub closures_rejected: usize,
    /// The graph was optimised.
    pub optimized: bool,
}

/// Counts over a run.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MapperStats {
    /// Scans added.
    pub scans: usize,
    /// Scans that scan matching did not place.
    pub unmatched: usize,
    /// Loop closures accepted.
    pub closures_accepted: usize,
    /// Loop closures found by the search and refused by ICP verification.
    pub closures_rejected: usize,
    /// Submaps started.
    pub submaps: usize,
    /// Optimisations of the pose graph.
    pub optimizations: usize,
    /// Time spent optimising the pose graph, s.
    pub optimization_s: f64,
}

/// The online mapper. See the module documentation.
#[derive(Debug)]
pub struct Mapper {
    params: MapperParams,
    graph: PoseGraph,
    scans: Vec<ScanNode>,
    odometry: Vec<Option<Se2>>,
    submaps: Vec<Submap>,
    /// Indices of the active submaps, oldest first (at most two).
    active: Vec<usize>,
    last_insert: Option<Se2>,
    last_optimized: usize,
    closures_since_optimized: usize,
    stats: MapperStats,
    surface: Vec<SurfacePoint>,
}

impl Mapper {
    /// A mapper with the given settings.
    #[must_use]
    pub fn new(params: MapperParams) -> Self {
        Self {
            params,
            graph: PoseGraph::new(),
            scans: Vec::new(),
            odometry: Vec::new(),
            submaps: Vec::new(),
            active: Vec::new(),
            last_insert: None,
            last_optimized: 0,
            closures_since_optimized: 0,
            stats: MapperStats::default(),
            surface: Vec::new(),
        }
    }

    /// The settings.
    #[must_use]
    pub fn params(&self) -> &MapperParams {
        &self.params
    }

    /// Adds a scan with its lines (sensor frame) and, when the robot has it, the odometry
    /// pose at the scan's time (`odom_from_robot`, any fixed odometry frame; the mount
    /// [`MapperParams::robot_from_sensor`] turns it into the sensor's). The first scan's
    /// sensor frame is the map frame. The returned pose is the sensor's, `map_from_sensor`.
    ///
    /// # Errors
    /// [`MapperError`] for non-finite odometry, or when the pose graph cannot be optimised.
    pub fn add_scan(
        &mut self,
        scan: &Scan,
        lines: &[Line],
        odometry: Option<Se2>,
    ) -> Result<ScanUpdate, MapperError> {
        let node = self.scans.len();
        if odometry.is_some_and(|o| !o.is_finite()) {
            return Err(MapperError::OdometryNotFinite { node });
        }
        let window = scan.range_window(Some(RangeWindow::new(
            self.params.min_range_m,
            self.params.max_range_m,
        )));
        let pts = scan.points(window);
        let mut normals = scan_normals(&pts, scan.angle_increment, self.params.normal_half_window);
        if self.params.line_normals {
            line_normals(&pts, lines, self.params.line_normals_rms_m, &mut normals);
        }
        self.surface.clear();
        for (sp, n) in pts.iter().zip(&normals) {
            if let Some(normal) = n {
                self.surface.push(SurfacePoint {
                    point: sp.point,
                    normal: *normal,
                });
            }
        }
        let odometry = odometry.map(|o| o * self.params.robot_from_sensor);
        let (guess, prior) = self.predict(odometry, lines);
        let (pose, information, match_error) = match self.match_scan(guess, prior.as_ref()) {
            Ok((pose, cov)) => (
                pose,
                cov.try_inverse().unwrap_or_else(weak_information),
                None,
            ),
            Err(e) => (guess, prior.unwrap_or_else(weak_information), e),
        };
        if !pose.is_finite() || !information.iter().all(|v| v.is_finite()) {
            // Nothing was changed yet: the mapper stays as it was.
            return Err(MapperError::PoseNotFinite { node });
        }
        self.graph.add_node(pose);
        if node > 0 {
            self.add_sequential_edge(node, information)?;
        }
        self.scans.push(ScanNode {
            stamp: scan.stamp,
            points: pts.iter().map(|p| p.point).collect(),
            lines: lines.to_vec(),
            matched: match_error.is_none(),
        });
        self.odometry.push(odometry);
        self.stats.scans += 1;
        if match_error.is_some() && node > 0 {
            self.stats.unmatched += 1;
        }
        self.insert_into_submaps(node, pose);
        let (accepted, rejected) = self.search_loops(node)?;
        let optimized = if self.closures_since_optimized > 0
            && node >= self.last_optimized + self.params.loops.optimize_every_scans
        {
            self.optimize()?;
            true
        } else {
            false
        };
        Ok(ScanUpdate {
            node,
            pose: self.graph.nodes()[node],
            match_error,
            closures_accepted: accepted,
            closures_rejected: rejected,
            optimized,
        })
    }

    /// Optimises the pose graph now (the mapper does so itself after loop closures).
    ///
    /// # Errors
    /// [`GraphError`] when the normal equations cannot be solved.
    pub fn optimize(&mut self) -> Result<OptimizeReport, GraphError> {
        let start = std::time::Instant::now();
        let report = self.graph.optimize(&OptimizeParams::default())?;
        self.stats.optimization_s += start.elapsed().as_secs_f64();
        self.last_optimized = self.scans.len().saturating_sub(1);
        self.closures_since_optimized = 0;
        self.stats.optimizations += 1;
        Ok(report)
    }

    /// `map_from_robot` of scan `node` now (the sensor's pose moved back by the mount).
    #[must_use]
    pub fn robot_pose(&self, node: usize) -> Option<Se2> {
        self.poses()
            .get(node)
            .map(|p| *p * self.params.robot_from_sensor.inverse())
    }

    /// `map_from_sensor` of every scan so far, in order.
    #[must_use]
    pub fn poses(&self) -> &[Se2] {
        self.graph.nodes()
    }

    /// What was kept of every scan, in order.
    #[must_use]
    pub fn scans(&self) -> &[ScanNode] {
        &self.scans
    }

    /// The pose graph (nodes are scans).
    #[must_use]
    pub fn graph(&self) -> &PoseGraph {
        &self.graph
    }

    /// Counts over the run so far.
    #[must_use]
    pub fn stats(&self) -> MapperStats {
        self.stats
    }

    /// The occupancy grid of every scan at its current pose.
    ///
    /// # Errors
    /// [`GridTooLarge`] when the map spans more cells than `params` allow.
    pub fn occupancy_grid(&self, params: &OccupancyParams) -> Result<OccupancyGrid, GridTooLarge> {
        OccupancyGrid::build(
            self.poses()
                .iter()
                .copied()
                .zip(self.scans.iter().map(|s| &s.points[..])),
            params,
        )
    }

    /// The line map of every scan's lines at its current pose.
    #[must_use]
    pub fn line_map(&self, params: &LineMapParams) -> Vec<MapLine> {
        build_line_map(
            self.poses()
                .iter()
                .copied()
                .zip(self.scans.iter().map(|s| &s.lines[..])),
            params,
        )
    }

    /// The predicted pose of the next scan and, with odometry, the information of that
    /// prediction; without odometry, [`Mapper::search_motion`] from the last motion, cut to
    /// the search window.
    fn predict(&self, odometry: Option<Se2>, lines: &[Line]) -> (Se2, Option<Matrix3<f64>>) {
        let n = self.scans.len();
        if n == 0 {
            return (Se2::IDENTITY, None);
        }
        let last = self.graph.nodes()[n - 1];
        match (self.odometry[n - 1], odometry) {
            (Some(a), Some(b)) => {
                let delta = a.between(&b);
                let p = &self.params;
                let st = (p.odometry_sigma_per_m * delta.translation().norm())
                    .max(p.odometry_sigma_min_m);
                let sr =
                    (p.odometry_sigma_per_rad * delta.theta.abs()).max(p.odometry_sigma_min_rad);
                let info = Matrix3::from_diagonal(&nalgebra::Vector3::new(
                    1.0 / (st * st),
                    1.0 / (st * st),
                    1.0 / (sr * sr),
                ));
                (last * delta, Some(info))
            }
            _ => {
                let repeated = last.between(&self.constant_velocity().unwrap_or(last));
                let seed = within_window(repeated, &self.params);
                (last * self.search_motion(seed, lines), None)
            }
        }
    }

    /// Without odometry: the motion since the previous scan, found by a correlative search of
    /// this scan's points in a grid of the previous scan's (within
    /// [`MapperParams::motion_window_m`] and [`MapperParams::motion_window_rad`] of
    /// `seed`), else by matching this scan's lines onto the previous scan's from `seed`
    /// (accepted within the ICP's basin), else `seed` itself.
    fn search_motion(&self, seed: Se2, lines: &[Line]) -> Se2 {
        let n = self.scans.len();
        let range = self.params.loops.search_range_m;
        let prev: Vec<Point2> = self.scans[n - 1]
            .points
            .iter()
            .copied()
            .filter(|p| p.coords.norm() <= range)
            .collect();
        let step = (self.surface.len() / self.params.loops.search_points.max(1)).max(1);
        let now: Vec<Point2> = self
            .surface
            .iter()
            .map(|p| p.point)
            .filter(|p| p.coords.norm() <= range)
            .step_by(step)
            .collect();
        let l = &self.params.loops;
        if let Some(grid) =
            CorrelativeGrid::new(&prev, l.grid_resolution_m, l.grid_sigma_m, l.grid_levels)
        {
            let window = SearchWindow {
                linear_m: self.params.motion_window_m,
                angular_rad: self.params.motion_window_rad,
            };
            if let Some(found) = grid.search(&now, seed, window, self.params.motion_min_score) {
                return found.pose;
            }
        }
        let basin = &self.params.icp;
        match match_lines(
            &self.scans[n - 1].lines,
            lines,
            seed,
            &LineMatchParams::default(),
        ) {
            Some(m)
                if m.pose.distance(&seed) < basin.basin_translation_m
                    && laserlines::math::angle_diff(m.pose.theta, seed.theta)
                        < basin.basin_rotation_rad =>
            {
                m.pose
            }
            _ => seed,
        }
    }

    /// Matches the current surface points onto the reference submap from `guess`: the pose
    /// and the match's covariance in the map frame, or why it failed.
    ///
    /// A match that fits fewer than [`MapperParams::confident_fraction`] of the points is
    /// tried again from the constant-velocity prediction and from the guess turned by
    /// `+-retry_rotation_rad` and twice that; the best fit wins.
    fn match_scan(
        &self,
        guess: Se2,
        prior: Option<&Matrix3<f64>>,
    ) -> Result<(Se2, Matrix3<f64>), Option<IcpError>> {
        let &s = self.active.first().ok_or(None)?;
        let sub = &self.submaps[s];
        let anchor = self.graph.nodes()[sub.anchor];
        let local_guess = anchor.between(&guess);
        let icp = &self.params.icp;
        let mut best = match_points(&sub.cloud, &self.surface, local_guess, prior, icp);
        if best
            .as_ref()
            .is_ok_and(|r| r.inlier_fraction >= self.params.confident_fraction)
        {
            return best.map(|r| self.to_map(&anchor, &r)).map_err(Some);
        }
        let step = self.params.retry_rotation_rad;
        let mut seeds = vec![];
        if let Some(cv) = self.constant_velocity() {
            seeds.push(anchor.between(&cv));
        }
        for k in [-2.0, -1.0, 1.0, 2.0] {
            seeds.push(Se2::new(
                local_guess.x,
                local_guess.y,
                local_guess.theta + k * step,
            ));
        }
        for seed in seeds {
            let r = match_points(&sub.cloud, &self.surface, seed, None, icp);
            let better = match (&r, &best) {
                (Ok(a), Ok(b)) => a.inlier_fraction > b.inlier_fraction + 0.02,
                (Ok(_), Err(_)) => true,
                _ => false,
            };
            if better {
                best = r;
            }
        }
        best.map(|r| self.to_map(&anchor, &r)).map_err(Some)
    }

    /// A match in a submap as a map-frame pose and covariance.
    fn to_map(&self, anchor: &Se2, r: &crate::icp::IcpResult) -> (Se2, Matrix3<f64>) {
        let cov =
            covariance_in_parent(&r.covariance, anchor.theta) * self.params.match_covariance_scale;
        (*anchor * r.pose, cov)
    }

    /// The last motion repeated from the last pose.
    fn constant_velocity(&self) -> Option<Se2> {
        let nodes = self.graph.nodes();
        let n = nodes.len();
        (n >= 2).then(|| nodes[n - 1] * nodes[n - 2].between(&nodes[n - 1]))
    }

    /// The edge from the previous scan to `node`: the relative pose of the two estimates,
    /// with the matcher's or the odometry's information (`information` in the map frame).
    fn add_sequential_edge(
        &mut self,
        node: usize,
        information: Matrix3<f64>,
    ) -> Result<(), GraphError> {
        let prev = self.graph.nodes()[node - 1];
        let cur = self.graph.nodes()[node];
        self.graph.add_edge(Edge {
            from: node - 1,
            to: node,
            measurement: prev.between(&cur),
            information: information_in_frame(&information, prev.theta),
            kernel: RobustKernel::None,
        })?;
        Ok(())
    }

    /// Inserts the scan into the active submaps when the robot moved enough, starting and
    /// finishing submaps as they fill.
    fn insert_into_submaps(&mut self, node: usize, pose: Se2) {
        let moved = self.last_insert.is_none_or(|last| {
            last.distance(&pose) >= self.params.insert_distance_m
                || laserlines::math::angle_diff(last.theta, pose.theta)
                    >= self.params.insert_rotation_rad
        });
        if !moved {
            return;
        }
        self.last_insert = Some(pose);
        let half = (self.params.scans_per_submap / 2).max(1);
        if self
            .active
            .last()
            .is_none_or(|&s| self.submaps[s].scans >= half)
        {
            self.submaps.push(Submap::new(
                node,
                self.params.voxel_m,
                crate::submap::INDEX_CELL_M,
            ));
            self.active.push(self.submaps.len() - 1);
            self.stats.submaps += 1;
        }
        for &s in &self.active {
            let anchor = self.graph.nodes()[self.submaps[s].anchor];
            self.submaps[s].insert(&anchor.between(&pose), &self.surface);
        }
        if self.active.len() > 1
            && self.submaps[self.active[0]].scans >= self.params.scans_per_submap
        {
            let s = self.active.remove(0);
            let l = &self.params.loops;
            self.submaps[s].finish(l.grid_resolution_m, l.grid_sigma_m, l.grid_levels);
        }
    }

    /// Searches the finished submaps near scan `node` for loop closures (every
    /// `loops.every_scans` scans); returns (accepted, rejected).
    fn search_loops(&mut self, node: usize) -> Result<(usize, usize), GraphError> {
        let every = self.params.loops.every_scans;
        if every == 0 || !node.is_multiple_of(every) || self.surface.is_empty() {
            return Ok((0, 0));
        }
        let pose = self.graph.nodes()[node];
        let l = &self.params.loops;
        let near: Vec<Point2> = self
            .surface
            .iter()
            .map(|p| p.point)
            .filter(|p| p.coords.norm() <= l.search_range_m)
            .collect();
        let step = (near.len() / l.search_points.max(1)).max(1);
        let search: Vec<Point2> = near.into_iter().step_by(step).collect();
        let (mut accepted, mut rejected) = (0, 0);
        for s in 0..self.submaps.len() {
            let sub = &self.submaps[s];
            if !sub.finished
                || sub
                    .last_closure
                    .is_some_and(|n| node < n + self.params.loops.skip_after_closure_scans)
            {
                continue;
            }
            let anchor = self.graph.nodes()[sub.anchor];
            if (anchor.transform(sub.centre()) - Point2::new(pose.x, pose.y)).norm()
                > self.params.loops.search_radius_m
            {
                continue;
            }
            let from = sub.anchor;
            match try_closure(sub, &anchor, &pose, &search, &self.surface, &self.params) {
                LoopOutcome::Accepted(edge) => {
                    self.submaps[s].last_closure = Some(node);
                    self.graph.add_edge(Edge {
                        from,
                        to: node,
                        ..edge
                    })?;
                    accepted += 1;
                }
                LoopOutcome::Rejected => rejected += 1,
                LoopOutcome::NotFound => {}
            }
        }
        self.stats.closures_accepted += accepted;
        self.stats.closures_rejected += rejected;
        self.closures_since_optimized += accepted;
        Ok((accepted, rejected))
    }
}

/// Information of a relative pose nobody measured well (1 m, 1 rad).
fn weak_information() -> Matrix3<f64> {
    Matrix3::identity()
}

/// The last motion as the seed of the next motion search without odometry: its translation
/// shortened to [`MapperParams::motion_window_m`] and its rotation to
/// [`MapperParams::motion_window_rad`]. A motion the search found is otherwise repeated and
/// searched again a window further, scan after scan: a wrong one grew to 10-13 m per scan
/// on the Freiburg campus log and ran the map off by a kilometre.
fn within_window(motion: Se2, params: &MapperParams) -> Se2 {
    let t = motion.translation().norm();
    let k = if t > params.motion_window_m {
        params.motion_window_m / t
    } else {
        1.0
    };
    let limit = params.motion_window_rad;
    Se2::new(
        motion.x * k,
        motion.y * k,
        motion.theta.clamp(-limit, limit),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_repeated_motion_is_cut_to_the_search_window() {
        let p = MapperParams::default();
        let (m, rad) = (p.motion_window_m, p.motion_window_rad);
        let small = Se2::new(0.3, -0.4, 0.2);
        assert_eq!(within_window(small, &p), small);
        let cut = within_window(Se2::new(-6.0, 8.0, -3.0), &p);
        assert!((cut.x + 0.6 * m).abs() < 1e-12 && (cut.y - 0.8 * m).abs() < 1e-12);
        assert_eq!(cut.theta, -rad);
    }
}
