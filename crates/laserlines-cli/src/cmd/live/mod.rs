//! `laserlines live`: a Hokuyo sensor (USB serial or Ethernet), its scans to lines as they
//! come, to a Foxglove live view, an MCAP recording and/or lines JSONL (`outputs`), with a
//! status line (`status`).

mod outputs;
mod status;
mod stop;

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use laserlines::Line;
use laserlines::registry::BoxedExtractor;
use laserlines_hokuyo::codec::Encoding;
use laserlines_hokuyo::{Endpoint, Scanner, ScannerOptions};
use laserlines_io::ScanRecord;

use outputs::Outputs;
use status::Tally;
use stop::Stop;

/// Arguments of `laserlines live`.
#[derive(Debug, Args)]
pub struct LiveArgs {
    /// The sensor: a serial device (/dev/ttyACM0, COM3) or HOST:PORT (192.168.0.10:10940).
    device: String,
    /// Fix the serial bit rate (default: try 115200, 19200, 38400); serial devices only.
    #[arg(long, value_parser = |s: &str| super::whole_in::<u32>(s, 1, i128::from(u32::MAX)), allow_negative_numbers = true)]
    baud: Option<u32>,
    /// Line extraction algorithm.
    #[arg(long, default_value = "hough-split")]
    algorithm: String,
    #[command(flatten)]
    params: super::ParamsArgs,
    /// Serve the scans and lines live to Foxglove on ws://127.0.0.1:PORT.
    #[arg(long)]
    view: bool,
    /// Port of the live view (0 picks a free one).
    #[arg(long, requires = "view", default_value_t = 8765, value_parser = super::whole::<u16>, allow_negative_numbers = true)]
    port: u16,
    /// Record scans and lines to this MCAP file (`.mcap`).
    #[arg(long)]
    record: Option<PathBuf>,
    /// Write the lines of every scan to this file: lines JSONL (`.jsonl`, `.jsonl.gz`, `-`
    /// for stdout), MCAP (`.mcap`) or Parquet (`.parquet`), as `extract -o` writes them.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// The three sector objects (left, front, right) of every scan: printed, and on
    /// `/sectors` in the live view and the recording.
    #[arg(long)]
    sectors: bool,
    /// Stop after this many scans (1 or more).
    #[arg(long, value_parser = |s: &str| super::whole_in::<u64>(s, 1, i128::MAX), allow_negative_numbers = true)]
    scans: Option<u64>,
    /// Stop after this many seconds (more than 0).
    #[arg(long, allow_negative_numbers = true)]
    duration: Option<f64>,
    /// Cluster count: so many neighbouring steps per beam (1..=99).
    #[arg(long, default_value_t = 1, value_parser = |s: &str| super::whole_in::<u32>(s, 1, 99), allow_negative_numbers = true)]
    cluster: u32,
    /// Scans to skip between two sent (0..=9).
    #[arg(long, default_value_t = 0, value_parser = |s: &str| super::whole_in::<u32>(s, 0, 9), allow_negative_numbers = true)]
    skip: u32,
    /// Use MS (2-character ranges, up to 4095 mm) instead of MD.
    #[arg(long)]
    ms: bool,
    /// Treat the link as lost after this many seconds without data (default: 10 scan
    /// periods, at least 1 s).
    #[arg(long, allow_negative_numbers = true)]
    silence: Option<f64>,
}

/// Opens the sensor with the request the options ask for (the whole measurement area, as
/// the sensor describes it, with the cluster count, skip and encoding chosen), and says
/// what it is on stderr.
fn open_sensor(args: &LiveArgs, endpoint: &Endpoint, silence: Option<Duration>) -> Result<Scanner> {
    let probe = ScannerOptions {
        silence,
        ..ScannerOptions::default()
    };
    let mut scanner = Scanner::open(endpoint, probe).context("cannot start the sensor")?;
    let mut request = scanner.info().full_request();
    request.cluster = args.cluster;
    request.skip = args.skip;
    if args.ms {
        request.encoding = Encoding::Two;
    }
    if request != *scanner.request() {
        scanner.close()?;
        let options = ScannerOptions {
            request: Some(request),
            silence,
            ..ScannerOptions::default()
        };
        scanner = Scanner::open(endpoint, options).context("cannot start the sensor")?;
    }
    let info = scanner.info();
    let period = info.scan_period_s() * f64::from(request.skip + 1);
    if let Some(s) = silence
        && s.as_secs_f64() < 2.0 * period
    {
        scanner.close()?;
        bail!(
            "--silence {} s is shorter than two of this sensor's scan periods (2 x {:.3} s): \
             the link would seem lost between two scans",
            s.as_secs_f64(),
            period
        );
    }
    errln!(
        "laserlines: {} ({}, serial {}, firmware {}) on {endpoint}: {} beams, {:.2} scans/s{}",
        info.model,
        info.protocol,
        info.serial,
        info.firmware,
        request.values(),
        1.0 / period,
        if scanner.stats().switched_from_scip11 {
            ", switched from SCIP 1.1"
        } else {
            ""
        }
    );
    Ok(scanner)
}

