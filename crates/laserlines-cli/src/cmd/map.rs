//! `laserlines map LOG -o DIR`: a map and a trajectory from a log of scans, with or without
//! odometry (`laserlines-slam`), written as files (`map_outputs`).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::{Args, ValueEnum};
use indicatif::ProgressBar;
use laserlines::LineExtractor;
use laserlines_foxglove::McapSceneWriter;
use laserlines_io::ScanRecord;
use laserlines_slam::{Mapper, MapperParams, Se2};

use super::map_outputs::{self, Outputs};
use crate::InputArgs;

/// A switch: loop closure, and the log's odometry once `--odometry auto` is resolved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum OnOff {
    /// On.
    On,
    /// Off.
    Off,
}

/// Whether the mapper takes the log's wheel odometry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Odometry {
    /// As the log allows: on when its first scan has odometry, off when it has none.
    Auto,
    /// On: every scan must have odometry.
    On,
    /// Off: the scans alone.
    Off,
}

/// Arguments of `laserlines map`.
#[derive(Debug, Args)]
pub struct MapArgs {
    #[command(flatten)]
    pub input: InputArgs,
    /// Output directory: trajectory.tum, map.pgm, map.yaml, map.png, lines.json, map.svg,
    /// and log-poses.tum and odometry.tum when the log has poses and odometry.
    #[arg(short, long, default_value = "laserlines-map")]
    pub output: PathBuf,
    /// Use the log's wheel odometry (`on`: CARMEN's odometry triple, never its laser pose;
    /// every scan must have it), or map from the scans alone (`off`); `auto` is `on` when the
    /// first scan has odometry and `off` (with a note) when it has none.
    #[arg(long, value_enum, default_value_t = Odometry::Auto)]
    pub odometry: Odometry,
    /// Search for loop closures (`off`: scan-to-submap matching alone).
    #[arg(long, value_enum, default_value_t = OnOff::On)]
    pub loop_closure: OnOff,
    /// Also write the run for Foxglove: the map as foxglove.Grid, poses, scans and lines.
    #[arg(long)]
    pub mcap: Option<PathBuf>,
    #[command(flatten)]
    pub params: super::ParamsArgs,
    /// Side of an occupancy grid cell, m (0.005 to 10).
    #[arg(long, default_value_t = 0.05, allow_negative_numbers = true)]
    pub resolution: f64,
    /// Count and skip bad records (reported in the summary) instead of stopping at the first.
    /// A failed read of the input itself (an I/O error, a corrupt gzip stream) still ends the
    /// run with an error.
    /// Without it, the scans before a bad record are still mapped and written, and the run
    /// ends with the error.
    #[arg(long)]
    pub skip_bad: bool,
}

/// Runs `laserlines map`.
pub fn run(args: &MapArgs) -> Result<()> {
    let start = Instant::now();
    let name = args.input.input.display().to_string();
    if !(0.005..=10.0).contains(&args.resolution) {
        bail!(
            "--resolution must lie from 0.005 to 10 m, got {}",
            super::compact(args.resolution)
        );
    }
    let reader = super::open_input(&args.input)?;
    // The output directory is made and tried before the mapping: a run of minutes must not
    // end in "cannot create". The folders made here are removed again, if still empty, when
    // the mapping fails before writing anything.
    let made = first_missing(&args.output);
    let unmake = || {
        if let Some(top) = &made {
            for dir in args.output.ancestors() {
                if std::fs::remove_dir(dir).is_err() || dir == top {
                    break;
                }
            }
        }
    };
    let Some(path) = &args.mcap else {
        map_outputs::prepare_dir(&args.output)?;
        return match map_log(args, &name, reader, None, start) {
            Ok(stopped) => stopped.map_or(Ok(()), Err),
            Err(e) => {
                unmake();
                Err(e)
            }
        };
    };
    let params = args.params.file_path();
    let inputs: Vec<&std::path::Path> = [Some(args.input.input.as_path()), params]
        .into_iter()
        .flatten()
        .collect();
    super::refuse_recording_over(path, &inputs, &args.output, &map_outputs::OUTPUT_FILES)?;
    // The MCAP too, first; removed when the mapping fails, so that no empty or partial file
    // is left where a run was expected.
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    let writer = McapSceneWriter::create(path)?;
    if let Err(e) = map_outputs::prepare_dir(&args.output) {
        super::remove_own_output(path);
        return Err(e);
    }
    match map_log(args, &name, reader, Some((path, writer)), start) {
        Ok(None) => Ok(()),
        // The scans before a bad record were mapped and written, the MCAP too.
        Ok(Some(stopped)) => Err(stopped),
        Err(e) => {
            super::remove_own_output(path);
            unmake();
            Err(e)
        }
    }
}

