//! `laserlines-ros2`: line segments from laser scans as a ROS 2 node, with no ROS install.

use std::io::{IsTerminal as _, Write as _};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context as _, Result};
use clap::Parser;
use laserlines_ros2::args::Ros2Args;
use laserlines_ros2::node::LineNode;
use laserlines_ros2::process::Processor;
use tracing::{info, warn};

fn run(args: &Ros2Args) -> Result<()> {
    let config = args.node_config()?;
    let limits = args.limits()?;
    let extractor = args.extractor()?;
    // A table of the params file the node does not read is said, as `laserlines` says it.
    if args.params.is_some() {
        let file = args.params_file()?;
        for table in file.tables().filter(|t| *t != args.algorithm) {
            warn!(
                "{}: [{table}] is not used by laserlines-ros2 (the algorithm is {})",
                file.name(),
                args.algorithm
            );
        }
    }
    let stop = Arc::new(AtomicBool::new(false));
    let s = Arc::clone(&stop);
    ctrlc::set_handler(move || s.store(true, Ordering::Relaxed)).context("cannot catch Ctrl-C")?;
    let processor = Processor::new(extractor, args.frame_id.clone(), args.sectors);
    let mut node = LineNode::new(&config, processor)?;
    info!(
        "{} ({}, domain {}{}): {} -> {} ({}/msg/LineSegmentList), {}{}",
        node.name(),
        args.algorithm,
        config.domain_id,
        config
            .only_networks
            .as_ref()
            .map_or_else(String::new, |n| format!(", interfaces {n:?}")),
        config.scan_topic,
        config.lines_topic,
        config.line_package,
        config.markers_topic,
        config
            .sectors_topic
            .as_ref()
            .map_or_else(String::new, |t| format!(", {t}")),
    );
    let counts = node.spin(&stop, &limits)?;
    info!("{counts}");
    Ok(())
}

fn main() -> ExitCode {
    let args = Ros2Args::parse();
    let filter = tracing_subscriber::EnvFilter::try_from_default_env().unwrap_or_else(|_| {
        tracing_subscriber::EnvFilter::new("info,rustdds=off,ros2_client=error")
    });
    tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(std::io::stderr)
        .with_ansi(std::io::stderr().is_terminal())
        .init();
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // A closed standard error loses the message, not the exit code.
            let _ = writeln!(
                std::io::stderr(),
                "laserlines-ros2: error: {}",
                laserlines_io::error_chain(e.as_ref())
            );
            ExitCode::from(2)
        }
    }
}
