//! Paths on the robot's own map: the nearest frontier and the way there.
//!
//! Everything here reads the robot's [`RobotMap`] only. Its knowledge grid (0.1 m) is
//! turned, within the box the scans have covered, into:
//!
//! - **clearance**: a chamfer distance transform (weights 5 and 7 per straight and diagonal
//!   step, i.e. 1 and 1.4 cells) from the occupied cells;
//! - **passable cells**: known free cells at least [`PlannerParams::clearance_m`] from any
//!   occupied cell (the footprint's circumradius is 0.32 m; cell centres are within 0.05 m
//!   of the walls they stand for). The robot's own cell and cells within
//!   [`PlannerParams::escape_radius_m`] of it need only
//!   [`PlannerParams::escape_clearance_m`], so that a robot that stands near a wall
//!   can still leave;
//! - **frontier cells**: passable cells with at least [`PlannerParams::min_unknown`] unknown
//!   cells among the 5 x 5 around them: the edge of what has been seen, where the robot
//!   can stand.
//!
//! Frontiers farther than [`PlannerParams::max_range_m`] from the start are left alone (a
//! robot that slips out of an arena through a gap would otherwise explore the open space
//! around it for ever).
//!
//! [`Planner::nearest_frontier`] runs Dijkstra's algorithm from the robot's cell over the
//! passable cells (8-neighbour steps; a step costs its length, more where the clearance is
//! below [`PlannerParams::preferred_clearance_m`], so that paths keep to the middle of
//! corridors) to the cheapest frontier cell away from the cells to avoid (frontiers tried
//! before), and returns the path to it.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use laserlines::math::Point2;

use crate::fence::Fence;
use crate::map::{CellState, RobotMap};
use crate::raster::floor_i64;

/// Settings of the planner. Distances in metres.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct PlannerParams {
    /// Least clearance of a passable cell, m. Default 0.3.
    pub clearance_m: f64,
    /// Least clearance near the robot (within `escape_radius_m` of it), m. Default 0.15.
    pub escape_clearance_m: f64,
    /// Radius around the robot where `escape_clearance_m` is enough, m. Default 0.6.
    pub escape_radius_m: f64,
    /// Below this clearance a cell costs more, m. Default 0.6.
    pub preferred_clearance_m: f64,
    /// Extra cost of a step at zero clearance, as a multiple of its length (falling
    /// linearly to 0 at the preferred clearance). Default 4.
    pub clearance_cost: f64,
    /// Unknown cells among the 5 x 5 around a passable cell that make it a frontier.
    /// Default 4.
    pub min_unknown: usize,
    /// Frontiers farther than this from the map's origin (the start) are not chosen, m:
    /// the area a run explores. Default 30.
    pub max_range_m: f64,
}

impl Default for PlannerParams {
    fn default() -> Self {
        Self {
            clearance_m: 0.3,
            escape_clearance_m: 0.15,
            escape_radius_m: 0.6,
            preferred_clearance_m: 0.6,
            clearance_cost: 4.0,
            min_unknown: 4,
            max_range_m: 30.0,
        }
    }
}

/// A path to a frontier.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The frontier cell's centre, map frame.
    pub goal: Point2,
    /// Cell centres from the robot's cell to the goal, map frame.
    pub path: Vec<Point2>,
    /// Length of the path, m.
    pub length_m: f64,
}

/// The largest cost factor of a step onto a cell (10 per unit of length at full
/// clearance), so that path costs stay far from `u32::MAX` for any `clearance_cost`.
const MAX_FACTOR: f64 = (1 << 20) as f64;

/// The cells of a `w` x `h` window within the square of half side `radius` (cells, rounded
/// up) around `(ci, cj)`, as indices `y * w + x`; nothing when the square misses the window.
fn disc_cells(
    (ci, cj): (i64, i64),
    radius: f64,
    (w, h): (usize, usize),
) -> impl Iterator<Item = usize> {
    let reach = if radius.is_finite() {
        radius.max(0.0).ceil().min((w.max(h) + 1) as f64) as i64
    } else if radius > 0.0 {
        (w.max(h) + 1) as i64
    } else {
        0
    };
    let x0 = ci.saturating_sub(reach).max(0);
    let x1 = ci.saturating_add(reach).min(w as i64 - 1);
    let y0 = cj.saturating_sub(reach).max(0);
    let y1 = cj.saturating_add(reach).min(h as i64 - 1);
    (y0..=y1).flat_map(move |y| (x0..=x1).map(move |x| y as usize * w + x as usize))
}

