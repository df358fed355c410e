//! The paper's three sectors around the robot and the "biggest and nearest" object in each.
//!
//! The field of view is split, in the ROBOT frame (REP 103: x forward, y left, angles
//! counter-clockwise from x), into
//!
//! | sector | angles | span |
//! |---|---|---|
//! | [`Sector::Left`] | +50 deg .. +120 deg | 70 deg |
//! | [`Sector::Front`] | -50 deg .. +50 deg | 100 deg |
//! | [`Sector::Right`] | -120 deg .. -50 deg | 70 deg |
//!
//! Every extracted line is moved from the laser frame into the robot frame and clipped to
//! each sector's wedge (the part of the segment whose bearing from the robot's origin lies
//! within the sector). A clipped piece is described by
//!
//! - **distance**: from the robot's origin to the nearest point of the clipped piece, m;
//! - **width**: the clipped piece's length, m (the visible length within the sector);
//! - **angle**: the line's direction in the robot frame, rad, in `(-pi/2, pi/2]` (a line has
//!   no sense of direction): 0 for a wall parallel to the robot's heading, `pi/2` for one
//!   straight across it.
//!
//! **The score.** In each sector the selected object is the piece with the largest
//! `score = width / max(distance, distance_floor)`: it grows with the size of the object
//! and falls with its distance, so that of two walls of the same width the nearer wins and
//! of two walls at the same distance the wider wins. For a wall seen face-on, the score is
//! about the angle it subtends (`2 atan(w / 2d) ~ w / d`). `distance_floor` (0.1 m) keeps
//! a tiny piece touching the robot from winning by its distance alone. Pieces narrower than
//! `min_width` are not objects. Ties (equal scores within 1e-12) go to the nearer piece, then
//! to the line that comes first.

use laserlines::Line;
pub use laserlines::geometry::{clip_to_wedge, nearest_on_segment};
use laserlines::math::{Isometry2, Point2};

/// One of the paper's three sectors.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Sector {
    /// +50 .. +120 deg (70 deg), the paper's `select_obj[0]`.
    Left,
    /// -50 .. +50 deg (100 deg), `select_obj[1]`.
    Front,
    /// -120 .. -50 deg (70 deg), `select_obj[2]`.
    Right,
}

impl Sector {
    /// The three sectors in the paper's order: left, front, right.
    pub const ALL: [Self; 3] = [Self::Left, Self::Front, Self::Right];

    /// The sector's bounds `(from, to)`, rad, counter-clockwise, robot frame.
    #[must_use]
    pub fn bounds_rad(self) -> (f64, f64) {
        let (from, to) = match self {
            Self::Left => (50.0_f64, 120.0_f64),
            Self::Front => (-50.0, 50.0),
            Self::Right => (-120.0, -50.0),
        };
        (from.to_radians(), to.to_radians())
    }

    /// The sector's index in [`Sector::ALL`] (left 0, front 1, right 2, as the paper's
    /// `select_obj[i]`).
    #[must_use]
    pub fn index(self) -> usize {
        match self {
            Self::Left => 0,
            Self::Front => 1,
            Self::Right => 2,
        }
    }

    /// The sector's name: `left`, `front` or `right`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Left => "left",
            Self::Front => "front",
            Self::Right => "right",
        }
    }

    /// The sector holding the bearing `angle` (rad, robot frame), if any. A bearing on a
    /// shared boundary belongs to the sector counter-clockwise of it (-50 deg to the front,
    /// +50 deg to the left); the outer bounds, +-120 deg, belong to their sectors.
    #[must_use]
    pub fn of_bearing(angle: f64) -> Option<Self> {
        let a = laserlines::math::wrap_angle(angle);
        Self::ALL.into_iter().find(|s| {
            let (from, to) = s.bounds_rad();
            a >= from && (a < to || (*s == Self::Left && a <= to))
        })
    }
}

/// Parameters of the selection.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(default, deny_unknown_fields)
)]
pub struct SectorParams {
    /// Clipped pieces shorter than this are not objects, m. Default 0.05 m.
    pub min_width: f64,
    /// The distance below which nearness no longer adds to the score, m. Default 0.1 m.
    pub distance_floor: f64,
}

