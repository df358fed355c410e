//! `laserlines extract`: lines of every scan, one JSON object per scan, in input order.
//!
//! The work flows through bounded batches of [`BATCH`] records, so that memory stays flat on
//! any log and every core is busy:
//!
//! - one pool thread reads the input and hands each batch to the pool as one task (the
//!   records still unparsed where the format allows it: [`laserlines_io::Pending`]); when
//!   enough batches wait, it extracts one itself;
//! - pool threads parse the records, extract their lines (one extractor per thread) and
//!   encode each scan's JSON line;
//! - this thread puts the finished batches back in input order, numbers the scans and writes
//!   them.
//!
//! At most [`IN_FLIGHT`] batches per thread are read, extracted or waiting to be written at
//! any time: the reader waits for a finished batch to be written before reading one more.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc::{Receiver, Sender, SyncSender, TryRecvError, channel, sync_channel};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;
use indicatif::ProgressBar;
use laserlines::{Line, LineExtractor, RangeNoise};
use laserlines_foxglove::LinesOutput;
use laserlines_io::{Pending, ReadError, ScanReader, ScanRecord, SkipCounts, encode_unnumbered};
use rayon::Yield;

use crate::InputArgs;

/// Records per batch.
pub const BATCH: usize = 64;
/// Batches in flight per extraction thread.
pub const IN_FLIGHT: usize = 4;

/// Arguments of `laserlines extract`.
#[derive(Debug, Args)]
pub struct ExtractArgs {
    #[command(flatten)]
    input: InputArgs,
    /// Output: lines JSONL (`.jsonl`, `.jsonl.gz` compressed; `-` for stdout), `.mcap` for
    /// Foxglove (scan, lines and pose), or `.parquet` (one row per line).
    #[arg(short, long, default_value = "-")]
    output: PathBuf,
    /// Line extraction algorithm.
    #[arg(long, default_value = "hough-split", value_parser = super::algorithm_parser())]
    algorithm: String,
    #[command(flatten)]
    params: super::ParamsArgs,
    /// Count and skip bad records (reported in the summary) instead of stopping at the first.
    /// A failed read of the input itself (an I/O error, a corrupt gzip stream) still ends the
    /// run with an error.
    #[arg(long)]
    skip_bad: bool,
    /// Extraction threads, 1 to 256 (default: one per core). The output is the same for any
    /// number.
    #[arg(short, long, allow_negative_numbers = true)]
    jobs: Option<i64>,
}

/// A record or the error in its place.
type Item = Result<ScanRecord, ReadError>;

/// One extractor per pool thread.
type Extractors = Vec<Mutex<Box<dyn LineExtractor + Send>>>;

/// One record on its way: as read, then parsed, with its lines and its JSON line (without
/// the scan number, known only when writing).
struct Slot {
    pending: Option<Pending>,
    /// Its parsing was left to the pool: its error is not in the reader's skip counts.
    deferred: bool,
    item: Option<Item>,
    lines: Vec<Line>,
    encoded: Vec<u8>,
    /// The noise the extractor assumed for this scan, if it models one.
    noise: Option<RangeNoise>,
}

/// A batch on its way through the pipeline: its place in the input and its records.
struct Batch {
    seq: u64,
    slots: Vec<Slot>,
}

/// Counts for the summary.
#[derive(Default)]
struct Totals {
    scans: u64,
    lines: u64,
    /// The run stopped at a record of the input (a bad record, a failed read), not at its
    /// output.
    input_stopped: bool,
    /// Errors of records parsed by the pool, by reason.
    skipped: SkipCounts,
    /// Sums of the assumed noise's `sigma_min` and `fraction`, and the scans they cover.
    noise: (f64, f64, u64),
}

/// Most extraction threads `--jobs` takes: more only add threads that wait.
pub const MAX_JOBS: usize = 256;

