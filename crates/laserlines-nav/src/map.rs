//! The robot's own map, built from its scans placed by its own pose estimate, and the scan
//! matching that keeps that estimate from drifting.
//!
//! A real robot has its scans and its wheel odometry, nothing else; so does this map. It
//! lives in the *map frame*: the odometry frame at the start, corrected by scan matching as
//! the run goes on (the odometry drifts, about 1 m in a few minutes with the simulator's
//! default noise, more than a 1.2 m corridor allows).
//!
//! Every [`MAP_STRIDE`]-th beam of a scan enters the map. Two grids, both grown on demand
//! in steps of [`GROW_STEP`] up to [`MAX_EXTENT`]:
//!
//! - **Knowledge** ([`MAP_CELL`] = 0.1 m): each cell is [`CellState::Unknown`] until a scan
//!   says something about it, then holds evidence that moves toward *occupied* by
//!   [`HIT_STEP`] for every beam ending in it and toward *free* by [`FREE_STEP`] for every
//!   scan whose fan covers its centre (the fan from the laser through the end points of
//!   consecutive beams; a beam without a return saw nothing within its range, and its end
//!   is taken [`NO_RETURN_FREE`] along it). Cells at [`OCCUPIED_AT`] or more
//!   are occupied. The explorer's frontiers and paths come from this grid.
//! - **Surfaces** ([`SURFACE_CELL`] = 0.2 m): the end points of beams shorter than
//!   [`SURFACE_RANGE`] (where the URG-04LX's noise is under 2 cm), summed per cell (weight,
//!   mean, second moments, weighted by the inverse variance of the range noise, until the
//!   weights add up to [`SURFACE_WINDOW`]); a cell
//!   whose points lie along a line (smaller spread at most a tenth of the larger) holds that
//!   line. [`RobotMap::match_scan`] fits a scan onto these lines: point-to-line ICP, each
//!   point paired with the nearest line among its cell and the eight around it, a few
//!   Gauss-Newton rounds on the pose, with a weak prior toward the odometry's prediction so
//!   that directions a scan cannot fix (along a featureless corridor) stay with the
//!   odometry. Lines fitted to the points themselves place walls to a few millimetres
//!   wherever they fall in a cell, which a grid of cell values cannot.

use laserlines::Scan;
use laserlines::math::{Isometry2, Point2, Vector2, wrap_angle};
use nalgebra::{Matrix3, Vector3};

use crate::raster::{BeamTable, FanRaster, floor_i64};

/// Side of a cell of the surface grid, m.
pub const SURFACE_CELL: f64 = 0.2;
/// End points of beams longer than this do not enter the surface grid, m.
pub const SURFACE_RANGE: f64 = 3.0;
/// The range noise the robot assumes for its URG-04LX, m: 5 mm up to 1 m, growing as
/// 0.5 % of the range beyond (the data sheet's +-1 % read as two standard deviations).
pub const NOISE_FLOOR: f64 = 0.005;
/// A surface cell takes points until their weights (1 for a point at most 1 m away,
/// `1 / range^2` beyond) add up to this, and no more.
pub const SURFACE_WINDOW: f32 = 40.0;
/// A surface cell holds a line when the smaller spread of its points is at most this
/// fraction of the larger (variances).
pub const LINEARITY: f32 = 0.05;
/// A scan point pairs only with a line whose normal is within 30 deg of its own: the cosine.
const NORMAL_AGREEMENT: f64 = 0.866;
/// Side of a cell of the knowledge grid, m.
pub const MAP_CELL: f64 = 0.1;
/// The grids grow in whole steps of this many metres (a multiple of both cell sizes, so that
/// the grids stay aligned).
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

/// The points of one surface cell: sums of their offsets from the cell's centre, and the
/// line fitted to them.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Surface {
    n: f32,
    sx: f32,
    sy: f32,
    sxx: f32,
    sxy: f32,
    syy: f32,
    /// The scan that last touched the cell (1-based; 0: none).
    stamp: u32,
}