/// Chamfer weight of a straight step.
const STRAIGHT: u32 = 5;
/// Chamfer weight of a diagonal step.
const DIAGONAL: u32 = 7;
/// Clearance at most this is computed (chamfer units, 2 m); farther counts as this.
const FAR: u16 = 100;

/// The planner's working memory, kept between plans (see the [module docs](self)).
#[derive(Debug, Clone, Default)]
pub struct Planner {
    /// The window of the knowledge grid planned over: first column and row, size.
    window: (usize, usize, usize, usize),
    /// The window's cell states (`CellState as u8`).
    state: Vec<u8>,
    clearance: Vec<u16>,
    /// Summed-area table of the unknown cells, `(w + 1) x (h + 1)`.
    summed: Vec<u32>,
    /// Step cost factor per cell (`u32::MAX`: not passable).
    factor: Vec<u32>,
    cost: Vec<u32>,
    parent: Vec<u32>,
    heap: BinaryHeap<Reverse<(u32, u32)>>,
    /// Spots the robot could not pass (map frame) and the radius closed around each, m.
    blocked: Vec<Point2>,
    blocked_radius: f64,
    /// The fence the paths keep inside (see [`crate::fence`]).
    fence: Option<Fence>,
}

impl Planner {
    /// A planner.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Closes the cells within `radius` of each of `spots` (map frame) to the paths planned
    /// from now on, except those within `radius` of the robot itself: places where the
    /// map shows a way but the robot could not get through (a gap its safety layer finds
    /// too narrow). An empty list, or a radius that is not finite and positive, opens them
    /// all again.
    pub fn set_blocked(&mut self, spots: &[Point2], radius: f64) {
        self.blocked.clear();
        self.blocked
            .extend(spots.iter().filter(|p| p.x.is_finite() && p.y.is_finite()));
        self.blocked_radius = if radius.is_finite() {
            radius.max(0.0)
        } else {
            0.0
        };
    }

    /// Keeps the paths planned from now on inside `fence` (none: no fence): the cells beyond
    /// it count as walls, not as unknown ground. A robot outside the fence plans without it.
    pub fn set_fence(&mut self, fence: Option<Fence>) {
        self.fence = fence;
    }

    /// The path from `from` (map frame) to the nearest frontier of `map` that is farther
    /// than `avoid_radius` from every point of `avoid`; `None` when no such frontier can be
    /// reached. When `keep` is a frontier within `hysteresis_m` of path length of the
    /// nearest one, the path to `keep` is returned instead (so that a robot on its way does
    /// not waver between two frontiers about as near).
    pub fn nearest_frontier(
        &mut self,
        map: &RobotMap,
        from: Point2,
        avoid: &[Point2],
        avoid_radius: f64,
        keep: Option<(Point2, f64)>,
        params: &PlannerParams,
    ) -> Option<Plan> {
        let win = self.load_window(map)?;
        if let Some(fence) = self.fence.filter(|f| f.contains(from)) {
            self.close_outside(map, &win, &fence);
        }
        self.chamfer_clearance(&win);
        self.count_unknowns(&win);
        let start = win.cell_of(map, from)?;
        self.step_factors(map, &win, start, params);
        let goal = self.search(map, &win, start, avoid, avoid_radius, keep, params)?;
        self.path_to(map, &win, start, goal)
    }

    /// The window of the knowledge grid around the scanned box (and 3 cells), with its
    /// cells' states; `None` for an empty map.
    fn load_window(&mut self, map: &RobotMap) -> Option<Window> {
        let grid = map.knowledge();
        let (lo, hi) = map.extent()?;
        let (u0, v0) = grid.to_cells(lo);
        let (u1, v1) = grid.to_cells(hi);
        let clamp = |x: f64, n: usize| floor_i64(x).clamp(0, n as i64 - 1) as usize;
        if grid.cols == 0 || grid.rows == 0 {
            return None;
        }
        let (i0, j0) = (clamp(u0 - 3.0, grid.cols), clamp(v0 - 3.0, grid.rows));
        let (i1, j1) = (clamp(u1 + 3.0, grid.cols), clamp(v1 + 3.0, grid.rows));
        let win = Window {
            i0,
            j0,
            w: i1 - i0 + 1,
            h: j1 - j0 + 1,
            cols: grid.cols,
            cell: grid.cell,
        };
        self.window = (i0, j0, win.w, win.h);
        // The window's states, row by row (no division per lookup later).
        self.state.clear();
        self.state.reserve(win.w * win.h);
        for j in 0..win.h {
            let row = win.grid_index(0, j);
            self.state
                .extend((row..row + win.w).map(|c| map.state_at(c) as u8));
        }
        Some(win)
    }

