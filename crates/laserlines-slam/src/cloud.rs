//! Points with surface normals, and the grid index that finds a point's nearest neighbour:
//! the reference side of point-to-line matching.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use laserlines::math::{Point2, Vector2};
use laserlines::{Line, RangeWindow, Scan, ScanPoint};

/// A point on a surface with the surface's unit normal there (pointing toward the sensor
/// that saw it), in some frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// The point, m.
    pub point: Point2,
    /// The unit normal.
    pub normal: Vector2,
}

/// Estimates normals of scan points (in beam order, sensor frame) from their neighbours.
///
/// For each point, the points of the beams within `half_window` either side that lie within
/// `radius(range)` of it (the larger of 0.15 m and 3.5 beam spacings at its range) are
/// fitted by principal components; a point whose neighbourhood is not flat (smaller spread
/// more than a tenth of the larger), or that has fewer than three neighbours, gets `None`.
/// Normals point toward the sensor.
#[must_use]
pub fn scan_normals(
    points: &[ScanPoint],
    angle_increment: f64,
    half_window: usize,
) -> Vec<Option<Vector2>> {
    let spacing = angle_increment.abs();
    let mut out = Vec::with_capacity(points.len());
    for (i, sp) in points.iter().enumerate() {
        let radius = (3.5 * spacing * sp.range).max(0.15);
        let lo = i.saturating_sub(half_window);
        let hi = (i + half_window + 1).min(points.len());
        let (mut n, mut sx, mut sy) = (0.0, 0.0, 0.0);
        let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
        for q in &points[lo..hi] {
            let d = q.point - sp.point;
            if d.norm_squared() > radius * radius {
                continue;
            }
            n += 1.0;
            sx += d.x;
            sy += d.y;
            sxx += d.x * d.x;
            sxy += d.x * d.y;
            syy += d.y * d.y;
        }
        out.push(if n < 3.0 {
            None
        } else {
            flat_normal(n, sx, sy, sxx, sxy, syy).map(|nv| orient_toward(nv, sp.point))
        });
    }
    out
}

/// Gives the points of `points` (in beam order) that support one of `lines` the line's
/// normal, toward the sensor: a point supports a line when its beam lies in the line's
/// `first..=last` (across the seam of a full turn when `first > last`) within three times the line's RMS residual (at least 5 mm) of it. Every
/// such point of a line whose RMS residual is `replace_rms` (m) or more takes it; on a
/// smoother line only those whose neighbourhood gave no normal ([`scan_normals`]) do.
///
/// A line is fitted to all its points, so its direction holds where the few neighbours of a
/// point are too noisy to tell one: ranges noisy to 1-2 % of the range, as cheap scanners
/// read them, leave most points without a flat neighbourhood, and the rest with normals off
/// by degrees (seven beams 0.3 m apart with 15 mm of noise fix a direction to about 4 deg).
pub fn line_normals(
    points: &[ScanPoint],
    lines: &[Line],
    replace_rms: f64,
    normals: &mut [Option<Vector2>],
) {
    for line in lines {
        let (c, s) = (line.alpha.cos(), line.alpha.sin());
        let reach = 3.0 * line.rms.max(0.005);
        // Every point of a rough line takes its normal; on a smooth one, those without one.
        let all = line.rms >= replace_rms;
        // `r >= 0`: the normal `(cos alpha, sin alpha)` points away from the sensor.
        let toward = Vector2::new(-c, -s);
        if !(reach.is_finite() && toward.x.is_finite() && toward.y.is_finite()) {
            continue;
        }
        // The points of `first..=last`; a line across the seam of a full turn has two runs,
        // from `first` to the end and from the start to `last`.
        let from = points.partition_point(|p| p.index < line.first);
        let to = points.partition_point(|p| p.index <= line.last);
        let runs = if line.wraps() {
            [(from, points.len()), (0, to)]
        } else {
            [(from, to), (0, 0)]
        };
        for (lo, hi) in runs {
            // `normals` shorter than `points` leaves the rest as they are.
            let (Some(points), Some(normals)) = (points.get(lo..hi), normals.get_mut(lo..hi))
            else {
                continue;
            };
            for (p, n) in points.iter().zip(normals) {
                if (all || n.is_none()) && (p.point.x * c + p.point.y * s - line.r).abs() <= reach {
                    *n = Some(toward);
                }
            }
        }
    }
}