impl Surface {
    /// Adds a point (offset from the cell's centre) of weight `w` (the inverse variance of
    /// its range noise relative to [`NOISE_FLOOR`]'s).
    fn add(&mut self, dx: f32, dy: f32, w: f32) {
        if self.n >= SURFACE_WINDOW {
            return;
        }
        self.n += w;
        self.sx += w * dx;
        self.sy += w * dy;
        self.sxx += w * dx * dx;
        self.sxy += w * dx * dy;
        self.syy += w * dy * dy;
    }

    /// The line fitted to the points (see the [module docs](self)) for a cell centred at
    /// `centre`: its unit normal `(nx, ny)` and offset `d`, the line being `n . p = d` in
    /// the map frame; `[0, 0, 0]` when the points do not lie along a line.
    fn line(&self, centre: Point2) -> [f32; 3] {
        const NONE: [f32; 3] = [0.0; 3];
        if self.n < 2.0 {
            return NONE;
        }
        let (mx, my) = (self.sx / self.n, self.sy / self.n);
        let a = self.sxx / self.n - mx * mx;
        let b = self.sxy / self.n - mx * my;
        let c = self.syy / self.n - my * my;
        let half_sum = 0.5 * (a + c);
        let root = (0.25 * (a - c) * (a - c) + b * b).sqrt();
        let (big, small) = (half_sum + root, half_sum - root);
        if !(big > 1e-6 && small <= LINEARITY * big) {
            return NONE;
        }
        // The eigenvector of the smaller eigenvalue, from whichever row is better
        // conditioned.
        let (u, v) = if (a - small).abs() >= (c - small).abs() {
            (b, small - a)
        } else {
            (small - c, b)
        };
        let norm = u.hypot(v);
        if !(norm > 0.0 && norm.is_finite()) {
            return NONE;
        }
        let (nx, ny) = (f64::from(u / norm), f64::from(v / norm));
        let d = nx * (centre.x + f64::from(mx)) + ny * (centre.y + f64::from(my));
        [nx as f32, ny as f32, d as f32]
    }
}

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

/// A growable grid over the map frame; cell `(i, j)` spans `origin + cell * [i, i + 1] x
/// [j, j + 1]`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Grid<T> {
    pub(crate) origin: Point2,
    pub(crate) cell: f64,
    pub(crate) cols: usize,
    pub(crate) rows: usize,
    pub(crate) cells: Vec<T>,
    fill: T,
}

impl<T: Copy> Grid<T> {
    fn new(cell: f64, fill: T) -> Self {
        Self {
            origin: Point2::origin(),
            cell,
            cols: 0,
            rows: 0,
            cells: Vec::new(),
            fill,
        }
    }

    /// `p` in continuous cell units (cell `(i, j)` spans `[i, i + 1] x [j, j + 1]`).
    pub(crate) fn to_cells(&self, p: Point2) -> (f64, f64) {
        (
            (p.x - self.origin.x) / self.cell,
            (p.y - self.origin.y) / self.cell,
        )
    }

    /// The index of cell `(i, j)`, if it is in the grid.
    pub(crate) fn index_of(&self, i: i64, j: i64) -> Option<usize> {
        (i >= 0 && j >= 0 && i < self.cols as i64 && j < self.rows as i64)
            .then(|| j as usize * self.cols + i as usize)
    }

    /// The index of the cell holding `p`, if any.
    pub(crate) fn index(&self, p: Point2) -> Option<usize> {
        let (u, v) = self.to_cells(p);
        if !(u.is_finite() && v.is_finite()) {
            return None;
        }
        self.index_of(floor_i64(u), floor_i64(v))
    }

    /// The centre of cell `index`, map frame.
    pub(crate) fn centre(&self, index: usize) -> Point2 {
        let (i, j) = (index % self.cols.max(1), index / self.cols.max(1));
        Point2::new(
            self.origin.x + (i as f64 + 0.5) * self.cell,
            self.origin.y + (j as f64 + 0.5) * self.cell,
        )
    }

