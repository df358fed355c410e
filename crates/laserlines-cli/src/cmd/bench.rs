//! `laserlines bench`: every selected extractor on the same scans, in one process; accuracy
//! against ground truth (simulated suites) or coverage (real logs), and speed. `--tune`
//! chooses an extractor's parameters on a training suite instead.

use std::fs;
use std::io::{self, IsTerminal};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use laserlines::{LineExtractor, registry};
use laserlines_eval::{
    BenchOptions, BenchReport, BenchScan, DEFAULT_SCANS_PER_SUITE, MatchParams, SENSORS,
    SpeedRatio, TEST_SEED, TRAIN_SEED, arena_scans_counted, plain_scans, sensor, suite_scans,
};
use laserlines_harness::arenas;
use laserlines_render::ScatterChart;
use laserlines_sim::arena::ArenaOptions;
use serde::Serialize;

use super::ALGORITHMS;
use laserlines_io::params::ParamsFile;

/// The extractor whose speed the paper claims, and the baseline it compares with.
const FAST: &str = "hough-split";
const BASELINE: &str = "iterative-hough";

/// Arguments of `laserlines bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Simulated scene suite with ground truth: rooms, corridors, maze, boxes, clutter,
    /// glancing, far, or all (the default when no --data is given); or arenas: random free
    /// poses inside RoboCup Rescue arenas (the bundled ones, or those of --arenas), scenes
    /// no default was chosen on.
    #[arg(long, conflicts_with = "data")]
    suite: Option<String>,
    /// With --suite arenas: the arenas, as `.raf` files or names of bundled arenas (default:
    /// the four bundled ones). Implies --suite arenas.
    #[arg(long, num_args = 1.., conflicts_with = "data")]
    arenas: Vec<String>,
    /// Real logs to run on instead (any format `extract` reads); no ground truth.
    #[arg(long, num_args = 1..)]
    data: Vec<PathBuf>,
    /// Extractors to compare: `all` or a comma-separated list of names.
    #[arg(long, default_value = "all")]
    algorithms: String,
    /// Scans per simulated suite (1 to 20000; default 100), or at most this many scans per log
    /// (at least 1; default: all).
    #[arg(long, value_parser = super::whole::<usize>, allow_negative_numbers = true)]
    scans: Option<usize>,
    /// Seed of the simulated suites (default: the test seed, 2; with --tune the training
    /// seed, 1).
    #[arg(
        long,
        conflicts_with = "data",
        value_parser = super::whole::<u64>,
        allow_negative_numbers = true
    )]
    seed: Option<u64>,
    /// Simulated sensor and conditions: urg04lx, urg04lx-artefacts (mixed pixels and
    /// dropouts), or the field conditions urg04lx-half, urg04lx-full, urg04lx-1.5x (noise at
    /// half, once and 1.5 times the data sheet's band as one standard deviation, chair legs,
    /// mixed pixels, 0-5 % dropouts) and urg04lx-real (those conditions at a real URG-04LX's
    /// noise: 4 mm below 3 m, 1 % of the range beyond), or another scanner in those
    /// conditions at its data sheet's noise: utm30lx, ust10lx, lms1xx, lms2xx, rplidar-a1,
    /// rplidar-a2, ydlidar-x4 (30-70 % dropouts), or a depth camera's depth read as a scan
    /// (noise and steps growing with the square of the range): kinect, realsense-d435.
    #[arg(long, default_value = "urg04lx", conflicts_with = "data")]
    sensor: String,
    /// Which lines count as right: strict (each visible piece, intersection over union of
    /// the beams >= 1/2, tolerances of 1 cm / 0.5 deg widened to 4 standard errors of an
    /// ideal fit) or field (pieces of a wall behind small obstacles as one, |dr| <= 5 cm,
    /// 3 deg, half of the line on the wall).
    #[arg(long, default_value = "strict", value_parser = ["strict", "field"], conflicts_with = "data")]
    criteria: String,
    /// Share of each simulated scan's beams whose reading is spurious (sunlight, dust, a
    /// retroreflector's echo): a range anywhere from the sensor's minimum (at least 0.1 m)
    /// to its reach (at most 5.5 m), the ground truth that of the clean scan. 0..=1.
    #[arg(
        long,
        default_value_t = 0.0,
        allow_negative_numbers = true,
        conflicts_with = "data"
    )]
    spurious: f64,
    /// Timed extractions of each scan by each extractor (1 to 1000); the fastest counts.
    #[arg(long, default_value_t = 1, value_parser = super::repeat_count, allow_negative_numbers = true)]
    repeat: usize,
    /// TOML file of parameters (one table per algorithm), as for `extract`.
    #[arg(long)]
    params: Option<PathBuf>,
    /// Start every compared extractor that has a preset of this name from it (hough-split:
    /// paper, navigation, walls, complete), as `extract --preset` does; the others keep their
    /// defaults.
    #[arg(long, conflicts_with = "tune")]
    preset: Option<String>,
    /// Output folder for results.json, results.csv and accuracy-speed.svg.
    #[arg(short, long, default_value = "laserlines-bench")]
    output: PathBuf,
    /// Instead of comparing, choose ALGORITHM's parameters on the suite (coordinate search
    /// maximising F1) and print them as a params-file table.
    #[arg(long, value_name = "ALGORITHM", conflicts_with = "data")]
    tune: Option<String>,
}

