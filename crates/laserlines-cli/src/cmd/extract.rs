//! `laserlines extract`: lines of every scan, one JSON object per scan, in input order.

use std::io::{self, IsTerminal};
use std::path::PathBuf;
use std::time::Instant;

use anyhow::Result;
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use laserlines::Line;

use crate::InputArgs;

/// Arguments of `laserlines extract`.
#[derive(Debug, Args)]
pub struct ExtractArgs {
    #[command(flatten)]
    input: InputArgs,
    /// Output: lines JSONL (`.gz` compresses; `-` for stdout), or `.mcap` for Foxglove (scan,
    /// lines and pose).
    #[arg(short, long, default_value = "-")]
    output: PathBuf,
    /// Line extraction algorithm.
    #[arg(long, default_value = "hough-split")]
    algorithm: String,
    /// TOML file of parameters (one table per algorithm, e.g. `[hough-split]`).
    #[arg(long)]
    params: Option<PathBuf>,
    /// Count and skip bad records (reported in the summary) instead of stopping at the first.
    #[arg(long)]
    skip_bad: bool,
}

/// Runs the command.
pub fn run(args: &ExtractArgs) -> Result<()> {
    let mut extractor = super::make_extractor(&args.algorithm, args.params.as_deref())?;
    let reader = super::open_input(&args.input)?;
    let mut writer = laserlines_foxglove::LinesOutput::create(&args.output)?;
    let progress = if io::stderr().is_terminal() {
        let pb = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
        pb.set_style(
            ProgressStyle::with_template("{spinner} {pos} scans {per_sec} {elapsed}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        pb
    } else {
        ProgressBar::hidden()
    };
    let start = Instant::now();
    let mut lines: Vec<Line> = Vec::new();
    let mut scans = 0u64;
    let mut total_lines = 0u64;
    let mut reader = reader;
    for item in reader.by_ref() {
        let record = match item {
            Ok(r) => r,
            Err(e) if args.skip_bad => {
                // The reader counts it under its reason for the summary.
                progress.suspend(|| eprintln!("laserlines: skipped: {e}"));
                continue;
            }
            Err(e) => return Err(e.into()),
        };
        extractor.extract_into(&record.scan, &mut lines);
        writer.write_record(scans, &record, &lines)?;
        scans += 1;
        total_lines += lines.len() as u64;
        progress.inc(1);
    }
    writer.close()?;
    progress.finish_and_clear();
    let skipped = reader.skipped();
    let secs = start.elapsed().as_secs_f64();
    eprintln!(
        "{}: {scans} scans, {total_lines} lines ({:.1} per scan), skipped: {skipped}, {:.0} scans/s",
        reader.name(),
        if scans > 0 {
            total_lines as f64 / scans as f64
        } else {
            0.0
        },
        if secs > 0.0 { scans as f64 / secs } else { 0.0 },
    );
    Ok(())
}