    /// The window's cells whose centres lie outside `fence` become walls.
    fn close_outside(&mut self, map: &RobotMap, win: &Window, fence: &Fence) {
        let inside = fence.inside_test();
        for k in 0..self.state.len() {
            if !inside(win.centre(map, k)) {
                self.state[k] = OCCUPIED;
            }
        }
    }

    /// Clearance: chamfer distance transform from the occupied cells, two passes.
    fn chamfer_clearance(&mut self, win: &Window) {
        let (w, h) = (win.w, win.h);
        self.clearance.clear();
        self.clearance.extend(
            self.state
                .iter()
                .map(|&s| if s == OCCUPIED { 0 } else { FAR }),
        );
        let d = &mut self.clearance;
        let relax = |d: &mut Vec<u16>, k: usize, other: usize, weight: u32| {
            let via = u32::from(d[other]) + weight;
            if via < u32::from(d[k]) {
                d[k] = via as u16;
            }
        };
        for j in 0..h {
            for i in 0..w {
                let k = j * w + i;
                if i > 0 {
                    relax(d, k, k - 1, STRAIGHT);
                }
                if j > 0 {
                    relax(d, k, k - w, STRAIGHT);
                    if i > 0 {
                        relax(d, k, k - w - 1, DIAGONAL);
                    }
                    if i + 1 < w {
                        relax(d, k, k - w + 1, DIAGONAL);
                    }
                }
            }
        }
        for j in (0..h).rev() {
            for i in (0..w).rev() {
                let k = j * w + i;
                if i + 1 < w {
                    relax(d, k, k + 1, STRAIGHT);
                }
                if j + 1 < h {
                    relax(d, k, k + w, STRAIGHT);
                    if i + 1 < w {
                        relax(d, k, k + w + 1, DIAGONAL);
                    }
                    if i > 0 {
                        relax(d, k, k + w - 1, DIAGONAL);
                    }
                }
            }
        }
    }

    /// The summed-area table of the unknown cells, `(w + 1) x (h + 1)`.
    fn count_unknowns(&mut self, win: &Window) {
        let (w, h, sw) = (win.w, win.h, win.w + 1);
        self.summed.clear();
        self.summed.resize(sw * (h + 1), 0);
        for j in 0..h {
            let mut row_sum = 0_u32;
            for i in 0..w {
                row_sum += u32::from(self.state[j * w + i] == UNKNOWN);
                self.summed[(j + 1) * sw + i + 1] = self.summed[j * sw + i + 1] + row_sum;
            }
        }
    }

    /// Unknown cells in the 5 x 5 around cell `k` of the window (outside the window counts
    /// as unknown).
    fn unknown_around(&self, win: &Window, k: usize) -> usize {
        let (w, h, sw) = (win.w, win.h, win.w + 1);
        let summed = &self.summed;
        let (i, j) = ((k % w) as i64, (k / w) as i64);
        let (x0, x1) = (
            (i - 2).max(0) as usize,
            ((i + 2).min(w as i64 - 1)) as usize,
        );
        let (y0, y1) = (
            (j - 2).max(0) as usize,
            ((j + 2).min(h as i64 - 1)) as usize,
        );
        let inside = summed[(y1 + 1) * sw + x1 + 1] + summed[y0 * sw + x0]
            - summed[y0 * sw + x1 + 1]
            - summed[(y1 + 1) * sw + x0];
        let outside = 25 - ((x1 - x0 + 1) * (y1 - y0 + 1)) as u32;
        (inside + outside) as usize
    }

