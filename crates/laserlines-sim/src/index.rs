//! A uniform-grid index over a [`World`] for fast ray casting and proximity queries.
//!
//! [`World::cast`] tests every wall and disc; a robot simulation casts hundreds of thousands
//! of rays per simulated minute in arenas of a hundred walls and more. [`WorldIndex`] files
//! each wall and disc under the grid cells it touches and walks a ray through the cells in
//! order (Amanatides-Woo traversal), so that a ray tests only the few obstacles along it.
//! It gives the same ranges as [`World::cast`] (the same intersection formulas); where two
//! obstacles tie exactly, the target reported may differ.

use laserlines::math::{Point2, Vector2, ceil_i64, floor_i64};

use laserlines::Scan;

use crate::laser::{LaserModel, MAX_BEAMS};
use crate::rng::Rng;
use crate::simulation::MIXED_PIXEL_MIN_JUMP;
use crate::world::{Hit, Target, World};
use laserlines::geometry::{
    circle_ray_hit, clip_ray_to_box, segment_ray_hit, segment_ray_hit_prepared, segment_touches_box,
};

/// Hits closer to each other than this (m) are a tie, won by the earlier obstacle.
const TIE_TOLERANCE: f64 = 1e-12;
/// Margin added around every obstacle when filing it under cells, m.
const FILE_MARGIN: f64 = 1e-6;

/// A uniform-grid index of a world's walls and discs (see the [module docs](self)).
///
/// ```
/// use laserlines_sim::{World, index::WorldIndex};
/// use laserlines::math::Point2;
/// let mut world = World::new();
/// world.add_box(Point2::new(0.0, 0.0), 4.0, 3.0, 0.3);
/// let index = WorldIndex::new(&world, 0.5);
/// for k in 0..100 {
///     let angle = k as f64 * 0.0628;
///     let fast = index.cast(Point2::new(0.3, -0.2), angle, 10.0).unwrap();
///     let slow = world.cast(Point2::new(0.3, -0.2), angle, 10.0).unwrap();
///     assert!((fast.range - slow.range).abs() < 1e-12);
/// }
/// ```
#[derive(Debug, Clone)]
pub struct WorldIndex {
    world: World,
    origin: Point2,
    cell: f64,
    cols: usize,
    rows: usize,
    /// Per cell, the range of `items` holding its obstacles.
    spans: Vec<(u32, u32)>,
    items: Vec<Target>,
}

impl WorldIndex {
    /// Indexes `world` with square cells of `cell_size` metres (clamped to at least 0.05 m;
    /// about half the typical wall length is a good choice). Obstacles with non-finite
    /// coordinates are left out of the index (the world's own cast ignores them too).
    #[must_use]
    pub fn new(world: &World, cell_size: f64) -> Self {
        let cell = if cell_size.is_finite() {
            cell_size.max(0.05)
        } else {
            0.5
        };
        let mut min = Point2::new(f64::INFINITY, f64::INFINITY);
        let mut max = Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
        let mut grow = |p: Point2, r: f64| {
            if p.x.is_finite() && p.y.is_finite() && r.is_finite() {
                min = Point2::new(min.x.min(p.x - r), min.y.min(p.y - r));
                max = Point2::new(max.x.max(p.x + r), max.y.max(p.y + r));
            }
        };
        for w in &world.walls {
            if finite(w.a) && finite(w.b) {
                grow(w.a, 0.0);
                grow(w.b, 0.0);
            }
        }
        for d in &world.discs {
            if d.radius > 0.0 {
                grow(d.centre, d.radius);
            }
        }
        if !(min.x.is_finite() && max.x.is_finite()) {
            min = Point2::origin();
            max = Point2::origin();
        }
        let origin = Point2::new(min.x - cell, min.y - cell);
        // At most 4096 x 4096 cells: a larger world gets larger cells.
        let span = (max.x - min.x).max(max.y - min.y) + 2.0 * cell;
        let cell = cell.max(span / 4096.0);
        let cols = (((max.x - origin.x) / cell).ceil() as usize + 1).max(1);
        let rows = (((max.y - origin.y) / cell).ceil() as usize + 1).max(1);

        let mut buckets: Vec<Vec<Target>> = vec![Vec::new(); cols * rows];
        let mut index = Self {
            world: world.clone(),
            origin,
            cell,
            cols,
            rows,
            spans: Vec::new(),
            items: Vec::new(),
        };
        for (i, w) in world.walls.iter().enumerate() {
            if !(finite(w.a) && finite(w.b)) {
                continue;
            }
            index.for_cells_near_segment(w.a, w.b, |c| buckets[c].push(Target::Wall(i)));
        }
        for (i, d) in world.discs.iter().enumerate() {
            if !(d.radius > 0.0 && d.radius.is_finite() && finite(d.centre)) {
                continue;
            }
            let r = Vector2::new(d.radius, d.radius);
            index.for_cells_in_box(d.centre - r, d.centre + r, |c| {
                buckets[c].push(Target::Disc(i));
            });
        }
        for b in &buckets {
            let from = index.items.len() as u32;
            index.items.extend_from_slice(b);
            index.spans.push((from, index.items.len() as u32));
        }
        index
    }