/// Runs the command.
pub fn run(args: &ExtractArgs) -> Result<()> {
    let (jobs, pool) = extraction_pool(args.jobs)?;
    super::refuse_same_file(&args.input.input, &args.output)?;
    super::output_folder_exists(&args.output)?;
    super::note_unused_tables(args.params.file_path(), &[&args.algorithm], "extract")?;
    let extractors: Extractors = (0..jobs)
        .map(|_| super::make_extractor(&args.algorithm, &args.params).map(Mutex::new))
        .collect::<Result<_>>()?;
    let reader = super::open_input(&args.input)?;
    let name = reader.name().to_owned();
    let input_bytes = input_size(&args.input.input);
    let mut writer = LinesOutput::create(&args.output)?;
    let encode = matches!(writer, LinesOutput::Jsonl(_));
    let progress = super::scan_spinner("");
    let start = Instant::now();

    let (tokens, finished, reader_back) = start_reader(reader, &pool, extractors, encode, jobs)?;
    let mut totals = Totals::default();
    let order = InOrder {
        finished,
        tokens,
        skip_bad: args.skip_bad,
        progress: &progress,
    };
    let written = order.write(&mut writer, &mut totals);
    // The lines of every scan before an error stay readable: the output is closed either way
    // (a Parquet file gets its footer, an MCAP its summary, a gzip stream its end).
    let closed = writer.close().map_err(anyhow::Error::from);
    progress.finish_and_clear();
    if totals.scans == 0 {
        // Nothing was extracted: no output file stands beside the error as if it were one.
        super::remove_own_output(&args.output);
    }
    let pipe = |r: Option<&anyhow::Error>| r.is_some_and(super::is_broken_pipe);
    if pipe(written.as_ref().err()) || pipe(closed.as_ref().err()) {
        // Its reader stopped early (`| head`): not an error, and the summary says so.
        errln!(
            "{name}: standard output closed by its reader after {} with {}, in {:.2} s",
            super::count(totals.scans, "scan"),
            super::count(totals.lines, "line"),
            start.elapsed().as_secs_f64()
        );
        return Ok(());
    }
    // What was written before an error, then the error itself (from `main`).
    let stopped = |done: &str| {
        errln!(
            "{name}: {} with {} {done}, in {:.2} s",
            super::count(totals.scans, "scan"),
            super::count(totals.lines, "line"),
            start.elapsed().as_secs_f64()
        );
    };
    let waiting = match written {
        Ok(waiting) => waiting,
        Err(e) => {
            // A bad record leaves the scans before it in a closed output; an output that
            // failed (a full disk) may hold none of them.
            stopped(if totals.input_stopped && closed.is_ok() {
                "written before the error"
            } else {
                "extracted before the output failed"
            });
            return Err(e);
        }
    };
    if let Err(e) = closed {
        // Every write went into the buffers and the output failed as they were flushed (a
        // full disk under a short run).
        stopped("extracted before the output failed");
        return Err(e);
    }
    anyhow::ensure!(
        waiting.is_empty(),
        "internal error: {} batches were extracted but never written",
        waiting.len()
    );
    let reader = reader_back
        .recv()
        .map_err(|_| anyhow::anyhow!("internal error: the reader did not come back"))?;
    let mut skipped = reader.skipped().clone();
    skipped.merge(&totals.skipped);
    summary(
        &name,
        &skipped,
        &totals,
        input_bytes,
        start.elapsed().as_secs_f64(),
    );
    if totals.scans == 0 {
        return Err(super::no_scans(&name, &skipped));
    }
    Ok(())
}

