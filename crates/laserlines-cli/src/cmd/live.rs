//! `laserlines live`: a Hokuyo sensor (USB serial or Ethernet), its scans to lines as they
//! come, to a Foxglove live view, an MCAP recording and/or lines JSONL.

use std::io::Write;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use laserlines::Line;
use laserlines::math::Isometry2;
use laserlines_foxglove::LinesOutput;
use laserlines_foxglove::live::LiveServer;
use laserlines_foxglove::scene::SceneClock;
use laserlines_foxglove::write::McapSceneWriter;
use laserlines_hokuyo::codec::Encoding;
use laserlines_hokuyo::{Endpoint, Scanner, ScannerOptions, ScannerStats};
use laserlines_io::ScanRecord;
use laserlines_nav::sectors::{Sector, SectorParams, select_objects};

/// Arguments of `laserlines live`.
#[derive(Debug, Args)]
pub struct LiveArgs {
    /// The sensor: a serial device (/dev/ttyACM0, COM3) or HOST:PORT (192.168.0.10:10940).
    device: String,
    /// Fix the serial bit rate (default: try 115200, 19200, 38400).
    #[arg(long)]
    baud: Option<u32>,
    /// Line extraction algorithm.
    #[arg(long, default_value = "hough-split")]
    algorithm: String,
    /// TOML file of parameters (one table per algorithm, e.g. `[hough-split]`).
    #[arg(long)]
    params: Option<PathBuf>,
    /// Serve the scans and lines live to Foxglove on ws://127.0.0.1:PORT.
    #[arg(long)]
    view: bool,
    /// Port of the live view (0 picks a free one).
    #[arg(long, default_value_t = 8765)]
    port: u16,
    /// Record scans and lines to this MCAP file.
    #[arg(long)]
    record: Option<PathBuf>,
    /// Write the lines of every scan to this JSONL file (`-` for stdout).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Print the three sector objects (left, front, right) of every scan.
    #[arg(long)]
    sectors: bool,
    /// Stop after this many scans.
    #[arg(long)]
    scans: Option<u64>,
    /// Stop after this many seconds.
    #[arg(long)]
    duration: Option<f64>,
    /// Cluster count: so many neighbouring steps per beam (1..=99).
    #[arg(long, default_value_t = 1)]
    cluster: u32,
    /// Scans to skip between two sent (0..=9).
    #[arg(long, default_value_t = 0)]
    skip: u32,
    /// Use MS (2-character ranges, up to 4095 mm) instead of MD.
    #[arg(long)]
    ms: bool,
    /// Treat the link as lost after this many seconds without data (default: 10 scan
    /// periods, at least 1 s).
    #[arg(long)]
    silence: Option<f64>,
}

/// Figures of the run shown in the status line.
#[derive(Default)]
struct Tally {
    scans: u64,
    lines: u64,
    window_start: Option<Instant>,
    window_scans: u64,
    extract_us_max: f64,
    latency_us_max: f64,
    extract_us_sum: f64,
    latency_us_sum: f64,
}

fn status_line(t: &Tally, stats: &ScannerStats, rate: f64) -> String {
    let n = t.scans.max(1) as f64;
    format!(
        "{:.1} scans/s, {} scans, dropped: {}, reconnects {}, clock offset {}, drift {:.1} ppm, extraction {:.0} us (max {:.0}), last byte to lines {:.0} us (max {:.0})",
        rate,
        t.scans,
        stats.dropped,
        stats.reconnects,
        stats
            .clock_offset_s
            .map_or_else(|| "-".to_owned(), |o| format!("{o:.3} s")),
        stats.drift * 1e6,
        t.extract_us_sum / n,
        t.extract_us_max,
        t.latency_us_sum / n,
        t.latency_us_max,
    )
}

fn describe_sectors(k: u64, lines: &[Line]) -> String {
    let objects = select_objects(lines, &Isometry2::identity(), &SectorParams::default());
    let parts: Vec<String> = [Sector::Left, Sector::Front, Sector::Right]
        .iter()
        .map(|&s| match objects.get(s) {
            Some(o) => format!(
                "{}: distance {:.3} m, width {:.3} m, angle {:.1} deg",
                s.name(),
                o.distance_m,
                o.width_m,
                o.angle_rad.to_degrees()
            ),
            None => format!("{}: none", s.name()),
        })
        .collect();
    format!("scan {k}: {}", parts.join("; "))
}