/// The matching `--criteria` asks for.
fn matching(args: &BenchArgs) -> MatchParams {
    if args.criteria == "field" {
        MatchParams::field()
    } else {
        MatchParams::default()
    }
}

/// `file` with `preset` applied to each of `names` that has it; an error when none has.
fn with_preset(mut file: ParamsFile, names: &[String], preset: &str) -> Result<ParamsFile> {
    let mut applied = false;
    for name in names {
        if registry::presets(name).is_some_and(|p| p.contains(&preset)) {
            file = file.with_preset(name, preset)?;
            applied = true;
        }
    }
    if !applied {
        bail!(
            "--preset {preset}: none of the extractors compared has it (hough-split's: {})",
            registry::presets("hough-split")
                .unwrap_or_default()
                .join(", ")
        );
    }
    Ok(file)
}

/// Runs the command.
pub fn run(args: &BenchArgs) -> Result<()> {
    if let Some(algorithm) = &args.tune {
        return tune(args, algorithm);
    }
    let names = selected(&args.algorithms)?;
    let mut file = ParamsFile::load_or_default(args.params.as_deref())?;
    if let Some(preset) = &args.preset {
        file = with_preset(file, &names, preset)?;
    }
    if let Some(p) = &args.params {
        for name in names.iter().filter(|n| !file.has(n)) {
            errln!("{}: no [{name}] table, defaults used", p.display());
        }
        let used: Vec<&str> = names.iter().map(String::as_str).collect();
        super::note_unused_tables(Some(p), &used, "bench")?;
    }
    // The classic extractors get the simulated sensor's noise: their noise thresholds are
    // scaled from the noise their defaults were chosen for (hough-split estimates its own).
    let scale = noise_scale(args)?;
    let mut extractors: Vec<Box<dyn LineExtractor + Send>> = names
        .iter()
        .map(|n| file.extractor_for_noise(n, scale))
        .collect::<Result<_, _>>()?;
    let (source, scans) = load_scans(args, args.seed.unwrap_or(TEST_SEED))?;
    let source = if scale == 1.0 {
        source
    } else {
        format!("{source}; noise thresholds of the other extractors scaled by {scale:.1}")
    };
    if scans.is_empty() {
        bail!("no scans to run on ({source})");
    }
    let progress = progress_bar(scans.len() as u64);
    let options = BenchOptions {
        repeat: args.repeat,
        matching: matching(args),
        ..BenchOptions::default()
    };
    let report = laserlines_eval::run(&source, &scans, &mut extractors, &options, &mut |k| {
        progress.set_position(k as u64)
    });
    progress.finish_and_clear();

    outln!("{source}\n");
    out!("{}", report.to_markdown());
    let ratio = report.speed_ratio(FAST, BASELINE);
    outln!();
    match (ratio, report.get(FAST), report.get(BASELINE)) {
        (Some(r), Some(f), Some(b)) => outln!(
            "{FAST} is {:.1} times faster than {BASELINE} in this run (median {:.1} us vs {:.0} us per scan; median of per-scan ratios {:.1}), one thread.",
            r.of_medians,
            f.speed.median_us_per_scan,
            b.speed.median_us_per_scan,
            r.median_of_ratios
        ),
        _ => outln!("speed ratio {FAST} / {BASELINE}: not measured (select both to measure it)"),
    }
    write_outputs(&args.output, &report, ratio)?;
    errln!(
        "wrote {}, {} and {}",
        args.output.join("results.json").display(),
        args.output.join("results.csv").display(),
        args.output.join("accuracy-speed.svg").display()
    );
    Ok(())
}