    /// The indexed world.
    #[must_use]
    pub fn world(&self) -> &World {
        &self.world
    }

    /// The cell size, m.
    #[must_use]
    pub fn cell_size(&self) -> f64 {
        self.cell
    }

    fn cell_of(&self, p: Point2) -> (i64, i64) {
        (
            floor_i64((p.x - self.origin.x) / self.cell),
            floor_i64((p.y - self.origin.y) / self.cell),
        )
    }

    fn clamp_cell(&self, (cx, cy): (i64, i64)) -> (usize, usize) {
        (
            cx.clamp(0, self.cols as i64 - 1) as usize,
            cy.clamp(0, self.rows as i64 - 1) as usize,
        )
    }

    fn for_cells_in_box(&self, lo: Point2, hi: Point2, mut f: impl FnMut(usize)) {
        let m = Vector2::new(FILE_MARGIN, FILE_MARGIN);
        let (x0, y0) = self.clamp_cell(self.cell_of(lo - m));
        let (x1, y1) = self.clamp_cell(self.cell_of(hi + m));
        for y in y0..=y1 {
            for x in x0..=x1 {
                f(y * self.cols + x);
            }
        }
    }

    /// Every cell within `FILE_MARGIN` of the segment (a conservative supercover).
    fn for_cells_near_segment(&self, a: Point2, b: Point2, mut f: impl FnMut(usize)) {
        let lo = Point2::new(a.x.min(b.x), a.y.min(b.y));
        let hi = Point2::new(a.x.max(b.x), a.y.max(b.y));
        let m = Vector2::new(FILE_MARGIN, FILE_MARGIN);
        let (x0, y0) = self.clamp_cell(self.cell_of(lo - m));
        let (x1, y1) = self.clamp_cell(self.cell_of(hi + m));
        for y in y0..=y1 {
            for x in x0..=x1 {
                let c0 = Point2::new(
                    self.origin.x + x as f64 * self.cell - FILE_MARGIN,
                    self.origin.y + y as f64 * self.cell - FILE_MARGIN,
                );
                let c1 = Point2::new(
                    c0.x + self.cell + 2.0 * FILE_MARGIN,
                    c0.y + self.cell + 2.0 * FILE_MARGIN,
                );
                if segment_touches_box(a, b, c0, c1) {
                    f(y * self.cols + x);
                }
            }
        }
    }

    fn cell_items(&self, c: usize) -> &[Target] {
        let (from, to) = self.spans[c];
        &self.items[from as usize..to as usize]
    }

    /// Every wall and disc filed under a cell that meets the box `lo..hi` (world frame, m);
    /// an obstacle may be listed more than once. Walls and discs farther away are never
    /// listed, so a caller can test exact distances on this short list.
    pub fn near_box(&self, lo: Point2, hi: Point2, mut f: impl FnMut(Target)) {
        if !(finite(lo) && finite(hi)) {
            return;
        }
        self.for_cells_in_box(lo, hi, |c| {
            for &t in self.cell_items(c) {
                f(t);
            }
        });
    }

    /// Casts a ray like [`World::cast`]: from `origin` at `angle` (rad, world frame), the
    /// nearest wall or disc within `max_range` (m, inclusive). Never panics; non-finite
    /// inputs give `None`.
    #[must_use]
    pub fn cast(&self, origin: Point2, angle: f64, max_range: f64) -> Option<Hit> {
        if !(finite(origin) && angle.is_finite()) || max_range.is_nan() || max_range < 0.0 {
            return None;
        }
        let (s, c) = angle.sin_cos();
        self.cast_dir(origin, Vector2::new(c, s), max_range)
    }

