//! `laserlines hokuyo-emulator`: a Hokuyo sensor in software, speaking SCIP 2.0 over TCP
//! or a pseudo-terminal, from the simulator in an arena or from a recorded log, with
//! injectable faults.

use std::io::Write;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use laserlines_hokuyo::emulator::{Emulator, Faults, Model, ModelName, ScanFeed, ServedLog};
use laserlines_hokuyo_emulator::{ArenaFeed, LogFeed};
use laserlines_sim::arena::{ArenaOptions, interior_start, load_raf};

use crate::InputArgs;

/// Arguments of `laserlines hokuyo-emulator`.
#[derive(Debug, Args)]
pub struct HokuyoEmulatorArgs {
    /// The sensor: urg-04lx (682 steps, 10 scans/s) or ust-10lx (1081 steps, 40 scans/s).
    #[arg(long, default_value = "urg-04lx")]
    model: String,
    /// Serve on TCP at ADDR:PORT (port 0 picks a free one; the address is printed).
    #[arg(long, conflicts_with = "pty")]
    tcp: Option<String>,
    /// Serve on a new pseudo-terminal (its device path is printed): the serial path.
    #[arg(long)]
    pty: bool,
    /// A RoboCup Rescue arena (.raf) for the simulated sensor to move in (default: the
    /// bundled maze_10m_x_14m).
    #[arg(long, conflicts_with = "log")]
    arena: Option<PathBuf>,
    /// Replay a recorded log instead (any format `extract` reads), over and over: from its
    /// first scan again after its last. The whole log is read before serving: a bad record
    /// (named by file and line or byte offset, as `extract` names it) or a log without scans
    /// is an error.
    #[arg(long)]
    log: Option<PathBuf>,
    /// Scans per second (default: the model's, 10 or 40), from 1/60 (one turn of the
    /// mirror a minute) up to 1000; the motor turns a whole number of times a minute, so the
    /// rate is rounded to the nearest multiple of 1/60.
    #[arg(long, allow_negative_numbers = true)]
    rate: Option<f64>,
    /// Seed of the simulated noise.
    #[arg(long, default_value_t = 0, value_parser = super::whole::<u64>, allow_negative_numbers = true)]
    seed: u64,
    /// Stop after this many seconds, more than 0 (default: until Ctrl-C).
    #[arg(long, allow_negative_numbers = true)]
    duration: Option<f64>,
    /// Write every scan sent as a JSON line (connection, time stamp, fault, readings in mm).
    #[arg(long)]
    served: Option<PathBuf>,
    /// Fault: every N-th scan with a wrong check character.
    #[arg(long, default_value_t = 0, value_parser = super::whole::<u64>, allow_negative_numbers = true)]
    bad_checksum_every: u64,
    /// Fault: every N-th scan with a data line cut short.
    #[arg(long, default_value_t = 0, value_parser = super::whole::<u64>, allow_negative_numbers = true)]
    truncate_every: u64,
    /// Fault: after N scans on a connection, send half a scan and drop the connection.
    #[arg(long, default_value_t = 0, value_parser = super::whole::<u64>, allow_negative_numbers = true)]
    drop_after: u64,
    /// Fault: stay unreachable this many seconds after dropping a connection (with
    /// --drop-after).
    #[arg(
        long,
        default_value_t = 0.0,
        requires = "drop_after",
        allow_negative_numbers = true
    )]
    down_for: f64,
    /// Fault: start in SCIP 1.1 (the host must switch with SCIP2.0).
    #[arg(long)]
    scip11: bool,
    /// Fault: answer every command this many milliseconds late (up to 1e12).
    #[arg(long, default_value_t = 0, value_parser = super::whole::<u64>, allow_negative_numbers = true)]
    reply_delay_ms: u64,
    /// Fault: after N scans on a connection, fall silent ...
    #[arg(long, default_value_t = 0, value_parser = super::whole::<u64>, allow_negative_numbers = true)]
    stall_after: u64,
    /// ... for this many seconds.
    #[arg(long, default_value_t = 5.0, allow_negative_numbers = true)]
    stall_for: f64,
    /// Fault: the sensor clock at start, ms (16777215 wraps at once; 16775216 after 2 s).
    #[arg(long, default_value_t = 0, value_parser = super::whole::<u32>, allow_negative_numbers = true)]
    clock_start_ms: u32,
}

fn feed(args: &HokuyoEmulatorArgs, model: &Model) -> Result<Box<dyn ScanFeed>> {
    if let Some(log) = &args.log {
        let input = InputArgs {
            input: log.clone(),
            format: None,
            topic: None,
        };
        let first = check_log(&input)?;
        if let Some(note) = resampling_note(&first, model) {
            errln!("laserlines: note: {}: {note}", log.display());
        }
        let reopen = Box::new(move || {
            let reader = super::open_input(&input).map_err(|e| format!("{e:#}"))?;
            // The log was read whole without error: a record that fails now (the file
            // changed) ends the pass, and the replay starts over.
            Ok(Box::new(reader.map_while(Result::ok).map(|r| r.scan))
                as Box<dyn Iterator<Item = laserlines::Scan> + Send>)
        });
        return Ok(Box::new(LogFeed::new(reopen).map_err(|e| anyhow!(e))?));
    }
    let arena = match &args.arena {
        Some(p) => load_raf(p, &ArenaOptions::default())?,
        None => laserlines_harness::arenas::bundled("maze_10m_x_14m", &ArenaOptions::default())
            .ok_or_else(|| anyhow!("the bundled arena is missing"))??,
    };
    let start = interior_start(&arena.world, 0.5)
        .with_context(|| format!("{}: no free spot to put the sensor", arena.name))?;
    Ok(Box::new(ArenaFeed::new(&arena.world, start, args.seed)))
}

