//! Ground-truth coverage: how much of the arena the laser has seen.
//!
//! The world is laid on a grid of [`COVERAGE_CELL`] = 0.1 m cells (its bounding box and 1 m
//! around it). A cell is *free for the robot* when its centre is at least the footprint's
//! circumradius (0.32 m for NAJI V) from every wall and disc: there the robot fits in any
//! heading. The *arena* is what its walls enclose once gaps up to a wall element wide are
//! closed ([`ArenaOutline`]); when that does not enclose the start
//! ([`CoverageRegion::Bounds`]: an arena open at its edges, a start outside), the bounding
//! box of the arena's largest group of walls and discs. Coverage is taken over the arena's
//! *floor*: its largest connected group of free cells (the floor a robot explores, with the
//! closed rooms no robot enters or sees left out), and the group of the start's cell when
//! that is another one. A start in a small pocket therefore covers little of the arena
//! however well the pocket is seen.
//!
//! A cell is *seen* when its centre lies in the area one scan's beams swept: the fan from
//! the laser through the end points of consecutive beams (noise-free ranges; the maximum
//! range where a beam hit nothing). With the URG-04LX's 0.35 deg between beams,
//! neighbouring beams end at most 3.4 cm apart at its 5.6 m range, so this is the area the
//! beams crossed, filled by scan lines instead of walked beam by beam. Coverage is the
//! fraction of the arena's free cells that are seen; the same fraction of the cells the
//! robot can reach from its start (free cells connected to it) is kept as well.
//!
//! This is the evaluation's ground truth: the explorer never reads it.

use laserlines::math::{Isometry2, Point2, Vector2};
use laserlines_sim::World;
use laserlines_sim::arena::ArenaOutline;
use laserlines_sim::cells::{clear_of, extent, flood4};
use laserlines_sim::index::WorldIndex;

use laserlines_nav::raster::{BeamTable, FanRaster};

/// Side of a coverage cell, m.
pub const COVERAGE_CELL: f64 = 0.1;

/// Margin of the grid around the world's bounding box, m.
const GRID_MARGIN: f64 = 1.0;

/// The most cells of the grid on a side (200 m): a run in a larger world is refused
/// ([`CoverageGrid::too_large`]).
pub const MAX_COVERAGE_CELLS: usize = 2000;

/// The grid's lower-left corner and its columns and rows (not clamped) for `world` and a
/// start at `start`.
fn grid_size(world: &World, start: Point2) -> (Point2, f64, f64) {
    let obstacles = world
        .walls
        .iter()
        .flat_map(|w| [w.a, w.b])
        .chain(world.discs.iter().map(|d| d.centre));
    let (lo, hi) = extent(obstacles.chain([start])).unwrap_or((Point2::origin(), Point2::origin()));
    let origin = Point2::new(lo.x - GRID_MARGIN, lo.y - GRID_MARGIN);
    let cols = ((hi.x - origin.x + GRID_MARGIN) / COVERAGE_CELL).ceil();
    let rows = ((hi.y - origin.y + GRID_MARGIN) / COVERAGE_CELL).ceil();
    (origin, cols, rows)
}

/// What coverage is taken over (see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CoverageRegion {
    /// The free area the arena's walls enclose, gaps up to a wall element closed (they
    /// enclose the start).
    Enclosed,
    /// The free area inside the bounding box of the arena's largest group of walls and
    /// discs (they do not enclose the start).
    Bounds,
}

impl CoverageRegion {
    /// `enclosed` or `bounds`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Enclosed => "enclosed",
            Self::Bounds => "bounds",
        }
    }
}

/// The coverage grid of one run (see the [module docs](self)).
#[derive(Debug, Clone)]
pub struct CoverageGrid {
    origin: Point2,
    cols: usize,
    rows: usize,
    region_kind: CoverageRegion,
    /// Cells inside the arena (whatever their clearance).
    inside: Vec<bool>,
    /// Free cells inside the arena: what coverage is taken over.
    region: Vec<bool>,
    /// Free cells connected to the start.
    reachable: Vec<bool>,
    seen: Vec<bool>,
    region_count: usize,
    reachable_count: usize,
    seen_count: usize,
    reachable_seen: usize,
    /// Scratch: the fan polygon of the last scan, cell units.
    polygon: Vec<(f64, f64)>,
    /// Scratch of the fan filling.
    raster: FanRaster,
    /// The beam directions, laser frame.
    beams: BeamTable,
}