    /// Per cell: `u32::MAX` when not passable, else the cost factor of a step onto it (10
    /// per unit of step length, more where the clearance is small). Near the start the
    /// escape clearance will do; blocked spots are closed, but never around the start.
    fn step_factors(&mut self, map: &RobotMap, win: &Window, start: usize, params: &PlannerParams) {
        let (w, h, cell) = (win.w, win.h, win.cell);
        let (si, sj) = ((start % w) as i64, (start / w) as i64);
        let units = |m: f64| to_units(m, cell);
        let need = units(params.clearance_m);
        let need_near = units(params.escape_clearance_m);
        let prefer = units(params.preferred_clearance_m).max(1);
        let near_start2 = (params.escape_radius_m / cell) * (params.escape_radius_m / cell);
        self.factor.clear();
        self.factor
            .extend(self.clearance.iter().zip(&self.state).map(|(&c, &s)| {
                let c = u32::from(c);
                if s != FREE || c < need_near {
                    return u32::MAX;
                }
                let clear = c.min(prefer);
                let extra =
                    params.clearance_cost.max(0.0) * f64::from(prefer - clear) / f64::from(prefer);
                let factor = (10.0 * (1.0 + extra)).round().min(MAX_FACTOR) as u32;
                // Below the clearance, passable only near the start (marked below).
                if c < need { u32::MAX - factor } else { factor }
            }));
        for k in disc_cells((si, sj), params.escape_radius_m.max(0.0) / cell, (w, h)) {
            let (di, dj) = ((k % w) as i64 - si, (k / w) as i64 - sj);
            if ((di * di + dj * dj) as f64) > near_start2 {
                continue;
            }
            let f = self.factor[k];
            if f != u32::MAX && f > u32::MAX / 2 {
                self.factor[k] = u32::MAX - f;
            }
        }
        for f in &mut self.factor {
            if *f != u32::MAX && *f > u32::MAX / 2 {
                *f = u32::MAX;
            }
        }
        self.close_blocked(map, win, (si, sj));
        let worst = (10.0 * (1.0 + params.clearance_cost.max(0.0))).min(MAX_FACTOR) as u32;
        self.factor[start] = self.factor[start].min(worst);
    }

    /// Closes the cells within the blocked radius of each blocked spot, but never those
    /// within it of the start cell `(si, sj)`.
    fn close_blocked(&mut self, map: &RobotMap, win: &Window, (si, sj): (i64, i64)) {
        if self.blocked.is_empty() || self.blocked_radius <= 0.0 {
            return;
        }
        let grid = map.knowledge();
        let r = self.blocked_radius / win.cell;
        for b in &self.blocked {
            let (bu, bv) = grid.to_cells(*b);
            let (bi, bj) = (
                floor_i64(bu).saturating_sub(win.i0 as i64),
                floor_i64(bv).saturating_sub(win.j0 as i64),
            );
            for k in disc_cells((bi, bj), r, (win.w, win.h)) {
                let (x, y) = ((k % win.w) as i64, (k / win.w) as i64);
                let (di, dj) = ((x - bi) as f64, (y - bj) as f64);
                let (ds, dt) = ((x - si) as f64, (y - sj) as f64);
                if di * di + dj * dj <= r * r && ds * ds + dt * dt > r * r {
                    self.factor[k] = u32::MAX;
                }
            }
        }
    }

    /// Dijkstra from `start` to the nearest frontier not avoided and within range (or to the
    /// kept goal, within the hysteresis); the goal cell.
    #[allow(clippy::too_many_arguments)]
    fn search(
        &mut self,
        map: &RobotMap,
        win: &Window,
        start: usize,
        avoid: &[Point2],
        avoid_radius: f64,
        keep: Option<(Point2, f64)>,
        params: &PlannerParams,
    ) -> Option<usize> {
        let n = win.w * win.h;
        let centre = |k: usize| win.centre(map, k);
        let avoided = |p: Point2| {
            avoid
                .iter()
                .any(|a| (a - p).norm_squared() < avoid_radius * avoid_radius)
        };
        self.cost.clear();
        self.cost.resize(n, u32::MAX);
        self.parent.clear();
        self.parent.resize(n, u32::MAX);
        self.heap.clear();
        self.cost[start] = 0;
        self.heap.push(Reverse((0, start as u32)));
        let mut nearest: Option<(u32, usize)> = None;
        let keep_cost_limit = keep.map(|(_, m)| to_units(m, win.cell) * 10);
        while let Some(Reverse((c, k))) = self.heap.pop() {
            let k = k as usize;
            if c > self.cost[k] {
                continue;
            }
            if let Some((nc, _)) = nearest {
                // Looking for the kept goal only, within the hysteresis.
                match (keep, keep_cost_limit) {
                    (Some(_), Some(extra)) if c <= nc.saturating_add(extra) => {}
                    _ => break,
                }
            }
            let frontier =
                self.factor[k] != u32::MAX && self.unknown_around(win, k) >= params.min_unknown;
            if k != start
                && frontier
                && !avoided(centre(k))
                && centre(k).coords.norm() <= params.max_range_m
            {
                if nearest.is_none() {
                    nearest = Some((c, k));
                }
                if let Some((goal, _)) = keep
                    && (centre(k) - goal).norm() <= 0.3
                {
                    return Some(k);
                }
                if keep.is_none() {
                    break;
                }
            }
            self.relax_neighbours(win, k, c);
        }
        nearest.map(|(_, k)| k)
    }

