//! The robot's own map, built from its scans placed by its own pose estimate (the scan
//! matching of `laserlines-slam`'s [`Tracker`](laserlines_slam::Tracker)), for the explorer's
//! frontiers, planner and safety layer.
//!
//! A real robot has its scans and its wheel odometry, nothing else; so does this map. It
//! lives in the *map frame*: the odometry frame at the start, corrected by scan matching as
//! the run goes on (the odometry drifts, about 1 m in a few minutes with the simulator's
//! default noise, more than a 1.2 m corridor allows).
//!
//! Every [`MAP_STRIDE`]-th beam of a scan enters the map, a grid of [`MAP_CELL`] = 0.1 m
//! cells grown on demand in steps of [`GROW_STEP`] up to [`MAX_EXTENT`]. Each cell is
//! [`CellState::Unknown`] until a scan says something about it, then holds evidence that
//! moves toward *occupied* by [`HIT_STEP`] for every beam ending in it and toward *free* by
//! [`FREE_STEP`] for every scan whose fan covers its centre (the fan from the laser through
//! the end points of consecutive beams; a beam without a return saw nothing within its
//! range, and its end is taken [`NO_RETURN_FREE`] along it). Cells at [`OCCUPIED_AT`] or
//! more are occupied. Each cell also sums the end points in it, so that walls are known
//! better than to a cell ([`RobotMap::occupied_near`]).

mod grid;
mod insert;

use laserlines::math::{Point2, Vector2};

use crate::raster::{BeamTable, FanRaster, floor_i64};
pub(crate) use grid::Grid;

/// Side of a cell of the map, m.
pub const MAP_CELL: f64 = 0.1;
/// The grids grow in whole steps of this many metres (a multiple of the cell size, so that
/// the knowledge grid and its centroids stay aligned).
pub const GROW_STEP: f64 = 4.0;
/// Largest extent of the map along either axis, m: scan points beyond are not mapped.
pub const MAX_EXTENT: f64 = 200.0;
/// Every this many beams of a scan enter the map: 0.7 deg apart for the URG-04LX, 2.5 cm
/// at 2 m, still several per cell of the knowledge grid.
pub const MAP_STRIDE: usize = 2;
/// How far a beam without a return counts as having seen free space, m (the URG-04LX reports
/// no return when nothing is within its 5.6 m; a real one also for dark or glancing
/// surfaces, hence less than the full range).
pub const NO_RETURN_FREE: f64 = 3.0;
/// Evidence of a cell seen for the first time, before its first update.
pub const NEUTRAL: u8 = 128;
/// Evidence added by one beam ending in a cell.
pub const HIT_STEP: u8 = 40;
/// Evidence removed by one scan whose fan covers a cell's centre.
pub const FREE_STEP: u8 = 6;
/// Evidence at which a cell is occupied.
pub const OCCUPIED_AT: u8 = 150;

/// What the robot knows about a cell of its map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CellState {
    /// No scan has said anything about it.
    Unknown,
    /// Seen through more than hit.
    Free,
    /// Hit more than seen through.
    Occupied,
}

impl CellState {
    fn of(evidence: u8) -> Self {
        match evidence {
            0 => Self::Unknown,
            e if e >= OCCUPIED_AT => Self::Occupied,
            _ => Self::Free,
        }
    }
}

/// The robot's map (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct RobotMap {
    knowledge: Grid<u8>,
    /// Per knowledge cell: the sum of the end points in it (offsets from its centre) and
    /// their count, so that walls are known better than to a cell.
    centroids: Grid<[f32; 3]>,
    known: usize,
    scans: usize,
    /// The box holding every scan's laser position and end points, map frame.
    extent: Option<(Point2, Point2)>,
    raster: FanRaster,
    poly: Vec<(f64, f64)>,
    /// Scratch: the end points of a scan.
    ends: Vec<Point2>,
    /// The scan's beam directions, laser frame.
    beams: BeamTable,
}

impl Default for RobotMap {
    fn default() -> Self {
        Self::new()
    }
}

impl RobotMap {
    /// An empty map.
    #[must_use]
    pub fn new() -> Self {
        Self {
            knowledge: Grid::new(MAP_CELL, 0),
            centroids: Grid::new(MAP_CELL, [0.0; 3]),
            known: 0,
            scans: 0,
            extent: None,
            raster: FanRaster::default(),
            poly: Vec::new(),
            ends: Vec::new(),
            beams: BeamTable::default(),
        }
    }

    /// Scans inserted so far.
    #[must_use]
    pub fn scans(&self) -> usize {
        self.scans
    }

    /// Knowledge cells no longer unknown.
    #[must_use]
    pub fn known_cells(&self) -> usize {
        self.known
    }

    /// What the map knows about the point `p` (map frame).
    #[must_use]
    pub fn state(&self, p: Point2) -> CellState {
        self.knowledge.index(p).map_or(CellState::Unknown, |c| {
            CellState::of(self.knowledge.cells[c])
        })
    }