    /// [`WorldIndex::cast`] along a unit direction vector `dir` instead of an angle.
    #[must_use]
    pub fn cast_dir(&self, origin: Point2, dir: Vector2, max_range: f64) -> Option<Hit> {
        if !(finite(origin) && dir.x.is_finite() && dir.y.is_finite())
            || max_range.is_nan()
            || max_range < 0.0
        {
            return None;
        }
        let mut best: Option<(f64, Target)> = None;
        let consider = |best: &mut Option<(f64, Target)>, t: Option<f64>, target: Target| {
            if let Some(t) = t
                && t.is_finite()
                && t <= max_range
                && best.is_none_or(|(bt, tb)| {
                    t < bt - TIE_TOLERANCE || (t <= bt + TIE_TOLERANCE && target_order(target, tb))
                })
            {
                *best = Some((t, target));
            }
        };
        let test = |best: &mut Option<(f64, Target)>, target: Target| match target {
            Target::Wall(i) => {
                let w = &self.world.walls[i];
                consider(best, segment_ray_hit(w.a, w.b, origin, dir), target);
            }
            Target::Disc(i) => {
                let d = &self.world.discs[i];
                consider(
                    best,
                    circle_ray_hit(d.centre, d.radius, origin, dir),
                    target,
                );
            }
        };

        // Clip the ray to the grid's box; walk the cells it crosses in order.
        let lo = self.origin;
        let hi = Point2::new(
            lo.x + self.cols as f64 * self.cell,
            lo.y + self.rows as f64 * self.cell,
        );
        let (t_in, t_out) = clip_ray_to_box(origin, dir, lo, hi)?;
        let t_end = t_out.min(if max_range.is_finite() {
            max_range
        } else {
            f64::INFINITY
        });
        if t_in > t_end {
            return None;
        }
        let start = origin + dir * t_in;
        let (mut cx, mut cy) = self.clamp_cell(self.cell_of(start));
        let step_x: i64 = if dir.x > 0.0 { 1 } else { -1 };
        let step_y: i64 = if dir.y > 0.0 { 1 } else { -1 };
        let next_boundary = |c: usize, step: i64, o: f64| {
            o + (c as f64 + if step > 0 { 1.0 } else { 0.0 }) * self.cell
        };
        let mut t_max_x = if dir.x != 0.0 {
            (next_boundary(cx, step_x, lo.x) - origin.x) / dir.x
        } else {
            f64::INFINITY
        };
        let mut t_max_y = if dir.y != 0.0 {
            (next_boundary(cy, step_y, lo.y) - origin.y) / dir.y
        } else {
            f64::INFINITY
        };
        let t_delta_x = if dir.x != 0.0 {
            self.cell / dir.x.abs()
        } else {
            f64::INFINITY
        };
        let t_delta_y = if dir.y != 0.0 {
            self.cell / dir.y.abs()
        } else {
            f64::INFINITY
        };
        loop {
            for &t in self.cell_items(cy * self.cols + cx) {
                test(&mut best, t);
            }
            let t_exit = t_max_x.min(t_max_y);
            if let Some((bt, _)) = best
                && bt <= t_exit - 1e-9
            {
                break;
            }
            if t_exit > t_end {
                break;
            }
            if t_max_x < t_max_y {
                let nx = cx as i64 + step_x;
                if nx < 0 || nx >= self.cols as i64 {
                    break;
                }
                cx = nx as usize;
                t_max_x += t_delta_x;
            } else {
                let ny = cy as i64 + step_y;
                if ny < 0 || ny >= self.rows as i64 {
                    break;
                }
                cy = ny as usize;
                t_max_y += t_delta_y;
            }
        }
        let (range, target) = best?;
        let point = origin + dir * range;
        if !finite(point) {
            return None;
        }
        Some(Hit {
            range,
            point,
            target,
        })
    }
}