impl CoverageGrid {
    /// The width and height (m, with the start and the grid's margins) of `world` when the
    /// grid cannot hold it ([`MAX_COVERAGE_CELLS`] on a side); `None` when it can.
    #[must_use]
    pub fn too_large(world: &World, start: Point2) -> Option<(f64, f64)> {
        let (_, cols, rows) = grid_size(world, start);
        let most = MAX_COVERAGE_CELLS as f64;
        // NaN (an absurd world) is too large as well.
        (!(cols <= most && rows <= most)).then_some((cols * COVERAGE_CELL, rows * COVERAGE_CELL))
    }

    /// The grid of `index`'s world for a robot of circumradius `radius` (m) starting at
    /// `start`. When the start cell itself is not free (nearer an obstacle than `radius`),
    /// what is reachable is counted from the nearest free cell within `radius` of it.
    #[must_use]
    pub fn new(index: &WorldIndex, start: Point2, radius: f64) -> Self {
        // At most `MAX_COVERAGE_CELLS` on a side: a larger world (which `too_large` tells,
        // and a run refuses) is clipped.
        let (origin, cols, rows) = grid_size(index.world(), start);
        let cols = (cols as usize).clamp(1, MAX_COVERAGE_CELLS);
        let rows = (rows as usize).clamp(1, MAX_COVERAGE_CELLS);
        let n = cols * rows;
        let mut grid = Self {
            origin,
            cols,
            rows,
            region_kind: CoverageRegion::Bounds,
            inside: vec![false; n],
            region: vec![false; n],
            reachable: vec![false; n],
            seen: vec![false; n],
            region_count: 0,
            reachable_count: 0,
            seen_count: 0,
            reachable_seen: 0,
            polygon: Vec::new(),
            raster: FanRaster::default(),
            beams: BeamTable::default(),
        };
        let radius = if radius.is_finite() {
            radius.max(0.0)
        } else {
            0.0
        };
        let free: Vec<bool> = (0..n)
            .map(|c| clear_of(index, grid.centre(c), radius))
            .collect();
        grid.reachable = grid.start_component(index, &free, start, radius);
        let outline = ArenaOutline::of_index(index);
        if outline.encloses(start) && !grid.leaks(&outline) {
            grid.region_kind = CoverageRegion::Enclosed;
            grid.inside = (0..n).map(|c| outline.encloses(grid.centre(c))).collect();
        } else {
            grid.inside = (0..n)
                .map(|c| outline.within_bounds(grid.centre(c)))
                .collect();
        }
        let floor: Vec<bool> = (0..n).map(|c| grid.inside[c] && free[c]).collect();
        grid.region = grid.main_floor(&floor, start);
        grid.region_count = grid.region.iter().filter(|r| **r).count();
        grid.reachable_count = grid.reachable.iter().filter(|r| **r).count();
        grid
    }

    /// True when over three quarters of the reachable floor within the arena's bounds lie
    /// outside its outline: a gap wider than the outline closes opens the floor the robot
    /// reaches, and the outline keeps only the corridors and rooms around the start (an
    /// arena's doors lead out of its bounds, not into them). An arena open at one side
    /// (`rc_2015_arena_big`: 60 % of its bounds enclosed) keeps its outline.
    fn leaks(&self, outline: &ArenaOutline) -> bool {
        let (mut in_bounds, mut open) = (0usize, 0usize);
        for c in (0..self.reachable.len()).filter(|&c| self.reachable[c]) {
            let p = self.centre(c);
            if outline.within_bounds(p) {
                in_bounds += 1;
                open += usize::from(!outline.encloses(p));
            }
        }
        4 * open > 3 * in_bounds
    }

    /// The largest 4-connected group of `floor` cells together with the group of `start`'s
    /// cell: the arena's floor without the closed rooms no robot enters.
    fn main_floor(&self, floor: &[bool], start: Point2) -> Vec<bool> {
        let mut group = vec![usize::MAX; floor.len()];
        let (mut largest, mut largest_size) = (usize::MAX, 0);
        let mut cells = Vec::new();
        for seed in 0..floor.len() {
            if !floor[seed] || group[seed] != usize::MAX {
                continue;
            }
            cells.clear();
            cells.push(seed);
            group[seed] = seed;
            let mut k = 0;
            while k < cells.len() {
                let c = cells[k];
                k += 1;
                let (x, y) = (c % self.cols, c / self.cols);
                let mut visit = |m: usize| {
                    if floor[m] && group[m] == usize::MAX {
                        group[m] = seed;
                        cells.push(m);
                    }
                };
                if x > 0 {
                    visit(c - 1);
                }
                if x + 1 < self.cols {
                    visit(c + 1);
                }
                if y > 0 {
                    visit(c - self.cols);
                }
                if y + 1 < self.rows {
                    visit(c + self.cols);
                }
            }
            if cells.len() > largest_size {
                (largest, largest_size) = (seed, cells.len());
            }
        }
        let own = self
            .cell_of(start)
            .map_or(usize::MAX, |s| if floor[s] { group[s] } else { usize::MAX });
        group
            .iter()
            .map(|&g| g != usize::MAX && (g == largest || g == own))
            .collect()
    }