impl Default for SectorParams {
    fn default() -> Self {
        Self {
            min_width: 0.05,
            distance_floor: 0.1,
        }
    }
}

/// A selected object: the part of one extracted line within one sector, robot frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectorObject {
    /// The sector.
    pub sector: Sector,
    /// Index of the line in the slice given to [`select_objects`].
    pub line: usize,
    /// One end of the clipped piece (the end at the sector's clockwise side), m.
    pub start: Point2,
    /// The other end, m.
    pub end: Point2,
    /// The nearest point of the clipped piece to the robot's origin, m.
    pub nearest: Point2,
    /// Distance from the robot's origin to `nearest`, m.
    pub distance_m: f64,
    /// Visible length within the sector, m.
    pub width_m: f64,
    /// Direction of the line in the robot frame, rad, in `(-pi/2, pi/2]`.
    pub angle_rad: f64,
    /// The selection score, `width / max(distance, distance_floor)`.
    pub score: f64,
}

/// The three selected objects of one scan (the paper's `select_obj[0..3]`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SectorObjects {
    /// Left, front, right (index by [`Sector::index`]); `None` when a sector holds no line.
    pub objects: [Option<SectorObject>; 3],
}

impl SectorObjects {
    /// The object of `sector`.
    #[must_use]
    pub fn get(&self, sector: Sector) -> Option<&SectorObject> {
        self.objects[sector.index()].as_ref()
    }
}

/// Direction of the line through `a` and `b`, rad, in `(-pi/2, pi/2]`.
#[must_use]
pub fn line_direction(a: Point2, b: Point2) -> f64 {
    let e = b - a;
    let mut t = e.y.atan2(e.x);
    if t <= -std::f64::consts::FRAC_PI_2 {
        t += std::f64::consts::PI;
    } else if t > std::f64::consts::FRAC_PI_2 {
        t -= std::f64::consts::PI;
    }
    t
}

/// Describes the part of the segment `a`-`b` (robot frame) within `sector`, or `None` when
/// it has no part there at least `params.min_width` long. `line` is carried into the
/// result.
#[must_use]
pub fn describe(
    a: Point2,
    b: Point2,
    sector: Sector,
    line: usize,
    params: &SectorParams,
) -> Option<SectorObject> {
    let (from, to) = sector.bounds_rad();
    let (start, end) = clip_to_wedge(a, b, from, to)?;
    let width = (end - start).norm();
    if width.is_nan() || width < params.min_width {
        return None;
    }
    let nearest = nearest_on_segment(Point2::origin(), start, end);
    let distance = nearest.coords.norm();
    let score = width / distance.max(params.distance_floor.max(1e-9));
    Some(SectorObject {
        sector,
        line,
        start,
        end,
        nearest,
        distance_m: distance,
        width_m: width,
        angle_rad: line_direction(a, b),
        score,
    })
}

/// True when `x` should replace the current best `y`.
fn better(x: &SectorObject, y: &SectorObject) -> bool {
    if x.score > y.score + 1e-12 {
        return true;
    }
    if x.score < y.score - 1e-12 {
        return false;
    }
    x.distance_m < y.distance_m || (x.distance_m == y.distance_m && x.line < y.line)
}

/// Selects the biggest and nearest object of each sector among `segments` given by their
/// end points in the ROBOT frame (see the [module docs](self) for the score).
#[must_use]
pub fn select_segments(segments: &[(Point2, Point2)], params: &SectorParams) -> SectorObjects {
    let mut out = SectorObjects::default();
    for (k, &(a, b)) in segments.iter().enumerate() {
        for sector in Sector::ALL {
            if let Some(obj) = describe(a, b, sector, k, params) {
                let slot = &mut out.objects[sector.index()];
                if slot.as_ref().is_none_or(|cur| better(&obj, cur)) {
                    *slot = Some(obj);
                }
            }
        }
    }
    out
}

