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

/// A relation whose time stamp matches no pose of the trajectory.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("relation {index} (0-based): no trajectory pose within {MAX_TIME_GAP_S} s of time {time}")]
pub struct UnmatchedTime {
    /// Index of the relation.
    pub index: usize,
    /// The time stamp without a pose, s.
    pub time: f64,
}

/// The errors of one relation: translational (m) and rotational (rad, in `[0, pi]`).
#[must_use]
pub fn relation_error(from: &Se2, to: &Se2, reference: &Se2) -> (f64, f64) {
    let d = from.between(to);
    let e = reference.inverse().compose(&d);
    (e.translation().norm(), wrap_angle(e.theta).abs())
}

/// Scores a trajectory (`(stamp, pose)`, any order) against relations.
///
/// # Errors
/// [`UnmatchedTime`] for the first relation with a time stamp that matches no pose.
pub fn score_relations(trajectory: &[(f64, Se2)], relations: &[Relation]) -> Result<RelationsScore, UnmatchedTime> {
    let mut sorted: Vec<(f64, Se2)> = trajectory.iter().copied().filter(|(t, _)| t.is_finite()).collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let find = |t: f64, index: usize| -> Result<Se2, UnmatchedTime> {
        let i = sorted.partition_point(|(s, _)| *s < t);
        let best = [i.checked_sub(1), Some(i)]
            .into_iter()
            .flatten()
            .filter_map(|k| sorted.get(k))
            .min_by(|a, b| (a.0 - t).abs().total_cmp(&(b.0 - t).abs()));
        match best {
            Some((s, p)) if (s - t).abs() <= MAX_TIME_GAP_S => Ok(*p),
            _ => Err(UnmatchedTime { index, time: t }),
        }
    };
    let mut errors = Vec::with_capacity(relations.len());
    for (k, r) in relations.iter().enumerate() {
        let a = find(r.t1, k)?;
        let b = find(r.t2, k)?;
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
