//! Leaving the wall for the nearest frontier and the way there: planning (with the retries,
//! the tight clearance and the blocked spots), progress and giving up, re-planning, and pure
//! pursuit along the path.

use laserlines::math::Point2;
use laserlines::robot::VelocityCommand;

use super::{Explorer, Mode};
use crate::map::{CellState, MAP_CELL};
use crate::planner::{Plan, PlannerParams};

/// The way to a frontier.
#[derive(Debug, Clone)]
pub(super) struct Travel {
    pub(super) plan: Plan,
    /// Index of the path point nearest the robot at the last scan.
    pub(super) along: usize,
    pub(super) planned_at: f64,
    /// The least length of path left so far, m, when it was reached and where the robot
    /// was then (map frame).
    pub(super) best: f64,
    pub(super) best_at: f64,
    pub(super) best_from: Point2,
    /// Planned with [`ExplorerParams::tight_clearance_m`].
    pub(super) tight: bool,
    /// Per path point: how far the robot may pass from it ([`Explorer::path_slack`]).
    pub(super) slack: Vec<f64>,
}

impl Explorer {
    /// Plans to the nearest frontier and starts driving there; `None` when there is none
    /// (then wall following goes on, and after a few such plans the exploration is
    /// complete).
    pub(super) fn start_travel(&mut self, time_s: f64, front_free: f64) -> Option<VelocityCommand> {
        let from = Point2::from(self.map_from_robot.translation.vector);
        self.update_blocked(time_s);
        let mut plan = self.plan_from(from, false);
        // No frontier left but some given up: try those again (from wherever the robot is
        // now), a limited number of times.
        if plan.is_none() && !self.avoid.is_empty() && self.retries < self.params.travel.retries {
            self.retries += 1;
            self.avoid.clear();
            plan = self.plan_from(from, false);
        }
        // None with the usual clearance: through gaps where the robot cannot turn.
        let mut tight = false;
        if plan.is_none() {
            plan = self.plan_from(from, true);
            tight = plan.is_some();
        }
        // Still none, with spots closed: open them again (a spot may be the only way on)
        // rather than call the exploration complete.
        if plan.is_none() && !self.blocked.is_empty() {
            self.blocked.clear();
            self.planner.set_blocked(&[], 0.0);
            for t in [false, true] {
                plan = self.plan_from(from, t);
                tight = t;
                if plan.is_some() {
                    break;
                }
            }
        }
        let Some(plan) = plan else {
            self.failed_plans += 1;
            // Try again after another stale spell; three empty plans in a row: done.
            self.last_new = time_s;
            if self.failed_plans >= 3 {
                self.explored = true;
            }
            return None;
        };
        self.failed_plans = 0;
        let best = plan.length_m;
        let slack = self.path_slack(&plan.path);
        self.travel = Some(Travel {
            slack,
            plan,
            along: 0,
            planned_at: time_s,
            best,
            best_at: time_s,
            best_from: from,
            tight,
        });
        self.mode = Mode::Travel;
        let step = self.travel_step(time_s, front_free);
        if step.is_none() {
            // Done at once (the frontier seen already): wall following for another spell.
            self.mode = Mode::Seek;
            self.last_new = time_s;
        }
        step
    }

    /// The path from `from` to the nearest frontier not given up, with the tight clearance
    /// when `tight`.
    fn plan_from(&mut self, from: Point2, tight: bool) -> Option<Plan> {
        let params = self.planner_params(tight);
        self.planner.nearest_frontier(
            &self.map,
            from,
            &self.avoid,
            self.params.travel.avoid_radius_m,
            None,
            &params,
        )
    }

    /// The planner's settings, with the tight clearance when `tight`.
    fn planner_params(&self, tight: bool) -> PlannerParams {
        let mut p = self.params.planner;
        if tight {
            p.clearance_m = p.clearance_m.min(self.params.travel.tight_clearance_m);
        }
        p
    }

    /// Drops the blocked spots older than `travel.blocked_s` and hands the rest to the planner.
    fn update_blocked(&mut self, time_s: f64) {
        let keep_for = self.params.travel.blocked_s;
        self.blocked.retain(|&(_, at)| time_s - at <= keep_for);
        let spots: Vec<Point2> = self.blocked.iter().map(|&(p, _)| p).collect();
        self.planner
            .set_blocked(&spots, self.params.travel.blocked_radius_m);
    }