/// The valid points of `scan` within `window` that have a normal ([`scan_normals`] with
/// `half_window`), sensor frame.
#[must_use]
pub fn scan_surface(scan: &Scan, window: RangeWindow, half_window: usize) -> Vec<SurfacePoint> {
    let points = scan.points(window);
    let normals = scan_normals(&points, scan.angle_increment, half_window);
    points
        .iter()
        .zip(normals)
        .filter_map(|(p, n)| {
            n.map(|normal| SurfacePoint {
                point: p.point,
                normal,
            })
        })
        .collect()
}

/// The normal of a flat spread of points given by their sums, `None` when not flat.
fn flat_normal(n: f64, sx: f64, sy: f64, sxx: f64, sxy: f64, syy: f64) -> Option<Vector2> {
    let (mx, my) = (sx / n, sy / n);
    let cxx = sxx / n - mx * mx;
    let cxy = sxy / n - mx * my;
    let cyy = syy / n - my * my;
    let tr = cxx + cyy;
    let disc = ((cxx - cyy) * (cxx - cyy) / 4.0 + cxy * cxy).sqrt();
    let big = tr / 2.0 + disc;
    let small = tr / 2.0 - disc;
    if big <= 0.0 || small > 0.1 * big {
        return None;
    }
    // Direction of the larger spread, then its perpendicular.
    let dir = if cxy.abs() > 1e-15 {
        Vector2::new(big - cyy, cxy)
    } else if cxx >= cyy {
        Vector2::new(1.0, 0.0)
    } else {
        Vector2::new(0.0, 1.0)
    };
    let len = dir.norm();
    (len > 0.0).then(|| Vector2::new(-dir.y / len, dir.x / len))
}

/// `normal` flipped, if needed, to point from `point` toward the origin.
fn orient_toward(normal: Vector2, point: Point2) -> Vector2 {
    if normal.dot(&point.coords) > 0.0 {
        -normal
    } else {
        normal
    }
}

/// A reference for point-to-line matching ([`crate::icp::match_points`]): the surface point
/// nearest to a query point.
pub trait NearestSurface {
    /// The surface point nearest to `q` within `max_distance` (m), if any; `normal` is the
    /// query's own unit normal (a reference may use it to tell apart the two faces of a thin
    /// wall; the matcher checks agreement itself).
    fn nearest_surface(
        &self,
        q: Point2,
        normal: Vector2,
        max_distance: f64,
    ) -> Option<SurfacePoint>;
}

impl NearestSurface for PointCloud {
    fn nearest_surface(
        &self,
        q: Point2,
        _normal: Vector2,
        max_distance: f64,
    ) -> Option<SurfacePoint> {
        self.nearest(q, max_distance).map(|(p, _)| *p)
    }
}

/// Points with normals in one frame, thinned to one per voxel, with a grid index for nearest
/// neighbour queries.
#[derive(Debug, Clone)]
pub struct PointCloud {
    points: Vec<SurfacePoint>,
    voxel: f64,
    voxels: HashMap<(i32, i32), u32, FastHash>,
    cell: f64,
    index: HashMap<(i32, i32), Vec<u32>, FastHash>,
}

impl PointCloud {
    /// An empty cloud keeping at most one point per square voxel of side `voxel_m`, indexed
    /// by cells of side `cell_m` (a query within `cell_m` looks at nine cells).
    #[must_use]
    pub fn new(voxel_m: f64, cell_m: f64) -> Self {
        Self {
            points: Vec::new(),
            voxel: voxel_m.max(1e-6),
            voxels: HashMap::default(),
            cell: cell_m.max(1e-3),
            index: HashMap::default(),
        }
    }

    /// Adds a point unless its voxel holds one already; true when added. Non-finite points
    /// are ignored.
    pub fn insert(&mut self, p: SurfacePoint) -> bool {
        if !(p.point.x.is_finite() && p.point.y.is_finite()) {
            return false;
        }
        let v = key(p.point, self.voxel);
        if self.voxels.contains_key(&v) {
            return false;
        }
        let id = u32::try_from(self.points.len()).unwrap_or(u32::MAX);
        if id == u32::MAX {
            return false;
        }
        self.voxels.insert(v, id);
        self.index
            .entry(key(p.point, self.cell))
            .or_default()
            .push(id);
        self.points.push(p);
        true
    }

