//! The safety layer: the near points remembered around the robot, and the check of every
//! command's sweep against them, with its fallbacks and the escape from a tight spot.

use laserlines::Scan;
use laserlines::math::{Isometry2, Point2, Vector2};
use laserlines::robot::{VelocityCommand, arc};

use super::{Explorer, Mode, SafetyParams};

/// When a command is safe: the footprint stays the safety margin clear of everything along
/// its sweep (the turning margin for a turn on the spot: zero linear speed, `STOP` included,
/// where it changes nothing); or, where the robot already stands
/// closer than that, the sweep never comes closer than the robot is now (and keeps 2 cm), so
/// that it can turn or back out of a tight spot.
#[derive(Debug, Clone, Copy)]
struct SafeRule {
    /// The clearance where the robot stands, as a command that keeps no extra margin for
    /// points out of view sees it.
    now_plain: f64,
    /// The same as a command that turns or backs sees it.
    now_turning: f64,
    /// The safety margin, m.
    margin: f64,
    /// The margin of a turn on the spot, m (at most `margin`).
    turn_margin: f64,
}

impl SafeRule {
    /// The rule for a robot whose clearance where it stands is `now_plain` and `now_turning`
    /// (see the fields), with the margins of `safety` (the turning margin at most the other).
    fn new(now_plain: f64, now_turning: f64, safety: &SafetyParams) -> Self {
        Self {
            now_plain,
            now_turning,
            margin: safety.margin,
            turn_margin: safety
                .turn_margin
                .unwrap_or(safety.margin)
                .min(safety.margin),
        }
    }

    fn safe(&self, c: VelocityCommand, clearance: f64) -> bool {
        let now = if toward_blind(c) {
            self.now_turning
        } else {
            self.now_plain
        };
        let margin = if c.linear_m_s == 0.0 {
            self.turn_margin
        } else {
            self.margin
        };
        clearance >= margin || (clearance >= now.min(margin) - 1e-3 && clearance >= now.min(0.02))
    }
}

impl Explorer {
    /// Keeps the scan's near points (map frame) for the safety layer: one per
    /// [`MEMORY_CELL`] square, the latest, while within `safety.memory_range_m` of the robot.
    /// Points stay when the laser no longer sees them, behind the robot or in view (the
    /// end of a thin wall seen end-on is between beams).
    pub(super) fn remember(&mut self, scan: &Scan, map_from_robot: &Isometry2) {
        self.scans += 1;
        let map_from_laser = map_from_robot * self.robot_from_laser;
        let robot_at = Point2::from(map_from_robot.translation.vector);
        let keep2 = self.params.safety.memory_range_m * self.params.safety.memory_range_m;
        self.memory
            .retain(|_, (m, _)| (*m - robot_at).norm_squared() <= keep2);
        let window = scan.range_window(None);
        let dirs = self
            .beams
            .get(scan.angle_min, scan.angle_increment, scan.ranges.len());
        // Near points only (only they matter to the safety layer), every third beam (2 cm
        // apart at 1 m).
        for (&r, dir) in scan.ranges.iter().zip(dirs).step_by(3) {
            if r >= 1.2 || !window.contains(r) {
                continue;
            }
            let p = map_from_laser * Point2::from(dir * r);
            let key = (floor_i32(p.x / MEMORY_CELL), floor_i32(p.y / MEMORY_CELL));
            self.memory.insert(key, (p, self.scans));
        }
    }

    /// True when the direction `v` (from the laser, in the robot's axes) lies outside the
    /// laser's field of view.
    fn in_blind_wedge(&self, v: Vector2) -> bool {
        let (d_first, d_last, narrow) = self.blind;
        let cross = |a: Vector2, b: Vector2| a.x * b.y - a.y * b.x;
        // The blind wedge runs counter-clockwise from the last beam round to the first.
        let after_last = cross(d_last, v) >= 0.0;
        let before_first = cross(v, d_first) >= 0.0;
        if narrow {
            after_last && before_first
        } else {
            after_last || before_first
        }
    }

