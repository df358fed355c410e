//! `laserlines`: line segments from 2D laser scans, on the command line.

/// `println!` that ends the process quietly (exit code 0) when standard output has been
/// closed, as when its reader stops early (`laserlines ... | head`), instead of panicking.
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout(), $($arg)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
        }
    }};
}

/// `eprintln!` that never panics: a message to standard error is dropped when that has been
/// closed (`laserlines ... 2>&1 | head`), and the run goes on to its exit code.
macro_rules! errln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

/// `print!` that ends the process quietly (exit code 0) when standard output has been closed,
/// as [`outln!`] does.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = write!(std::io::stdout(), $($arg)*) {
            if e.kind() == std::io::ErrorKind::BrokenPipe {
                std::process::exit(0);
            }
        }
    }};
}

/// `eprint!` that never panics, as [`errln!`].
macro_rules! err {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stderr(), $($arg)*);
    }};
}

mod cmd;
mod logging;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};

/// Line segments from 2D laser range scans: the g-weighted Hough transform, data segments and
/// recursive split of the NAJI V rescue robot, and the classic extractors.
#[derive(Debug, Parser)]
#[command(
    name = "laserlines",
    version,
    about = "Line segments from 2D laser range scans: extract them from logs, bags and sensors, \
             draw the paper's figures, compare extractors, simulate and view runs",
    long_about = None
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Extract lines from every scan of an input; writes one JSON object per scan.
    Extract(cmd::extract::ExtractArgs),
    /// Draw the paper's figures (raw scan, spider net, data segments, lines) for one scan.
    Render(cmd::render::RenderArgs),
    /// Run the whole pipeline on bundled real Hokuyo URG-04LX scans.
    Demo(cmd::demo::DemoArgs),
    /// Compare extractors on simulated suites with ground truth or on real logs: accuracy
    /// and speed as a table, JSON, CSV and a chart; `--tune` chooses parameters.
    Bench(cmd::bench::BenchArgs),
    /// Explore a rescue arena or a seeded maze with the simulated NAJI V; writes metrics and pictures.
    Simulate(cmd::simulate::SimulateArgs),
    /// Convert scans between formats without extracting (e.g. a log to an MCAP for Foxglove).
    Convert(cmd::convert::ConvertArgs),
    /// Replay a log with its lines on a Foxglove WebSocket on 127.0.0.1.
    View(cmd::view::ViewArgs),
    /// Read a Hokuyo sensor (USB serial or Ethernet, SCIP 2.0) and extract lines live.
    Live(cmd::live::LiveArgs),
    /// Emulate a Hokuyo sensor (SCIP 2.0 over TCP or a pseudo-terminal), with faults.
    HokuyoEmulator(cmd::hokuyo_emulator::HokuyoEmulatorArgs),
    /// Build a map and a trajectory from a log (scan matching, loop closure, pose graph).
    Map(cmd::map::MapArgs),
    /// Score a trajectory against relations (the Freiburg SLAM benchmark's metric).
    Relations(cmd::relations::RelationsArgs),
}

/// Where scans come from: a path (or `-` for stdin) and an optional format override.
#[derive(Debug, Clone, Args)]
pub struct InputArgs {
    /// Input file (.json, .jsonl or .ndjson, .csv, .dat, .mcap, .clf/.log for CARMEN, .bag for ROS 1,
    /// .db3; optionally .gz; .parquet, not gzipped), a ROS 2 bag directory (MCAP or sqlite3
    /// storage), or `-` for stdin.
    pub input: PathBuf,
    /// Input format, overriding the file extension (json, jsonl, csv, dat, mcap, carmen, bag,
    /// db3, parquet).
    #[arg(long)]
    pub format: Option<String>,
    /// Topic to read from an MCAP file or a ROS bag (default: the first LaserScan topic), or
    /// the laser message of a CARMEN log (FLASER, RLASER, ROBOTLASER1, RAWLASER1, ...;
    /// default: the front laser, FLASER and ROBOTLASER1).
    #[arg(long)]
    pub topic: Option<String>,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    logging::init();
    let result = match cli.command {
        Command::Extract(a) => cmd::extract::run(&a),
        Command::Render(a) => cmd::render::run(&a),
        Command::Demo(a) => cmd::demo::run(&a),
        Command::Bench(a) => cmd::bench::run(&a),
        Command::Simulate(a) => cmd::simulate::run(&a),
        Command::Convert(a) => cmd::convert::run(&a),
        Command::View(a) => cmd::view::run(&a),
        Command::Live(a) => cmd::live::run(&a),
        Command::HokuyoEmulator(a) => cmd::hokuyo_emulator::run(&a),
        Command::Map(a) => cmd::map::run(&a),
        Command::Relations(a) => cmd::relations::run(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // Standard output closed by its reader: not an error of ours.
        Err(e) if cmd::is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            errln!(
                "laserlines: error: {}",
                laserlines_io::error_chain(e.as_ref())
            );
            ExitCode::from(2)
        }
    }
}

#[cfg(test)]
mod tests {
    use anyhow::Context;
    use laserlines_io::error_chain;

    #[test]
    fn a_cause_already_in_the_message_is_not_repeated() {
        let io = std::io::Error::other("disk full");
        let named = anyhow::Error::new(io).context("out.mcap: disk full");
        assert_eq!(error_chain(named.as_ref()), "out.mcap: disk full");
        let plain: anyhow::Result<()> = Err(anyhow::anyhow!("disk full"));
        let e = plain.context("cannot write out.mcap").unwrap_err();
        assert_eq!(error_chain(e.as_ref()), "cannot write out.mcap: disk full");
        // A short cause that only appears inside the message is still given.
        let short: anyhow::Result<()> = Err(anyhow::anyhow!("full"));
        let e = short.context("disk full check failed").unwrap_err();
        assert_eq!(error_chain(e.as_ref()), "disk full check failed: full");
    }
}
