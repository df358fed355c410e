//! `laserlines relations TRAJECTORY RELATIONS`: the relations metric of Kuemmerle et al.
//! 2009 (`laserlines_slam::eval`) for a TUM trajectory against a relations file, or, with
//! `--every N`, against relations taken between the poses of a reference TUM trajectory
//! `N` poses apart (a consistency check against a trajectory that is not ground truth);
//! two trajectories with the same time stamps pose for pose are then paired by order.

use std::fs::File;
use std::io::BufReader;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use laserlines_io::trajectory::{StampedPose, read_relations, read_tum};
use laserlines_slam::Se2;
use laserlines_slam::eval::{
    MAX_TIME_GAP_S, Pairing, Relation, Summary, UnmatchedTime, Unpaired, relations_from_trajectory,
    score_relations,
};

/// Arguments of `laserlines relations`.
#[derive(Debug, Args)]
pub struct RelationsArgs {
    /// The trajectory to score (TUM: `t x y z qx qy qz qw`).
    pub trajectory: PathBuf,
    /// The relations (`t1 t2 x y z roll pitch yaw`), or with --every a reference trajectory
    /// (TUM).
    pub relations: PathBuf,
    /// Take relations between the poses of the reference trajectory this many poses apart
    /// (trajectories with the same stamps pose for pose are paired by order).
    #[arg(long, value_parser = every, allow_negative_numbers = true)]
    pub every: Option<usize>,
    /// Score only the relations whose two times the trajectory covers (a trajectory of part
    /// of a log), and say how many were left out; without it, such a relation is an error.
    #[arg(long)]
    pub covered: bool,
    /// With --every: move each pose of the reference by this offset in its own frame,
    /// `x,y,yaw_deg` (m, m, deg), before taking relations: a reference of the robot's base
    /// scored against a trajectory of its laser (`map` gives the laser's) takes the laser's
    /// mount, e.g. `0.15,0,0` for a laser 0.15 m ahead of the axle.
    #[arg(
        long,
        value_name = "X,Y,YAW_DEG",
        requires = "every",
        allow_hyphen_values = true
    )]
    pub reference_offset: Option<String>,
}

/// The value parser of `--every`: a whole number of poses, at least 1.
fn every(s: &str) -> Result<usize, String> {
    super::whole_in(s, 1, i128::MAX)
}

/// Runs `laserlines relations`.
pub fn run(args: &RelationsArgs) -> Result<()> {
    let offset = match args.reference_offset.as_deref() {
        Some(s) => {
            let [x, y, yaw] = super::xy_yaw_deg("--reference-offset", s)?;
            Some(Se2::new(x, y, yaw))
        }
        None => None,
    };
    let mut traj = read_trajectory(&args.trajectory)?;
    let rel_name = args.relations.display().to_string();
    let (relations, lines) = load_relations(args, &rel_name, &mut traj, offset)?;
    let relations = if args.covered {
        covered_only(args, &rel_name, &traj, relations)?
    } else {
        relations
    };
    let score = score_relations(&traj, &relations).map_err(|e| {
        let e = unpaired(args, &rel_name, &traj, lines.get(e.index).copied(), &e);
        if args.every.is_none() {
            not_a_trajectory(&args.relations, e)
        } else {
            e
        }
    })?;
    outln!(
        "{} of {rel_name}, {} of {}",
        super::count(score.n as u64, "relation"),
        super::count(traj.len() as u64, "pose"),
        args.trajectory.display()
    );
    let row = |name: &str, unit: &str, s: &Summary| {
        outln!(
            "{name:<30} {:>10.6} +- {:>10.6} {unit:<6} (max {:.6})",
            s.mean,
            s.std,
            s.max
        );
    };
    row("translational error", "m", &score.translation_m);
    row(
        "squared translational error",
        "m^2",
        &score.translation_sq_m2,
    );
    row("rotational error", "deg", &score.rotation_deg);
    row("squared rotational error", "deg^2", &score.rotation_sq_deg2);
    Ok(())
}