/// Runs the command.
pub fn run(args: &LiveArgs) -> Result<()> {
    let mut endpoint: Endpoint = args.device.parse().map_err(|e| anyhow!("{e}"))?;
    if let (Endpoint::Serial { baud, .. }, Some(b)) = (&mut endpoint, args.baud) {
        *baud = Some(b);
    }
    if !(1..=99).contains(&args.cluster) || args.skip > 9 {
        bail!("--cluster must be 1..=99 and --skip 0..=9");
    }
    let silence = args
        .silence
        .map(|s| {
            Duration::try_from_secs_f64(s).map_err(|_| anyhow!("--silence must be seconds > 0"))
        })
        .transpose()?;
    let duration = args
        .duration
        .map(|s| {
            Duration::try_from_secs_f64(s).map_err(|_| anyhow!("--duration must be seconds >= 0"))
        })
        .transpose()?;
    let mut extractor = super::make_extractor(&args.algorithm, args.params.as_deref())?;
    let stop = Arc::new(AtomicBool::new(false));
    let s = stop.clone();
    ctrlc::set_handler(move || s.store(true, Ordering::Relaxed)).context("cannot catch Ctrl-C")?;

    // The whole measurement area, as the sensor describes it, with the chosen options.
    let probe = ScannerOptions {
        silence,
        ..ScannerOptions::default()
    };
    let mut scanner = Scanner::open(&endpoint, probe).context("cannot start the sensor")?;
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
        scanner = Scanner::open(&endpoint, options).context("cannot start the sensor")?;
    }
    let info = scanner.info().clone();
    eprintln!(
        "laserlines: {} ({}, serial {}, firmware {}) on {endpoint}: {} beams, {:.2} scans/s{}",
        info.model,
        info.protocol,
        info.serial,
        info.firmware,
        request.values(),
        1.0 / (info.scan_period_s() * f64::from(request.skip + 1)),
        if scanner.stats().switched_from_scip11 {
            ", switched from SCIP 1.1"
        } else {
            ""
        }
    );

    let server = if args.view {
        let server = LiveServer::start("127.0.0.1", args.port)?;
        outln!(
            "laserlines: serving ws://127.0.0.1:{} (in Foxglove: Open connection, Foxglove WebSocket)",
            server.port()
        );
        std::io::stdout().flush()?;
        Some(server)
    } else {
        None
    };
    let mut recording = args
        .record
        .as_deref()
        .map(McapSceneWriter::create)
        .transpose()?;
    let mut output = args
        .output
        .as_deref()
        .map(LinesOutput::create)
        .transpose()?;

    let start = Instant::now();
    let mut tally = Tally::default();
    let mut clock = SceneClock::new();
    let mut lines: Vec<Line> = Vec::new();
    let mut last_status = Instant::now();
    let mut rate = 0.0;
    let tty = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let result = (|| -> Result<()> {
        while args.scans.is_none_or(|n| tally.scans < n)
            && duration.is_none_or(|d| start.elapsed() < d)
        {
            let Some(scan) = scanner.next_scan(&stop) else {
                break;
            };
            let t0 = Instant::now();
            extractor.extract_into(&scan.scan, &mut lines);
            let done = Instant::now();
            let extract_us = (done - t0).as_secs_f64() * 1e6;
            let latency_us = done.saturating_duration_since(scan.received).as_secs_f64() * 1e6;
            tally.extract_us_sum += extract_us;
            tally.latency_us_sum += latency_us;
            tally.extract_us_max = tally.extract_us_max.max(extract_us);
            tally.latency_us_max = tally.latency_us_max.max(latency_us);
            let record = ScanRecord::new(scan.scan);
            if let Some(s) = &server {
                s.publish(&record, &lines, clock.time_of(record.scan.stamp));
            }
            if let Some(w) = &mut recording {
                w.write_lines(&record, &lines)?;
            }
            if let Some(o) = &mut output {
                o.write_record(tally.scans, &record, &lines)?;
            }
            if args.sectors {
                outln!("{}", describe_sectors(tally.scans, &lines));
            }
            tally.scans += 1;
            tally.lines += lines.len() as u64;
            tally.window_scans += 1;
            let w0 = *tally.window_start.get_or_insert(done);
            if last_status.elapsed() >= Duration::from_secs(1) {
                let secs = done.duration_since(w0).as_secs_f64();
                if secs > 0.0 {
                    rate = (tally.window_scans - 1) as f64 / secs;
                }
                tally.window_start = Some(done);
                tally.window_scans = 1;
                let line = status_line(&tally, scanner.stats(), rate);
                if tty {
                    eprint!("\r{line}\x1b[K");
                } else {
                    eprintln!("laserlines: {line}");
                }
                last_status = Instant::now();
            }
        }
        Ok(())
    })();
    if tty {
        eprintln!();
    }
    // QT on every way out: the end of the run, Ctrl-C, an output error.
    let stats = scanner.stats().clone();
    let quit = scanner.close();
    if let Some(w) = recording {
        w.finish()?;
    }
    if let Some(o) = output {
        o.close()?;
    }
    if let Some(s) = server {
        s.stop();
    }
    eprintln!(
        "laserlines: {} scans, {} lines in {:.1} s; {}",
        tally.scans,
        tally.lines,
        start.elapsed().as_secs_f64(),
        status_line(&tally, &stats, rate)
    );
    result?;
    quit.context("the sensor did not confirm QT")?;
    Ok(())
}