    /// Number of points.
    #[must_use]
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// True when the cloud holds no point.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The points.
    #[must_use]
    pub fn points(&self) -> &[SurfacePoint] {
        &self.points
    }

    /// The point nearest to `q` within `max_distance` (m), with its squared distance.
    ///
    /// Looks at rings of cells around `q`'s cell, nearest first, and stops once no cell
    /// farther out can hold a nearer point.
    #[must_use]
    pub fn nearest(&self, q: Point2, max_distance: f64) -> Option<(&SurfacePoint, f64)> {
        let reach = (max_distance / self.cell).ceil().max(1.0) as i32;
        let (ci, cj) = key(q, self.cell);
        let mut best: Option<(u32, f64)> = None;
        let limit = max_distance * max_distance;
        for ring in 0..=reach {
            // Every point outside rings 0..ring is at least (ring) cells away from q.
            if let Some((_, b)) = best {
                let clear = f64::from(ring - 1).max(0.0) * self.cell;
                if ring > 0 && b <= clear * clear {
                    break;
                }
            }
            for (di, dj) in ring_cells(ring) {
                let Some(ids) = self
                    .index
                    .get(&(ci.saturating_add(di), cj.saturating_add(dj)))
                else {
                    continue;
                };
                for &id in ids {
                    let d2 = (self.points[id as usize].point - q).norm_squared();
                    if d2 <= limit && best.is_none_or(|(_, b)| d2 < b) {
                        best = Some((id, d2));
                    }
                }
            }
        }
        best.map(|(id, d2)| (&self.points[id as usize], d2))
    }
}

/// The cell offsets of the square ring at Chebyshev distance `ring` (the centre for 0).
fn ring_cells(ring: i32) -> impl Iterator<Item = (i32, i32)> {
    let top_bottom = (-ring..=ring).flat_map(move |d| [(d, -ring), (d, ring)]);
    let sides = (-ring + 1..ring).flat_map(move |d| [(-ring, d), (ring, d)]);
    // Ring 0 is the one centre cell (listed twice above).
    top_bottom
        .chain(sides)
        .take(if ring == 0 { 1 } else { usize::MAX })
}

/// The grid cell of `p` for cells of side `size`, saturating far from the origin.
fn key(p: Point2, size: f64) -> (i32, i32) {
    let f = |v: f64| {
        let k = laserlines::math::floor_i64(v / size);
        k.clamp(i64::from(i32::MIN / 2), i64::from(i32::MAX / 2)) as i32
    };
    (f(p.x), f(p.y))
}

/// A fast hasher for small integer keys (grid cells), in place of SipHash.
#[derive(Debug, Default, Clone, Copy)]
pub struct CellHasher(u64);

impl Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.write_u64(u64::from(*b));
        }
    }
    fn write_i32(&mut self, i: i32) {
        self.write_u64(u64::from(i as u32));
    }
    fn write_u64(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
}