/// The error of a relation that pairs with no pose (`line`: its line in the relations file).
fn unpaired(
    args: &RelationsArgs,
    rel_name: &str,
    traj: &[(f64, Se2)],
    line: Option<usize>,
    e: &UnmatchedTime,
) -> anyhow::Error {
    let at = match line {
        Some(line) => format!("{rel_name}:{line}: relation"),
        None => format!("{rel_name}: relation {}", e.index + 1),
    };
    let name = args.trajectory.display();
    match e.why {
        Unpaired::NoPose => {
            let span = match (traj.first(), traj.last()) {
                (Some(a), Some(b)) => format!(", whose poses span t = {}..{}", a.0, b.0),
                _ => String::new(),
            };
            anyhow::anyhow!(
                "{at} (t = {}): no pose of {name}{span} within {MAX_TIME_GAP_S} s (--covered \
                 scores only the relations the trajectory covers)",
                e.time
            )
        }
        Unpaired::StampsRepeat { lo, hi } => {
            let times = if lo == hi {
                format!("t = {lo} occurs")
            } else {
                format!("t = {lo}..{hi} occur")
            };
            anyhow::anyhow!(
                "{at} (t = {}): no single pose of {name} to pair with: its stamps go back or \
                 stand still there ({times} more than once), as in logs with broken stamps; \
                 two trajectories of one log with the same stamps pair pose by pose with \
                 --every N, and --covered leaves such relations out",
                e.time
            )
        }
    }
}

/// The relations to score: read from the relations file, or with `--every N` made from the
/// reference trajectory's poses `N` apart (each moved by `offset` first, when given; when the
/// two trajectories have the same stamps, both are renumbered pose by pose in `traj` and the
/// reference). Never empty. With them, the lines of the relations file they come from (none
/// with `--every`).
fn load_relations(
    args: &RelationsArgs,
    rel_name: &str,
    traj: &mut [(f64, Se2)],
    offset: Option<Se2>,
) -> Result<(Vec<Relation>, Vec<usize>)> {
    let mut lines = Vec::new();
    let relations: Vec<Relation> = match args.every {
        Some(n) => {
            let mut reference =
                read_trajectory(&args.relations).map_err(|e| not_relations(&args.relations, e))?;
            if let Some(offset) = offset {
                for (_, pose) in &mut reference {
                    *pose = pose.compose(&offset);
                }
            }
            // Two trajectories of one log (as `laserlines map` writes them) pair pose by pose,
            // so that logs whose time stamps repeat or are all zero can be checked too.
            let same_stamps = reference.len() == traj.len()
                && reference.iter().zip(traj.iter()).all(|(a, b)| a.0 == b.0);
            if same_stamps {
                for (k, (r, t)) in reference.iter_mut().zip(traj.iter_mut()).enumerate() {
                    (r.0, t.0) = (k as f64, k as f64);
                }
            }
            relations_from_trajectory(&reference, n)
        }
        None => read_relations(rel_name, open(&args.relations)?)
            .map_err(|e| not_a_trajectory(&args.relations, e.into()))?
            .into_iter()
            .map(|r| {
                lines.push(r.line);
                Relation {
                    t1: r.t1,
                    t2: r.t2,
                    delta: Se2::new(r.delta.x, r.delta.y, r.delta.theta),
                }
            })
            .collect(),
    };
    if relations.is_empty() {
        match args.every {
            Some(n) => bail!(
                "{rel_name}: no relations: --every {n} needs more than {n} poses of the \
                 reference that pair with the trajectory's"
            ),
            None => bail!("{rel_name}: no relations"),
        }
    }
    Ok((relations, lines))
}

