//! A fence: a rectangle in the explorer's map frame that the robot keeps inside, as an
//! operator who knows the extent of the arena sets it (a virtual wall, as a costmap's keep-out
//! zone is one). An arena open at its entrance, or with a gap in its outer wall, otherwise
//! leads a wall follower out onto the floor around it, where there is nothing to map.
//!
//! The explorer treats the fence as a wall wherever its laser would see one:
//! - each beam that reaches the fence within the laser's range before a real surface (or
//!   returns nothing) shows it, and runs of such beams along one side of the fence become
//!   lines ([`fence_lines`]), which the sectors report and the wall follower follows;
//! - its points near the robot join the safety layer's ([`Fence::points_near`]);
//! - the planner closes the cells beyond it and never takes them for unknown ground.
//!
//! The map is the laser's alone: the fence is never written into it. The fence acts while the
//! robot's own estimate of where it stands lies inside it: a robot whose estimate is outside
//! (it started there, or its estimate drifted across) is not held by it. The lines it adds may
//! cover beams that a real line of the same scan covers too (a beam whose return lies beyond
//! the fence).

use laserlines::Line;
use laserlines::Scan;
use laserlines::geometry::polar_line;
use laserlines::math::{Isometry2, Matrix2, Point2, Vector2};
use laserlines::params::{self, ParamsError};

/// A beam shows the fence when the fence lies nearer than its return by more than this, m
/// (a real wall standing on the fence is not doubled by it).
const NEARER_BY: f64 = 0.05;

/// A rectangle in the explorer's map frame, m and rad: the odometry frame at the first scan,
/// which is the robot's start pose when its odometry starts at zero (as in the simulator).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(deny_unknown_fields)
)]
pub struct Fence {
    /// Centre `[x, y]`, m.
    pub centre: [f64; 2],
    /// Half the side lengths `[along, across]` the rectangle's own axes, m.
    pub half_extent: [f64; 2],
    /// Direction of the rectangle's first axis in the map frame, rad.
    pub yaw: f64,
}

impl Fence {
    /// The axis-aligned box `lo`..`hi` of a frame `world` as a fence in the map frame of a
    /// robot that starts at `world_from_start` (its start pose in `world`) with its odometry
    /// at zero.
    #[must_use]
    pub fn from_box(lo: Point2, hi: Point2, world_from_start: &Isometry2) -> Self {
        let centre = world_from_start.inverse() * Point2::from((lo.coords + hi.coords) * 0.5);
        Self {
            centre: [centre.x, centre.y],
            half_extent: [(hi.x - lo.x).abs() * 0.5, (hi.y - lo.y).abs() * 0.5],
            yaw: 0.0 - world_from_start.rotation.angle(),
        }
    }

    /// Checks that every number is finite and the half extents positive.
    ///
    /// # Errors
    /// A [`ParamsError`] naming the first bad field.
    pub fn validate(&self) -> Result<(), ParamsError> {
        params::finite("fence.centre", self.centre[0])?;
        params::finite("fence.centre", self.centre[1])?;
        params::positive("fence.half_extent", self.half_extent[0])?;
        params::positive("fence.half_extent", self.half_extent[1])?;
        params::finite("fence.yaw", self.yaw)
    }

    /// `p` (map frame) in the rectangle's own axes, from its centre.
    fn local(&self, p: Point2) -> Vector2 {
        self.local_with(p, self.yaw.sin_cos())
    }

    /// [`Fence::local`] with the yaw's sine and cosine given.
    fn local_with(&self, p: Point2, (s, c): (f64, f64)) -> Vector2 {
        let d = Vector2::new(p.x - self.centre[0], p.y - self.centre[1]);
        Vector2::new(c * d.x + s * d.y, -s * d.x + c * d.y)
    }

    /// True when `p` (map frame) lies inside the fence.
    #[must_use]
    pub fn contains(&self, p: Point2) -> bool {
        self.inside_test()(p)
    }