    /// One step on the way to the frontier: re-plans when due, gives up a frontier without
    /// progress, and steers along the path. `None` when the way has ended (arrived, the
    /// frontier seen on the way, or no frontier left).
    pub(super) fn travel_step(&mut self, time_s: f64, front_free: f64) -> Option<VelocityCommand> {
        let p = self.params;
        let from = Point2::from(self.map_from_robot.translation.vector);
        let mut travel = self.travel.take()?;
        let goal = travel.plan.goal;
        if !self.goal_still_open(goal, from) {
            return None;
        }
        let give_up = self.track_progress(&mut travel, from, time_s);
        if self.explored {
            return None;
        }
        if give_up || time_s - travel.planned_at >= p.travel.replan_s {
            self.replan(&mut travel, from, give_up, time_s)?;
        }
        let target = pursuit_target(&mut travel, from, p.travel.lookahead_m).unwrap_or(goal);
        self.travel = Some(travel);
        self.mode = Mode::Travel;
        Some(self.steer_to(target, front_free))
    }

    /// False when the way to `goal` has ended: arrived, or the frontier is no longer one
    /// (seen on the way, or blocked), or the robot stands at it and still cannot see it.
    fn goal_still_open(&mut self, goal: Point2, from: Point2) -> bool {
        let resolved = self.map.unknown_around(goal, 2) < self.params.planner.min_unknown
            || self.map.state(goal) != CellState::Free;
        if resolved {
            self.frontiers += 1;
            return false;
        }
        if (from - goal).norm() < 0.3 {
            // There, and still unknown around it: the robot cannot see it from where it
            // can stand (behind a post, in a wall's shadow). Not a frontier to come back to.
            self.give_up(goal);
            return false;
        }
        true
    }

    /// Gives the frontier at `goal` up; once `travel.fruitless_give_ups` different ones
    /// (farther than `travel.avoid_radius_m` apart) have been given up while the map grew by
    /// less than `travel.fruitless_gain_m2`, the exploration is complete.
    fn give_up(&mut self, goal: Point2) {
        self.avoid.push(goal);
        let p = self.params.travel;
        let fruitful = (p.fruitless_gain_m2 / (MAP_CELL * MAP_CELL))
            .ceil()
            .max(1.0) as u64;
        let (goals, since) = &mut self.fruitless;
        if self.known.saturating_sub(*since) >= fruitful {
            goals.clear();
            *since = self.known;
        }
        if goals.iter().all(|g| (g - goal).norm() > p.avoid_radius_m) {
            goals.push(goal);
        }
        if p.fruitless_give_ups > 0 && goals.len() >= p.fruitless_give_ups {
            self.explored = true;
        }
    }

    /// Measures progress along the path; true when the frontier is given up (no progress
    /// for `travel.give_up_s`), closing the spot ahead when the robot stood still.
    fn track_progress(&mut self, travel: &mut Travel, from: Point2, time_s: f64) -> bool {
        // Progress is measured along the path: what is left of it.
        let left = remaining(&travel.plan.path, travel.along, from);
        if left < travel.best - 0.2 {
            travel.best = left;
            travel.best_at = time_s;
            travel.best_from = from;
        }
        // Seeing new ground on the way is progress too.
        if self.last_new >= time_s {
            travel.best_at = time_s;
            travel.best_from = from;
        }
        let give_up = time_s - travel.best_at > self.params.travel.give_up_s;
        if give_up {
            self.give_up(travel.plan.goal);
            // Stuck where the map shows a way: close the spot the path led to next.
            if (from - travel.best_from).norm() < 0.5 {
                let ahead = travel
                    .plan
                    .path
                    .iter()
                    .skip(travel.along)
                    .find(|q| (*q - from).norm() >= 0.4)
                    .copied();
                if let Some(spot) = ahead {
                    self.blocked.push((spot, time_s));
                }
            }
            travel.best_at = time_s;
            travel.best_from = from;
        }
        give_up
    }

    /// A new plan from `from`, keeping the goal unless it was given up; `None` when no
    /// frontier is left.
    fn replan(
        &mut self,
        travel: &mut Travel,
        from: Point2,
        give_up: bool,
        time_s: f64,
    ) -> Option<()> {
        let p = self.params;
        let goal = travel.plan.goal;
        self.update_blocked(time_s);
        let keep = (!give_up).then_some((goal, p.travel.hysteresis_m));
        let plan = self.planner.nearest_frontier(
            &self.map,
            from,
            &self.avoid,
            p.travel.avoid_radius_m,
            keep,
            &self.planner_params(travel.tight),
        )?;
        if (plan.goal - goal).norm() > 0.3 {
            // Another frontier: its path is measured from here on, but the clock runs on.
            travel.best = plan.length_m;
        }
        travel.slack = self.path_slack(&plan.path);
        travel.plan = plan;
        travel.along = 0;
        travel.planned_at = time_s;
        Some(())
    }