/// The highest folder of `dir`'s path (`dir` itself included) that does not exist: the
/// first that creating `dir` makes.
fn first_missing(dir: &std::path::Path) -> Option<std::path::PathBuf> {
    dir.ancestors()
        .take_while(|a| !a.as_os_str().is_empty() && !a.exists())
        .last()
        .map(std::path::Path::to_path_buf)
}

/// What the reading of a log gave the mapper.
#[derive(Default)]
struct Mapped {
    stamps: Vec<f64>,
    log_poses: Vec<Option<laserlines_io::Pose2>>,
    log_odometry: Vec<Option<laserlines_io::Pose2>>,
    /// Each scan with its lines, for the MCAP (empty without `--mcap`).
    kept: Vec<(ScanRecord, Vec<laserlines::Line>)>,
    /// What ended the reading, without `--skip-bad`.
    stopped: Option<Stop>,
    /// Scans skipped with `--skip-bad` for want of odometry under `--odometry on`.
    without_odometry: u64,
}

/// What ended the reading of a log before its end.
enum Stop {
    /// A bad record, or a read error.
    Read(laserlines_io::ReadError),
    /// A scan without odometry under `--odometry on` (the error names it).
    NoOdometry(anyhow::Error),
}

/// The reason `--skip-bad` counts a scan without odometry under.
const NO_ODOMETRY: &str = "scan without odometry (--odometry on)";

/// Maps the scans of `reader` and writes the outputs (and the MCAP to `mcap`, when given).
/// A bad record without `--skip-bad` ends the reading: the scans before it are mapped and
/// written, and the error comes back as `Ok(Some(error))`.
fn map_log(
    args: &MapArgs,
    name: &str,
    mut reader: laserlines_io::ScanReader,
    mut mcap: Option<(&PathBuf, McapSceneWriter<std::io::BufWriter<std::fs::File>>)>,
    start: Instant,
) -> Result<Option<anyhow::Error>> {
    super::note_unused_tables(args.params.file_path(), &["hough-split"], "map")?;
    let mut params = MapperParams::default();
    if args.loop_closure == OnOff::Off {
        params.loops.every_scans = 0;
    }
    let mut mapper = Mapper::new(params);
    let progress = super::scan_spinner(" mapped");
    let run = read_and_map(args, name, &mut reader, &mut mapper, &progress)?;
    // What the reader left out by design (other messages of a log, readings sharing a beam)
    // is said too, not only the bad records of --skip-bad.
    let stopped_read = match &run.stopped {
        Some(Stop::Read(e)) => Some(e),
        _ => None,
    };
    let mut skipped = skipped_besides(reader.skipped(), stopped_read);
    skipped.add_n(NO_ODOMETRY, run.without_odometry);
    if run.stamps.is_empty() {
        return Err(match run.stopped {
            Some(Stop::Read(e)) => e.into(),
            Some(Stop::NoOdometry(e)) => e,
            None => super::no_scans(name, &skipped),
        });
    }
    if let Some(note) = stamp_note(&run.stamps) {
        progress.suspend(|| errln!("laserlines: {name}: {note}"));
    }
    progress.set_message("optimising");
    mapper
        .optimize()
        .with_context(|| format!("{name}: final optimisation"))?;
    progress.finish_and_clear();
    let mapped_s = start.elapsed().as_secs_f64();
    let outputs = Outputs {
        dir: &args.output,
        name,
        mapper: &mapper,
        stamps: &run.stamps,
        log_poses: &run.log_poses,
        log_odometry: &run.log_odometry,
        resolution_m: args.resolution,
    };
    let mut files = map_outputs::write_all(&outputs)?;
    if let Some((path, writer)) = mcap.take() {
        map_outputs::write_mcap(writer, &outputs, &run.kept)?;
        files.push(path.clone());
    }
    summary(
        name,
        &mapper,
        mapped_s,
        start.elapsed().as_secs_f64(),
        &files,
    );
    if args.skip_bad || !skipped.is_empty() {
        errln!("{name}: skipped: {skipped}");
    }
    let mapped = run.stamps.len();
    Ok(run.stopped.map(|e| stopped_error(e, name, mapped, args)))
}