    /// The safety layer: checks `wanted` against the remembered points and returns the
    /// command to commit.
    pub(super) fn safe_command(
        &mut self,
        wanted: VelocityCommand,
        map_from_robot: &Isometry2,
        time_s: f64,
    ) -> VelocityCommand {
        let pts = self.near_points(map_from_robot);
        // Where the robot stands now, as a command that keeps the extra margin for points
        // out of view sees it, and as one that does not.
        let rule = SafeRule::new(
            self.sweep_clearance(&pts, VelocityCommand::STOP, 0.0),
            self.sweep_clearance(&pts, VelocityCommand::new(0.0, 1.0), 0.0),
            &self.params.safety,
        );
        let (mut chosen, blocked) = self.first_safe(wanted, &pts, &rule);
        // Stuck: the wanted motion blocked (nothing safe, or only a way round it) for about
        // a second: escape.
        let stuck = blocked && self.mode != Mode::Escape;
        // Stuck scans add up, free ones count half back: a robot that keeps switching
        // between a blocked turn and a way out is stuck too.
        self.stuck_score = if stuck {
            self.stuck_score + 1.0
        } else {
            (self.stuck_score - 0.5).max(0.0)
        };
        if stuck && self.stuck_score > 10.0 {
            if let Some(c) = self.escape_motion(&pts, &rule) {
                self.mode = Mode::Escape;
                self.escape = c;
                self.escape_until = time_s + ESCAPE_S;
                chosen = c;
            }
            self.stuck_score = 0.0;
        }
        self.scratch_points = pts;
        chosen
    }

    /// The remembered points near the robot, robot frame: those this scan sees (returned)
    /// and those out of view (kept in `scratch_blind`).
    fn near_points(&mut self, map_from_robot: &Isometry2) -> Vec<Point2> {
        let robot_from_map = map_from_robot.inverse();
        let mut pts = std::mem::take(&mut self.scratch_points);
        let mut blind = std::mem::take(&mut self.scratch_blind);
        pts.clear();
        blind.clear();
        let reach = self.footprint.circumradius() + 0.5;
        let laser = self.robot_from_laser.translation.vector;
        for (m, seen) in self.memory.values() {
            let q = robot_from_map * m;
            if q.coords.norm_squared() < reach * reach {
                // This scan's points in view are sure; the others were seen from elsewhere.
                if *seen < self.scans || self.in_blind_wedge(q.coords - laser) {
                    blind.push(q);
                } else {
                    pts.push(q);
                }
            }
        }
        // The fence is exact: its points count as seen.
        let at = Point2::from(map_from_robot.translation.vector);
        if let Some(fence) = self.params.fence.filter(|f| f.contains(at)) {
            let start = pts.len();
            fence.points_near(at, reach, MEMORY_CELL, &mut pts);
            for q in &mut pts[start..] {
                *q = robot_from_map * *q;
            }
        }
        self.scratch_blind = blind;
        pts
    }

    /// The first safe command of the wanted one and its fallbacks, and whether the wanted
    /// motion is blocked (only a way round it is safe, or nothing: then the robot stops).
    fn first_safe(
        &self,
        wanted: VelocityCommand,
        pts: &[Point2],
        rule: &SafeRule,
    ) -> (VelocityCommand, bool) {
        let s = self.side.sign();
        // Slower, then turning on the spot, then turning while creeping forward or back
        // (a corner too tight to turn in), then turning either way. When none of these
        // will do for a while, the robot escapes.
        let candidates = [
            wanted,
            VelocityCommand::new(wanted.linear_m_s * 0.5, wanted.angular_rad_s),
            VelocityCommand::new(wanted.linear_m_s * 0.25, wanted.angular_rad_s * 0.5),
            VelocityCommand::new(0.0, wanted.angular_rad_s),
            VelocityCommand::new(0.1, wanted.angular_rad_s),
            VelocityCommand::new(-0.1, wanted.angular_rad_s),
            VelocityCommand::new(0.0, -s * self.params.follow.turn_rate),
            VelocityCommand::new(0.0, s * self.params.follow.turn_rate),
        ];
        for (k, c) in candidates.into_iter().enumerate() {
            if rule.safe(c, self.sweep_clearance(pts, c, 1.0)) {
                // Only a slower version of the wanted motion: not blocked.
                return (c, k > 2 && c != wanted);
            }
        }
        (VelocityCommand::STOP, wanted != VelocityCommand::STOP)
    }