/// `--covered`: the relations whose two times `traj` covers (each pairing with a single
/// pose), saying how many were left out and why; an error when none is.
fn covered_only(
    args: &RelationsArgs,
    rel_name: &str,
    traj: &[(f64, Se2)],
    relations: Vec<Relation>,
) -> Result<Vec<Relation>> {
    let all = relations.len();
    let (mut outside, mut repeated) = (0, 0);
    let pairing = Pairing::new(traj);
    let covered: Vec<Relation> = relations
        .into_iter()
        .enumerate()
        .filter(|(k, r)| match pairing.poses_of(r, *k).map_err(|e| e.why) {
            Ok(_) => true,
            Err(Unpaired::NoPose) => {
                outside += 1;
                false
            }
            Err(Unpaired::StampsRepeat { .. }) => {
                repeated += 1;
                false
            }
        })
        .map(|(_, r)| r)
        .collect();
    let name = args.trajectory.display();
    if covered.is_empty() {
        bail!(
            "{rel_name}: none of its {all} relations pairs with poses of {name} ({outside} \
             outside its times, within {MAX_TIME_GAP_S} s of a pose; {repeated} where its \
             stamps go back or stand still)"
        );
    }
    if outside > 0 {
        outln!(
            "{rel_name}: {outside} of {all} relations left out: the trajectory does not cover \
             their times"
        );
    }
    if repeated > 0 {
        outln!(
            "{rel_name}: {repeated} of {all} relations left out: the trajectory's stamps go \
             back or stand still at their times, so they pair with no single pose"
        );
    }
    Ok(covered)
}

/// `e`, or when the relations file reads as a TUM trajectory (8 numbers per row too, but
/// a unit quaternion at the end), an error that says so and names `--every`.
fn not_a_trajectory(path: &Path, e: anyhow::Error) -> anyhow::Error {
    let name = path.display().to_string();
    if holds_any(path, read_tum) {
        anyhow::anyhow!(
            "{name}: a TUM trajectory (t x y z qx qy qz qw), not relations (t1 t2 x y z roll \
             pitch yaw): to check against a reference trajectory, give --every N (relations \
             between its poses N apart)"
        )
    } else {
        e
    }
}

/// `e`, or when the reference given to `--every` reads as relations (8 numbers per row too),
/// an error that says so.
fn not_relations(path: &Path, e: anyhow::Error) -> anyhow::Error {
    let name = path.display().to_string();
    if holds_any(path, read_relations) {
        anyhow::anyhow!(
            "{name}: relations (t1 t2 x y z roll pitch yaw), not a TUM trajectory (t x y z qx qy \
             qz qw): --every N takes a reference trajectory; without --every the relations \
             file is scored as it is"
        )
    } else {
        e
    }
}

/// True when `path` reads by `read` (the other format) into at least one item.
fn holds_any<T, E>(
    path: &Path,
    read: impl FnOnce(&str, BufReader<File>) -> Result<Vec<T>, E>,
) -> bool {
    let name = path.display().to_string();
    open(path)
        .ok()
        .and_then(|input| read(&name, input).ok())
        .is_some_and(|items| !items.is_empty())
}

fn open(path: &Path) -> Result<BufReader<File>> {
    Ok(BufReader::new(File::open(path).with_context(|| {
        format!("{}: cannot open", path.display())
    })?))
}

fn read_trajectory(path: &Path) -> Result<Vec<(f64, Se2)>> {
    let name = path.display().to_string();
    let poses: Vec<StampedPose> = match read_tum(&name, open(path)?) {
        Ok(poses) => poses,
        Err(e) if holds_any(path, read_relations) => bail!(
            "{e}; {name} reads as relations (t1 t2 x y z roll pitch yaw): the trajectory comes \
             first, `laserlines relations TRAJECTORY.tum RELATIONS`"
        ),
        Err(e) => return Err(e.into()),
    };
    if poses.is_empty() {
        bail!("{name}: no poses");
    }
    Ok(poses
        .iter()
        .map(|p| (p.t, Se2::new(p.pose.x, p.pose.y, p.pose.theta)))
        .collect())
}