impl WorldIndex {
    /// Simulates one scan like [`crate::simulate`] into reused buffers: `scan` gets the
    /// reported ranges and the model's geometry, `true_ranges` the noise-free range of every
    /// beam (NaN where the beam hit nothing within `range_min..=range_max`). No visible
    /// pieces are computed.
    ///
    /// The beams are cast all at once by an angular sweep rather than one by one: every
    /// wall and disc within `range_max` of the laser is tested against the beams whose
    /// directions fall within the angle it subtends (one beam of margin on each side), with
    /// the exact intersection formulas of [`WorldIndex::cast`]; a beam already stopped
    /// nearer than the obstacle's nearest point skips it. Obstacles are taken nearest
    /// first, so that hidden ones cost one comparison per beam. The ranges are those of
    /// [`WorldIndex::cast_dir`] along the same directions.
    ///
    /// The noise-free ranges agree with [`crate::simulate`]'s to about 1e-12 m (the beam
    /// directions are computed by repeated rotation instead of a sine and cosine per beam).
    /// The range noise is drawn from `rng` by a ziggurat sampler of the standard normal
    /// distribution (Marsaglia and Tsang's method, in Doornik's form) rather than
    /// [`Rng::gaussian`]'s Box-Muller transform, which costs a logarithm, a square root, a
    /// sine and a cosine per pair of draws: the same distribution, other draws. Mixed
    /// pixels and dropouts draw as in [`crate::simulate`].
    pub fn scan_into(
        &self,
        world_from_laser: &laserlines::math::Isometry2,
        model: &LaserModel,
        rng: &mut Rng,
        scan: &mut Scan,
        true_ranges: &mut Vec<f64>,
    ) {
        let n = model.beams.min(MAX_BEAMS);
        let origin = Point2::from(world_from_laser.translation.vector);
        let yaw = world_from_laser.rotation.angle();
        let range_max = if model.range_max.is_nan() {
            -1.0
        } else {
            model.range_max
        };
        true_ranges.clear();
        true_ranges.resize(n, f64::NAN);
        let mut targets: Vec<Option<Target>> = vec![None; n];
        let mut no_hit = vec![0_u8; n];
        // Beam directions by repeated rotation: no sine or cosine per beam.
        let (s0, c0) = (yaw + model.angle_min).sin_cos();
        let (s_inc, c_inc) = model.angle_increment.sin_cos();
        let mut dirs = Vec::with_capacity(n);
        let mut dir = Vector2::new(c0, s0);
        for i in 0..n {
            if i > 0 {
                dir = Vector2::new(c_inc * dir.x - s_inc * dir.y, s_inc * dir.x + c_inc * dir.y);
            }
            dirs.push(dir);
        }
        const NO_HIT: u8 = 1;
        const MIXED: u8 = 2;
        const DROPPED: u8 = 4;
        let mut best: Vec<Option<(f64, Target)>> = vec![None; n];
        let fan = Fan {
            origin,
            base: yaw + model.angle_min,
            increment: model.angle_increment,
            dirs: &dirs,
            range_max,
        };
        if fan.is_valid() {
            self.sweep(&fan, &mut best);
        }
        for i in 0..n {
            match best[i] {
                Some((range, target)) if finite(origin + dirs[i] * range) => {
                    if range >= model.range_min && range > 0.0 {
                        true_ranges[i] = range;
                        targets[i] = Some(target);
                    }
                }
                _ => no_hit[i] |= NO_HIT,
            }
        }
        let ranges = &mut scan.ranges;
        ranges.clear();
        ranges.extend_from_slice(true_ranges);
        for r in ranges.iter_mut() {
            if r.is_finite() {
                let sigma = model.noise.sigma(*r);
                if sigma > 0.0 {
                    *r += sigma * standard_normal(rng);
                }
            }
        }
        if model.mixed_pixels > 0.0 {
            for i in 1..n {
                let (ra, rb) = (true_ranges[i - 1], true_ranges[i]);
                let edge = ra.is_finite()
                    && rb.is_finite()
                    && targets[i - 1] != targets[i]
                    && (ra - rb).abs() > MIXED_PIXEL_MIN_JUMP;
                if !edge || no_hit[i - 1] & MIXED != 0 || !rng.chance(model.mixed_pixels) {
                    continue;
                }
                let j = if rng.chance(0.5) { i - 1 } else { i };
                let (near, far) = if ra < rb { (ra, rb) } else { (rb, ra) };
                ranges[j] = near + (far - near) * rng.range(0.05, 0.95);
                no_hit[j] |= MIXED;
            }
        }
        if model.dropout > 0.0 {
            for (i, r) in ranges.iter_mut().enumerate() {
                if r.is_finite() && rng.chance(model.dropout) {
                    *r = f64::NAN;
                    no_hit[i] |= DROPPED;
                }
            }
        }
        let step = model.round_to.filter(|q| q.is_finite() && *q > 0.0);
        if let Some(q) = step {
            let per_step = 1.0 / q;
            for r in ranges.iter_mut() {
                *r = round_half_away(*r * per_step) * q;
            }
        }
        // Measurable: positive, within the limits, finite (NaN fails every comparison).
        let lowest = model.range_min.max(f64::MIN_POSITIVE);
        for r in ranges.iter_mut() {
            if !(*r >= lowest && *r <= range_max && *r < f64::INFINITY) {
                *r = f64::NAN;
            }
        }
        if model.max_range_returns {
            for (r, &flags) in ranges.iter_mut().zip(&no_hit) {
                if flags & NO_HIT != 0 && flags & DROPPED == 0 {
                    *r = model.range_max;
                }
            }
        }
        scan.angle_min = model.angle_min;
        scan.angle_increment = model.angle_increment;
        scan.range_min = model.range_min;
        scan.range_max = model.range_max;
        scan.intensities = None;
    }

