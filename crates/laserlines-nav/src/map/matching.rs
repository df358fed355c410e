//! Scan matching: a scan's points fitted onto the map's surface lines (point-to-line ICP
//! with a prior toward the odometry's prediction).

use laserlines::math::{Isometry2, Point2, Vector2, wrap_angle};
use nalgebra::{Matrix3, Vector3};

use super::{NORMAL_AGREEMENT, RobotMap};
use crate::raster::floor_i64;

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

impl RobotMap {
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
        let start = Vector3::new(x0, y0, t0);
        let prior = Vector3::new(params.prior_xy, params.prior_xy, params.prior_theta);
        let mut xi = start;
        // Pairs of a point (index) and its line; made afresh in the first rounds, then kept
        // while the pose settles.
        let mut pairs: Vec<(usize, [f64; 3])> = Vec::with_capacity(points.len());
        let mut moved = true;
        for round in 0..params.iterations.max(1) {
            // Pair afresh in the first round, and in the second after a step of more than
            // a centimetre or a hundredth of a radian. Pairs farther than the gate are not
            // the same wall; the gate narrows once the first step is taken.
            if round == 0 || (round == 1 && moved) {
                let gate = if round == 0 {
                    params.gate_m
                } else {
                    0.5 * params.gate_m
                };
                self.pair(points, &xi, gate, &mut pairs);
            }
            let (mut h, mut g) = normal_equations(points, &pairs, &xi);
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

    /// Pairs each point, placed by the pose `xi`, with its nearest line within `gate`.
    fn pair(
        &self,
        points: &[MatchPoint],
        xi: &Vector3<f64>,
        gate: f64,
        pairs: &mut Vec<(usize, [f64; 3])>,
    ) {
        let (s, c) = xi.z.sin_cos();
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
}

/// The Gauss-Newton normal equations `H step = g` of the point-to-line distances of `pairs`
/// at the pose `xi`, with a Huber weight beyond 2 cm.
fn normal_equations(
    points: &[MatchPoint],
    pairs: &[(usize, [f64; 3])],
    xi: &Vector3<f64>,
) -> (Matrix3<f64>, Vector3<f64>) {
    let (s, c) = xi.z.sin_cos();
    // The six distinct entries and the right-hand side.
    let (mut hxx, mut hxy, mut hxt, mut hyy, mut hyt, mut htt) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let (mut gx, mut gy, mut gt) = (0.0, 0.0, 0.0);
    for &(k, [nx, ny, d]) in pairs {
        let m = &points[k];
        let p = m.point;
        let qx = c * p.x - s * p.y + xi.x;
        let qy = s * p.x + c * p.y + xi.y;
        let r = nx * qx + ny * qy - d;
        // The Jacobian (nx, ny, jt): jt from turning the point about the robot.
        let jt = nx * (-s * p.x - c * p.y) + ny * (c * p.x - s * p.y);
        let w = m.weight.clamp(0.0, 1.0) * if r.abs() <= 0.02 { 1.0 } else { 0.02 / r.abs() };
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
    (
        Matrix3::new(hxx, hxy, hxt, hxy, hyy, hyt, hxt, hyt, htt),
        Vector3::new(gx, gy, gt),
    )
}