/// Selects the biggest and nearest object of each sector among extracted `lines` (laser
/// frame), with the laser at `robot_from_laser` on the robot.
///
/// ```
/// use laserlines_nav::sectors::{SectorParams, Sector, select_objects};
/// use laserlines::Line;
/// use laserlines::math::{Isometry2, Matrix2, Point2};
/// // A wall 1 m ahead, from 1 m right to 1 m left.
/// let line = Line {
///     start: Point2::new(1.0, -1.0), end: Point2::new(1.0, 1.0), r: 1.0, alpha: 0.0,
///     first: 0, last: 10, points: 11, rms: 0.0, covariance: Matrix2::zeros(),
/// };
/// let objects = select_objects(&[line], &Isometry2::identity(), &SectorParams::default());
/// let front = objects.get(Sector::Front).unwrap();
/// assert!((front.distance_m - 1.0).abs() < 1e-12);
/// // Its ends are at -45 and +45 deg, inside the front sector: all 2 m are visible there.
/// assert!((front.width_m - 2.0).abs() < 1e-9);
/// assert!((front.angle_rad - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
/// assert!(objects.get(Sector::Left).is_none());
/// ```
#[must_use]
pub fn select_objects(
    lines: &[Line],
    robot_from_laser: &Isometry2,
    params: &SectorParams,
) -> SectorObjects {
    let segments: Vec<(Point2, Point2)> = lines
        .iter()
        .map(|l| (robot_from_laser * l.start, robot_from_laser * l.end))
        .collect();
    select_segments(&segments, params)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    fn p(x: f64, y: f64) -> Point2 {
        Point2::new(x, y)
    }

    #[test]
    fn sector_bounds_cover_240_degrees() {
        let total: f64 = Sector::ALL
            .iter()
            .map(|s| {
                let (a, b) = s.bounds_rad();
                b - a
            })
            .sum();
        assert!((total.to_degrees() - 240.0).abs() < 1e-9);
        assert_eq!(Sector::of_bearing(0.0), Some(Sector::Front));
        assert_eq!(Sector::of_bearing(50f64.to_radians()), Some(Sector::Left));
        assert_eq!(Sector::of_bearing(120f64.to_radians()), Some(Sector::Left));
        assert_eq!(Sector::of_bearing(-50f64.to_radians()), Some(Sector::Front));
        assert_eq!(
            Sector::of_bearing(-120f64.to_radians()),
            Some(Sector::Right)
        );
        assert_eq!(Sector::of_bearing(-121f64.to_radians()), None);
        assert_eq!(Sector::of_bearing(3.0), None);
    }

    #[test]
    fn clipping_by_hand() {
        // A wall at y = 1 from x = -3 to 3, clipped to the left sector 50..120 deg:
        // x from 1/tan(120 deg) = -0.577 to 1/tan(50 deg) = 0.839.
        let (from, to) = Sector::Left.bounds_rad();
        let (s, e) = clip_to_wedge(p(-3.0, 1.0), p(3.0, 1.0), from, to).unwrap();
        assert!((s.x - 1.0 / 50f64.to_radians().tan()).abs() < 1e-12);
        assert!((e.x - 1.0 / 120f64.to_radians().tan()).abs() < 1e-12);
        // Behind the robot: nothing.
        assert!(clip_to_wedge(p(-3.0, -1.0), p(3.0, -1.0), from, to).is_none());
        // Wholly inside: unchanged.
        let (s, e) = clip_to_wedge(p(0.0, 2.0), p(0.1, 1.0), from, to).unwrap();
        assert!((s - p(0.1, 1.0)).norm() < 1e-12 && (e - p(0.0, 2.0)).norm() < 1e-12);
        // Degenerate input.
        assert!(clip_to_wedge(p(f64::NAN, 0.0), p(1.0, 1.0), from, to).is_none());
        assert!(clip_to_wedge(p(0.0, 0.0), p(0.0, 0.0), from, to).is_none());
        assert!(clip_to_wedge(p(0.0, 1.0), p(0.0, 2.0), 0.0, 4.0).is_none());
    }

    #[test]
    fn description_of_a_side_wall() {
        let obj = describe(
            p(-3.0, 0.6),
            p(3.0, 0.6),
            Sector::Left,
            7,
            &SectorParams::default(),
        )
        .unwrap();
        assert_eq!(obj.line, 7);
        assert!((obj.distance_m - 0.6).abs() < 1e-12);
        assert!((obj.nearest - p(0.0, 0.6)).norm() < 1e-12);
        let w = 0.6 / 50f64.to_radians().tan() + 0.6 / 60f64.to_radians().tan();
        assert!((obj.width_m - w).abs() < 1e-12);
        assert!(obj.angle_rad.abs() < 1e-12);
        assert!((obj.score - w / 0.6).abs() < 1e-12);
        // The direction is the same whichever way the segment runs.
        let back = describe(
            p(3.0, 0.6),
            p(-3.0, 0.6),
            Sector::Left,
            7,
            &SectorParams::default(),
        )
        .unwrap();
        assert!(back.angle_rad.abs() < 1e-12);
        assert!((line_direction(p(0.0, 0.0), p(0.0, -1.0)) - FRAC_PI_2).abs() < 1e-12);
        assert!((line_direction(p(0.0, 0.0), p(-1.0, -1.0)) - FRAC_PI_2 / 2.0).abs() < 1e-12);
    }

    #[test]
    fn selection_prefers_big_and_near() {
        let params = SectorParams::default();
        // Front: a 1 m wall at 2 m (score 0.5) against a 0.6 m box at 1 m (score 0.6).
        let far_wall = (p(2.0, -0.5), p(2.0, 0.5));
        let near_box = (p(1.0, -0.3), p(1.0, 0.3));
        let objs = select_segments(&[far_wall, near_box], &params);
        assert_eq!(objs.get(Sector::Front).unwrap().line, 1);
        // A wider wall at the same distance wins.
        let wide = (p(1.0, -0.4), p(1.0, 0.4));
        let objs = select_segments(&[near_box, wide], &params);
        assert_eq!(objs.get(Sector::Front).unwrap().line, 1);
        // Of equal widths the nearer wins.
        let near = (p(1.5, 0.0), p(1.5, 0.5));
        let farther = (p(2.5, -0.5), p(2.5, 0.0));
        let objs = select_segments(&[farther, near], &params);
        assert_eq!(objs.get(Sector::Front).unwrap().line, 1);
        // Equal scores: the nearer wins, then the first line.
        let a = (p(1.0, -0.1), p(1.0, 0.1));
        let b = (p(2.0, -0.2), p(2.0, 0.2));
        let objs = select_segments(&[b, a], &params);
        assert_eq!(objs.get(Sector::Front).unwrap().line, 1);
        let objs = select_segments(&[a, a], &params);
        assert_eq!(objs.get(Sector::Front).unwrap().line, 0);
        // Too narrow: no object.
        let crumb = (p(1.0, 0.0), p(1.0, 0.01));
        assert!(
            select_segments(&[crumb], &params)
                .get(Sector::Front)
                .is_none()
        );
        // The floor: a 0.2 m piece at 0.02 m does not beat a 1 m wall at 0.5 m.
        let touching = (p(0.02, -0.1), p(0.02, 0.1));
        let wall = (p(0.5, -0.5), p(0.5, 0.5));
        let objs = select_segments(&[touching, wall], &params);
        assert_eq!(objs.get(Sector::Front).unwrap().line, 1);
    }

    #[test]
    fn a_line_spanning_sectors_is_split_among_them() {
        // A wall at x = 0.5 from y = -3 to 3 is in all three sectors.
        let objs = select_segments(&[(p(0.5, -3.0), p(0.5, 3.0))], &SectorParams::default());
        for s in Sector::ALL {
            assert!(objs.get(s).is_some(), "{s:?}");
        }
        let left = objs.get(Sector::Left).unwrap();
        // Nearest point of the left piece: at bearing 50 deg.
        assert!((left.distance_m - 0.5 / 50f64.to_radians().cos()).abs() < 1e-12);
        assert!((objs.get(Sector::Front).unwrap().distance_m - 0.5).abs() < 1e-12);
    }
}