    /// The nearest hit of every beam of `fan` (see [`WorldIndex::scan_into`]) into `best`
    /// (one slot per beam, `None` on entry).
    fn sweep(&self, fan: &Fan<'_>, best: &mut [Option<(f64, Target)>]) {
        let origin = fan.origin;
        let range_max = fan.range_max;
        // The obstacles within range, with the distance to their nearest point.
        let mut near: Vec<(f64, Target)> = Vec::new();
        let add_wall = |i: usize, near: &mut Vec<(f64, Target)>| {
            let w = &self.world.walls[i];
            if finite(w.a) && finite(w.b) {
                let d = laserlines::line::distance_to_segment(origin, w.a, w.b);
                if d <= range_max {
                    near.push((d, Target::Wall(i)));
                }
            }
        };
        let add_disc = |i: usize, near: &mut Vec<(f64, Target)>| {
            let d = &self.world.discs[i];
            if d.radius > 0.0 && d.radius.is_finite() && finite(d.centre) {
                let gap = ((d.centre - origin).norm() - d.radius).max(0.0);
                if gap <= range_max {
                    near.push((gap, Target::Disc(i)));
                }
            }
        };
        let count = self.world.walls.len() + self.world.discs.len();
        if count <= SWEEP_ALL_BELOW || !range_max.is_finite() {
            for i in 0..self.world.walls.len() {
                add_wall(i, &mut near);
            }
            for i in 0..self.world.discs.len() {
                add_disc(i, &mut near);
            }
        } else {
            let mut listed = vec![false; count];
            let walls = self.world.walls.len();
            let r = Vector2::new(range_max, range_max);
            self.near_box(origin - r, origin + r, |t| {
                let k = match t {
                    Target::Wall(i) => i,
                    Target::Disc(i) => walls + i,
                };
                if !listed[k] {
                    listed[k] = true;
                    match t {
                        Target::Wall(i) => add_wall(i, &mut near),
                        Target::Disc(i) => add_disc(i, &mut near),
                    }
                }
            });
        }
        near.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
        for &(d_near, target) in &near {
            let (from, to, all) = match target {
                Target::Wall(i) => {
                    let w = &self.world.walls[i];
                    if d_near <= 1e-9 * (1.0 + (w.a - origin).norm()) {
                        (0.0, 0.0, true)
                    } else {
                        let ra = fan.relative(w.a - origin);
                        let rb = fan.relative(w.b - origin);
                        let (lo, hi) = if ra <= rb { (ra, rb) } else { (rb, ra) };
                        if hi - lo <= std::f64::consts::PI {
                            (lo, hi, false)
                        } else {
                            (hi, lo + std::f64::consts::TAU, false)
                        }
                    }
                }
                Target::Disc(i) => {
                    let d = &self.world.discs[i];
                    let c = d.centre - origin;
                    let dist = c.norm();
                    if dist <= d.radius * (1.0 + 1e-9) + 1e-12 {
                        (0.0, 0.0, true)
                    } else {
                        let half = (d.radius / dist).min(1.0).asin();
                        let rc = fan.relative(c);
                        (rc - half, rc + half, false)
                    }
                }
            };
            // The wall's direction and length, once for all its beams.
            let (e, len) = match target {
                Target::Wall(k) => {
                    let w = &self.world.walls[k];
                    let e = w.b - w.a;
                    (e, e.norm())
                }
                Target::Disc(_) => (Vector2::zeros(), 1.0),
            };
            if !(len > 0.0 && len.is_finite()) {
                // A degenerate wall is never hit.
                continue;
            }
            let hidden_below = d_near - TIE_TOLERANCE;
            let mut test = |i: usize| {
                if let Some((bt, _)) = best[i]
                    && bt < hidden_below
                {
                    return;
                }
                let dir = fan.dirs[i];
                let t = match target {
                    Target::Wall(k) => {
                        let w = &self.world.walls[k];
                        segment_ray_hit_prepared(w.a, w.b, e, len, origin, dir)
                    }
                    Target::Disc(k) => {
                        let d = &self.world.discs[k];
                        circle_ray_hit(d.centre, d.radius, origin, dir)
                    }
                };
                if let Some(t) = t
                    && t.is_finite()
                    && t <= range_max
                    && best[i].is_none_or(|(bt, tb)| {
                        t < bt - TIE_TOLERANCE
                            || (t <= bt + TIE_TOLERANCE && target_order(target, tb))
                    })
                {
                    best[i] = Some((t, target));
                }
            };
            if all {
                (0..fan.dirs.len()).for_each(&mut test);
            } else {
                for (a, b) in fan.beams_between(from, to) {
                    (a..=b).for_each(&mut test);
                }
            }
        }
    }
}

/// Below this many walls and discs a sweep lists them all instead of asking the grid.
const SWEEP_ALL_BELOW: usize = 512;

/// The beams of one scan, for [`WorldIndex::sweep`].
struct Fan<'a> {
    origin: Point2,
    /// Direction of beam 0, rad, world frame.
    base: f64,
    /// Angle between beams, rad (either sign).
    increment: f64,
    /// The unit direction of every beam, world frame.
    dirs: &'a [Vector2],
    range_max: f64,
}

impl Fan<'_> {
    fn is_valid(&self) -> bool {
        finite(self.origin)
            && self.base.is_finite()
            && self.increment.is_finite()
            && self.increment != 0.0
            && self.range_max >= 0.0
            && !self.dirs.is_empty()
    }

    /// The angle of the direction `v` counted from beam 0 in the beams' sense of rotation,
    /// in `[0, 2 pi)`: beam `i` is at `i * |increment|`.
    fn relative(&self, v: Vector2) -> f64 {
        let a = self.increment.signum() * (fast_atan2(v.y, v.x) - self.base);
        a.rem_euclid(std::f64::consts::TAU)
    }

    /// The index ranges of the beams at relative angles `from..=to` (`to - from` below
    /// `2 pi`, any start), widened by one beam and a little on each side.
    fn beams_between(&self, from: f64, to: f64) -> impl Iterator<Item = (usize, usize)> + use<> {
        let step = self.increment.abs();
        let margin = step + 1e-9;
        let last = self.dirs.len() as f64 - 1.0;
        let tau = std::f64::consts::TAU;
        [-1.0, 0.0, 1.0].into_iter().filter_map(move |k: f64| {
            let lo = ceil_i64((from + k * tau - margin) / step).max(0);
            let hi = (floor_i64((to + k * tau + margin) / step) as f64).min(last) as i64;
            (lo <= hi).then_some((lo as usize, hi as usize))
        })
    }
}

