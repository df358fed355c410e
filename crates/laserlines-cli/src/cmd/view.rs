//! `laserlines view`: replay a log with its lines on a Foxglove WebSocket.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use clap::Args;
use laserlines::{Line, LineExtractor};
use laserlines_foxglove::live::{LiveServer, Pacer};
use laserlines_foxglove::scene::SceneClock;
use laserlines_io::{ReadError, ScanReader, ScanRecord};

use crate::InputArgs;

/// Arguments of `laserlines view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    #[command(flatten)]
    input: InputArgs,
    /// Line extraction algorithm.
    #[arg(long, default_value = "hough-split", value_parser = super::algorithm_parser())]
    algorithm: String,
    #[command(flatten)]
    params: super::ParamsArgs,
    /// Replay speed: 1.0 is real time (scan stamps, or 10 scans/s without), 2.0 twice as
    /// fast, 0 as fast as possible. No scan waits longer than 1 s / rate: a jump of the
    /// stamps by more than 1 s counts as 1 s, a step backwards is not waited for (both are
    /// counted in a warning and the summary).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    rate: f64,
    /// Port to serve on, on 127.0.0.1 (0 picks a free one).
    #[arg(long, default_value_t = 8765, value_parser = super::whole::<u16>, allow_negative_numbers = true)]
    port: u16,
    /// Start at once instead of waiting for a viewer to subscribe to /scan.
    #[arg(long)]
    no_wait: bool,
    /// Replay again and again until interrupted (Ctrl-C ends any replay after the scan in
    /// hand, with its summary).
    #[arg(long = "loop")]
    repeat: bool,
    /// Count and skip bad records (reported in the summary) instead of stopping at the first.
    /// A failed read of the input itself (an I/O error, a corrupt gzip stream) still ends the
    /// run with an error.
    #[arg(long)]
    skip_bad: bool,
}

/// Runs the command.
pub fn run(args: &ViewArgs) -> Result<()> {
    if !(args.rate.is_finite() && args.rate >= 0.0) {
        bail!(
            "--rate must be a number >= 0 (0 = as fast as possible), got {}",
            super::compact(args.rate)
        );
    }
    super::note_unused_tables(args.params.file_path(), &[&args.algorithm], "view")?;
    let mut extractor = super::make_extractor(&args.algorithm, &args.params)?;
    // Open and read the first record before serving, so that a bad or empty input fails at
    // once.
    let mut reader = super::open_input(&args.input)?;
    let mut first = match reader.next() {
        None => return Err(super::no_scans(reader.name(), reader.skipped())),
        Some(Err(e)) if !super::skips(args.skip_bad, &e) => {
            return Err(super::read_error(e, args.skip_bad));
        }
        some => some,
    };
    let stop = Arc::new(AtomicBool::new(false));
    let s = stop.clone();
    ctrlc::set_handler(move || s.store(true, Ordering::Relaxed)).context("cannot catch Ctrl-C")?;
    let server = LiveServer::start("127.0.0.1", args.port)?;
    // Both status lines on stderr, like every other status line of laserlines.
    errln!(
        "laserlines: serving ws://127.0.0.1:{} (in Foxglove: Open connection, Foxglove WebSocket)",
        server.port()
    );
    if !args.no_wait {
        errln!("laserlines: waiting for a viewer to subscribe to /scan");
        while !server.wait_for_viewer(Some(Duration::from_millis(100))) {
            if stop.load(Ordering::Relaxed) {
                errln!("laserlines: interrupted before a viewer subscribed");
                server.stop();
                return Ok(());
            }
        }
    }
    loop {
        let replay = Replay {
            server: &server,
            rate: args.rate,
            skip_bad: args.skip_bad,
            stop: &stop,
        };
        let scans = match replay.run(first.take(), &mut reader, &mut *extractor) {
            Ok(scans) => scans,
            Err(e) => {
                server.stop();
                return Err(e);
            }
        };
        let interrupted = stop.load(Ordering::Relaxed);
        if interrupted {
            errln!("laserlines: interrupted");
        }
        if scans == 0 && !interrupted {
            server.stop();
            return Err(super::no_scans(reader.name(), reader.skipped()));
        }
        if !args.repeat || interrupted {
            break;
        }
        reader = super::open_input(&args.input)?;
    }
    // Give the last messages time to leave before the server closes.
    std::thread::sleep(Duration::from_millis(500));
    server.stop();
    Ok(())
}

/// One pass over the input.
struct Replay<'a> {
    server: &'a LiveServer,
    rate: f64,
    skip_bad: bool,
    /// Set by Ctrl-C: the pass ends after the scan in hand.
    stop: &'a AtomicBool,
}