    /// [`Fence::contains`] as a function, for many points (the yaw's sine and cosine once).
    pub fn inside_test(&self) -> impl Fn(Point2) -> bool + '_ {
        let sc = self.yaw.sin_cos();
        move |p| {
            let q = self.local_with(p, sc);
            q.x.abs() < self.half_extent[0] && q.y.abs() < self.half_extent[1]
        }
    }

    /// The corners, map frame, counter-clockwise; side `k` runs from corner `k` to `k + 1`.
    #[must_use]
    pub fn corners(&self) -> [Point2; 4] {
        let (s, c) = self.yaw.sin_cos();
        let [hx, hy] = self.half_extent;
        [(hx, -hy), (hx, hy), (-hx, hy), (-hx, -hy)].map(|(x, y)| {
            Point2::new(
                self.centre[0] + c * x - s * y,
                self.centre[1] + s * x + c * y,
            )
        })
    }

    /// Where a ray from `origin` (map frame, inside the fence) along `dir` leaves it: the
    /// distance in lengths of `dir` (m for a unit vector), and the side. `None` from outside
    /// the fence, or for a `dir` that is zero or not finite.
    #[must_use]
    pub fn ray_exit(&self, origin: Point2, dir: Vector2) -> Option<(f64, usize)> {
        if !self.contains(origin) {
            return None;
        }
        self.exit_local(self.local(origin), dir, self.yaw.sin_cos())
    }

    /// [`Fence::ray_exit`] from a point inside, given in the rectangle's own axes (`o`), with
    /// the yaw's sine and cosine.
    fn exit_local(&self, o: Vector2, dir: Vector2, (s, c): (f64, f64)) -> Option<(f64, usize)> {
        let d = Vector2::new(c * dir.x + s * dir.y, -s * dir.x + c * dir.y);
        // Sides: 0 at +x, 1 at +y, 2 at -x, 3 at -y (of the rectangle's axes).
        let mut best: Option<(f64, usize)> = None;
        for (axis, (o, d)) in [(o.x, d.x), (o.y, d.y)].into_iter().enumerate() {
            if d == 0.0 || !d.is_finite() {
                continue;
            }
            let h = self.half_extent[axis];
            let (t, side) = if d > 0.0 {
                ((h - o) / d, axis)
            } else {
                ((-h - o) / d, axis + 2)
            };
            if best.is_none_or(|(b, _)| t < b) {
                best = Some((t, side));
            }
        }
        best
    }

    /// Points of the fence within `reach` of `p` (map frame), `step` apart along each side,
    /// appended to `out`.
    pub fn points_near(&self, p: Point2, reach: f64, step: f64, out: &mut Vec<Point2>) {
        if !(step > 0.0 && reach > 0.0) {
            return;
        }
        let k = self.corners();
        for i in 0..4 {
            let (a, b) = (k[i], k[(i + 1) % 4]);
            let len = (b - a).norm();
            if len <= 0.0 {
                continue;
            }
            let u = (b - a) / len;
            let along = (p - a).dot(&u);
            let off2 = (p - a).norm_squared() - along * along;
            let half2 = reach * reach - off2;
            if half2 < 0.0 {
                continue;
            }
            let half = half2.sqrt();
            let (t0, t1) = ((along - half).max(0.0), (along + half).min(len));
            let mut t = (t0 / step).ceil() * step;
            while t <= t1 {
                out.push(a + u * t);
                t += step;
            }
        }
    }
}

/// The fence as the laser at `map_from_laser` sees it in `scan`: one line (laser frame) per
/// run of two or more consecutive beams that meet the same side of the fence within the
/// laser's range and more than 5 cm before their return (or that return nothing), from the
/// first beam's point on the fence to the last's. Lines are exact (no noise): `rms` 0 and a
/// zero covariance. Appended to `out`; nothing when the laser stands outside the fence.
pub fn fence_lines(fence: &Fence, scan: &Scan, map_from_laser: &Isometry2, out: &mut Vec<Line>) {
    let origin = Point2::from(map_from_laser.translation.vector);
    if !fence.contains(origin) {
        return;
    }
    let window = scan.range_window(None);
    let yaw = map_from_laser.rotation.angle();
    // The laser's place in the rectangle's axes, once for all beams.
    let (o, sc) = (fence.local(origin), fence.yaw.sin_cos());
    // The current run: its side, first beam and point (laser frame), last beam and point.
    let mut run: Option<(usize, usize, Point2, usize, Point2)> = None;
    let close = |run: Option<(usize, usize, Point2, usize, Point2)>, out: &mut Vec<Line>| {
        if let Some((_, first, a, last, b)) = run
            && last > first
            && let Some(line) = exact_line(first, a, last, b)
        {
            out.push(line);
        }
    };
    for (i, &r) in scan.ranges.iter().enumerate() {
        let phi = scan.angle_min + scan.angle_increment * i as f64;
        let (s, c) = (phi + yaw).sin_cos();
        let hit = fence
            .exit_local(o, Vector2::new(c, s), sc)
            .filter(|&(d, _)| d <= scan.range_max && (!window.contains(r) || d < r - NEARER_BY));
        let Some((d, side)) = hit else {
            close(run.take(), out);
            continue;
        };
        let p = Point2::new(d * phi.cos(), d * phi.sin());
        run = match run {
            Some((run_side, first, a, _, _)) if run_side == side => Some((side, first, a, i, p)),
            _ => {
                close(run, out);
                Some((side, i, p, i, p))
            }
        };
    }
    close(run, out);
}