/// The algorithm names of `--algorithms`.
fn selected(list: &str) -> Result<Vec<String>> {
    if list.trim() == "all" {
        return Ok(ALGORITHMS.iter().map(|s| (*s).to_string()).collect());
    }
    let mut out: Vec<String> = Vec::new();
    for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        if !ALGORITHMS.contains(&name) {
            bail!(
                "unknown algorithm {name:?}: expected all or a comma-separated list of {}",
                ALGORITHMS.join(", ")
            );
        }
        if !out.iter().any(|o| o == name) {
            out.push(name.to_string());
        }
    }
    if out.is_empty() {
        bail!("--algorithms: no algorithm given");
    }
    Ok(out)
}

/// The scans to run on and a description of them.
/// The factor from the noise the classic extractors were tuned for to the simulated sensor's
/// (1 on real logs, whose noise is the sensor's own).
fn noise_scale(args: &BenchArgs) -> Result<f64> {
    if !args.data.is_empty() {
        return Ok(1.0);
    }
    Ok(simulated_sensor(args)?.noise_scale())
}

/// The sensor's name, and the share of spurious returns when there are any.
fn sensor_text(args: &BenchArgs) -> String {
    if args.spurious > 0.0 {
        format!(
            "{} with {} of the beams spurious",
            args.sensor, args.spurious
        )
    } else {
        args.sensor.clone()
    }
}

fn simulated_sensor(args: &BenchArgs) -> Result<laserlines_eval::workload::Sensor> {
    let mut s = sensor(&args.sensor).ok_or_else(|| {
        anyhow!(
            "unknown sensor {:?}: expected one of {}",
            args.sensor,
            SENSORS.join(", ")
        )
    })?;
    if !(0.0..=1.0).contains(&args.spurious) {
        bail!(
            "--spurious {}: expected a share of the beams from 0 to 1",
            args.spurious
        );
    }
    s.spurious = args.spurious;
    Ok(s)
}

/// Most scans per simulated suite (all of them are drawn before the run and held, about
/// 1 GB for the seven suites at this count).
const MAX_SIMULATED_SCANS: usize = 20_000;

fn load_scans(args: &BenchArgs, seed: u64) -> Result<(String, Vec<BenchScan>)> {
    if args.data.is_empty() {
        let suite = args.suite.as_deref().unwrap_or(if args.arenas.is_empty() {
            "all"
        } else {
            ARENAS
        });
        let model = simulated_sensor(args)?;
        let count = args.scans.unwrap_or(DEFAULT_SCANS_PER_SUITE);
        if !(1..=MAX_SIMULATED_SCANS).contains(&count) {
            // The scans are drawn and held before the run: bounded, so memory is.
            bail!(
                "--scans must be from 1 to {MAX_SIMULATED_SCANS} per simulated suite, got {count}"
            );
        }
        if suite == ARENAS {
            return arena_suite(args, seed, count, &model);
        }
        if suite != laserlines_sim::scenes::ALL && !laserlines_sim::scenes::SUITES.contains(&suite)
        {
            bail!(
                "unknown scene suite {suite:?}; known suites: {}, {}, {ARENAS}",
                laserlines_sim::scenes::SUITES.join(", "),
                laserlines_sim::scenes::ALL
            );
        }
        if !args.arenas.is_empty() {
            bail!("--arenas needs --suite arenas, not --suite {suite}");
        }
        let scans = suite_scans(suite, seed, count, &model)?;
        let source = format!(
            "suite {suite}, seed {seed}, {count} scans per suite, sensor {}",
            sensor_text(args)
        );
        return Ok((source, scans));
    }
    if args.scans == Some(0) {
        bail!("--scans must be at least 1 (at most this many scans of each log), got 0");
    }
    let mut all = Vec::new();
    let mut parts = Vec::new();
    for path in &args.data {
        // Any input `extract` reads: MCAP and ROS 2 bags too.
        let reader = laserlines_foxglove::open_scans(path, &laserlines_io::ReadOptions::default())?;
        let limit = args.scans.unwrap_or(usize::MAX);
        let mut scans = Vec::new();
        for record in reader.take(limit) {
            scans.push(record?.scan);
        }
        let group = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        parts.push(format!(
            "{group} ({})",
            super::count(scans.len() as u64, "scan")
        ));
        all.extend(plain_scans(&group, scans));
    }
    Ok((format!("data: {}", parts.join(", ")), all))
}

/// The suite of scenes inside arenas.
const ARENAS: &str = "arenas";