    /// The cells `ok` connected to the cell of `start` by a 4-neighbour flood fill. When
    /// that cell is not `ok` (a start nearer an obstacle than the robot's radius, from which
    /// it can still back off), from the nearest `ok` cell within `radius` plus one cell of
    /// it that a straight move reaches; none when there is no such cell (a start on or in
    /// an obstacle).
    fn start_component(
        &self,
        index: &WorldIndex,
        ok: &[bool],
        start: Point2,
        radius: f64,
    ) -> Vec<bool> {
        let mut reached = vec![false; ok.len()];
        if let Some(s) = self.nearest_ok(index, ok, start, radius + COVERAGE_CELL) {
            flood4(self.cols, ok, &[s], &mut reached);
        }
        reached
    }

    /// The `ok` cell nearest `p`, its centre within `reach` (m) and in straight sight of
    /// `p`: `p`'s own cell when that is `ok`. None when `p` touches an obstacle.
    fn nearest_ok(&self, index: &WorldIndex, ok: &[bool], p: Point2, reach: f64) -> Option<usize> {
        let own = self.cell_of(p)?;
        if ok[own] {
            return Some(own);
        }
        if index.world().clearance(p) <= 0.0 {
            return None;
        }
        let span = (reach / COVERAGE_CELL).ceil() as isize;
        let (x0, y0) = ((own % self.cols) as isize, (own / self.cols) as isize);
        let mut near = Vec::new();
        for dy in -span..=span {
            for dx in -span..=span {
                let (x, y) = (x0 + dx, y0 + dy);
                if x < 0 || y < 0 || x >= self.cols as isize || y >= self.rows as isize {
                    continue;
                }
                let c = y as usize * self.cols + x as usize;
                let d = (self.centre(c) - p).norm();
                if ok[c] && d <= reach {
                    near.push((d, c));
                }
            }
        }
        near.sort_by(|a, b| a.0.total_cmp(&b.0));
        near.into_iter()
            .find(|&(d, c)| {
                let to = self.centre(c) - p;
                index.cast(p, to.y.atan2(to.x), d).is_none()
            })
            .map(|(_, c)| c)
    }

    fn centre(&self, c: usize) -> Point2 {
        let (x, y) = (c % self.cols, c / self.cols);
        Point2::new(
            self.origin.x + (x as f64 + 0.5) * COVERAGE_CELL,
            self.origin.y + (y as f64 + 0.5) * COVERAGE_CELL,
        )
    }

    fn cell_of(&self, p: Point2) -> Option<usize> {
        let fx = ((p.x - self.origin.x) / COVERAGE_CELL).floor();
        let fy = ((p.y - self.origin.y) / COVERAGE_CELL).floor();
        if !(fx >= 0.0 && fy >= 0.0 && fx < self.cols as f64 && fy < self.rows as f64) {
            return None;
        }
        Some(fy as usize * self.cols + fx as usize)
    }

    /// What coverage is taken over.
    #[must_use]
    pub fn region_kind(&self) -> CoverageRegion {
        self.region_kind
    }

    /// Number of cells coverage is taken over (the arena's free cells).
    #[must_use]
    pub fn region_cells(&self) -> usize {
        self.region_count
    }

    /// The arena's free area, m^2: what coverage is taken over.
    #[must_use]
    pub fn region_area_m2(&self) -> f64 {
        self.region_count as f64 * COVERAGE_CELL * COVERAGE_CELL
    }

    /// Number of free cells connected to the start.
    #[must_use]
    pub fn reachable_cells(&self) -> usize {
        self.reachable_count
    }

    /// The free area connected to the start, m^2.
    #[must_use]
    pub fn reachable_area_m2(&self) -> f64 {
        self.reachable_count as f64 * COVERAGE_CELL * COVERAGE_CELL
    }

