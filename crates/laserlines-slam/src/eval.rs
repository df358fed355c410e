//! The relations metric of Kuemmerle et al. 2009 ("On measuring the accuracy of SLAM
//! algorithms"), as the Freiburg benchmark's metric evaluator reports it.
//!
//! A relation `(t1, t2, z)` says where the robot was at `t2` seen from where it was at `t1`
//! (`z = x(t1)^-1 * x(t2)`, from a reference such as a manually verified alignment). For an
//! estimated trajectory `x`, its poses at `t1` and `t2` (the nearest within
//! [`MAX_TIME_GAP_S`] of each) give `d = x(t1)^-1 * x(t2)`, and the error is
//! `e = z^-1 * d`. For every relation the metric takes
//!
//! - the translational error `|t(e)|` (the distance between the translations of `d` and
//!   `z`, both seen from `t1`), m, and its square, m^2;
//! - the rotational error `|theta(e)|`, the heading difference wrapped to `[0, pi]`, reported
//!   in degrees, and its square, deg^2;
//!
//! and reports each as mean and standard deviation (over the N relations, dividing by N)
//! with N and the largest value.

use laserlines::math::wrap_angle;

use crate::se2::Se2;

/// Relations are matched to trajectory poses at most this far apart in time, s.
pub const MAX_TIME_GAP_S: f64 = 0.1;

/// One relation: the pose at `t2` seen from the pose at `t1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Relation {
    /// First time stamp, s.
    pub t1: f64,
    /// Second time stamp, s.
    pub t2: f64,
    /// `x(t1)^-1 * x(t2)`.
    pub delta: Se2,
}

/// Mean, standard deviation (population) and largest value of a set of errors.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Summary {
    /// Mean.
    pub mean: f64,
    /// Standard deviation, dividing by N.
    pub std: f64,
    /// Largest value.
    pub max: f64,
}

impl Summary {
    /// The summary of `values` (zeros for none).
    #[must_use]
    pub fn of(values: &[f64]) -> Self {
        if values.is_empty() {
            return Self::default();
        }
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let var = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / n;
        Self {
            mean,
            std: var.max(0.0).sqrt(),
            max: values.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        }
    }
}

/// The metric over a set of relations.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RelationsScore {
    /// Relations scored.
    pub n: usize,
    /// Translational error, m.
    pub translation_m: Summary,
    /// Squared translational error, m^2.
    pub translation_sq_m2: Summary,
    /// Rotational error, deg.
    pub rotation_deg: Summary,
    /// Squared rotational error, deg^2.
    pub rotation_sq_deg2: Summary,
    /// Per relation: `(translational error m, rotational error deg)`, in input order.
    pub errors: Vec<(f64, f64)>,
}

/// Why a relation's time pairs with no pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Unpaired {
    /// No pose lies within [`MAX_TIME_GAP_S`] of it.
    NoPose,
    /// The nearest pose's stamp lies where the trajectory's stamps go back or stand still,
    /// from `lo` to `hi` (s): those times occur more than once along it, so that the time
    /// cannot tell which of its poses is meant.
    StampsRepeat {
        /// The lowest stamp of the stretch, s.
        lo: f64,
        /// The highest, s.
        hi: f64,
    },
}

/// A relation whose time stamp pairs with no single pose of the trajectory.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("relation {index} (0-based): {}", match why {
    Unpaired::NoPose => format!("no trajectory pose within {MAX_TIME_GAP_S} s of time {time}"),
    Unpaired::StampsRepeat { lo, hi } => format!(
        "time {time} pairs with no single pose: the trajectory's stamps go back or stand \
         still there ({lo}..{hi} s occur more than once)"
    ),
})]
pub struct UnmatchedTime {
    /// Index of the relation.
    pub index: usize,
    /// The time stamp without a pose, s.
    pub time: f64,
    /// Why.
    pub why: Unpaired,
}

