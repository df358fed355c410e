//! `laserlines convert`: scans from one format into another, without extracting lines.

use std::path::PathBuf;

use anyhow::{Result, anyhow};
use clap::Args;
use laserlines_foxglove::ScanOutput;
use laserlines_io::Format;

use crate::InputArgs;

/// Arguments of `laserlines convert`.
#[derive(Debug, Args)]
pub struct ConvertArgs {
    #[command(flatten)]
    input: InputArgs,
    /// Output file: .mcap (Foxglove: /scan, and /tf when the input has poses), .parquet (one
    /// row per scan), .json, .jsonl or .csv (optionally .gz); `-` for stdout with --to.
    output: PathBuf,
    /// Output format, overriding the extension (json, jsonl, csv, mcap, parquet).
    #[arg(long)]
    to: Option<String>,
    /// Count and skip bad records (reported in the summary) instead of stopping at the first.
    #[arg(long)]
    skip_bad: bool,
}

/// Runs the command.
pub fn run(args: &ConvertArgs) -> Result<()> {
    let to = match &args.to {
        Some(name) => Some(Format::from_name(name).ok_or_else(|| {
            anyhow!(
                "unknown output format {name:?}: expected one of json, jsonl, csv, mcap, parquet"
            )
        })?),
        None => None,
    };
    let mut reader = super::open_input(&args.input)?;
    let mut sink = ScanOutput::create(&args.output, to)?;
    let mut scans = 0u64;
    for item in reader.by_ref() {
        let record = match item {
            Ok(r) => r,
            Err(e) if args.skip_bad => {
                // The reader counts it under its reason for the summary.
                eprintln!("laserlines: skipped: {e}");
                continue;
            }
            Err(e) => return Err(e.into()),
        };
        sink.write(&record)?;
        scans += 1;
    }
    sink.close()?;
    eprintln!(
        "{}: {scans} scans written to {}, skipped: {}",
        reader.name(),
        args.output.display(),
        reader.skipped()
    );
    Ok(())
}