    /// Of short straight and curved motions either way, the safe one that ends with the most
    /// room after `ESCAPE_S` ([`Explorer::room_after`]): clearance all round the footprint,
    /// and room to turn on the spot, so that a robot stuck where it cannot turn (a post beside
    /// a corner, a wall end) moves to where it can.
    fn escape_motion(&self, pts: &[Point2], rule: &SafeRule) -> Option<VelocityCommand> {
        let mut best: Option<(f64, VelocityCommand)> = None;
        for v in [0.15, -0.15] {
            for w in [0.0, 0.8, -0.8] {
                let c = VelocityCommand::new(v, w);
                if !rule.safe(c, self.sweep_clearance(pts, c, 1.0)) {
                    continue;
                }
                let end = self.room_after(pts, c, ESCAPE_S);
                if best.is_none_or(|(b, _)| end > b + 1e-9) {
                    best = Some((end, c));
                }
            }
        }
        best.map(|(_, c)| c)
    }

    /// The room around the robot after driving `c` for `t` seconds: the least distance
    /// between the footprint and the points `pts` (robot frame), plus the room to turn on the
    /// spot (the least distance from the robot's centre to a point, less the footprint's
    /// circumradius). Points out of view count `BLIND_MARGIN` nearer in both. Only the near
    /// points the safety layer holds count (within 0.5 m of the footprint's circle where the
    /// robot stands now): a motion of up to 0.18 m can end with the nearest obstacle beyond
    /// them, where the room is taken as at most 1 m and 1.5 m, so it ranks the motions that
    /// end near an obstacle, which is what an escape has to tell apart.
    fn room_after(&self, pts: &[Point2], c: VelocityCommand, t: f64) -> f64 {
        let half = self.footprint.half();
        let inv = arc(c.linear_m_s * t, c.angular_rad_s * t).inverse();
        // (distance to the footprint, distance to the centre) of a point.
        let gaps = |q: &Point2| {
            let l = inv * q;
            let dx = (l.x.abs() - half.x).max(0.0);
            let dy = (l.y.abs() - half.y).max(0.0);
            ((dx * dx + dy * dy).sqrt(), l.coords.norm())
        };
        let least = |(a, b): (f64, f64), (c, d): (f64, f64)| (a.min(c), b.min(d));
        let seen = pts.iter().map(gaps).fold((1.0, 1.5), least);
        let blind = self
            .scratch_blind
            .iter()
            .map(|q| {
                let (side, centre) = gaps(q);
                (side - BLIND_MARGIN, centre - BLIND_MARGIN)
            })
            .fold((1.0, 1.5), least);
        let (side, centre) = least(seen, blind);
        side + centre - self.footprint.circumradius()
    }

