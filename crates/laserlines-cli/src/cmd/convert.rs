//! `laserlines convert`: scans from one format into another, without extracting lines.

use std::path::{Path, PathBuf};

use anyhow::{Result, anyhow, bail};
use clap::Args;
use laserlines_foxglove::ScanOutput;
use laserlines_io::Format;

use crate::InputArgs;

/// The formats `convert` writes.
const WRITTEN: &str = "json, jsonl, csv, mcap, parquet";

/// Arguments of `laserlines convert`.
#[derive(Debug, Args)]
pub struct ConvertArgs {
    #[command(flatten)]
    input: InputArgs,
    /// Output file: .mcap (Foxglove: /scan, and /tf when the input has poses), .parquet (one
    /// row per scan), .json (one scan, or an array of them), .jsonl, or .csv (one scan per
    /// file); .json, .jsonl and .csv optionally .gz; `-` for stdout with --to (not for MCAP or
    /// Parquet, which are files).
    output: PathBuf,
    /// Output format, overriding the extension (json, jsonl, csv, mcap, parquet).
    #[arg(long)]
    to: Option<String>,
    /// Convert only scan K (0-based, counting the scans read, as `render --scan` does): one
    /// scan of a log for a format that holds one (.csv), or a single object rather than an
    /// array (.json).
    #[arg(long, value_name = "K")]
    scan: Option<usize>,
    /// Count and skip bad records (reported in the summary) instead of stopping at the first.
    /// A failed read of the input itself (an I/O error, a corrupt gzip stream) still ends the
    /// run with an error.
    #[arg(long)]
    skip_bad: bool,
}

/// Runs the command. On an error, a file it was writing is removed: a partial conversion
/// would pass for a whole one.
pub fn run(args: &ConvertArgs) -> Result<()> {
    let to = output_format(args)?;
    super::refuse_same_file(&args.input.input, &args.output)?;
    super::output_folder_exists(&args.output)?;
    let mut reader = super::open_input(&args.input)?;
    let mut sink = ScanOutput::create(&args.output, Some(to))?;
    let mut scans = 0u64;
    // Scans read, for `--scan`.
    let mut read = 0usize;
    let written = (|| -> Result<()> {
        for item in reader.by_ref() {
            let record = match item {
                Ok(r) => r,
                Err(e) if super::skips(args.skip_bad, &e) => {
                    // The reader counts it under its reason for the summary.
                    errln!("laserlines: skipped: {e}");
                    continue;
                }
                Err(e) => return Err(super::read_error(e, args.skip_bad)),
            };
            read += 1;
            if args.scan.is_some_and(|k| k != read - 1) {
                continue;
            }
            sink.write(&record).map_err(|e| one_scan_hint(e.into()))?;
            scans += 1;
            if args.scan.is_some() {
                break;
            }
        }
        sink.close()?;
        if let (Some(k), 0) = (args.scan, scans) {
            bail!(
                "{}: has no scan {k} (it holds {})",
                reader.name(),
                super::count(read as u64, "scan")
            );
        }
        if scans == 0 {
            return Err(super::no_scans(reader.name(), reader.skipped()));
        }
        Ok(())
    })();
    if let Err(e) = written {
        remove_partial(&args.output);
        return Err(e);
    }
    errln!(
        "{}: {} written to {}, skipped: {}",
        reader.name(),
        super::count(scans, "scan"),
        args.output.display(),
        reader.skipped()
    );
    Ok(())
}

/// `e`, with the way out when it is a second scan for a format of one scan per file.
fn one_scan_hint(e: anyhow::Error) -> anyhow::Error {
    let one_per_file = e.chain().any(|c| {
        matches!(
            c.downcast_ref::<laserlines_io::WriteError>(),
            Some(laserlines_io::WriteError::OneScanPerFile { .. })
        )
    });
    if one_per_file {
        anyhow!(
            "{} (--scan K converts one scan of the log; .json, .jsonl, .mcap and .parquet hold them all)",
            laserlines_io::error_chain(e.as_ref())
        )
    } else {
        e
    }
}

/// The output format: `--to`, or told from the output's name.
fn output_format(args: &ConvertArgs) -> Result<Format> {
    let format = match &args.to {
        Some(name) => Format::from_name(name)
            .ok_or_else(|| anyhow!("unknown output format {name:?}: expected one of {WRITTEN}"))?,
        None => Format::from_path(&args.output).ok_or_else(|| {
            anyhow!(
                "{}: cannot tell the output format from the name; expected a name ending in \
                 .mcap, .parquet, .json, .jsonl, .ndjson or .csv (the last four optionally \
                 followed by .gz), or --to FORMAT (one of {WRITTEN})",
                args.output.display()
            )
        })?,
    };
    if !(matches!(format, Format::Mcap | Format::Parquet) || format.is_writable()) {
        bail!(
            "{}: convert does not write the {format} format; it writes {WRITTEN}",
            args.output.display()
        );
    }
    Ok(format)
}

/// Removes the output of a failed conversion when it is a regular file
/// ([`super::remove_own_output`]).
fn remove_partial(path: &Path) {
    if super::remove_own_output(path) {
        errln!(
            "laserlines: removed the partial {} (the conversion failed)",
            path.display()
        );
    }
}
