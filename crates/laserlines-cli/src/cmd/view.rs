//! `laserlines view`: replay a log with its lines on a Foxglove WebSocket.

use std::time::{Duration, Instant};

use anyhow::{Result, bail};
use clap::Args;
use laserlines::Line;
use laserlines_foxglove::live::{LiveServer, Pacer};
use laserlines_foxglove::scene::SceneClock;

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
    /// fast, 0 as fast as possible.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    rate: f64,
    /// Port to serve on, on 127.0.0.1 (0 picks a free one).
    #[arg(long, default_value_t = 8765)]
    port: u16,
    /// Start at once instead of waiting for a viewer to subscribe to /scan.
    #[arg(long)]
    no_wait: bool,
    /// Replay again and again until interrupted.
    #[arg(long = "loop")]
    repeat: bool,
    /// Count and skip bad records (reported in the summary) instead of stopping at the first.
    #[arg(long)]
    skip_bad: bool,
}

/// Runs the command.
pub fn run(args: &ViewArgs) -> Result<()> {
    if !(args.rate.is_finite() && args.rate >= 0.0) {
        bail!(
            "--rate must be a number >= 0 (0 = as fast as possible), got {}",
            args.rate
        );
    }
    super::note_unused_tables(args.params.file_path(), &[&args.algorithm], "view")?;
    let mut extractor = super::make_extractor(&args.algorithm, &args.params)?;
    // Open once before serving, so that a bad input fails at once.
    let mut reader = super::open_input(&args.input)?;
    let server = LiveServer::start("127.0.0.1", args.port)?;
    // Both status lines on stderr, like every other status line of laserlines.
    eprintln!(
        "laserlines: serving ws://127.0.0.1:{} (in Foxglove: Open connection, Foxglove WebSocket)",
        server.port()
    );
    if !args.no_wait {
        eprintln!("laserlines: waiting for a viewer to subscribe to /scan");
        server.wait_for_viewer(None);
    }
    let mut lines: Vec<Line> = Vec::new();
    loop {
        let start = Instant::now();
        let mut clock = SceneClock::new();
        let mut pacer = Pacer::new(args.rate);
        let mut scans = 0u64;
        let mut total_lines = 0u64;
        for item in reader.by_ref() {
            let record = match item {
                Ok(r) => r,
                Err(e) if args.skip_bad => {
                    eprintln!("laserlines: skipped: {e}");
                    continue;
                }
                Err(e) => {
                    server.stop();
                    return Err(e.into());
                }
            };
            extractor.extract_into(&record.scan, &mut lines);
            let time = clock.time_of(record.scan.stamp);
            std::thread::sleep(pacer.delay(time, Instant::now()));
            server.publish(&record, &lines, time);
            scans += 1;
            total_lines += lines.len() as u64;
        }
        eprintln!(
            "{}: {}, {} replayed in {:.1} s, skipped: {}",
            reader.name(),
            super::count(scans, "scan"),
            super::count(total_lines, "line"),
            start.elapsed().as_secs_f64(),
            reader.skipped()
        );
        if scans == 0 {
            server.stop();
            return Err(super::no_scans(reader.name(), reader.skipped()));
        }
        if !args.repeat {
            break;
        }
        reader = super::open_input(&args.input)?;
    }
    // Give the last messages time to leave before the server closes.
    std::thread::sleep(Duration::from_millis(500));
    server.stop();
    Ok(())
}