/// A noise-free line from `a` (beam `first`) to `b` (beam `last`), laser frame; `None` when
/// the two points coincide.
fn exact_line(first: usize, a: Point2, last: usize, b: Point2) -> Option<Line> {
    let (r, alpha) = polar_line(a, b)?;
    Some(Line {
        start: a,
        end: b,
        r,
        alpha,
        first,
        last,
        points: last - first + 1,
        rms: 0.0,
        covariance: Matrix2::zeros(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn room() -> Fence {
        // x in -1..3, y in -2..2.
        Fence {
            centre: [1.0, 0.0],
            half_extent: [2.0, 2.0],
            yaw: 0.0,
        }
    }

    #[test]
    fn a_box_seen_from_a_turned_start_is_the_same_rectangle() {
        let start = Isometry2::new(Vector2::new(1.0, 1.0), 0.3);
        let f = Fence::from_box(Point2::new(0.0, 0.0), Point2::new(4.0, 2.0), &start);
        // The world point (3.9, 1.9) is inside, (4.1, 1.0) and (2.0, -0.1) are not.
        let inv = start.inverse();
        assert!(f.contains(inv * Point2::new(3.9, 1.9)));
        assert!(!f.contains(inv * Point2::new(4.1, 1.0)));
        assert!(!f.contains(inv * Point2::new(2.0, -0.1)));
        // The world corner (4, 2) is a corner.
        let corner = inv * Point2::new(4.0, 2.0);
        assert!(f.corners().iter().any(|c| (c - corner).norm() < 1e-12));
    }

    #[test]
    fn a_ray_leaves_through_the_side_it_meets_first() {
        let f = room();
        let (d, side) = f
            .ray_exit(Point2::origin(), Vector2::new(1.0, 0.0))
            .unwrap();
        assert!((d - 3.0).abs() < 1e-12 && side == 0);
        let (d, side) = f
            .ray_exit(Point2::origin(), Vector2::new(-1.0, 0.0))
            .unwrap();
        assert!((d - 1.0).abs() < 1e-12 && side == 2);
        let u = Vector2::new(1.0, 1.0).normalize();
        let (d, side) = f.ray_exit(Point2::origin(), u).unwrap();
        assert!((d - 2.0 * 2f64.sqrt()).abs() < 1e-12 && side == 1);
        assert!(f.ray_exit(Point2::new(5.0, 0.0), u).is_none());
    }

    #[test]
    fn points_near_lie_on_the_fence_within_reach() {
        let f = room();
        let mut pts = Vec::new();
        // 0.5 m from the side x = -1: its points within 1 m span 2 sqrt(0.75) = 1.73 m.
        f.points_near(Point2::new(-0.5, 0.0), 1.0, 0.03, &mut pts);
        assert!(!pts.is_empty());
        for p in &pts {
            assert!((p.x + 1.0).abs() < 1e-12, "{p}");
            assert!((p - Point2::new(-0.5, 0.0)).norm() <= 1.0 + 1e-12);
        }
        assert_eq!(pts.len(), 58, "1.73 m at 3 cm");
        pts.clear();
        f.points_near(Point2::new(1.0, 0.0), 1.0, 0.03, &mut pts);
        assert!(pts.is_empty());
    }

    #[test]
    fn lines_show_the_fence_where_nothing_nearer_stands() {
        let f = room();
        // A laser at the origin facing +x, 181 beams over +-90 deg: a real wall at x = 2 m
        // in front (|y| < 0.5), nothing elsewhere.
        let n = 181;
        let inc = std::f64::consts::PI / 180.0;
        let ranges = (0..n)
            .map(|i| {
                let phi = -std::f64::consts::FRAC_PI_2 + inc * i as f64;
                let r = 2.0 / phi.cos();
                if phi.cos() > 0.0 && (r * phi.sin()).abs() < 0.5 {
                    r
                } else {
                    f64::NAN
                }
            })
            .collect();
        let scan = Scan::new(-std::f64::consts::FRAC_PI_2, inc, 0.02, 5.6, ranges).unwrap();
        let mut lines = Vec::new();
        fence_lines(&f, &scan, &Isometry2::identity(), &mut lines);
        // The sides y = -2 and y = 2 (to where they leave the range) and x = 3 beside the
        // wall, on both sides of it.
        let on = |l: &Line, r: f64, alpha_deg: f64| {
            (l.r - r).abs() < 1e-9 && (l.alpha.to_degrees() - alpha_deg).abs() < 1e-9
        };
        assert!(lines.iter().any(|l| on(l, 2.0, -90.0)), "{lines:?}");
        assert!(lines.iter().any(|l| on(l, 2.0, 90.0)), "{lines:?}");
        let far: Vec<&Line> = lines.iter().filter(|l| on(l, 3.0, 0.0)).collect();
        assert_eq!(far.len(), 2, "{lines:?}");
        for l in &far {
            assert!(
                l.start.y.abs().min(l.end.y.abs()) >= 0.5 * 1.5 - 1e-9,
                "{l:?}"
            );
        }
        // Every line lies on the fence, within the laser's range.
        for l in &lines {
            for p in [l.start, l.end] {
                assert!(p.coords.norm() <= 5.6 + 1e-9);
                let q = f.local(p);
                let on_side = (q.x.abs() - 2.0).abs() < 1e-9 || (q.y.abs() - 2.0).abs() < 1e-9;
                assert!(on_side, "{p}");
            }
        }
        // From outside, nothing.
        lines.clear();
        let outside = Isometry2::new(Vector2::new(4.0, 0.0), 0.0);
        fence_lines(&f, &scan, &outside, &mut lines);
        assert!(lines.is_empty());
    }
    #[test]
    fn lines_of_a_turned_fence_seen_from_a_moved_laser_lie_on_it() {
        let f = Fence {
            centre: [0.5, -0.3],
            half_extent: [2.5, 1.5],
            yaw: 0.4,
        };
        let map_from_laser = Isometry2::new(Vector2::new(0.3, -0.2), 0.7);
        // All round, no returns: every side is seen, each as one line or (where the scan's
        // first and last beams meet) two.
        let n = 360;
        let scan = Scan::new(-PI, 2.0 * PI / n as f64, 0.02, 5.6, vec![f64::NAN; n]).unwrap();
        let mut lines = Vec::new();
        fence_lines(&f, &scan, &map_from_laser, &mut lines);
        assert!((4..=5).contains(&lines.len()), "{lines:?}");
        let at = f.local(Point2::from(map_from_laser.translation.vector));
        let mut sides = [false; 4];
        for l in &lines {
            let (a, b) = (
                f.local(map_from_laser * l.start),
                f.local(map_from_laser * l.end),
            );
            // Both ends on one side; `r` is the laser's distance to that side's line.
            let side = [
                (a.x - 2.5, b.x - 2.5, 2.5 - at.x),
                (a.y - 1.5, b.y - 1.5, 1.5 - at.y),
                (a.x + 2.5, b.x + 2.5, at.x + 2.5),
                (a.y + 1.5, b.y + 1.5, at.y + 1.5),
            ]
            .iter()
            .position(|&(da, db, _)| da.abs() < 1e-9 && db.abs() < 1e-9)
            .unwrap_or_else(|| panic!("{l:?} off the fence"));
            sides[side] = true;
            let expected = [2.5 - at.x, 1.5 - at.y, at.x + 2.5, at.y + 1.5][side];
            assert!((l.r - expected).abs() < 1e-9, "{l:?}: r {expected}");
            let normal = Vector2::new(l.alpha.cos(), l.alpha.sin());
            assert!((l.start.coords.dot(&normal) - l.r).abs() < 1e-9, "{l:?}");
            assert!(l.alpha > -PI && l.alpha <= PI);
        }
        assert_eq!(sides, [true; 4]);
    }

    #[test]
    fn a_side_straight_behind_the_laser_has_alpha_pi() {
        let f = room();
        // Facing +x, the side x = -1 seen by beams round 180 deg.
        let n = 361;
        let scan = Scan::new(-PI, 2.0 * PI / 360.0, 0.02, 5.6, vec![f64::NAN; n]).unwrap();
        let mut lines = Vec::new();
        fence_lines(&f, &scan, &Isometry2::identity(), &mut lines);
        let behind: Vec<&Line> = lines.iter().filter(|l| (l.r - 1.0).abs() < 1e-9).collect();
        assert!(!behind.is_empty(), "{lines:?}");
        for l in behind {
            assert_eq!(l.alpha, PI, "{l:?}");
        }
    }
}
