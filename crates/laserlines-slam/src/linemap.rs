//! The line map: the lines of all scans placed in the map frame by their scans' poses, and
//! merged where they are one wall (the paper's object-based map).
//!
//! Lines are taken longest first. A line joins a wall already in the map when their
//! directions agree within [`LineMapParams::max_angle_rad`], both of its end points lie
//! within [`LineMapParams::max_offset_m`] of the wall's line, and along the wall it overlaps
//! or leaves a gap of at most [`LineMapParams::max_gap_m`]. A wall's line is the
//! length-weighted mean of its members' lines; its extent covers theirs.

use std::collections::HashMap;

use laserlines::Line;
use laserlines::math::{Point2, Vector2, wrap_angle};

use crate::cloud::FastHash;
use crate::se2::Se2;

/// Settings of [`build_line_map`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineMapParams {
    /// Largest angle between a line and a wall it joins, rad (default 3 deg).
    pub max_angle_rad: f64,
    /// Largest distance of a line's end points from a wall's line, m (default 0.06).
    pub max_offset_m: f64,
    /// Largest gap along a wall bridged by a line, m (default 0.2).
    pub max_gap_m: f64,
    /// Lines shorter than this are left out, m (default 0.2).
    pub min_length_m: f64,
}

impl Default for LineMapParams {
    fn default() -> Self {
        Self {
            max_angle_rad: 3f64.to_radians(),
            max_offset_m: 0.06,
            max_gap_m: 0.2,
            min_length_m: 0.2,
        }
    }
}

/// A wall of the line map, in the map frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapLine {
    /// One end, m.
    pub start: Point2,
    /// The other end, m.
    pub end: Point2,
    /// Distance of the infinite line from the map origin, m (`>= 0`).
    pub r: f64,
    /// Direction of its normal, rad.
    pub alpha: f64,
    /// Scan lines merged into it.
    pub lines: usize,
    /// Scan points supporting those lines.
    pub points: usize,
}

/// A wall being built: weighted sums of its members' normals and offsets, and its extent.
#[derive(Debug, Clone, Copy)]
struct Wall {
    normal_sum: Vector2,
    offset_sum: f64,
    weight: f64,
    lo: f64,
    hi: f64,
    lines: usize,
    points: usize,
}

impl Wall {
    fn normal(&self) -> Vector2 {
        let n = self.normal_sum.norm();
        if n > 0.0 {
            self.normal_sum / n
        } else {
            Vector2::new(1.0, 0.0)
        }
    }
    fn offset(&self) -> f64 {
        self.offset_sum / self.weight.max(1e-12)
    }
    fn direction(&self) -> Vector2 {
        let n = self.normal();
        Vector2::new(-n.y, n.x)
    }
    fn point_at(&self, s: f64) -> Point2 {
        Point2::from(self.normal() * self.offset() + self.direction() * s)
    }
}

/// Merges the lines of every scan (`lines` in the sensor frame, seen from `map_from_sensor`)
/// into walls.
#[must_use]
pub fn build_line_map<'a>(
    scans: impl Iterator<Item = (Se2, &'a [Line])>,
    params: &LineMapParams,
) -> Vec<MapLine> {
    let mut placed: Vec<(Point2, Point2, usize)> = Vec::new();
    for (pose, lines) in scans {
        for l in lines {
            let (a, b) = (pose.transform(l.start), pose.transform(l.end));
            if (b - a).norm() >= params.min_length_m
                && a.coords
                    .iter()
                    .chain(b.coords.iter())
                    .all(|v| v.is_finite())
            {
                placed.push((a, b, l.points));
            }
        }
    }
    placed.sort_by(|x, y| (y.1 - y.0).norm().total_cmp(&(x.1 - x.0).norm()));
    let mut walls: Vec<Wall> = Vec::new();
    // Walls indexed by the cells (1 m) their extents pass through.
    let mut index: HashMap<(i64, i64), Vec<usize>, FastHash> = HashMap::default();
    for (a, b, points) in placed {
        let mid = Point2::from((a.coords + b.coords) / 2.0);
        let cell = cell_of(mid);
        let mut joined = None;
        'search: for di in -1..=1 {
            for dj in -1..=1 {
                for &w in index
                    .get(&(cell.0 + di, cell.1 + dj))
                    .map_or(&[][..], |v| v)
                {
                    if fits(&walls[w], a, b, params) {
                        joined = Some(w);
                        break 'search;
                    }
                }
            }
        }
        let w = match joined {
            Some(w) => {
                add(&mut walls[w], a, b, points);
                w
            }
            None => {
                walls.push(new_wall(a, b, points));
                walls.len() - 1
            }
        };
        // Index the wall along its whole extent, so that later pieces anywhere on it find it.
        let wall = walls[w];
        let steps = ((wall.hi - wall.lo).max(0.0)).ceil() as i64;
        for k in 0..=steps {
            let c = cell_of(wall.point_at(wall.lo + (k as f64).min(wall.hi - wall.lo)));
            let list = index.entry(c).or_default();
            if !list.contains(&w) {
                list.push(w);
            }
        }
    }
    walls.iter().map(to_map_line).collect()
}