/// The poses of a trajectory (`(stamp, pose)` in the order the robot went) by time: a time
/// pairs with the pose nearest in time, within [`MAX_TIME_GAP_S`], unless that pose's stamp
/// is one the trajectory's stamps pass more than once (where they go back or stand still:
/// broken stamps of some logs), as the time then cannot tell which pose is meant. Built once
/// for any number of times.
#[derive(Debug, Clone)]
pub struct Pairing {
    /// The poses with a finite stamp, by stamp.
    sorted: Vec<(f64, Se2)>,
    /// The stretches of times that occur more than once, merged, in order.
    repeated: Vec<(f64, f64)>,
}

impl Pairing {
    /// The pairing of `trajectory`'s poses.
    #[must_use]
    pub fn new(trajectory: &[(f64, Se2)]) -> Self {
        let mut sorted: Vec<(f64, Se2)> = trajectory
            .iter()
            .copied()
            .filter(|(t, _)| t.is_finite())
            .collect();
        sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
        Self {
            sorted,
            repeated: repeated_times(trajectory),
        }
    }

    /// The pose time `t` pairs with.
    ///
    /// # Errors
    /// Why it pairs with none, or with no single one.
    pub fn pose_at(&self, t: f64) -> Result<Se2, Unpaired> {
        let i = self.sorted.partition_point(|(s, _)| *s < t);
        let best = [i.checked_sub(1), Some(i)]
            .into_iter()
            .flatten()
            .filter_map(|k| self.sorted.get(k))
            .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()));
        let (s, p) = match best {
            Some((s, p)) if (s - t).abs() <= MAX_TIME_GAP_S => (*s, *p),
            _ => return Err(Unpaired::NoPose),
        };
        let k = self.repeated.partition_point(|span| span.1 < s);
        match self.repeated.get(k) {
            Some(&(lo, hi)) if lo <= s => Err(Unpaired::StampsRepeat { lo, hi }),
            _ => Ok(p),
        }
    }

    /// The poses relation `r` (the `index`-th) pairs with, at `t1` and at `t2`.
    ///
    /// # Errors
    /// [`UnmatchedTime`] for the first of its times that pairs with no single pose.
    pub fn poses_of(&self, r: &Relation, index: usize) -> Result<(Se2, Se2), UnmatchedTime> {
        let at = |time: f64| {
            self.pose_at(time)
                .map_err(|why| UnmatchedTime { index, time, why })
        };
        Ok((at(r.t1)?, at(r.t2)?))
    }
}

/// The stretches of times that occur more than once along `trajectory` (in its order):
/// wherever a stamp is not above the one before, the times from it to that one, merged
/// where they overlap, in order.
fn repeated_times(trajectory: &[(f64, Se2)]) -> Vec<(f64, f64)> {
    let mut spans: Vec<(f64, f64)> = trajectory
        .windows(2)
        .filter(|w| w[0].0.is_finite() && w[1].0.is_finite() && w[1].0 <= w[0].0)
        .map(|w| (w[1].0, w[0].0))
        .collect();
    spans.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut merged: Vec<(f64, f64)> = Vec::with_capacity(spans.len());
    for (lo, hi) in spans {
        match merged.last_mut() {
            Some(last) if lo <= last.1 => last.1 = last.1.max(hi),
            _ => merged.push((lo, hi)),
        }
    }
    merged
}

/// The errors of one relation: translational (m) and rotational (rad, in `[0, pi]`).
#[must_use]
pub fn relation_error(from: &Se2, to: &Se2, reference: &Se2) -> (f64, f64) {
    let d = from.between(to);
    let e = reference.inverse().compose(&d);
    (e.translation().norm(), wrap_angle(e.theta).abs())
}