    /// Per point of `path`: how far from it the robot's centre may pass on its way. The
    /// footprint turned any way needs its circumradius and the safety margin of room around
    /// its centre; where the point has more room than that to the nearest occupied cell the
    /// difference may be taken (up to [`MAX_SLACK`]), and at least [`CHORD_TOLERANCE`].
    fn path_slack(&mut self, path: &[Point2]) -> Vec<f64> {
        let need = self.footprint.circumradius() + self.params.safety.margin;
        let mut near = std::mem::take(&mut self.scratch_points);
        let slack = path
            .iter()
            .map(|&q| {
                near.clear();
                self.map.occupied_near(q, need + MAX_SLACK, &mut near);
                let room = near
                    .iter()
                    .map(|o| (o - q).norm())
                    .fold(need + MAX_SLACK, f64::min);
                (room - need).max(CHORD_TOLERANCE)
            })
            .collect();
        self.scratch_points = near;
        slack
    }

    /// The command that steers toward `target` (map frame): on the spot when it lies more
    /// than 0.5 rad off the heading, else along an arc, slower when turning or near
    /// obstacles.
    fn steer_to(&self, target: Point2, front_free: f64) -> VelocityCommand {
        let p = self.params;
        let local = self.map_from_robot.inverse() * target;
        let alpha = local.y.atan2(local.x);
        if alpha.abs() > 0.5 {
            VelocityCommand::new(0.0, alpha.signum() * p.follow.turn_rate)
        } else {
            let omega = (2.5 * alpha).clamp(-p.follow.turn_rate, p.follow.turn_rate);
            let v = p.travel.speed
                * (1.0 - alpha.abs() / 0.7).max(0.2)
                * ((front_free - 0.1) / 0.8).clamp(0.25, 1.0);
            VelocityCommand::new(v, omega)
        }
    }
}

/// Pure pursuit: the path point nearest the robot (searched ahead of the last one), then,
/// from the point after it on, the first one at least `lookahead` away (the path's end when
/// none is), or the last one before it whose chord from the robot passes each path point in
/// between within that point's slack, so that the robot does not cut a bend of the path
/// toward what the bend goes round (a robot standing off a tight path steers to the next
/// point, back onto the path); `None` for an empty path.
fn pursuit_target(travel: &mut Travel, from: Point2, lookahead: f64) -> Option<Point2> {
    let path = &travel.plan.path;
    let mut along = travel.along.min(path.len().saturating_sub(1));
    let mut best = f64::INFINITY;
    for (k, q) in path.iter().enumerate().skip(travel.along).take(40) {
        let d = (q - from).norm_squared();
        if d < best {
            best = d;
            along = k;
        }
    }
    travel.along = along;
    let ahead = path.get(along..)?;
    debug_assert_eq!(travel.slack.len(), path.len());
    let slack = travel.slack.get(along..).unwrap_or(&[]);
    let mut target = *ahead.first()?;
    for (k, &q) in ahead.iter().enumerate().skip(1) {
        let between = ahead.get(1..k).unwrap_or(&[]);
        let room = slack.get(1..k.min(slack.len())).unwrap_or(&[]);
        if !chord_follows(from, q, between, room) {
            break;
        }
        target = q;
        if (q - from).norm() >= lookahead {
            break;
        }
    }
    Some(target)
}

/// The least slack of a path point, m: half a map cell, the most a path of cell centres
/// strays from the line it stands for.
const CHORD_TOLERANCE: f64 = 0.05;

/// The most slack of a path point, m: more than a chord 0.5 m long (the default lookahead)
/// passes from the path it cuts, so that only the room near the path counts.
const MAX_SLACK: f64 = 0.3;