/// The number of extraction threads `--jobs` asks for (default: one per core) and their pool.
fn extraction_pool(jobs: Option<i64>) -> Result<(usize, rayon::ThreadPool)> {
    let jobs = match jobs {
        Some(n) => usize::try_from(n)
            .ok()
            .filter(|n| (1..=MAX_JOBS).contains(n))
            .ok_or_else(|| anyhow::anyhow!("--jobs must be from 1 to {MAX_JOBS}, got {n}"))?,
        None => std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .thread_name(|i| format!("extract-{i}"))
        .build()
        .context("cannot start the extraction threads")?;
    Ok((jobs, pool))
}

/// The reading side of the pipeline, run on one pool thread.
struct ReadLoop {
    reader: ScanReader,
    extractors: Arc<Extractors>,
    encode: bool,
    jobs: usize,
    tokens: Receiver<()>,
    finished: Sender<Batch>,
    /// Batches handed to the pool and not yet started.
    waiting: Arc<AtomicUsize>,
}

impl ReadLoop {
    /// Reads batches and hands each to the pool, while a token allows one more batch in flight.
    /// When enough batches wait (or no token is left), this thread extracts one of them
    /// instead, so that reading is never starved of a core and no core idles.
    fn run(mut self) -> ScanReader {
        let mut seq = 0u64;
        loop {
            if self.waiting.load(Ordering::Acquire) > self.jobs
                && rayon::yield_now() == Some(Yield::Executed)
            {
                continue;
            }
            let token = match self.tokens.try_recv() {
                Ok(()) => true,
                Err(TryRecvError::Empty) => {
                    if rayon::yield_now() == Some(Yield::Executed) {
                        continue;
                    }
                    // Nothing to extract here: wait for the writer to make room.
                    self.tokens.recv().is_ok()
                }
                Err(TryRecvError::Disconnected) => false,
            };
            if !token {
                break; // the writer stopped
            }
            let slots: Vec<Slot> = std::iter::from_fn(|| self.reader.next_pending())
                .take(BATCH)
                .map(|pending| Slot {
                    deferred: matches!(pending, Pending::Deferred(_)),
                    pending: Some(pending),
                    item: None,
                    lines: Vec::new(),
                    noise: None,
                    encoded: Vec::new(),
                })
                .collect();
            if slots.is_empty() {
                break;
            }
            let mut batch = Batch { seq, slots };
            seq += 1;
            let extractors = Arc::clone(&self.extractors);
            let (finished, waiting) = (self.finished.clone(), Arc::clone(&self.waiting));
            let encode = self.encode;
            waiting.fetch_add(1, Ordering::AcqRel);
            rayon::spawn_fifo(move || {
                waiting.fetch_sub(1, Ordering::AcqRel);
                extract_batch(&extractors, &mut batch, encode);
                // The writer may have stopped on an error: nothing more to do then.
                let _ = finished.send(batch);
            });
        }
        // Extract what still waits (with one thread, nobody else will).
        while rayon::yield_now() == Some(Yield::Executed) {}
        self.reader
    }
}

/// Starts the reading loop on a pool thread. Returns the sender of tokens (one per written
/// batch: the reader may read one more), the receiver of extracted batches, and the receiver
/// of the reader at the end (for its skip counts).
fn start_reader(
    reader: ScanReader,
    pool: &rayon::ThreadPool,
    extractors: Extractors,
    encode: bool,
    jobs: usize,
) -> Result<(SyncSender<()>, Receiver<Batch>, Receiver<ScanReader>)> {
    let in_flight = IN_FLIGHT * jobs;
    let (token_tx, token_rx) = sync_channel::<()>(in_flight);
    for _ in 0..in_flight {
        token_tx
            .send(())
            .context("cannot start the extraction pipeline")?;
    }
    let (finished_tx, finished_rx) = channel::<Batch>();
    let (back_tx, back_rx) = sync_channel::<ScanReader>(1);
    let read_loop = ReadLoop {
        reader,
        extractors: Arc::new(extractors),
        encode,
        jobs,
        tokens: token_rx,
        finished: finished_tx,
        waiting: Arc::new(AtomicUsize::new(0)),
    };
    pool.spawn(move || {
        let reader = read_loop.run();
        let _ = back_tx.send(reader);
    });
    Ok((token_tx, finished_rx, back_rx))
}

/// Parses, extracts and encodes every record of a batch, on the calling pool thread with its
/// own extractor.
///
/// A batch is one task: the parallelism comes from the batches in flight. (Splitting a batch
/// further with rayon would let a thread that waits for its other half run whole later
/// batches meanwhile, so that batches finish out of order and the in-order writer waits.)
fn extract_batch(extractors: &Extractors, batch: &mut Batch, encode: bool) {
    let index = rayon::current_thread_index().unwrap_or(0) % extractors.len();
    // Each pool thread takes its own extractor: the lock is never contended. A poisoned lock
    // means an extractor panicked, which ends the process anyway.
    let mut extractor = extractors[index]
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    for slot in &mut batch.slots {
        let Some(pending) = slot.pending.take() else {
            continue;
        };
        let item = pending.parse();
        if let Ok(record) = &item {
            extractor.extract_into(&record.scan, &mut slot.lines);
            slot.noise = extractor.range_noise();
            slot.encoded.clear();
            // Encoding into memory cannot fail; should it, the writer encodes again.
            if encode && encode_unnumbered(record, &slot.lines, &mut slot.encoded).is_err() {
                slot.encoded.clear();
            }
        }
        slot.item = Some(item);
    }
}

/// The finished batches and what writing them in input order needs.
struct InOrder<'a> {
    finished: Receiver<Batch>,
    tokens: SyncSender<()>,
    skip_bad: bool,
    progress: &'a ProgressBar,
}