/// Hash maps keyed by grid cells.
pub type FastHash = BuildHasherDefault<CellHasher>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_noisy_walls_points_take_its_lines_normal() {
        // A wall 2 m ahead (x = 2) with a zigzag of +-3 cm on its ranges: too rough for
        // most neighbourhoods of 7 beams, not for the line fitted to all of it. One spike
        // 0.5 m off the line keeps what its neighbourhood says.
        let inc = 0.5_f64.to_radians();
        let a0 = -30.0_f64.to_radians();
        let mut ranges: Vec<f64> = (0..121)
            .map(|i| {
                let zig = if i % 2 == 0 { 0.03 } else { -0.03 };
                2.0 / (a0 + i as f64 * inc).cos() + zig
            })
            .collect();
        ranges[60] = 1.5;
        let scan = Scan::new(a0, inc, 0.1, 10.0, ranges).unwrap();
        let pts = scan.points(RangeWindow::new(0.1, 10.0));
        let line = Line {
            start: Point2::new(2.0, -1.15),
            end: Point2::new(2.0, 1.15),
            r: 2.0,
            alpha: 0.0,
            first: 0,
            last: 120,
            points: 120,
            rms: 0.03,
            covariance: laserlines::math::Matrix2::identity() * 1e-6,
        };
        let mut normals = scan_normals(&pts, inc, 3);
        let before = normals.iter().filter(|n| n.is_some()).count();
        assert!(before < 60, "{before} neighbourhood normals");
        let spike = normals[60];
        // Below `replace_rms`, only the points without a normal of their own take the line's.
        let mut kept = normals.clone();
        line_normals(&pts, std::slice::from_ref(&line), 0.05, &mut kept);
        for (k, (a, b)) in normals.iter().zip(&kept).enumerate() {
            assert!(a.is_none() || a == b, "{k}");
        }
        assert!(kept.iter().filter(|n| n.is_some()).count() > 100);
        // A line across the seam of a full turn (`last` before `first`) gives its normal to
        // the points of beams `90..` and `..=10` only; too few normals change nothing.
        let across = Line {
            first: 90,
            last: 10,
            ..line
        };
        let mut wrapped = normals.clone();
        line_normals(&pts, &[across], 0.0, &mut wrapped);
        for (k, (a, b)) in normals.iter().zip(&wrapped).enumerate() {
            let on = k <= 10 || k >= 90;
            assert!(
                if on {
                    *b == Some(Vector2::new(-1.0, -0.0))
                } else {
                    a == b
                },
                "{k}"
            );
        }
        let mut same = normals.clone();
        line_normals(&pts, std::slice::from_ref(&line), 0.0, &mut same[..5]);
        line_normals(&pts, &[line], 0.015, &mut normals);
        for (k, n) in normals.iter().enumerate() {
            if k == 60 {
                assert_eq!(*n, spike);
            } else {
                let n = n.unwrap();
                assert!((n.x + 1.0).abs() < 1e-12 && n.y.abs() < 1e-12, "{k}: {n:?}");
            }
        }
    }

    #[test]
    fn normals_of_a_wall_point_at_the_sensor() {
        // A wall 2 m ahead (x = 2), seen over +-30 deg.
        let inc = 0.5_f64.to_radians();
        let n = 121;
        let a0 = -30.0_f64.to_radians();
        let ranges = (0..n).map(|i| 2.0 / (a0 + i as f64 * inc).cos()).collect();
        let scan = Scan::new(a0, inc, 0.1, 10.0, ranges).unwrap();
        let pts = scan.points(RangeWindow::new(0.1, 10.0));
        let normals = scan_normals(&pts, inc, 3);
        for nv in normals {
            let nv = nv.unwrap();
            assert!((nv.x + 1.0).abs() < 1e-9 && nv.y.abs() < 1e-9, "{nv:?}");
        }
    }

    #[test]
    fn a_corner_point_has_no_normal() {
        // An L: down the wall x = 1 to the corner (1, 0), then along y = 0, 5 cm apart.
        let corner: Vec<(f64, f64)> = (0..7)
            .map(|k| (1.0, 0.3 - 0.05 * f64::from(k)))
            .chain((1..7).map(|k| (1.0 - 0.05 * f64::from(k), 0.0)))
            .collect();
        let pts: Vec<ScanPoint> = corner
            .iter()
            .enumerate()
            .map(|(i, &(x, y))| ScanPoint {
                index: i,
                range: f64::hypot(x, y),
                angle: f64::atan2(y, x),
                point: Point2::new(x, y),
            })
            .collect();
        let normals = scan_normals(&pts, 0.01, 3);
        assert!(normals[6].is_none());
        let n0 = normals[0].unwrap();
        assert!((n0.x + 1.0).abs() < 1e-9, "{n0:?}");
    }

    #[test]
    fn nearest_finds_the_closest_point_within_reach() {
        let mut c = PointCloud::new(0.05, 0.3);
        let n = Vector2::new(1.0, 0.0);
        for k in 0..20 {
            assert!(c.insert(SurfacePoint {
                point: Point2::new(f64::from(k) * 0.1, 0.0),
                normal: n,
            }));
        }
        // Same voxel: thinned away.
        assert!(!c.insert(SurfacePoint {
            point: Point2::new(0.01, 0.01),
            normal: n,
        }));
        assert_eq!(c.len(), 20);
        let (p, d2) = c.nearest(Point2::new(0.74, 0.2), 0.5).unwrap();
        assert!((p.point.x - 0.7).abs() < 1e-12);
        assert!((d2 - (0.04f64 * 0.04 + 0.04)).abs() < 1e-12);
        assert!(c.nearest(Point2::new(0.74, 0.6), 0.5).is_none());
        // Reach larger than a cell.
        assert!(c.nearest(Point2::new(3.0, 0.0), 1.2).is_some());
    }
}