/// Scores a trajectory (`(stamp, pose)` in the order the robot went) against relations, each
/// time paired with a pose as [`Pairing`] pairs it.
///
/// # Errors
/// [`UnmatchedTime`] for the first relation with a time stamp that pairs with no pose, or
/// with no single one.
pub fn score_relations(
    trajectory: &[(f64, Se2)],
    relations: &[Relation],
) -> Result<RelationsScore, UnmatchedTime> {
    let pairing = Pairing::new(trajectory);
    let mut errors = Vec::with_capacity(relations.len());
    for (k, r) in relations.iter().enumerate() {
        let (a, b) = pairing.poses_of(r, k)?;
        let (t, rot) = relation_error(&a, &b, &r.delta);
        errors.push((t, rot.to_degrees()));
    }
    let trans: Vec<f64> = errors.iter().map(|e| e.0).collect();
    let rot: Vec<f64> = errors.iter().map(|e| e.1).collect();
    let sq = |v: &[f64]| v.iter().map(|x| x * x).collect::<Vec<_>>();
    Ok(RelationsScore {
        n: errors.len(),
        translation_m: Summary::of(&trans),
        translation_sq_m2: Summary::of(&sq(&trans)),
        rotation_deg: Summary::of(&rot),
        rotation_sq_deg2: Summary::of(&sq(&rot)),
        errors,
    })
}

