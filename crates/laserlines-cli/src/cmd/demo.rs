//! `laserlines demo`: the whole pipeline on bundled real Hokuyo URG-04LX scans.

use std::fs;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;
use laserlines::{HoughSplit, HoughSplitParams, Line, LineExtractor};
use laserlines_io::LinesWriter;
use laserlines_render::{RenderOptions, render_hough_split};

/// Arguments of `laserlines demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Output folder.
    #[arg(short, long, default_value = "laserlines-demo")]
    output: PathBuf,
    /// Scan to draw as the paper's figures (0-based; the excerpt holds 40 scans).
    #[arg(long, default_value_t = 20, value_parser = super::index, allow_negative_numbers = true)]
    figure_scan: usize,
    /// Timing passes over the whole excerpt (1 to 1000).
    #[arg(long, default_value_t = 50, value_parser = super::repeat_count, allow_negative_numbers = true)]
    repeat: usize,
}

/// Runs the command.
pub fn run(args: &DemoArgs) -> Result<()> {
    let records = laserlines_io::demo::urg04lx_excerpt()?;
    if args.figure_scan >= records.len() {
        anyhow::bail!(
            "--figure-scan must be less than {} (the excerpt's scans count from 0), got {}",
            records.len(),
            args.figure_scan
        );
    }
    super::create_output_dir(&args.output)?;
    let mut hs = HoughSplit::new(HoughSplitParams::default())?;

    // Lines of every scan, written as JSONL.
    let jsonl = args.output.join("lines.jsonl");
    let mut writer = LinesWriter::create(&jsonl)?;
    let mut lines: Vec<Line> = Vec::new();
    let mut counts = Vec::with_capacity(records.len());
    for (k, rec) in records.iter().enumerate() {
        hs.extract_into(&rec.scan, &mut lines);
        counts.push(lines.len());
        writer.write_record(k as u64, rec, &lines)?;
    }
    writer.close()?;

    // The paper's figures for one scan.
    let k = args.figure_scan;
    let figure = args.output.join(format!("hough-split-scan{k:02}.svg"));
    if let Some(rec) = records.get(k) {
        let lines = hs.extract(&rec.scan);
        let svg = render_hough_split(&rec.scan, &hs, &lines, &RenderOptions::default());
        fs::write(&figure, svg).with_context(|| format!("cannot write {}", figure.display()))?;
    }

    // Speed: median time per scan over repeated passes (single thread, reused workspace).
    let mut per_scan = Vec::with_capacity(args.repeat);
    for _ in 0..args.repeat {
        let t = Instant::now();
        for rec in &records {
            hs.extract_into(std::hint::black_box(&rec.scan), &mut lines);
        }
        per_scan.push(t.elapsed().as_secs_f64() * 1e6 / records.len().max(1) as f64);
    }
    per_scan.sort_by(f64::total_cmp);
    let median_us = per_scan[per_scan.len() / 2];

    let total: usize = counts.iter().sum();
    let n = counts.len().max(1);
    outln!(
        "laserlines demo: {} real URG-04LX scans (BreezySLAM exp1 excerpt)",
        records.len()
    );
    outln!(
        "  lines per scan: mean {:.1}, min {}, max {}",
        total as f64 / n as f64,
        counts.iter().min().copied().unwrap_or(0),
        counts.iter().max().copied().unwrap_or(0)
    );
    outln!(
        "  hough-split: {median_us:.1} us per scan (median of {}, one thread)",
        super::count(per_scan.len() as u64, "pass")
    );
    outln!("  wrote {}", jsonl.display());
    outln!("  wrote {}", figure.display());
    Ok(())
}