/// Layers of the ziggurat.
const ZIGGURAT_LAYERS: usize = 128;
/// The ziggurat's base layer starts at this x (Marsaglia and Tsang's 128-layer value).
const ZIGGURAT_R: f64 = 3.442_619_855_899;
/// The area of each layer (and of the base with its tail).
const ZIGGURAT_V: f64 = 9.912_563_035_262_17e-3;

/// The ziggurat's tables: the layers' right edges `x[0..=128]` (`x[0]` the base's width
/// with its tail folded in, `x[1] = R`, `x[128] = 0`) and the ratios `x[i + 1] / x[i]`.
struct Ziggurat {
    x: [f64; ZIGGURAT_LAYERS + 1],
    ratio: [f64; ZIGGURAT_LAYERS],
}

impl Ziggurat {
    fn new() -> Self {
        let mut x = [0.0; ZIGGURAT_LAYERS + 1];
        let mut f = (-0.5 * ZIGGURAT_R * ZIGGURAT_R).exp();
        x[0] = ZIGGURAT_V / f;
        x[1] = ZIGGURAT_R;
        for i in 2..ZIGGURAT_LAYERS {
            x[i] = (-2.0 * (ZIGGURAT_V / x[i - 1] + f).ln()).sqrt();
            f = (-0.5 * x[i] * x[i]).exp();
        }
        x[ZIGGURAT_LAYERS] = 0.0;
        let mut ratio = [0.0; ZIGGURAT_LAYERS];
        for i in 0..ZIGGURAT_LAYERS {
            ratio[i] = x[i + 1] / x[i];
        }
        Self { x, ratio }
    }
}

/// A draw from the standard normal distribution by the ziggurat method: one draw of the
/// generator and a multiplication nearly always (99 %), a rejection test with two
/// exponentials in the layers' wedges, and the tail beyond `R` by Marsaglia's method.
fn standard_normal(rng: &mut Rng) -> f64 {
    static TABLES: std::sync::OnceLock<Ziggurat> = std::sync::OnceLock::new();
    let z = TABLES.get_or_init(Ziggurat::new);
    loop {
        let bits = rng.next_u64();
        // The layer from the low 7 bits, a signed uniform from the top 53.
        let i = (bits & (ZIGGURAT_LAYERS as u64 - 1)) as usize;
        let u = 2.0 * ((bits >> 11) as f64 * (1.0 / (1_u64 << 53) as f64)) - 1.0;
        if u.abs() < z.ratio[i] {
            return u * z.x[i];
        }
        if i == 0 {
            // The tail beyond R.
            loop {
                let a = (1.0 - rng.uniform()).ln() / ZIGGURAT_R;
                let b = (1.0 - rng.uniform()).ln();
                if -2.0 * b >= a * a {
                    return if u < 0.0 {
                        a - ZIGGURAT_R
                    } else {
                        ZIGGURAT_R - a
                    };
                }
            }
        }
        let x = u * z.x[i];
        let f0 = (-0.5 * (z.x[i] * z.x[i] - x * x)).exp();
        let f1 = (-0.5 * (z.x[i + 1] * z.x[i + 1] - x * x)).exp();
        if f1 + rng.uniform() * (f0 - f1) < 1.0 {
            return x;
        }
    }
}

/// `atan2(y, x)` to within 1e-7 rad without a library call (arguments reduced to
/// `|u| <= tan(pi/8)`, then eight terms of the series of `atan u`): for choosing the beams
/// a wall subtends, whose one-beam margin (6 mrad for the URG-04LX) is far wider.
#[inline]
fn fast_atan2(y: f64, x: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    let (ax, ay) = (x.abs(), y.abs());
    let (big, small) = if ax >= ay { (ax, ay) } else { (ay, ax) };
    if big.is_nan() || big <= 0.0 || big.is_infinite() {
        return y.atan2(x);
    }
    let t = small / big;
    // atan t = pi/4 + atan((t - 1) / (t + 1)) brings t in [0, 1] to |u| <= tan(pi/8).
    let (u, base) = if t > 0.414_213_562_373_095 {
        ((t - 1.0) / (t + 1.0), FRAC_PI_4)
    } else {
        (t, 0.0)
    };
    let u2 = u * u;
    let series = u
        * (1.0
            + u2 * (-1.0 / 3.0
                + u2 * (1.0 / 5.0
                    + u2 * (-1.0 / 7.0
                        + u2 * (1.0 / 9.0 + u2 * (-1.0 / 11.0 + u2 * (1.0 / 13.0 - u2 / 15.0)))))));
    let mut a = base + series;
    if ay > ax {
        a = FRAC_PI_2 - a;
    }
    if x < 0.0 {
        a = PI - a;
    }
    if y < 0.0 { -a } else { a }
}

/// `x.round()` (halves away from zero) without a library call; `x` unchanged when it is
/// not finite or too large to have a fraction.
#[inline]
fn round_half_away(x: f64) -> f64 {
    if x.is_nan() || x.abs() >= 4_503_599_627_370_496.0 {
        return x;
    }
    let t = (x.abs() + 0.5) as i64 as f64;
    // x.abs() + 0.5 may round up just below a half: keep f64::round's answer there.
    let t = if x.abs() < t - 0.5 { t - 1.0 } else { t };
    t.copysign(x)
}