/// `--suite arenas`: `count` scans in each arena of `--arenas` (default: the bundled ones).
fn arena_suite(
    args: &BenchArgs,
    seed: u64,
    count: usize,
    sensor: &laserlines_eval::workload::Sensor,
) -> Result<(String, Vec<BenchScan>)> {
    let names: Vec<String> = if args.arenas.is_empty() {
        arenas::BUNDLED
            .iter()
            .map(|(n, _)| (*n).to_string())
            .collect()
    } else {
        args.arenas.clone()
    };
    let mut loaded = Vec::with_capacity(names.len());
    for name in &names {
        loaded.push(arenas::load(name, &ArenaOptions::default())?);
    }
    let (scans, counts) = arena_scans_counted(&loaded, seed, count, sensor);
    // An arena with little free floor gives fewer.
    let mut listed = Vec::with_capacity(loaded.len());
    for (arena, &got) in loaded.iter().zip(&counts) {
        if got == 0 && count > 0 {
            errln!(
                "warning: {}: no free floor inside it was found, no scans",
                arena.name
            );
        }
        listed.push(format!("{} ({got})", arena.name));
    }
    let source = format!(
        "suite arenas ({}), seed {seed}, up to {count} scans per arena, sensor {}",
        listed.join(", "),
        sensor_text(args)
    );
    Ok((source, scans))
}

fn progress_bar(len: u64) -> ProgressBar {
    if io::stderr().is_terminal() {
        let pb = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
        pb.set_style(
            ProgressStyle::with_template("{bar:40} {pos}/{len} scans {elapsed} (eta {eta})")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        pb
    } else {
        ProgressBar::hidden()
    }
}

/// The JSON document: the report and the measured speed ratio.
#[derive(Serialize)]
struct JsonOutput<'a> {
    #[serde(flatten)]
    report: &'a BenchReport,
    /// How many times faster hough-split is than iterative-hough in this run.
    hough_split_vs_iterative_hough: Option<SpeedRatio>,
}

fn write(path: &Path, text: &str) -> Result<()> {
    fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

fn write_outputs(dir: &Path, report: &BenchReport, ratio: Option<SpeedRatio>) -> Result<()> {
    super::create_output_dir(dir)?;
    let json = serde_json::to_string_pretty(&JsonOutput {
        report,
        hough_split_vs_iterative_hough: ratio,
    })?;
    write(&dir.join("results.json"), &(json + "\n"))?;
    write(&dir.join("results.csv"), &report.to_csv())?;
    write(&dir.join("accuracy-speed.svg"), &chart(report).to_svg())
}

/// Accuracy against speed, one point per extractor, log-scale time.
fn chart(report: &BenchReport) -> ScatterChart {
    let truth = report.overall.iter().all(|m| m.truth.is_some());
    let y_label = if truth {
        "F1 of TP rate and 1 - FP rate [%]"
    } else {
        "valid points explained by lines [%]"
    };
    let mut c = ScatterChart::new(
        format!("Accuracy against speed ({})", report.source),
        "median time per scan [us], one thread (log scale)",
        y_label,
    );
    c.log_x = true;
    for m in &report.overall {
        let y = match m.truth {
            Some(t) if truth => t.f1,
            _ => m.explained_fraction,
        };
        c.add(m.speed.median_us_per_scan, 100.0 * y, m.algorithm.clone());
    }
    c
}

/// `--tune`: the coordinate search on the training suite.
fn tune(args: &BenchArgs, algorithm: &str) -> Result<()> {
    if !ALGORITHMS.contains(&algorithm) {
        bail!(
            "unknown algorithm {algorithm:?}: expected one of {}",
            ALGORITHMS.join(", ")
        );
    }
    let (source, scans) = load_scans(args, args.seed.unwrap_or(TRAIN_SEED))?;
    errln!("tuning {algorithm} on {source}");
    let result = laserlines_eval::tune(algorithm, &scans, &matching(args), &mut |line| {
        errln!("  {line}")
    })?;
    let (a, b) = (&result.start_metrics, &result.chosen_metrics);
    outln!(
        "# {algorithm} tuned on {source}: {} parameter sets evaluated",
        result.evaluations
    );
    outln!(
        "# F1 {:.4} -> {:.4}, TP rate {:.4} -> {:.4}, FP rate {:.4} -> {:.4}",
        a.f1,
        b.f1,
        a.true_positive_rate,
        b.true_positive_rate,
        a.false_positive_rate,
        b.false_positive_rate
    );
    for (from, to) in result.changed() {
        outln!("# {}: {} -> {}", to.name, from.value, to.value);
    }
    out!("{}", result.to_toml());
    Ok(())
}