/// The extractor of scan matching: the params file's `[hough-split]` as
/// [`laserlines::HoughSplitParams::for_mapping`] sets it, with a note on standard error of
/// the keys the file gives that it sets its own way.
fn mapping_extractor(args: &MapArgs) -> Result<laserlines::HoughSplit> {
    let hough_split = &laserlines::registry::HOUGH_SPLIT;
    let file = args.params.file(hough_split.name)?;
    let given = file.algorithm_params(hough_split)?;
    let shown = serde_json::to_value(&given)?;
    let used = given.for_mapping();
    let taken = serde_json::to_value(&used)?;
    let overridden: Vec<String> = file
        .keys(hough_split.name)
        .filter(|k| shown.get(k) != taken.get(k))
        .map(|k| format!("{k} = {}", taken[k]))
        .collect();
    if !overridden.is_empty() {
        errln!(
            "laserlines: {}: map takes [hough-split] {} for scan matching, not the file's \
             values (see `map` in the README)",
            file.name(),
            overridden.join(", ")
        );
    }
    laserlines::HoughSplit::new(used).context("hough-split parameters")
}

/// What the reader skipped, less the bad record that stopped the reading: the reader counts
/// each bad record it returns, but that one ended the map and was not skipped.
fn skipped_besides(
    skipped: &laserlines_io::SkipCounts,
    stopped: Option<&laserlines_io::ReadError>,
) -> laserlines_io::SkipCounts {
    let stop = stopped
        .filter(|e| e.is_bad_record())
        .map(laserlines_io::ReadError::reason);
    let mut out = laserlines_io::SkipCounts::new();
    for (reason, n) in skipped.iter() {
        let n = if stop == Some(reason) {
            n.saturating_sub(1)
        } else {
            n
        };
        out.add_n(reason, n);
    }
    out
}

/// Reads the scans of `reader` into `mapper`, each with its lines and (with `--odometry
/// on`) the log's odometry; a bad record is skipped and reported with `--skip-bad`, and
/// otherwise ends the reading.
fn read_and_map(
    args: &MapArgs,
    name: &str,
    reader: &mut laserlines_io::ScanReader,
    mapper: &mut Mapper,
    progress: &ProgressBar,
) -> Result<Mapped> {
    let mut extractor = mapping_extractor(args)?;
    let mut lines = Vec::new();
    let mut run = Mapped::default();
    // `auto` is resolved at the first scan.
    let mut mode = match args.odometry {
        Odometry::Auto => None,
        Odometry::On => Some(OnOff::On),
        Odometry::Off => Some(OnOff::Off),
    };
    for item in reader.by_ref() {
        let record = match item {
            Ok(r) => r,
            Err(e) if super::skips(args.skip_bad, &e) => {
                // The reader counts it under its reason for the summary.
                progress.suspend(|| errln!("laserlines: skipped: {e}"));
                continue;
            }
            Err(e) => {
                run.stopped = Some(Stop::Read(e));
                break;
            }
        };
        // The scan's index among the scans read, counting those skipped for want of
        // odometry.
        let k = run.stamps.len() + run.without_odometry as usize;
        let on_off = *mode.get_or_insert_with(|| {
            if record.odometry.is_some() {
                OnOff::On
            } else {
                progress.suspend(|| {
                    errln!("laserlines: {name}: no odometry in the first scan: mapped from the scans alone (--odometry off)");
                });
                OnOff::Off
            }
        });
        let odometry = match odometry_of(&record, on_off, name, k) {
            Ok(o) => o,
            Err(e) if args.skip_bad => {
                progress.suspend(|| errln!("laserlines: skipped: {e:#}"));
                run.without_odometry += 1;
                continue;
            }
            Err(e) => {
                run.stopped = Some(Stop::NoOdometry(e));
                break;
            }
        };
        extractor.extract_into(&record.scan, &mut lines);
        mapper
            .add_scan(&record.scan, &lines, odometry)
            .with_context(|| format!("{name}: scan {k}"))?;
        run.stamps.push(record.scan.stamp.unwrap_or(k as f64 * 0.1));
        run.log_poses.push(record.pose);
        run.log_odometry.push(record.odometry);
        if args.mcap.is_some() {
            run.kept.push((record, lines.clone()));
        }
        progress.inc(1);
    }
    Ok(run)
}