/// Relations between the poses of a reference trajectory every `step` poses apart
/// (for a consistency check against a trajectory that is not ground truth).
#[must_use]
pub fn relations_from_trajectory(reference: &[(f64, Se2)], step: usize) -> Vec<Relation> {
    let step = step.max(1);
    reference
        .windows(step + 1)
        .step_by(step)
        .map(|w| Relation {
            t1: w[0].0,
            t2: w[step].0,
            delta: w[0].1.between(&w[step].1),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    /// Three poses: the origin, 1 m ahead, then a quarter turn left 1 m to the side.
    fn trajectory() -> Vec<(f64, Se2)> {
        vec![
            (0.0, Se2::new(0.0, 0.0, 0.0)),
            (1.0, Se2::new(1.0, 0.0, 0.0)),
            (2.0, Se2::new(1.0, 1.0, FRAC_PI_2)),
        ]
    }

    #[test]
    fn hand_computed_errors() {
        let relations = [
            // The reference says 1.1 m ahead: 0.1 m off, no rotation error.
            Relation {
                t1: 0.0,
                t2: 1.0,
                delta: Se2::new(1.1, 0.0, 0.0),
            },
            // Right translation (1 m left of pose 1), heading 0.1 rad more: 5.7296 deg.
            Relation {
                t1: 1.0,
                t2: 2.0,
                delta: Se2::new(0.0, 1.0, FRAC_PI_2 + 0.1),
            },
            // Time 2.05 takes the pose at 2.0 (within 0.1 s); 0.2 m off along y.
            Relation {
                t1: 0.0,
                t2: 2.05,
                delta: Se2::new(1.0, 1.2, FRAC_PI_2),
            },
        ];
        let s = score_relations(&trajectory(), &relations).unwrap();
        assert_eq!(s.n, 3);
        let close = |a: f64, b: f64| (a - b).abs() < 1e-9;
        assert!(
            close(s.errors[0].0, 0.1) && close(s.errors[0].1, 0.0),
            "{:?}",
            s.errors
        );
        assert!(
            close(s.errors[1].0, 0.0) && close(s.errors[1].1, 0.1f64.to_degrees()),
            "{:?}",
            s.errors
        );
        assert!(
            close(s.errors[2].0, 0.2) && close(s.errors[2].1, 0.0),
            "{:?}",
            s.errors
        );
        assert!(close(s.translation_m.mean, 0.1));
        assert!(close(s.translation_m.std, (0.02f64 / 3.0).sqrt()));
        assert!(close(s.translation_m.max, 0.2));
        assert!(close(s.translation_sq_m2.mean, 0.05 / 3.0));
        assert!(close(s.rotation_deg.mean, 0.1f64.to_degrees() / 3.0));
        assert!(close(
            s.rotation_sq_deg2.mean,
            0.1f64.to_degrees().powi(2) / 3.0
        ));
        assert!(close(s.rotation_deg.max, 0.1f64.to_degrees()));
    }

    #[test]
    fn headings_wrap_across_pi() {
        let t = [
            (0.0, Se2::IDENTITY),
            (1.0, Se2::new(0.0, 0.0, -std::f64::consts::PI + 0.01)),
        ];
        let r = [Relation {
            t1: 0.0,
            t2: 1.0,
            delta: Se2::new(0.0, 0.0, std::f64::consts::PI - 0.01),
        }];
        let s = score_relations(&t, &r).unwrap();
        assert!(
            (s.errors[0].1 - 0.02f64.to_degrees()).abs() < 1e-9,
            "{:?}",
            s.errors
        );
    }

    #[test]
    fn a_time_without_a_pose_is_an_error() {
        let r = [
            Relation {
                t1: 0.0,
                t2: 1.0,
                delta: Se2::IDENTITY,
            },
            Relation {
                t1: 0.5,
                t2: 1.0,
                delta: Se2::IDENTITY,
            },
        ];
        assert_eq!(
            score_relations(&trajectory(), &r),
            Err(UnmatchedTime {
                index: 1,
                time: 0.5,
                why: Unpaired::NoPose
            })
        );
    }

    #[test]
    fn a_time_where_the_stamps_go_back_or_stand_still_pairs_with_no_pose() {
        let pose = |x: f64| Se2::new(x, 0.0, 0.0);
        // The stamps go back from 3 to 2 (2..3 s occur twice) and stand still at 5.
        let t: Vec<(f64, Se2)> = [0.0, 1.0, 2.0, 3.0, 2.0, 3.0, 4.0, 5.0, 5.0, 6.0]
            .iter()
            .enumerate()
            .map(|(k, &s)| (s, pose(k as f64)))
            .collect();
        let at = |t1: f64, t2: f64| Relation {
            t1,
            t2,
            delta: Se2::IDENTITY,
        };
        let why = |r: Relation| score_relations(&t, &[r]).map(|_| ()).map_err(|e| e.why);
        assert_eq!(why(at(0.0, 1.0)), Ok(()));
        assert_eq!(why(at(4.0, 6.0)), Ok(()));
        // Near 1 s, the nearest pose's stamp is 1: a time passed once.
        assert_eq!(why(at(1.04, 6.0)), Ok(()));
        let back = Err(Unpaired::StampsRepeat { lo: 2.0, hi: 3.0 });
        assert_eq!(why(at(2.5, 6.0)), Err(Unpaired::NoPose));
        assert_eq!(why(at(0.0, 2.0)), back);
        assert_eq!(why(at(2.95, 4.0)), back);
        assert_eq!(
            why(at(5.0, 6.0)),
            Err(Unpaired::StampsRepeat { lo: 5.0, hi: 5.0 })
        );
        // A sorted copy pairs everywhere: the repeats are in the order of the poses.
        let mut sorted = t.clone();
        sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
        sorted.dedup_by(|a, b| a.0 == b.0);
        assert!(score_relations(&sorted, &[at(2.0, 5.0)]).is_ok());
        let e = score_relations(&t, &[at(0.0, 2.0)]).unwrap_err();
        assert_eq!(
            e.to_string(),
            "relation 0 (0-based): time 2 pairs with no single pose: the trajectory's stamps \
             go back or stand still there (2..3 s occur more than once)"
        );
    }

    #[test]
    fn relations_of_a_trajectory_with_itself_score_zero() {
        let t = trajectory();
        let r = relations_from_trajectory(&t, 1);
        assert_eq!(r.len(), 2);
        assert_eq!((r[1].t1, r[1].t2), (1.0, 2.0));
        let s = score_relations(&t, &r).unwrap();
        assert!(s.translation_m.max < 1e-12 && s.rotation_deg.max < 1e-9);
        assert_eq!(relations_from_trajectory(&t, 2).len(), 1);
    }
}
