//! `laserlines extract`: lines of every scan, one JSON object per scan, in input order.
//!
//! The work runs as a pipeline over bounded batches of [`BATCH`] records, so that memory
//! stays flat on any log and every core is busy:
//!
//! - a reader thread parses the input and hands over batches (at most [`QUEUED`] wait);
//! - the batch is extracted on a rayon pool, one extractor per pool thread, each scan's JSON
//!   line encoded there too;
//! - meanwhile this thread writes the previous batch, in input order.

use std::io::{self, IsTerminal};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::mpsc::{Receiver, sync_channel};
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use laserlines::{Line, LineExtractor};
use laserlines_foxglove::LinesOutput;
use laserlines_io::{ReadError, ScanReader, ScanRecord, encode_lines};
use rayon::prelude::*;

use crate::InputArgs;

/// Records per batch.
pub const BATCH: usize = 256;
/// Batches read ahead of the one being extracted.
pub const QUEUED: usize = 2;

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
    /// Extraction threads (default: one per core). The output is the same for any number.
    #[arg(short, long)]
    jobs: Option<usize>,
}

/// What the reader hands over: records and errors, in input order.
type Item = Result<ScanRecord, ReadError>;

/// The result of one record: its number among the scans, its lines, its encoded JSON line.
#[derive(Default)]
struct Slot {
    scan: u64,
    lines: Vec<Line>,
    encoded: Vec<u8>,
}

/// A batch on its way through the pipeline.
struct Batch {
    items: Vec<Item>,
    slots: Vec<Slot>,
}

/// Counts for the summary.
#[derive(Default)]
struct Totals {
    scans: u64,
    lines: u64,
}