/// True when every point of `between` lies within its slack (the same index of `slack`;
/// [`CHORD_TOLERANCE`] where `slack` ends) of the segment from `from` to `to`.
fn chord_follows(from: Point2, to: Point2, between: &[Point2], slack: &[f64]) -> bool {
    let d = to - from;
    let len2 = d.norm_squared();
    between.iter().enumerate().all(|(k, q)| {
        let t = if len2 > 0.0 {
            ((q - from).dot(&d) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (from + d * t - q).norm() <= slack.get(k).copied().unwrap_or(CHORD_TOLERANCE)
    })
}

/// The length of `path` left from point `along` on, plus the way from `from` to that point.
fn remaining(path: &[Point2], along: usize, from: Point2) -> f64 {
    let rest = path.get(along..).unwrap_or(&[]);
    let to_path = rest.first().map_or(0.0, |p| (p - from).norm());
    to_path + rest.windows(2).map(|s| (s[1] - s[0]).norm()).sum::<f64>()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A path of cell centres 0.1 m apart going up x = 0 to (0, 0.3), then right along
    /// y = 0.3, with `slack` at every point.
    fn bend(slack: f64) -> Travel {
        let mut path: Vec<Point2> = (0..=3)
            .map(|k| Point2::new(0.0, 0.1 * f64::from(k)))
            .collect();
        path.extend((1..=8).map(|k| Point2::new(0.1 * f64::from(k), 0.3)));
        Travel {
            slack: vec![slack; path.len()],
            plan: Plan {
                goal: *path.last().unwrap_or(&Point2::origin()),
                length_m: 1.1,
                path,
            },
            along: 0,
            planned_at: 0.0,
            best: 1.1,
            best_at: 0.0,
            best_from: Point2::origin(),
            tight: false,
        }
    }

    #[test]
    fn the_target_stays_on_the_near_side_of_a_tight_bend() {
        // The chord to (0.1, 0.3) passes (0, 0.2) 6.3 cm off, beyond 5 cm of slack: the
        // target is the bend, (0, 0.3), not (0.4, 0.3) a lookahead away.
        let mut travel = bend(CHORD_TOLERANCE);
        let target = pursuit_target(&mut travel, Point2::origin(), 0.5).unwrap();
        assert!((target - Point2::new(0.0, 0.3)).norm() < 1e-12, "{target}");
    }

    #[test]
    fn with_room_round_the_bend_the_target_lies_a_lookahead_away() {
        let mut travel = bend(MAX_SLACK);
        let target = pursuit_target(&mut travel, Point2::origin(), 0.45).unwrap();
        assert!((target - Point2::new(0.4, 0.3)).norm() < 1e-12, "{target}");
    }

    #[test]
    fn each_point_is_checked_against_its_own_slack_past_the_nearest() {
        // Along the bend's second leg from (0.1, 0.3), room everywhere but at (0.5, 0.3),
        // moved 8 cm off the line to (0.5, 0.38): the chord to (0.6, 0.3) passes it 8 cm
        // off, beyond its 5 cm, so the target stops there. A slack read one point off would
        // put the 5 cm on a point of the line and let the chord through.
        let mut travel = bend(MAX_SLACK);
        travel.plan.path[8] = Point2::new(0.5, 0.38);
        travel.slack[8] = CHORD_TOLERANCE;
        travel.along = 4;
        let from = Point2::new(0.1, 0.3);
        let target = pursuit_target(&mut travel, from, 0.45).unwrap();
        assert_eq!(travel.along, 4);
        assert!((target - Point2::new(0.5, 0.38)).norm() < 1e-12, "{target}");
        // With room there too, a lookahead away.
        travel.slack[8] = MAX_SLACK;
        let target = pursuit_target(&mut travel, from, 0.45).unwrap();
        assert!((target - Point2::new(0.6, 0.3)).norm() < 1e-12, "{target}");
    }

    #[test]
    fn three_frontiers_given_up_while_the_map_stands_still_end_the_exploration() {
        use crate::explorer::ExplorerParams;
        use laserlines::robot::RobotDescription;
        let params = ExplorerParams::default();
        assert_eq!(params.travel.fruitless_give_ups, 3);
        let mut e = Explorer::new(params, &RobotDescription::default());
        // Two different frontiers (1 m apart), and the same one again: not yet.
        for k in 0..2 {
            e.give_up(Point2::new(f64::from(k), 0.0));
        }
        e.give_up(Point2::new(0.1, 0.0));
        assert!(!e.explored);
        // The map grows by 1 m^2 (100 cells of 0.1 m): the count starts again.
        e.known += 100;
        for k in 0..2 {
            e.give_up(Point2::new(f64::from(k), 5.0));
        }
        assert!(!e.explored);
        // A third with no growth: complete.
        e.give_up(Point2::new(9.0, 9.0));
        assert!(e.explored);
    }

    #[test]
    fn a_chord_within_each_points_slack_follows_the_path() {
        let from = Point2::origin();
        let to = Point2::new(1.0, 0.0);
        let between = [Point2::new(0.5, 0.04), Point2::new(0.7, -0.2)];
        assert!(!chord_follows(from, to, &between, &[0.05, 0.1]));
        assert!(chord_follows(from, to, &between, &[0.05, 0.25]));
        // Past the slacks given, the least slack.
        assert!(!chord_follows(from, to, &between, &[0.05]));
    }
}