impl Replay<'_> {
    /// Replays `first` (a record already read) and `reader` to its end (or to Ctrl-C), prints
    /// its summary and returns the number of scans replayed. A record that ends the pass
    /// (without `--skip-bad`) is an error, after a summary of what was replayed before it.
    fn run(
        &self,
        first: Option<Result<ScanRecord, ReadError>>,
        reader: &mut ScanReader,
        extractor: &mut dyn LineExtractor,
    ) -> Result<u64> {
        let start = Instant::now();
        let mut clock = SceneClock::new();
        let mut pacer = Pacer::new(self.rate);
        let (mut scans, mut total_lines) = (0u64, 0u64);
        let mut lines: Vec<Line> = Vec::new();
        let mut warned = false;
        let name = reader.name().to_owned();
        for item in first.into_iter().chain(reader.by_ref()) {
            if self.stop.load(Ordering::Relaxed) {
                break;
            }
            let record = match item {
                Ok(r) => r,
                Err(e) if super::skips(self.skip_bad, &e) => {
                    errln!("laserlines: skipped: {e}");
                    continue;
                }
                Err(e) => {
                    errln!(
                        "{name}: {}, {} replayed before the error",
                        super::count(scans, "scan"),
                        super::count(total_lines, "line"),
                    );
                    return Err(super::read_error(e, self.skip_bad));
                }
            };
            extractor.extract_into(&record.scan, &mut lines);
            let time = clock.time_of(record.scan.stamp);
            let wait = pacer.delay(time, Instant::now());
            if !warned && !stamp_notes(&clock, &pacer).is_empty() {
                warned = true;
                errln!(
                    "laserlines: warning: {}: scan {scans} has a stamp that {}; no scan waits \
                     longer than {} s / --rate (counted in the summary)",
                    name,
                    stamp_trouble(&pacer),
                    Pacer::MAX_STEP_S
                );
            }
            nap(wait, self.stop);
            self.server.publish(&record, &lines, time);
            scans += 1;
            total_lines += lines.len() as u64;
        }
        let notes = stamp_notes(&clock, &pacer);
        errln!(
            "{}: {}, {} replayed in {:.1} s, skipped: {}{}",
            reader.name(),
            super::count(scans, "scan"),
            super::count(total_lines, "line"),
            start.elapsed().as_secs_f64(),
            reader.skipped(),
            if notes.is_empty() {
                String::new()
            } else {
                format!(", stamps: {notes}")
            }
        );
        Ok(scans)
    }
}

/// What was wrong with the scans' stamps so far, counted (empty when nothing was).
fn stamp_notes(clock: &SceneClock, pacer: &Pacer) -> String {
    let mut notes = Vec::new();
    if pacer.gaps() > 0 {
        let gaps = super::count(pacer.gaps(), "gap");
        notes.push(format!("{gaps} over {} s", Pacer::MAX_STEP_S));
    }
    if pacer.backward_steps() > 0 {
        notes.push(super::count(pacer.backward_steps(), "backward step"));
    }
    if clock.unusable() > 0 {
        let unusable = super::count(clock.unusable(), "unusable stamp");
        notes.push(format!("{unusable} (paced 0.1 s apart)"));
    }
    notes.join(", ")
}

/// The first trouble with the stamps, in words, for the warning.
fn stamp_trouble(pacer: &Pacer) -> String {
    if pacer.gaps() > 0 {
        format!("jumps ahead by more than {} s", Pacer::MAX_STEP_S)
    } else if pacer.backward_steps() > 0 {
        "steps backwards".to_owned()
    } else {
        "is not usable (not finite, negative, or 2^32 s and more): such scans are paced 0.1 s \
         apart"
            .to_owned()
    }
}

/// Sleeps for `d` (however long: `Duration::MAX` at a rate near 0), in slices of 50 ms,
/// ending early when `stop` is set.
fn nap(d: Duration, stop: &AtomicBool) {
    let start = Instant::now();
    loop {
        let left = d.saturating_sub(start.elapsed());
        if left.is_zero() || stop.load(Ordering::Relaxed) {
            return;
        }
        std::thread::sleep(left.min(Duration::from_millis(50)));
    }
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::AtomicBool;
    use std::time::Duration;

    use super::nap;

    #[test]
    fn a_nap_of_any_length_ends_when_stopped() {
        // At `--rate 1e-300` a scan's wait is `Duration::MAX`, past any `Instant`.
        nap(Duration::MAX, &AtomicBool::new(true));
        nap(Duration::from_millis(1), &AtomicBool::new(false));
    }
}
