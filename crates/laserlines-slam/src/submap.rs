//! Submaps: the surface points of a run of consecutive scans, held rigid in the frame of
//! their first scan (the *anchor*), against which later scans are matched.

use laserlines::math::Point2;

use crate::cloud::{PointCloud, SurfacePoint};
use crate::correlative::CorrelativeGrid;
use crate::se2::Se2;

/// Side of the cells of a submap's nearest-neighbour index, m.
pub const INDEX_CELL_M: f64 = 0.2;

/// A submap: points with normals in the anchor's frame.
#[derive(Debug, Clone)]
pub struct Submap {
    /// The node (scan) whose frame the submap is in.
    pub anchor: usize,
    /// Surface points, `anchor` frame, one per voxel.
    pub cloud: PointCloud,
    /// Scans inserted so far.
    pub scans: usize,
    /// True once no more scans are inserted.
    pub finished: bool,
    /// The search grid for loop closure, built when the submap is finished.
    pub grid: Option<CorrelativeGrid>,
    /// The last scan closed against this submap.
    pub last_closure: Option<usize>,
    /// Mean of the points, `anchor` frame, m.
    centre_sum: (f64, f64, usize),
}

impl Submap {
    /// An empty submap in the frame of node `anchor`.
    #[must_use]
    pub fn new(anchor: usize, voxel_m: f64, cell_m: f64) -> Self {
        Self {
            anchor,
            cloud: PointCloud::new(voxel_m, cell_m),
            scans: 0,
            finished: false,
            grid: None,
            last_closure: None,
            centre_sum: (0.0, 0.0, 0),
        }
    }

    /// Adds a scan's surface points (scan frame) seen from `anchor_from_scan`.
    pub fn insert(&mut self, anchor_from_scan: &Se2, points: &[SurfacePoint]) {
        for p in points {
            let q = SurfacePoint {
                point: anchor_from_scan.transform(p.point),
                normal: anchor_from_scan.rotate(p.normal),
            };
            if self.cloud.insert(q) {
                self.centre_sum.0 += q.point.x;
                self.centre_sum.1 += q.point.y;
                self.centre_sum.2 += 1;
            }
        }
        self.scans += 1;
    }

    /// Marks the submap finished and builds its search grid.
    pub fn finish(&mut self, resolution_m: f64, sigma_m: f64, levels: usize) {
        self.finished = true;
        let pts: Vec<Point2> = self.cloud.points().iter().map(|p| p.point).collect();
        self.grid = CorrelativeGrid::new(&pts, resolution_m, sigma_m, levels);
    }

    /// Mean of the points in the anchor frame (the origin when empty), m.
    #[must_use]
    pub fn centre(&self) -> Point2 {
        let (sx, sy, n) = self.centre_sum;
        if n == 0 {
            Point2::origin()
        } else {
            Point2::new(sx / n as f64, sy / n as f64)
        }
    }
}