    /// Dijkstra's step from cell `k` at cost `c` to its 8 neighbours.
    fn relax_neighbours(&mut self, win: &Window, k: usize, c: u32) {
        let (wi, hi) = (win.w as i64, win.h as i64);
        let (i, j) = ((k % win.w) as i64, (k / win.w) as i64);
        for (di, dj, weight) in [
            (-1_i64, 0_i64, STRAIGHT),
            (1, 0, STRAIGHT),
            (0, -1, STRAIGHT),
            (0, 1, STRAIGHT),
            (-1, -1, DIAGONAL),
            (1, -1, DIAGONAL),
            (-1, 1, DIAGONAL),
            (1, 1, DIAGONAL),
        ] {
            let (x, y) = (i + di, j + dj);
            if x < 0 || y < 0 || x >= wi || y >= hi {
                continue;
            }
            let m = (y * wi + x) as usize;
            let f = self.factor[m];
            if f == u32::MAX {
                continue;
            }
            let via = c.saturating_add((weight * f).max(1));
            if via < self.cost[m] {
                self.cost[m] = via;
                self.parent[m] = k as u32;
                self.heap.push(Reverse((via, m as u32)));
            }
        }
    }

    /// The plan from `start` to `goal` along the search's parents.
    fn path_to(&self, map: &RobotMap, win: &Window, start: usize, goal: usize) -> Option<Plan> {
        let mut path = Vec::new();
        let mut k = goal;
        path.push(win.centre(map, k));
        while k != start {
            let p = self.parent[k];
            if p == u32::MAX {
                return None;
            }
            k = p as usize;
            path.push(win.centre(map, k));
        }
        path.reverse();
        let length_m = path.windows(2).map(|s| (s[1] - s[0]).norm()).sum();
        Some(Plan {
            goal: win.centre(map, goal),
            path,
            length_m,
        })
    }
}

/// The window of the knowledge grid a plan runs over.
#[derive(Debug, Clone, Copy)]
struct Window {
    /// First column and row in the grid.
    i0: usize,
    j0: usize,
    /// Size in cells.
    w: usize,
    h: usize,
    /// The grid's columns.
    cols: usize,
    /// The grid's cell side, m.
    cell: f64,
}

impl Window {
    /// The grid index of the window's cell `(i, j)`.
    fn grid_index(&self, i: usize, j: usize) -> usize {
        (self.j0 + j) * self.cols + self.i0 + i
    }

    /// The centre of the window's cell `k`, map frame.
    fn centre(&self, map: &RobotMap, k: usize) -> Point2 {
        map.knowledge()
            .centre(self.grid_index(k % self.w, k / self.w))
    }

    /// The window's cell holding `p`, if any.
    fn cell_of(&self, map: &RobotMap, p: Point2) -> Option<usize> {
        let (u, v) = map.knowledge().to_cells(p);
        if !(u.is_finite() && v.is_finite()) {
            return None;
        }
        let (si, sj) = (
            floor_i64(u).saturating_sub(self.i0 as i64),
            floor_i64(v).saturating_sub(self.j0 as i64),
        );
        if !(si >= 0 && sj >= 0 && (si as usize) < self.w && (sj as usize) < self.h) {
            return None;
        }
        Some(sj as usize * self.w + si as usize)
    }
}

/// A distance in chamfer units (5 per cell of side `cell`).
fn to_units(m: f64, cell: f64) -> u32 {
    (m / cell * f64::from(STRAIGHT)).round().max(0.0) as u32
}

const UNKNOWN: u8 = CellState::Unknown as u8;
const FREE: u8 = CellState::Free as u8;
const OCCUPIED: u8 = CellState::Occupied as u8;