    /// The least distance between the footprint and the points `pts` (robot frame) while
    /// driving `c` for the time to react and stop (`horizon` 0: where the robot stands
    /// now); at most 1 m.
    fn sweep_clearance(&self, pts: &[Point2], c: VelocityCommand, horizon: f64) -> f64 {
        let half = self.footprint.half();
        // Points remembered out of the laser's view were seen from elsewhere: an obstacle
        // may reach nearer on its unseen side (the far side of a barrel). Turning or
        // backing toward them keeps BLIND_MARGIN more.
        let extra = if toward_blind(c) { BLIND_MARGIN } else { 0.0 };
        let v = c.linear_m_s.abs();
        // One scan period to react, then braking.
        let span = horizon * (0.15 + v / self.max_accel.max(1e-3));
        let steps = if horizon > 0.0 { 6 } else { 1 };
        let mut least2: f64 = 1.0;
        let mut least_blind2: f64 = (1.0 + extra) * (1.0 + extra);
        for k in 1..=steps {
            let t = span * f64::from(k) / f64::from(steps);
            let pose = arc(c.linear_m_s * t, c.angular_rad_s * t.min(0.3));
            let inv = pose.inverse();
            for q in pts {
                let l = inv * q;
                let dx = (l.x.abs() - half.x).max(0.0);
                let dy = (l.y.abs() - half.y).max(0.0);
                least2 = least2.min(dx * dx + dy * dy);
            }
            for q in &self.scratch_blind {
                let l = inv * q;
                let dx = (l.x.abs() - half.x).max(0.0);
                let dy = (l.y.abs() - half.y).max(0.0);
                least_blind2 = least_blind2.min(dx * dx + dy * dy);
            }
        }
        least2.sqrt().min((least_blind2.sqrt() - extra).max(0.0))
    }
}

/// Side of the squares in which the safety layer remembers one scan point, m.
const MEMORY_CELL: f64 = 0.03;

/// A hasher for small integer keys (multiply and fold): deterministic, and far cheaper than
/// the default for the safety layer's few hundred points a scan.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct CellHasher(u64);

impl std::hash::Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }

    fn write_i32(&mut self, v: i32) {
        self.write_u64(u64::from(v as u32));
    }

    fn write_u64(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

/// The [`CellHasher`] for the remembered points.
pub(super) type CellHash = std::hash::BuildHasherDefault<CellHasher>;

/// `x.floor() as i32`, saturating, without a library call.
fn floor_i32(x: f64) -> i32 {
    let t = x as i32;
    if f64::from(t) > x {
        t.saturating_sub(1)
    } else {
        t
    }
}

/// How long an escape from a tight spot lasts, s.
const ESCAPE_S: f64 = 1.2;

/// Extra margin the safety layer keeps from points it remembers but does not see in this
/// scan when turning or backing (and counts in the room an escape ends with), m.
const BLIND_MARGIN: f64 = 0.06;

/// True for a command that turns or backs: toward points out of the laser's view.
fn toward_blind(c: VelocityCommand) -> bool {
    c.linear_m_s < 0.0 || c.angular_rad_s.abs() > 0.05
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_turn_on_the_spot_keeps_the_turning_margin_and_other_motions_the_full_one() {
        // The robot stands 0.18 m clear (its centre 0.38 m from a wall beside it); turning
        // brings a corner to 6 cm of the wall.
        let safety = SafetyParams {
            margin: 0.08,
            turn_margin: Some(0.05),
            ..SafetyParams::default()
        };
        let rule = SafeRule::new(0.18, 0.18, &safety);
        assert!(rule.safe(VelocityCommand::new(0.0, 1.0), 0.06));
        assert!(!rule.safe(VelocityCommand::new(0.0, 1.0), 0.04));
        assert!(!rule.safe(VelocityCommand::new(0.1, 0.5), 0.06));
        assert!(!rule.safe(VelocityCommand::new(-0.1, 0.0), 0.06));
        assert!(rule.safe(VelocityCommand::new(0.1, 0.5), 0.08));
        // Already nearer than the turning margin: a turn may not come nearer still.
        let tight = SafeRule {
            now_plain: 0.035,
            now_turning: 0.035,
            ..rule
        };
        assert!(tight.safe(VelocityCommand::new(0.0, 1.0), 0.035));
        assert!(!tight.safe(VelocityCommand::new(0.0, 1.0), 0.03));
        // By default, and never above the other margin, the turning margin is the margin.
        for turn_margin in [None, Some(0.2)] {
            let rule = SafeRule::new(
                0.18,
                0.18,
                &SafetyParams {
                    turn_margin,
                    ..safety
                },
            );
            assert_eq!(rule.turn_margin, 0.08);
            assert!(!rule.safe(VelocityCommand::new(0.0, 1.0), 0.06));
        }
    }
}