fn cell_of(p: Point2) -> (i64, i64) {
    (
        laserlines::math::floor_i64(p.x),
        laserlines::math::floor_i64(p.y),
    )
}

/// The wall of one segment.
fn new_wall(a: Point2, b: Point2, points: usize) -> Wall {
    let d = (b - a).normalize();
    let mut n = Vector2::new(d.y, -d.x);
    let mut offset = n.dot(&a.coords);
    if offset < 0.0 {
        n = -n;
        offset = -offset;
    }
    let len = (b - a).norm();
    let mut w = Wall {
        normal_sum: n * len,
        offset_sum: offset * len,
        weight: len,
        lo: 0.0,
        hi: 0.0,
        lines: 1,
        points,
    };
    let dir = w.direction();
    let (sa, sb) = (dir.dot(&a.coords), dir.dot(&b.coords));
    w.lo = sa.min(sb);
    w.hi = sa.max(sb);
    w
}

/// True when the segment `a`-`b` lies on `wall`.
fn fits(wall: &Wall, a: Point2, b: Point2, params: &LineMapParams) -> bool {
    let n = wall.normal();
    let d = (b - a) / (b - a).norm().max(1e-12);
    if d.dot(&n).abs() > params.max_angle_rad.sin() {
        return false;
    }
    let off = wall.offset();
    if (n.dot(&a.coords) - off).abs() > params.max_offset_m
        || (n.dot(&b.coords) - off).abs() > params.max_offset_m
    {
        return false;
    }
    let dir = wall.direction();
    let (sa, sb) = (dir.dot(&a.coords), dir.dot(&b.coords));
    sa.min(sb) <= wall.hi + params.max_gap_m && sa.max(sb) >= wall.lo - params.max_gap_m
}

/// Adds the segment `a`-`b` to `wall`.
fn add(wall: &mut Wall, a: Point2, b: Point2, points: usize) {
    let len = (b - a).norm();
    let n0 = wall.normal();
    let d = (b - a) / len.max(1e-12);
    let mut n = Vector2::new(d.y, -d.x);
    if n.dot(&n0) < 0.0 {
        n = -n;
    }
    let offset = n.dot(&a.coords);
    wall.normal_sum += n * len;
    wall.offset_sum += offset * len;
    wall.weight += len;
    let dir = wall.direction();
    let (sa, sb) = (dir.dot(&a.coords), dir.dot(&b.coords));
    wall.lo = wall.lo.min(sa.min(sb));
    wall.hi = wall.hi.max(sa.max(sb));
    wall.lines += 1;
    wall.points += points;
}

fn to_map_line(w: &Wall) -> MapLine {
    let n = w.normal();
    let (mut r, mut alpha) = (w.offset(), n.y.atan2(n.x));
    if r < 0.0 {
        r = -r;
        alpha = wrap_angle(alpha + std::f64::consts::PI);
    }
    MapLine {
        start: w.point_at(w.lo),
        end: w.point_at(w.hi),
        r,
        alpha,
        lines: w.lines,
        points: w.points,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use laserlines::math::Matrix2;

    fn line(a: (f64, f64), b: (f64, f64)) -> Line {
        Line {
            start: Point2::new(a.0, a.1),
            end: Point2::new(b.0, b.1),
            r: 0.0,
            alpha: 0.0,
            first: 0,
            last: 1,
            points: 10,
            rms: 0.0,
            covariance: Matrix2::zeros(),
        }
    }

    #[test]
    fn pieces_of_one_wall_merge_and_a_parallel_wall_stays_apart() {
        // A wall along y = 2 seen in three overlapping pieces from two poses, and a parallel
        // wall 0.5 m behind it.
        let from_origin = [
            line((0.0, 2.0), (1.5, 2.0)),
            line((1.4, 2.01), (3.0, 2.01)),
            line((0.0, 2.5), (2.0, 2.5)),
        ];
        // From (2, 0) facing +y, the wall y = 2 is 2 m ahead; the piece spans map x 2.9..4.0.
        let pose = Se2::new(2.0, 0.0, std::f64::consts::FRAC_PI_2);
        let seen = [line((2.0, -0.9), (2.0, -2.0))];
        let map = build_line_map(
            [(Se2::IDENTITY, &from_origin[..]), (pose, &seen[..])].into_iter(),
            &LineMapParams::default(),
        );
        assert_eq!(map.len(), 2, "{map:?}");
        let wall = map.iter().find(|m| m.lines == 3).unwrap();
        assert!((wall.r - 2.0).abs() < 0.01, "{wall:?}");
        assert!((wall.alpha - std::f64::consts::FRAC_PI_2).abs() < 0.01);
        let xs = [wall.start.x, wall.end.x];
        assert!(
            (xs[0].min(xs[1]) - 0.0).abs() < 0.01 && (xs[0].max(xs[1]) - 4.0).abs() < 0.01,
            "{wall:?}"
        );
        let other = map.iter().find(|m| m.lines == 1).unwrap();
        assert!((other.r - 2.5).abs() < 1e-9);
    }
}