    /// Grows the grid to hold the box `lo..hi` (map frame), in whole [`GROW_STEP`]s on a
    /// lattice through the map origin; growth beyond [`MAX_EXTENT`] is refused (the grid
    /// stays as it is).
    fn ensure(&mut self, lo: Point2, hi: Point2) {
        if !(lo.x.is_finite() && lo.y.is_finite() && hi.x.is_finite() && hi.y.is_finite()) {
            return;
        }
        let have_lo = self.origin;
        let have_hi = Point2::new(
            self.origin.x + self.cols as f64 * self.cell,
            self.origin.y + self.rows as f64 * self.cell,
        );
        let empty = self.cols == 0 || self.rows == 0;
        if !empty
            && lo.x >= have_lo.x
            && lo.y >= have_lo.y
            && hi.x <= have_hi.x
            && hi.y <= have_hi.y
        {
            return;
        }
        let snap_lo = |v: f64| (v / GROW_STEP).floor() * GROW_STEP;
        let snap_hi = |v: f64| (v / GROW_STEP).ceil() * GROW_STEP;
        let (mut new_lo, mut new_hi) = (
            Point2::new(snap_lo(lo.x), snap_lo(lo.y)),
            Point2::new(snap_hi(hi.x), snap_hi(hi.y)),
        );
        if !empty {
            new_lo = Point2::new(new_lo.x.min(have_lo.x), new_lo.y.min(have_lo.y));
            new_hi = Point2::new(new_hi.x.max(have_hi.x), new_hi.y.max(have_hi.y));
        }
        if new_hi.x - new_lo.x > MAX_EXTENT || new_hi.y - new_lo.y > MAX_EXTENT {
            return;
        }
        let cols = ((new_hi.x - new_lo.x) / self.cell).round() as usize;
        let rows = ((new_hi.y - new_lo.y) / self.cell).round() as usize;
        let mut cells = vec![self.fill; cols * rows];
        if !empty {
            let di = ((have_lo.x - new_lo.x) / self.cell).round() as usize;
            let dj = ((have_lo.y - new_lo.y) / self.cell).round() as usize;
            for j in 0..self.rows {
                let from = j * self.cols;
                let to = (j + dj) * cols + di;
                cells[to..to + self.cols].copy_from_slice(&self.cells[from..from + self.cols]);
            }
        }
        self.origin = new_lo;
        self.cols = cols;
        self.rows = rows;
        self.cells = cells;
    }
}

/// A scan point to be matched: robot frame, with the unit normal of the scan's outline
/// there when its neighbours give one, and its weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MatchPoint {
    /// The point, robot frame, m.
    pub point: Point2,
    /// The outline's unit normal at the point, robot frame (either sense).
    pub normal: Option<Vector2>,
    /// Weight of the point, 0..1: `(sigma_0 / sigma)^2` for a range noise `sigma`, where
    /// `sigma_0` is the noise of the best points (1 for them).
    pub weight: f64,
}

/// Settings of the scan matching.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct MatchParams {
    /// Most rounds of pairing and Gauss-Newton step per scan. Default 5.
    pub iterations: usize,
    /// Points farther than this from their line in the first round are left out, m (half
    /// that in later rounds). Default 0.1.
    pub gate_m: f64,
    /// Weight of the prior toward the odometry's prediction on x and y, 1/m^2, where each
    /// paired point's distance from its line weighs 1/m^2: about (the points' noise / the
    /// odometry's error over one scan)^2, (1.5 cm / 3 mm)^2. Default 25.
    pub prior_xy: f64,
    /// Weight of the prior on the heading, 1/rad^2 in the same units: (1.5 cm / 9 mrad)^2.
    /// Default 3.
    pub prior_theta: f64,
    /// A match that moves the pose farther than this from the prediction is refused, m.
    /// Default 0.1 (the odometry errs by millimetres over one scan).
    pub max_shift_m: f64,
    /// The same for the heading, rad. Default 0.1.
    pub max_turn_rad: f64,
    /// Fewer points paired with mapped lines than this and the match is refused. Default 20.
    pub min_support: usize,
}

impl Default for MatchParams {
    fn default() -> Self {
        Self {
            iterations: 5,
            gate_m: 0.1,
            prior_xy: 25.0,
            prior_theta: 3.0,
            max_shift_m: 0.1,
            max_turn_rad: 0.1,
            min_support: 20,
        }
    }
}