    /// Number of the arena's free cells seen so far.
    #[must_use]
    pub fn seen_cells(&self) -> usize {
        self.seen_count
    }

    /// The fraction of the arena's free cells seen so far, 0..1 (0 when there are none).
    #[must_use]
    pub fn coverage(&self) -> f64 {
        if self.region_count == 0 {
            0.0
        } else {
            self.seen_count as f64 / self.region_count as f64
        }
    }

    /// The fraction of the free cells connected to the start seen so far, 0..1.
    #[must_use]
    pub fn reachable_coverage(&self) -> f64 {
        if self.reachable_count == 0 {
            0.0
        } else {
            self.reachable_seen as f64 / self.reachable_count as f64
        }
    }

    /// The centres of the arena's free cells not seen so far.
    #[must_use]
    pub fn unseen(&self) -> Vec<Point2> {
        (0..self.cols * self.rows)
            .filter(|&c| self.region[c] && !self.seen[c])
            .map(|c| self.centre(c))
            .collect()
    }

    /// True when the cell holding `p` is free and connected to the start.
    #[must_use]
    pub fn is_reachable(&self, p: Point2) -> bool {
        self.cell_of(p).is_some_and(|c| self.reachable[c])
    }

    /// True when the cell holding `p` is one coverage is taken over.
    #[must_use]
    pub fn in_region(&self, p: Point2) -> bool {
        self.cell_of(p).is_some_and(|c| self.region[c])
    }

    /// True when `p` lies in the arena (enclosed by its walls, or inside their bounds);
    /// a robot whose centre is not has left the arena.
    #[must_use]
    pub fn in_arena(&self, p: Point2) -> bool {
        self.cell_of(p).is_some_and(|c| self.inside[c])
    }

    /// True when the cell holding `p` has been seen.
    #[must_use]
    pub fn is_seen(&self, p: Point2) -> bool {
        self.cell_of(p).is_some_and(|c| self.seen[c])
    }

    /// Marks the cells of one scan's swept area (see the [module docs](self)): beam `i`
    /// leaves the laser at `world_from_laser` at `angle_min + i * angle_increment` and runs
    /// to `true_ranges[i]`, or to `range_max` where that is not finite. Fewer than two
    /// beams sweep no area.
    pub fn mark_scan(
        &mut self,
        world_from_laser: &Isometry2,
        angle_min: f64,
        angle_increment: f64,
        true_ranges: &[f64],
        range_max: f64,
    ) {
        let o = Point2::from(world_from_laser.translation.vector);
        let yaw = world_from_laser.rotation.angle();
        if !(o.x.is_finite() && o.y.is_finite() && yaw.is_finite() && angle_increment.is_finite()) {
            return;
        }
        // The fan polygon in cell units: the laser, then every beam's end.
        let to_cells = |p: Point2| {
            (
                (p.x - self.origin.x) / COVERAGE_CELL,
                (p.y - self.origin.y) / COVERAGE_CELL,
            )
        };
        let mut poly = std::mem::take(&mut self.polygon);
        poly.clear();
        poly.push(to_cells(o));
        let (s_yaw, c_yaw) = yaw.sin_cos();
        let dirs = self
            .beams
            .get(angle_min, angle_increment, true_ranges.len());
        for (&r, d) in true_ranges.iter().zip(dirs) {
            let dir = Vector2::new(c_yaw * d.x - s_yaw * d.y, s_yaw * d.x + c_yaw * d.y);
            let len = if r.is_finite() { r } else { range_max };
            let len = if len.is_finite() { len.max(0.0) } else { 0.0 };
            poly.push(to_cells(o + dir * len));
        }
        let mut raster = std::mem::take(&mut self.raster);
        let (seen, region, reachable) = (&mut self.seen, &self.region, &self.reachable);
        let (count, reachable_count) = (&mut self.seen_count, &mut self.reachable_seen);
        let cols = self.cols;
        raster.fill(&poly, cols, self.rows, |row, first, last| {
            let (from, to) = (row * cols + first, row * cols + last);
            for ((s, r), q) in seen[from..=to]
                .iter_mut()
                .zip(&region[from..=to])
                .zip(&reachable[from..=to])
            {
                if !*s {
                    *s = true;
                    *count += usize::from(*r);
                    *reachable_count += usize::from(*q);
                }
            }
        });
        self.raster = raster;
        self.polygon = poly;
    }
}

#[cfg(test)]
mod tests;