    /// The centres of all occupied knowledge cells, map frame (for pictures).
    #[must_use]
    pub fn occupied_cells(&self) -> Vec<Point2> {
        (0..self.knowledge.cells.len())
            .filter(|&c| self.knowledge.cells[c] >= OCCUPIED_AT)
            .map(|c| self.knowledge.centre(c))
            .collect()
    }

    /// Appends the occupied knowledge cells within `reach` of `p` (map frame) to `out`:
    /// the mean of the end points in each (the cell's centre if it has none).
    pub fn occupied_near(&self, p: Point2, reach: f64, out: &mut Vec<Point2>) {
        let (u, v) = self.knowledge.to_cells(p);
        if !(u.is_finite() && v.is_finite() && reach.is_finite()) {
            return;
        }
        // No farther than the grid reaches (a huge `reach` would only loop over nothing).
        let span = self.knowledge.cols.max(self.knowledge.rows) as f64;
        let r = (reach / self.knowledge.cell).ceil().clamp(0.0, span) as i64;
        let (i, j) = (floor_i64(u), floor_i64(v));
        for dj in -r..=r {
            for di in -r..=r {
                if let Some(c) = self
                    .knowledge
                    .index_of(i.saturating_add(di), j.saturating_add(dj))
                    && self.knowledge.cells[c] >= OCCUPIED_AT
                {
                    let [sx, sy, n] = self.centroids.cells[c];
                    let q = self.knowledge.centre(c)
                        + if n > 0.0 {
                            Vector2::new(f64::from(sx / n), f64::from(sy / n))
                        } else {
                            Vector2::zeros()
                        };
                    if (q - p).norm_squared() <= reach * reach {
                        out.push(q);
                    }
                }
            }
        }
    }

    /// Unknown knowledge cells among the `(2 radius + 1)^2` cells around the one holding `p`
    /// (cells outside the grid count as unknown).
    #[must_use]
    pub fn unknown_around(&self, p: Point2, radius: usize) -> usize {
        let (u, v) = self.knowledge.to_cells(p);
        if !(u.is_finite() && v.is_finite()) {
            return 0;
        }
        let (i, j) = (floor_i64(u), floor_i64(v));
        let r = radius as i64;
        let mut unknown = 0;
        for dj in -r..=r {
            for di in -r..=r {
                let known = self
                    .knowledge
                    .index_of(i.saturating_add(di), j.saturating_add(dj))
                    .is_some_and(|c| self.knowledge.cells[c] != 0);
                unknown += usize::from(!known);
            }
        }
        unknown
    }

    /// The box holding every scan's laser position and end points so far, map frame.
    #[must_use]
    pub fn extent(&self) -> Option<(Point2, Point2)> {
        self.extent
    }

    /// The knowledge grid, for the planner.
    pub(crate) fn knowledge(&self) -> &Grid<u8> {
        &self.knowledge
    }

    /// The state of knowledge cell `index`.
    pub(crate) fn state_at(&self, index: usize) -> CellState {
        CellState::of(self.knowledge.cells[index])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use laserlines::Scan;
    use laserlines::math::Isometry2;

    /// A wall across the laser's view at x = 3 (beams from -60 to 60 deg, 0.5 deg apart).
    fn wall_scan() -> Scan {
        let inc = 0.5_f64.to_radians();
        let min = -60.0_f64.to_radians();
        let ranges = (0..241)
            .map(|i| 3.0 / (min + f64::from(i) * inc).cos())
            .collect();
        Scan::new(min, inc, 0.02, 5.6, ranges).unwrap()
    }

    #[test]
    fn growing_the_grids_keeps_what_they_hold() {
        let mut map = RobotMap::new();
        let newly = map.insert_scan(&Isometry2::identity(), &wall_scan());
        assert!(newly > 100, "{newly}");
        let wall = [Point2::new(2.95, 0.3), Point2::new(3.05, 0.3)];
        assert_eq!(map.state(Point2::new(1.0, 0.0)), CellState::Free);
        assert!(wall.iter().any(|&p| map.state(p) == CellState::Occupied));
        map.knowledge
            .ensure(Point2::new(-30.0, -30.0), Point2::new(30.0, 30.0));
        assert_eq!(map.state(Point2::new(1.0, 0.0)), CellState::Free);
        assert!(wall.iter().any(|&p| map.state(p) == CellState::Occupied));
        assert_eq!(map.knowledge.origin, Point2::new(-32.0, -32.0));
        // Beyond the largest extent nothing grows.
        let cols = map.knowledge.cols;
        map.knowledge
            .ensure(Point2::new(0.0, 0.0), Point2::new(500.0, 1.0));
        assert_eq!(map.knowledge.cols, cols);
    }
}