/// Scans to lines to the outputs until the scan count or duration is reached, the sensor is
/// given up on, or `stop` is set (Ctrl-C).
fn stream(
    args: &LiveArgs,
    duration: Option<Duration>,
    scanner: &mut Scanner,
    extractor: &mut BoxedExtractor,
    outputs: &mut Outputs,
    tally: &mut Tally,
    stop: &AtomicBool,
) -> Result<()> {
    let start = Instant::now();
    let mut lines: Vec<Line> = Vec::new();
    let tty = std::io::IsTerminal::is_terminal(&std::io::stderr());
    while args.scans.is_none_or(|n| tally.scans < n) && duration.is_none_or(|d| start.elapsed() < d)
    {
        let Some(scan) = scanner.next_scan(stop) else {
            break;
        };
        let t0 = Instant::now();
        extractor.extract_into(&scan.scan, &mut lines);
        let done = Instant::now();
        let extract_us = (done - t0).as_secs_f64() * 1e6;
        let latency_us = done.saturating_duration_since(scan.received).as_secs_f64() * 1e6;
        outputs.publish(tally.scans, &ScanRecord::new(scan.scan), &lines)?;
        tally.add(lines.len(), extract_us, latency_us, done);
        tally.report(scanner.stats(), done, tty);
    }
    if tty {
        errln!();
    }
    Ok(())
}

/// Runs the command.
pub fn run(args: &LiveArgs) -> Result<()> {
    let mut endpoint: Endpoint = args.device.parse().map_err(|e| anyhow!("{e}"))?;
    match (&mut endpoint, args.baud) {
        (Endpoint::Serial { baud, .. }, Some(b)) => *baud = Some(b),
        (_, Some(b)) => bail!(
            "--baud {b}: {endpoint} is a sensor on the network (HOST:PORT), which has no bit \
             rate; --baud goes with a serial device"
        ),
        _ => {}
    }
    if args.sectors && args.output.as_deref() == Some(Path::new("-")) {
        bail!(
            "--sectors prints the sector objects on standard output, which -o - takes for the \
             lines: give -o a file"
        );
    }
    let silence = args
        .silence
        .map(|s| super::seconds("--silence", s, false))
        .transpose()?;
    let duration = args
        .duration
        .map(|s| super::seconds("--duration", s, false))
        .transpose()?;
    super::note_unused_tables(args.params.file_path(), &[&args.algorithm], "live")?;
    // An output of a name it cannot have, or in a folder that does not exist, is named
    // before the sensor is opened.
    if let Some(path) = &args.output {
        laserlines_foxglove::files::LinesOutput::check_name(path)?;
    }
    if let Some(path) = &args.record {
        laserlines_foxglove::files::mcap_name(path)?;
    }
    for path in [args.output.as_deref(), args.record.as_deref()]
        .into_iter()
        .flatten()
    {
        super::output_folder_exists(path)?;
    }
    if let (Some(out), Some(record)) = (&args.output, &args.record)
        && super::same_path(out, record)
    {
        bail!(
            "{}: -o and --record name one file; two writers would interleave in it, give them \
             different names",
            record.display()
        );
    }
    let mut extractor = super::make_extractor(&args.algorithm, &args.params)?;
    let stop = Stop::install(duration)?;

    // A bare host name reads as a serial device: say what a network sensor looks like (not
    // on Windows, where a bare name is how serial ports are named: COM3, CNCA0).
    if let Endpoint::Serial { path, .. } = &endpoint
        && !cfg!(windows)
        && !path.contains('/')
        && !std::path::Path::new(path).exists()
    {
        bail!(
            "{path}: no such serial device; a sensor on the network is HOST:PORT (e.g. \
             {path}:10940, 192.168.0.10:10940)"
        );
    }
    let mut scanner = open_sensor(args, &endpoint, silence)?;
    if stop.started() {
        scanner.close().context("the sensor did not confirm QT")?;
        errln!("laserlines: stopped while the sensor was starting: no scan read, nothing written");
        return Ok(());
    }
    let mut outputs = Outputs::open(args)?;
    let start = Instant::now();
    let mut tally = Tally::start();
    let result = stream(
        args,
        duration,
        &mut scanner,
        &mut extractor,
        &mut outputs,
        &mut tally,
        stop.flag(),
    );
    // QT on every way out: the end of the run, Ctrl-C, an output error. Scans lost to an
    // outage still going on are counted first.
    scanner.count_missed_until_now();
    let stats = scanner.stats().clone();
    tally.close_window(Instant::now());
    let quit = scanner.close();
    outputs.close()?;
    // The run's average rate, then the status line, whose rate is its last window's (an
    // outage or a reconnection shows in the average only).
    let secs = start.elapsed().as_secs_f64();
    errln!(
        "laserlines: {} scans, {} lines in {secs:.1} s, {:.1} scans/s on average; at the end: {}",
        tally.scans,
        tally.lines,
        if secs > 0.0 {
            tally.scans as f64 / secs
        } else {
            0.0
        },
        tally.status_line(&stats)
    );
    result?;
    quit.context("the sensor did not confirm QT")?;
    Ok(())
}