/// Reads the log of `--log` whole and returns its first scan: its first bad record is the
/// error, and so is a log that gives no scan.
fn check_log(input: &InputArgs) -> Result<laserlines::Scan> {
    let mut reader = super::open_input(input)?;
    let mut first = None;
    for item in reader.by_ref() {
        let scan = item?.scan;
        first.get_or_insert(scan);
    }
    first.ok_or_else(|| super::no_scans(reader.name(), reader.skipped()))
}

/// What serving the log's scans as `model` changes, when their geometry is not the model's:
/// each step reads where its ray meets the chord between the two beams beside it on one
/// surface (else the nearest beam), and steps outside the log's field of view and ranges
/// beyond the model's reach send no echo.
fn resampling_note(scan: &laserlines::Scan, model: &Model) -> Option<String> {
    let step = std::f64::consts::TAU / f64::from(model.ares);
    let first = model.step_angle(model.amin);
    let reach = f64::from(model.dmax_mm) / 1000.0;
    let same = scan.ranges.len() == model.steps()
        && (scan.angle_increment - step).abs() < 1e-6
        && (scan.angle_min - first).abs() < 1e-6
        && scan.range_max <= reach;
    let deg = f64::to_degrees;
    (!same).then(|| {
        format!(
            "its scans ({} beams of {:.3} deg from {:.1} deg, up to {} m) are served at the \
             {}'s {} steps of {:.3} deg from {:.1} deg, up to {} m: each step reads the chord \
             between the two beams beside it on one surface, else the nearest beam, and steps \
             outside the log's field of view and ranges beyond {} m send no echo",
            scan.ranges.len(),
            deg(scan.angle_increment),
            deg(scan.angle_min),
            super::compact(scan.range_max),
            model.name,
            model.steps(),
            deg(step),
            deg(first),
            super::compact(reach),
            super::compact(reach),
        )
    })
}

/// Runs the command.
pub fn run(args: &HokuyoEmulatorArgs) -> Result<()> {
    let name: ModelName = args.model.parse().map_err(|e: String| anyhow!(e))?;
    let mut model = Model::new(name);
    if let Some(rate) = args.rate {
        // The motor's speed in whole turns a minute, at least one.
        let rpm = (rate * 60.0).round();
        if !(rate.is_finite() && rate <= 1000.0 && rpm >= 1.0) {
            bail!(
                "--rate must be scans per second, from 1/60 (one a minute) up to 1000, got {}",
                super::compact(rate)
            );
        }
        model.scan_rpm = rpm as u32;
    }
    let duration = args
        .duration
        .map(|d| super::seconds("--duration", d, false))
        .transpose()?;
    let faults = Faults {
        bad_checksum_every: args.bad_checksum_every,
        truncate_every: args.truncate_every,
        drop_after: args.drop_after,
        down_for: super::seconds("--down-for", args.down_for, true)?,
        start_in_scip11: args.scip11,
        reply_delay: super::milliseconds("--reply-delay-ms", args.reply_delay_ms)?,
        stall_after: args.stall_after,
        stall_for: super::seconds("--stall-for", args.stall_for, true)?,
        clock_start_ms: args.clock_start_ms,
    };
    let log = match &args.served {
        Some(p) => ServedLog::to_writer(Box::new(std::io::BufWriter::new(
            std::fs::File::create(p).with_context(|| format!("cannot create {}", p.display()))?,
        ))),
        None => ServedLog::default(),
    };
    let feed = feed(args, &model)?;
    let emulator = Emulator::new(model, feed, faults, log);
    let handle = if args.pty {
        emulator
            .serve_pty()
            .context("cannot open a pseudo-terminal")?
    } else {
        let addr = args.tcp.as_deref().unwrap_or("127.0.0.1:10940");
        emulator
            .serve_tcp(addr)
            .with_context(|| format!("cannot serve on {addr}"))?
    };
    match (handle.local_addr(), handle.pty_path()) {
        (Some(a), _) => outln!("laserlines: emulated {name} on {a}"),
        (_, Some(p)) => outln!("laserlines: emulated {name} on {p}"),
        _ => {}
    }
    std::io::stdout().flush()?;
    let stop = Arc::new(AtomicBool::new(false));
    let s = stop.clone();
    ctrlc::set_handler(move || s.store(true, Ordering::Relaxed)).context("cannot catch Ctrl-C")?;
    let until = duration.map(|d| Instant::now() + d);
    while !stop.load(Ordering::Relaxed)
        && until.is_none_or(|u| Instant::now() < u)
        && !handle.is_finished()
    {
        std::thread::sleep(Duration::from_millis(20));
    }
    let sent = handle.log().count();
    handle.stop()?;
    errln!("laserlines: emulator sent {sent} scans");
    Ok(())
}