/// The robot's map (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct RobotMap {
    surfaces: Grid<Surface>,
    /// The line of each surface cell, `[nx, ny, d]` (see [`Surface::line`]), apart from the
    /// sums so that the matching reads 12 bytes a cell.
    lines: Grid<[f32; 3]>,
    touched: Vec<usize>,
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
    /// Scratch: the end points of a scan and their ranges.
    ends: Vec<(Point2, f64)>,
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
            surfaces: Grid::new(SURFACE_CELL, Surface::default()),
            lines: Grid::new(SURFACE_CELL, [0.0; 3]),
            touched: Vec::new(),
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

    /// Inserts a scan taken with the laser at `map_from_laser` (see the [module
    /// docs](self)); returns how many knowledge cells it made known.
    pub fn insert_scan(&mut self, map_from_laser: &Isometry2, scan: &Scan) -> usize {
        let o = Point2::from(map_from_laser.translation.vector);
        let yaw = map_from_laser.rotation.angle();
        if !(o.x.is_finite() && o.y.is_finite() && yaw.is_finite()) {
            return 0;
        }
        let window = scan.range_window(None);
        let reach = if scan.range_max.is_finite() {
            scan.range_max.clamp(0.0, 20.0)
        } else {
            20.0
        } + 0.5;
        let r = Vector2::new(reach, reach);
        self.surfaces.ensure(o - r, o + r);
        self.lines.ensure(o - r, o + r);
        self.knowledge.ensure(o - r, o + r);
        self.centroids.ensure(o - r, o + r);
        if self.knowledge.cols == 0 {
            return 0;
        }
        self.scans += 1;
        let before = self.known;
        // The fan, knowledge-grid cell units.
        let mut poly = std::mem::take(&mut self.poly);
        poly.clear();
        poly.push(self.knowledge.to_cells(o));
        let (s_yaw, c_yaw) = yaw.sin_cos();
        let n = scan.ranges.len();
        let mut ends = std::mem::take(&mut self.ends);
        ends.clear();
        let mut beams = std::mem::take(&mut self.beams);
        let dirs = beams.get(scan.angle_min, scan.angle_increment, n);
        for (i, (&range, d)) in scan.ranges.iter().zip(dirs).enumerate() {
            // Every MAP_STRIDE-th beam, and the last (so that the fan keeps its span).
            if i % MAP_STRIDE != 0 && i + 1 != n {
                continue;
            }
            let dir = Vector2::new(c_yaw * d.x - s_yaw * d.y, s_yaw * d.x + c_yaw * d.y);
            if window.contains(range) {
                let p = o + dir * range;
                poly.push(self.knowledge.to_cells(p));
                ends.push((p, range));
            } else {
                let free = NO_RETURN_FREE.min(scan.range_max.max(0.0));
                poly.push(self.knowledge.to_cells(o + dir * free));
            }
        }
        self.beams = beams;
        let mut raster = std::mem::take(&mut self.raster);
        let (cells, cols, known) = (
            &mut self.knowledge.cells,
            self.knowledge.cols,
            &mut self.known,
        );
        raster.fill(&poly, cols, self.knowledge.rows, |row, first, last| {
            for v in &mut cells[row * cols + first..=row * cols + last] {
                if *v == 0 {
                    *v = NEUTRAL;
                    *known += 1;
                }
                *v = v.saturating_sub(FREE_STEP).max(1);
            }
        });
        self.raster = raster;
        self.poly = poly;
        // The extent holds the whole fan (the ends of beams without a return too).
        let (mut lo, mut hi) = self.extent.unwrap_or((o, o));
        for &(u, v) in &self.poly {
            let p = Point2::new(
                self.knowledge.origin.x + u * self.knowledge.cell,
                self.knowledge.origin.y + v * self.knowledge.cell,
            );
            lo = Point2::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = Point2::new(hi.x.max(p.x), hi.y.max(p.y));
        }
        self.extent = Some((lo, hi));
        let stamp = u32::try_from(self.scans).unwrap_or(u32::MAX);
        self.touched.clear();
        for &(p, range) in &ends {
            if let Some(c) = self.knowledge.index(p) {
                let v = &mut self.knowledge.cells[c];
                if *v == 0 {
                    *v = NEUTRAL;
                    self.known += 1;
                }
                *v = v.saturating_add(HIT_STEP);
                let centre = self.knowledge.centre(c);
                let sum = &mut self.centroids.cells[c];
                if sum[2] < 1000.0 {
                    sum[0] += (p.x - centre.x) as f32;
                    sum[1] += (p.y - centre.y) as f32;
                    sum[2] += 1.0;
                }
            }
            if range <= SURFACE_RANGE
                && let Some(c) = self.surfaces.index(p)
            {
                let centre = self.surfaces.centre(c);
                let cell = &mut self.surfaces.cells[c];
                // Weighted by the inverse variance of the URG-04LX's range noise (5 mm to
                // 1 m, 0.5 % of the range beyond), relative to the nearest points: a
                // cell's line comes mostly from its nearest views.
                let sigma = NOISE_FLOOR * range.max(1.0);
                let w = (NOISE_FLOOR / sigma).powi(2);
                cell.add((p.x - centre.x) as f32, (p.y - centre.y) as f32, w as f32);
                if cell.stamp != stamp {
                    cell.stamp = stamp;
                    self.touched.push(c);
                }
            }
        }
        for &c in &self.touched {
            self.lines.cells[c] = self.surfaces.cells[c].line(self.surfaces.centre(c));
        }
        self.ends = ends;
        self.known - before
    }

    /// The line nearest to `q` (map frame) among the surface cells around it whose normal is
    /// within 30 deg of `normal` (either sense; any line when `normal` is `None`):
    /// `[nx, ny, d]` (the line `n . p = d`).
    fn nearest_line(&self, q: Point2, normal: Option<Vector2>) -> Option<[f64; 3]> {
        let grid = &self.lines;
        let inv = 1.0 / grid.cell;
        let (u, v) = ((q.x - grid.origin.x) * inv, (q.y - grid.origin.y) * inv);
        if !(u.is_finite() && v.is_finite()) {
            return None;
        }
        let (i, j) = (floor_i64(u), floor_i64(v));
        let mut best: Option<(f64, [f64; 3])> = None;
        let (x0, x1) = (
            i.saturating_sub(1).max(0),
            i.saturating_add(1).min(grid.cols as i64 - 1),
        );
        let (y0, y1) = (
            j.saturating_sub(1).max(0),
            j.saturating_add(1).min(grid.rows as i64 - 1),
        );
        if x0 > x1 || y0 > y1 {
            return None;
        }
        for y in y0 as usize..=y1 as usize {
            let row = &grid.cells[y * grid.cols + x0 as usize..=y * grid.cols + x1 as usize];
            for &[nx, ny, d] in row {
                if nx == 0.0 && ny == 0.0 {
                    continue;
                }
                let (nx, ny, d) = (f64::from(nx), f64::from(ny), f64::from(d));
                if normal.is_some_and(|m| (m.x * nx + m.y * ny).abs() < NORMAL_AGREEMENT) {
                    continue;
                }
                let r = (nx * q.x + ny * q.y - d).abs();
                if best.is_none_or(|(b, _)| r < b) {
                    best = Some((r, [nx, ny, d]));
                }
            }
        }
        best.map(|(_, line)| line)
    }

    /// Fits the scan points `points` (robot frame) onto the map's lines (each point onto
    /// the nearest line whose normal agrees with its own within 30 deg), starting from and
    /// pulled toward the predicted pose `guess` (map frame); returns the matched pose, or
    /// `None` when the map cannot place the scan (too few points near mapped lines, or a
    /// match farther from the prediction than `params` allow).
    #[must_use]
    pub fn match_scan(
        &self,
        points: &[MatchPoint],
        guess: &Isometry2,
        params: &MatchParams,
    ) -> Option<Isometry2> {
        let (x0, y0, t0) = (
            guess.translation.vector.x,
            guess.translation.vector.y,
            guess.rotation.angle(),
        );
        if self.scans == 0 || !(x0.is_finite() && y0.is_finite() && t0.is_finite()) {
            return None;
        }
        let prior = Vector3::new(params.prior_xy, params.prior_xy, params.prior_theta);
        let mut xi = Vector3::new(x0, y0, t0);
        // Pairs of a point (index) and its line; made afresh in the first rounds, then kept
        // while the pose settles.
        let mut pairs: Vec<(usize, [f64; 3])> = Vec::with_capacity(points.len());
        let mut moved = true;
        for round in 0..params.iterations.max(1) {
            let (s, c) = xi.z.sin_cos();
            // Pair afresh in the first round, and in the second after a step of more than
            // a centimetre or a hundredth of a radian.
            if round == 0 || (round == 1 && moved) {
                // Pairs farther than the gate are not the same wall; the gate narrows once
                // the first step is taken.
                let gate = if round == 0 {
                    params.gate_m
                } else {
                    0.5 * params.gate_m
                };
                pairs.clear();
                for (k, m) in points.iter().enumerate() {
                    let p = m.point;
                    let q = Point2::new(c * p.x - s * p.y + xi.x, s * p.x + c * p.y + xi.y);
                    let normal = m
                        .normal
                        .map(|v| Vector2::new(c * v.x - s * v.y, s * v.x + c * v.y));
                    if let Some(line) = self.nearest_line(q, normal)
                        && (line[0] * q.x + line[1] * q.y - line[2]).abs() <= gate
                    {
                        pairs.push((k, line));
                    }
                }
            }
            // The normal equations' six distinct entries and right-hand side.
            let (mut hxx, mut hxy, mut hxt, mut hyy, mut hyt, mut htt) =
                (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
            let (mut gx, mut gy, mut gt) = (0.0, 0.0, 0.0);
            for &(k, [nx, ny, d]) in &pairs {
                let m = &points[k];
                let p = m.point;
                let qx = c * p.x - s * p.y + xi.x;
                let qy = s * p.x + c * p.y + xi.y;
                let r = nx * qx + ny * qy - d;
                // The Jacobian (nx, ny, jt): jt from turning the point about the robot.
                let jt = nx * (-s * p.x - c * p.y) + ny * (c * p.x - s * p.y);
                // Huber weight beyond 2 cm.
                let w =
                    m.weight.clamp(0.0, 1.0) * if r.abs() <= 0.02 { 1.0 } else { 0.02 / r.abs() };
                let (wx, wy, wt) = (w * nx, w * ny, w * jt);
                hxx += wx * nx;
                hxy += wx * ny;
                hxt += wx * jt;
                hyy += wy * ny;
                hyt += wy * jt;
                htt += wt * jt;
                gx -= wx * r;
                gy -= wy * r;
                gt -= wt * r;
            }
            let mut h = Matrix3::new(hxx, hxy, hxt, hxy, hyy, hyt, hxt, hyt, htt);
            let mut g = Vector3::new(gx, gy, gt);
            let off = Vector3::new(xi.x - x0, xi.y - y0, wrap_angle(xi.z - t0));
            for k in 0..3 {
                h[(k, k)] += prior[k];
                g[k] -= prior[k] * off[k];
            }
            let step = h.lu().solve(&g)?;
            if !(step.x.is_finite() && step.y.is_finite() && step.z.is_finite()) {
                return None;
            }
            xi += step;
            if round == 0 {
                moved = step.x.hypot(step.y) > 0.01 || step.z.abs() > 0.01;
            }
            if round >= 1 && step.x.abs() < 1e-4 && step.y.abs() < 1e-4 && step.z.abs() < 1e-4 {
                break;
            }
        }
        let support = pairs.len();
        let shift = (xi.x - x0).hypot(xi.y - y0);
        let turn = wrap_angle(xi.z - t0).abs();
        (support >= params.min_support
            && shift <= params.max_shift_m
            && turn <= params.max_turn_rad)
            .then(|| Isometry2::new(Vector2::new(xi.x, xi.y), wrap_angle(xi.z)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
        map.surfaces
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