/// The error that ends a run stopped by `stop` after `mapped` scans, saying what was written.
fn stopped_error(stop: Stop, name: &str, mapped: usize, args: &MapArgs) -> anyhow::Error {
    let mapped = super::count(mapped as u64, "scan");
    let dir = args.output.display();
    let e = match stop {
        Stop::Read(e) => e,
        Stop::NoOdometry(e) => {
            return e.context(format!(
                "{name}: stopped at a scan without odometry; the map of the {mapped} before \
                 it is written ({dir}; --skip-bad skips such scans)"
            ));
        }
    };
    if e.is_bad_record() {
        anyhow::Error::from(e).context(format!(
            "{name}: stopped at a bad record; the map of the {mapped} before it is written \
             ({dir}; --skip-bad skips bad records)"
        ))
    } else {
        anyhow::Error::from(e).context(format!(
            "{name}: stopped where the input could not be read further; the map of the \
             {mapped} before it is written ({dir})"
        ))
    }
}

/// The odometry of scan `k` the mapper takes: the record's with `--odometry on` (an error
/// naming the scan when it has none), none with `--odometry off`.
fn odometry_of(record: &ScanRecord, mode: OnOff, name: &str, k: usize) -> Result<Option<Se2>> {
    Ok(match (mode, record.odometry) {
        (OnOff::On, Some(p)) => Some(Se2::new(p.x, p.y, p.theta)),
        (OnOff::On, None) => bail!(
            "{name}: scan {k}{}: no odometry (the log gives none for this scan{}); map it with --odometry off",
            record
                .line
                .map(|l| format!(" (line {l})"))
                .unwrap_or_default(),
            if record.pose.is_some() {
                ", only a pose, which is not used as odometry"
            } else {
                ""
            }
        ),
        (OnOff::Off, _) => None,
    })
}

/// The summary on stderr.
fn summary(name: &str, mapper: &Mapper, mapped_s: f64, total_s: f64, files: &[PathBuf]) {
    let s = mapper.stats();
    let rate = if mapped_s > 0.0 {
        s.scans as f64 / mapped_s
    } else {
        0.0
    };
    errln!(
        "{name}: {} ({} not matched, kept at their prediction), {}, loop closures: {} accepted, {} rejected; {} in {:.2} s; mapped in {:.2} s ({:.0} scans/s), {:.2} s with the outputs",
        super::count(s.scans as u64, "scan"),
        s.unmatched,
        super::count(s.submaps as u64, "submap"),
        s.closures_accepted,
        s.closures_rejected,
        super::count(s.optimizations as u64, "optimisation"),
        s.optimization_s,
        mapped_s,
        rate,
        total_s
    );
    let list: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
    errln!("wrote {}", list.join(", "));
}

/// Words for stamps that do not increase from scan to scan (broken in some logs: all zero,
/// or printed with too few digits), which leave a trajectory that cannot be paired with
/// another by time; `None` when they increase.
fn stamp_note(stamps: &[f64]) -> Option<String> {
    let stuck = stamps
        .windows(2)
        .filter(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
        .count();
    if stuck == 0 {
        return None;
    }
    let all_same = stamps.iter().all(|&t| t == stamps[0]);
    let how = if all_same {
        format!("all are {} s", stamps[0])
    } else {
        format!(
            "{stuck} of {} steps go back or stand still",
            stamps.len() - 1
        )
    };
    Some(format!(
        "the scans' stamps do not increase ({how}): the trajectory files keep them as \
         written, so they cannot be paired with another trajectory by time; `laserlines \
         relations --every N` pairs two trajectories of this log pose by pose"
    ))
}