impl InOrder<'_> {
    /// Writes the batches in input order as they finish; returns those never written (none
    /// unless something went wrong). Ends when the reader thread and every extraction task
    /// are done (all senders dropped); on an error it returns, and dropping the receiver
    /// ends the reader thread.
    fn write(self, writer: &mut LinesOutput, totals: &mut Totals) -> Result<BTreeMap<u64, Batch>> {
        let mut waiting: BTreeMap<u64, Batch> = BTreeMap::new();
        let mut next = 0u64;
        for batch in self.finished {
            waiting.insert(batch.seq, batch);
            while let Some(batch) = waiting.remove(&next) {
                write_batch(writer, batch, self.skip_bad, self.progress, totals)?;
                next += 1;
                // The reader may read one more batch; it may also be done already.
                let _ = self.tokens.send(());
            }
        }
        Ok(waiting)
    }
}

/// Writes a batch in input order, numbering its scans; reports or returns its errors.
fn write_batch(
    writer: &mut LinesOutput,
    batch: Batch,
    skip_bad: bool,
    progress: &ProgressBar,
    totals: &mut Totals,
) -> Result<()> {
    let count = batch.slots.len() as u64;
    for slot in batch.slots {
        let record = match slot.item {
            Some(Ok(record)) => record,
            Some(Err(e)) => {
                if slot.deferred && e.is_bad_record() {
                    // The reader counted the others.
                    totals.skipped.add(e.reason());
                }
                if !super::skips(skip_bad, &e) {
                    totals.input_stopped = true;
                    return Err(super::read_error(e, skip_bad));
                }
                progress.suspend(|| errln!("laserlines: skipped: {e}"));
                continue;
            }
            None => anyhow::bail!("internal error: a record was never parsed"),
        };
        let scan = totals.scans;
        match &mut *writer {
            LinesOutput::Jsonl(w) if !slot.encoded.is_empty() => {
                w.write_numbered(scan, &slot.encoded)?;
            }
            other => other.write_record(scan, &record, &slot.lines)?,
        }
        totals.scans += 1;
        totals.lines += slot.lines.len() as u64;
        if let Some(n) = slot.noise {
            totals.noise.0 += n.sigma_min;
            totals.noise.1 += n.fraction;
            totals.noise.2 += 1;
        }
    }
    progress.inc(count);
    Ok(())
}

/// Size of the input, bytes: of the file, or of the files of a directory (a ROS 2 bag);
/// `None` for standard input.
pub fn input_size(path: &Path) -> Option<u64> {
    if path == Path::new("-") {
        return None;
    }
    let meta = std::fs::metadata(path).ok()?;
    if !meta.is_dir() {
        return Some(meta.len());
    }
    let files = std::fs::read_dir(path).ok()?;
    Some(
        files
            .filter_map(|e| e.ok()?.metadata().ok())
            .filter(std::fs::Metadata::is_file)
            .map(|m| m.len())
            .sum(),
    )
}

/// The summary on stderr: scans, lines, skips with reasons, speed.
fn summary(name: &str, skipped: &SkipCounts, totals: &Totals, bytes: Option<u64>, secs: f64) {
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
    errln!(
        "{name}: {}, {} ({per_scan:.1} per scan), skipped: {}, {secs:.2} s, {speed}",
        super::count(totals.scans, "scan"),
        super::count(totals.lines, "line"),
        skipped,
    );
    let (s, f, n) = totals.noise;
    if n > 0 {
        let mean = RangeNoise::new(s / n as f64, f / n as f64);
        errln!(
            "{name}: range noise (estimated from each scan unless the parameters give it), \
             mean over the scans: {mean}"
        );
    }
    if totals.scans > 0 && totals.lines == 0 {
        let scans = if totals.scans == 1 {
            "the scan".to_owned()
        } else {
            format!("any of the {} scans", totals.scans)
        };
        errln!(
            "{name}: note: no line in {scans}; if the scans see walls, check the parameters \
             (--params, --preset), the scans' range limits and that the ranges are in metres"
        );
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::input_size;

    #[test]
    fn the_size_of_a_directory_input_is_that_of_its_files() {
        let dir = std::env::temp_dir().join(format!("laserlines-size-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        std::fs::write(dir.join("bag_0.db3"), vec![0u8; 3000]).unwrap();
        std::fs::write(dir.join("metadata.yaml"), vec![0u8; 500]).unwrap();
        std::fs::write(dir.join("sub/other"), vec![0u8; 7000]).unwrap();
        assert_eq!(input_size(&dir), Some(3500));
        assert_eq!(input_size(&dir.join("bag_0.db3")), Some(3000));
        assert_eq!(input_size(std::path::Path::new("-")), None);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