/// Runs the command.
pub fn run(args: &ExtractArgs) -> Result<()> {
    let jobs = match args.jobs {
        Some(0) => anyhow::bail!("--jobs must be at least 1"),
        Some(n) => n,
        None => std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .thread_name(|i| format!("extract-{i}"))
        .build()
        .context("cannot start the extraction threads")?;
    let extractors = (0..jobs)
        .map(|_| super::make_extractor(&args.algorithm, args.params.as_deref()).map(Mutex::new))
        .collect::<Result<Vec<_>>>()?;
    let reader = super::open_input(&args.input)?;
    let name = reader.name().to_owned();
    let input_bytes = input_size(&args.input.input);
    let mut writer = LinesOutput::create(&args.output)?;
    let encode = matches!(writer, LinesOutput::Jsonl(_));
    let progress = progress_bar();
    let start = Instant::now();

    let (batches, reader_thread) = spawn_reader(reader)?;
    let mut totals = Totals::default();
    let mut next_scan = 0u64;
    let mut pending: Option<Batch> = None;
    let mut spare: Vec<Vec<Slot>> = Vec::new();
    loop {
        let mut next = batches.recv().ok().map(|items| {
            let mut slots = spare.pop().unwrap_or_default();
            slots.resize_with(items.len(), Slot::default);
            slots.truncate(items.len());
            for (slot, item) in slots.iter_mut().zip(&items) {
                if item.is_ok() {
                    slot.scan = next_scan;
                    next_scan += 1;
                }
            }
            Batch { items, slots }
        });
        let mut written = Ok(());
        pool.in_place_scope(|scope| {
            if let Some(batch) = next.as_mut() {
                let extractors = &extractors;
                scope.spawn(move |_| extract_batch(extractors, batch, encode));
            }
            if let Some(done) = pending.take() {
                written = write_batch(
                    &mut writer,
                    done.items,
                    &done.slots,
                    args.skip_bad,
                    &progress,
                    &mut totals,
                );
                spare.push(done.slots);
            }
        });
        // On an error, return: dropping the receiver ends the reader thread.
        written?;
        match next {
            Some(batch) => pending = Some(batch),
            None => break,
        }
    }
    writer.close()?;
    progress.finish_and_clear();
    let reader = reader_thread
        .join()
        .map_err(|_| anyhow::anyhow!("the reader thread panicked"))?;
    summary(
        &name,
        &reader,
        &totals,
        input_bytes,
        start.elapsed().as_secs_f64(),
    );
    Ok(())
}

/// Starts the thread that reads batches of records.
fn spawn_reader(
    mut reader: ScanReader,
) -> Result<(Receiver<Vec<Item>>, std::thread::JoinHandle<ScanReader>)> {
    let (tx, rx) = sync_channel::<Vec<Item>>(QUEUED);
    let handle = std::thread::Builder::new()
        .name("read".to_owned())
        .spawn(move || {
            loop {
                let batch: Vec<Item> = reader.by_ref().take(BATCH).collect();
                if batch.is_empty() || tx.send(batch).is_err() {
                    return reader;
                }
            }
        })
        .context("cannot start the reader thread")?;
    Ok((rx, handle))
}

/// Extracts (and encodes) every record of a batch, in parallel, one extractor per thread.
fn extract_batch(
    extractors: &[Mutex<Box<dyn LineExtractor + Send>>],
    batch: &mut Batch,
    encode: bool,
) {
    batch
        .items
        .par_iter()
        .zip(batch.slots.par_iter_mut())
        .with_min_len(4)
        .for_each(|(item, slot)| {
            let Ok(record) = item else { return };
            let index = rayon::current_thread_index().unwrap_or(0) % extractors.len();
            // Each pool thread takes its own extractor: the lock is never contended. A
            // poisoned lock means an extractor panicked, which ends the process anyway.
            let mut extractor = extractors[index]
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            extractor.extract_into(&record.scan, &mut slot.lines);
            slot.encoded.clear();
            if encode {
                // Encoding into memory cannot fail; should it, the writer re-encodes below.
                if encode_lines(slot.scan, record, &slot.lines, &mut slot.encoded).is_err() {
                    slot.encoded.clear();
                }
            }
        });
}

/// Writes a batch in input order; reports or returns its read errors.
fn write_batch(
    writer: &mut LinesOutput,
    items: Vec<Item>,
    slots: &[Slot],
    skip_bad: bool,
    progress: &ProgressBar,
    totals: &mut Totals,
) -> Result<()> {
    let count = items.len() as u64;
    for (item, slot) in items.into_iter().zip(slots) {
        let record = match item {
            Ok(record) => record,
            Err(e) if skip_bad => {
                // The reader counts it under its reason for the summary.
                progress.suspend(|| eprintln!("laserlines: skipped: {e}"));
                continue;
            }
            Err(e) => return Err(e.into()),
        };
        match &mut *writer {
            LinesOutput::Jsonl(w) if !slot.encoded.is_empty() => w.write_encoded(&slot.encoded)?,
            other => other.write_record(slot.scan, &record, &slot.lines)?,
        }
        totals.scans += 1;
        totals.lines += slot.lines.len() as u64;
    }
    progress.inc(count);
    Ok(())
}

fn progress_bar() -> ProgressBar {
    if io::stderr().is_terminal() {
        let pb = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
        pb.set_style(
            ProgressStyle::with_template("{spinner} {pos} scans {per_sec} {elapsed}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        pb
    } else {
        ProgressBar::hidden()
    }
}

/// Size of the input file, bytes (`None` for standard input).
fn input_size(path: &Path) -> Option<u64> {
    if path == Path::new("-") {
        return None;
    }
    std::fs::metadata(path).ok().map(|m| m.len())
}

/// The summary on stderr: scans, lines, skips with reasons, speed.
fn summary(name: &str, reader: &ScanReader, totals: &Totals, bytes: Option<u64>, secs: f64) {
    let per = |n: f64| if secs > 0.0 { n / secs } else { 0.0 };
    let per_scan = if totals.scans > 0 {
        totals.lines as f64 / totals.scans as f64
    } else {
        0.0
    };
    let speed = match bytes {
        Some(b) => format!(
            "{:.0} scans/s, {:.1} MB/s",
            per(totals.scans as f64),
            per(b as f64) / 1e6
        ),
        None => format!("{:.0} scans/s", per(totals.scans as f64)),
    };
    eprintln!(
        "{name}: {} scans, {} lines ({per_scan:.1} per scan), skipped: {}, {secs:.2} s, {speed}",
        totals.scans,
        totals.lines,
        reader.skipped(),
    );
}