/// True when `a` should win a tie against `b` (the world's order: walls by index, then discs).
fn target_order(a: Target, b: Target) -> bool {
    match (a, b) {
        (Target::Wall(i), Target::Wall(j)) | (Target::Disc(i), Target::Disc(j)) => i < j,
        (Target::Wall(_), Target::Disc(_)) => true,
        (Target::Disc(_), Target::Wall(_)) => false,
    }
}

fn finite(p: Point2) -> bool {
    p.x.is_finite() && p.y.is_finite()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    #[test]
    fn same_ranges_as_the_world_on_random_rays() {
        let mut rng = Rng::new(3);
        let mut world = World::new();
        for _ in 0..60 {
            let a = Point2::new(rng.range(-6.0, 6.0), rng.range(-6.0, 6.0));
            let b = a + Vector2::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
            world.add_segment(a, b);
        }
        // Grid-aligned walls, as in arenas: rays along them and through their ends.
        for k in -4..4 {
            let x = 1.2 * f64::from(k) + 0.6;
            world.add_segment(Point2::new(x, -0.6), Point2::new(x, 0.6));
            world.add_segment(Point2::new(-0.6, x), Point2::new(0.6, x));
        }
        for _ in 0..10 {
            world.add_disc(
                Point2::new(rng.range(-6.0, 6.0), rng.range(-6.0, 6.0)),
                rng.range(0.05, 0.5),
            );
        }
        for cell in [0.3, 0.5, 1.2, 5.0] {
            let index = WorldIndex::new(&world, cell);
            for _ in 0..3000 {
                let o = Point2::new(rng.range(-8.0, 8.0), rng.range(-8.0, 8.0));
                let angle = if rng.chance(0.2) {
                    f64::from(rng.below(8) as u32) * std::f64::consts::FRAC_PI_4
                } else {
                    rng.range(-4.0, 4.0)
                };
                let max = rng.range(0.0, 12.0);
                let fast = index.cast(o, angle, max).map(|h| h.range);
                let slow = world.cast(o, angle, max).map(|h| h.range);
                match (fast, slow) {
                    (Some(f), Some(s)) => assert!((f - s).abs() < 1e-9, "{f} vs {s}"),
                    (None, None) => {}
                    other => panic!("{other:?} at {o} angle {angle} max {max}"),
                }
            }
        }
    }

    /// The sweep of `scan_into` gives, beam by beam, what `cast_dir` gives along the same
    /// direction: random worlds, poses on and off walls, both senses of rotation, full turns.
    #[test]
    fn the_sweep_agrees_with_casting_beam_by_beam() {
        let mut rng = Rng::new(17);
        let (mut hits, mut misses) = (0, 0);
        for trial in 0..40 {
            let mut world = World::new();
            for _ in 0..(if trial % 5 == 0 { 700 } else { 40 }) {
                let a = Point2::new(rng.range(-6.0, 6.0), rng.range(-6.0, 6.0));
                let b = a + Vector2::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
                world.add_segment(a, b);
            }
            for k in -3..3 {
                let x = 1.2 * f64::from(k);
                world.add_segment(Point2::new(x, -0.6), Point2::new(x, 0.6));
            }
            for _ in 0..8 {
                world.add_disc(
                    Point2::new(rng.range(-6.0, 6.0), rng.range(-6.0, 6.0)),
                    rng.range(0.05, 0.5),
                );
            }
            let index = WorldIndex::new(&world, 0.6);
            let mut model = LaserModel::urg04lx().ideal();
            match trial % 4 {
                1 => {
                    model.angle_increment = -model.angle_increment;
                    model.angle_min = -model.angle_min;
                }
                2 => {
                    model.beams = 1024;
                    model.angle_min = -std::f64::consts::PI;
                }
                3 => model.range_max = 30.0,
                _ => {}
            }
            for _ in 0..20 {
                let o = if rng.chance(0.1) {
                    // On a wall's line, or at a wall's end.
                    let w = world.walls[rng.below(world.walls.len())];
                    if rng.chance(0.5) {
                        w.a
                    } else {
                        w.a + (w.b - w.a) * 0.5
                    }
                } else {
                    Point2::new(rng.range(-7.0, 7.0), rng.range(-7.0, 7.0))
                };
                let yaw = if rng.chance(0.3) {
                    f64::from(rng.below(8) as u32) * std::f64::consts::FRAC_PI_4
                } else {
                    rng.range(-4.0, 4.0)
                };
                let pose = laserlines::math::Isometry2::new(o.coords, yaw);
                let mut scan = Scan::default();
                let mut truth = Vec::new();
                index.scan_into(&pose, &model, &mut Rng::new(1), &mut scan, &mut truth);
                let (s0, c0) = (yaw + model.angle_min).sin_cos();
                let (si, ci) = model.angle_increment.sin_cos();
                let mut dir = Vector2::new(c0, s0);
                for (i, &got) in truth.iter().enumerate() {
                    if i > 0 {
                        dir = Vector2::new(ci * dir.x - si * dir.y, si * dir.x + ci * dir.y);
                    }
                    let want = index
                        .cast_dir(o, dir, model.range_max)
                        .map(|h| h.range)
                        .filter(|&r| r >= model.range_min && r > 0.0);
                    if want.is_some() {
                        hits += 1;
                    } else {
                        misses += 1;
                    }
                    match want {
                        Some(w) => assert!(
                            (got - w).abs() <= 1e-12 * (1.0 + w),
                            "trial {trial} beam {i}: {got} vs {w} at {o} yaw {yaw}"
                        ),
                        None => assert!(got.is_nan(), "trial {trial} beam {i}: {got} vs none"),
                    }
                }
            }
        }
        assert!(
            hits > 100_000 && misses > 1000,
            "{hits} hits, {misses} misses"
        );
    }

    #[test]
    fn the_ziggurat_draws_a_standard_normal() {
        let mut rng = Rng::new(21);
        let n = 2_000_000;
        let (mut sum, mut sum2, mut beyond2, mut beyond3, mut beyond4) = (0.0, 0.0, 0, 0, 0);
        let mut positive = 0;
        for _ in 0..n {
            let x = standard_normal(&mut rng);
            assert!(x.is_finite());
            sum += x;
            sum2 += x * x;
            beyond2 += usize::from(x.abs() > 2.0);
            beyond3 += usize::from(x.abs() > 3.0);
            beyond4 += usize::from(x.abs() > 4.0);
            positive += usize::from(x > 0.0);
        }
        let nf = n as f64;
        let mean = sum / nf;
        let var = sum2 / nf - mean * mean;
        assert!(mean.abs() < 0.003, "mean {mean}");
        assert!((var - 1.0).abs() < 0.005, "variance {var}");
        // P(|x| > 2) = 0.0455, P(|x| > 3) = 0.0027, P(|x| > 4) = 6.3e-5.
        let p = |k: usize| k as f64 / nf;
        assert!((p(beyond2) - 0.045_5).abs() < 0.001, "{}", p(beyond2));
        assert!((p(beyond3) - 0.002_70).abs() < 0.000_2, "{}", p(beyond3));
        assert!((p(beyond4) - 6.33e-5).abs() < 2.5e-5, "{}", p(beyond4));
        assert!((p(positive) - 0.5).abs() < 0.002);
    }

    #[test]
    fn fast_atan2_is_close() {
        let mut rng = Rng::new(8);
        let mut worst: f64 = 0.0;
        for _ in 0..200_000 {
            let (x, y) = (rng.range(-10.0, 10.0), rng.range(-10.0, 10.0));
            worst = worst.max((fast_atan2(y, x) - y.atan2(x)).abs());
        }
        for (x, y) in [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0), (1.0, 1.0)] {
            worst = worst.max((fast_atan2(y, x) - f64::atan2(y, x)).abs());
        }
        assert!(worst < 1e-7, "{worst}");
        assert!(fast_atan2(f64::NAN, 1.0).is_nan());
    }

    #[test]
    fn fast_rounding_agrees_with_the_library() {
        let mut rng = Rng::new(5);
        let specials = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            2.5,
            -2.5,
            0.499_999_999_999_999_94,
            1e15 + 0.5,
            4_503_599_627_370_495.5,
            1e300,
            -7.000_000_000_000_001,
        ];
        for x in specials
            .into_iter()
            .chain((0..10_000).map(|_| rng.range(-5000.0, 5000.0)))
        {
            assert_eq!(round_half_away(x).to_bits(), x.round().to_bits(), "{x}");
            if x.abs() < 1e15 {
                assert_eq!(floor_i64(x), x.floor() as i64, "{x}");
                assert_eq!(ceil_i64(x), x.ceil() as i64, "{x}");
            }
        }
        assert!(round_half_away(f64::NAN).is_nan());
        assert_eq!(round_half_away(f64::INFINITY), f64::INFINITY);
    }

    #[test]
    fn degenerate_inputs_give_none() {
        let mut world = World::new();
        world.add_segment(Point2::new(1.0, -1.0), Point2::new(1.0, 1.0));
        let index = WorldIndex::new(&world, 0.5);
        assert!(index.cast(Point2::new(f64::NAN, 0.0), 0.0, 5.0).is_none());
        assert!(index.cast(Point2::origin(), f64::INFINITY, 5.0).is_none());
        assert!(index.cast(Point2::origin(), 0.0, -1.0).is_none());
        assert!(index.cast(Point2::origin(), 0.0, 0.5).is_none());
        assert!(index.cast(Point2::new(50.0, 50.0), 0.0, 5.0).is_none());
        let empty = WorldIndex::new(&World::new(), 0.5);
        assert!(empty.cast(Point2::origin(), 0.0, 5.0).is_none());
        assert!((index.cast(Point2::origin(), 0.0, 5.0).unwrap().range - 1.0).abs() < 1e-12);
    }
}
